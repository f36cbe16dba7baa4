//! The saturation operator.

use crate::memoryless::map_samples;
use crate::{check, check_input, Float, Operator, Result, Trial};
use serde::{Deserialize, Serialize};

/// Parameters of the [`Saturation`] operator.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SaturationParams<T> {
    /// Lower limit.
    pub lo: T,
    /// Upper limit, `hi > lo`.
    pub hi: T,
}

impl<T: Float> SaturationParams<T> {
    /// Checks finite limits with `lo < hi`.
    pub fn validate(&self) -> Result<()> {
        check::ordered("lo", self.lo, "hi", self.hi)
    }
}

/// Saturation `sat(x) = clamp(x, lo, hi)` with `lo < hi` (memoryless).
/// Tangent: 1 strictly inside, 0 at and beyond the limits.
///
/// ```
/// use hysteron_operators::{Operator, Saturation};
/// let mut s = Saturation::new(-1.0_f64, 2.0).unwrap();
/// assert_eq!(s.run(&[-3.0, 0.5, 5.0]).unwrap(), vec![-1.0, 0.5, 2.0]);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Saturation<T> {
    p: SaturationParams<T>,
}

impl<T: Float> Saturation<T> {
    /// A saturation with limits `lo < hi`.
    pub fn new(lo: T, hi: T) -> Result<Self> {
        Self::from_params(SaturationParams { lo, hi })
    }

    /// A saturation from validated parameters.
    pub fn from_params(p: SaturationParams<T>) -> Result<Self> {
        p.validate()?;
        Ok(Self { p })
    }

    /// The parameters.
    pub fn parameters(&self) -> &SaturationParams<T> {
        &self.p
    }
}

impl<T: Float> Operator<T> for Saturation<T> {
    fn name(&self) -> &'static str {
        "saturation"
    }

    #[inline]
    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        let x = check_input(x)?;
        let SaturationParams { lo, hi } = self.p;
        let tangent = if x > lo && x < hi {
            T::one()
        } else {
            T::zero()
        };
        Ok(Trial {
            output: x.max(lo).min(hi),
            tangent,
        })
    }

    fn commit(&mut self) {}

    fn reset(&mut self) {}

    fn process(&mut self, xs: &[T], ys: &mut [T]) -> Result<()> {
        let SaturationParams { lo, hi } = self.p;
        map_samples(xs, ys, |x| x.max(lo).min(hi))
    }

    fn n_params(&self) -> usize {
        2
    }

    fn params_into(&self, out: &mut Vec<T>) {
        out.extend([self.p.lo, self.p.hi]);
    }

    fn param_names(&self) -> Vec<String> {
        vec!["lo".into(), "hi".into()]
    }

    fn set_params(&mut self, p: &[T]) -> Result<()> {
        check::count(2, p)?;
        *self = Self::from_params(SaturationParams { lo: p[0], hi: p[1] })?;
        Ok(())
    }
}
