//! The dead-zone operator.

use crate::memoryless::map_samples;
use crate::{check, check_input, Domain, Float, Operator, Result, Trial};
use serde::{Deserialize, Serialize};

/// Parameters of the [`DeadZone`] operator.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DeadZoneParams<T> {
    /// Left limit `b_l ≤ 0`.
    pub b_l: T,
    /// Right limit `b_r ≥ 0`.
    pub b_r: T,
}

impl<T: Float> DeadZoneParams<T> {
    /// Checks `b_l ≤ 0 ≤ b_r`.
    pub fn validate(&self) -> Result<()> {
        check::non_positive("b_l", self.b_l)?;
        check::non_negative("b_r", self.b_r)
    }
}

/// Dead-zone with limits `b_l ≤ 0 ≤ b_r` (memoryless):
///
/// `dz(x) = x − b_r` for `x > b_r`, `x − b_l` for `x < b_l`, `0` between.
///
/// With the same limits as a [`Saturation`](crate::Saturation),
/// `dz(x) + sat(x) = x`. Tangent: 1 outside the zone (one-sided 1 at its
/// edges), 0 inside.
///
/// ```
/// use hysteron_operators::{DeadZone, Operator};
/// let mut dz = DeadZone::new(-1.0_f64, 2.0).unwrap();
/// assert_eq!(dz.run(&[-3.0, 0.0, 5.0]).unwrap(), vec![-2.0, 0.0, 3.0]);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct DeadZone<T> {
    p: DeadZoneParams<T>,
}

/// The dead-zone map.
#[inline(always)]
pub fn dead_zone<T: Float>(b_l: T, b_r: T, x: T) -> T {
    if x > b_r {
        x - b_r
    } else if x < b_l {
        x - b_l
    } else {
        T::zero()
    }
}

impl<T: Float> DeadZone<T> {
    /// A dead-zone with limits `b_l ≤ 0 ≤ b_r`.
    pub fn new(b_l: T, b_r: T) -> Result<Self> {
        Self::from_params(DeadZoneParams { b_l, b_r })
    }

    /// A symmetric dead-zone `[−b, b]`.
    pub fn symmetric(b: T) -> Result<Self> {
        check::non_negative("b", b)?;
        Self::new(-b, b)
    }

    /// A dead-zone from validated parameters.
    pub fn from_params(p: DeadZoneParams<T>) -> Result<Self> {
        p.validate()?;
        Ok(Self { p })
    }

    /// The parameters.
    pub fn parameters(&self) -> &DeadZoneParams<T> {
        &self.p
    }
}

impl<T: Float> Operator<T> for DeadZone<T> {
    fn name(&self) -> &'static str {
        "deadzone"
    }

    #[inline]
    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        let x = check_input(x)?;
        let DeadZoneParams { b_l, b_r } = self.p;
        let tangent = if x >= b_r || x <= b_l {
            T::one()
        } else {
            T::zero()
        };
        Ok(Trial {
            output: dead_zone(b_l, b_r, x),
            tangent,
        })
    }

    fn commit(&mut self) {}

    fn reset(&mut self) {}

    fn process(&mut self, xs: &[T], ys: &mut [T]) -> Result<()> {
        let DeadZoneParams { b_l, b_r } = self.p;
        map_samples(xs, ys, |x| dead_zone(b_l, b_r, x))
    }

    fn n_params(&self) -> usize {
        2
    }

    fn params_into(&self, out: &mut Vec<T>) {
        out.extend([self.p.b_l, self.p.b_r]);
    }

    fn param_names(&self) -> Vec<String> {
        vec!["b_l".into(), "b_r".into()]
    }

    fn param_domains(&self) -> Vec<Domain> {
        vec![Domain::NonPositive, Domain::NonNegative]
    }

    fn set_params(&mut self, p: &[T]) -> Result<()> {
        check::count(2, p)?;
        *self = Self::from_params(DeadZoneParams {
            b_l: p[0],
            b_r: p[1],
        })?;
        Ok(())
    }
}
