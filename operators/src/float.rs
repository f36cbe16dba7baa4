//! The floating-point alias every operator is generic over.

use core::fmt::{Debug, Display};

/// A real scalar usable by hysteron operators: `f32` and `f64`.
///
/// This is a trait alias over [`num_traits::Float`] with the extra bounds the
/// framework needs (thread-safe, printable). It has no serde bound:
/// serialization belongs to the spec layer, so a dual-number type can
/// serve as the scalar. It is implemented
/// for every type that meets the bounds, so users never implement it by hand.
pub trait Float:
    num_traits::Float + num_traits::FloatConst + Debug + Display + Default + Send + Sync + 'static
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
        + Debug
        + Display
        + Default
        + Send
        + Sync
        + 'static
{
}
