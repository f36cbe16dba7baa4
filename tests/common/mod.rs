//! Helpers shared by the library's integration tests.
#![allow(dead_code)] // each test crate uses a subset

use hysteron::prelude::*;

/// The bit patterns of `v` (for bit-for-bit comparisons that show where
/// they differ).
pub fn bits<T: Float>(v: &[T]) -> Vec<u64> {
    v.iter().map(|y| y.as_f64().to_bits()).collect()
}

/// The reference loop every `process` must equal: `trial` then `commit`,
/// sample by sample.
pub fn trial_commit_loop<T: Float, O: Operator<T> + ?Sized>(op: &mut O, xs: &[T]) -> Vec<T> {
    xs.iter()
        .map(|&x| {
            let t = op.trial(x).expect("trial");
            op.commit();
            t.output
        })
        .collect()
}
