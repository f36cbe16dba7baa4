//! The `simulate` job: runs a model spec (JSON, see
//! [`Spec`]) over one column of a CSV file and writes
//! the input's columns plus the output (column `y`, or the name given by
//! `--output-column`), optionally with a loop figure of the output over the
//! input.
//!
//! The record is streamed: rows are read, run through the model and
//! written [`CHUNK`] at a time, so the job's memory does not grow with the
//! record (with `--plot` it keeps the plotted points, 16 bytes per row,
//! until the figure is drawn; a time column is read in a first pass that
//! keeps nothing). Output values are written by [`csvio::fmt_f64`]; the
//! input's fields are written back verbatim (re-quoted where needed).
//!
//! Nothing is written unless everything succeeded: the output goes to a
//! temporary file that replaces the destination only after the last row
//! was run and the figure drawn (a bad row or an operator error half-way
//! leaves no file behind); then the figure is written atomically. The
//! output may not be the input or the model file (compared after
//! canonicalization, also when the output does not exist yet).

use crate::csvio::{self, CsvIoError};
use crate::model_file::{self, ModelFileError};
use crate::models::Spec;
use crate::output::OutputError;
use crate::period::{self, Period, PeriodError, SamplePeriodArgs};
use crate::plot::{self, file_name};
use crate::Operator;
use std::fmt;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// The default name of the output column.
pub const OUTPUT_COLUMN: &str = "y";

/// Run a model spec (JSON) over one column of a CSV file (with a
/// header); the output holds all input columns plus `y`.
#[derive(Debug, Clone, PartialEq, clap::Args)]
pub struct SimulateOptions {
    /// The model, the input file and its column.
    #[command(flatten)]
    pub record: RecordInput,
    /// The output CSV file (written atomically; may not be the input).
    #[arg(long, value_name = "OUT.csv")]
    pub output: PathBuf,
    /// Also draw the output over the input column as an SVG figure.
    #[arg(long, value_name = "LOOP.svg")]
    pub plot: Option<PathBuf>,
    /// The name of the output column written (an error if the input
    /// already has a column of that name).
    #[arg(long, value_name = "NAME", default_value = OUTPUT_COLUMN)]
    pub output_column: String,
    /// Where the sample period of the rate-dependent nodes of the model
    /// comes from (see [`period`]).
    #[command(flatten)]
    pub period: SamplePeriodArgs,
}

/// The model and the record it runs over, as `simulate` and
/// `sensitivity` take them: their first command-line flags.
#[derive(Debug, Clone, PartialEq, clap::Args)]
pub struct RecordInput {
    /// The model spec (JSON, see hysteron::models::Spec); the model
    /// runs from its initial state.
    #[arg(long, value_name = "SPEC.json")]
    pub model: PathBuf,
    /// The input CSV file, with a header row of distinct column names
    /// (blank lines only at the end of the file; every value of the
    /// input column a finite number).
    #[arg(long, value_name = "IN.csv")]
    pub input: PathBuf,
    /// The input column.
    #[arg(long, value_name = "NAME", default_value = "x")]
    pub column: String,
}

/// An error of the simulate job (one-line message naming file, row and
/// column where relevant); `sensitivity` fails in these ways too.
#[derive(Debug, thiserror::Error)]
pub enum SimulateError {
    /// An output path names an input file.
    #[error(transparent)]
    SameFile(#[from] csvio::SameFile),
    /// The model spec could not be read, parsed or built.
    #[error(transparent)]
    Model(#[from] ModelFileError),
    /// The input could not be read or is invalid (no data rows, a cell
    /// that is not a finite number, ...).
    #[error("input {0}")]
    Input(CsvIoError),
    /// No sample period could be chosen (the spec's and the data's
    /// disagree).
    #[error(transparent)]
    Period(PeriodError),
    /// The input already has a column named like an output column.
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
    /// Writing an output or drawing a figure failed.
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// What the simulate job did.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulateReport {
    /// Samples simulated (data rows).
    pub samples: usize,
    /// The model's operator name.
    pub model: &'static str,
    /// The sample period the model ran at (`None` for a rate-independent
    /// model).
    pub period: Option<Period>,
    /// Files written.
    pub files: Vec<PathBuf>,
}

impl fmt::Display for SimulateReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "simulated {} samples with a `{}` model",
            self.samples, self.model
        )?;
        write_period_and_files(f, self.period.as_ref(), &self.files)
    }
}

