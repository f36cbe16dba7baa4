//! Work per closed loop `∮ y dx` against closed forms (PI bank of plays,
//! Bouc-Wen spring with `n = 1`), the trapezoid rule's error, and the sign
//! of the loop work for passive operators on random amplitudes.
//!
//! Run `cargo test --test energy -- --nocapture` to see the measured
//! errors (`LAWS_CASES_FACTOR=k` multiplies the number of random cases).

use hysteron::composition::PiBankParams;
use hysteron::models::describing::{SineOptions, SteadyCycle};
use hysteron::models::energy::{bouc_wen_n1_loop, loop_energy, pi_bank_loop_work};
use hysteron::operators::MmsParams;
use hysteron::prelude::*;
use proptest::prelude::*;
use proptest::test_runner::{TestCaseError, TestRunner};
use std::cell::Cell;
use std::f64::consts::PI;

const EPS: f64 = f64::EPSILON;

fn opts(n: usize, periods: usize) -> SineOptions {
    SineOptions {
        samples_per_period: n,
        settle_periods: periods,
        ..SineOptions::default()
    }
}

/// The largest input step of the sampled sine, `2A sin(π/N)` (at the zero
/// crossings).
fn dx_max(a: f64, n: usize) -> f64 {
    2.0 * a * (PI / n as f64).sin()
}

/// Rounding of the trapezoid sum: `N` terms of size `≤ max|y| · Δx`, a
/// few ulps each.
fn rounding(n: usize, a: f64, y_max: f64) -> f64 {
    4.0 * n as f64 * EPS * y_max * dx_max(a, n).max(a / n as f64)
}

/// The loop area of a PI bank with positive weights is the dissipation
/// `Σ_{r_j < A} 4 w_j r_j (A − r_j)` (written out here, independently of
/// `pi_bank_loop_work`), whatever the orientation of the loop.
#[test]
fn pi_bank_loop_area_is_the_positive_dissipation() {
    let (r, w) = (vec![0.0, 0.2, 0.5, 0.8], vec![0.5, 1.0, 0.6, 0.3]);
    let bank = PiBank::new(0.2, r.clone(), w.clone()).unwrap();
    for &a in &[0.3, 0.7, 1.2] {
        let want: f64 = r
            .iter()
            .zip(&w)
            .filter(|(&r, _)| r < a)
            .map(|(&r, &w)| 4.0 * w * r * (a - r))
            .sum();
        // Trapezoid error ≤ Σ_{0 < r_j < A} 2 w_j Δx²/8, Δx = 2 A sin(π/N).
        let n = 4096;
        let dx = 2.0 * a * (std::f64::consts::PI / n as f64).sin();
        let bound: f64 = r
            .iter()
            .zip(&w)
            .filter(|(&r, _)| r > 0.0 && r < a)
            .map(|(_, &w)| 2.0 * w * dx * dx / 8.0)
            .sum();
        let e = loop_energy(&bank, a, &opts(n, 3)).unwrap();
        assert!(
            want > 0.0 && e.work < 0.0,
            "A = {a}: play loops run counterclockwise"
        );
        assert!(
            (e.area() - want).abs() <= bound + 1e-12 * want,
            "A = {a}: {} vs {want} (bound {bound:e})",
            e.area()
        );
    }
}

