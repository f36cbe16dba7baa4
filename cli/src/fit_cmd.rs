//! The `fit` job: fits chosen parameters of a model spec (JSON, see
//! [`Spec`]) to one record or several (two columns of CSV files, input and measured
//! output) with Levenberg-Marquardt
//! ([`fit_records`](crate::identify::fit_records), from several starting
//! points with `--starts`: [`fit_multistart`]), prints a report and writes
//! the fitted spec, optionally with a figure of measured and fitted output.
//!
//! * The free parameters are named as the built model's
//!   [`param_names`](hysteron::Parameters::param_names) (`left.mms.f_c`) or by a
//!   unique suffix after a dot (`f_c`), see [`free_by_names`]; the others
//!   keep the spec's values. The fit starts from the spec's values.
//! * The fitted spec is the input spec with all parameters replaced by the
//!   fitted ones ([`Spec::with_params`]): same tree, same solver options;
//!   `simulate` runs it.
//! * While the fit runs, a one-line progress display (iteration,
//!   evaluations, cost, elapsed time) is drawn on stderr when stderr is a
//!   terminal; it is cleared before anything else is printed, so errors
//!   stay one line. It is never drawn when stderr is not a terminal.
//!
//! * `--band FILE` writes the uncertainty band of the fitted output over
//!   each record's input (CSV: `record` with several records, the input
//!   column, `output`, `lower`, `upper`), from the covariance of the
//!   shared parameters ([`Fit::predict_band`](crate::identify::Fit::predict_band);
//!   each record's own parameters held at its values); `--covariance FILE`
//!   writes that covariance (JSON), which `validate --covariance` reads.
//!
//! Nothing is written unless everything before succeeded: model and data
//! are read and checked, the fit run, the fitted spec built and simulated
//! over the record, and the figure drawn in memory first; then the files are
//! written atomically. No output may be the data or the model file, nor
//! another output (compared after canonicalization).
//!
//! # Exit status
//!
//! A fit that ran to the end but did not converge (the evaluation budget,
//! `--patience`, ran out, or the solver stopped on a numerical problem) is
//! not an error: the report is printed with a `NOT CONVERGED` line and the
//! last iterate is written like a converged fit, and the program exits with
//! code [`EXIT_NOT_CONVERGED`](crate::fitting::EXIT_NOT_CONVERGED) (3) so that scripts can tell. A converged
//! fit exits with 0; errors (nothing written) with 1.

use crate::args;
use crate::band::{self as band_file, BandArgs};
use crate::csvio::{self, CsvIoError};
use crate::fitting::{not_converged_note, ProgressArgs};
use crate::identify::band::{BandError, Covariance};
use crate::identify::{
    fit_multistart, free_by_names, FitError, FitOptions, FitReport, Jacobian, MultiStart, Record,
};
use crate::model_file::{self, ModelFileError};
use crate::models::Spec;
use crate::output::OutputError;
use crate::period::{self, Period, PeriodError, SamplePeriodArgs};
use crate::plot::{self, file_name, pairs, Panel, PlotError, Series, Style};
use crate::Operator;
use std::fmt;
use std::path::{Path, PathBuf};

