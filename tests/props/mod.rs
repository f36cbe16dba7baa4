//! The proptest harness shared by the property-test files (`laws`,
//! `preisach`, `friction`, `pi_inverse`): case counts, the measured-maximum
//! runner, and small helpers.
#![allow(dead_code)] // each test crate uses a subset

use proptest::prelude::*;
use proptest::test_runner::{TestCaseError, TestRunner};
use std::cell::Cell;
use std::fmt::Debug;

/// `n` times the environment variable `LAWS_CASES_FACTOR` (default 1), for
/// a deeper run.
pub fn cases(n: u32) -> u32 {
    let factor = std::env::var("LAWS_CASES_FACTOR")
        .ok()
        .and_then(|f| f.parse::<u32>().ok())
        .unwrap_or(1);
    n * factor
}

/// A proptest configuration with [`cases`]`(n)` cases that writes no
/// regression files.
pub fn config(n: u32) -> ProptestConfig {
    ProptestConfig {
        cases: cases(n),
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// Turns a library error into a test failure.
pub fn ok<T>(r: hysteron::Result<T>) -> Result<T, TestCaseError> {
    r.map_err(|e| TestCaseError::fail(format!("library error: {e}")))
}

/// Trials and commits `xs`: the outputs with their tangents.
pub fn trials(
    op: &mut impl hysteron::Operator<f64>,
    xs: &[f64],
) -> Result<Vec<hysteron::Trial<f64>>, TestCaseError> {
    xs.iter()
        .map(|&x| {
            let t = ok(op.trial(x))?;
            op.commit();
            Ok(t)
        })
        .collect()
}

/// Runs `property` on [`cases`]`(n)` random values; the property returns a
/// measured error (in the unit named by `label`), the largest one is
/// printed at the end and returned.
pub fn measure<S>(
    label: &str,
    n: u32,
    strategy: S,
    property: impl Fn(S::Value) -> Result<f64, TestCaseError>,
) -> f64
where
    S: Strategy,
    S::Value: Debug,
{
    let max = Cell::new(0.0_f64);
    let mut runner = TestRunner::new(config(n));
    let result = runner.run(&strategy, |v| {
        let e = property(v)?;
        max.set(max.get().max(e));
        Ok(())
    });
    let n = runner.config().cases;
    match result {
        Ok(()) => eprintln!("{label}: max {:.3e} over {n} cases", max.get()),
        Err(e) => panic!("{label}: {e}"),
    }
    max.get()
}

/// The bit patterns, for exact comparisons that also see signed zeros.
pub fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|y| y.to_bits()).collect()
}

/// `max |x|`.
pub fn max_abs(xs: &[f64]) -> f64 {
    xs.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// `a + (b − a) t`, kept inside `[a, b]` (rounding could step outside, which
/// would add a reversal).
pub fn lerp(a: f64, b: f64, t: f64) -> f64 {
    (a + (b - a) * t).clamp(a.min(b), a.max(b))
}

/// Inserts `m_i` linearly interpolated samples before each sample `x_i`
/// (the first segment starts at the initial input 0). Returns the refined
/// signal and the indices of the original samples in it.
pub fn refine(xs: &[f64], ms: &[usize]) -> (Vec<f64>, Vec<usize>) {
    let mut fine = Vec::new();
    let mut at = Vec::with_capacity(xs.len());
    let mut prev = 0.0;
    for (i, &x) in xs.iter().enumerate() {
        let m = ms[i % ms.len()];
        for k in 1..=m {
            fine.push(lerp(prev, x, k as f64 / (m + 1) as f64));
        }
        at.push(fine.len());
        fine.push(x);
        prev = x;
    }
    (fine, at)
}
