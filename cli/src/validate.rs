//! The `validate` job: runs a model spec (JSON, see [`Spec`]) over the
//! input column of one or more records (CSV files with a header) and
//! scores its output against each record's measured output column: one
//! table row per record and a mean row, optionally written as CSV, and
//! optionally a figure per record.
//!
//! * Each record is simulated by a fresh model, from the spec's initial
//!   state; a time column or `--dt` also sets the sample period of the
//!   spec's rate-dependent nodes (as for `simulate` and `fit`).
//! * The figures are those of [`hysteron_identify::metrics`](crate::identify::metrics):
//!   RMS and largest absolute error, and NRMSE = RMS(F_model − F_meas) /
//!   RMS(F_meas) with the RMS about zero (not the standard deviation).
//! * `--lowpass HZ` adds the NRMSE of both signals after a 4th-order
//!   Butterworth low-pass at HZ run forward and backward (zero phase,
//!   [`Lowpass`]); the whole record is filtered, then scored like the raw
//!   signals.
//! * `--skip SECONDS`: the samples at `i·dt < SECONDS` are simulated (a
//!   warm-up) but not scored.
//!
//! * `--covariance FILE` (written by `fit --covariance`, with the fitted
//!   spec as `--model`) draws the model's uncertainty band over each
//!   record's input in its figure ([`band::predict_band`](crate::identify::band::predict_band));
//!   it needs `--plot`, and the file's values must be the spec's.
//!
//! Nothing is written unless every record was read, run and scored and
//! every figure drawn; then the files are written atomically. No output
//! may be a record or the model file (compared after canonicalization),
//! and two records with the same file stem cannot both have a figure.

use crate::args;
use crate::band::{self as band_file, BandArgs, CovarianceFileError};
use crate::csvio::{self, CsvIoError};
use crate::identify::band::{Band, BandError, Covariance};
use crate::identify::metrics::{self, ErrorFigures, Lowpass, MetricsError};
use crate::model_file::{self, ModelFileError};
use crate::models::Spec;
use crate::output::OutputError;
use crate::period::{self, DtSource, Period, PeriodError};
use crate::plot::{self, file_name, pairs, Panel, PlotError, Series, Style};
use crate::Operator;
use std::fmt;
use std::path::{Path, PathBuf};

