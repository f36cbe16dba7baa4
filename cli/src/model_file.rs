//! Model spec files named on the command line, and the one error every
//! command gives when such a file cannot be read, parsed or built.

use crate::models::SpecError;
use std::path::{Path, PathBuf};

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
