#![allow(clippy::unwrap_used, clippy::indexing_slicing, clippy::panic)]
//! The Sobol indices against the Ishigami function's analytic ones, and
//! every refusal with the field it names.

use hysteron_identify::sobol::{
    sobol, sobol_of_model, Factor, SobolError, SobolOptions, Statistic, MAX_FACTORS,
};
use hysteron_models::Spec;
use hysteron_operators::{declare_params, memoryless_step_law, Memoryless, Stepped, Trial};
use std::f64::consts::PI;

const A: f64 = 7.0;
const B: f64 = 0.1;

declare_params! {
    /// The Ishigami function's three variables, and one it ignores.
    pub struct IshigamiParams<T>: Copy {
        /// First variable.
        x1: T => Real = 0.0,
        /// Second variable.
        x2: T => Real = 0.0,
        /// Third variable.
        x3: T => Real = 0.0,
        /// A variable the function does not use.
        inert: T => Real = 0.0,
    }
    law: "ishigami", "y = sin x1 + a sin² x2 + b x3⁴ sin x1";
}

memoryless_step_law!(IshigamiParams);

impl<T: hysteron_operators::Float> Memoryless<T> for IshigamiParams<T> {
    fn eval(&self, _: T) -> Trial<T> {
        let (a, b) = (T::lit(A), T::lit(B));
        let s1 = self.x1.sin();
        let s2 = self.x2.sin();
        Trial {
            output: s1 + a * s2 * s2 + b * self.x3.powi(4) * s1,
            tangent: T::zero(),
        }
    }
}

/// A memoryless leaf whose output is the Ishigami function of its
/// parameters, whatever its input.
type Ishigami = Stepped<IshigamiParams<f64>, f64>;

fn ishigami() -> Ishigami {
    Stepped::from_params(IshigamiParams {
        x1: 0.0,
        x2: 0.0,
        x3: 0.0,
        inert: 0.0,
    })
    .unwrap()
}

fn around(names: &[&str]) -> Vec<Factor> {
    names.iter().map(|n| Factor::new(*n, -PI, PI)).collect()
}

/// The analytic partial variances for `x_i` uniform on `[−π, π]`, from the
/// moments `E[sin² x] = 1/2`, `E[sin⁴ x] = 3/8`, `E[x⁴] = π⁴/5`,
/// `E[x⁸] = π⁸/9`:
///
/// * `E[f | x1] = a/2 + (1 + b π⁴/5) sin x1`: `V1 = (1 + b π⁴/5)² / 2`;
/// * `E[f | x2] = a sin² x2 + const`: `V2 = a² (3/8 − 1/4) = a²/8`;
/// * `E[f | x3] = a/2`: `V3 = 0`;
/// * `E[f | x1, x3] = a/2 + (1 + b x3⁴) sin x1`, of variance
///   `(1 + 2bπ⁴/5 + b²π⁸/9)/2`: `V13 = b²π⁸ (1/9 − 1/25)/2 = 8 b²π⁸/225`;
/// * no other interaction (`f` is a sum of a function of `x2` and one of
///   `(x1, x3)`).
///
/// Returns `(V, [S1, S2, S3], [ST1, ST2, ST3])`.
fn analytic() -> (f64, [f64; 3], [f64; 3]) {
    let pi4 = PI.powi(4);
    let pi8 = PI.powi(8);
    let v1 = 0.5 * (1.0 + B * pi4 / 5.0).powi(2);
    let v2 = A * A / 8.0;
    let v3 = 0.0;
    let v13 = 8.0 * B * B * pi8 / 225.0;
    let v = v1 + v2 + v3 + v13;
    // the closed form of the literature agrees with the sum of the parts
    let closed = A * A / 8.0 + B * pi4 / 5.0 + B * B * pi8 / 18.0 + 0.5;
    assert!((v - closed).abs() < 1e-12 * v, "{v} vs {closed}");
    (
        v,
        [v1 / v, v2 / v, v3 / v],
        [(v1 + v13) / v, v2 / v, (v3 + v13) / v],
    )
}

