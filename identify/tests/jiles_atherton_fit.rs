//! The Jiles-Atherton model's five parameters recovered from a major and
//! a minor loop: exactly without noise, and within three standard errors
//! with 1 % noise.
// The no-panic lints of the workspace Cargo.toml are for the library code.
#![allow(clippy::unwrap_used, clippy::indexing_slicing)]

use hysteron_identify::{fit, FitOptions, FitReport};
use hysteron_models::experiments::through_corners;
use hysteron_operators::{JilesAtherton, JilesAthertonParams, Operator, Parameters};
use rand::{rngs::StdRng, SeedableRng};
use rand_distr::{Distribution, Normal};

fn truth() -> JilesAthertonParams<f64> {
    JilesAthertonParams {
        ms: 1.2,
        a: 0.4,
        k: 0.3,
        c: 0.3,
        alpha: 0.15,
    }
}

/// Two major cycles of amplitude 3, then a minor loop between −0.5 and
/// 1.2 (straight segments, 0.01 apart).
fn field() -> Vec<f64> {
    through_corners(&[0.0, 3.0, -3.0, 3.0, -3.0, 1.2, -0.5, 1.2], 0.01).unwrap()
}

/// The truth's response to [`field`], with Gaussian noise of `noise`
/// times its peak (seed 11).
fn record(noise: f64) -> (Vec<f64>, Vec<f64>) {
    let h = field();
    let clean = JilesAtherton::from_params(truth())
        .unwrap()
        .run(&h)
        .unwrap();
    let peak = clean.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    let normal = Normal::new(0.0, noise * peak).unwrap();
    let mut rng = StdRng::seed_from_u64(11);
    let m = clean.iter().map(|v| v + normal.sample(&mut rng)).collect();
    (h, m)
}

/// Fits all five parameters from the truth scaled by 1.3, 0.7, 1.25, 0.8
/// and 1.2.
fn fit_from_perturbed_start(h: &[f64], m: &[f64]) -> FitReport {
    let t = truth();
    let start = JilesAthertonParams {
        ms: t.ms * 1.3,
        a: t.a * 0.7,
        k: t.k * 1.25,
        c: t.c * 0.8,
        alpha: t.alpha * 1.2,
    };
    let model = JilesAtherton::from_params(start).unwrap();
    let free: Vec<usize> = (0..model.n_params()).collect();
    let f = fit(&model, h, m, &free, &FitOptions::default()).unwrap();
    assert!(f.report.status.converged(), "{:?}", f.report.status);
    println!(
        "{} iterations, {} evaluations, {:?}, rms {:e}",
        f.report.iterations, f.report.evaluations, f.report.wall_time, f.report.rms
    );
    f.report
}

fn true_values() -> Vec<f64> {
    JilesAtherton::from_params(truth()).unwrap().params()
}

#[test]
fn noise_free_loops_recover_the_five_parameters() {
    let (h, m) = record(0.0);
    let r = fit_from_perturbed_start(&h, &m);
    let want = true_values();
    for p in &r.params {
        let rel = (p.value - want[p.index]).abs() / want[p.index];
        assert!(
            rel < 1e-6,
            "{}: {} vs {} (rel {rel:e})",
            p.name,
            p.value,
            want[p.index]
        );
    }
}

#[test]
fn noisy_loops_recover_the_parameters_within_three_standard_errors() {
    let (h, m) = record(0.01);
    let r = fit_from_perturbed_start(&h, &m);
    let want = true_values();
    for p in &r.params {
        let se = p.std_error.unwrap();
        let off = (p.value - want[p.index]).abs();
        assert!(
            off < 3.0 * se,
            "{}: {} vs {} (se {se:e})",
            p.name,
            p.value,
            want[p.index]
        );
        // and the check is not vacuous: the three-standard-error interval
        // excludes 0, so each parameter is determined by the data
        assert!(3.0 * se < want[p.index], "{}: se {se:e}", p.name);
    }
}
