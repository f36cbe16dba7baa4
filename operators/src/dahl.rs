//! The Dahl friction model, in closed form per branch.

use crate::{check, declare_params, reversal, Float, Result, StepLaw, Stepped, Trial};

declare_params! {
    /// Parameters of the [`Dahl`] friction operator.
    pub struct DahlParams<T>: Copy {
        /// Rest stiffness `σ > 0` (slope `dF/dx` at `F = 0`), force per input unit.
        sigma: T => Positive = 40.0,
        /// Coulomb friction level `F_c > 0`.
        f_c: T => Positive = 1.5,
        /// Shape exponent `α ≥ 0` (Dahl: 1 for most materials; 0 gives the
        /// elastoplastic element, larger values a rounder approach).
        alpha: T => NonNegative = 1.5,
        /// Friction force at input `x = 0` before the first sample (default 0).
        /// With `|f0| ≤ F_c` the force stays in `[−F_c, F_c]`.
        #[serde(default)]
        f0: T => Real = 0.3,
    }
    check = DahlParams::ratios;
    law: "dahl", "dF/dx = σ |1 − (F/F_c) sgn ẋ|^α sgn(1 − (F/F_c) sgn ẋ)";
}

impl<T: Float> DahlParams<T> {
    /// `σ/F_c` and `f0/F_c` must be finite.
    fn ratios(&self) -> Result<()> {
        if !(self.sigma / self.f_c).is_finite() {
            return Err(check::invalid(
                "sigma",
                self.sigma,
                "σ / F_c must be finite",
            ));
        }
        if !(self.f0 / self.f_c).is_finite() {
            return Err(check::invalid("f0", self.f0, "f0 / F_c must be finite"));
        }
        Ok(())
    }
}

/// The committed state: last input and output, the start of the current
/// branch and its direction (`0` before any motion).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DahlState<T> {
    x: T,
    f: T,
    x_r: T,
    f_r: T,
    dir: i8,
}

/// The distance to saturation after travel: `|w|` for `|w_r| = a` and
/// scaled travel `u = (σ/F_c)·|x − x_r|`, from
/// `d|w|/du = −|w|^α`:
///
/// * `α = 1`: `a e^{−u}` (over dual numbers with `α` seeded, the first
///   order in `ε`: `a exp(−u + ε (u ln a − u²/2))`, so that `∂/∂α` is the
///   general form's limit);
/// * `α ≠ 1` (`ε = 1 − α`): `|w|^ε = a^ε − ε u`, evaluated as
///   `a · exp(ln(1 − ε u a^{−ε}) / ε)` (accurate for `α` near 1), and 0
///   once `ε u a^{−ε} ≥ 1` (`α < 1` reaches saturation in finite travel).
#[inline(always)]
fn decay<T: Float>(a: T, u: T, alpha: T) -> T {
    if a == T::zero() || (u == T::zero() && !u.has_derivatives()) {
        return a;
    }
    if !u.is_finite() {
        return T::zero();
    }
    let eps = T::one() - alpha;
    if eps == T::zero() {
        if alpha.has_derivatives() {
            // Over dual numbers at α = 1: the first order in ε of the
            // general form, `a exp(−u + ε (u ln a − u²/2))`, whose value is
            // the closed form's and whose ∂/∂α is the limit of the general
            // form's.
            let two = T::lit(2.0);
            return a * (-u + eps * (u * a.ln() - u * u / two)).exp();
        }
        return a * (-u).exp();
    }
    let c = eps * u * a.powf(-eps);
    if c >= T::one() {
        return T::zero();
    }
    let l = if c.is_finite() {
        (-c).ln_1p()
    } else {
        // α > 1 and c = −∞ by overflow: ln(1 + |c|) = ln|c| to within
        // 1/|c|, taken in logarithms.
        (-eps).ln() + u.ln() - eps * a.ln()
    };
    a * (l / eps).exp()
}

