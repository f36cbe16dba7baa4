//! A linear mass-spring-damper driven by force (rate-dependent).

use crate::{check, check_input, check_output, Domain, Float, Operator, Result, Trial};
use serde::{Deserialize, Serialize};

/// Parameters of the [`MassSpringDamper`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MassSpringDamperParams<T> {
    /// Mass `m > 0`.
    pub m: T,
    /// Viscous damping `c ≥ 0`.
    pub c: T,
    /// Stiffness `k ≥ 0`.
    pub k: T,
    /// Sample period `dt > 0` (s). Not a fitted parameter.
    pub dt: T,
}

impl<T: Float> MassSpringDamperParams<T> {
    /// Checks `m > 0`, `c ≥ 0`, `k ≥ 0`, `dt > 0`.
    pub fn validate(&self) -> Result<()> {
        check::positive("m", self.m)?;
        check::non_negative("c", self.c)?;
        check::non_negative("k", self.k)?;
        check::positive("dt", self.dt)
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct State<T> {
    y: T,
    v: T,
    a: T,
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
/// ([`set_dt`](Self::set_dt)).
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
#[derive(Debug, Clone, PartialEq)]
pub struct MassSpringDamper<T> {
    p: MassSpringDamperParams<T>,
    s: State<T>,
    pending: Option<State<T>>,
}

impl<T: Float> MassSpringDamper<T> {
    /// An oscillator with mass `m`, damping `c`, stiffness `k` and sample
    /// period `dt`, at rest.
    pub fn new(m: T, c: T, k: T, dt: T) -> Result<Self> {
        Self::from_params(MassSpringDamperParams { m, c, k, dt })
    }

    /// An oscillator from validated parameters.
    pub fn from_params(p: MassSpringDamperParams<T>) -> Result<Self> {
        p.validate()?;
        Ok(Self {
            p,
            s: Self::rest(),
            pending: None,
        })
    }

    fn rest() -> State<T> {
        State {
            y: T::zero(),
            v: T::zero(),
            a: T::zero(),
        }
    }

    /// The parameters.
    pub fn parameters(&self) -> &MassSpringDamperParams<T> {
        &self.p
    }

    /// Changes the sample period (`dt > 0`) and resets.
    pub fn set_dt(&mut self, dt: T) -> Result<()> {
        *self = Self::from_params(MassSpringDamperParams { dt, ..self.p })?;
        Ok(())
    }

    /// The committed velocity.
    pub fn velocity(&self) -> T {
        self.s.v
    }

    #[inline(always)]
    fn k_eff(&self) -> T {
        let MassSpringDamperParams { m, c, k, dt } = self.p;
        let four = T::lit(4.0);
        k + T::lit(2.0) * c / dt + four * m / (dt * dt)
    }
}

impl<T: Float> Operator<T> for MassSpringDamper<T> {
    fn name(&self) -> &'static str {
        "mass-spring-damper"
    }

    #[inline]
    fn trial(&mut self, u: T) -> Result<Trial<T>> {
        self.pending = None;
        let u = check_input(u)?;
        let MassSpringDamperParams { m, c, dt, .. } = self.p;
        let State { y, v, a } = self.s;
        let (two, four) = (T::lit(2.0), T::lit(4.0));
        let k_eff = self.k_eff();
        let p_eff = u + m * (four * y / (dt * dt) + four * v / dt + a) + c * (two * y / dt + v);
        let y1 = p_eff / k_eff;
        let a1 = four * (y1 - y) / (dt * dt) - four * v / dt - a;
        let v1 = v + dt / two * (a + a1);
        let t = check_output(
            "mass-spring-damper",
            u,
            Trial {
                output: y1,
                tangent: T::one() / k_eff,
            },
        )?;
        if !(a1.is_finite() && v1.is_finite()) {
            return Err(crate::Error::NonFiniteOutput {
                operator: "mass-spring-damper",
                input: u.as_f64(),
            });
        }
        self.pending = Some(State {
            y: y1,
            v: v1,
            a: a1,
        });
        Ok(t)
    }

    #[inline]
    fn commit(&mut self) {
        if let Some(s) = self.pending.take() {
            self.s = s;
        }
    }

    fn reset(&mut self) {
        self.s = Self::rest();
        self.pending = None;
    }

    fn n_params(&self) -> usize {
        3
    }

    fn params_into(&self, out: &mut Vec<T>) {
        out.extend([self.p.m, self.p.c, self.p.k]);
    }

    fn param_names(&self) -> Vec<String> {
        vec!["m".into(), "c".into(), "k".into()]
    }

    fn param_domains(&self) -> Vec<Domain> {
        vec![Domain::Positive, Domain::NonNegative, Domain::NonNegative]
    }

    fn set_params(&mut self, p: &[T]) -> Result<()> {
        check::count(3, p)?;
        *self = Self::from_params(MassSpringDamperParams {
            m: p[0],
            c: p[1],
            k: p[2],
            dt: self.p.dt,
        })?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
