//! A viscous damper (rate-dependent).

use crate::{check, declare_params, Float, Result, StepLaw, Stepped, Trial};

declare_params! {
    /// Parameters of the [`ViscousDamper`].
    pub struct ViscousDamperParams<T>: Copy {
        /// Damping coefficient `c ≥ 0`.
        c: T => NonNegative = 2.0,
        /// Sample period `dt > 0` (s) until the structure above sets one
        /// ([`SamplePeriod::set_sample_period`](crate::SamplePeriod::set_sample_period)).
        /// Not a fitted parameter.
        dt: T => fixed = 0.01,
    }
    check = |p| check::positive("dt", p.dt);
    law: "viscous_damper", "F = c ẋ, ẋ the backward difference (x_k − x_{k−1})/dt";
}

/// Viscous damper, force from displacement: `F = c ẋ`, `c ≥ 0`.
///
/// **Rate-dependent**: it holds its sample period `dt`. The velocity is the
/// backward difference `v_{k+1} = (x_{k+1} − x_k)/dt` (first-order
/// accurate; the trapezoidal differentiator `2Δx/dt − v_k` would be
/// second-order but rings at the Nyquist frequency after any kink in the
/// input), so the tangent is `dF/dx = c/dt`. It starts at rest (`x = 0`).
/// Parameter `[c]`; `dt` is fixed.
///
/// ```
/// use hysteron_operators::{Operator, ViscousDamper};
/// // a ramp of slope 2: F = c·2
/// let mut d = ViscousDamper::new(3.0_f64, 0.01).unwrap();
/// let x: Vec<f64> = (1..=100).map(|i| 0.02 * i as f64).collect();
/// let f = d.run(&x).unwrap();
/// assert!((f[99] - 6.0).abs() < 1e-9);
/// ```
pub type ViscousDamper<T> = Stepped<ViscousDamperParams<T>, T>;

impl<T: Float> ViscousDamper<T> {
    /// A damper with coefficient `c ≥ 0` and sample period `dt > 0`.
    pub fn new(c: T, dt: T) -> Result<Self> {
        Self::from_params(ViscousDamperParams { c, dt })
    }
}

impl<T: Float> StepLaw<T> for ViscousDamperParams<T> {
    type State = T;

    fn initial(&self) -> T {
        T::zero()
    }

    #[inline(always)]
    fn step(&self, x_prev: &T, x: T) -> Result<(T, Trial<T>)> {
        let ViscousDamperParams { c, dt } = *self;
        let v = (x - *x_prev) / dt;
        Ok((
            x,
            Trial {
                output: c * v,
                tangent: c / dt,
            },
        ))
    }

    fn set_sample_period(&mut self, dt: T) -> Result<()> {
        check::set_positive("dt", &mut self.dt, dt)
    }
}
