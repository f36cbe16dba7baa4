//! The Python exceptions and how the library's errors map onto them.
//!
//! ```text
//! ValueError
//! └── HysteronError          every error of the package
//!     ├── SpecError          a spec that is not valid JSON or not a spec
//!     ├── ParameterError     a parameter outside its domain, a wrong count,
//!     │                      an unknown or ambiguous parameter name
//!     ├── InputError         an input that is not a finite 1-D float array
//!     ├── SolverError        an implicit solve or the state failed at a sample
//!     ├── AnalysisError      describing function / loop energy (not steady)
//!     └── FitError           a fit that cannot start
//! ```
//!
//! Messages are the library's, as the CLI prints them: a parameter error
//! names the parameter's path, an error at a sample says `at sample i`
//! (the exception's `sample` attribute holds `i`).

use hysteron::identify::band::BandError as RustBandError;
use hysteron::identify::FitError as RustFitError;
use hysteron::models::describing::AnalysisError as RustAnalysisError;
use hysteron::models::SpecError as RustSpecError;
use hysteron::Error;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::PyErr;

pyo3::create_exception!(
    hysteron_rs,
    HysteronError,
    PyValueError,
    "Every error of hysteron_rs (a ValueError)."
);
pyo3::create_exception!(
    hysteron_rs,
    SpecError,
    HysteronError,
    "A spec that is not valid JSON or not a spec; the message names the path in the document."
);
pyo3::create_exception!(
    hysteron_rs,
    ParameterError,
    HysteronError,
    "A parameter outside its domain, a parameter vector of the wrong length, or an unknown or ambiguous parameter name."
);
pyo3::create_exception!(
    hysteron_rs,
    InputError,
    HysteronError,
    "An input that is not a non-empty, finite, 1-D float array (the message names the sample)."
);
pyo3::create_exception!(
    hysteron_rs,
    SolverError,
    HysteronError,
    "A model that failed while running: an implicit solve without a root, a jump, a non-finite output."
);
pyo3::create_exception!(
    hysteron_rs,
    AnalysisError,
    HysteronError,
    "A describing-function or loop-energy analysis that could not run or did not reach a steady cycle."
);
pyo3::create_exception!(
    hysteron_rs,
    FitError,
    HysteronError,
    "A fit that cannot start (empty or mismatched records, no free parameters, a bad option)."
);

/// Registers the exception classes in the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("HysteronError", py.get_type::<HysteronError>())?;
    m.add("SpecError", py.get_type::<SpecError>())?;
    m.add("ParameterError", py.get_type::<ParameterError>())?;
    m.add("InputError", py.get_type::<InputError>())?;
    m.add("SolverError", py.get_type::<SolverError>())?;
    m.add("AnalysisError", py.get_type::<AnalysisError>())?;
    m.add("FitError", py.get_type::<FitError>())?;
    Ok(())
}

/// The exception of a library error, with `sample` set for an error at a
/// sample.
pub fn operator_error(py: Python<'_>, e: Error) -> PyErr {
    let message = e.to_string();
    let (sample, inner) = match e {
        Error::AtSample { index, source } => (Some(index), *source),
        other => (None, other),
    };
    let err = match inner {
        Error::InvalidParameter { .. } | Error::ParamCount { .. } => {
            ParameterError::new_err(message)
        }
        Error::NonFiniteInput { .. } | Error::LengthMismatch { .. } => InputError::new_err(message),
        _ => SolverError::new_err(message),
    };
    if let Some(i) = sample {
        // Setting an attribute on a fresh exception instance cannot fail
        // but for memory exhaustion; the message carries the index anyway.
        let _ = err.value(py).setattr("sample", i);
    }
    err
}

/// The exception of a spec error: a parameter rejected when building is
/// a [`ParameterError`], anything else about the document a [`SpecError`].
pub fn spec_error(e: RustSpecError) -> PyErr {
    match e {
        RustSpecError::Invalid { .. } => ParameterError::new_err(e.to_string()),
        other => SpecError::new_err(other.to_string()),
    }
}

/// The exception of a fit error.
pub fn fit_error(py: Python<'_>, e: RustFitError) -> PyErr {
    match e {
        RustFitError::UnknownParameter { .. } | RustFitError::AmbiguousParameter { .. } => {
            ParameterError::new_err(e.to_string())
        }
        RustFitError::Start(inner) => {
            let err = operator_error(py, inner);
            FitError::new_err(format!(
                "the model fails at the starting parameters: {}",
                err.value(py)
            ))
        }
        other => FitError::new_err(other.to_string()),
    }
}

/// The exception of a band error: the input's errors an [`InputError`]
/// (`sample` set for a sample that is not finite), the model's as
/// [`operator_error`], a fit without a covariance or a dual twin and too
/// few draws a [`FitError`], a bad `level` or `draws` a [`HysteronError`].
pub fn band_error(py: Python<'_>, e: RustBandError) -> PyErr {
    match e {
        RustBandError::Model(inner) => operator_error(py, inner),
        RustBandError::NonFiniteInput { sample, .. } => {
            let err = InputError::new_err(e.to_string());
            let _ = err.value(py).setattr("sample", sample);
            err
        }
        RustBandError::EmptyInput => InputError::new_err(e.to_string()),
        RustBandError::Singular | RustBandError::NoDualTwin | RustBandError::TooFewDraws { .. } => {
            FitError::new_err(e.to_string())
        }
        RustBandError::NonFiniteSensitivity { .. } => SolverError::new_err(e.to_string()),
        other => HysteronError::new_err(other.to_string()),
    }
}

/// The exception of an analysis error.
pub fn analysis_error(e: RustAnalysisError) -> PyErr {
    AnalysisError::new_err(e.to_string())
}
