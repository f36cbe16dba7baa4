//! The floating-point alias every operator is generic over.

use crate::Differentiable;
use core::fmt::{Debug, Display};

/// A real scalar usable by hysteron operators: `f32`, `f64` and the dual
/// numbers [`DualN`](crate::DualN) (values with their derivatives).
///
/// This is a trait alias over [`num_traits::Float`] with the extra bounds the
/// framework needs (thread-safe, printable, and [`Differentiable`], which
/// says whether the scalar carries derivatives). It has no serde bound:
/// serialization belongs to the spec layer. It is implemented
/// for every type that meets the bounds, so users never implement it by hand.
pub trait Float:
    num_traits::Float
    + num_traits::FloatConst
    + Differentiable
    + Debug
    + Display
    + Default
    + Send
    + Sync
    + 'static
{
    /// Converts a constant (a literal written as `f64`) into `Self`.
    ///
    /// Every `Float` can represent an `f64` approximately, so this never fails.
    #[inline(always)]
    fn lit(v: f64) -> Self {
        <Self as num_traits::NumCast>::from(v).unwrap_or_else(Self::nan)
    }

    /// This value as `f64`, for error messages and reports.
    #[inline(always)]
    fn as_f64(self) -> f64 {
        self.to_f64().unwrap_or(f64::NAN)
    }
}

impl<T> Float for T where
    T: num_traits::Float
        + num_traits::FloatConst
        + Differentiable
        + Debug
        + Display
        + Default
        + Send
        + Sync
        + 'static
{
}

/// Whether the values of `T` are `f64` values, computed in `f64`
/// arithmetic (`f64` and the dual numbers over it): where
/// [`Hints::trial_value`](crate::Hints::trial_value) gives the values
/// of `trial` bit for bit.
#[inline(always)]
pub(crate) fn values_are_f64<T: Float>() -> bool {
    T::epsilon().as_f64() == f64::EPSILON && T::max_value().as_f64() == f64::MAX
}
