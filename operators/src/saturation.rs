//! The saturation operator.

use crate::memoryless::map_samples;
use crate::{check, declare_params, Float, Result, StepLaw, Stepped, Trial};

declare_params! {
    /// Parameters of the [`Saturation`] operator.
    #[derive(Copy)]
    pub struct SaturationParams<T> {
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

impl<T: Float> StepLaw<T> for SaturationParams<T> {
    type State = ();

    fn initial(&self) {}

    #[inline(always)]
    fn step(&self, _: &(), x: T) -> Result<((), Trial<T>)> {
        let SaturationParams { lo, hi } = *self;
        let tangent = if x > lo && x < hi {
            T::one()
        } else {
            T::zero()
        };
        Ok((
            (),
            Trial {
                output: x.max(lo).min(hi),
                tangent,
            },
        ))
    }

    fn run(&self, _: &mut (), xs: &[T], ys: &mut [T]) -> Result<()> {
        let SaturationParams { lo, hi } = *self;
        map_samples(<Self as crate::Declared<T>>::KIND, xs, ys, |x| x.max(lo).min(hi))
    }

}
