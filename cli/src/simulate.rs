//! The `simulate` job: runs a model spec (JSON, see
//! [`Spec`]) over one column of a CSV file and writes
//! the input's columns plus the output (column `y`, or the name given by
//! `--output-column`), optionally with a loop figure of the output over the
//! input.
//!
//! Nothing is written unless everything before succeeded: the model is
//! loaded and built, the input read and checked, the whole run simulated
//! and the figure drawn in memory first; then the output (and figure) are
//! written atomically. The output may not be the input or the model file
//! (compared after canonicalization, also when the output does not exist
//! yet).

use crate::csvio::{self, CsvIoError};
use crate::model_file::ModelFileError;
use crate::models::Spec;
use crate::plot::{self, PlotError};
use crate::Operator;
use std::fmt;
use std::path::{Path, PathBuf};

/// The default name of the output column.
pub const OUTPUT_COLUMN: &str = "y";

/// Options of the simulate job.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulateOptions {
    /// The model spec (JSON).
    pub model: PathBuf,
    /// The input CSV file (with a header row).
    pub input: PathBuf,
    /// The input column.
    pub column: String,
    /// The output CSV file.
    pub output: PathBuf,
    /// Optional SVG figure of the output over the input column.
    pub plot: Option<PathBuf>,
    /// The name of the output column ([`OUTPUT_COLUMN`] by default); it may
    /// not be a column of the input already.
    pub output_column: String,
    /// Where the sample period of the rate-dependent nodes of the model
    /// comes from (default: the spec's own `dt`).
    pub dt: crate::period::DtSource,
}

/// An error of the simulate job (one-line message naming file, row and
/// column where relevant).
#[derive(Debug, thiserror::Error)]
pub enum SimulateError {
    /// An output path names an input file.
    #[error(transparent)]
    SameFile(#[from] csvio::SameFile),
    /// The model spec could not be read, parsed or built.
    #[error(transparent)]
    Model(#[from] ModelFileError),
    /// The input could not be read or is invalid.
    #[error("input {0}")]
    Input(CsvIoError),
    /// The input already has a column named like the output column.
    #[error(
        "input `{}` already has a column `{}`: name the output column otherwise \
         with --output-column",
        .0.display(),
        .1
    )]
    OutputColumnExists(PathBuf, String),
    /// The operator failed at a sample.
    #[error("model `{}` failed{}", .0.model.display(), .0.location())]
    Operator(Box<csvio::SampleFailure>),
    /// Writing the output failed.
    #[error("output {0}")]
    Write(CsvIoError),
    /// Drawing the figure failed.
    #[error("plot `{}`: {}", .0.display(), .1)]
    Plot(PathBuf, PlotError),
}

/// What the simulate job did.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulateReport {
    /// Samples simulated (data rows).
    pub samples: usize,
    /// The model's operator name.
    pub model: &'static str,
    /// Files written.
    pub files: Vec<PathBuf>,
}

impl fmt::Display for SimulateReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "simulated {} samples with a `{}` model; wrote {}",
            self.samples,
            self.model,
            crate::csvio::join_paths(&self.files)
        )
    }
}

/// Runs the model over the input; see the module docs.
pub fn run(opts: &SimulateOptions) -> Result<SimulateReport, SimulateError> {
    let inputs = [
        ("input", opts.input.as_path()),
        ("model", opts.model.as_path()),
    ];
    csvio::refuse_same("output", &opts.output, &inputs).map_err(SimulateError::SameFile)?;
    if let Some(p) = &opts.plot {
        csvio::refuse_same("plot", p, &inputs).map_err(SimulateError::SameFile)?;
        csvio::refuse_same("plot", p, &[("output", opts.output.as_path())])
            .map_err(SimulateError::SameFile)?;
    }

    let model_err = |e| ModelFileError::new(&opts.model, e);
    let spec = Spec::from_json_file(&opts.model).map_err(model_err)?;
    let spec = opts
        .dt
        .apply(spec, &opts.input)
        .map_err(SimulateError::Input)?;
    let mut model = spec.build().map_err(model_err)?;

    let table = csvio::read_column(&opts.input, &opts.column).map_err(SimulateError::Input)?;
    let out_name = opts.output_column.trim();
    if table.headers.iter().any(|h| h.trim() == out_name) {
        return Err(SimulateError::OutputColumnExists(
            opts.input.clone(),
            out_name.to_string(),
        ));
    }

    let y = model.run(&table.values).map_err(|e| {
        SimulateError::Operator(Box::new(csvio::SampleFailure::locate(
            &opts.model,
            &opts.input,
            "input",
            &opts.column,
            &table.values,
            &table.lines,
            e,
        )))
    })?;

    let svg = match &opts.plot {
        Some(p) => {
            let title = format!("{} over {}", file_name(&opts.model), file_name(&opts.input));
            let panel = plot::loop_panel(&title, &opts.column, out_name, &table.values, &y);
            Some(
                plot::render(&[panel], 1, 1, (760, 560))
                    .map_err(|e| SimulateError::Plot(p.clone(), e))?,
            )
        }
        None => None,
    };

    // Both destinations must be writable before either is written.
    csvio::target_dir(&opts.output).map_err(SimulateError::Write)?;
    if let Some(p) = &opts.plot {
        csvio::target_dir(p).map_err(SimulateError::Write)?;
    }
    csvio::write_with_column(&opts.output, &table, out_name, &y).map_err(SimulateError::Write)?;
    let mut files = vec![opts.output.clone()];
    if let (Some(p), Some(svg)) = (&opts.plot, svg) {
        csvio::write_string_atomic(p, &svg).map_err(SimulateError::Write)?;
        files.push(p.clone());
    }
    Ok(SimulateReport {
        samples: y.len(),
        model: model.name(),
        files,
    })
}

fn file_name(p: &Path) -> String {
    p.file_name()
        .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into())
}
