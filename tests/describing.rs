//! The describing function against closed forms (linear gain, play /
//! backlash, saturation, the relay as the limit of a steep saturation),
//! the convergence of its quadrature with the samples per period, and its
//! input validation and steady-state check.
//!
//! Run `cargo test --test describing -- --nocapture` to see the measured
//! errors and orders.

use hysteron::models::describing::{
    describing_function, play_describing_function, saturation_describing_function, AnalysisError,
    SineOptions, SteadyCycle,
};
use hysteron::operators::PlayParams;
use hysteron::prelude::*;
use std::f64::consts::PI;

const EPS: f64 = f64::EPSILON;

fn opts(n: usize) -> SineOptions {
    SineOptions {
        samples_per_period: n,
        settle_periods: 4,
        ..SineOptions::default()
    }
}

/// Least-squares slope of `log e` over `log N` (the convergence order is
/// minus that).
fn order(ns: &[usize], es: &[f64]) -> f64 {
    let xs: Vec<f64> = ns.iter().map(|&n| (n as f64).ln()).collect();
    let ys: Vec<f64> = es.iter().map(|e| e.ln()).collect();
    let (mx, my) = (
        xs.iter().sum::<f64>() / xs.len() as f64,
        ys.iter().sum::<f64>() / ys.len() as f64,
    );
    let num: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let den: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    -num / den
}

/// Samples per period from 64 to 16384 in steps of about √2 (multiples
/// of 4): the kinks fall at varying places between samples, so the error
/// fluctuates around its `O(N⁻²)` envelope and the fitted order is an
/// average over those places.
fn ladder() -> Vec<usize> {
    (0..17)
        .map(|k| 4 * (16.0 * 2f64.powf(k as f64 / 2.0)).round() as usize)
        .collect()
}

/// A rigorous bound on the quadrature error of `N(A)` (both components)
/// for a steady output `y(θ)` that is piecewise `c ± f(A sin θ)` with
/// `|y|, |dy/dθ|, |d²y/dθ²| ≤ kA` on its smooth pieces (play: `k = 1`;
/// saturation of slope `k`): the integrand `g = y · (sin θ | cos θ)/(πA)`
/// has `|g''| ≤ 4k/π` there and its derivative jumps by at most `k/π` at
/// the `kinks` points per period. On a sample
/// interval the trapezoid rule errs by at most `h³ max|g''|/12`, plus
/// `|J| h²/8` if a kink lies inside: in total
/// `h² k (kinks/(8π) + 2/3)` per component, `h = 2π/N`.
fn bound(n: usize, k: f64, kinks: f64) -> f64 {
    let h = 2.0 * PI / n as f64;
    2f64.sqrt() * h * h * k * (kinks / (8.0 * PI) + 2.0 / 3.0)
}

/// A linear gain is band-limited: `N = k` to rounding, all other
/// harmonics zero, at any `N` (the rule is exact; the error is the
/// rounding of `N` products summed, `≲ N ε |k|`).
#[test]
fn linear_gain_is_exact() {
    for &k in &[2.5, -0.75] {
        for &n in &[8, 12, 100, 1024] {
            for &a in &[1e-3, 1.0, 37.0] {
                let g = Gain::new(k).unwrap();
                let d = describing_function(&g, a, &opts(n)).unwrap();
                let tol = 4.0 * n as f64 * EPS * k.abs();
                assert!((d.re - k).abs() <= tol, "k={k} N={n} A={a}: {}", d.re);
                assert!(d.im.abs() <= tol, "k={k} N={n}: im {}", d.im);
                assert!((d.gain - k.abs()).abs() <= tol);
                let expected_phase = if k > 0.0 { 0.0 } else { PI };
                assert!(
                    (d.phase.abs() - expected_phase).abs() <= 1e-12,
                    "{}",
                    d.phase
                );
                for (j, &(ak, bk)) in d.harmonics.iter().enumerate() {
                    if j != 1 {
                        assert!(ak.abs() + bk.abs() <= tol * a, "harmonic {j}: {ak} {bk}");
                    }
                }
            }
        }
    }
}