#[test]
fn pi_bank_loop_matches_the_closed_form_within_the_kink_bound() {
    let p = PiBankParams {
        a0: 0.4,
        r: vec![0.0, 0.13, 0.37, 0.61, 0.9, 1.7],
        w: vec![1.0, 0.8, -0.2, 0.5, 0.3, 2.0],
        y0: vec![0.0, 0.1, -0.2, 0.3, 0.0, 1.0],
    };
    let bank = PiBank::from_params(p.clone()).unwrap();
    for &a in &[1.0, 0.5, 2.5] {
        let exact = pi_bank_loop_work(&p, a);
        for &n in &[64, 256, 1024, 4096] {
            let c = SteadyCycle::compute(&bank, a, &opts(n, 3)).unwrap();
            let w = c.loop_work();
            // each play r_j < A has two kinks per loop, slope jump w_j
            let kinks: f64 =
                p.r.iter()
                    .zip(&p.w)
                    .filter(|(&r, _)| r > 0.0 && r < a)
                    .map(|(_, w)| 2.0 * w.abs())
                    .sum();
            let y_max = c.y.iter().fold(0.0_f64, |m, y| m.max(y.abs()));
            let bound = kinks * dx_max(a, n).powi(2) / 8.0 + rounding(n, a, y_max);
            let e = (w - exact).abs();
            assert!(
                e <= bound,
                "A={a} N={n}: {w} vs {exact} (error {e:e} > {bound:e})"
            );
            if n == 4096 {
                eprintln!(
                    "PI bank A={a}: ∮ y dx = {exact:.10} exact, error {e:.2e} at N={n} \
                     (kink bound {bound:.2e})"
                );
            }
        }
    }
}

/// When every kink of `y(x)` is a sample (thresholds `r = (A − x_k)/2`
/// for sample values `x_k`), `y` is linear on every segment and the
/// trapezoid rule is exact up to rounding.
#[test]
fn pi_bank_loop_is_exact_when_the_kinks_are_samples() {
    let (a, n) = (1.7, 400);
    let c0 = SteadyCycle::compute(&Gain::new(1.0).unwrap(), a, &opts(n, 2)).unwrap();
    // the falling branch's kink of a play is at x = A − 2r; the rising one
    // at −(A − 2r), also a sample by the antisymmetry of the input
    let r: Vec<f64> = [7, 31, 52, 80, 99]
        .iter()
        .map(|&k| (a - c0.x[n / 4 + k]) / 2.0)
        .collect();
    let p = PiBankParams {
        a0: 0.3,
        w: vec![1.0, 0.5, 0.25, 2.0, 0.7],
        r,
        y0: vec![],
    };
    let bank = PiBank::from_params(p.clone()).unwrap();
    let c = SteadyCycle::compute(&bank, a, &opts(n, 3)).unwrap();
    let exact = pi_bank_loop_work(&p, a);
    let e = (c.loop_work() - exact).abs();
    let y_max = c.y.iter().fold(0.0_f64, |m, y| m.max(y.abs()));
    eprintln!("PI bank, kinks at samples: ∮ y dx = {exact:.12}, error {e:.2e} (N = {n})");
    // rounding: the sum, and the kink positions `A − 2r` off by an ulp
    assert!(e <= rounding(n, a, y_max) + 16.0 * EPS * a * y_max, "{e:e}");
    // ... while a generic threshold set is off by O(Δx²)
    let mut q = p.clone();
    for r in &mut q.r {
        *r += 1e-3;
    }
    let c = SteadyCycle::compute(&PiBank::from_params(q.clone()).unwrap(), a, &opts(n, 3)).unwrap();
    assert!((c.loop_work() - pi_bank_loop_work(&q, a)).abs() > 1e3 * e.max(EPS));
}

