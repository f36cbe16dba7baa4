//! Friction whose sliding levels carry a reversal transient: after each
//! change of slip direction the level starts off its steady value and
//! relaxes toward it with the slip.

use crate::{check, declare_params, Float, Result, StepLaw, Stepped, Trial};

declare_params! {
    /// Parameters of the [`TransientFriction`] element.
    pub struct TransientFrictionParams<T>: Copy {
        /// Spring stiffness `k > 0`.
        k: T => Positive = 4.0,
        /// Steady sliding level in the positive direction, `f_pos ≥ 0`.
        f_pos: T => NonNegative = 1.5,
        /// Steady sliding level in the negative direction, `f_neg ≥ 0`.
        f_neg: T => NonNegative = 1.0,
        /// Relative excess of the positive level at the onset of positive
        /// slip, `a_pos ≥ −1`: the level is `f_pos (1 + a_pos)` there (a
        /// breakaway peak for `a_pos > 0`, a dip for `a_pos < 0`). With
        /// `a_pos > 0`, `a_pos f_pos < k λ` (the level may not soften faster
        /// than the spring stiffens).
        a_pos: T => AtLeast(-1.0) = 0.3,
        /// Relative excess of the negative level at the onset of negative
        /// slip, `a_neg ≥ −1` (as `a_pos`).
        a_neg: T => AtLeast(-1.0) = -0.3,
        /// Slip constant `λ > 0` (input units; `lam`, as `lambda` is a
        /// keyword in Python): the excess decays as `e^{−u/λ}` with the
        /// slip `u` since the onset.
        lam: T => Positive = 0.5,
        /// Force at input `x = 0` before the first sample (default 0), one
        /// the element can hold: in `[−f_neg (1 + a_neg), f_pos (1 + a_pos)]`.
        #[serde(default)]
        f0: T => Real = 0.0,
    }
    check = TransientFrictionParams::consistent;
    law: "transient_friction", "F = k · (x − x_p), x_p moving only to keep −L_neg(u) ≤ F ≤ L_pos(u), L(u) = f (1 + a e^{−u/λ}) with u the slip since the last change of slip direction";
}

impl<T: Float> TransientFrictionParams<T> {
    /// `f0` holdable, every level over `k` representable, and a level that
    /// does not soften faster than the spring stiffens: `a f < k λ`.
    fn consistent(&self) -> Result<()> {
        let (onset_pos, onset_neg) = (self.level(1, T::zero()), self.level(-1, T::zero()));
        if self.f0 > onset_pos || self.f0 < -onset_neg {
            return Err(check::invalid(
                "f0",
                self.f0,
                "must lie in [−f_neg (1 + a_neg), f_pos (1 + a_pos)] (a force the element can hold)",
            ));
        }
        for (name, f, a) in [
            ("a_pos", self.f_pos, self.a_pos),
            ("a_neg", self.f_neg, self.a_neg),
        ] {
            if a > T::zero() && a * f >= self.k * self.lam {
                return Err(check::invalid(
                    name,
                    a,
                    "with a > 0, a · f must be below k · lam (the level may not soften faster than the spring stiffens)",
                ));
            }
        }
        check::level_over_stiffness("f_pos", self.f_pos, self.k)?;
        check::level_over_stiffness("f_neg", self.f_neg, self.k)?;
        check::start_over_stiffness(self.f0, self.k)?;
        Ok(())
    }

    /// The level `L(u) = f (1 + a e^{−u/λ})` of direction `dir` (`±1`)
    /// after a slip `u` since its onset.
    #[inline(always)]
    fn level(&self, dir: i8, u: T) -> T {
        let (f, a) = self.direction(dir);
        f * (T::one() + a * (-u / self.lam).exp())
    }

    /// `(f, a)` of direction `dir`: positive for `dir > 0`, else negative.
    #[inline(always)]
    fn direction(&self, dir: i8) -> (T, T) {
        if dir > 0 {
            (self.f_pos, self.a_pos)
        } else {
            (self.f_neg, self.a_neg)
        }
    }

