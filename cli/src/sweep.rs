//! The `sweep` job: runs a model spec (JSON, see
//! [`Spec`](crate::models::Spec)) once per parameter set of a CSV file over
//! one input column, as an [`Ensemble`] (play and MMS leaves, PI banks of
//! fewer than 64 plays not a multiple of eight, the Bouc-Wen spring where
//! every set has `n = 1`, and the Bouc-Wen benchmark system, eight
//! instances per vector instruction, any other model one instance at a
//! time, in parallel).
//!
//! * The parameter sets (`--params`): a CSV file whose header names
//!   parameters as the built model's
//!   [`param_names`](hysteron::Parameters::param_names) (`left.mms.f_c`) or
//!   by a unique suffix after a dot (`f_c`), as `fit --free` takes them
//!   (see [`free_by_names`]), and whose data rows are the sets (finite
//!   numbers); parameters it does not name keep the spec's values.
//! * The output holds the input column, then one column per set,
//!   `set_<row>` with the set's data row in the parameter file (`set_1`
//!   for the first). A file whose name ends in `.parquet` is written as
//!   Parquet ([`parquet_file`]: one `DOUBLE` column per name, the bits
//!   unchanged), any other as CSV (values written by [`csvio::fmt_f64`],
//!   which reads back to the same bits). A set that
//!   fails (a value out of its parameter's domain, or a run the model
//!   refuses at a sample) has `NaN` in its column, and the report names it
//!   with its error; the other sets run.
//! * Every set runs from the model's initial state, and gives the bits the
//!   model gives alone with those parameters (`simulate` on a spec holding
//!   them).
//!
//! The output is written atomically, and may not be the input, the
//! parameter file or the model file.

use crate::csvio::{self, CsvIoError};
use crate::identify::ensemble::{Ensemble, EnsembleError, InstanceFailure, Kernel};
use crate::identify::{free_by_names, FitError};
use crate::output::OutputError;
use crate::parquet_file;
use crate::period::{Period, SamplePeriodArgs};
use crate::simulate::{write_period_and_files, RecordInput, SimulateError};
use nalgebra::DMatrix;
use std::fmt;
use std::path::PathBuf;

/// Run a model spec (JSON) once per parameter set (rows of a CSV file
/// whose header names parameters) over one column of a CSV file, all
/// sets together (play and MMS leaves, PI banks of fewer than 64 plays not
/// a multiple of eight, Bouc-Wen springs with n = 1 and the Bouc-Wen
/// benchmark system eight per vector instruction);
/// writes the input column and one output column per set, set_1,
/// set_2, … (NaN for a set that failed, which the report names with
/// its error).
#[derive(Debug, Clone, PartialEq, clap::Args)]
pub struct SweepOptions {
    /// The model, and the input column it runs over.
    #[command(flatten)]
    pub record: RecordInput,
    /// The parameter sets: a CSV file whose header names parameters (full
    /// names, left.mms.f_c, or unique suffixes, f_c) and whose rows are
    /// the sets; the others keep the spec's values.
    #[arg(long, value_name = "SETS.csv")]
    pub params: PathBuf,
    /// The output file: the input column, then one column per set, set_1,
    /// set_2, … (NaN for a set that failed); Parquet if its name ends in
    /// .parquet, CSV otherwise.
    #[arg(long, value_name = "OUT.csv|OUT.parquet")]
    pub output: PathBuf,
    /// The sample period of a rate-dependent model.
    #[command(flatten)]
    pub period: SamplePeriodArgs,
}

/// An error of the sweep job (one line naming file, row and column where
/// relevant). One set's failure is not an error: see
/// [`SweepReport::failures`].
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// The model, the input or the output (as `simulate` reads and writes
    /// them).
    #[error(transparent)]
    Record(#[from] SimulateError),
    /// The parameter file could not be read or is invalid.
    #[error("params {0}")]
    Params(CsvIoError),
    /// A parameter named twice in the header (as two spellings of one
    /// path).
    #[error("params `{}`: parameter `{name}` is named by two columns", path.display())]
    NamedTwice {
        /// The parameter file.
        path: PathBuf,
        /// The parameter's full path.
        name: String,
    },
    /// A parameter name of the header is unknown or ambiguous.
    #[error("params `{}`: {error}", path.display())]
    ParamName {
        /// The parameter file.
        path: PathBuf,
        /// What the name matched.
        error: FitError,
    },
    /// The ensemble refused the model or the input.
    #[error("{0}")]
    Ensemble(EnsembleError),
}

