//! Recovery of known parameters from synthetic records.
// The no-panic lints of the workspace Cargo.toml are for the library code.
#![allow(clippy::unwrap_used, clippy::indexing_slicing)]

mod common;

use common::assert_recovered_within;
use hysteron_identify::{fit, free_by_names, FitOptions, FitReport};
use hysteron_operators::Parameters;
use hysteron_operators::{BoucWen, Gain, Operator};
use rand::{rngs::StdRng, SeedableRng};
use rand_distr::{Distribution, Normal};

/// A decaying sine of 20 000 samples: reversals at many amplitudes.
fn decaying_sine(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| {
            let t = i as f64 / n as f64;
            2.0 * (-2.0 * t).exp() * (std::f64::consts::TAU * 10.0 * t).sin()
        })
        .collect()
}

fn truth(n: f64) -> BoucWen<f64> {
    BoucWen::constant(3.0, 0.3, 1.0, 0.8, 0.4, n).unwrap()
}

const FREE: [&str; 4] = ["w", "beta", "gamma", "n"];

fn perturbed(start: &BoucWen<f64>, factors: &[f64]) -> Box<dyn Operator<f64>> {
    let mut m: Box<dyn Operator<f64>> = Box::new(start.clone());
    let idx = free_by_names(m.as_ref(), &FREE).unwrap();
    let mut p = m.params();
    for (&i, f) in idx.iter().zip(factors) {
        p[i] *= f;
    }
    m.set_params(&p).unwrap();
    m
}

/// Fits `FREE` to `(x, y)` from the truth `t` scaled by 1.3, 0.7, 1.25
/// and 1.2, checks that it converged, and returns the report with the true
/// parameter vector.
fn fit_from_perturbed_start(t: &BoucWen<f64>, x: &[f64], y: &[f64]) -> (FitReport, Vec<f64>) {
    let start = perturbed(t, &[1.3, 0.7, 1.25, 1.2]);
    let idx = free_by_names(start.as_ref(), &FREE).unwrap();
    let f = fit(start.as_ref(), x, y, &idx, &FitOptions::default()).unwrap();
    assert!(f.report.status.converged(), "{:?}", f.report.status);
    (f.report, t.params())
}

#[test]
fn noise_free_bouc_wen_recovers_its_parameters() {
    let x = decaying_sine(20_000);
    let t = truth(1.5);
    let y = t.clone().run(&x).unwrap();
    let (r, want) = fit_from_perturbed_start(&t, &x, &y);
    assert_recovered_within(&r, &want, 1e-6);
    println!(
        "noise-free: {} iterations, {} evaluations, {:?}, rms {:e}",
        r.iterations, r.evaluations, r.wall_time, r.rms
    );
}

/// `fit` reports the NRMSE that `validate` and `compare` score
/// (`metrics::errors`: RMS about zero). On a record with a large mean the
/// standard deviation is a fifth of the RMS, so a report that divided by
/// it would be five times too large.
#[test]
fn fit_reports_the_nrmse_that_validate_scores() {
    let x: Vec<f64> = decaying_sine(2_000).iter().map(|v| 5.0 + v).collect();
    let noise = Normal::new(0.0, 0.05).unwrap();
    let mut rng = StdRng::seed_from_u64(7);
    let y: Vec<f64> = x.iter().map(|v| 3.0 * v + noise.sample(&mut rng)).collect();
    let start = Gain::new(1.0).unwrap();
    let mut f = fit(&start, &x, &y, &[0], &FitOptions::default()).unwrap();
    let scored = hysteron_identify::metrics::errors(&f.model.run(&x).unwrap(), &y).unwrap();
    let reported = f.report.nrmse.unwrap();
    assert!(
        (reported - scored.nrmse).abs() <= 1e-12 * scored.nrmse,
        "fit {reported:e} vs validate {:e}",
        scored.nrmse
    );
    assert!((f.report.rms - scored.rms).abs() <= 1e-12 * scored.rms);
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let sd = (y.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / y.len() as f64).sqrt();
    assert!(
        scored.rms / sd > 4.0 * reported,
        "the two definitions must differ here"
    );
}

#[test]
fn noisy_bouc_wen_truth_lies_within_three_standard_errors() {
    let x = decaying_sine(20_000);
    let t = truth(1.5);
    let clean = t.clone().run(&x).unwrap();
    let sd = 0.01 * (clean.iter().map(|v| v * v).sum::<f64>() / clean.len() as f64).sqrt();
    let mut rng = StdRng::seed_from_u64(7);
    let noise = Normal::new(0.0, sd).unwrap();
    let y: Vec<f64> = clean.iter().map(|v| v + noise.sample(&mut rng)).collect();
    let (r, want) = fit_from_perturbed_start(&t, &x, &y);
    for p in &r.params {
        let se = p.std_error.expect("standard error");
        let z = (p.value - want[p.index]).abs() / se;
        println!(
            "{}: {:.6} ± {:.2e} (true {}, z = {z:.2}), ci {:?}",
            p.name, p.value, se, want[p.index], p.ci95
        );
        assert!(
            z < 3.0,
            "{}: {} is {z:.1} standard errors from {}",
            p.name,
            p.value,
            want[p.index]
        );
        let (lo, hi) = p.ci95.unwrap();
        assert!(lo < p.value && p.value < hi);
    }
    assert!(
        (r.rms / sd - 1.0).abs() < 0.05,
        "rms {} vs noise {}",
        r.rms,
        sd
    );
}

