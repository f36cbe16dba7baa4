//! `hysteron export-fmu`: a model spec as an FMI 2.0 (the default) or,
//! with `--fmi 3`, an FMI 3.0 co-simulation FMU.
//!
//! The FMU is a zip archive holding `modelDescription.xml` (the input `x`,
//! the output `y`, and every parameter as a tunable Real (FMI 3.0:
//! Float64) named by its path with the spec's value as its start; FMI 3.0
//! describes a vector parameter, `w[0]`, `w[1]`, …, as one array `w`, and
//! adds the independent variable `time`), the binary (a copy of
//! `libhysteron_c.so`, which implements the `fmi2*` and `fmi3*` functions
//! for any spec) as `binaries/linux64/<id>.so` (FMI 2.0) or
//! `binaries/x86_64-linux/<id>.so` (FMI 3.0), and `resources/model.json`
//! (the spec, read when the FMU is instantiated). The semantics are those
//! of `hysteron_c::fmi2` and `hysteron_c::fmi3`.

use crate::csvio::{self, CsvIoError, SameFile};
use crate::model_file::{self, ModelFileError};
use hysteron_c::{fmi2, fmi3, Model};
use std::io::Write;
use std::path::{Path, PathBuf};
use zip::write::SimpleFileOptions;

/// Write a model spec (JSON) as an FMI 2.0 co-simulation FMU: input x,
/// output y, every parameter a tunable Real named by its path, for
/// Simulink, OpenModelica, Dymola, FMPy and other FMI hosts (Linux
/// x86-64 binary).
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
    /// The FMU binary.
    #[command(flatten)]
    pub binary: FmuBinary,
    /// The FMI version: 2 (FMI 2.0) or 3 (FMI 3.0).
    #[arg(long, value_name = "VERSION", default_value = "2", value_parser = ["2", "3"])]
    pub fmi: String,
}

/// The FMU binary that `export-fmu` packs, and `fmu-compat` with it: the
/// `--library` flag of both.
#[derive(Debug, Clone, Default, PartialEq, clap::Args)]
pub struct FmuBinary {
    /// The FMU binary (default: libhysteron_c.so next to this program,
    /// built by `cargo build --release`).
    #[arg(long, value_name = "libhysteron_c.so")]
    pub library: Option<PathBuf>,
}

impl ExportFmuOptions {
    /// The FMI version asked for.
    fn version(&self) -> FmiVersion {
        FmiVersion::from_flag(&self.fmi).unwrap_or(FmiVersion::V2)
    }
}

/// The FMI version of an FMU, with what depends on it in the archive and
/// around it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FmiVersion {
    /// FMI 2.0.
    V2,
    /// FMI 3.0.
    V3,
}

impl FmiVersion {
    /// The version of a `--fmi` value (`2` or `3`).
    pub fn from_flag(flag: &str) -> Option<Self> {
        match flag {
            "2" => Some(FmiVersion::V2),
            "3" => Some(FmiVersion::V3),
            _ => None,
        }
    }

    /// Its `--fmi` value.
    pub fn flag(self) -> &'static str {
        match self {
            FmiVersion::V2 => "2",
            FmiVersion::V3 => "3",
        }
    }

    /// The version number, `2.0` or `3.0`.
    pub fn number(self) -> &'static str {
        match self {
            FmiVersion::V2 => "2.0",
            FmiVersion::V3 => "3.0",
        }
    }

    /// The standard's name for Linux x86-64, the platform folder of the
    /// binary (under `binaries/`).
    pub fn platform(self) -> &'static str {
        match self {
            FmiVersion::V2 => "linux64",
            FmiVersion::V3 => "x86_64-linux",
        }
    }

    /// The name of the `DoStep` function.
    pub fn do_step(self) -> &'static str {
        match self {
            FmiVersion::V2 => "fmi2DoStep",
            FmiVersion::V3 => "fmi3DoStep",
        }
    }
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
    #[error("export-fmu packs Linux x86-64 binaries only: this program was built for {0}")]
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
    /// The FMI version.
    pub fmi: FmiVersion,
}

