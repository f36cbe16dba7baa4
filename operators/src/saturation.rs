//! The saturation operator.

use crate::{check, declare_params, Float, Memoryless, Result, Stepped, Trial};

declare_params! {
    /// Parameters of the [`Saturation`] operator.
    pub struct SaturationParams<T>: Copy {
        /// Lower limit.
        lo: T => Real = -1.0,
        /// Upper limit, `hi > lo`.
        hi: T => Real = 0.75,
    }
    check = |p| check::ordered("lo", p.lo, "hi", p.hi);
    law: "saturation", "y = clamp(x, lo, hi)";
}

/// Saturation `sat(x) = clamp(x, lo, hi)` with `lo < hi` (memoryless).
/// Tangent: 1 strictly inside, 0 at and beyond the limits.
///
/// ```
/// use hysteron_operators::{Operator, Saturation};
/// let mut s = Saturation::new(-1.0_f64, 2.0).unwrap();
/// assert_eq!(s.run(&[-3.0, 0.5, 5.0]).unwrap(), vec![-1.0, 0.5, 2.0]);
/// ```
pub type Saturation<T> = Stepped<SaturationParams<T>, T>;

impl<T: Float> Saturation<T> {
    /// A saturation with limits `lo < hi`.
    pub fn new(lo: T, hi: T) -> Result<Self> {
        Self::from_params(SaturationParams { lo, hi })
    }
}

crate::memoryless_step_law!(SaturationParams);

impl<T: Float> Memoryless<T> for SaturationParams<T> {
    #[inline(always)]
    fn eval(&self, x: T) -> Trial<T> {
        let SaturationParams { lo, hi } = *self;
        let tangent = if x > lo && x < hi {
            T::one()
        } else {
            T::zero()
        };
        Trial {
            output: x.max(lo).min(hi),
            tangent,
        }
    }

    #[inline(always)]
    fn value(&self, x: T) -> T {
        x.max(self.lo).min(self.hi)
    }
}
