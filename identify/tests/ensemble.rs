//! The ensemble's contract: every instance of every registered leaf, and
//! of composed models, gives the bits (or the error) it gives alone, on
//! whichever kernel the ensemble picks; the lane kernels are picked where
//! they exist; bad input is a typed error.

#![allow(clippy::unwrap_used, clippy::indexing_slicing, clippy::panic)]

use hysteron_identify::ensemble::{Ensemble, EnsembleError, Kernel};
use hysteron_models::spec::registry::LEAVES;
use hysteron_models::Spec;
use hysteron_operators::Operator;
use nalgebra::DMatrix;

/// Reversals of growing amplitude, holds and small steps.
fn input(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| {
            let t = i as f64 / n as f64;
            let hold = if i % 23 == 5 { 0.0 } else { 1.0 };
            (0.2 + 2.0 * t) * (std::f64::consts::TAU * 4.0 * t).sin() * hold
                + 0.05 * (i as f64 * 0.37).sin()
        })
        .collect()
}

/// `n` parameter rows around the model's own: entry `j` of row `i` scaled
/// by `1 + 0.03 ((i + j) mod 7 − 3)`, and row 2 with its first entry made
/// negative (out of domain for most leaves).
fn rows_around(model: &dyn Operator<f64>, n: usize) -> DMatrix<f64> {
    let p = model.params();
    DMatrix::from_fn(n, p.len(), |i, j| {
        let v = p[j] * (1.0 + 0.03 * (((i + j) % 7) as f64 - 3.0));
        if i == 2 && j == 0 {
            -1.0 - v.abs()
        } else {
            v
        }
    })
}

/// Runs `spec` as an ensemble of `n` instances and checks each against
/// its own model run alone; returns the kernel used.
fn check_against_alone(spec: &Spec, n: usize) -> Kernel {
    let model = spec.build().unwrap();
    check_rows(spec, &rows_around(&*model, n), &input(600)).0
}

/// [`check_against_alone`] for the rows `params` over `x`; the kernel and
/// the failed instances.
fn check_rows(spec: &Spec, params: &DMatrix<f64>, x: &[f64]) -> (Kernel, Vec<usize>) {
    let (model, n, x) = (spec.build().unwrap(), params.nrows(), x.to_vec());
    let ensemble = Ensemble::new(spec, params).unwrap();
    let run = ensemble.run(&x).unwrap();
    for i in 0..n {
        let row: Vec<f64> = params.row(i).iter().copied().collect();
        let mut alone = dyn_clone::clone_box(&*model);
        let expected = alone.set_params(&row).and_then(|()| alone.run(&x));
        let failure = run.failures.iter().find(|f| f.instance == i);
        match (expected, failure) {
            (Ok(y), None) => {
                let got = run.row(i).unwrap();
                for (k, (a, b)) in y.iter().zip(got).enumerate() {
                    assert_eq!(
                        a.to_bits(),
                        b.to_bits(),
                        "{}: instance {i}, sample {k}: {a} alone, {b} in the ensemble",
                        spec.kind()
                    );
                }
            }
            (Err(e), Some(f)) => {
                assert_eq!(e, f.error, "{}: instance {i}", spec.kind());
                assert!(run.row(i).unwrap().iter().all(|v| v.is_nan()));
            }
            (expected, failure) => panic!(
                "{}: instance {i}: alone {:?}, in the ensemble {failure:?}",
                spec.kind(),
                expected.map(|_| "ok")
            ),
        }
    }
    let failed = run.failures.iter().map(|f| f.instance).collect();
    (ensemble.kernel(), failed)
}

/// Every registered leaf at its example (a rate-dependent one at 1 ms):
/// 19 instances, two full blocks of lanes and a part.
#[test]
fn every_leaf_in_an_ensemble_is_each_instance_alone() {
    for leaf in LEAVES {
        let spec = leaf.example_spec().or_dt(1e-3);
        let kernel = check_against_alone(&spec, 19);
        let want = match leaf.kind() {
            "play" => Kernel::Lanes("play"),
            "pi_bank" => Kernel::Lanes("pi_bank"),
            "mms" => Kernel::Lanes("mms"),
            // (its example has n = 1.5; with n = 1 in lanes, see below)
            "bouc_wen" => Kernel::Instances,
            _ => Kernel::Instances,
        };
        assert_eq!(kernel, want, "{}", leaf.kind());
    }
}