impl std::fmt::Display for ExportFmuReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "wrote {} (FMI {} co-simulation, model identifier `{}`: input x, output y, {} tunable parameters)",
            self.output.display(),
            self.fmi.number(),
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

impl FmuBinary {
    /// The binary's bytes: from `--library`, or `libhysteron_c.so` next to
    /// this program.
    fn read(&self) -> Result<Vec<u8>, ExportFmuError> {
        if !(cfg!(target_os = "linux") && cfg!(target_arch = "x86_64")) {
            return Err(ExportFmuError::Platform(std::env::consts::OS));
        }
        let path = match &self.library {
            Some(p) => p.clone(),
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
        Ok(bytes)
    }
}

/// Writes the FMU.
pub fn run(opts: &ExportFmuOptions) -> Result<ExportFmuReport, ExportFmuError> {
    let spec = model_file::read(&opts.model)?;
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
    let binary = opts.binary.read()?;
    let version = opts.version();
    let description = match version {
        FmiVersion::V2 => fmi2::model_description(&model, &json, &id, &id),
        FmiVersion::V3 => fmi3::model_description(&model, &json, &id, &id),
    };
    csvio::refuse_same("output", &opts.output, &[("model", opts.model.as_path())])?;
    csvio::write_atomic(&opts.output, |w| {
        let mut zip = zip::ZipWriter::new(w);
        let deflate =
            SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
        let binary_options = deflate.unix_permissions(0o755);
        zip.start_file("modelDescription.xml", deflate)?;
        zip.write_all(description.as_bytes())?;
        zip.start_file(
            format!("binaries/{}/{id}.so", version.platform()),
            binary_options,
        )?;
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
        fmi: version,
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

    /// The archive's entries and its description, for FMI `fmi`.
    fn export(fmi: &str) -> (Vec<String>, String) {
        let dir = tempfile::tempdir().unwrap();
        let library = dir.path().join("libhysteron_c.so");
        std::fs::write(&library, b"\x7fELF not really a library").unwrap();
        let spec = dir.path().join("play.json");
        std::fs::write(&spec, r#"{"type": "play", "r": 0.5}"#).unwrap();
        let opts = ExportFmuOptions {
            model: spec,
            output: dir.path().join("m.fmu"),
            name: Some("m".into()),
            binary: FmuBinary {
                library: Some(library),
            },
            fmi: fmi.into(),
        };
        let report = run(&opts).unwrap();
        assert_eq!(report.parameters, 2);
        let mut zip = zip::ZipArchive::new(std::fs::File::open(&opts.output).unwrap()).unwrap();
        let mut names: Vec<String> = zip.file_names().map(|n| n.unwrap().into_owned()).collect();
        names.sort();
        let mut xml = String::new();
        std::io::Read::read_to_string(&mut zip.by_name("modelDescription.xml").unwrap(), &mut xml)
            .unwrap();
        (names, xml)
    }

    #[test]
    fn fmi_3_archives_have_the_3_0_layout_and_2_stays_the_default() {
        if !(cfg!(target_os = "linux") && cfg!(target_arch = "x86_64")) {
            return;
        }
        let (names, xml) = export("3");
        assert_eq!(
            names,
            [
                "binaries/x86_64-linux/m.so",
                "modelDescription.xml",
                "resources/model.json"
            ]
        );
        assert!(xml.contains(r#"fmiVersion="3.0""#), "{xml}");
        assert!(xml.contains(r#"causality="independent""#), "{xml}");
        let (names, xml) = export("2");
        assert_eq!(
            names,
            [
                "binaries/linux64/m.so",
                "modelDescription.xml",
                "resources/model.json"
            ]
        );
        assert!(xml.contains(r#"fmiVersion="2.0""#), "{xml}");
        let defaults = <ExportFmuOptions as clap::Args>::augment_args(clap::Command::new("x"))
            .try_get_matches_from(["x", "--model", "a.json", "--output", "a.fmu"])
            .unwrap();
        assert_eq!(defaults.get_one::<String>("fmi").unwrap(), "2");
    }
}
