//! Why a fit could not start.

use hysteron_operators::Error;

/// Why a fit could not start.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FitError {
    /// The record is empty, the columns differ in length, or a value is not
    /// finite.
    #[error("data: {0}")]
    Data(String),
    /// A requested free parameter is not among the model's.
    #[error("unknown parameter `{name}` (the model has: {available})")]
    UnknownParameter {
        /// The requested name.
        name: String,
        /// The model's parameter names.
        available: String,
    },
    /// A requested name matches several parameters.
    #[error("parameter name `{name}` is ambiguous: {matches}")]
    AmbiguousParameter {
        /// The requested name.
        name: String,
        /// The matching parameter names.
        matches: String,
    },
    /// Nothing to fit.
    #[error("no free parameters")]
    NoFreeParameters,
    /// A parameter index is out of range.
    #[error("parameter index {index} out of range (the model has {len})")]
    BadIndex {
        /// The index.
        index: usize,
        /// Number of parameters.
        len: usize,
    },
    /// The model cannot be simulated with the starting parameters.
    #[error("the model fails at the starting parameters: {0}")]
    Start(#[source] Error),
    /// The model cannot be simulated with the starting parameters on one
    /// of several records.
    #[error("the model fails at the starting parameters on record {record}: {source}")]
    RecordStart {
        /// The record (its index in the order given).
        record: usize,
        /// The model's error.
        #[source]
        source: Error,
    },
    /// A parameter is listed twice (in `free`, in `own`, or in both).
    #[error("parameter index {index} is listed twice")]
    Repeated {
        /// The index.
        index: usize,
    },
    /// An option is out of range.
    #[error("option `{name}`: {reason}")]
    Option {
        /// The option.
        name: &'static str,
        /// What it must satisfy.
        reason: &'static str,
    },
}

/// `Ok` where `holds`, else [`FitError::Option`] naming the option.
pub(crate) fn option(
    holds: bool,
    name: &'static str,
    reason: &'static str,
) -> Result<(), FitError> {
    if holds {
        Ok(())
    } else {
        Err(FitError::Option { name, reason })
    }
}
