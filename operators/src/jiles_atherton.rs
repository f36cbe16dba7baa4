//! The Jiles-Atherton model of ferromagnetic hysteresis (the classical,
//! field-driven formulation with the Langevin anhysteretic), integrated in
//! the field's travel to a tolerance.

use crate::ode::dopri5;
use crate::{check, declare_params, Error, Float, Result, StepLaw, Stepped, Trial};
use core::cell::Cell;

declare_params! {
    /// Parameters of the [`JilesAtherton`] model, in the units of the
    /// field `H` (input) and the magnetization `M` (output), e.g. A/m.
    pub struct JilesAthertonParams<T>: Copy {
        /// Saturation magnetization `Ms > 0` (output units).
        ms: T => Positive = 1.0,
        /// Shape of the anhysteretic curve `a > 0` (input units): the
        /// effective field over which it rises.
        a: T => Positive = 0.3,
        /// Pinning `k > 0` (input units): the width of the loops, about
        /// the coercive field.
        k: T => Positive = 0.5,
        /// Reversibility `c ∈ [0, 1]`: the share of the anhysteretic
        /// followed reversibly.
        c: T => UnitInterval = 0.2,
        /// Inter-domain coupling `α ≥ 0` (output to input units), with
        /// `α c Ms / (3 a) < 1`.
        alpha: T => NonNegative = 0.1,
    }
    check = JilesAthertonParams::coupling_below_one;
    law: "jiles_atherton", "M = c M_an + (1 − c) M_irr, M_an = Ms L((H + α M)/a), L(u) = coth u − 1/u, dM_irr/dH_e = δ_M (M_an − M_irr)/(δ k), δ = sgn Ḣ, δ_M = 1 where δ (M_an − M_irr) > 0 else 0";
}

impl<T: Float> JilesAthertonParams<T> {
    /// `α c Ms / (3 a) < 1`: at `H_e = 0` the reversible part alone would
    /// otherwise make `dM/dH` infinite (the coupling `α` feeds the
    /// magnetization back into the field faster than it grows).
    fn coupling_below_one(&self) -> Result<()> {
        let feedback = self.alpha * self.c * self.ms / (T::lit(3.0) * self.a);
        check::require(
            feedback < T::one(),
            "alpha",
            self.alpha,
            "alpha · c · ms / (3 a) must be < 1 (else dM/dH is infinite at zero field)",
        )
    }

    /// The anhysteretic magnetization `M_an = Ms L(H_e / a)` and its slope
    /// `dM_an/dH_e = (Ms / a) L'(H_e / a)`.
    #[inline(always)]
    fn anhysteretic(&self, he: T) -> (T, T) {
        let (l, dl) = langevin(he / self.a);
        (self.ms * l, self.ms / self.a * dl)
    }

    /// `δ (M_an − M_irr)` at the state: positive where the irreversible
    /// magnetization moves (`δ_M = 1`).
    #[inline(always)]
    fn lag(&self, dir: T, [h, m, m_irr]: &[T; 3]) -> T {
        dir * (self.anhysteretic(*h + self.alpha * *m).0 - *m_irr)
    }

    /// `(dM/dH, dM_irr/dH)` travelling in direction `dir`, with `δ_M = 1`
    /// where `moving`; `None` where `1 − α dM/dH_e ≤ 0` (the coupling
    /// makes the slope infinite or negative).
    #[inline(always)]
    fn slopes(&self, dir: T, moving: bool, [h, m, m_irr]: &[T; 3]) -> Option<(T, T)> {
        let (m_an, chi_an) = self.anhysteretic(*h + self.alpha * *m);
        let irr = if moving {
            dir * (m_an - *m_irr) / self.k
        } else {
            T::zero()
        };
        let dm = self.c * chi_an + (T::one() - self.c) * irr;
        let denominator = T::one() - self.alpha * dm;
        (denominator > T::zero()).then(|| (dm / denominator, irr / denominator))
    }