    /// The slip `Δ > 0` of one step sliding in direction `dir` with elastic
    /// stretch `e` (measured in that direction, `k e > L(u0)`) from a slip
    /// `u0` since the onset: the root of
    ///
    /// `g(Δ) = k (e − Δ) − L(u0 + Δ)`,
    ///
    /// strictly decreasing (`g' = −k − L' < 0` by `a f < k λ`), with `g(0) >
    /// 0` and `g ≤ 0` at `e − f min(1, 1 + a)/k`. The root is found on
    /// values by safeguarded Newton (bisection where a step leaves the
    /// bracket) to a few ulps; one more Newton step in `T` from it carries
    /// the derivatives (the implicit function theorem:
    /// `∂Δ = −∂g / g'` at the root). Returns `(Δ, dL/du at u0 + Δ)`.
    fn slip(&self, dir: i8, e: T, u0: T) -> (T, T) {
        let (f, a) = self.direction(dir);
        let (k, lam) = (self.k, self.lam);
        let g = |d: T| {
            let decay = (-(u0 + d) / lam).exp();
            let value = k * (e - d) - f * (T::one() + a * decay);
            let slope = -f * a * decay / lam; // L'(u0 + d)
            (value, slope)
        };
        let (kv, fv, av, ev) = (k.as_f64(), f.as_f64(), a.as_f64(), e.as_f64());
        let (u0v, lv) = (u0.as_f64(), lam.as_f64());
        let gv = |d: f64| {
            let decay = (-(u0v + d) / lv).exp();
            (
                kv * (ev - d) - fv * (1.0 + av * decay),
                -fv * av * decay / lv,
            )
        };
        let (mut lo, mut hi) = (0.0_f64, (ev - fv * (1.0 + av.min(0.0)) / kv).max(0.0));
        let mut d = (ev - fv * (1.0 + av * (-u0v / lv).exp()) / kv).clamp(lo, hi);
        for _ in 0..200 {
            let (value, slope) = gv(d);
            if value > 0.0 {
                lo = d;
            } else {
                hi = d;
            }
            let newton = d + value / (kv + slope);
            let next = if newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
            let settled = (next - d).abs() <= 4.0 * f64::EPSILON * d.abs().max(ev.abs());
            d = next;
            if settled || hi - lo <= 4.0 * f64::EPSILON * hi.abs() {
                break;
            }
        }
        let d = T::lit(d);
        let (value, slope) = g(d);
        let d = d + value / (k + slope);
        let (_, slope) = g(d);
        (d, slope)
    }
}

/// The state between samples: the slip position `x_p`, the slip `u` since
/// the last change of slip direction, and that direction (`+1`, `−1`, or
/// `0` before the first slip).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TransientFrictionState<T> {
    /// Slip position `x_p`: `F = k (x − x_p)`.
    pub x_p: T,
    /// Slip `u ≥ 0` since the onset of slip in `dir`.
    pub u: T,
    /// Direction of the last slip: `1`, `−1`, or `0` before any.
    pub dir: i8,
}

/// Elastoplastic element whose sliding levels carry a reversal transient:
/// a massless block pulled through a linear spring over a surface whose
/// resistance, after the block starts to slide in a new direction, starts
/// at `f (1 + a)` and relaxes toward its steady value `f` with the slip
/// (the excess static friction of a brake, the run-in of a band after
/// each reversal),
///
/// `F = k · (x − x_p)`,  `−L_neg(u) ≤ F ≤ L_pos(u)`,
/// `L_±(u) = f_± (1 + a_± e^{−u/λ})`,
///
/// where the slip `x_p` moves only as far as needed to keep the force in
/// that interval, and `u` is the slip since the last change of slip
/// direction: sliding on in one direction after sticking keeps `u`,
/// sliding the other way starts it at 0 (so does the first slip).
/// Starting slip: `x_p = −f0/k`.
///
/// While sliding, each sample solves `k (x − x_p − Δ) = L(u + Δ)` for the
/// slip `Δ` (safeguarded Newton on values to a few ulps, then one Newton
/// step in the scalar type for the derivatives); the tangent is
/// `k L'/(k + L')`, negative on a softening breakaway. The root is unique
/// because the level may not soften faster than the spring stiffens
/// (`a f < k λ`, checked). The law is rate-independent: the slip after a
/// monotone stretch of input depends only on where it ends, so
/// intermediate samples change the result by rounding only. With
/// `a_pos = a_neg = 0` it is the [`AsymmetricFriction`](crate::AsymmetricFriction)
/// element, to rounding.
///
/// ```
/// use hysteron_operators::{Operator, TransientFriction};
/// // k = 10, steady levels 1, a breakaway 50 % above them, relaxing over 0.2
/// let mut f = TransientFriction::new(10.0_f64, 1.0, 1.0, 0.5, 0.2).unwrap();
/// let y = f.run(&[0.1, 0.15, 0.5, 3.0]).unwrap();
/// assert_eq!(y[0], 1.0); // sticking: k x
/// assert!((y[1] - 1.5).abs() < 1e-12); // at the breakaway level
/// assert!(y[2] < 1.5 && y[2] > 1.0); // relaxing with the slip
/// assert!((y[3] - 1.0).abs() < 1e-5); // steady after a long slide
/// ```
pub type TransientFriction<T> = Stepped<TransientFrictionParams<T>, T>;

