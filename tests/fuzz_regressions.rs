//! Inputs the cargo-fuzz targets (`fuzz/`) found failing, one test each,
//! named after what went wrong.

use hysteron::models::spec::registry::leaf_kind;
use hysteron::prelude::*;

/// A registered leaf built from its declared example, as the fuzz targets
/// build them.
fn example(kind: &str) -> Box<dyn Operator<f64>> {
    let leaf = leaf_kind(kind).unwrap();
    leaf.build(&leaf.example()).unwrap()
}

/// `operator_contract`: a cascade whose first stage is flat (a play inside
/// its gap, tangent 0) and whose second stage is vertical there (the
/// inverse of a play inside its gap, tangent +∞) reported the chain rule's 0 · ∞ =
/// NaN as its tangent. The first stage's output does not move, so neither
/// does the cascade's: the tangent is 0.
#[test]
fn cascade_of_flat_into_vertical_has_tangent_zero_not_nan() {
    let mut op = example("play").then(example("play").inverse());
    let t = op.trial(0.0).unwrap();
    assert_eq!(t.output, op.clone().run(&[0.0]).unwrap()[0]);
    assert!(t.output.is_finite());
    assert_eq!(t.tangent, 0.0, "tangent {}", t.tangent);
}

/// `operator_contract`: a feedback loop whose forward path is vertical (the
/// inverse of a dead zone inside its zone, tangent +∞) computed its tangent
/// `A'/(1 + A'B')` as ∞/∞ = NaN. The limit is `1/B'`.
#[test]
fn feedback_with_vertical_forward_path_has_tangent_one_over_back() {
    let back = Oversample::new(example("mass_spring_damper"), 3).unwrap();
    let mut op = example("dead_zone").inverse().feedback(back);
    let t = op.trial(0.0).unwrap();
    assert!(t.output.is_finite());
    assert!(!t.tangent.is_nan(), "tangent {}", t.tangent);
}

/// `operator_contract`: a mechanical series of two elements, one of them
/// rigid (the inverse of a dead zone inside its zone, tangent +∞),
/// computed its stiffness `kl·kr/(kl + kr)` as ∞/∞ = NaN. A rigid element
/// adds no compliance: the stiffness is the other element's.
#[test]
fn series_with_a_rigid_element_has_the_other_stiffness() {
    let mut op = example("dead_zone")
        .inverse()
        .series(example("pi_inverse").inverse());
    let t = op.trial(0.0).unwrap();
    assert!(t.output.is_finite());
    assert!(!t.tangent.is_nan(), "tangent {}", t.tangent);
}

/// `operator_contract`: a feedback loop whose back path is vertical (the
/// inverse of a dead zone inside its zone, tangent +∞) and whose forward
/// path is flat there (an elastoplastic element sliding at x = 4.2e255)
/// computed `A'/(1 + A'B')` as 0/(1 + 0·∞) = NaN. The limit is 0 (and 0 for
/// any finite `A'`).
#[test]
fn feedback_with_vertical_back_path_has_tangent_zero() {
    let mut op = example("elastoplastic").feedback(example("dead_zone").inverse());
    match op.trial(4.2183963570748966e255) {
        Ok(t) => {
            assert!(t.output.is_finite());
            assert_eq!(t.tangent, 0.0, "tangent {}", t.tangent);
        }
        Err(e) => panic!("the fuzzer's case ran without an error: {e}"),
    }
}

/// `operator_contract`: a cascade whose first stage is vertical (the
/// inverse of a backlash contact inside its gap, tangent +∞) and whose
/// second stage is flat (a play inside its gap) reported ∞ · 0 = NaN as its
/// tangent. The slope is not defined by the two tangents there; the flat
/// stage's 0 is reported.
#[test]
fn cascade_of_vertical_into_flat_has_tangent_zero_not_nan() {
    let mut op = example("backlash_contact").inverse().then(example("play"));
    let t = op.trial(0.0).unwrap();
    assert!(t.output.is_finite());
    assert_eq!(t.tangent, 0.0, "tangent {}", t.tangent);
}

/// `operator_contract`: a gain's batch loop checked its outputs only after
/// the whole batch, so `[an input that overflows, NaN]` failed at sample 1
/// (the NaN input) in `process` but at sample 0 (the overflow) in the
/// trial/commit loop. The batch now fails where the loop does, with the
/// same error, and the memoryless leaves share that loop.
#[test]
fn a_gain_overflowing_before_a_nan_input_fails_at_the_overflow() {
    let xs = [10.0, f64::NAN];
    let mut op = Gain::new(1e308).unwrap();
    let trial = op.trial(xs[0]).unwrap_err().to_string();
    let processed = op.clone().run(&xs).unwrap_err();
    assert!(processed.to_string().contains("sample 0"), "{processed}");
    assert!(
        processed.to_string().contains(&trial),
        "{processed} vs {trial}"
    );
    // the model is left as the trial loop leaves it: nothing committed
    assert_eq!(op.run(&[1.0]).unwrap(), [1e308]);
}