    /// The side of `δ (M_an − M_irr) = 0` the state is on: its sign beyond
    /// `snap`, else the moving side, which the flow enters from the
    /// surface (there `d/dH [δ (M_an − M_irr)] = dM_an/dH > 0`).
    fn moving(&self, dir: T, y: &[T; 3], snap: f64) -> bool {
        let lag = self.lag(dir, y).as_f64();
        lag > 0.0 || lag.abs() <= snap
    }

    /// The error where `1 − α dM/dH_e` reached 0.
    fn singular(&self) -> Error {
        check::invalid(
            "alpha",
            self.alpha,
            "alpha · dM/dH_e reached 1 on this input: the coupling makes dM/dH infinite (alpha too large for ms, a, k and c)",
        )
    }
}

/// The Langevin function `L(u) = coth u − 1/u` and its derivative
/// `L'(u) = 1/u² − 1/sinh² u`; by their series for `|u| < 0.1`, where the
/// differences cancel (to `u⁹` and `u⁸`: relative error below `1e-14`).
#[inline(always)]
pub(crate) fn langevin<T: Float>(u: T) -> (T, T) {
    let l = T::lit;
    if u.as_f64().abs() < 0.1 {
        let u2 = u * u;
        let value = u
            * (l(1.0 / 3.0)
                + u2 * (l(-1.0 / 45.0)
                    + u2 * (l(2.0 / 945.0) + u2 * (l(-1.0 / 4725.0) + u2 * l(2.0 / 93555.0)))));
        let slope = l(1.0 / 3.0)
            + u2 * (l(-1.0 / 15.0)
                + u2 * (l(2.0 / 189.0) + u2 * (l(-1.0 / 675.0) + u2 * l(2.0 / 10395.0))));
        (value, slope)
    } else {
        let sinh = u.sinh();
        let value = T::one() / u.tanh() - T::one() / u;
        let slope = T::one() / (u * u) - T::one() / (sinh * sinh);
        (value, slope)
    }
}

/// The state between samples: the field of the last sample, the
/// magnetization and its irreversible part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JilesAthertonState<T> {
    /// The field `H` of the last sample.
    pub h: T,
    /// The magnetization `M` there.
    pub m: T,
    /// Its irreversible part `M_irr`.
    pub m_irr: T,
}

/// The local error held per sub-step, relative to `Ms` (over `f64`; over
/// `f32`, `64 ε`).
const RTOL: f64 = 1e-11;

