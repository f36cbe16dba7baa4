//! The LuGre friction model (rate-dependent), integrated exactly per sample.

use crate::{check, declare_params, Float, Result, StepLaw, Stepped, Trial};

declare_params! {
    /// Parameters of the [`LuGre`] friction operator.
    pub struct LuGreParams<T>: Copy {
        /// Bristle stiffness `σ0 > 0` (force per input unit).
        sigma0: T => Positive = 1e4,
        /// Bristle damping `σ1 ≥ 0` (force per velocity).
        sigma1: T => NonNegative = 50.0,
        /// Viscous friction `σ2 ≥ 0` (force per velocity).
        sigma2: T => NonNegative = 0.4,
        /// Coulomb friction level `F_c > 0`.
        f_c: T => Positive = 1.0,
        /// Static (stiction) friction level `F_s > 0`. Usually `F_s ≥ F_c`;
        /// `F_s < F_c` is allowed (`g` then rises with speed and stays
        /// positive).
        f_s: T => Positive = 1.5,
        /// Stribeck velocity `v_s > 0` (input units per second).
        v_s: T => Positive = 0.01,
        /// Stribeck exponent `δ > 0` (default 2).
        #[serde(default = "two")]
        delta: T => Positive = 2.0,
        /// Bristle deflection at input `x = 0` before the first sample
        /// (default 0).
        #[serde(default)]
        z0: T => Real = 1e-5,
        /// Sample period `dt > 0` (s) until the structure above sets one
        /// ([`SamplePeriod::set_sample_period`](crate::SamplePeriod::set_sample_period)).
        /// Not a fitted parameter.
        dt: T => fixed = 1e-3,
    }
    check = |p| check::positive("dt", p.dt);
    law: "lugre", "ż = v − σ0 |v| z / g(v), g(v) = F_c + (F_s − F_c) exp(−|v/v_s|^δ), F = σ0 z + σ1 ż + σ2 v";
}

fn two<T: Float>() -> T {
    T::lit(2.0)
}

impl<T: Float> LuGreParams<T> {
    /// The Stribeck curve `g(v) = F_c + (F_s − F_c) exp(−|v/v_s|^δ)`
    /// (`> 0`, between `F_c` and `F_s`).
    pub fn stribeck(&self, v: T) -> T {
        self.f_c + (self.f_s - self.f_c) * (-(v / self.v_s).abs().powf(self.delta)).exp()
    }

    /// The steady-state friction force at constant velocity `v`:
    /// `g(v) sgn(v) + σ2 v` (0 at `v = 0`).
    pub fn steady_state(&self, v: T) -> T {
        if v == T::zero() {
            T::zero()
        } else {
            self.stribeck(v) * v.signum() + self.sigma2 * v
        }
    }
}

/// The committed state: last input, bristle deflection, last direction of
/// motion (`0` before any motion).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LuGreState<T> {
    x: T,
    z: T,
    dir: i8,
}

