//! `hysteron export-fmu`: a model spec as an FMI 2.0 co-simulation FMU.
//!
//! The FMU is a zip archive holding `modelDescription.xml` (the input `x`,
//! the output `y`, and every parameter as a tunable Real named by its path
//! with the spec's value as its start), `binaries/linux64/<id>.so` (a copy
//! of `libhysteron_c.so`, which implements the `fmi2*` functions for any
//! spec) and `resources/model.json` (the spec, read when the FMU is
//! instantiated). The semantics are those of `hysteron_c::fmi2`.

use crate::csvio::{self, CsvIoError, SameFile};
use crate::model_file::ModelFileError;
use crate::models::Spec;
use hysteron_c::fmi2::model_description;
use hysteron_c::Model;
use std::io::Write;
use std::path::{Path, PathBuf};
use zip::write::SimpleFileOptions;

/// Options of `hysteron export-fmu`: its command-line flags, whose doc
/// comments are their help.
#[derive(Debug, Clone, clap::Args)]
pub struct ExportFmuOptions {
    /// The model spec (JSON, see hysteron::models::Spec).
    #[arg(long, value_name = "SPEC.json")]
    pub model: PathBuf,
    /// The FMU to write (a zip archive, written atomically).
    #[arg(long, value_name = "MODEL.fmu")]
    pub output: PathBuf,
    /// The model's name and identifier (letters, digits and `_`;
    /// default: the output's file name).
    #[arg(long, value_name = "NAME")]
    pub name: Option<String>,
    /// The FMU binary (default: libhysteron_c.so next to this program,
    /// built by `cargo build --release`).
    #[arg(long, value_name = "libhysteron_c.so")]
    pub library: Option<PathBuf>,
}

/// Why an FMU could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ExportFmuError {
    /// The spec file.
    #[error(transparent)]
    Model(#[from] ModelFileError),
    /// The model name is not usable as an FMI model identifier.
    #[error(
        "--name `{0}`: a model identifier is a letter or `_` followed by letters, digits or `_`"
    )]
    Name(String),
    /// The FMU binary was not found or not readable.
    #[error("the FMU binary `{}`: {reason}; build it with `cargo build --release -p hysteron-c`, or give its path with --library", path.display())]
    Library {
        /// Where it was looked for.
        path: PathBuf,
        /// What went wrong.
        reason: String,
    },
    /// Only Linux x86-64 binaries are packed.
    #[error("export-fmu packs binaries/linux64 only: this program was built for {0}")]
    Platform(&'static str),
    /// The output names the model file.
    #[error(transparent)]
    SameFile(#[from] SameFile),
    /// Writing the archive.
    #[error(transparent)]
    Write(#[from] CsvIoError),
}

/// What was written.
#[derive(Debug, Clone, PartialEq)]
pub struct ExportFmuReport {
    /// The FMU.
    pub output: PathBuf,
    /// The model identifier (the binary's name).
    pub identifier: String,
    /// Number of tunable parameters.
    pub parameters: usize,
}

impl std::fmt::Display for ExportFmuReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "wrote {} (FMI 2.0 co-simulation, model identifier `{}`: input x, output y, {} tunable parameters)",
            self.output.display(),
            self.identifier,
            self.parameters
        )
    }
}

/// A model identifier from `name`: letters, digits and `_`, not starting
/// with a digit (a C identifier, as FMI demands of `modelIdentifier`).
fn identifier(name: &str) -> Result<String, ExportFmuError> {
    let ok = name
        .chars()
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    if ok {
        Ok(name.to_string())
    } else {
        Err(ExportFmuError::Name(name.to_string()))
    }
}

/// The default model name: the output's file stem with every character
/// that cannot stand in an identifier replaced by `_`.
fn default_name(output: &Path) -> String {
    let stem = output
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut id: String = stem
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if !id.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') {
        id.insert(0, '_');
    }
    id
}

/// The FMU binary: `--library`, or `libhysteron_c.so` next to this
/// program.
fn library(given: Option<&Path>) -> Result<(PathBuf, Vec<u8>), ExportFmuError> {
    if !(cfg!(target_os = "linux") && cfg!(target_arch = "x86_64")) {
        return Err(ExportFmuError::Platform(std::env::consts::OS));
    }
    let path = match given {
        Some(p) => p.to_path_buf(),
        None => std::env::current_exe()
            .ok()
            .and_then(|exe| exe.parent().map(|d| d.join("libhysteron_c.so")))
            .unwrap_or_else(|| PathBuf::from("libhysteron_c.so")),
    };
    let bytes = std::fs::read(&path).map_err(|e| ExportFmuError::Library {
        path: path.clone(),
        reason: e.to_string(),
    })?;
    if !bytes.starts_with(b"\x7fELF") {
        return Err(ExportFmuError::Library {
            path,
            reason: "not an ELF shared library".into(),
        });
    }
    Ok((path, bytes))
}

/// Writes the FMU.
pub fn run(opts: &ExportFmuOptions) -> Result<ExportFmuReport, ExportFmuError> {
    let spec =
        Spec::from_json_file(&opts.model).map_err(|e| ModelFileError::new(&opts.model, e))?;
    let json = spec
        .to_json_pretty()
        .map_err(|e| ModelFileError::new(&opts.model, e))?;
    let model = Model::from_json(&json).map_err(|e| ModelFileError::new(&opts.model, e))?;
    let id = identifier(
        &opts
            .name
            .clone()
            .unwrap_or_else(|| default_name(&opts.output)),
    )?;
    let (_, binary) = library(opts.library.as_deref())?;
    let description = model_description(&model, &json, &id, &id);
    csvio::refuse_same("output", &opts.output, &[("model", opts.model.as_path())])?;
    csvio::write_atomic(&opts.output, |w| {
        let mut zip = zip::ZipWriter::new(w);
        let deflate =
            SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
        let binary_options = deflate.unix_permissions(0o755);
        zip.start_file("modelDescription.xml", deflate)?;
        zip.write_all(description.as_bytes())?;
        zip.start_file(format!("binaries/linux64/{id}.so"), binary_options)?;
        zip.write_all(&binary)?;
        zip.start_file("resources/model.json", deflate)?;
        zip.write_all(json.as_bytes())?;
        zip.finish()?;
        Ok(())
    })?;
    Ok(ExportFmuReport {
        output: opts.output.clone(),
        identifier: id,
        parameters: model.names().len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identifiers_are_c_identifiers() {
        assert_eq!(identifier("paper_model").unwrap(), "paper_model");
        for bad in ["", "1a", "a-b", "a b", "ä"] {
            assert!(identifier(bad).is_err(), "{bad}");
        }
        assert_eq!(
            default_name(Path::new("out/my-model.v2.fmu")),
            "my_model_v2"
        );
        assert_eq!(default_name(Path::new("2d.fmu")), "_2d");
    }
}