#[test]
fn batches_equal_sequential_runs_and_report_errors_per_entry() {
    use hysteron_identify::batch::{simulate_parameter_sets, simulate_records};
    let model: Box<dyn Operator<f64>> = Box::new(truth(1.0));
    let x = decaying_sine(2_000);
    let base = model.params();
    let mut bad = base.clone();
    bad[0] = 2.0; // w outside [0, 1]
    let sets: Vec<Vec<f64>> = vec![
        base.clone(),
        {
            let mut p = base.clone();
            p[2] = 1.1;
            p
        },
        bad,
    ];
    let out = simulate_parameter_sets(model.as_ref(), &sets, &x);
    assert_eq!(out.len(), 3);
    for (p, r) in sets.iter().zip(&out).take(2) {
        let mut m = model.clone();
        m.set_params(p).unwrap();
        assert_eq!(r.as_ref().unwrap(), &m.run(&x).unwrap());
    }
    assert!(out[2].is_err());
    let records = vec![x.clone(), x[..500].to_vec(), vec![0.1, f64::NAN]];
    let out = simulate_records(model.as_ref(), &records);
    assert_eq!(out[0].as_ref().unwrap(), &model.clone().run(&x).unwrap());
    assert_eq!(out[1].as_ref().unwrap().len(), 500);
    assert!(out[2].is_err());

    // Into preallocated buffers: the same outputs, bit for bit.
    use hysteron_identify::batch::process_records;
    let inputs: Vec<&[f64]> = records.iter().map(|r| r.as_slice()).collect();
    let mut buffers: Vec<Vec<f64>> = records.iter().map(|r| vec![0.0; r.len()]).collect();
    let mut outputs: Vec<&mut [f64]> = buffers.iter_mut().map(|b| b.as_mut_slice()).collect();
    let done = process_records(model.as_ref(), &inputs, &mut outputs);
    assert!(done[0].is_ok() && done[1].is_ok() && done[2].is_err());
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&buffers[0]), bits(out[0].as_ref().unwrap()));
    assert_eq!(bits(&buffers[1]), bits(out[1].as_ref().unwrap()));
    // An input without an output buffer is an error, not a silent skip.
    let mut short: Vec<&mut [f64]> = buffers[..1].iter_mut().map(|b| b.as_mut_slice()).collect();
    let done = process_records(model.as_ref(), &inputs[..2], &mut short);
    assert!(done[0].is_ok());
    assert!(matches!(
        done[1],
        Err(hysteron_operators::Error::LengthMismatch { .. })
    ));
}

/// The correlation matrix is a correlation matrix (unit diagonal,
/// symmetric, entries in [−1, 1]); with noise it exists, and two
/// parameters that only act as a product (`w · k` of a scaled gain) are
/// reported as correlated beyond 0.99, or the covariance as singular.
#[test]
fn correlation_matrix_is_reported_and_flags_a_product() {
    use hysteron_composition::OperatorExt;
    use hysteron_operators::Gain;
    let x = decaying_sine(20_000);
    let t = truth(1.5);
    let mut rng = StdRng::seed_from_u64(7);
    let noise = Normal::new(0.0, 0.01).unwrap();
    let y: Vec<f64> = t
        .clone()
        .run(&x)
        .unwrap()
        .into_iter()
        .map(|v| v + noise.sample(&mut rng))
        .collect();
    let start = perturbed(&t, &[1.1, 0.9, 1.1, 1.05]);
    let idx = free_by_names(start.as_ref(), &FREE).unwrap();
    let f = fit(start.as_ref(), &x, &y, &idx, &FitOptions::default()).unwrap();
    let c = f
        .report
        .correlation
        .expect("a noisy, well-posed fit has one");
    assert_eq!(c.len(), FREE.len());
    for (i, row) in c.iter().enumerate() {
        assert!((row[i] - 1.0).abs() < 1e-12, "diagonal {}", row[i]);
        for (j, v) in row.iter().enumerate() {
            assert!((v - c[j][i]).abs() < 1e-12);
            assert!(v.abs() <= 1.0 + 1e-12, "{v}");
        }
    }

    // y = w · k · x: only the product is identifiable.
    let product = Gain::new(1.5_f64).unwrap().scaled(2.0).unwrap();
    let yp: Vec<f64> = x.iter().map(|v| 3.3 * v + noise.sample(&mut rng)).collect();
    let all: Vec<usize> = (0..product.n_params()).collect();
    let f = fit(&product, &x, &yp, &all, &FitOptions::default()).unwrap();
    if let Some(c) = f.report.correlation {
        assert!(c[0][1].abs() > 0.99, "product correlation {}", c[0][1]);
    }
}