/// PI banks with a rest of plays after their whole groups of eight (13:
/// a group and a rest, the bank's two sums) step in lanes, each instance
/// with its bank's bits; banks of whole groups (16) one instance at a
/// time. A row with a negative threshold fails alone and in the ensemble.
#[test]
fn pi_banks_in_lanes_are_each_instance_alone() {
    for (m, want) in [(13, Kernel::Lanes("pi_bank")), (16, Kernel::Instances)] {
        let r: Vec<String> = (0..m).map(|k| format!("{}", 0.1 * k as f64)).collect();
        let w: Vec<String> = (0..m)
            .map(|k| format!("{}", 1.0 / (1.0 + k as f64)))
            .collect();
        let spec = Spec::from_json(&format!(
            r#"{{"type": "pi_bank", "a0": 0.2, "r": [{}], "w": [{}]}}"#,
            r.join(", "),
            w.join(", ")
        ))
        .unwrap();
        let model = spec.build().unwrap();
        let mut rows = rows_around(&*model, 21);
        // (column 0 is `a0`, any sign: a threshold made negative instead)
        rows[(2, 0)] = 0.2;
        rows[(5, 3)] = -0.1;
        let (kernel, failed) = check_rows(&spec, &rows, &input(700));
        assert_eq!(kernel, want, "{m} plays");
        assert_eq!(failed, vec![5], "{m} plays");
    }
}

/// A row's exponent and `β` (against `γ = 0.4 ± 3 %`), the kernel the
/// ensemble takes, and how many rows at least diverge under the large
/// input.
struct BoucWenRows {
    n: fn(usize) -> f64,
    beta: fn(usize) -> f64,
    kernel: Kernel,
    diverging: usize,
}

/// The Bouc-Wen spring steps in lanes with `n = 1` in every instance
/// (closed form), and one instance at a time with other exponents (each
/// on its tabulated flow, or integrated where none is): softening and
/// hardening sets, a piecewise
/// stiffness map, a row out of its domain, and rows whose state diverges
/// under a large input (flagged by the lanes, with the error each gives
/// alone), over an input driven far enough for every branch piece and the
/// saturating tails.
#[test]
fn bouc_wen_in_lanes_is_each_instance_alone() {
    let cases = [
        // β from −0.9 to 0.9: hardening sets (β + γ < 0) diverge
        BoucWenRows {
            n: |_| 1.0,
            beta: |i| -0.9 + 0.1 * i as f64,
            kernel: Kernel::Lanes("bouc_wen"),
            diverging: 3,
        },
        // tabulated softening sets (β ≥ γ), and two hardening ones
        // (integrated; they diverge)
        BoucWenRows {
            n: |i| 1.3 + 0.15 * i as f64,
            beta: |i| {
                if i % 8 == 3 {
                    -0.9
                } else {
                    0.45 + 0.05 * i as f64
                }
            },
            kernel: Kernel::Instances,
            diverging: 2,
        },
    ];
    for stiffness in ["1.5", r#"{"z": [0.0, 0.5, 2.0], "s": [1.0, 1.6, 3.0]}"#] {
        let spec = Spec::from_json(&format!(
            r#"{{"type": "bouc_wen", "w": 0.3, "alpha": 1.0, "beta": 0.6, "gamma": 0.4,
                "n": 1.0, "h0": 0.2, "z0": -0.1, "stiffness": {stiffness}}}"#
        ))
        .unwrap();
        let model = spec.build().unwrap();
        let names = model.param_names();
        let col = |name: &str| names.iter().position(|n| n == name).unwrap();
        for case in &cases {
            let mut params = rows_around(&*model, 19);
            for i in 0..19 {
                params[(i, col("n"))] = (case.n)(i);
                params[(i, col("beta"))] = (case.beta)(i);
            }
            // (β = γ: a side with c = 0)
            params[(17, col("gamma"))] = params[(17, col("beta"))];
            for (scale, diverging) in [(1.0, 0), (40.0, case.diverging)] {
                let x: Vec<f64> = input(600).iter().map(|v| scale * v).collect();
                let (kernel, failed) = check_rows(&spec, &params, &x);
                assert_eq!(kernel, case.kernel);
                // row 2 is refused; at scale 40 the hardening rows diverge
                assert!(failed.contains(&2), "{failed:?}");
                assert!(failed.len() > diverging, "{failed:?}");
            }
        }
    }
}