/// Fit parameters of a model spec (JSON) to one record or several
/// (input and measured output columns of CSV files) with
/// Levenberg-Marquardt, starting from the spec's values; prints a
/// report (per record too) and writes the fitted spec. Exit code 3 when
/// the fit ran but did not converge.
#[derive(Debug, Clone, PartialEq, clap::Args)]
pub struct FitCmdOptions {
    /// The model spec (JSON); its parameters are the starting values.
    #[arg(long, value_name = "SPEC.json")]
    pub model: PathBuf,
    /// A record: a CSV file (or .csv.gz) with a header row of distinct
    /// column names (blank lines only at the end of the file). Repeat
    /// for several records: one parameter set is fitted to all, each
    /// record simulated from the model's initial state.
    #[arg(long, value_name = "DATA.csv", required = true)]
    pub data: Vec<PathBuf>,
    /// The input column of the record.
    #[arg(long, value_name = "NAME", default_value = "x")]
    pub input_column: String,
    /// The measured output column of the record.
    #[arg(long, value_name = "NAME", default_value = "y")]
    pub output_column: String,
    /// Parameters to fit, comma-separated: full names as the model
    /// lists them (left.mms.f_c) or unique suffixes (f_c).
    #[arg(long, value_name = "NAMES", value_delimiter = ',')]
    pub free: Vec<String>,
    /// Parameters fitted separately for each record, comma-separated
    /// (an initial state or preload, e.g. f0): reported per record; the
    /// fitted spec keeps their starting values.
    #[arg(long, value_name = "NAMES", value_delimiter = ',')]
    pub own: Vec<String>,
    /// Seconds at the start of each record that the model runs but the
    /// residual does not count (warm-up from the initial state); needs
    /// --dt or --time-column.
    #[arg(long, value_name = "SECONDS", allow_hyphen_values = true)]
    pub skip: Option<f64>,
    /// Hard bound on the work: at most N model runs over the records in
    /// the search (trial steps and Jacobian columns alike; the report
    /// at the end adds 2·free + 1). The fit then ends at its best point,
    /// not converged (exit code 3).
    #[arg(long, value_name = "N", value_parser = args::at_least_1, allow_negative_numbers = true)]
    pub max_evaluations: Option<usize>,
    /// Wall-time limit of the search in seconds: no new model run starts
    /// after it (the Jacobian under way finishes). The fit then ends at
    /// its best point, not converged (exit code 3).
    #[arg(long, value_name = "SECONDS", value_parser = args::positive_f64, allow_hyphen_values = true)]
    pub max_seconds: Option<f64>,
    /// Where to write the fitted spec (JSON, written atomically; may
    /// not be the model or data file).
    #[arg(long, value_name = "FITTED.json")]
    pub output: PathBuf,
    /// Also draw measured and fitted output (over the input and over
    /// the sample index) and the residual as an SVG figure.
    #[arg(long, value_name = "FIT.svg")]
    pub plot: Option<PathBuf>,
    /// Also write the uncertainty band of the fitted output over each
    /// record's input as CSV (written atomically): columns record (with
    /// several records), the input column, output (the fitted model's),
    /// lower, upper; see --band-level and --band-method.
    #[arg(long, value_name = "BAND.csv")]
    pub band: Option<PathBuf>,
    /// Also write the covariance of the fitted shared parameters as JSON
    /// (names, indices, values, matrix): `validate --covariance` reads it
    /// with the fitted spec to draw the band on other records.
    #[arg(long, value_name = "COV.json")]
    pub covariance: Option<PathBuf>,
    /// The band's level and method (for --band).
    #[command(flatten)]
    pub band_args: BandArgs,
    /// Levenberg-Marquardt's patience: at most PATIENCE·(free + 1) trial
    /// steps; each accepted step also runs 2·free simulations for its
    /// Jacobian, so at most PATIENCE·(free + 1)·(2·free + 1) model runs
    /// (at least 1; for a hard bound use --max-evaluations or
    /// --max-seconds).
    #[arg(long, value_name = "N", default_value_t = PATIENCE, value_parser = args::at_least_1, allow_negative_numbers = true)]
    pub patience: usize,
    /// How the Jacobian is computed: `exact` (forward-mode derivatives
    /// through the model over dual numbers, one simulation per 8
    /// parameters; see the guide's docs/derivatives.md) or `fd` (central finite
    /// differences, two simulations per parameter).
    #[arg(long, value_enum, default_value_t = JACOBIAN)]
    pub jacobian: JacobianArg,
    /// Fit from N starting points: the spec's own and N − 1 from a Latin
    /// hypercube around it (see --spread), in parallel; the best is
    /// kept and the report says how many starts reached its cost
    /// (within 1 %).
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = args::at_least_1, allow_negative_numbers = true)]
    pub starts: usize,
    /// Half-width of the hypercube in the fit's internal parameters: a
    /// positive parameter starts within a factor e^S of its value, one
    /// in [0, 1] within ±S in its logit, an unbounded one within
    /// ±S·max(|p|, 1). Default ln 4.
    #[arg(long, value_name = "S", default_value_t = SPREAD, value_parser = args::positive_f64, allow_hyphen_values = true)]
    pub spread: f64,
    /// Seed of the hypercube (the same seed, the same starts).
    #[arg(long, value_name = "K", default_value_t = 0)]
    pub seed: u64,
    /// Whether to draw the progress line.
    #[command(flatten)]
    pub progress: ProgressArgs,
    /// Where the sample period of the rate-dependent nodes comes from (a
    /// time column is read from `data`); the fitted spec keeps it.
    #[command(flatten)]
    pub period: SamplePeriodArgs,
}

