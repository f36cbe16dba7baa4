//! The `sensitivity` job: runs a model spec (JSON, see
//! [`Spec`](crate::models::Spec)) over one column of a CSV file, like
//! `simulate`, and writes with the output the
//! derivatives of the output with respect to chosen parameters,
//! `∂y_k/∂p_i`, computed by forward-mode automatic differentiation
//! ([`sensitivity`]).
//!
//! * The parameters (`--params`) are named as the built model's
//!   [`param_names`](hysteron::Parameters::param_names) (`left.mms.f_c`) or by a
//!   unique suffix after a dot (`f_c`), as `fit --free` takes them (see
//!   [`free_by_names`]); each is given at most once.
//! * The output holds the input's columns (verbatim), the output column
//!   (`y`, or the name given by `--output-column`), then one column per
//!   parameter, `dy/d<path>` with the parameter's full path
//!   (`dy/dleft.mms.f_c`), in the order given. Values are written by
//!   [`csvio::fmt_f64`].
//! * The model runs from its initial state; at a kink of a hysteresis
//!   branch the derivative is that of the branch the model takes.
//!
//! Unlike `simulate`, the record is held in memory (the derivatives run in
//! passes of [`DUAL_WIDTH`](crate::operators::DUAL_WIDTH) parameters over
//! the whole input). Nothing is written unless everything succeeded: the
//! output is written atomically, and may not be the input or the model file
//! (compared after canonicalization).

use crate::csvio::{self, CsvIoError};
use crate::identify::free_by_names;
use crate::model_file::ModelFileError;
use crate::models::sensitivity::{sensitivity, Sensitivity, SensitivityError};
use crate::output::OutputError;
use crate::period::SamplePeriodArgs;
use crate::simulate::{
    write_csv, write_error, write_period_and_files, InputColumn, RecordInput, RecordModel,
    SimulateError, SimulateReport,
};
use crate::Operator;
use std::fmt;
use std::path::PathBuf;

/// The default name of the output column (as for `simulate`).
pub const OUTPUT_COLUMN: &str = crate::simulate::OUTPUT_COLUMN;

/// Run a model spec (JSON) over one column of a CSV file (with a
/// header) and compute the derivatives of its output with respect to
/// chosen parameters, ∂y_k/∂p, by forward-mode automatic
/// differentiation (dual numbers, no step size to choose; at a
/// kink, the derivative of the branch the model takes). The output
/// holds all input columns, `y`, then one column `dy/d<path>` per
/// parameter (e.g. dy/dleft.mms.f_c), in the order given.
#[derive(Debug, Clone, PartialEq, clap::Args)]
pub struct SensitivityOptions {
    /// The model, the input file and its column.
    #[command(flatten)]
    pub record: RecordInput,
    /// The parameters, comma-separated: full names as the model lists
    /// them (left.mms.f_c) or unique suffixes (f_c), each at most once;
    /// the columns are named by the full names.
    #[arg(long, value_name = "NAMES", value_delimiter = ',', required = true)]
    pub params: Vec<String>,
    /// The output CSV file (written atomically; may not be the input).
    #[arg(long, value_name = "OUT.csv")]
    pub output: PathBuf,
    /// The name of the output column written (the derivative columns
    /// are then `d<NAME>/d<path>`; an error if the input already has a
    /// column of one of these names).
    #[arg(long, value_name = "NAME", default_value = OUTPUT_COLUMN)]
    pub output_column: String,
    /// Where the sample period of the rate-dependent nodes of the model
    /// comes from (default: the spec's own `dt`).
    #[command(flatten)]
    pub period: SamplePeriodArgs,
}

