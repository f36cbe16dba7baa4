//! What the leaves' unit tests share: input paths, the sampling-refinement
//! check of rate independence, central differences of a step or a trial,
//! and the field an out-of-range parameter is refused for.

use crate::{Error, Operator, Result, StepLaw};
use std::fmt::Debug;

/// `n` samples of `(a0 + slope t) sin(2π periods t)` at `t = i/n`: cycles
/// whose amplitude ramps from `a0`.
pub(crate) fn ramped_sine(n: usize, a0: f64, slope: f64, periods: f64) -> Vec<f64> {
    (0..n)
        .map(|i| {
            let t = i as f64 / n as f64;
            (a0 + slope * t) * (std::f64::consts::TAU * periods * t).sin()
        })
        .collect()
}

/// Asserts that refining `coarse` `m`-fold changes `op`'s outputs at the
/// shared samples by less than `rel` times its largest output `|y|`.
pub(crate) fn assert_refines_within<O: Operator<f64> + Clone>(
    op: &O,
    coarse: &[f64],
    m: usize,
    rel: f64,
) {
    let peak = match op.clone().run(coarse) {
        Ok(y) => y.iter().fold(0.0_f64, |p, v| p.max(v.abs())),
        Err(e) => panic!("the coarse run failed: {e}"),
    };
    let (i, d) = refinement_difference(op, coarse, m);
    assert!(d < rel * peak, "sample {i}: {d:e} (peak {peak:e})");
}

/// The central difference `(y(x + h) − y(x − h)) / 2h` of one step of
/// `law` from the state `s`.
pub(crate) fn step_difference<L: StepLaw<f64>>(law: &L, s: &L::State, x: f64, h: f64) -> f64 {
    let output = |x| match law.step(s, x) {
        Ok((_, t)) => t.output,
        Err(e) => panic!("the step at {x} failed: {e}"),
    };
    (output(x + h) - output(x - h)) / (2.0 * h)
}

/// The central difference `(y(x + h) − y(x − h)) / 2h` of `op`'s trials
/// from its committed state (the pending trial is replaced).
pub(crate) fn trial_difference<O: Operator<f64> + ?Sized>(op: &mut O, x: f64, h: f64) -> f64 {
    let mut output = |x| match op.trial(x) {
        Ok(t) => t.output,
        Err(e) => panic!("the trial at {x} failed: {e}"),
    };
    (output(x + h) - output(x - h)) / (2.0 * h)
}

/// Asserts that the tangent of `op`'s trial at `x` is the central
/// difference of its trials over `±h`, to `rel · max(|tangent|,
/// |difference|, 1)`; `context` names the case in the failure.
pub(crate) fn assert_trial_tangent<O: Operator<f64> + ?Sized>(
    op: &mut O,
    x: f64,
    h: f64,
    rel: f64,
    context: &dyn std::fmt::Display,
) {
    let tangent = match op.trial(x) {
        Ok(t) => t.tangent,
        Err(e) => panic!("{context}: the trial at {x} failed: {e}"),
    };
    let fd = trial_difference(op, x, h);
    let scale = tangent.abs().max(fd.abs()).max(1.0);
    assert!(
        (tangent - fd).abs() < rel * scale,
        "{context}: {tangent} vs {fd}"
    );
}

/// The field named by the [`Error::InvalidParameter`] that building refused
/// with; panics on anything else.
pub(crate) fn rejected_field<O: Debug>(built: Result<O>) -> String {
    match built {
        Err(Error::InvalidParameter { name, .. }) => name,
        other => panic!("expected an invalid parameter, got {other:?}"),
    }
}

/// The largest `|y_coarse[i] − y_fine[m i]|` of fresh copies of `op` run
/// over `coarse` and over the same path with each increment split into `m`
/// equal ones, with the sample where it is: `(i, difference)`.
pub(crate) fn refinement_difference<O: Operator<f64> + Clone>(
    op: &O,
    coarse: &[f64],
    m: usize,
) -> (usize, f64) {
    let mut fine = Vec::with_capacity(coarse.len() * m);
    for w in coarse.windows(2) {
        if let [a, b] = w {
            fine.extend((0..m).map(|j| a + (b - a) * j as f64 / m as f64));
        }
    }
    fine.extend(coarse.last());
    let (yc, yf) = match (op.clone().run(coarse), op.clone().run(&fine)) {
        (Ok(yc), Ok(yf)) => (yc, yf),
        (Err(e), _) | (_, Err(e)) => panic!("the refinement check's runs failed: {e}"),
    };
    yc.iter()
        .zip(yf.iter().step_by(m))
        .map(|(a, b)| (a - b).abs())
        .enumerate()
        .fold(
            (0, 0.0),
            |worst, (i, d)| if d > worst.1 { (i, d) } else { worst },
        )
}
