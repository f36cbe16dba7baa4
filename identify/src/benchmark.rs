//! Identification of the Bouc-Wen benchmark system (Noël & Schoukens) from
//! a measured record, with the composed model of
//! `hysteron_models::benchmark`.

use crate::{fit, free_by_names, FitError, FitOptions, FitReport};
use hysteron_models::benchmark::{boucwen_system, BoucWenBenchmarkParams};
use hysteron_models::composition::OperatorExt;
use hysteron_models::signal::fft_upsample;
use hysteron_operators::Error;

/// The seven physical parameters, as named in the composed system
/// (`forward.mass-spring-damper.*`, `back.bouc_wen.*`; unique suffixes).
pub const FREE: [&str; 7] = ["m", "c", "k", "alpha", "beta", "gamma", "n"];

/// Why the benchmark identification failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BenchmarkError {
    /// The start parameters or the record are invalid.
    #[error("{0}")]
    Model(#[from] Error),
    /// The fit could not run.
    #[error("fit: {0}")]
    Fit(#[from] FitError),
}

/// The result of [`identify_boucwen`].
#[derive(Debug, Clone, PartialEq)]
pub struct BenchmarkIdentification {
    /// The identified system.
    pub params: BoucWenBenchmarkParams,
    /// The fit report (parameters with standard errors and intervals).
    pub report: FitReport,
}

/// Fits `m, c, k, A, β', γ', n` of the benchmark system to a record `(u, y)`
/// sampled at `start.fs` that starts from rest and whose input is periodic
/// over the record (the multisine records are whole periods): the input is
/// upsampled `start.upsample` times by exact trigonometric interpolation,
/// the system runs at the integration rate from rest, and its output at
/// the data samples is compared with `y` (the fit's `stride`). The fit is
/// a continuation: six parameters with `n` held at its start, then all
/// seven; the report is the second fit's.
pub fn identify_boucwen(
    u: &[f64],
    y: &[f64],
    start: &BoucWenBenchmarkParams,
    opts: &FitOptions,
) -> Result<BenchmarkIdentification, BenchmarkError> {
    let fine = fft_upsample(u, start.upsample)?;
    let model = boucwen_system(start)?.boxed();
    let opts = FitOptions {
        stride: start.upsample,
        ..opts.clone()
    };
    // Continuation: the exponent changes the units of β' and γ' (1/m^n),
    // so a wrong n makes a long, curved valley. First fit the other six
    // with n held, then all seven from there.
    let six = free_by_names(model.as_ref(), &FREE[..6])?;
    let first = fit(model.as_ref(), &fine, y, &six, &opts)?;
    let all = free_by_names(first.model.as_ref(), &FREE)?;
    let f = fit(first.model.as_ref(), &fine, y, &all, &opts)?;
    // `i < 7`: the report has one entry per name of `FREE` (7).
    #[allow(clippy::indexing_slicing)]
    let v = |i: usize| f.report.params[i].value;
    let params = BoucWenBenchmarkParams {
        m: v(0),
        c: v(1),
        k: v(2),
        a: v(3),
        beta: v(4),
        gamma: v(5),
        n: v(6),
        ..*start
    };
    Ok(BenchmarkIdentification {
        params,
        report: f.report,
    })
}