/// An error of the sensitivity job (one-line message naming file, row and
/// column where relevant).
#[derive(Debug, thiserror::Error)]
pub enum SensitivityCmdError {
    /// What `simulate` can fail on too: an output path naming an input
    /// file, the model spec, the input, the sample period, an output
    /// column the input already has, the model at a sample, writing the
    /// output.
    #[error(transparent)]
    Run(#[from] SimulateError),
    /// A `--params` name is unknown, ambiguous or repeated, or none is
    /// given; the message lists the model's parameters where it helps.
    #[error("--params: model `{}`: {}", .0.display(), .1)]
    Params(PathBuf, String),
    /// A derivative is not finite (an infinite slope).
    #[error(
        "model `{}`: {} at sample {}: input `{}`, row {} (line {}), column `{}` = {}",
        .0.model.display(),
        .0.message,
        .0.sample,
        .0.file.display(),
        .0.row,
        .0.line,
        .0.column,
        csvio::fmt_f64(.0.value)
    )]
    NonFiniteDerivative(Box<NonFinite>),
}

/// Where a derivative is not finite.
#[derive(Debug, Clone, PartialEq)]
pub struct NonFinite {
    /// The model spec.
    pub model: PathBuf,
    /// What is not finite (`∂y/∂p is not finite`).
    pub message: String,
    /// The sample (0-based).
    pub sample: usize,
    /// The input file.
    pub file: PathBuf,
    /// Its data row (1-based).
    pub row: usize,
    /// The line in the file.
    pub line: u64,
    /// The input column.
    pub column: String,
    /// The input value at the sample.
    pub value: f64,
}

/// What the sensitivity job did.
#[derive(Debug, Clone, PartialEq)]
pub struct SensitivityReport {
    /// The run, as `simulate` reports one: samples (data rows), the
    /// model's operator name, its sample period, the files written.
    pub run: SimulateReport,
    /// The parameters' full paths, in the order of the columns.
    pub params: Vec<String>,
}

impl fmt::Display for SensitivityReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "computed the sensitivities to {} parameter(s) ({}) over {} samples with a `{}` \
             model",
            self.params.len(),
            self.params.join(", "),
            self.run.samples,
            self.run.model,
        )?;
        write_period_and_files(f, self.run.period.as_ref(), &self.run.files)
    }
}

/// The name of the derivative column of `output` with respect to `param`:
/// `d<output>/d<param>` (`dy/dleft.mms.f_c`).
pub fn derivative_column(output: &str, param: &str) -> String {
    format!("d{output}/d{param}")
}

/// Runs the job; see the module docs.
pub fn run(opts: &SensitivityOptions) -> Result<SensitivityReport, SensitivityCmdError> {
    let record = &opts.record;
    record.refuse_overwrite(&opts.output, None)?;
    let RecordModel {
        spec,
        period,
        model,
    } = record.load_model(&opts.period)?;
    let params = full_names(opts, model.as_ref())?;

    let out_name = opts.output_column.trim();
    let mut new_columns = vec![out_name.to_string()];
    new_columns.extend(params.iter().map(|p| derivative_column(out_name, p)));
    let InputColumn {
        mut reader,
        index,
        name,
    } = record.open(&new_columns)?;

    let mut rows = Vec::new();
    let mut xs = Vec::new();
    let mut row = csvio::Row::default();
    while reader.read_row(&mut row).map_err(SimulateError::Input)? {
        xs.push(
            reader
                .number(&row, index, &name)
                .map_err(SimulateError::Input)?,
        );
        rows.push(std::mem::take(&mut row));
    }
    if xs.is_empty() {
        return Err(SimulateError::Input(CsvIoError::NoRows {
            path: opts.record.input.clone(),
        })
        .into());
    }
    csvio::target_dir(&opts.output).map_err(|e| SimulateError::from(OutputError::Write(e)))?;

    let refs: Vec<&str> = params.iter().map(String::as_str).collect();
    let result = sensitivity(&spec, &xs, &refs).map_err(|e| locate(opts, &rows, &xs, e))?;

    write(opts, &reader, &rows, &new_columns, &result)?;
    Ok(SensitivityReport {
        run: SimulateReport {
            samples: xs.len(),
            model: model.name(),
            period,
            files: vec![opts.output.clone()],
        },
        params,
    })
}

