//! # hysteron-identify
//!
//! Parameter identification for any hysteron model:
//!
//! * [`fit`]: Levenberg-Marquardt (the `levenberg-marquardt` crate, on
//!   nalgebra) over any subset of a model's flat parameter vector, one
//!   record or several ([`fit_records`]), bounded parameters fitted
//!   through a reparametrization ([`Reparam`]); the Jacobian is exact by
//!   default, from one pass of the model over dual numbers per 8
//!   parameters ([`Jacobian::Exact`], forward-mode derivatives through
//!   every operator and implicit solve), with central finite differences
//!   as the alternative ([`Jacobian::FiniteDifferences`]); a [`FitReport`]
//!   gives standard errors, confidence intervals and identifiability
//!   warnings ([`diagnostics`]);
//! * [`multistart`]: the same fit from a Latin hypercube of starts, the
//!   best kept;
//! * [`band`]: uncertainty bands around a fitted model's output
//!   ([`Fit::predict_band`]), linearized or Monte Carlo;
//! * [`batch`]: many parameter sets or many records simulated in parallel;
//! * [`sobol`]: global sensitivity, the Sobol first-order and total
//!   indices of a statistic of a model's output (Saltelli design, one
//!   ensemble for all runs);
//! * [`metrics`]: error figures of a model against a measured record (RMS,
//!   largest error, NRMSE) and a zero-phase Butterworth low-pass.
//!
//! Kept in its own crate so that nalgebra stays out of the core.

#![warn(missing_docs)]
// The library promises never to panic on user input: no unwrap/expect/panic
// and no unchecked indexing outside tests (the lints are in the workspace
// Cargo.toml; each exception is an `allow` with the invariant that makes it safe).

pub mod band;
pub mod batch;
pub mod benchmark;
mod compressed;
pub mod diagnostics;
pub mod ensemble;
mod error;
mod fit;
pub mod metrics;
pub mod multistart;
mod options;
mod outcome;
pub mod paper;
mod problem;
mod record;
pub mod report;
pub mod selection;
pub mod sobol;
mod transform;
mod triangular;

pub use error::FitError;
pub use fit::{fit, fit_records, fit_with_progress, free_by_names};
pub use multistart::{fit_multistart, MultiStart};
pub use options::{FitOptions, Jacobian, Progress};
pub use outcome::{
    Fit, FitReport, FitStatus, FittedParam, IdentifiabilityWarning, RecordFit, StartsSummary,
};
pub use record::Record;
pub use transform::{Reparam, BOUNDARY_NUDGE};
