//! The Jiles-Atherton model's five parameters recovered from a major and
//! a minor loop: exactly without noise, and within three standard errors
//! with 1 % noise.
// The no-panic lints of the workspace Cargo.toml are for the library code.
#![allow(clippy::unwrap_used, clippy::indexing_slicing)]

mod common;

use common::assert_recovered_within;
use common::jiles_atherton::{perturbed_start, record, truth};
use hysteron_identify::{fit, FitOptions, FitReport};
use hysteron_operators::{JilesAtherton, Parameters};

/// Fits all five parameters from [`perturbed_start`].
fn fit_from_perturbed_start(h: &[f64], m: &[f64]) -> FitReport {
    let model = perturbed_start();
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
    assert_recovered_within(&r, &true_values(), 1e-6);
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