/// The Jiles-Atherton model (Jiles & Atherton 1986), driven by the
/// magnetic field `H`, output the magnetization `M`:
///
/// `M = c M_an + (1 − c) M_irr`,  `M_an = Ms L(H_e / a)`,
/// `H_e = H + α M`,  `L(u) = coth u − 1/u` (Langevin),
/// `dM_irr/dH_e = δ_M (M_an − M_irr) / (δ k)`,  `δ = sgn Ḣ`,
///
/// so that, with `dM/dH_e = c dM_an/dH_e + (1 − c) dM_irr/dH_e`,
///
/// `dM/dH = (dM/dH_e) / (1 − α dM/dH_e)`,
///
/// from the demagnetized state `H = M = M_irr = 0`. `δ_M` is 1 where
/// `δ (M_an − M_irr) > 0` and 0 elsewhere: just after a reversal the
/// irreversible part waits until the anhysteretic comes back to it,
/// instead of moving away from it, which would give the negative
/// differential susceptibility of the uncorrected model (the correction of
/// Jiles, Thoelke & Devine 1992). It is rate-independent: `M` depends on
/// the path of `H`, not on time. For the flux density, `B = μ0 (H + M)`
/// is a `parallel` of gains.
///
/// **Integration.** Each sample integrates `(H, M, M_irr)` over the field's
/// travel from the last sample by adaptive Dormand–Prince 5(4), each
/// sub-step's local error below `1e-11 Ms`, and each sub-step ending
/// where `δ_M` switches (the flow is continuous there but not smooth), so
/// that the derivatives are as accurate as the values; refining the
/// sampling changes the output by the tolerance only. The tangent is
/// `dM/dH` at the end of the step, in the direction travelled (upward at
/// the start).
///
/// **Errors.** Besides the parameters' domains, `α c Ms / (3 a) < 1` is
/// checked when it is built. Where an input drives `α dM/dH_e` to 1 (a
/// coupling too large for the other parameters), the sample's error names
/// `alpha`.
///
/// ```
/// use hysteron_operators::{JilesAtherton, JilesAthertonParams, Operator};
/// let p = JilesAthertonParams { ms: 1.0, a: 0.3, k: 0.5, c: 0.2, alpha: 0.1 };
/// let mut ja = JilesAtherton::from_params(p).unwrap();
/// // up to H = 3 and back just past H = 0
/// let h: Vec<f64> = (0..=64).map(|i| 3.0 * (i as f64 * 0.05).sin()).collect();
/// let m = ja.run(&h).unwrap();
/// assert!(m.iter().all(|v| v.abs() < 1.0)); // below saturation
/// assert!(h[64] < 0.0 && m[64] > 0.0); // remanence: M lags H
/// ```
///
/// Reference: D. C. Jiles and D. L. Atherton, "Theory of ferromagnetic
/// hysteresis", J. Magn. Magn. Mater. 61 (1986) 48–60; D. C. Jiles,
/// J. B. Thoelke and M. K. Devine, "Numerical determination of hysteresis
/// parameters for the modeling of magnetic properties using the theory of
/// ferromagnetic hysteresis", IEEE Trans. Magn. 28 (1992) 27–35.
pub type JilesAtherton<T> = Stepped<JilesAthertonParams<T>, T>;

impl<T: Float> StepLaw<T> for JilesAthertonParams<T> {
    type State = JilesAthertonState<T>;
    const RESTS_WHEN_HELD: bool = true;

    fn initial(&self) -> JilesAthertonState<T> {
        JilesAthertonState {
            h: T::zero(),
            m: T::zero(),
            m_irr: T::zero(),
        }
    }