/// The `--params` names (trimmed, empty ones dropped) as the model's full
/// parameter paths.
fn full_names(
    opts: &SensitivityOptions,
    model: &(dyn Operator<f64> + 'static),
) -> Result<Vec<String>, SensitivityCmdError> {
    let params_err =
        |message: String| SensitivityCmdError::Params(opts.record.model.clone(), message);
    let names: Vec<&str> = opts
        .params
        .iter()
        .map(|s| s.trim())
        .filter(|s| !s.is_empty())
        .collect();
    let all = model.param_names();
    if names.is_empty() {
        return Err(params_err(format!(
            "no parameter given (the model has: {})",
            all.join(", ")
        )));
    }
    let indices = free_by_names(model, &names).map_err(|e| params_err(e.to_string()))?;
    let mut full = Vec::with_capacity(indices.len());
    for (&i, &asked) in indices.iter().zip(&names) {
        let path = all.get(i).cloned().unwrap_or_else(|| asked.to_string());
        if full.contains(&path) {
            let also = if path == asked {
                String::new()
            } else {
                format!(" (as `{asked}`)")
            };
            return Err(params_err(format!(
                "parameter `{path}` is given twice{also}"
            )));
        }
        full.push(path);
    }
    Ok(full)
}

/// The library's error as the job's, located in the input file.
fn locate(
    opts: &SensitivityOptions,
    rows: &[csvio::Row],
    xs: &[f64],
    e: SensitivityError,
) -> SensitivityCmdError {
    let params_err =
        |message: String| SensitivityCmdError::Params(opts.record.model.clone(), message);
    match e {
        SensitivityError::Spec(e) => {
            SimulateError::from(ModelFileError::new(&opts.record.model, e)).into()
        }
        SensitivityError::EmptyInput => SimulateError::Input(CsvIoError::NoRows {
            path: opts.record.input.clone(),
        })
        .into(),
        e @ (SensitivityError::NoParameters { .. }
        | SensitivityError::UnknownParameter { .. }
        | SensitivityError::Repeated { .. }) => params_err(e.to_string()),
        SensitivityError::Model(e) => opts.record.operator_failure(e, (rows, xs, 0)).into(),
        SensitivityError::NonFiniteDerivative { sample, param } => {
            let (row, line) = rows
                .get(sample)
                .map_or((sample + 1, 0), |r| (r.row(), r.line()));
            SensitivityCmdError::NonFiniteDerivative(Box::new(NonFinite {
                model: opts.record.model.clone(),
                message: format!("∂y/∂{param} is not finite"),
                sample,
                file: opts.record.input.clone(),
                row,
                line,
                column: opts.record.column.clone(),
                value: xs.get(sample).copied().unwrap_or(f64::NAN),
            }))
        }
    }
}

/// Writes the input's rows with the output and derivative columns,
/// atomically.
fn write(
    opts: &SensitivityOptions,
    reader: &csvio::CsvReader,
    rows: &[csvio::Row],
    new_columns: &[String],
    result: &Sensitivity,
) -> Result<(), SimulateError> {
    let write_err = |e| write_error(&opts.output, e);
    write_csv(&opts.output, |out| {
        out.write_record(
            reader
                .headers()
                .iter()
                .chain(new_columns.iter().map(String::as_str)),
        )
        .map_err(write_err)?;
        let mut cells = vec![String::new(); new_columns.len()];
        for (k, row) in rows.iter().enumerate() {
            let values = std::iter::once(&result.output)
                .chain(&result.columns)
                .map(|c| c.get(k).copied().unwrap_or(f64::NAN));
            for (cell, v) in cells.iter_mut().zip(values) {
                cell.clear();
                csvio::push_f64(cell, v);
            }
            out.write_record(row.fields().chain(cells.iter().map(String::as_str)))
                .map_err(write_err)?;
        }
        Ok(())
    })
}