/// The play's describing function against the closed form
/// [`play_describing_function`], and the order of convergence in `N`.
#[test]
fn play_matches_the_backlash_closed_form() {
    for &(r, a) in &[(0.3, 1.0), (0.1, 1.0), (0.45, 1.0), (1.0, 3.7), (0.2, 0.25)] {
        let play = Play::new(r).unwrap();
        let (re, im) = play_describing_function(r, a);
        let ns = ladder();
        let mut errs = Vec::new();
        for &n in &ns {
            let d = describing_function(&play, a, &opts(n)).unwrap();
            let e = (d.re - re).hypot(d.im - im);
            assert!(e <= bound(n, 1.0, 2.0), "N={n}: error {e:e}");
            errs.push(e);
            // lag: phase in (−π/2, 0)
            assert!(d.phase < 0.0 && d.phase > -PI / 2.0, "{}", d.phase);
        }
        let p = order(&ns, &errs);
        let worst = errs
            .iter()
            .zip(&ns)
            .map(|(e, &n)| e / bound(n, 1.0, 2.0))
            .fold(0.0, f64::max);
        eprintln!(
            "play r={r} A={a}: N(A) = {re:.6} {im:+.6}i; error {:.2e} at N=64, {:.2e} at N=16384; \
             fitted order {p:.2}; max error/bound {worst:.3}",
            errs[0],
            errs[ns.len() - 1]
        );
        // kinks: O(N⁻²) on average over where they fall
        assert!((1.7..2.6).contains(&p), "order {p}");
    }
    // A ≤ r: the steady output is constant, N = 0 exactly (y = const
    // times an exact cosine/sine sum, zero to rounding)
    let d = describing_function(&Play::new(2.0).unwrap(), 1.5, &opts(256)).unwrap();
    assert!(d.gain < 1e-15, "{}", d.gain);
    assert_eq!(play_describing_function(2.0, 1.5), (0.0, 0.0));
    // initial states are wiped out: the same steady cycle
    let p0 = Play::from_params(PlayParams { r: 0.3, y0: 0.3 }).unwrap();
    let d0 = describing_function(&p0, 1.0, &opts(512)).unwrap();
    let d1 = describing_function(&Play::new(0.3).unwrap(), 1.0, &opts(512)).unwrap();
    assert_eq!(d0, d1);
}

/// Saturation with limits `±δ` and slope `k` (a gain then a saturation
/// at `±kδ`): a real describing function (no phase), against
/// [`saturation_describing_function`].
#[test]
fn saturation_matches_its_closed_form() {
    for &(k, delta, a) in &[
        (1.0, 0.5, 1.0),
        (1.0, 0.9, 1.0),
        (3.0, 0.2, 2.0),
        (1.0, 2.0, 1.0),
    ] {
        let sat = Gain::new(k)
            .unwrap()
            .then(Saturation::new(-k * delta, k * delta).unwrap());
        let exact = saturation_describing_function(k, delta, a);
        let ns = ladder();
        let mut errs = Vec::new();
        for &n in &ns {
            let d = describing_function(&sat, a, &opts(n)).unwrap();
            let e = (d.re - exact).hypot(d.im);
            assert!(e <= bound(n, k, 4.0), "N={n}: error {e:e}");
            errs.push(e);
        }
        if a <= delta {
            // linear inside the limits: exact up to rounding
            eprintln!(
                "saturation k={k} δ={delta} A={a}: linear, max error {:.2e}",
                errs.iter().fold(0.0_f64, |m, &e| m.max(e))
            );
            assert!(errs.iter().all(|&e| e < 1e-12), "{errs:?}");
        } else {
            let p = order(&ns, &errs);
            eprintln!(
                "saturation k={k} δ={delta} A={a}: N = {exact:.6}; error {:.2e} at N=64, \
                 {:.2e} at N=16384; fitted order {p:.2}",
                errs[0],
                errs[ns.len() - 1]
            );
            assert!((1.7..2.6).contains(&p), "order {p}");
        }
    }
}