/// Score a model spec (JSON) against measured records: simulate it over
/// each record's input column (a fresh model per record, from its
/// initial state) and print one table row per record plus a mean row:
/// | record | samples | RMS | max |err| | NRMSE | low-passed NRMSE |.
/// RMS and max are of F_model − F_meas over the scored samples;
/// NRMSE = RMS(F_model − F_meas) / RMS(F_meas), where RMS is about
/// zero (√(Σ F²/n)), not the standard deviation. The mean row averages
/// each figure over the records (unweighted) and sums the samples.
#[derive(Debug, Clone, PartialEq, clap::Args)]
pub struct ValidateOptions {
    /// The model spec (JSON, see hysteron::models::Spec).
    #[arg(long, value_name = "SPEC.json")]
    pub model: PathBuf,
    /// A record: a CSV file with a header row of distinct column names
    /// (repeat for several records; every record needs the input,
    /// output and time columns, matched by name).
    #[arg(long, value_name = "DATA.csv", required = true)]
    pub data: Vec<PathBuf>,
    /// The input and measured output columns of every record.
    #[command(flatten)]
    pub columns: ScoredColumns,
    /// Also score both signals after a 4th-order Butterworth low-pass
    /// at HZ run forward and backward (zero phase; the whole record is
    /// filtered, then scored): the "low-passed NRMSE" column. Needs
    /// --time-column or --dt; HZ must be below Nyquist (half the
    /// sample rate).
    #[arg(long, value_name = "HZ", value_parser = args::positive_f64, allow_hyphen_values = true)]
    pub lowpass: Option<f64>,
    // `--dt` as in `SamplePeriodArgs`, but also the low-pass's sample rate
    // and the length of --skip; the help lists the registry's
    // rate-dependent kinds.
    #[arg(
        long,
        value_name = "SECONDS",
        conflicts_with = "time_column",
        value_parser = args::positive_f64,
        allow_hyphen_values = true,
        help = period::dt_help() + "; also the low-pass's sample rate and the length of --skip"
    )]
    pub dt: Option<f64>,
    // `--time-column`, as in `SamplePeriodArgs`.
    #[arg(long, value_name = "NAME", help = period::TIME_COLUMN_HELP)]
    pub time_column: Option<String>,
    /// Simulate but do not score the first SECONDS of each record
    /// (the samples i with i·dt < SECONDS; a warm-up). Needs
    /// --time-column or --dt; a record not longer is an error.
    #[arg(long, value_name = "SECONDS", value_parser = args::non_negative_f64, allow_hyphen_values = true)]
    pub skip: Option<f64>,
    /// Also write DIR/STEM.svg per record, STEM its file stem (DIR created if
    /// missing): the loop (output over input) and the output over
    /// time, the measurement as a thin sky-blue line (low-passed when
    /// --lowpass is given) under the model as a thick vermillion line.
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
    /// Also write the table as CSV (one row per record, no mean row;
    /// columns record,samples,rms,max_abs_err,nrmse and
    /// lowpassed_nrmse with --lowpass; written atomically, may not be
    /// an input).
    #[arg(long, value_name = "OUT.csv")]
    pub csv: Option<PathBuf>,
    /// Also draw the model's uncertainty band in each figure (needs
    /// --plot): the covariance file that `fit --covariance` wrote, with
    /// the fitted spec it wrote as --model; the band is computed over
    /// each record's input (see --band-level and --band-method) and
    /// drawn under the model and, in a third panel, about it.
    #[arg(long, value_name = "COV.json")]
    pub covariance: Option<PathBuf>,
    /// The band's level and method (for --covariance).
    #[command(flatten)]
    pub band_args: BandArgs,
}

impl ValidateOptions {
    /// Where the sample period comes from (a time column is read from each
    /// record); needed by `lowpass` and `skip`.
    pub fn dt_source(&self) -> DtSource {
        DtSource::from_options(self.dt, self.time_column.clone())
    }
}

/// The columns `validate` scores, and `compare` with it: the input, and
/// the measured output.
#[derive(Debug, Clone, PartialEq, clap::Args)]
pub struct ScoredColumns {
    /// The input column of every record.
    #[arg(long, value_name = "NAME", default_value = "x")]
    pub input_column: String,
    /// The measured output column of every record.
    #[arg(long, value_name = "NAME", default_value = "F")]
    pub output_column: String,
}

