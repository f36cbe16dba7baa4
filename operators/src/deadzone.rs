//! The dead-zone operator.

use crate::{check, declare_params, Float, Memoryless, Result, Stepped, Trial};

declare_params! {
    /// Parameters of the [`DeadZone`] operator.
    pub struct DeadZoneParams<T>: Copy {
        /// Left limit `b_l ≤ 0`.
        b_l: T => NonPositive = -0.5,
        /// Right limit `b_r ≥ 0`.
        b_r: T => NonNegative = 1.0,
    }
    law: "dead_zone", "y = x − b_r above b_r, x − b_l below b_l, 0 in between";
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
pub type DeadZone<T> = Stepped<DeadZoneParams<T>, T>;

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
}

crate::memoryless_step_law!(DeadZoneParams);

impl<T: Float> Memoryless<T> for DeadZoneParams<T> {
    #[inline(always)]
    fn eval(&self, x: T) -> Trial<T> {
        let DeadZoneParams { b_l, b_r } = *self;
        let tangent = if x >= b_r || x <= b_l {
            T::one()
        } else {
            T::zero()
        };
        Trial {
            output: dead_zone(b_l, b_r, x),
            tangent,
        }
    }

    #[inline(always)]
    fn value(&self, x: T) -> T {
        dead_zone(self.b_l, self.b_r, x)
    }
}