/// The default of [`FitCmdOptions::patience`] (`--patience`), which
/// `compare`'s fits use too.
pub const PATIENCE: usize = 200;

/// The default of [`FitCmdOptions::jacobian`] (`--jacobian`), which
/// `compare`'s fits use too.
pub const JACOBIAN: JacobianArg = JacobianArg::Exact;

/// The default of [`FitCmdOptions::spread`] (`--spread`), which
/// `compare`'s fits use too: ln 4, the library's
/// ([`MultiStart::default`]).
pub const SPREAD: f64 = 2.0 * std::f64::consts::LN_2;

impl FitCmdOptions {
    /// The starting points ([`fit_multistart`]; one start: a plain fit).
    pub fn multi_start(&self) -> MultiStart {
        MultiStart {
            starts: self.starts,
            spread: self.spread,
            seed: self.seed,
        }
    }
}

/// `--jacobian`: how the Jacobian is computed ([`FitOptions::jacobian`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum JacobianArg {
    /// Forward-mode derivatives.
    Exact,
    /// Central finite differences.
    Fd,
}

impl From<JacobianArg> for Jacobian {
    fn from(arg: JacobianArg) -> Self {
        match arg {
            JacobianArg::Exact => Jacobian::Exact,
            JacobianArg::Fd => Jacobian::FiniteDifferences,
        }
    }
}

