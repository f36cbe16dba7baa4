//! Parameters and inputs at the ends of `f64`: near `±1.8e308`, subnormal,
//! zero. Every registered leaf (its example spec) and every example spec of
//! the repository (`examples/specs/*.json`: the paper model, Bouc-Wen
//! benchmark, series, feedback, inverse…) takes each parameter set to each
//! extreme value in turn and runs inputs just as extreme. The promise
//! checked: no panic; a rejected parameter vector is a typed error that
//! leaves the model as it was; every output is finite or the sample is a
//! typed error; `process` gives what trial + commit gives, the same error
//! included.

use hysteron::models::spec::registry::LEAVES;
use hysteron::models::Spec;
use hysteron::prelude::*;

mod common;
use common::bits;

/// Parameter values at the ends of the range of `f64`.
const EXTREME_PARAMS: [f64; 9] = [
    1e308,
    -1e308,
    f64::MAX,
    1e300,
    5e-324,
    -5e-324,
    f64::MIN_POSITIVE,
    1e-300,
    0.0,
];

/// Inputs with reversals between ordinary and extreme magnitudes.
const EXTREME_INPUTS: [f64; 14] = [
    0.0,
    0.5,
    -0.5,
    5e-324,
    -5e-324,
    1.0,
    1e300,
    -1e300,
    f64::MAX,
    -f64::MAX,
    1e-300,
    0.25,
    1e308,
    0.0,
];

/// Runs `xs` through `op` by trial + commit until the first error: the
/// outputs, and the index of the failing sample if any. Panics (failing
/// the test) on a non-finite output.
fn trial_commit(label: &str, op: &mut dyn Operator<f64>, xs: &[f64]) -> (Vec<f64>, Option<usize>) {
    let mut ys = Vec::new();
    for (i, &x) in xs.iter().enumerate() {
        match op.trial(x) {
            Ok(t) => {
                assert!(
                    t.output.is_finite(),
                    "{label}: sample {i} (x = {x:e}) gave {} without an error",
                    t.output
                );
                op.commit();
                ys.push(t.output);
            }
            Err(_) => return (ys, Some(i)),
        }
    }
    (ys, None)
}

/// Every parameter of `op` set to every extreme value, one at a time.
fn check_extremes(label: &str, op: Box<dyn Operator<f64>>) -> (usize, usize) {
    let p = op.params();
    let names = op.param_names();
    let (mut accepted, mut refused) = (0, 0);
    for (i, name) in names.iter().enumerate() {
        for v in EXTREME_PARAMS {
            let mut q = p.clone();
            q[i] = v;
            let mut m = op.clone();
            let label = format!("{label}, {name} = {v:e}");
            if m.set_params(&q).is_err() {
                assert_eq!(
                    bits(&m.params()),
                    bits(&p),
                    "{label}: a refused parameter vector changed the model"
                );
                refused += 1;
                continue;
            }
            accepted += 1;
            let mut batch = m.clone();
            let (ys, failed) = trial_commit(&label, &mut *m, &EXTREME_INPUTS);
            let mut out = vec![0.0; EXTREME_INPUTS.len()];
            match batch.process(&EXTREME_INPUTS, &mut out) {
                Ok(()) => {
                    assert_eq!(failed, None, "{label}: process ran what trial refused");
                    assert_eq!(
                        bits(&out),
                        bits(&ys),
                        "{label}: process differs from trial + commit"
                    );
                }
                Err(e) => assert!(
                    failed.is_some(),
                    "{label}: process failed ({e}) where trial + commit ran"
                ),
            }
        }
    }
    (accepted, refused)
}

#[test]
fn every_leaf_at_the_ends_of_f64() {
    let mut total = (0, 0);
    for leaf in LEAVES {
        let op = leaf.example_spec().build().expect("example spec");
        let (a, r) = check_extremes(leaf.kind(), op);
        total = (total.0 + a, total.1 + r);
    }
    eprintln!(
        "leaves: {} parameter vectors accepted, {} refused",
        total.0, total.1
    );
    // Both branches are exercised.
    assert!(total.0 > 50 && total.1 > 50, "{total:?}");
}

#[test]
fn every_example_spec_at_the_ends_of_f64() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/specs");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).expect("examples/specs") {
        let path = entry.expect("entry").path();
        if path.extension().and_then(|e| e.to_str()) != Some("json") {
            continue;
        }
        let spec = Spec::from_json_file(&path).expect("example spec");
        let op = spec.build().expect("builds");
        check_extremes(&path.display().to_string(), op);
        n += 1;
    }
    assert!(n >= 3, "{n} example specs");
}