#[test]
fn ishigami_indices_agree_with_the_analytic_ones() {
    let (v, first, total) = analytic();
    let opts = SobolOptions {
        samples: 1 << 14,
        seed: 0,
    };
    let s = sobol_of_model(
        &ishigami(),
        &[0.0, 1.0],
        &around(&["x1", "x2", "x3"]),
        &Statistic::Mean,
        &opts,
    )
    .unwrap();
    assert_eq!(s.names, ["x1", "x2", "x3"]);
    assert_eq!(s.samples, 1 << 14);
    assert_eq!(s.evaluations, (1 << 14) * 5);
    for i in 0..3 {
        eprintln!(
            "x{}: S = {:.5} (analytic {:.5}, error {:+.1e}), ST = {:.5} (analytic {:.5}, error {:+.1e})",
            i + 1,
            s.first[i],
            first[i],
            s.first[i] - first[i],
            s.total[i],
            total[i],
            s.total[i] - total[i]
        );
        assert!((s.first[i] - first[i]).abs() < 1e-2, "S{}", i + 1);
        assert!((s.total[i] - total[i]).abs() < 1e-2, "ST{}", i + 1);
    }
    eprintln!("V = {:.5} (analytic {v:.5})", s.variance);
    assert!((s.variance - v).abs() < 1e-2 * v);
    assert!((s.mean - A / 2.0).abs() < 1e-2 * A);
}

#[test]
fn a_parameter_without_influence_gets_zero_indices() {
    let s = sobol_of_model(
        &ishigami(),
        &[0.0],
        &around(&["x1", "inert", "x2"]),
        &Statistic::Mean,
        &SobolOptions {
            samples: 1 << 14,
            seed: 3,
        },
    )
    .unwrap();
    assert_eq!(s.names, ["x1", "inert", "x2"]);
    // f(A_B^(inert)) is f(A) bit for bit: both estimators vanish exactly
    assert_eq!(s.first[1], 0.0);
    assert_eq!(s.total[1], 0.0);
    // with x3 held at 0, f = sin x1 + a sin² x2 is additive: V1 = 1/2,
    // V2 = a²/8, no interaction
    let v = 0.5 + A * A / 8.0;
    for (i, vi) in [(0, 0.5), (2, A * A / 8.0)] {
        assert!((s.first[i] - vi / v).abs() < 1e-2, "{s:?}");
        assert!((s.total[i] - vi / v).abs() < 1e-2, "{s:?}");
    }
}

