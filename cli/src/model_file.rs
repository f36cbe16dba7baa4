//! Model spec files named on the command line: how the commands read and
//! build them, and the one error every command gives when such a file
//! cannot be read, parsed or built.

use crate::models::{Spec, SpecError};
use crate::Operator;
use std::path::{Path, PathBuf};

/// Reads and parses the spec file at `path`.
pub fn read(path: &Path) -> Result<Spec, ModelFileError> {
    Spec::from_json_file(path).map_err(|e| ModelFileError::new(path, e))
}

/// Builds `spec`, read from the spec file at `path` (which its error
/// names).
pub fn build(path: &Path, spec: &Spec) -> Result<Box<dyn Operator<f64>>, ModelFileError> {
    spec.build().map_err(|e| ModelFileError::new(path, e))
}

/// Reads the spec file at `path` and builds it once to check it, so that
/// the spec's own errors come before any record is read: a sample period
/// the spec leaves to the data is a stand-in ([`Spec::STAND_IN_DT`]) for
/// this check. Returns the spec as read, and the model so built.
pub fn read_checked(path: &Path) -> Result<(Spec, Box<dyn Operator<f64>>), ModelFileError> {
    let spec = read(path)?;
    let model = build(path, &spec.or_dt(Spec::STAND_IN_DT))?;
    Ok((spec, model))
}

/// A model spec file that could not be read, parsed or built: `model
/// `PATH`: message`, the message naming the exact field where the spec
/// layer knows it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("model `{}`: {}", path.display(), message(error))]
pub struct ModelFileError {
    /// The spec file.
    pub path: PathBuf,
    /// What the spec layer said.
    pub error: SpecError,
}

impl ModelFileError {
    /// Wraps `error`, raised for the spec file at `path`.
    pub fn new(path: &Path, error: SpecError) -> Self {
        ModelFileError {
            path: path.to_path_buf(),
            error,
        }
    }
}

/// The spec error's message; an I/O error's without its path, which the
/// wrapper already names.
pub fn message(error: &SpecError) -> String {
    match error {
        SpecError::Io { message, .. } => message.clone(),
        e => e.to_string(),
    }
}