/// Bouc-Wen `n = 1`, constant stiffness: the closed form of
/// [`bouc_wen_n1_loop`] against the trapezoid rule on the sampled loop.
/// The spring integrates `n = 1` exactly at the samples; `h(z)` has
/// corners only at the reversals (samples) and a jump of `h''` at its zero
/// crossing, so the trapezoid error is `O(N⁻²)`: ratios `e(N)/e(2N) ≈ 4`.
#[test]
fn bouc_wen_n1_loop_matches_the_closed_form() {
    let cases = [
        // (k, w, α, β, γ, A)
        (2.0, 0.3, 1.0, 0.6, 0.4, 1.0),
        (5.0, 0.1, 1.0, 0.8, 0.0, 1.5),
        (1.0, 0.5, 2.0, 1.0, -0.5, 0.7),
        (3.0, 0.0, 1.0, 0.5, 0.5, 2.0),
        (1.5, 0.2, 0.5, 3.0, 1.0, 0.4),
    ];
    for &(k, w, alpha, beta, gamma, a) in &cases {
        let spring = BoucWen::constant(k, w, alpha, beta, gamma, 1.0).unwrap();
        let exact = bouc_wen_n1_loop(alpha, beta, gamma, w, k, a).unwrap();
        if gamma == 0.0 {
            let hm = alpha / beta * (beta * a).tanh();
            assert!((exact.h_turn - hm).abs() <= 4.0 * EPS * hm);
        }
        let mut errs = Vec::new();
        let mut works = Vec::new();
        let ns = [256, 512, 1024, 2048, 4096, 8192, 16384, 32768, 65536];
        for &n in &ns {
            let c = SteadyCycle::compute(&spring, a, &opts(n, 60)).unwrap();
            works.push(c.loop_work());
            errs.push((c.loop_work() - exact.work).abs() / exact.work);
            // the turning state matches the fixed point
            let h_top = (c.y[n / 4] - w * k * a) / ((1.0 - w) * k);
            if w < 1.0 {
                assert!((h_top - exact.h_turn).abs() <= 1e-12 * exact.h_turn.max(1.0));
            }
        }
        let ratios: Vec<f64> = errs.windows(2).map(|e| e[0] / e[1]).collect();
        // One Richardson step removes the N⁻² term: what is left checks
        // the closed form far below the trapezoid error.
        let j = ns.len() - 3;
        let richardson = (4.0 * works[j + 1] - works[j]) / 3.0;
        let rich_err = (richardson - exact.work).abs() / exact.work;
        eprintln!(
            "Bouc-Wen n=1 k={k} w={w} α={alpha} β={beta} γ={gamma} A={a}: ∮ H dz = {:.12}, \
             h_m = {:.12}; relative error {:.2e} at N=256, {:.2e} at N=65536; ratios {:?}; \
             Richardson (N = {}, {}) {rich_err:.2e}",
            exact.work,
            exact.h_turn,
            errs[0],
            errs[ns.len() - 1],
            ratios.iter().map(|r| format!("{r:.3}")).collect::<Vec<_>>(),
            ns[j],
            ns[j + 1]
        );
        assert!(rich_err < 1e-11, "Richardson {rich_err:e}");
        assert!(errs[ns.len() - 1] < 2e-9, "{:e}", errs[ns.len() - 1]);
        // O(N⁻²) while the truncation error dominates rounding
        for (i, r) in ratios.iter().enumerate().take(5) {
            assert!((3.5..4.5).contains(r), "ratio {i}: {r}");
        }
    }
    // outside the bounded class, no closed form
    assert!(bouc_wen_n1_loop(1.0, 0.2, 0.5, 0.3, 1.0, 1.0).is_err());
    assert!(bouc_wen_n1_loop(-1.0, 0.5, 0.2, 0.3, 1.0, 1.0).is_err());
    assert!(bouc_wen_n1_loop(1.0, 0.5, 0.2, 0.3, 1.0, f64::NAN).is_err());
}