/// How the reports of `simulate` and `sensitivity` end: ` at a sample
/// period of P` (for a rate-dependent model), then `; wrote FILES`.
pub(crate) fn write_period_and_files(
    f: &mut fmt::Formatter<'_>,
    period: Option<&Period>,
    files: &[PathBuf],
) -> fmt::Result {
    if let Some(p) = period {
        write!(f, " at a sample period of {p}")?;
    }
    write!(f, "; wrote {}", csvio::join_paths(files))
}

/// Rows read, run and written at a time.
pub const CHUNK: usize = 8192;

impl SimulateError {
    /// A period error: one reading the data is an input error.
    fn period(e: PeriodError) -> Self {
        match e {
            PeriodError::Data(e) => SimulateError::Input(e),
            e => SimulateError::Period(e),
        }
    }
}

impl RecordInput {
    /// Refuses an output, and a figure if any, that names the input or
    /// the model file, and a figure that names the output.
    pub(crate) fn refuse_overwrite(
        &self,
        output: &Path,
        plot: Option<&Path>,
    ) -> Result<(), SimulateError> {
        let inputs = [
            ("input", self.input.as_path()),
            ("model", self.model.as_path()),
        ];
        csvio::refuse_overwrites(&inputs, &[("output", Some(output)), ("plot", plot)])?;
        Ok(())
    }

    /// Reads the model spec and builds it at the sample period of the
    /// input that `period` chooses; the spec's own errors come first (a
    /// period it leaves out is a stand-in for that check).
    pub(crate) fn load_model(
        &self,
        period: &SamplePeriodArgs,
    ) -> Result<RecordModel, SimulateError> {
        let (spec, _) = model_file::read_checked(&self.model)?;
        let (spec, period) = period::for_record(&spec, &period.source(), &self.input)
            .map_err(SimulateError::period)?;
        let model = model_file::build(&self.model, &spec)?;
        Ok(RecordModel {
            spec,
            period,
            model,
        })
    }

    /// Opens the input and finds its column, refusing an input that
    /// already has a column named like one of `new_columns`.
    pub(crate) fn open(&self, new_columns: &[String]) -> Result<InputColumn, SimulateError> {
        let reader = csvio::CsvReader::open(&self.input).map_err(SimulateError::Input)?;
        let index = reader.column(&self.column).map_err(SimulateError::Input)?;
        let name = reader.headers()[index].trim().to_string();
        let taken = new_columns
            .iter()
            .find(|c| reader.headers().iter().any(|h| h.trim() == c.as_str()));
        if let Some(taken) = taken {
            return Err(SimulateError::OutputColumnExists(
                self.input.clone(),
                taken.clone(),
            ));
        }
        Ok(InputColumn {
            reader,
            index,
            name,
        })
    }

    /// The model's failure at a sample, located in the input column:
    /// `run` holds the data rows and input values run and the number of
    /// the first of them.
    pub(crate) fn operator_failure(
        &self,
        e: crate::Error,
        (rows, xs, first): (&[csvio::Row], &[f64], usize),
    ) -> SimulateError {
        let at = |i: usize| {
            let (row, line) = rows
                .get(i)
                .map_or((first + i + 1, 0), |r| (r.row(), r.line()));
            (first + i, row, line, xs.get(i).copied())
        };
        let failure =
            csvio::SampleFailure::locate_in(&self.model, &self.input, "input", &self.column, e, at);
        SimulateError::Operator(Box::new(failure))
    }
}

/// A model spec file made ready to run over one record
/// ([`RecordInput::load_model`]).
pub(crate) struct RecordModel {
    /// The spec at the record's sample period.
    pub spec: Spec,
    /// That period (`None` for a rate-independent model).
    pub period: Option<Period>,
    /// The model built from `spec`, in its initial state.
    pub model: Box<dyn Operator<f64>>,
}

/// The input column of a record being extended by new columns
/// ([`RecordInput::open`]).
pub(crate) struct InputColumn {
    /// The record's reader, at its first data row.
    pub reader: csvio::CsvReader,
    /// The column's index.
    pub index: usize,
    /// Its header, trimmed.
    pub name: String,
}