    fn step(&self, s: &JilesAthertonState<T>, x: T) -> Result<(JilesAthertonState<T>, Trial<T>)> {
        let travel = x - s.h;
        let dir = if travel < T::zero() {
            -T::one()
        } else {
            T::one()
        };
        let ms = self.ms.as_f64();
        // what the scalar can resolve: f32 holds a looser tolerance
        let eps = T::epsilon().as_f64();
        let rtol = RTOL.max(64.0 * eps);
        let snap = 1e-9_f64.max(16.0 * eps) * ms;
        let singular = Cell::new(false);
        let start = [s.h, s.m, s.m_irr];
        let [_, m, m_irr] = if travel == T::zero() {
            start
        } else {
            let flow = |y: &[T; 3], moving: bool| match self.slopes(dir, moving, y) {
                Some((dm, dm_irr)) => [dir, dir * dm, dir * dm_irr],
                None => {
                    singular.set(true);
                    [T::nan(); 3]
                }
            };
            let sides = (
                |y: &[T; 3]| self.moving(dir, y, snap),
                |y: &[T; 3]| self.lag(dir, y).as_f64(),
                snap,
            );
            let h_scale = self.a.as_f64().max(x.as_f64().abs());
            let scale = |_: &[T; 3]| [h_scale, ms, ms];
            match dopri5(
                flow,
                sides,
                start,
                travel.abs(),
                scale,
                rtol,
                "jiles_atherton",
            ) {
                Ok(y) => y,
                Err(_) if singular.get() => return Err(self.singular()),
                Err(e) => return Err(e),
            }
        };
        let end = [x, m, m_irr];
        let (tangent, _) = self
            .slopes(dir, self.moving(dir, &end, 0.0), &end)
            .ok_or_else(|| self.singular())?;
        let next = JilesAthertonState { h: x, m, m_irr };
        Ok((next, Trial { output: m, tangent }))
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::indexing_slicing)]
    use super::*;
    use crate::test_support::{refinement_difference, rejected_field, step_difference};
    use crate::Operator;

    fn params() -> JilesAthertonParams<f64> {
        JilesAthertonParams {
            ms: 1.0,
            a: 0.3,
            k: 0.5,
            c: 0.2,
            alpha: 0.1,
        }
    }

    /// Cycles of growing amplitude with inner loops.
    fn cycles(n: usize) -> Vec<f64> {
        (0..n)
            .map(|i| {
                let t = i as f64 / n as f64;
                (0.5 + 2.5 * t) * (std::f64::consts::TAU * 4.0 * t).sin()
                    + 0.2 * (std::f64::consts::TAU * 37.0 * t).sin()
            })
            .collect()
    }

    /// The series and the closed form of `L` and `L'` agree where both
    /// hold, and `L` has its limits.
    #[test]
    fn langevin_series_meets_the_closed_form() {
        for u in [0.0999, -0.0999, 0.1, -0.1] {
            let (l, dl) = langevin(u);
            let closed = 1.0 / f64::tanh(u) - 1.0 / u;
            let closed_slope = 1.0 / (u * u) - 1.0 / f64::sinh(u).powi(2);
            assert!((l - closed).abs() < 1e-14, "{u}: {l} vs {closed}");
            assert!(
                (dl - closed_slope).abs() < 1e-12,
                "{u}: {dl} vs {closed_slope}"
            );
        }
        assert_eq!(langevin(0.0_f64), (0.0, 1.0 / 3.0));
        assert!((langevin(800.0_f64).0 - (1.0 - 1.0 / 800.0)).abs() < 1e-15);
        assert_eq!(langevin(800.0_f64).1, 1.0 / (800.0 * 800.0));
    }

    /// Without hysteresis (`c = 1`: all reversible) and without coupling,
    /// `M` is the anhysteretic curve `Ms L(H / a)` on any path.
    #[test]
    fn fully_reversible_it_is_the_anhysteretic_curve() {
        let p = JilesAthertonParams {
            c: 1.0,
            alpha: 0.0,
            ..params()
        };
        let h = cycles(800);
        let m = JilesAtherton::from_params(p).unwrap().run(&h).unwrap();
        for (i, (&hi, &mi)) in h.iter().zip(&m).enumerate() {
            let want = p.ms * langevin(hi / p.a).0;
            assert!((mi - want).abs() < 1e-10, "sample {i}: {mi} vs {want}");
        }
    }

    /// On the first magnetization curve with `c = 0` and `α = 0`,
    /// `M_irr` follows `dM/dH = (M_an − M)/k` while it lags: at a small
    /// field, where `M_an ≈ Ms H/(3a)`, the closed form of that linear
    /// equation from `M = 0` is `M = (Ms/(3a)) (H − k (1 − e^{−H/k}))`.
    #[test]
    fn initial_curve_meets_its_small_field_closed_form() {
        let p = JilesAthertonParams {
            ms: 1.0,
            a: 100.0,
            k: 0.5,
            c: 0.0,
            alpha: 0.0,
        };
        let mut ja = JilesAtherton::from_params(p).unwrap();
        let h: Vec<f64> = (1..=100).map(|i| 0.01 * i as f64).collect();
        let m = ja.run(&h).unwrap();
        let chi = p.ms / (3.0 * p.a);
        for (&hi, &mi) in h.iter().zip(&m) {
            let want = chi * (hi - p.k * (1.0 - (-hi / p.k).exp()));
            // the cubic term of L at H/a ≤ 0.01 is below 4e-5 of it
            assert!(
                (mi - want).abs() < 5e-5 * want.abs() + 1e-13,
                "H = {hi}: {mi} vs {want}"
            );
        }
    }

    /// After a reversal `M_irr` holds until the anhysteretic returns to
    /// it (`δ_M`): the slope just after a reversal is the reversible one,
    /// never negative.
    #[test]
    fn the_slope_after_a_reversal_is_never_negative() {
        let mut ja = JilesAtherton::from_params(params()).unwrap();
        let h = cycles(3000);
        for (i, &x) in h.iter().enumerate() {
            let t = ja.trial(x).unwrap();
            assert!(t.tangent >= 0.0, "sample {i}: dM/dH = {}", t.tangent);
            ja.commit();
        }
    }

    /// Rate-independent: the same path sampled 1× and 8× finer gives the
    /// same outputs at the shared samples, to the tolerance.
    #[test]
    fn refining_the_sampling_changes_the_output_by_the_tolerance_only() {
        let op = JilesAtherton::from_params(params()).unwrap();
        let (i, d) = refinement_difference(&op, &cycles(300), 8);
        assert!(d < 1e-9, "sample {i}: {d:e}");
    }

    /// The loop is closed: after a symmetric cycle repeated, `M` returns
    /// to itself, and the remanence and coercivity have the loop's signs.
    #[test]
    fn a_repeated_cycle_closes_its_loop() {
        let period: Vec<f64> = (0..400)
            .map(|i| 3.0 * (std::f64::consts::TAU * i as f64 / 400.0).sin())
            .collect();
        let mut ja = JilesAtherton::from_params(params()).unwrap();
        let mut last = Vec::new();
        for _ in 0..6 {
            last = ja.run(&period).unwrap();
        }
        let again = ja.run(&period).unwrap();
        for (a, b) in last.iter().zip(&again) {
            assert!((a - b).abs() < 1e-9, "{a} vs {b}");
        }
        // H = 0 going down (sample 200): positive remanence
        assert!(again[200] > 0.05, "{}", again[200]);
    }

    /// The tangent is the derivative of the output in the input, against
    /// a central difference of the step, on both sides of reversals.
    #[test]
    fn tangent_matches_a_central_difference() {
        let p = params();
        let h = cycles(500);
        let mut ja = JilesAtherton::from_params(p).unwrap();
        for (i, &x) in h.iter().enumerate() {
            let t = ja.trial(x).unwrap();
            let s = *ja.state();
            if (x - s.h).abs() > 1e-3 {
                let fd = step_difference(&p, &s, x, 1e-6 * (x - s.h).signum());
                assert!(
                    (t.tangent - fd).abs() < 1e-5 * fd.abs().max(1e-2),
                    "sample {i}: {} vs {fd}",
                    t.tangent
                );
            }
            ja.commit();
        }
    }

    /// Out-of-range parameters name their field; a coupling that makes
    /// `dM/dH` infinite is an error at build or at the sample.
    #[test]
    fn invalid_parameters_are_typed_errors() {
        let named = |p: JilesAthertonParams<f64>| rejected_field(JilesAtherton::from_params(p));
        assert_eq!(named(JilesAthertonParams { k: 0.0, ..params() }), "k");
        assert_eq!(named(JilesAthertonParams { c: 1.5, ..params() }), "c");
        assert_eq!(
            named(JilesAthertonParams {
                ms: f64::NAN,
                ..params()
            }),
            "ms"
        );
        assert_eq!(
            named(JilesAthertonParams {
                alpha: 20.0,
                ..params()
            }),
            "alpha"
        );
        // allowed at build (α c Ms/(3a) = 0.2), singular once M_irr lags
        let strong = JilesAthertonParams {
            alpha: 1.5,
            ..params()
        };
        let mut ja = JilesAtherton::from_params(strong).unwrap();
        match ja.run(&cycles(400)) {
            Err(Error::AtSample { source, .. }) => {
                assert!(
                    matches!(*source, Error::InvalidParameter { ref name, .. } if name == "alpha"),
                    "{source:?}"
                )
            }
            other => panic!("{other:?}"),
        }
    }
}