/// An error of the validate job (one line naming file, row and column
/// where relevant).
#[derive(Debug, thiserror::Error)]
pub enum ValidateError {
    /// `--covariance` without `--plot`: the band is drawn in the figures.
    #[error("--covariance draws the uncertainty band in the figures: give --plot DIR too")]
    CovarianceWithoutPlot,
    /// The covariance file could not be read or is not the model's.
    #[error(transparent)]
    Covariance(#[from] CovarianceFileError),
    /// The band could not be computed on a record.
    #[error("data `{}`: band: {source}", path.display())]
    Band {
        /// The record.
        path: PathBuf,
        /// Why.
        source: BandError,
    },
    /// An output path names an input file or another output.
    #[error(transparent)]
    SameFile(#[from] csvio::SameFile),
    /// `--input-column` and `--output-column` name the same column.
    #[error("--input-column and --output-column both name the column `{0}`")]
    SameColumn(String),
    /// The model spec could not be read, parsed or built.
    #[error(transparent)]
    Model(#[from] ModelFileError),
    /// A record could not be read or is invalid.
    #[error("data {0}")]
    Data(CsvIoError),
    /// A later record lacks a column the first record has.
    #[error(
        "data `{}`: no column `{column}` in the header (columns: {}), but the first record `{}` \
         has it: the records' headers differ in the needed columns",
        path.display(),
        available.join(", "),
        first.display()
    )]
    HeaderMismatch {
        /// The record lacking the column.
        path: PathBuf,
        /// The column.
        column: String,
        /// Its header.
        available: Vec<String>,
        /// The first record.
        first: PathBuf,
    },
    /// No sample period could be chosen (the spec's and a record's time
    /// column disagree).
    #[error(transparent)]
    Period(PeriodError),
    /// `--lowpass` or `--skip` without a sample period.
    #[error("{0} needs the sample period: give --time-column NAME or --dt SECONDS")]
    NeedsRate(&'static str),
    /// The cut-off is not below a record's Nyquist frequency.
    #[error(
        "--lowpass {cutoff} Hz must be below the Nyquist frequency {nyquist} Hz of record `{}` \
         (sample period {dt} s)",
        path.display()
    )]
    AboveNyquist {
        /// The record.
        path: PathBuf,
        /// The cut-off (Hz).
        cutoff: f64,
        /// Half its sample rate (Hz).
        nyquist: f64,
        /// Its sample period (s).
        dt: f64,
    },
    /// A record not longer than `--skip`.
    #[error(
        "data `{}`: {samples} samples of {dt} s ({} s) are not longer than --skip {skip} s: \
         nothing left to score",
        path.display(),
        csvio::fmt_f64(*samples as f64 * dt)
    )]
    SkipTooLong {
        /// The record.
        path: PathBuf,
        /// Its samples.
        samples: usize,
        /// Its sample period.
        dt: f64,
        /// `--skip`.
        skip: f64,
    },
    /// The model failed at a sample.
    #[error("model `{}` failed{}", .0.model.display(), .0.location())]
    Operator(Box<csvio::SampleFailure>),
    /// The model's output is not finite at a sample.
    #[error(
        "model `{}` gives a non-finite output {value} at sample {sample}: data `{}`, row {row} \
         (line {line}), column `{column}` = {}",
        model.display(),
        path.display(),
        csvio::fmt_f64(*input)
    )]
    NonFiniteOutput {
        /// The model spec.
        model: PathBuf,
        /// The record.
        path: PathBuf,
        /// 0-based sample.
        sample: usize,
        /// 1-based data row.
        row: usize,
        /// Line in the file.
        line: u64,
        /// The input column.
        column: String,
        /// The input value.
        input: f64,
        /// The output.
        value: f64,
    },
    /// The figures of a record cannot be computed (for example a
    /// measured column that is zero at every scored sample).
    #[error("data `{}`, column `{column}`: {error}", path.display())]
    Metrics {
        /// The record.
        path: PathBuf,
        /// The measured column.
        column: String,
        /// What failed.
        error: MetricsError,
    },
    /// Two records would have the same figure.
    #[error(
        "records `{}` and `{}` have the same file stem: both figures would be `{}`",
        first.display(),
        second.display(),
        svg.display()
    )]
    SameStem {
        /// The first record.
        first: PathBuf,
        /// The second.
        second: PathBuf,
        /// The figure both would write.
        svg: PathBuf,
    },
    /// Writing an output or drawing a figure failed.
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// One record's row of the table.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordRow {
    /// The record, as named on the command line.
    pub record: PathBuf,
    /// Its sample period, if known.
    pub dt: Option<f64>,
    /// The sample period the model ran at, and where it came from (`None`
    /// for a rate-independent model).
    pub period: Option<Period>,
    /// Samples not scored (`--skip`).
    pub skipped: usize,
    /// RMS, largest error and NRMSE over the scored samples.
    pub figures: ErrorFigures,
    /// The NRMSE after the low-pass (with `--lowpass`).
    pub lowpassed_nrmse: Option<f64>,
}

/// What the validate job did.
#[derive(Debug, Clone, PartialEq)]
pub struct ValidateReport {
    /// The model spec.
    pub model: PathBuf,
    /// The root node of the spec.
    pub kind: &'static str,
    /// Input and output column.
    pub columns: (String, String),
    /// `--lowpass`.
    pub lowpass: Option<f64>,
    /// `--skip`.
    pub skip: Option<f64>,
    /// One row per record.
    pub rows: Vec<RecordRow>,
    /// Files written.
    pub files: Vec<PathBuf>,
}

