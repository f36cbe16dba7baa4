//! A linear mass-spring-damper driven by force (rate-dependent).

use crate::{check, declare_params, CastScalar, Float, Result, StepLaw, Stepped, Trial};

declare_params! {
    /// Parameters of the [`MassSpringDamper`].
    pub struct MassSpringDamperParams<T>: Copy {
        /// Mass `m > 0`.
        m: T => Positive = 2.0,
        /// Viscous damping `c ≥ 0`.
        c: T => NonNegative = 10.0,
        /// Stiffness `k ≥ 0`.
        k: T => NonNegative = 5e4,
        /// Sample period `dt > 0` (s) until the structure above sets one
        /// ([`SamplePeriod::set_sample_period`](crate::SamplePeriod::set_sample_period)).
        /// Not a fitted parameter.
        dt: T => fixed = 1.0 / 15000.0,
    }
    check = |p| check::positive("dt", p.dt);
    law: "mass_spring_damper", "m ÿ + c ẏ + k y = u (input force u, output displacement y; Newmark average acceleration, step dt)";
}

/// The state of a [`MassSpringDamper`]: displacement, velocity and
/// acceleration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MsdState<T> {
    /// Displacement `y`.
    pub y: T,
    /// Velocity `ẏ`.
    pub v: T,
    /// Acceleration `ÿ`.
    pub a: T,
}

/// Linear single-degree-of-freedom oscillator driven by a force `u`, with
/// displacement output: `m ÿ + c ẏ + k y = u`.
///
/// **Rate-dependent**: it holds its sample period `dt`, and every sample
/// advances time by `dt`. Integration is Newmark's average-acceleration
/// rule (`γ = 1/2`, `β = 1/4`, the trapezoidal rule): unconditionally
/// stable, second-order accurate, no numerical damping (period elongation
/// `≈ (ω dt)²/12`). It is implicit with a direct feed-through:
///
/// `y_{k+1} = (u_{k+1} + m (4 y_k/dt² + 4 v_k/dt + a_k) + c (2 y_k/dt + v_k)) / k_eff`,
/// `k_eff = k + 2c/dt + 4m/dt²`,
///
/// so the tangent is `dy/du = 1/k_eff` and the operator can sit in an
/// implicit loop ([`Feedback`] in `hysteron-composition`). It starts at rest
/// (`y = v = a = 0`, `u = 0`). Parameters `[m, c, k]`; `dt` is fixed
/// ([`SamplePeriod::set_sample_period`](crate::SamplePeriod::set_sample_period)).
///
/// In a combinator with rate-independent operators the whole model becomes
/// rate-dependent: its samples must be spaced by `dt`.
///
/// [`Feedback`]: https://docs.rs/hysteron-composition
///
/// ```
/// use hysteron_operators::{MassSpringDamper, Operator};
/// // a constant force settles at u / k
/// let mut msd = MassSpringDamper::new(1.0_f64, 4.0, 100.0, 1e-3).unwrap();
/// let y = msd.run(&vec![5.0; 20_000]).unwrap();
/// assert!((y[19_999] - 0.05).abs() < 1e-9);
/// ```
pub type MassSpringDamper<T> = Stepped<MassSpringDamperParams<T>, T>;

impl<T: Float> MassSpringDamper<T> {
    /// An oscillator with mass `m`, damping `c`, stiffness `k` and sample
    /// period `dt`, at rest.
    pub fn new(m: T, c: T, k: T, dt: T) -> Result<Self> {
        Self::from_params(MassSpringDamperParams { m, c, k, dt })
    }

    /// An oscillator from validated parameters.
    /// The committed velocity.
    pub fn velocity(&self) -> T {
        self.state().v
    }
}

/// The constants of a [`MassSpringDamper`]'s step: `q = 2/dt`, `q²` and
/// `k_eff = k + q c + q² m` (`= k + 2c/dt + 4m/dt²`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewmarkTerms<T> {
    /// `q = 2/dt`.
    pub q: T,
    /// `q²`.
    pub q2: T,
    /// `k_eff = k + q c + q² m`, the inverse of the tangent `dy/du`.
    pub k_eff: T,
}

impl<T: Float> MassSpringDamperParams<T> {
    /// The step's constants ([`NewmarkTerms`]).
    #[inline(always)]
    pub fn newmark_terms(&self) -> NewmarkTerms<T> {
        let MassSpringDamperParams { m, c, k, dt } = *self;
        // The equations of the type's doc with `q = 2/dt` (so `4/dt = 2q`,
        // `4/dt² = q²`): two divisions where the terms as written take
        // eight, each of which costs a pass over every derivative over
        // dual numbers.
        let q = T::lit(2.0) / dt;
        let q2 = q * q;
        NewmarkTerms {
            q,
            q2,
            k_eff: k + q * c + q2 * m,
        }
    }