/// Dahl friction (Dahl 1968), written in the input domain:
///
/// `dF/dx = σ |1 − (F/F_c) sgn(ẋ)|^α sgn(1 − (F/F_c) sgn(ẋ))`.
///
/// Dahl's model is usually written in time, `dF/dt = σ (1 − (F/F_c)
/// sgn(v))^α v`; the velocity enters only through `v = ẋ`, so dividing by
/// `ẋ` gives the form above: the model is **rate-independent** (a
/// hysteresis operator with local memory, like [`Mms`](crate::Mms)), and
/// that is how it is implemented. It has no static (stiction) force and no
/// Stribeck effect; see [`LuGre`](crate::LuGre) for those.
///
/// With `s = sgn(ẋ)` and `w = 1 − s F/F_c` (the scaled distance to the
/// Coulomb level `s F_c`), each branch since the last reversal at
/// `(x_r, F_r)` has a closed form in the travel `u = (σ/F_c) |x − x_r|`:
/// `|w|` decreases with `d|w|/du = −|w|^α` and `w` keeps its sign, so
///
/// * `α = 1`: `w = w_r e^{−u}`, i.e.
///   `F = s F_c − (s F_c − F_r) exp(−σ |x − x_r| / F_c)`;
/// * `α ≠ 1`: `|w|^{1−α} = |w_r|^{1−α} − (1 − α) u` (linear in `x`), and
///   for `α < 1`, `w = 0` (sliding at `s F_c`) from `u = |w_r|^{1−α}/(1−α)`
///   on; `α = 0` is the elastoplastic element with stiffness `σ`.
///
/// No ODE is integrated, so the operator is exactly rate-independent: the
/// output depends only on the branch start and the input. Each branch is
/// monotone from `F_r` towards `s F_c` (clamped to that interval against
/// rounding), so `|F| ≤ F_c` whenever `|f0| ≤ F_c`. Tangent:
/// `dF/dx = σ |w|^α sgn(w)` on the branch of the current motion (at a
/// standstill that of continuing in the last direction, upward before any
/// motion). Parameters `[sigma, f_c, alpha, f0]`.
///
/// ```
/// use hysteron_operators::{Dahl, Operator};
/// let mut f = Dahl::new(100.0_f64, 2.0, 1.0).unwrap();
/// let y = f.run(&[0.01, 0.05]).unwrap();
/// // α = 1: F = F_c (1 − e^{−σ x / F_c})
/// assert!((y[1] - 2.0 * (1.0 - (-2.5_f64).exp())).abs() < 1e-15);
/// ```
pub type Dahl<T> = Stepped<DahlParams<T>, T>;

impl<T: Float> Dahl<T> {
    /// Dahl friction with rest stiffness `sigma`, Coulomb level `f_c` and
    /// exponent `alpha`, starting unloaded.
    pub fn new(sigma: T, f_c: T, alpha: T) -> Result<Self> {
        Self::from_params(DahlParams {
            sigma,
            f_c,
            alpha,
            f0: T::zero(),
        })
    }

    /// The committed friction force.
    pub fn output(&self) -> T {
        self.state().f
    }
}

impl<T: Float> DahlParams<T> {
    fn start(p: &DahlParams<T>) -> DahlState<T> {
        DahlState {
            x: T::zero(),
            f: p.f0,
            x_r: T::zero(),
            f_r: p.f0,
            dir: 0,
        }
    }

    /// One step from state `s` to input `x`: the new state and the tangent.
    #[inline(always)]
    fn advance(p: &DahlParams<T>, s: &DahlState<T>, x: T) -> (DahlState<T>, T) {
        let dir = reversal::travel(s.x, x, s.dir);
        let (x_r, f_r) = reversal::point(dir, s.dir, (s.x, s.f), (s.x_r, s.f_r));
        let sign = if dir < 0 { -T::one() } else { T::one() };
        let target = sign * p.f_c;
        let w_r = T::one() - sign * f_r / p.f_c;
        let u = p.sigma / p.f_c * (x - x_r).abs();
        let w = decay(w_r.abs(), u, p.alpha);
        let w = if w_r < T::zero() { -w } else { w };
        let f = if x == s.x {
            s.f
        } else {
            let v = target * (T::one() - w);
            v.max(f_r.min(target)).min(f_r.max(target))
        };
        let tangent = if w == T::zero() {
            T::zero()
        } else {
            let m = p.sigma * w.abs().powf(p.alpha);
            if w < T::zero() {
                -m
            } else {
                m
            }
        };
        (
            DahlState {
                x,
                f,
                x_r,
                f_r,
                dir,
            },
            tangent,
        )
    }
}

impl<T: Float> StepLaw<T> for DahlParams<T> {
    type State = DahlState<T>;

    fn initial(&self) -> DahlState<T> {
        Self::start(self)
    }