/// The ideal relay `±M` as the limit of a saturation of slope `K → ∞`
/// (`δ = M/K`): the closed form tends to `4M/(πA)` like `O(K⁻²)`, and the
/// computed describing function follows it.
#[test]
fn relay_is_the_limit_of_a_steep_saturation() {
    let (m, a) = (1.5, 0.8);
    let relay = 4.0 * m / (PI * a);
    let mut last = f64::INFINITY;
    for &k in &[10.0, 100.0, 1000.0, 1e4] {
        let sat = Gain::new(k).unwrap().then(Saturation::new(-m, m).unwrap());
        let closed = saturation_describing_function(k, m / k, a);
        let d = describing_function(&sat, a, &opts(4096)).unwrap();
        let to_relay = (d.gain - relay).abs();
        eprintln!(
            "relay limit K={k:e}: closed form − relay = {:.3e}, computed − closed = {:.3e}, \
             computed − relay = {to_relay:.3e}",
            closed - relay,
            d.gain - closed
        );
        // closed form: N = (4M/πA)(1 − (δ/A)²/6 + …), δ = M/K
        let predicted = relay * (m / k / a).powi(2) / 6.0;
        assert!(((relay - closed) - predicted).abs() < 0.1 * predicted);
        assert!(to_relay < last, "not converging to the relay");
        last = to_relay;
    }
    assert!(last < 1e-5 * relay, "{last}");
}

#[test]
fn bad_arguments_are_typed_errors() {
    let play = Play::new(0.1).unwrap();
    let name = |r: Result<_, AnalysisError>| match r {
        Err(AnalysisError::InvalidArgument { name, .. }) => name,
        other => panic!("expected InvalidArgument, got {other:?}"),
    };
    for a in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(
            name(describing_function(&play, a, &SineOptions::default())),
            "amplitude"
        );
    }
    for n in [0, 4, 6, 10, 1 << 25] {
        assert_eq!(
            name(describing_function(&play, 1.0, &opts(n))),
            "samples_per_period"
        );
    }
    for p in [0, 1] {
        let o = SineOptions {
            settle_periods: p,
            ..SineOptions::default()
        };
        assert_eq!(name(describing_function(&play, 1.0, &o)), "settle_periods");
    }
    for tol in [f64::NAN, -1e-9] {
        let o = SineOptions {
            steady_tol: tol,
            ..SineOptions::default()
        };
        assert_eq!(name(describing_function(&play, 1.0, &o)), "steady_tol");
    }
}

/// A response that has not settled is an error, not a number: a lightly
/// damped linear oscillator (a mass-spring-damper driven at its sample
/// period) still rings after 3 periods.
#[test]
fn an_unsettled_response_is_not_steady() {
    let msd = MassSpringDamper::new(1.0, 0.05, 40.0, 0.01).unwrap();
    let o = SineOptions {
        samples_per_period: 64,
        settle_periods: 3,
        ..SineOptions::default()
    };
    match describing_function(&msd, 1.0, &o) {
        Err(e @ AnalysisError::NotSteady { .. }) => {
            assert!(e.to_string().contains("not periodic"), "{e}");
        }
        other => panic!("expected NotSteady, got {other:?}"),
    }
    // ... and settles after enough periods (the free oscillation decays
    // like e^{−c t/(2m)}: by e^{−0.016} per period of 0.64 s)
    let o = SineOptions {
        settle_periods: 3000,
        ..o
    };
    let d = describing_function(&msd, 1.0, &o).unwrap_or_else(|e| panic!("{e}"));
    assert!(d.change <= 1e-9 && d.gain > 0.0);
}

/// An operator failure names the period; the caller's operator is not
/// touched (the analysis runs a reset clone).
#[test]
fn operator_errors_and_the_callers_state() {
    // the inverse of a saturation has no solution beyond its limits
    let inv = Saturation::new(-1.0, 1.0).unwrap().inverse();
    match describing_function(&inv, 2.0, &opts(64)) {
        Err(AnalysisError::Operator { period: 0, .. }) => {}
        other => panic!("expected an operator error, got {other:?}"),
    }
    let mut play = Play::new(0.25).unwrap();
    play.run(&[3.0]).unwrap();
    let before = play.clone();
    let d = describing_function(&play, 1.0, &opts(256)).unwrap();
    assert_eq!(play, before);
    assert_eq!(
        d,
        describing_function(&Play::new(0.25).unwrap(), 1.0, &opts(256)).unwrap()
    );
    // the cycle's input hits ±A exactly and is antisymmetric
    let c = SteadyCycle::compute(&play, 1.3, &opts(16)).unwrap();
    assert_eq!((c.x[4], c.x[12]), (1.3, -1.3));
    for i in 0..8 {
        assert_eq!(c.x[i + 8], -c.x[i]);
    }
    assert_eq!(c.x[3], c.x[5]);
}
