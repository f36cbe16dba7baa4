//! Identifiability diagnostics of real fits: a well-posed fit has no
//! warnings, two merged Maxwell-slip elements are reported by name.
// The no-panic lints of the workspace Cargo.toml are for the library code.
#![allow(clippy::unwrap_used, clippy::indexing_slicing)]

use hysteron_identify::{
    fit, fit_multistart, free_by_names, FitOptions, FitReport, IdentifiabilityWarning, MultiStart,
    Record,
};
use hysteron_operators::Parameters;
use hysteron_operators::{BoucWen, MaxwellSlip, Operator, Play};
use rand::{rngs::StdRng, SeedableRng};
use rand_distr::{Distribution, Normal};

/// A decaying sine of 4 000 samples: reversals at many amplitudes.
fn input() -> Vec<f64> {
    let n = 4000;
    (0..n)
        .map(|i| {
            let t = i as f64 / n as f64;
            1.5 * (-1.5 * t).exp() * (std::f64::consts::TAU * 8.0 * t).sin()
        })
        .collect()
}

/// Fits the break-away forces of a two-element Maxwell-slip bank of unit
/// stiffnesses to its own record (true forces `f_b`) plus 0.5 % noise,
/// from 20 % off.
fn fit_forces(f_b: [f64; 2]) -> FitReport {
    let truth = MaxwellSlip::new(vec![1.0, 1.0], f_b.to_vec()).unwrap();
    let x = input();
    let clean = truth.clone().run(&x).unwrap();
    let mut rng = StdRng::seed_from_u64(7);
    let noise = Normal::new(0.0, 0.005).unwrap();
    let y: Vec<f64> = clean.iter().map(|v| v + noise.sample(&mut rng)).collect();
    let start = MaxwellSlip::new(vec![1.0, 1.0], vec![1.2 * f_b[0], 0.8 * f_b[1]]).unwrap();
    let free = free_by_names(&start, &["f_b[0]", "f_b[1]"]).unwrap();
    fit(&start, &x, &y, &free, &FitOptions::default())
        .unwrap()
        .report
}

/// A Bouc-Wen spring's shape (`w`, `β`, `γ`) from a decaying sine with
/// 0.5 % noise: recovered, and nothing to warn about.
#[test]
fn a_well_posed_fit_has_no_warnings() {
    let truth = BoucWen::constant(3.0, 0.3, 1.0, 0.8, 0.4, 1.0).unwrap();
    let x = input();
    let clean = truth.clone().run(&x).unwrap();
    let mut rng = StdRng::seed_from_u64(11);
    let noise = Normal::new(0.0, 0.01).unwrap();
    let y: Vec<f64> = clean.iter().map(|v| v + noise.sample(&mut rng)).collect();
    let free = free_by_names(&truth, &["w", "beta", "gamma"]).unwrap();
    let mut start = truth.clone();
    let mut p = start.params();
    for (&i, f) in free.iter().zip([1.2, 0.8, 1.25]) {
        p[i] *= f;
    }
    start.set_params(&p).unwrap();
    let r = fit(&start, &x, &y, &free, &FitOptions::default())
        .unwrap()
        .report;
    assert!(r.status.converged(), "{r}");
    for (fp, want) in r.params.iter().zip([0.3, 0.8, 0.4]) {
        assert!((fp.value - want).abs() < 0.02 * want, "{r}");
    }
    assert!(r.warnings.is_empty(), "{r}");
    let k = r.condition_number.unwrap();
    assert!(k.is_finite() && k >= 1.0, "{r}");
    assert!(r.to_string().contains("cond(JᵀJ)"), "{r}");
    assert!(!r.to_string().contains("warning"), "{r}");
}

/// Equal break-away forces and stiffnesses: the two elements are one
/// element twice, their Jacobian columns coincide at the truth, and only
/// the sum of the forces is determined. The report says so, naming both.
#[test]
fn merged_elements_are_reported() {
    let r = fit_forces([0.5, 0.5]);
    let text = r.to_string();
    let names_both = |w: &IdentifiabilityWarning| match w {
        IdentifiabilityWarning::Singular { names } => names == &["f_b[0]", "f_b[1]"],
        IdentifiabilityWarning::Correlated { first, second, rho } => {
            first.ends_with("f_b[0]") && second.ends_with("f_b[1]") && rho.abs() > 0.99
        }
        IdentifiabilityWarning::WideInterval { .. }
        | IdentifiabilityWarning::Undetermined { .. } => false,
    };
    assert!(r.warnings.iter().any(names_both), "{text}");
    assert!(text.contains("warning: "), "{text}");
    // a singular or nearly singular JᵀJ
    assert!(r.condition_number.is_none_or(|k| k > 1e6), "{text}");
}

/// A fit that lands exactly on noise-free data has zero residuals, so zero
/// standard errors; its correlations come from `(JᵀJ)⁻¹` alone and exist,
/// and a regular `JᵀJ` is not reported as singular.
#[test]
fn zero_residuals_keep_the_correlations() {
    let truth = MaxwellSlip::new(vec![1.0, 1.0], vec![0.2, 0.8]).unwrap();
    let x = input();
    let y = truth.clone().run(&x).unwrap();
    let free = free_by_names(&truth, &["f_b[0]", "f_b[1]"]).unwrap();
    let r = fit(&truth, &x, &y, &free, &FitOptions::default())
        .unwrap()
        .report;
    assert_eq!(r.cost, 0.0, "{r}");
    let rho = r.correlation.as_ref().unwrap();
    assert!(
        (rho[0][0] - 1.0).abs() < 1e-12 && (rho[1][1] - 1.0).abs() < 1e-12,
        "{r}"
    );
    assert!(rho[0][1].abs() < 0.99, "{r}");
    assert!(r.warnings.is_empty(), "{r}");
    assert!(r.condition_number.is_some(), "{r}");
}

/// A play's threshold from a start beyond the input's amplitude: there the
/// output never moves, the gradient is zero and a single start stays where
/// it began; eight Latin-hypercube starts (within a factor 4) include some
/// below the amplitude, which find the truth, and the report says how many
/// did.
#[test]
fn multiple_starts_find_what_one_start_misses() {
    let x = input();
    let y = Play::new(0.3).unwrap().run(&x).unwrap();
    let start = Play::new(2.0).unwrap();
    let free = free_by_names(&start, &["r"]).unwrap();
    let opts = FitOptions::default();
    let one = fit(&start, &x, &y, &free, &opts).unwrap().report;
    assert_eq!(one.params[0].value, 2.0, "{one}");
    let records = [Record {
        x: &x,
        y: &y,
        skip: 0,
    }];
    let ms = MultiStart {
        starts: 8,
        ..MultiStart::default()
    };
    let many = fit_multistart(&start, &records, &free, &[], &opts, &ms, &|_| {})
        .unwrap()
        .report;
    let summary = many.starts.as_ref().unwrap();
    assert_eq!(summary.costs.len(), 8);
    assert!(summary.reached >= 1 && summary.reached < 8, "{many}");
    assert_ne!(summary.best, 0, "{many}");
    assert!((many.params[0].value - 0.3).abs() < 1e-9, "{many}");
    assert!(many.cost < 1e-20 && one.cost > 1.0, "{one}\n{many}");
    assert!(many.to_string().contains("starts       8"), "{many}");
}