impl<T: Float> TransientFriction<T> {
    /// An element with stiffness `k`, steady levels `f_pos, f_neg`, the
    /// same relative excess `a` at the onset of slip in either direction
    /// and slip constant `lam`, unloaded.
    pub fn new(k: T, f_pos: T, f_neg: T, a: T, lam: T) -> Result<Self> {
        Self::from_params(TransientFrictionParams {
            k,
            f_pos,
            f_neg,
            a_pos: a,
            a_neg: a,
            lam,
            f0: T::zero(),
        })
    }
}

impl<T: Float> StepLaw<T> for TransientFrictionParams<T> {
    type State = TransientFrictionState<T>;

    fn initial(&self) -> TransientFrictionState<T> {
        TransientFrictionState {
            x_p: -(self.f0 / self.k),
            u: T::zero(),
            dir: 0,
        }
    }

    fn step(
        &self,
        s: &TransientFrictionState<T>,
        x: T,
    ) -> Result<(TransientFrictionState<T>, Trial<T>)> {
        let k = self.k;
        let e = x - s.x_p;
        // The direction the spring pulls, and the slip since that direction's onset.
        let dir: i8 = if e > T::zero() { 1 } else { -1 };
        let u0 = if s.dir == dir { s.u } else { T::zero() };
        let stretch = if dir > 0 { e } else { -e };
        if k * stretch <= self.level(dir, u0) {
            return Ok((
                *s,
                Trial {
                    output: k * e,
                    tangent: k,
                },
            ));
        }
        let (d, slope) = self.slip(dir, stretch, u0);
        let sign = if dir > 0 { T::one() } else { -T::one() };
        let x_p = s.x_p + sign * d;
        Ok((
            TransientFrictionState {
                x_p,
                u: u0 + d,
                dir,
            },
            Trial {
                output: k * (x - x_p),
                tangent: k * slope / (k + slope),
            },
        ))
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::indexing_slicing)]
    use super::*;
    use crate::test_support::{refinement_difference, step_difference};
    use crate::{AsymmetricFriction, Operator};

    fn element(a_pos: f64, a_neg: f64, lam: f64) -> TransientFriction<f64> {
        TransientFriction::from_params(TransientFrictionParams {
            k: 10.0,
            f_pos: 1.5,
            f_neg: 1.0,
            a_pos,
            a_neg,
            lam,
            f0: 0.0,
        })
        .unwrap()
    }

    fn cycles(n: usize) -> Vec<f64> {
        (0..n)
            .map(|i| {
                let t = i as f64 / n as f64;
                (2.0 - 1.5 * t) * (std::f64::consts::TAU * 3.0 * t).sin() + 0.2 * (37.0 * t).sin()
            })
            .collect()
    }

    /// With no transient it is the asymmetric element, to rounding.
    #[test]
    fn without_a_transient_it_is_the_asymmetric_element() {
        let x = cycles(3_000);
        let y = element(0.0, 0.0, 0.3).run(&x).unwrap();
        let want = AsymmetricFriction::new(10.0, 1.5, 1.0)
            .unwrap()
            .run(&x)
            .unwrap();
        for (i, (a, b)) in y.iter().zip(&want).enumerate() {
            assert!((a - b).abs() <= 1e-14, "sample {i}: {a} vs {b}");
        }
    }

    /// While sliding the force is on the level of the slip since the onset:
    /// `F = f (1 + a e^{−u/λ})`, with `u` the slip position's travel.
    #[test]
    fn sliding_force_follows_the_closed_form_level() {
        let mut op = element(0.4, -0.3, 0.2);
        let x: Vec<f64> = (0..=400).map(|i| 0.01 * i as f64).collect();
        let y = op.run(&x).unwrap();
        let p = op.parameters();
        // the onset: F = k x reaches f_pos (1 + a_pos) = 2.1 at x = 0.21
        for (&xi, &yi) in x.iter().zip(&y) {
            if xi <= 0.2 {
                assert_eq!(yi, 10.0 * xi);
            } else if xi >= 0.22 {
                // slip u = x − F/k (x_p starts at 0)
                let u = xi - yi / p.k;
                let level = p.f_pos * (1.0 + p.a_pos * (-u / p.lam).exp());
                assert!((yi - level).abs() <= 1e-13, "x = {xi}: {yi} vs {level}");
            }
        }
    }

    /// Refining the sampling of the same path changes the output at the
    /// shared samples by rounding only: rate-independent.
    #[test]
    fn refining_the_sampling_changes_nothing_but_rounding() {
        let (i, d) = refinement_difference(&element(0.3, -0.2, 0.1), &cycles(500), 7);
        assert!(d <= 1e-12, "sample {i}: {d:e}");
    }

    /// A reversal restarts the transient; sliding on after a stick keeps it.
    #[test]
    fn only_a_change_of_slip_direction_restarts_the_transient() {
        let mut op = element(0.5, 0.5, 0.1);
        // slide forward far: steady level 1.5
        op.run(&[0.5, 2.0]).unwrap();
        // unload a little (stick), load again: slides on at the steady level
        let y = op.run(&[1.95, 2.1]).unwrap();
        assert!((y[1] - 1.5).abs() < 1e-6, "{}", y[1]);
        // x_p = 2.1 − 1.5/k = 1.95; the negative onset level is
        // f_neg (1 + a_neg) = 1.5, reached at x = 1.8: sticking just before
        let y = op.run(&[1.801, 1.79]).unwrap();
        // (the forward level is 1.5 + 0.75 e^{−u/λ}, u ≈ 1.9: 4e-9 above 1.5)
        assert!((y[0] + 1.49).abs() < 1e-7, "{}", y[0]);
        // just past it the element slides near the onset level, far above
        // the steady 1.0: the transient restarted
        let u = op.state().u;
        assert!(u > 0.0 && u < 0.05, "{u}");
        let level = 1.0 * (1.0 + 0.5 * (-u / 0.1).exp());
        assert!((y[1] + level).abs() < 1e-12, "{} vs {level}", y[1]);
        assert!(y[1] < -1.4, "{}", y[1]);
    }

    #[test]
    fn a_level_that_softens_faster_than_the_spring_is_rejected() {
        let e = TransientFriction::<f64>::new(10.0, 1.0, 1.0, 2.0, 0.2).unwrap_err();
        assert!(e.to_string().contains("a_pos"), "{e}");
        let e = TransientFriction::<f64>::from_params(TransientFrictionParams {
            f0: 1.6,
            ..*element(0.0, 0.0, 1.0).parameters()
        })
        .unwrap_err();
        assert!(e.to_string().contains("f0"), "{e}");
    }

    /// The tangent is the derivative of the output: a central difference
    /// of one step from the same state.
    #[test]
    fn tangent_is_the_step_derivative() {
        let p = *element(0.4, 0.2, 0.3).parameters();
        let s = TransientFrictionState {
            x_p: 0.1,
            u: 0.05,
            dir: 1,
        };
        for x in [0.2, 0.4, 0.6, -0.1, -0.3] {
            let (_, t) = p.step(&s, x).unwrap();
            let fd = step_difference(&p, &s, x, 1e-7);
            assert!(
                (t.tangent - fd).abs() <= 1e-6 * (1.0 + fd.abs()),
                "x = {x}: {} vs {fd}",
                t.tangent
            );
        }
    }
}