/// `∮ y dx ≥ 0` (clockwise loops) for the dissipative operators, and
/// `≤ 0` for plays and PI banks of plays with positive weights (their
/// loops run counterclockwise; `∮ x dy = −∮ y dx ≥ 0`), on random
/// parameters and amplitudes. Slack: the trapezoid sum's rounding. The
/// stop and the elastic-plastic element are also checked against their
/// closed form `4 r (A − r)` (`k` times that for elastic-plastic with
/// `r = F_b/k`) within the kink bound.
#[test]
fn loop_work_sign_of_passive_operators() {
    let n = 256;
    let worst = Cell::new(f64::INFINITY);
    let mut runner = TestRunner::new(ProptestConfig {
        cases: 256
            * std::env::var("LAWS_CASES_FACTOR")
                .ok()
                .and_then(|f| f.parse::<u32>().ok())
                .unwrap_or(1),
        failure_persistence: None,
        ..ProptestConfig::default()
    });
    let ops = (
        0_u8..6,
        0.05_f64..3.0,
        (0.0_f64..2.0, 0.5_f64..20.0),
        (0.0_f64..1.0, 1.0_f64..3.0, 0.0_f64..1.0, 1.0_f64..3.0),
        prop::collection::vec((0.0_f64..2.0, 0.0_f64..1.0), 1..6),
    );
    let result = runner.run(
        &ops,
        |(kind, a, (p1, p2), (bw_w, bw_beta, bw_g, bw_n), plays)| {
            // β ≥ |γ| (γ ∈ [−β/2, β]) and (β + γ) A^n ≥ 0.5: the transient
            // decays like e^{−2(β+γ)A} per half period for n = 1 (with
            // |h| ~ A the rate scales like (β + γ) A^n for n > 1)
            let beta = bw_beta / a.powf(bw_n);
            let gamma = (1.5 * bw_g - 0.5) * beta;
            let (op, sign, closed): (Box<dyn Operator<f64>>, f64, Option<f64>) = match kind {
                0 => (
                    Stop::new(p1).unwrap().boxed(),
                    1.0,
                    Some(4.0 * p1.min(a) * (a - p1.min(a))),
                ),
                1 => {
                    let (k, f_b) = (p2, p1);
                    let r = (f_b / k).min(a);
                    (
                        ElastoPlastic::new(k, f_b).unwrap().boxed(),
                        1.0,
                        Some(4.0 * k * r * (a - r)),
                    )
                }
                2 => (
                    Mms::from_params(MmsParams {
                        f_c: p1 + 0.1,
                        k: p2 / a,
                        y0: 0.0,
                    })
                    .unwrap()
                    .boxed(),
                    1.0,
                    None,
                ),
                3 => (
                    BoucWen::constant(2.0, bw_w, 1.0, beta, gamma, bw_n)
                        .unwrap()
                        .boxed(),
                    1.0,
                    None,
                ),
                4 => (Play::new(p1).unwrap().boxed(), -1.0, None),
                _ => {
                    let (r, w): (Vec<f64>, Vec<f64>) = plays.iter().copied().unzip();
                    (PiBank::new(0.3, r, w).unwrap().boxed(), -1.0, None)
                }
            };
            let c = SteadyCycle::compute(&op, a, &opts(n, 80))
                .map_err(|e| TestCaseError::fail(format!("{e}")))?;
            let work = c.loop_work();
            let y_max = c.y.iter().fold(0.0_f64, |m, y| m.max(y.abs()));
            let slack = rounding(n, a, y_max);
            prop_assert!(
                sign * work >= -slack,
                "kind {}: ∮ y dx = {:e} has the wrong sign",
                kind,
                work
            );
            if let Some(exact) = closed {
                let k = if kind == 1 { p2 } else { 1.0 };
                let bound = 2.0 * k * dx_max(a, n).powi(2) / 8.0 + slack;
                prop_assert!(
                    (work - exact).abs() <= bound,
                    "kind {}: {} vs closed form {}",
                    kind,
                    work,
                    exact
                );
            }
            if y_max > 0.0 {
                worst.set(worst.get().min(sign * work / (y_max * a)));
            }
            Ok(())
        },
    );
    if let Err(e) = result {
        panic!("{e}");
    }
    eprintln!(
        "loop work sign: smallest sign·∮ y dx / (max|y| A) = {:.3e}",
        worst.get()
    );
    // the public convenience agrees with the cycle's
    let stop = Stop::new(0.2).unwrap();
    let e = loop_energy(&stop, 1.0, &opts(n, 3)).unwrap();
    assert_eq!(
        e.work,
        SteadyCycle::compute(&stop, 1.0, &opts(n, 3))
            .unwrap()
            .loop_work()
    );
}