/// LuGre friction (Canudas de Wit, Olsson, Åström, Lischinsky 1995),
/// driven by position:
///
/// `dz/dt = v − σ0 |v| z / g(v)`,  `g(v) = F_c + (F_s − F_c) exp(−|v/v_s|^δ)`,
///
/// `F = σ0 z + σ1 dz/dt + σ2 v`,
///
/// with bristle deflection `z` and sliding velocity `v = ẋ`.
///
/// **Rate-dependent**: it holds its sample period `dt`. The input is a
/// position sampled every `dt`; between samples it is taken as linear, so
/// the velocity is constant over each sample, `v = (x_{k+1} − x_k)/dt`
/// (the same backward difference as [`ViscousDamper`](crate::ViscousDamper)).
/// With `v` constant the bristle equation is **linear** in `z`, and it is
/// integrated exactly over the sample:
///
/// `z_{k+1} = z_ss + (z_k − z_ss) exp(−σ0 |Δx| / g(v))`,  `z_ss = g(v) sgn(v) / σ0`
///
/// (the exponent is `σ0 |v| dt / g(v)`). There is no step-size error
/// beyond the piecewise-linear reading of the input and no stiffness
/// problem: any `dt` is stable, and `z_{k+1}` lies between `z_k` and
/// `z_ss` (clamped there against rounding), so
/// `|z| ≤ max(|z0|, max(F_c, F_s)/σ0)`.
///
/// The output uses the end-of-sample value of `dz/dt`, `σ0|v|/g(v) ·
/// (z_ss − z_{k+1})`: `F_{k+1}` is the model's force at `t_{k+1}` (the left
/// limit) for the linearly interpolated input, exactly. At constant
/// velocity from rest this gives the closed form
/// `z = (g/σ0)(1 − exp(−σ0 x/g))` (pre-sliding stiffness `σ0` for small
/// `x`, steady sliding at `g(v) sgn(v) + σ2 v`, the Stribeck curve).
/// Against a smooth input path the error is that of the interpolation:
/// first order in `dt` when `σ1` or `σ2` is non-zero (`v` is the mean
/// velocity over the sample, not the velocity at its end).
///
/// The tangent `dF/dx_{k+1}` is the exact derivative of this update
/// (negative where the Stribeck curve falls); at a standstill it is the
/// one-sided derivative in the last direction of motion (upward before
/// any motion). It starts at `x = 0`, `z = z0`, at rest. Parameters
/// `[sigma0, sigma1, sigma2, f_c, f_s, v_s, delta, z0]`; `dt` is fixed
/// ([`SamplePeriod::set_sample_period`](crate::SamplePeriod::set_sample_period)).
///
/// ```
/// use hysteron_operators::{LuGre, LuGreParams, Operator};
/// let p = LuGreParams {
///     sigma0: 1e5, sigma1: 300.0, sigma2: 0.4, f_c: 1.0, f_s: 1.5,
///     v_s: 0.01, delta: 2.0, z0: 0.0, dt: 1e-3,
/// };
/// let mut f = LuGre::from_params(p).unwrap();
/// // constant velocity 0.02: steady sliding on the Stribeck curve
/// let x: Vec<f64> = (1..=1000).map(|i| 0.02 * i as f64 * 1e-3).collect();
/// let y = f.run(&x).unwrap();
/// assert!((y[999] - p.steady_state(0.02)).abs() < 1e-12);
/// ```
pub type LuGre<T> = Stepped<LuGreParams<T>, T>;

impl<T: Float> LuGre<T> {
    /// The committed bristle deflection `z`.
    pub fn bristle(&self) -> T {
        self.state().z
    }
}

impl<T: Float> LuGreParams<T> {
    #[inline(always)]
    fn advance(p: &LuGreParams<T>, s: &LuGreState<T>, x: T) -> (LuGreState<T>, T, T) {
        let one = T::one();
        let dx = x - s.x;
        let v = dx / p.dt;
        let dir = if dx > T::zero() {
            1
        } else if dx < T::zero() {
            -1
        } else {
            s.dir
        };
        let sign = if dir < 0 { -one } else { one };
        // Stribeck curve and h = v g'(v) (finite for every δ > 0).
        let r = (v / p.v_s).abs().powf(p.delta);
        let e = (-r).exp();
        // between F_c and F_s, also after rounding (the bristle bound uses it)
        let g = (p.f_c + (p.f_s - p.f_c) * e)
            .max(p.f_c.min(p.f_s))
            .min(p.f_c.max(p.f_s));
        let h = if e == T::zero() {
            T::zero() // also for r = ∞ (|v/v_s| overflowed), not ∞·0
        } else {
            -(p.f_s - p.f_c) * p.delta * r * e
        };
        // θ = σ0 |v| dt / g, the exponent over the sample.
        let theta = p.sigma0 * dx.abs() / g;
        let decay = (-theta).exp();
        let rise = -(-theta).exp_m1(); // 1 − e^{−θ}, accurate for small θ
        let z_ss = sign * g / p.sigma0;
        let (z, zdot) = if dx == T::zero() {
            (s.z, T::zero())
        } else {
            let z1 = s.z + (z_ss - s.z) * rise;
            let z1 = z1.max(s.z.min(z_ss)).min(s.z.max(z_ss));
            // dz/dt at the end of the sample: (σ0|v|/g)(z_ss − z1), with
            // z_ss − z1 = (z_ss − z_k) e^{−θ} taken without cancellation.
            let rate = theta / p.dt;
            (z1, (z_ss - s.z) * (rate * decay))
        };
        let force = p.sigma0 * z + p.sigma1 * zdot + p.sigma2 * v;
        // Tangent dF/dx_{k+1}; B = dθ/dx, Q = (1 − e^{−θ})/θ.
        let b = p.sigma0 * sign / g * (one - h / g);
        let q = if theta == T::zero() {
            one
        } else {
            rise / theta
        };
        let dz = (z_ss - s.z) * decay * b + q * h / g;
        let dzdot =
            (one - p.sigma0 * sign * z / g * (one - h / g)) / p.dt - p.sigma0 * v.abs() / g * dz;
        let tangent = p.sigma0 * dz + p.sigma1 * dzdot + p.sigma2 / p.dt;
        (LuGreState { x, z, dir }, force, tangent)
    }
}

