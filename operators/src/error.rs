//! The one error type of hysteron.

/// Everything that can go wrong when building or running an operator.
///
/// Values are carried as `f64` so the error type is not generic; they are
/// for messages only.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A parameter is outside its valid range, or not finite.
    #[error("invalid parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's name (a path through combinators where known).
        name: String,
        /// The offending value.
        value: f64,
        /// What the parameter must satisfy.
        reason: &'static str,
    },
    /// A parameter vector of the wrong length was passed to `set_params`.
    #[error("parameter vector has {got} entries, the operator has {expected}")]
    ParamCount {
        /// The number of parameters the operator has.
        expected: usize,
        /// The number that was passed.
        got: usize,
    },
    /// An input sample is NaN or infinite.
    #[error("input sample {value} is not finite")]
    NonFiniteInput {
        /// The offending value.
        value: f64,
    },
    /// A finite input drove the operator to a non-finite output
    /// (for example an unbounded Bouc-Wen state that overflowed).
    #[error("operator `{operator}` produced a non-finite output at input {input}")]
    NonFiniteOutput {
        /// The operator's name.
        operator: &'static str,
        /// The input that was applied.
        input: f64,
    },
    /// Input and output buffers passed to `process` differ in length.
    #[error("input has {input} samples but output has room for {output}")]
    LengthMismatch {
        /// Input length.
        input: usize,
        /// Output length.
        output: usize,
    },
    /// An implicit solve could not bracket its root: the equation has no
    /// solution it could find (for example a non-monotone loop, or a target
    /// outside the range of an operator being inverted).
    #[error("{solver}: no sign change found around {around} after {expansions} expansions")]
    NoBracket {
        /// Which solver failed.
        solver: &'static str,
        /// Where the search started.
        around: f64,
        /// How many times the search interval was widened.
        expansions: usize,
    },
    /// An implicit solve had its root bracketed but did not reach the
    /// tolerance within the iteration limit.
    #[error("{solver}: not converged after {iterations} iterations (bracket width {width})")]
    NotConverged {
        /// Which solver failed.
        solver: &'static str,
        /// Iterations spent.
        iterations: usize,
        /// Width of the final bracket.
        width: f64,
    },
    /// An implicit solve found where its residual changes sign, but the
    /// residual jumps there instead of passing through zero: the operator
    /// it solves for is discontinuous (a relay, a discrete Preisach grid)
    /// and no input gives the target.
    #[error("{solver}: the operator jumps from {below} to {above} at input {at}: no input reaches a target in between")]
    Jump {
        /// Which solver failed.
        solver: &'static str,
        /// The input where the jump is.
        at: f64,
        /// The output just below the jump.
        below: f64,
        /// The output just above the jump.
        above: f64,
    },
    /// An error at a given sample of a batch.
    #[error("at sample {index}: {source}")]
    AtSample {
        /// Index of the sample in the batch passed to `process`.
        index: usize,
        /// The error at that sample.
        source: Box<Error>,
    },
}

/// Shorthand for `Result<T, hysteron::Error>`.
pub type Result<T, E = Error> = core::result::Result<T, E>;

impl Error {
    /// Prefixes the parameter name of an [`Error::InvalidParameter`] with a
    /// path segment (used by combinators); other errors pass unchanged.
    pub fn in_path(self, prefix: &str) -> Self {
        match self {
            Error::InvalidParameter {
                name,
                value,
                reason,
            } => Error::InvalidParameter {
                name: format!("{prefix}.{name}"),
                value,
                reason,
            },
            other => other,
        }
    }

    /// Wraps an error with the index of the sample it happened at.
    pub fn at_sample(self, index: usize) -> Self {
        Error::AtSample {
            index,
            source: Box::new(self),
        }
    }

    /// The error of a block of samples that starts at sample `offset` of a
    /// longer record, as that record's: its sample index moved by `offset`
    /// (an error without one is returned as it is).
    pub fn offset_by(self, offset: usize) -> Self {
        match self {
            Error::AtSample { index, source } => Error::AtSample {
                index: index + offset,
                source,
            },
            other => other,
        }
    }
}