    /// One Newmark average-acceleration step from state `s` under the
    /// force `u`, with the constants `t` of [`newmark_terms`](Self::newmark_terms):
    /// the next state (the equations of [`MassSpringDamper`]), unchecked.
    /// The [`step`](StepLaw::step) of the oscillator, which refuses a state
    /// that is not finite; a kernel that steps many oscillators calls it,
    /// with the constants computed once, for the same bits.
    ///
    /// ```
    /// use hysteron_operators::{MassSpringDamperParams, MsdState};
    /// let p = MassSpringDamperParams { m: 1.0, c: 0.0, k: 4.0, dt: 0.5 };
    /// let rest = MsdState { y: 0.0, v: 0.0, a: 0.0 };
    /// let t = p.newmark_terms();
    /// assert_eq!((t.k_eff, p.newmark(&t, &rest, 24.0).y), (20.0, 1.2));
    /// ```
    #[inline(always)]
    pub fn newmark(&self, t: &NewmarkTerms<T>, s: &MsdState<T>, u: T) -> MsdState<T> {
        let MassSpringDamperParams { m, c, dt, .. } = *self;
        let NewmarkTerms { q, q2, k_eff } = *t;
        let MsdState { y, v, a } = *s;
        let two_v = v + v;
        let p_eff = u + m * (q2 * y + q * two_v + a) + c * (q * y + v);
        let y1 = p_eff / k_eff;
        let a1 = q2 * (y1 - y) - q * two_v - a;
        let v1 = v + dt * T::lit(0.5) * (a + a1);
        MsdState {
            y: y1,
            v: v1,
            a: a1,
        }
    }
}

impl<T: Float> StepLaw<T> for MassSpringDamperParams<T> {
    type State = MsdState<T>;

    fn initial(&self) -> MsdState<T> {
        MsdState {
            y: T::zero(),
            v: T::zero(),
            a: T::zero(),
        }
    }

    #[inline(always)]
    fn step(&self, s: &MsdState<T>, u: T) -> Result<(MsdState<T>, Trial<T>)> {
        let t = self.newmark_terms();
        let next = self.newmark(&t, s, u);
        if !(next.a.is_finite() && next.v.is_finite()) {
            return Err(crate::Error::NonFiniteOutput {
                operator: <Self as crate::Declared<T>>::KIND,
                input: u.as_f64(),
            });
        }
        Ok((
            next,
            Trial {
                output: next.y,
                tangent: T::one() / t.k_eff,
            },
        ))
    }

    /// [`step`](StepLaw::step) over `f64` on the values of the parameters
    /// and the state: the same operations on the same values.
    fn step_value(&self, s: &MsdState<T>, x: f64) -> Option<Result<Trial<f64>>> {
        let v = |t: T| t.as_f64();
        let law: MassSpringDamperParams<f64> = self.cast_scalar();
        let s = MsdState {
            y: v(s.y),
            v: v(s.v),
            a: v(s.a),
        };
        Some(law.step(&s, x).map(|(_, t)| t))
    }

    fn fold_probe(&self, s: &mut MsdState<T>, along: &T) -> bool {
        if !self.dt.probe_free() {
            return false;
        }
        for v in [&mut s.y, &mut s.v, &mut s.a] {
            v.fold_probe(along);
        }
        true
    }

    fn set_sample_period(&mut self, dt: T) -> Result<()> {
        check::set_positive("dt", &mut self.dt, dt)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Operator;

    /// Displacement at t = 0.5 s for the smooth force u(t) = 1 − cos(20 t),
    /// integrated with step `dt`.
    fn end_value(dt: f64) -> f64 {
        let mut msd = MassSpringDamper::new(2.0, 3.0, 5e3, dt).unwrap();
        let n = (0.5 / dt).round() as usize;
        let u: Vec<f64> = (1..=n)
            .map(|i| 1.0 - (20.0 * i as f64 * dt).cos())
            .collect();
        *msd.run(&u).unwrap().last().unwrap()
    }

    #[test]
    fn second_order_convergence() {
        // Against a run with a 64× finer step: errors fall 4× per halving.
        let reference = end_value(1e-3 / 64.0);
        let e: Vec<f64> = [1e-3, 5e-4, 2.5e-4]
            .iter()
            .map(|&dt| (end_value(dt) - reference).abs())
            .collect();
        let (r1, r2) = (e[0] / e[1], e[1] / e[2]);
        assert!(
            r1 > 3.6 && r1 < 4.4 && r2 > 3.6 && r2 < 4.4,
            "ratios {r1} {r2} ({e:?})"
        );
    }

    #[test]
    fn tangent_is_the_feed_through() {
        let mut msd = MassSpringDamper::new(2.0_f64, 10.0, 5e4, 1.0 / 15000.0).unwrap();
        msd.trial(3.0).unwrap();
        msd.commit();
        let a = msd.trial(1.0).unwrap();
        let b = msd.trial(1.0 + 1e-3).unwrap();
        assert!(
            ((b.output - a.output) / 1e-3 - a.tangent).abs() < 1e-12 * a.tangent.abs().max(1e-12)
        );
    }
}