/// An error of the fit job (one-line message naming file, row and column
/// where relevant).
#[derive(Debug, thiserror::Error)]
pub enum FitCmdError {
    /// An output path names an input file or the other output.
    #[error(transparent)]
    SameFile(#[from] csvio::SameFile),
    /// `--input-column` and `--output-column` name the same column.
    #[error("--input-column and --output-column both name the column `{0}`")]
    SameColumn(String),
    /// The model spec could not be read, parsed or built.
    #[error(transparent)]
    Model(#[from] ModelFileError),
    /// The data could not be read or is invalid.
    #[error("data {0}")]
    Data(CsvIoError),
    /// No sample period could be chosen (the spec's and a record's time
    /// column disagree).
    #[error(transparent)]
    Period(PeriodError),
    /// `--skip` is given without a sample period (`--dt` or
    /// `--time-column`).
    #[error("--skip needs the sample period: give --dt or --time-column")]
    SkipWithoutPeriod,
    /// `--skip` is negative or not finite.
    #[error("--skip must be a finite number of seconds ≥ 0 (got {0})")]
    BadSkip(f64),
    /// A record is not longer than its warm-up.
    #[error("data `{}`: --skip {skip} s is {samples} samples, but the record has only {rows}", path.display())]
    ShortRecord {
        /// The record.
        path: PathBuf,
        /// The warm-up in seconds.
        skip: f64,
        /// The warm-up in samples.
        samples: usize,
        /// The record's rows.
        rows: usize,
    },
    /// The records' time columns give different sample periods.
    #[error("data `{}`: its time column steps {dt} s, but `{}` steps {first} s (every record must have the model's period)", path.display(), first_path.display())]
    PeriodMismatch {
        /// The record that differs.
        path: PathBuf,
        /// Its period.
        dt: f64,
        /// The first record.
        first_path: PathBuf,
        /// The first record's period.
        first: f64,
    },
    /// The same data file is given twice.
    #[error("--data `{}` is given twice", .0.display())]
    DuplicateData(PathBuf),
    /// `--free` names no parameter.
    #[error("--free names no parameter of model `{}` (the model has: {available})", model.display())]
    NoFree {
        /// The model spec.
        model: PathBuf,
        /// The model's parameter names.
        available: String,
    },
    /// A `--free` or `--own` name is unknown or ambiguous.
    #[error("{}: model `{}`: {}", .0, .1.display(), .2)]
    Free(&'static str, PathBuf, FitError),
    /// A `--free` parameter that the spec cannot hold on its own (the
    /// slider's `limits.r0` or the spring's `z0` of a `transmission`
    /// spec, tied by `z0 = −slider0`).
    #[error(
        "--free: parameter `{name}` of model `{}` cannot be fitted on its own: a spring in a \
         gap starts at rest, its z0 is -r0 of the gap (-slider0 in a `transmission` spec); \
         keep both fixed",
        model.display()
    )]
    Tied {
        /// The model spec.
        model: PathBuf,
        /// The parameter's full name.
        name: String,
    },
    /// Two `--free`/`--own` names give the same parameter.
    #[error("--free/--own: parameter `{name}` of model `{}` is named twice", model.display())]
    DuplicateFree {
        /// The model spec.
        model: PathBuf,
        /// The parameter's full name.
        name: String,
    },
    /// The model cannot be simulated over the record with the starting
    /// parameters.
    #[error("model `{}` fails at the starting parameters{}", .0.model.display(), .0.location())]
    Start(Box<csvio::SampleFailure>),
    /// The fit could not run.
    #[error("fit: {0}")]
    Fit(FitError),
    /// The fitted parameters could not be written into the spec, or the
    /// fitted spec cannot be simulated over the record.
    #[error("fitted parameters of model `{}`: {}", .0.display(), .1)]
    Fitted(PathBuf, String),
    /// The band or the covariance could not be computed (a singular
    /// fit, a model without a dual twin, too few Monte-Carlo draws ran).
    #[error("{flag}: {source}")]
    Band {
        /// `--band` or `--covariance`.
        flag: &'static str,
        /// Why.
        source: BandError,
    },
    /// Writing an output or drawing a figure failed.
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// What the fit job did: the library's report plus where.
#[derive(Debug, Clone, PartialEq)]
pub struct FitCmdReport {
    /// The model spec.
    pub model: PathBuf,
    /// The root node of the spec (`"series"`).
    pub kind: &'static str,
    /// Number of model parameters.
    pub n_params: usize,
    /// The data files, in the order of the report's records.
    pub data: Vec<PathBuf>,
    /// Input and output column.
    pub columns: (String, String),
    /// Samples in each record.
    pub samples: Vec<usize>,
    /// The sample period the model ran at (`None` for a rate-independent
    /// model).
    pub period: Option<Period>,
    /// The fit.
    pub report: FitReport,
    /// Files written.
    pub files: Vec<PathBuf>,
}

impl FitCmdReport {
    /// Whether the fit converged (exit code 0, otherwise
    /// [`EXIT_NOT_CONVERGED`](crate::fitting::EXIT_NOT_CONVERGED)).
    pub fn converged(&self) -> bool {
        self.report.status.converged()
    }
}

impl fmt::Display for FitCmdReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let data = match self.data.as_slice() {
            [one] => format!("`{}`", one.display()),
            many => format!("{} records", many.len()),
        };
        writeln!(
            f,
            "fit of `{}` ({}, {} parameters, {} free) to {data}: {} samples, {} -> {}",
            self.model.display(),
            self.kind,
            self.n_params,
            self.report.params.len(),
            self.samples.iter().sum::<usize>(),
            self.columns.0,
            self.columns.1
        )?;
        if let Some(p) = &self.period {
            writeln!(f, "sample period: {p}")?;
        }
        if self.data.len() > 1 {
            for (i, (d, n)) in self.data.iter().zip(&self.samples).enumerate() {
                writeln!(f, "record {i}: `{}` ({n} samples)", d.display())?;
            }
        }
        write!(f, "{}", self.report)?;
        not_converged_note(f, &self.report)?;
        write!(f, "wrote {}", csvio::join_paths(&self.files))
    }
}