/// What the sweep job did.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepReport {
    /// Parameter sets run.
    pub sets: usize,
    /// Samples per set.
    pub samples: usize,
    /// How the sets were stepped.
    pub kernel: Kernel,
    /// The sample period (`None` for a rate-independent model).
    pub period: Option<Period>,
    /// The sets that failed, by index (row − 1 of the parameter file).
    pub failures: Vec<InstanceFailure>,
    /// Files written.
    pub files: Vec<PathBuf>,
}

impl fmt::Display for SweepReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let kernel = match self.kernel {
            Kernel::Lanes(leaf) => format!("the {leaf} lane kernel"),
            Kernel::Instances => "one instance at a time".to_string(),
        };
        write!(
            f,
            "ran {} parameter sets ({} failed) over {} samples, {kernel}",
            self.sets,
            self.failures.len(),
            self.samples
        )?;
        write_period_and_files(f, self.period.as_ref(), &self.files)?;
        for failure in &self.failures {
            write!(
                f,
                "\nset_{} (params row {}) failed: {}",
                failure.instance + 1,
                failure.instance + 1,
                failure.error
            )?;
        }
        Ok(())
    }
}

/// Runs the sweep; see the module docs.
pub fn run(opts: &SweepOptions) -> Result<SweepReport, SweepError> {
    let record = &opts.record;
    record.refuse_overwrite(&opts.output, None)?;
    csvio::refuse_same("output", &opts.output, &[("params", opts.params.as_path())])
        .map_err(SimulateError::from)?;
    let loaded = record.load_model(&opts.period)?;
    let params = parameter_sets(opts, &*loaded.model)?;
    let ensemble = Ensemble::new(&loaded.spec, &params).map_err(SweepError::Ensemble)?;
    let columns = csvio::read_columns(&record.input, &[&record.column])
        .map_err(|e| SweepError::Record(SimulateError::Input(e)))?;
    let x = columns.values.first().map_or(&[][..], |c| &c[..]);
    let run = ensemble.run(x).map_err(SweepError::Ensemble)?;
    let input_name = columns.headers[columns.indices[0]].trim().to_string();
    let names: Vec<String> = (1..=ensemble.len()).map(|r| format!("set_{r}")).collect();
    let mut out: Vec<(&str, &[f64])> = vec![(input_name.as_str(), x)];
    out.extend(
        names
            .iter()
            .map(String::as_str)
            .zip(run.outputs.chunks(x.len())),
    );
    let written = if parquet_file::is_parquet(&opts.output) {
        parquet_file::write_columns(&opts.output, &out)
    } else {
        csvio::write_columns(&opts.output, &out)
    };
    written.map_err(|e| SimulateError::Output(OutputError::Write(e)))?;
    Ok(SweepReport {
        sets: ensemble.len(),
        samples: x.len(),
        kernel: ensemble.kernel(),
        period: loaded.period,
        failures: run.failures,
        files: vec![opts.output.clone()],
    })
}

/// The parameter matrix: one row per data row of the parameter file, the
/// model's own values where the file names no column.
fn parameter_sets(
    opts: &SweepOptions,
    model: &(dyn crate::Operator<f64> + 'static),
) -> Result<DMatrix<f64>, SweepError> {
    let headers = csvio::CsvReader::open(&opts.params)
        .map_err(SweepError::Params)?
        .headers()
        .iter()
        .map(|h| h.trim().to_string())
        .collect::<Vec<_>>();
    let names: Vec<&str> = headers.iter().map(String::as_str).collect();
    let indices = free_by_names(model, &names).map_err(|error| SweepError::ParamName {
        path: opts.params.clone(),
        error,
    })?;
    let all = model.param_names();
    for (k, j) in indices.iter().enumerate() {
        if indices[..k].contains(j) {
            return Err(SweepError::NamedTwice {
                path: opts.params.clone(),
                name: all.get(*j).cloned().unwrap_or_default(),
            });
        }
    }
    let columns = csvio::read_columns(&opts.params, &names).map_err(SweepError::Params)?;
    let own = model.params();
    let rows = columns.lines.len();
    let mut params = DMatrix::from_fn(rows, own.len(), |_, j| own.get(j).copied().unwrap_or(0.0));
    for (&j, values) in indices.iter().zip(&columns.values) {
        for (i, &v) in values.iter().enumerate() {
            params[(i, j)] = v;
        }
    }
    Ok(params)
}