/// The CSV header of `--csv` (snake case of the table's header).
pub const CSV_HEADER: [&str; 5] = ["record", "samples", "rms", "max_abs_err", "nrmse"];
/// The CSV column of the low-passed NRMSE (with `--lowpass`).
pub const CSV_LOWPASSED: &str = "lowpassed_nrmse";

/// A number for the table: 4 significant digits.
fn short(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if (1e-3..1e5).contains(&a) {
        let digits = (3 - a.log10().floor() as i32).max(0) as usize;
        format!("{v:.digits$}")
    } else {
        format!("{v:.3e}")
    }
}

impl ValidateReport {
    /// The mean over records of RMS, max, NRMSE and low-passed NRMSE
    /// (unweighted), and the total of scored samples.
    pub fn mean(&self) -> (usize, f64, f64, f64, Option<f64>) {
        let n = self.rows.len().max(1) as f64;
        let sum = |f: &dyn Fn(&RecordRow) -> f64| self.rows.iter().map(f).sum::<f64>() / n;
        (
            self.rows.iter().map(|r| r.figures.samples).sum(),
            sum(&|r| r.figures.rms),
            sum(&|r| r.figures.max_abs),
            sum(&|r| r.figures.nrmse),
            self.lowpass
                .map(|_| sum(&|r| r.lowpassed_nrmse.unwrap_or(f64::NAN))),
        )
    }

    /// The table as CSV text (one row per record, no mean row).
    pub fn to_csv(&self) -> Result<String, csv::Error> {
        let mut w = csv::Writer::from_writer(Vec::new());
        let mut header: Vec<&str> = CSV_HEADER.to_vec();
        if self.lowpass.is_some() {
            header.push(CSV_LOWPASSED);
        }
        w.write_record(&header)?;
        for r in &self.rows {
            let mut row = vec![
                r.record.display().to_string(),
                r.figures.samples.to_string(),
                csvio::fmt_f64(r.figures.rms),
                csvio::fmt_f64(r.figures.max_abs),
                csvio::fmt_f64(r.figures.nrmse),
            ];
            if let Some(v) = r.lowpassed_nrmse {
                row.push(csvio::fmt_f64(v));
            }
            w.write_record(&row)?;
        }
        let bytes = w
            .into_inner()
            .map_err(|e| csv::Error::from(e.into_error()))?;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    }
}

impl fmt::Display for ValidateReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "validation of `{}` ({}) on {} record{}, {} -> {}",
            self.model.display(),
            self.kind,
            self.rows.len(),
            if self.rows.len() == 1 { "" } else { "s" },
            self.columns.0,
            self.columns.1
        )?;
        if let Some(s) = self.skip {
            write!(
                f,
                "; first {} s of each record not scored",
                csvio::fmt_f64(s)
            )?;
        }
        if let Some(hz) = self.lowpass {
            write!(
                f,
                "; low-passed: 4th-order Butterworth at {} Hz, forward and backward",
                csvio::fmt_f64(hz)
            )?;
        }
        writeln!(f)?;
        let periods: Vec<&Period> = self.rows.iter().filter_map(|r| r.period.as_ref()).collect();
        match periods.as_slice() {
            [] => {}
            [first, rest @ ..] if rest.iter().all(|p| p == first) => {
                writeln!(f, "sample period: {first}")?;
            }
            _ => {
                for r in &self.rows {
                    if let Some(p) = &r.period {
                        writeln!(f, "sample period of `{}`: {p}", r.record.display())?;
                    }
                }
            }
        }
        writeln!(
            f,
            "NRMSE = RMS(model - measured) / RMS(measured), RMS about zero"
        )?;
        let lp = self.lowpass.is_some();
        let mut header = "| record | samples | RMS | max \\|err\\| | NRMSE |".to_string();
        let mut rule = "|---|---:|---:|---:|---:|".to_string();
        if lp {
            header.push_str(" low-passed NRMSE |");
            rule.push_str("---:|");
        }
        writeln!(f, "{header}")?;
        writeln!(f, "{rule}")?;
        let line = |f: &mut fmt::Formatter<'_>,
                    name: &str,
                    n: usize,
                    rms: f64,
                    max: f64,
                    nrmse: f64,
                    lpn: Option<f64>|
         -> fmt::Result {
            write!(
                f,
                "| {name} | {n} | {} | {} | {} |",
                short(rms),
                short(max),
                short(nrmse)
            )?;
            if let Some(v) = lpn {
                write!(f, " {} |", short(v))?;
            }
            writeln!(f)
        };
        for r in &self.rows {
            let name = r.record.display().to_string().replace('|', "\\|");
            let fig = &r.figures;
            line(
                f,
                &name,
                fig.samples,
                fig.rms,
                fig.max_abs,
                fig.nrmse,
                r.lowpassed_nrmse,
            )?;
        }
        let (n, rms, max, nrmse, lpn) = self.mean();
        line(f, "mean", n, rms, max, nrmse, lpn)?;
        if self.files.is_empty() {
            Ok(())
        } else {
            write!(f, "wrote {}", csvio::join_paths(&self.files))
        }
    }
}