/// The Bouc-Wen benchmark system (a mass-spring-damper with the spring
/// fed back, oversampled 20 times) steps in lanes, and so does its
/// feedback alone; with a spring of another exponent, one instance at a
/// time. Its parameters spread around their own (one row refused), over a
/// force like the benchmark's, and under a force 40 times as large.
#[test]
fn the_benchmark_system_in_lanes_is_each_instance_alone() {
    let system =
        Spec::from_json(include_str!("../../examples/specs/boucwen-benchmark.json")).unwrap();
    let Spec::Oversample { inner, .. } = &system else {
        panic!("the benchmark system is oversampled");
    };
    let force: Vec<f64> = input(300).iter().map(|v| 30.0 * v).collect();
    for (spec, kernel) in [
        (&system, Kernel::Lanes("msd_feedback")),
        (&**inner, Kernel::Lanes("msd_feedback")),
    ] {
        let model = spec.build().unwrap();
        let mut params = rows_around(&*model, 11);
        // (the spring's exponent kept at 1)
        let names = model.param_names();
        let n = names.iter().position(|n| n.ends_with(".n")).unwrap();
        params.column_mut(n).fill(1.0);
        for scale in [1.0, 40.0] {
            let x: Vec<f64> = force.iter().map(|v| scale * v).collect();
            let (got, failed) = check_rows(spec, &params, &x);
            assert_eq!(got, kernel);
            assert!(failed.contains(&2), "{failed:?}");
        }
    }
    let other = Spec::from_json(
        &include_str!("../../examples/specs/boucwen-benchmark.json")
            .replace(r#""n": 1.0"#, r#""n": 1.5"#),
    )
    .unwrap();
    assert_eq!(check_against_alone(&other, 3), Kernel::Instances);
}

/// Composed models (the paper's, a PI cascade) run one instance at a time
/// with the same results.
#[test]
fn composed_models_in_an_ensemble_are_each_instance_alone() {
    let paper = Spec::from_json(include_str!("../../examples/specs/paper.json")).unwrap();
    assert_eq!(check_against_alone(&paper, 5), Kernel::Instances);
    let cascade = Spec::from_json(
        r#"{"type": "cascade", "first": {"type": "play", "r": 0.3},
            "second": {"type": "mms", "f_c": 1.0, "k": 20.0}}"#,
    )
    .unwrap();
    assert_eq!(check_against_alone(&cascade, 9), Kernel::Instances);
}

/// An ensemble of a built model (here one already stepped away from its
/// initial state) gives every instance the bits that the spec's ensemble
/// gives it, one instance at a time.
#[test]
fn an_ensemble_of_a_built_model_starts_each_instance_afresh() {
    let spec = Spec::from_json(r#"{"type": "mms", "f_c": 1.0, "k": 20.0}"#).unwrap();
    let mut model = spec.build().unwrap();
    model.run(&[0.3, 0.7]).unwrap();
    let params = rows_around(&*model, 11);
    let x = input(300);
    let of_model = Ensemble::of_model(&*model, &params).unwrap();
    assert_eq!(of_model.kernel(), Kernel::Instances);
    let from_spec = Ensemble::new(&spec, &params).unwrap();
    assert_eq!(from_spec.kernel(), Kernel::Lanes("mms"));
    let (a, b) = (of_model.run(&x).unwrap(), from_spec.run(&x).unwrap());
    assert_eq!(a.failures, b.failures);
    assert!(!a.failures.is_empty());
    for (k, (u, v)) in a.outputs.iter().zip(&b.outputs).enumerate() {
        assert!(u.to_bits() == v.to_bits(), "value {k}: {u} vs {v}");
    }
}

/// Bad shapes and inputs are typed errors naming what is wrong.
#[test]
fn bad_matrices_and_inputs_are_typed_errors() {
    let spec = Spec::from_json(r#"{"type": "mms", "f_c": 1.0, "k": 20.0}"#).unwrap();
    match Ensemble::new(&spec, &DMatrix::zeros(2, 2)) {
        Err(EnsembleError::Columns {
            expected: 3,
            got: 2,
            names,
        }) => {
            assert_eq!(names, "f_c, k, y0")
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        Ensemble::new(&spec, &DMatrix::zeros(0, 3)),
        Err(EnsembleError::NoInstances)
    ));
    let ensemble = Ensemble::new(&spec, &DMatrix::from_element(3, 3, 1.0)).unwrap();
    let err = ensemble.run(&[0.0, f64::INFINITY]).unwrap_err();
    assert_eq!(
        err.to_string(),
        "input: at sample 1: input sample inf is not finite"
    );
    assert!(matches!(ensemble.run(&[]), Err(EnsembleError::EmptyInput)));
}
