//! Helpers shared by the identification crate's integration tests.
#![allow(dead_code)] // each test crate uses a subset

pub mod jiles_atherton;

use hysteron_identify::FitReport;

/// Asserts that every fitted parameter of `r` lies within the relative
/// error `tol` of its true value `want[index]`.
pub fn assert_recovered_within(r: &FitReport, want: &[f64], tol: f64) {
    for p in &r.params {
        let rel = (p.value - want[p.index]).abs() / want[p.index].abs();
        assert!(
            rel < tol,
            "{}: {} vs {} (rel {rel:e})",
            p.name,
            p.value,
            want[p.index]
        );
    }
}