/// A record read and scored, with what its figure needs.
struct Scored {
    row: RecordRow,
    x: Vec<f64>,
    measured: Vec<f64>,
    model: Vec<f64>,
    /// The low-passed measurement (with `--lowpass`).
    measured_lp: Option<Vec<f64>>,
    /// The model's uncertainty band (with `--covariance`).
    band: Option<Band>,
}

/// The first `skip` seconds of a record sampled every `dt`, in samples:
/// the samples `i` with `i·dt < skip` (a thousandth of a step of slack,
/// so that `skip` a whole number of steps skips exactly that many).
fn skipped_samples(skip: f64, dt: f64) -> usize {
    let steps = skip / dt - 1e-3;
    if steps <= 0.0 {
        0
    } else if steps >= usize::MAX as f64 {
        usize::MAX
    } else {
        steps.ceil() as usize
    }
}

/// Runs the validation; see the module docs.
pub fn run(opts: &ValidateOptions) -> Result<ValidateReport, ValidateError> {
    // Outputs may not be inputs, nor each other.
    let mut inputs: Vec<(&'static str, &Path)> = vec![("model", opts.model.as_path())];
    inputs.extend(opts.data.iter().map(|d| ("data", d.as_path())));
    if let Some(c) = &opts.csv {
        csvio::refuse_same("--csv output", c, &inputs)?;
    }
    let mut svgs: Vec<PathBuf> = Vec::new();
    if let Some(dir) = &opts.plot {
        for (i, d) in opts.data.iter().enumerate() {
            // `<stem>.svg`, appended (with_extension would cut a stem with
            // dots, `sine_0.5Hz`, at its last dot); a compressed record
            // `A.csv.gz` gives `A.svg`, like `A.csv`.
            let mut stem = Path::new(d.file_stem().unwrap_or(d.as_os_str()));
            let csv = stem
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
            if csv && d.extension().is_some_and(|e| e.eq_ignore_ascii_case("gz")) {
                if let Some(inner) = stem.file_stem() {
                    stem = Path::new(inner);
                }
            }
            let mut name = stem.as_os_str().to_os_string();
            name.push(".svg");
            let svg = dir.join(name);
            if let Some(j) = svgs.iter().position(|s| s == &svg) {
                return Err(ValidateError::SameStem {
                    first: opts.data[j].clone(),
                    second: opts.data[i].clone(),
                    svg,
                });
            }
            csvio::refuse_same("plot", &svg, &inputs)?;
            if let Some(c) = &opts.csv {
                csvio::refuse_same("plot", &svg, &[("--csv output", c.as_path())])?;
            }
            svgs.push(svg);
        }
    }
    if opts.columns.input_column.trim() == opts.columns.output_column.trim() {
        return Err(ValidateError::SameColumn(opts.columns.input_column.clone()));
    }
    if opts.covariance.is_some() && opts.plot.is_none() {
        return Err(ValidateError::CovarianceWithoutPlot);
    }
    let (spec, checked) = model_file::read_checked(&opts.model)?;
    let kind = spec.kind();
    let cov = match &opts.covariance {
        Some(path) => Some(band_file::read_for(path, checked.as_ref())?),
        None => None,
    };
    // A rate-independent model has no period unless one is given (a
    // rate-dependent one's is checked with each record).
    let source = opts.dt_source();
    if source == DtSource::Spec && !spec.is_rate_dependent() {
        if opts.lowpass.is_some() {
            return Err(ValidateError::NeedsRate("--lowpass"));
        }
        if opts.skip.is_some() {
            return Err(ValidateError::NeedsRate("--skip"));
        }
    }

    let mut scored: Vec<Scored> = Vec::with_capacity(opts.data.len());
    let mut columns = (String::new(), String::new());
    for (k, path) in opts.data.iter().enumerate() {
        let s = score(opts, &source, &spec, cov.as_ref(), path, k)?;
        if k == 0 {
            columns = s.1;
        }
        scored.push(s.0);
    }

    // Figures are drawn in memory before anything is written.
    let mut figures = Vec::new();
    for (s, svg) in scored.iter().zip(&svgs) {
        let text = figure(opts, s, &columns).map_err(|e| OutputError::Plot(svg.clone(), e))?;
        figures.push((svg.clone(), text));
    }

    let mut report = ValidateReport {
        model: opts.model.clone(),
        kind,
        columns,
        lowpass: opts.lowpass,
        skip: opts.skip,
        rows: scored.into_iter().map(|s| s.row).collect(),
        files: Vec::new(),
    };

    let csv_text = report
        .to_csv()
        .map_err(|e| OutputError::Write(csv_error(opts.csv.as_deref(), e)))?;
    if let Some(c) = &opts.csv {
        csvio::target_dir(c).map_err(OutputError::Write)?;
    }
    if let Some(dir) = &opts.plot {
        std::fs::create_dir_all(dir).map_err(|e| OutputError::PlotDir(dir.clone(), e))?;
    }
    if let Some(c) = &opts.csv {
        csvio::write_string_atomic(c, &csv_text).map_err(OutputError::Write)?;
        report.files.push(c.clone());
    }
    for (svg, text) in figures {
        csvio::write_string_atomic(&svg, &text).map_err(OutputError::Write)?;
        report.files.push(svg);
    }
    Ok(report)
}

fn csv_error(path: Option<&Path>, e: csv::Error) -> CsvIoError {
    CsvIoError::Io {
        path: path.map_or_else(PathBuf::new, Path::to_path_buf),
        source: std::io::Error::other(e.to_string()),
    }
}

/// Reads record `k` at `path`, runs a fresh model over it and scores it;
/// also returns the input and output column names as in its header.
fn score(
    opts: &ValidateOptions,
    source: &DtSource,
    spec: &Spec,
    cov: Option<&Covariance>,
    path: &Path,
    k: usize,
) -> Result<(Scored, (String, String)), ValidateError> {
    let wanted = [
        opts.columns.input_column.as_str(),
        opts.columns.output_column.as_str(),
    ];
    let cols = csvio::read_columns(path, &wanted).map_err(|e| match e {
        CsvIoError::MissingColumn {
            path,
            column,
            available,
        } if k > 0 => ValidateError::HeaderMismatch {
            path,
            column,
            available,
            first: opts.data[0].clone(),
        },
        e => ValidateError::Data(e),
    })?;
    let name = |i: usize| cols.headers[cols.indices[i]].trim().to_string();
    let (input_name, output_name) = (name(0), name(1));
    if cols.indices[0] == cols.indices[1] {
        return Err(ValidateError::SameColumn(input_name));
    }
    let mut values = cols.values.into_iter();
    let x = values.next().unwrap_or_default();
    let measured = values.next().unwrap_or_default();
    let period = period::resolve(spec, source, path).map_err(|e| match e {
        PeriodError::Data(e) => ValidateError::Data(e),
        e => ValidateError::Period(e),
    })?;
    let dt = period.as_ref().map(|p| p.dt);
    if dt.is_none() {
        if opts.lowpass.is_some() {
            return Err(ValidateError::NeedsRate("--lowpass"));
        }
        if opts.skip.is_some() {
            return Err(ValidateError::NeedsRate("--skip"));
        }
    }
    let n = x.len();

    let lowpass = match (opts.lowpass, dt) {
        (Some(hz), Some(dt)) => Some(Lowpass::butterworth(hz, 1.0 / dt).map_err(|e| match e {
            MetricsError::AboveNyquist { cutoff, nyquist } => ValidateError::AboveNyquist {
                path: path.to_path_buf(),
                cutoff,
                nyquist,
                dt,
            },
            error => ValidateError::Metrics {
                path: path.to_path_buf(),
                column: output_name.clone(),
                error,
            },
        })?),
        _ => None,
    };
    let skipped = match (opts.skip, dt) {
        (Some(skip), Some(dt)) => {
            let s = skipped_samples(skip, dt);
            if s >= n {
                return Err(ValidateError::SkipTooLong {
                    path: path.to_path_buf(),
                    samples: n,
                    dt,
                    skip,
                });
            }
            s
        }
        _ => 0,
    };

    // A fresh model per record, from the spec's initial state.
    let spec = period.as_ref().map_or(spec.clone(), |p| p.apply(spec));
    let period = period.filter(|_| spec.is_rate_dependent());
    let mut model = model_file::build(&opts.model, &spec)?;
    let y = model.run(&x).map_err(|e| {
        ValidateError::Operator(Box::new(csvio::SampleFailure::locate(
            &opts.model,
            path,
            "data",
            &input_name,
            &x,
            &cols.lines,
            e,
        )))
    })?;
    if let Some(i) = y.iter().position(|v| !v.is_finite()) {
        return Err(ValidateError::NonFiniteOutput {
            model: opts.model.clone(),
            path: path.to_path_buf(),
            sample: i,
            row: i + 1,
            line: cols.lines.get(i).copied().unwrap_or(i as u64 + 2),
            column: input_name,
            input: x[i],
            value: y[i],
        });
    }

    let band = match cov {
        Some(cov) => Some(
            opts.band_args
                .band(model.as_ref(), cov, &x)
                .map_err(|source| ValidateError::Band {
                    path: path.to_path_buf(),
                    source,
                })?,
        ),
        None => None,
    };

    let metrics_err = |error| ValidateError::Metrics {
        path: path.to_path_buf(),
        column: output_name.clone(),
        error,
    };
    let figures = metrics::errors(&y[skipped..], &measured[skipped..]).map_err(metrics_err)?;
    let (lowpassed_nrmse, measured_lp) = match &lowpass {
        Some(lp) => {
            let m = lp.filtfilt(&y).map_err(metrics_err)?;
            let r = lp.filtfilt(&measured).map_err(metrics_err)?;
            let e = metrics::errors(&m[skipped..], &r[skipped..]).map_err(metrics_err)?;
            (Some(e.nrmse), Some(r))
        }
        None => (None, None),
    };
    Ok((
        Scored {
            row: RecordRow {
                record: path.to_path_buf(),
                dt,
                period,
                skipped,
                figures,
                lowpassed_nrmse,
            },
            x,
            measured,
            model: y,
            measured_lp,
            band,
        },
        (input_name, output_name),
    ))
}

/// A record's figure: the loop (output over input) and the output over
/// time (or sample), measured as a thin sky-blue line (low-passed with
/// `--lowpass`) under the model as a thick vermillion line.
fn figure(
    opts: &ValidateOptions,
    s: &Scored,
    (input, output): &(String, String),
) -> Result<String, PlotError> {
    let (measured, label) = match (&s.measured_lp, opts.lowpass) {
        (Some(lp), Some(hz)) => (
            lp.as_slice(),
            format!("measured, low-passed at {} Hz", csvio::fmt_f64(hz)),
        ),
        _ => (s.measured.as_slice(), "measured".to_string()),
    };
    let title = format!(
        "{} on {}: NRMSE {}",
        file_name(&opts.model),
        file_name(&s.row.record),
        short(s.row.figures.nrmse)
    );
    let mut loop_panel = Panel::new(&title, input, output);
    loop_panel
        .series
        .push(Series::line(label.clone(), pairs(&s.x, measured), 5));
    loop_panel
        .series
        .push(Series::line("model", pairs(&s.x, &s.model), 1).with_style(Style::ThickLine));

    let n = s.x.len();
    let (time, time_label) = match s.row.dt {
        Some(dt) => {
            let (scale, label) = plot::power_of_ten(n.saturating_sub(1) as f64 * dt, "t (s)");
            let t: Vec<f64> = (0..n).map(|i| i as f64 * dt / scale).collect();
            (t, label)
        }
        None => {
            let (scale, label) = plot::power_of_ten(n.saturating_sub(1) as f64, "sample");
            ((0..n).map(|i| i as f64 / scale).collect(), label)
        }
    };
    let mut time_panel = Panel::new(&format!("{output} over time"), &time_label, output);
    time_panel
        .series
        .push(Series::line(label, pairs(&time, measured), 5));
    let Some(b) = &s.band else {
        time_panel
            .series
            .push(Series::line("model", pairs(&time, &s.model), 1).with_style(Style::ThickLine));
        return plot::render(&[loop_panel, time_panel], 1, 2, (1200, 500));
    };
    // The band's edges as thin purple lines under the model, and, since a
    // band is often narrower than the model's line, a third panel of the
    // edges about the model (lower − model, upper − model; the
    // measurement's noise, often far wider, left out so the band shows).
    let band_label = format!(
        "{} % band ({})",
        csvio::fmt_f64(100.0 * b.level),
        b.method.name()
    );
    time_panel
        .series
        .push(Series::line(band_label.clone(), pairs(&time, &b.lower), 3));
    time_panel
        .series
        .push(Series::line("", pairs(&time, &b.upper), 3));
    time_panel
        .series
        .push(Series::line("model", pairs(&time, &s.model), 1).with_style(Style::ThickLine));
    // plotters labels ticks with a fixed format: the edges are scaled by a
    // power of ten named in the axis label (as `fit`'s residual)
    let largest = b
        .lower
        .iter()
        .chain(&b.upper)
        .zip(s.model.iter().chain(&s.model))
        .fold(0.0_f64, |a, (e, m)| a.max((e - m).abs()));
    let (scale, axis) = plot::power_of_ten(largest, &format!("{output} - model"));
    let about = |edge: &[f64]| -> Vec<(f64, f64)> {
        let d = edge.iter().zip(&s.model).map(|(e, m)| (e - m) / scale);
        time.iter().copied().zip(d).collect()
    };
    let mut band_panel = Panel::new(&format!("{band_label} about the model"), &time_label, &axis);
    band_panel
        .series
        .push(Series::line("edges - model", about(&b.lower), 3));
    band_panel.series.push(Series::line("", about(&b.upper), 3));
    plot::render(&[loop_panel, time_panel, band_panel], 1, 3, (1800, 500))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skip_counts_samples_before_the_time() {
        assert_eq!(skipped_samples(0.0, 0.1), 0);
        assert_eq!(skipped_samples(0.5, 1.0 / 1024.0), 512);
        assert_eq!(skipped_samples(0.3, 0.1), 3); // 0.3/0.1 = 2.9999999999999996
        assert_eq!(skipped_samples(0.25, 0.1), 3);
        assert_eq!(skipped_samples(1e300, 1e-300), usize::MAX);
    }

    #[test]
    fn table_numbers_have_4_significant_digits() {
        assert_eq!(short(0.0), "0");
        assert_eq!(short(0.123456), "0.1235");
        assert_eq!(short(12.3456), "12.35");
        assert_eq!(short(1.5e-7), "1.500e-7");
    }
}