impl<T: Float> StepLaw<T> for LuGreParams<T> {
    type State = LuGreState<T>;

    fn initial(&self) -> LuGreState<T> {
        LuGreState {
            x: T::zero(),
            z: self.z0,
            dir: 0,
        }
    }

    #[inline(always)]
    fn step(&self, s: &LuGreState<T>, x: T) -> Result<(LuGreState<T>, Trial<T>)> {
        let (s, output, tangent) = Self::advance(self, s, x);
        Ok((s, Trial { output, tangent }))
    }

    fn set_sample_period(&mut self, dt: T) -> Result<()> {
        check::set_positive("dt", &mut self.dt, dt)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::assert_trial_tangent;
    use crate::{Error, Operator};

    fn params() -> LuGreParams<f64> {
        LuGreParams {
            sigma0: 1e4,
            sigma1: 50.0,
            sigma2: 0.4,
            f_c: 1.0,
            f_s: 1.5,
            v_s: 0.01,
            delta: 2.0,
            z0: 0.0,
            dt: 1e-3,
        }
    }

    /// The tangent is the derivative of the update: central differences
    /// (step 1e-7 of the sample's travel; truncation O(h²), rounding
    /// ~1e-16·|F|/h) agree to 1e-5 relative.
    #[test]
    fn tangent_is_the_derivative_of_the_update() {
        for delta in [2.0, 1.0, 0.6] {
            for z0 in [0.0, 1e-4, -1.2e-4] {
                let p = LuGreParams {
                    delta,
                    z0,
                    ..params()
                };
                for dx in [3e-6, -2e-5, 1e-4, -8e-6, 5e-3] {
                    let mut f = LuGre::from_params(p).unwrap();
                    f.trial(0.25 * dx).unwrap();
                    f.commit();
                    let x = dx;
                    let case = format!("δ={delta} z0={z0} dx={dx}");
                    assert_trial_tangent(&mut f, x, 1e-7 * dx.abs(), 1e-5, &case);
                }
            }
        }
    }

    /// At a standstill the tangent is the one-sided derivative in the last
    /// direction: `σ0 (1 − s σ0 z/F_s) + σ1 (1 − s σ0 z/F_s)/dt + σ2/dt`.
    #[test]
    fn standstill_tangent() {
        let p = params();
        let mut f = LuGre::from_params(p).unwrap();
        f.run(&[-1e-5, -2e-5]).unwrap();
        let z = f.bristle();
        let t = f.trial(-2e-5).unwrap();
        let slope = 1.0 + p.sigma0 * z / p.f_s;
        let expected = p.sigma0 * slope + p.sigma1 * slope / p.dt + p.sigma2 / p.dt;
        assert!(
            (t.tangent - expected).abs() < 1e-9 * expected.abs(),
            "{} {expected}",
            t.tangent
        );
        assert_eq!(t.output, p.sigma0 * z);
    }

    #[test]
    fn invalid_parameters_are_typed_errors() {
        let p = params();
        for (q, name) in [
            (LuGreParams { sigma0: 0.0, ..p }, "sigma0"),
            (LuGreParams { sigma1: -1.0, ..p }, "sigma1"),
            (
                LuGreParams {
                    sigma2: f64::NAN,
                    ..p
                },
                "sigma2",
            ),
            (LuGreParams { f_c: 0.0, ..p }, "f_c"),
            (LuGreParams { f_s: -1.0, ..p }, "f_s"),
            (LuGreParams { v_s: 0.0, ..p }, "v_s"),
            (LuGreParams { delta: 0.0, ..p }, "delta"),
            (
                LuGreParams {
                    z0: f64::INFINITY,
                    ..p
                },
                "z0",
            ),
            (LuGreParams { dt: 0.0, ..p }, "dt"),
            (LuGreParams { dt: -1e-3, ..p }, "dt"),
        ] {
            match LuGre::from_params(q).unwrap_err() {
                Error::InvalidParameter { name: n, .. } => assert_eq!(n, name),
                other => panic!("{other}"),
            }
        }
        // F_s < F_c is allowed
        assert!(LuGre::from_params(LuGreParams { f_s: 0.5, ..p }).is_ok());
        // a velocity that overflows is an error, not a NaN
        let mut f = LuGre::from_params(LuGreParams { dt: 1e-300, ..p }).unwrap();
        assert!(matches!(f.trial(1e10), Err(Error::NonFiniteOutput { .. })));
    }
}