    #[inline(always)]
    fn step(&self, s: &DahlState<T>, x: T) -> Result<(DahlState<T>, Trial<T>)> {
        let (s, tangent) = Self::advance(self, s, x);
        let output = s.f;
        Ok((s, Trial { output, tangent }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::trial_difference;
    use crate::Parameters;
    use crate::{Error, Operator};

    #[test]
    fn decay_closed_forms() {
        // α = 2: |w| = a / (1 + a u); α = 0.5: |w| = (√a − u/2)²; α = 0:
        // a − u; each against the formula written out directly.
        for &(a, u) in &[(1.0_f64, 0.3_f64), (2.0, 1.7), (0.25, 0.01), (1.5, 4.0)] {
            let e2 = (decay(a, u, 2.0_f64) - a / (1.0 + a * u)).abs();
            let h = (a.sqrt() - u / 2.0).max(0.0);
            let e5 = (decay(a, u, 0.5) - h * h).abs();
            let e0 = (decay(a, u, 0.0) - (a - u).max(0.0)).abs();
            let e1 = (decay(a, u, 1.0) - a * (-u).exp()).abs();
            assert!(
                e2 < 4e-16 && e5 < 4e-16 && e0 < 4e-16 && e1 < 4e-16,
                "{a} {u}: {e2} {e5} {e0} {e1}"
            );
        }
        // α near 1 approaches the exponential continuously.
        let (a, u) = (1.3_f64, 2.0_f64);
        let near = decay(a, u, 1.0 + 1e-9);
        assert!((near - a * (-u).exp()).abs() < 1e-8, "{near}");
        // overflow of the α > 1 argument is taken in logarithms:
        // |w| = ((α−1) u)^{−1/(α−1)} when a^{1−α} is negligible.
        let big = decay(1.9, 3.0, 2000.0);
        let expected = (1999.0_f64 * 3.0).powf(-1.0 / 1999.0);
        assert!((big - expected).abs() < 1e-12, "{big} {expected}");
        // never negative, never NaN
        assert_eq!(decay(1.0, f64::INFINITY, 0.5), 0.0);
        assert_eq!(decay(0.0, 1.0, 0.5), 0.0);
    }

    /// The tangent is `dF/dx` of the branch: central differences (step
    /// 1e-7 of the travel; truncation O(h²), rounding ~1e-16·F_c/h) agree
    /// to 1e-6 relative, on rising and falling branches, from inside and
    /// beyond `F_c`.
    #[test]
    fn tangent_is_the_derivative_of_the_branch() {
        for alpha in [0.3_f64, 1.0, 1.7, 3.0] {
            for f0 in [0.0, 0.8, -1.6] {
                for (x_r, x) in [(0.0, 0.02), (0.05, 0.01), (-0.03, -0.07)] {
                    let p = DahlParams {
                        sigma: 40.0,
                        f_c: 1.5,
                        alpha,
                        f0,
                    };
                    let mut f = Dahl::from_params(p).unwrap();
                    f.trial(x_r).unwrap();
                    f.commit();
                    let t: f64 = f.trial(x).unwrap().tangent;
                    let fd = trial_difference(&mut f, x, 1e-7 * (x - x_r).abs());
                    assert!(
                        (t - fd).abs() < 1e-6 * t.abs().max(1.0),
                        "α={alpha} f0={f0} {x_r}→{x}: {t} vs {fd}"
                    );
                }
            }
        }
        // at a standstill: the tangent of continuing in the last direction
        let mut f = Dahl::new(40.0_f64, 1.5, 1.0).unwrap();
        f.run(&[0.02, 0.01]).unwrap();
        let y = f.output();
        let t = f.trial(0.01).unwrap();
        assert_eq!(t.output, y);
        assert!((t.tangent - 40.0 * (1.0 + y / 1.5)).abs() < 1e-12, "{t:?}");
    }

    #[test]
    fn invalid_parameters_are_typed_errors() {
        for (p, name) in [
            ([0.0, 1.0, 1.0, 0.0], "sigma"),
            ([1.0, -1.0, 1.0, 0.0], "f_c"),
            ([1.0, 1.0, -0.5, 0.0], "alpha"),
            ([1.0, 1.0, f64::NAN, 0.0], "alpha"),
            ([1.0, 1.0, 1.0, f64::INFINITY], "f0"),
            ([1e300, 1e-300, 1.0, 0.0], "sigma"),
            ([1.0, 1e-300, 1.0, 1e300], "f0"),
        ] {
            let e = Dahl::new(1.0, 1.0, 1.0)
                .unwrap()
                .set_params(&p)
                .unwrap_err();
            match e {
                Error::InvalidParameter { name: n, .. } => assert_eq!(n, name),
                other => panic!("{other}"),
            }
        }
    }
}