/// Writes the CSV file `path` atomically: `write` writes its records to
/// the CSV writer (see [`write_error`]); errors of the file system, of the
/// final flush and of `write` leave no file behind.
pub(crate) fn write_csv(
    path: &Path,
    write: impl FnOnce(&mut csv::Writer<&mut BufWriter<&mut File>>) -> Result<(), SimulateError>,
) -> Result<(), SimulateError> {
    csvio::write_csv_atomic_with(path, |e| OutputError::Write(e).into(), write)
}

/// A CSV writer's error while writing `path`, as the job's error.
pub(crate) fn write_error(path: &Path, e: csv::Error) -> SimulateError {
    OutputError::Write(csvio::csv_write_error(path, e)).into()
}

/// Runs the model over the input; see the module docs.
pub fn run(opts: &SimulateOptions) -> Result<SimulateReport, SimulateError> {
    let record = &opts.record;
    record.refuse_overwrite(&opts.output, opts.plot.as_deref())?;
    let RecordModel {
        period, mut model, ..
    } = record.load_model(&opts.period)?;
    let out_name = opts.output_column.trim();
    let InputColumn {
        mut reader,
        index,
        name,
    } = record.open(&[out_name.to_string()])?;

    // Both destinations must be writable before either is written.
    csvio::target_dir(&opts.output).map_err(OutputError::Write)?;
    if let Some(p) = &opts.plot {
        csvio::target_dir(p).map_err(OutputError::Write)?;
    }

    let mut points = opts.plot.as_ref().map(|_| plot::PointStore::default());
    let mut samples = 0;
    let mut svg = None;
    let write_err = |e| write_error(&opts.output, e);
    write_csv(&opts.output, |out| {
        out.write_record(reader.headers().iter().chain([out_name]))
            .map_err(write_err)?;
        let mut rows = vec![csvio::Row::default(); CHUNK];
        let (mut xs, mut ys) = (vec![0.0; CHUNK], vec![0.0; CHUNK]);
        let mut y_text = String::new();
        loop {
            let mut n = 0;
            while n < CHUNK
                && reader
                    .read_row(&mut rows[n])
                    .map_err(SimulateError::Input)?
            {
                xs[n] = reader
                    .number(&rows[n], index, &name)
                    .map_err(SimulateError::Input)?;
                n += 1;
            }
            if n == 0 {
                break;
            }
            model.process(&xs[..n], &mut ys[..n]).map_err(|e| {
                let run = (&rows[..n], &xs[..n], samples);
                record.operator_failure(e, run)
            })?;
            for (row, &y) in rows[..n].iter().zip(&ys[..n]) {
                y_text.clear();
                csvio::push_f64(&mut y_text, y);
                out.write_record(row.fields().chain([y_text.as_str()]))
                    .map_err(write_err)?;
            }
            if let Some(points) = &mut points {
                points.extend(xs[..n].iter().copied().zip(ys[..n].iter().copied()));
            }
            samples += n;
            if n < CHUNK {
                break;
            }
        }
        if samples == 0 {
            return Err(SimulateError::Input(CsvIoError::NoRows {
                path: record.input.clone(),
            }));
        }
        // The figure is drawn before the output is in place, so that a
        // figure that cannot be drawn leaves no output either.
        if let (Some(p), Some(points)) = (&opts.plot, points.take()) {
            let title = format!(
                "{} over {}",
                file_name(&record.model),
                file_name(&record.input)
            );
            let panel = plot::loop_panel_from_store(&title, &record.column, out_name, &points);
            drop(points);
            svg = Some(
                plot::render(&[panel], 1, 1, (760, 560))
                    .map_err(|e| OutputError::Plot(p.clone(), e))?,
            );
        }
        Ok(())
    })?;
    let mut files = vec![opts.output.clone()];
    if let (Some(p), Some(svg)) = (&opts.plot, svg) {
        csvio::write_string_atomic(p, &svg).map_err(OutputError::Write)?;
        files.push(p.clone());
    }
    Ok(SimulateReport {
        samples,
        model: model.name(),
        period,
        files,
    })
}