/// Refuses a free parameter that the model ties to another
/// ([`Spec::tied_params`]: a gap's `r0` and its spring's `z0 = −r0`), which
/// [`Spec::with_params`] cannot move on its own.
fn refuse_tied(
    opts: &FitCmdOptions,
    spec: &Spec,
    model: &(dyn Operator<f64> + 'static),
    free: &[usize],
) -> Result<(), FitCmdError> {
    let tied = spec.tied_params();
    let names = model.param_names();
    match free.iter().find(|&&i| tied.contains(&names[i])) {
        Some(&i) => Err(FitCmdError::Tied {
            model: opts.model.clone(),
            name: names[i].clone(),
        }),
        None => Ok(()),
    }
}

/// Resolves the `--free` or `--own` names (`flag`) to parameter indices.
fn indices(
    opts: &FitCmdOptions,
    model: &(dyn Operator<f64> + 'static),
    flag: &'static str,
    names: &[String],
) -> Result<Vec<usize>, FitCmdError> {
    let names: Vec<&str> = names
        .iter()
        .map(|s| s.trim())
        .filter(|s| !s.is_empty())
        .collect();
    free_by_names(model, &names).map_err(|e| FitCmdError::Free(flag, opts.model.clone(), e))
}

/// One record as read: input and output columns and their file lines.
struct Loaded {
    x: Vec<f64>,
    y: Vec<f64>,
    lines: Vec<u64>,
    input_name: String,
    output_name: String,
}

fn load(opts: &FitCmdOptions, path: &Path) -> Result<Loaded, FitCmdError> {
    let mut columns = csvio::read_columns(path, &[&opts.input_column, &opts.output_column])
        .map_err(FitCmdError::Data)?;
    let input_name = columns.headers[columns.indices[0]].trim().to_string();
    let output_name = columns.headers[columns.indices[1]].trim().to_string();
    if columns.indices[0] == columns.indices[1] {
        return Err(FitCmdError::SameColumn(input_name));
    }
    let y = columns.values.pop().unwrap_or_default();
    let x = columns.values.pop().unwrap_or_default();
    Ok(Loaded {
        x,
        y,
        lines: columns.lines,
        input_name,
        output_name,
    })
}

/// The sample period of the records ([`period::resolve`] of each; every
/// record must give the first one's, within the rounding of written
/// stamps), and the spec run at it.
fn with_period(opts: &FitCmdOptions, spec: Spec) -> Result<(Spec, Option<Period>), FitCmdError> {
    let Some(first_path) = opts.data.first() else {
        return Ok((spec, None));
    };
    let source = opts.period.source();
    let first = period::resolve(&spec, &source, first_path).map_err(period_error)?;
    for path in opts.data.iter().skip(1) {
        let other = period::resolve(&spec, &source, path).map_err(period_error)?;
        if let (Some(first), Some(other)) = (&first, &other) {
            if (other.dt - first.dt).abs() > csvio::TIME_STEP_REL_TOL * first.dt {
                return Err(FitCmdError::PeriodMismatch {
                    path: path.clone(),
                    dt: other.dt,
                    first_path: first_path.clone(),
                    first: first.dt,
                });
            }
        }
    }
    let spec = first.as_ref().map_or(spec.clone(), |p| p.apply(&spec));
    Ok((spec, first))
}

fn period_error(e: PeriodError) -> FitCmdError {
    match e {
        PeriodError::Data(e) => FitCmdError::Data(e),
        e => FitCmdError::Period(e),
    }
}

/// Runs the fit; see the module docs.
pub fn run(opts: &FitCmdOptions) -> Result<FitCmdReport, FitCmdError> {
    let mut inputs: Vec<(&'static str, &Path)> =
        opts.data.iter().map(|d| ("data", d.as_path())).collect();
    inputs.push(("model", opts.model.as_path()));
    let outputs = [
        ("output", Some(opts.output.as_path())),
        ("plot", opts.plot.as_deref()),
        ("band", opts.band.as_deref()),
        ("covariance", opts.covariance.as_deref()),
    ];
    csvio::refuse_overwrites(&inputs, &outputs)?;
    for (j, d) in opts.data.iter().enumerate() {
        let same = |e: &PathBuf| csvio::same_file(e, d);
        if opts.data[..j].iter().any(same) {
            return Err(FitCmdError::DuplicateData(d.clone()));
        }
    }
    if opts.input_column.trim() == opts.output_column.trim() {
        return Err(FitCmdError::SameColumn(opts.input_column.clone()));
    }
    let skip_seconds = match opts.skip {
        Some(s) if !(s >= 0.0 && s.is_finite()) => return Err(FitCmdError::BadSkip(s)),
        other => other,
    };

    let (spec, _) = model_file::read_checked(&opts.model)?;
    let (spec, period) = with_period(opts, spec)?;
    let model = model_file::build(&opts.model, &spec)?;

    let free = indices(opts, model.as_ref(), "--free", &opts.free)?;
    let own = indices(opts, model.as_ref(), "--own", &opts.own)?;
    if free.is_empty() && own.is_empty() {
        return Err(FitCmdError::NoFree {
            model: opts.model.clone(),
            available: model.param_names().join(", "),
        });
    }
    let all: Vec<usize> = free.iter().chain(&own).copied().collect();
    for (j, &i) in all.iter().enumerate() {
        if all[..j].contains(&i) {
            return Err(FitCmdError::DuplicateFree {
                model: opts.model.clone(),
                name: model.param_names()[i].clone(),
            });
        }
    }
    refuse_tied(opts, &spec, model.as_ref(), &all)?;

    let loaded = opts
        .data
        .iter()
        .map(|d| load(opts, d))
        .collect::<Result<Vec<Loaded>, _>>()?;
    let skip = match (skip_seconds, &period) {
        (None, _) => 0,
        (Some(_), None) => return Err(FitCmdError::SkipWithoutPeriod),
        (Some(s), Some(p)) => (s / p.dt).round() as usize,
    };
    let period = period.filter(|_| spec.is_rate_dependent());
    for (l, path) in loaded.iter().zip(&opts.data) {
        if skip >= l.y.len() {
            return Err(FitCmdError::ShortRecord {
                path: path.clone(),
                skip: skip_seconds.unwrap_or(0.0),
                samples: skip,
                rows: l.y.len(),
            });
        }
    }
    let (input_name, output_name) = match loaded.first() {
        Some(l) => (l.input_name.clone(), l.output_name.clone()),
        None => (opts.input_column.clone(), opts.output_column.clone()),
    };
    let records: Vec<Record<'_>> = loaded
        .iter()
        .map(|l| Record {
            x: &l.x,
            y: &l.y,
            skip,
        })
        .collect();

    let fit_opts = FitOptions {
        patience: opts.patience,
        jacobian: opts.jacobian.into(),
        max_evaluations: opts.max_evaluations,
        max_seconds: opts.max_seconds,
        ..FitOptions::default()
    };
    let fit = {
        let display = opts.progress.display();
        let progress = |p| display.update(p);
        fit_multistart(
            model.as_ref(),
            &records,
            &free,
            &own,
            &fit_opts,
            &opts.multi_start(),
            &progress,
        )
    }
    .map_err(|e| {
        let (r, error) = match e {
            FitError::Start(error) => (0, error),
            FitError::RecordStart { record, source } => (record, source),
            other => return FitCmdError::Fit(other),
        };
        let (Some(l), Some(path)) = (loaded.get(r), opts.data.get(r)) else {
            return FitCmdError::Fit(FitError::Start(error));
        };
        FitCmdError::Start(Box::new(csvio::SampleFailure::locate(
            &opts.model,
            path,
            "data",
            &l.input_name,
            &l.x,
            &l.lines,
            error,
        )))
    })?;
    let cov = match (&opts.band, &opts.covariance) {
        (None, None) => None,
        (band, _) => Some(
            Covariance::of_fit(&fit).map_err(|source| FitCmdError::Band {
                flag: if band.is_some() {
                    "--band"
                } else {
                    "--covariance"
                },
                source,
            })?,
        ),
    };
    let report = fit.report;

    // The fitted spec, checked to build to exactly the fitted parameters
    // and simulated over every record (what `simulate` will do with it;
    // per-record parameters at each record's own values).
    let fitted_err = |e: String| FitCmdError::Fitted(opts.model.clone(), e);
    let fitted = spec
        .with_params(&report.all_params)
        .map_err(|e| fitted_err(e.to_string()))?;
    let fitted_model = fitted.build().map_err(|e| fitted_err(e.to_string()))?;
    let bits = |p: &[f64]| p.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    if bits(&fitted_model.params()) != bits(&report.all_params) {
        return Err(fitted_err(
            "the fitted spec does not hold the fitted parameters".into(),
        ));
    }
    let mut y_fit = Vec::with_capacity(loaded.len());
    let mut bands = Vec::new();
    for (r, l) in loaded.iter().enumerate() {
        let mut p = report.all_params.clone();
        for fp in report.params.iter().filter(|fp| fp.record == Some(r)) {
            if let Some(v) = p.get_mut(fp.index) {
                *v = fp.value;
            }
        }
        let mut m = fitted_model.clone();
        m.set_params(&p)
            .map_err(|e| fitted_err(format!("record {r}: {e}")))?;
        y_fit.push(
            m.run(&l.x)
                .map_err(|e| fitted_err(format!("simulating record {r}: {e}")))?,
        );
        // the band of record r: its own parameters held at its values
        if let (Some(_), Some(cov)) = (&opts.band, &cov) {
            m.reset();
            let band = opts
                .band_args
                .band(m.as_ref(), cov, &l.x)
                .map_err(|source| FitCmdError::Band {
                    flag: "--band",
                    source,
                })?;
            bands.push((l.x.clone(), band));
        }
    }
    let cov_json = match &cov {
        Some(c) if opts.covariance.is_some() => {
            Some(band_file::to_json(c).map_err(|e| fitted_err(e.to_string()))?)
        }
        _ => None,
    };
    let json = fitted
        .to_json_pretty()
        .map_err(|e| fitted_err(e.to_string()))?;

    let svg = match &opts.plot {
        Some(p) => Some(
            figure(opts, &input_name, &output_name, &loaded, &y_fit)
                .map_err(|e| OutputError::Plot(p.clone(), e))?,
        ),
        None => None,
    };

    // Both destinations must be writable before either is written.
    csvio::target_dir(&opts.output).map_err(OutputError::Write)?;
    for p in [&opts.plot, &opts.band, &opts.covariance]
        .into_iter()
        .flatten()
    {
        csvio::target_dir(p).map_err(OutputError::Write)?;
    }
    csvio::write_string_atomic(&opts.output, &(json + "\n")).map_err(OutputError::Write)?;
    let mut files = vec![opts.output.clone()];
    if let (Some(p), Some(svg)) = (&opts.plot, svg) {
        csvio::write_string_atomic(p, &svg).map_err(OutputError::Write)?;
        files.push(p.clone());
    }
    if let Some(p) = &opts.band {
        band_file::write_csv(p, &input_name, &bands).map_err(OutputError::Write)?;
        files.push(p.clone());
    }
    if let (Some(p), Some(text)) = (&opts.covariance, cov_json) {
        csvio::write_string_atomic(p, &text).map_err(OutputError::Write)?;
        files.push(p.clone());
    }
    Ok(FitCmdReport {
        model: opts.model.clone(),
        kind: spec.kind(),
        n_params: model.n_params(),
        data: opts.data.clone(),
        columns: (input_name, output_name),
        samples: loaded.iter().map(|l| l.y.len()).collect(),
        period,
        report,
        files,
    })
}

/// Per record, one row: measured and fitted output over the input (the
/// loop), over the sample index, and the residual over the sample index.
/// The measured trace is a thin line under the fitted one, so neither
/// hides the other.
fn figure(
    opts: &FitCmdOptions,
    input: &str,
    output: &str,
    records: &[Loaded],
    fits: &[Vec<f64>],
) -> Result<String, PlotError> {
    let mut panels = Vec::new();
    for ((l, y_fit), path) in records.iter().zip(fits).zip(&opts.data) {
        let (x, y) = (&l.x, &l.y);
        let title = format!("{} fitted to {}", file_name(&opts.model), file_name(path));
        // plotters labels ticks with a fixed format: keep the numbers on
        // the axes short by scaling the sample index and the residual by a
        // power of ten named in the axis label.
        let (index_scale, index_label) =
            plot::power_of_ten(x.len().saturating_sub(1) as f64, "sample");
        let index: Vec<f64> = (0..x.len()).map(|i| i as f64 / index_scale).collect();
        let residual: Vec<f64> = y_fit.iter().zip(y).map(|(f, m)| f - m).collect();
        let largest = residual.iter().fold(0.0_f64, |a, r| a.max(r.abs()));
        let (res_scale, res_label) = plot::power_of_ten(largest, &format!("{output} residual"));
        let residual: Vec<f64> = residual.iter().map(|r| r / res_scale).collect();

        let mut loop_panel = Panel::new(&title, input, output);
        loop_panel
            .series
            .push(Series::line("measured", pairs(x, y), 7));
        loop_panel
            .series
            .push(Series::line("fitted", pairs(x, y_fit), 1).with_style(Style::ThickLine));

        let mut time_panel = Panel::new(&format!("{output} over sample"), &index_label, output);
        time_panel
            .series
            .push(Series::line("measured", pairs(&index, y), 7));
        time_panel
            .series
            .push(Series::line("fitted", pairs(&index, y_fit), 1).with_style(Style::ThickLine));

        let mut res_panel = Panel::new("residual (fitted - measured)", &index_label, &res_label);
        res_panel
            .series
            .push(Series::line("", pairs(&index, &residual), 0));
        panels.extend([loop_panel, time_panel, res_panel]);
    }
    let rows = records.len().max(1);
    plot::render(&panels, rows, 3, (1500, 480 * rows as u32))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_is_the_default_of_the_starts() {
        assert_eq!(SPREAD, MultiStart::default().spread);
    }
}