#[test]
fn a_spec_and_its_built_model_give_the_same_indices() {
    // a play: the lane kernel for the spec, one instance at a time for the
    // built model; every instance gives the bits it gives alone
    let spec = Spec::from_json(r#"{"type": "play", "r": 0.3}"#).unwrap();
    let x: Vec<f64> = (0..=200)
        .map(|i| 1.2 * (i as f64 * std::f64::consts::TAU / 100.0).sin())
        .collect();
    let factors = [Factor::new("r", 0.1, 0.5), Factor::new("y0", -0.2, 0.2)];
    let opts = SobolOptions {
        samples: 64,
        seed: 9,
    };
    for statistic in [
        Statistic::Energy,
        Statistic::Work,
        Statistic::Peak,
        Statistic::Rms,
        Statistic::custom(|_, y| y[y.len() / 2]),
    ] {
        let from_spec = sobol(&spec, &x, &factors, &statistic, &opts).unwrap();
        let model = spec.build().unwrap();
        let from_model = sobol_of_model(&*model, &x, &factors, &statistic, &opts).unwrap();
        assert_eq!(from_spec, from_model, "{statistic:?}");
        // the play's loop area, 4 r (A − r) per steady cycle, is set by r
        if statistic.name() == "energy" {
            assert!(from_spec.first[0] > 0.9, "{from_spec:?}");
        }
    }
}

#[test]
fn another_seed_gives_another_estimate_of_the_same_indices() {
    let run = |seed| {
        sobol_of_model(
            &ishigami(),
            &[0.0],
            &around(&["x1", "x2", "x3"]),
            &Statistic::Mean,
            &SobolOptions {
                samples: 1 << 12,
                seed,
            },
        )
        .unwrap()
    };
    let (a, b) = (run(1), run(2));
    assert_ne!(a.first, b.first);
    for i in 0..3 {
        assert!((a.total[i] - b.total[i]).abs() < 3e-2, "{a:?} {b:?}");
    }
}

fn refusal(factors: &[Factor], x: &[f64], samples: usize) -> SobolError {
    sobol_of_model(
        &ishigami(),
        x,
        factors,
        &Statistic::Mean,
        &SobolOptions { samples, seed: 0 },
    )
    .unwrap_err()
}

#[test]
fn bad_factors_are_refused_by_name() {
    let e = refusal(&around(&["x9"]), &[0.0], 64);
    assert!(matches!(&e, SobolError::UnknownFactor { name, .. } if name == "x9"));
    assert!(e.to_string().starts_with("factor `x9`: "), "{e}");

    let e = refusal(&around(&["x1", "x2", "x1"]), &[0.0], 64);
    assert!(
        matches!(&e, SobolError::RepeatedFactor { name, first, .. } if name == "x1" && first == "x1"),
        "{e}"
    );

    for (low, high) in [
        (1.0, 1.0),
        (2.0, 1.0),
        (f64::NAN, 1.0),
        (0.0, f64::INFINITY),
    ] {
        let e = refusal(&[Factor::new("x2", low, high)], &[0.0], 64);
        assert!(
            matches!(&e, SobolError::Bounds { name, .. } if name == "x2"),
            "{e}"
        );
        assert!(e.to_string().starts_with("factor `x2`: bounds"), "{e}");
    }

    assert_eq!(refusal(&[], &[0.0], 64), SobolError::NoFactors);
    let many: Vec<Factor> = (0..=MAX_FACTORS)
        .map(|_| Factor::new("x1", 0.0, 1.0))
        .collect();
    assert_eq!(
        refusal(&many, &[0.0], 64),
        SobolError::TooManyFactors {
            got: MAX_FACTORS + 1,
            max: MAX_FACTORS
        }
    );
}

#[test]
fn bad_sample_counts_and_inputs_are_refused() {
    for samples in [0, 8, 100, 3 << 10, 1 << 17] {
        let e = refusal(&around(&["x1"]), &[0.0], samples);
        assert_eq!(e, SobolError::Samples { got: samples });
        assert!(e.to_string().starts_with("samples: "), "{e}");
    }
    assert_eq!(refusal(&around(&["x1"]), &[], 64), SobolError::EmptyInput);
    let e = refusal(&around(&["x1"]), &[0.0, 1.0, f64::NAN], 64);
    assert!(
        matches!(e, SobolError::NonFiniteInput { sample: 2, .. }),
        "{e}"
    );
}

#[test]
fn a_statistic_that_does_not_vary_is_refused() {
    let e = refusal(&around(&["inert"]), &[0.0], 64);
    assert!(matches!(e, SobolError::ZeroVariance { .. }), "{e}");
}

#[test]
fn a_failing_run_names_its_factor_values() {
    // a play's threshold below 0 is out of its domain
    let spec = Spec::from_json(r#"{"type": "play", "r": 0.3}"#).unwrap();
    let e = sobol(
        &spec,
        &[0.0, 1.0, 0.0],
        &[Factor::new("r", -0.5, 0.5)],
        &Statistic::Peak,
        &SobolOptions::default(),
    )
    .unwrap_err();
    match &e {
        SobolError::Run { factors, .. } => {
            assert_eq!(factors.len(), 1);
            assert_eq!(factors[0].0, "r");
            assert!(factors[0].1 < 0.0, "{e}");
        }
        other => panic!("{other}"),
    }
    let message = e.to_string();
    assert!(
        message.starts_with("run ") && message.contains("(r = -"),
        "{message}"
    );

    let e = sobol_of_model(
        &ishigami(),
        &[0.0],
        &around(&["x1"]),
        &Statistic::custom(|_, _| f64::NAN),
        &SobolOptions::default(),
    )
    .unwrap_err();
    assert!(
        matches!(&e, SobolError::NonFiniteStatistic { factors, .. } if factors[0].0 == "x1"),
        "{e}"
    );
    let e = sobol(
        &Spec::from_json(r#"{"type": "play", "r": -1}"#).unwrap(),
        &[0.0],
        &[Factor::new("r", 0.0, 1.0)],
        &Statistic::Peak,
        &SobolOptions::default(),
    )
    .unwrap_err();
    assert!(matches!(e, SobolError::Model(_)), "{e}");
}
