//! `hysteron`: the command-line program (see `hysteron --help`).
//!
//! * `hysteron paper [--out DIR]`: runs the paper's experiments, writes a
//!   CSV per experiment and the figures (see [`hysteron_cli::paper`]);
//! * `hysteron simulate --model SPEC.json --input IN.csv [--column x]
//!   --output OUT.csv [--plot LOOP.svg] [--dt SECONDS | --time-column t]`:
//!   runs a model spec over one column of a CSV file (see
//!   [`hysteron_cli::simulate`]); `--dt` or a uniformly spaced time column sets
//!   the sample period of the spec's rate-dependent nodes, which otherwise
//!   is the spec's own and must agree with a column named `t` or `time`
//!   (see [`hysteron_cli::period`]);
//! * `hysteron sensitivity --model SPEC.json --input IN.csv [--column x]
//!   --params a,b --output OUT.csv [--dt SECONDS | --time-column t]`: runs a
//!   model spec over one column of a CSV file and writes the output with
//!   its derivatives `dy/d<param>` by forward-mode automatic
//!   differentiation (see [`hysteron_cli::sensitivity`]);
//! * `hysteron fit --model SPEC.json --data DATA.csv [--input-column x]
//!   [--output-column y] --free a,b,c --output FITTED.json [--plot FIT.svg]
//!   [--dt SECONDS | --time-column t]`:
//!   fits parameters of a model spec to a record (see
//!   [`hysteron_cli::fit_cmd`]);
//! * `hysteron validate --model SPEC.json --data A.csv [--data B.csv ...]
//!   [--input-column x] [--output-column F] [--lowpass HZ] [--time-column t
//!   | --dt SECONDS] [--skip SECONDS] [--plot DIR] [--csv OUT.csv]`: scores
//!   a model spec against measured records (RMS, max |error|, NRMSE; see
//!   [`hysteron_cli::validate`]);
//! * `hysteron analyze --model SPEC.json --amplitudes A1,A2,...
//!   [--samples-per-period N] [--settle-periods P] [--steady-tol TOL]
//!   [--dt SECONDS] [--precision DIGITS] [--output OUT.csv]`: the describing function and the
//!   work per loop of a model spec driven by sines (see
//!   [`hysteron_cli::analyze`]);
//! * `hysteron identify-paper --loop LOOP.csv --chirp CHIRP.csv --output
//!   FITTED.json [--plot DIR]`: the paper's two-stage identification and
//!   a joint refinement (see [`hysteron_cli::identify_paper`]).
//!
//! * `hysteron export-fmu --model SPEC.json --output MODEL.fmu [--name
//!   NAME] [--library libhysteron_c.so]`: the spec as an FMI 2.0
//!   co-simulation FMU (see [`hysteron_cli::export_fmu`]).
//!
//! * `hysteron compare --candidates CANDIDATES.json --train DATA.csv ...
//!   --validate DATA.csv ... --work-dir DIR [--lowpass HZ] [--csv OUT.csv]
//!   [--plot OUT.svg]`: fits candidate structures, scores them on held-out
//!   records and ranks them (see [`hysteron_cli::compare`]).
//!
//! * `hysteron operators [--figures DIR]`: lists every operator a spec can
//!   name, with its equation and parameters (see
//!   [`hysteron_cli::models::spec::reference`]), and draws each one's loop
//!   (see [`hysteron_cli::reference_figures`]).
//!
//! * `hysteron bench [--samples N] [--runs R] [--kernel NAME]`: times the
//!   the performance kernels (see [`hysteron_cli::bench`]).
//!
//! Exit codes: 0 on success (and for `--help`, `--version`); 1 for every
//! error, bad input of any kind: a job's errors are one line on stderr
//! (`error: ...`), errors in the arguments themselves are clap's message
//! (also `error: ...`, with a usage hint), and numeric options say what
//! they need (`--dt` must be positive and finite, `--patience` at least 1;
//! negative numbers are read as values and refused, see
//! [`hysteron_cli::args`]); 3 for a fit that ran but did not converge (its
//! report says so and its result is written).

use clap::{Parser, Subcommand, ValueEnum};
use hysteron_cli::identify::{Jacobian, MultiStart};
use hysteron_cli::models::describing::SineOptions;
use hysteron_cli::{
    analyze, args, bench, compare, csvio, export_fmu, fit_cmd, fitting, identify_paper, paper,
    period, sensitivity, simulate, validate,
};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Debug, Parser)]
#[command(
    name = "hysteron",
    version,
    about = "Hysteresis operators: the paper's experiments, and model specs run over CSV data"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// The columns `validate` and `compare` score: the input, and the measured
/// output.
#[derive(Debug, clap::Args)]
struct ScoredColumns {
    /// The input column of every record.
    #[arg(long, value_name = "NAME", default_value = "x")]
    input_column: String,
    /// The measured output column of every record.
    #[arg(long, value_name = "NAME", default_value = "F")]
    output_column: String,
}

/// `--dt` or `--time-column`, the sample period of the rate-dependent nodes,
/// as `simulate` and `fit` take it.
#[derive(Debug, clap::Args)]
struct SamplePeriodArgs {
    // The help lists the registry's rate-dependent kinds.
    #[arg(
        long,
        value_name = "SECONDS",
        conflicts_with = "time_column",
        value_parser = args::positive_f64,
        allow_hyphen_values = true,
        help = period::dt_help()
    )]
    dt: Option<f64>,
    #[arg(long, value_name = "NAME", help = period::TIME_COLUMN_HELP)]
    time_column: Option<String>,
}

impl SamplePeriodArgs {
    fn source(self) -> period::DtSource {
        period::DtSource::from_options(self.dt, self.time_column)
    }
}

/// `fit --jacobian`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum JacobianArg {
    /// Forward-mode derivatives.
    Exact,
    /// Central finite differences.
    Fd,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run the experiments of Ruderman & Bertram (2015): one CSV per
    /// experiment (t,x,F,z,slider,friction,h) and the figures loops.svg,
    /// chirp.svg and stiffness.svg; prints a summary.
    Paper {
        /// Output directory (created if missing).
        #[arg(long, value_name = "DIR", default_value = "out")]
        out: PathBuf,
    },
    /// Run a model spec (JSON) over one column of a CSV file (with a
    /// header); the output holds all input columns plus `y`.
    Simulate {
        /// The model spec (JSON, see hysteron::models::Spec).
        #[arg(long, value_name = "SPEC.json")]
        model: PathBuf,
        /// The input CSV file, with a header row of distinct column names
        /// (blank lines only at the end of the file).
        #[arg(long, value_name = "IN.csv")]
        input: PathBuf,
        /// The input column.
        #[arg(long, value_name = "NAME", default_value = "x")]
        column: String,
        /// The output CSV file (written atomically; may not be the input).
        #[arg(long, value_name = "OUT.csv")]
        output: PathBuf,
        /// Also draw the output over the input column as an SVG figure.
        #[arg(long, value_name = "LOOP.svg")]
        plot: Option<PathBuf>,
        /// The name of the output column written (an error if the input
        /// already has a column of that name).
        #[arg(long, value_name = "NAME", default_value = "y")]
        output_column: String,
        #[command(flatten)]
        period: SamplePeriodArgs,
    },
    /// Run a model spec (JSON) over one column of a CSV file (with a
    /// header) and compute the derivatives of its output with respect to
    /// chosen parameters, ∂y_k/∂p, by forward-mode automatic
    /// differentiation (dual numbers, no step size to choose; at a
    /// kink, the derivative of the branch the model takes). The output
    /// holds all input columns, `y`, then one column `dy/d<path>` per
    /// parameter (e.g. dy/dleft.mms.f_c), in the order given.
    Sensitivity {
        /// The model spec (JSON, see hysteron::models::Spec); the model
        /// runs from its initial state.
        #[arg(long, value_name = "SPEC.json")]
        model: PathBuf,
        /// The input CSV file, with a header row of distinct column names
        /// (blank lines only at the end of the file; every value of the
        /// input column a finite number).
        #[arg(long, value_name = "IN.csv")]
        input: PathBuf,
        /// The input column.
        #[arg(long, value_name = "NAME", default_value = "x")]
        column: String,
        /// The parameters, comma-separated: full names as the model lists
        /// them (left.mms.f_c) or unique suffixes (f_c), each at most once;
        /// the columns are named by the full names.
        #[arg(long, value_name = "NAMES", value_delimiter = ',', required = true)]
        params: Vec<String>,
        /// The output CSV file (written atomically; may not be the input).
        #[arg(long, value_name = "OUT.csv")]
        output: PathBuf,
        /// The name of the output column written (the derivative columns
        /// are then `d<NAME>/d<path>`; an error if the input already has a
        /// column of one of these names).
        #[arg(long, value_name = "NAME", default_value = "y")]
        output_column: String,
        #[command(flatten)]
        period: SamplePeriodArgs,
    },
    /// Fit parameters of a model spec (JSON) to one record or several
    /// (input and measured output columns of CSV files) with
    /// Levenberg-Marquardt, starting from the spec's values; prints a
    /// report (per record too) and writes the fitted spec. Exit code 3 when
    /// the fit ran but did not converge.
    Fit {
        /// The model spec (JSON); its parameters are the starting values.
        #[arg(long, value_name = "SPEC.json")]
        model: PathBuf,
        /// A record: a CSV file (or .csv.gz) with a header row of distinct
        /// column names (blank lines only at the end of the file). Repeat
        /// for several records: one parameter set is fitted to all, each
        /// record simulated from the model's initial state.
        #[arg(long, value_name = "DATA.csv", required = true)]
        data: Vec<PathBuf>,
        /// The input column of the record.
        #[arg(long, value_name = "NAME", default_value = "x")]
        input_column: String,
        /// The measured output column of the record.
        #[arg(long, value_name = "NAME", default_value = "y")]
        output_column: String,
        /// Parameters to fit, comma-separated: full names as the model
        /// lists them (left.mms.f_c) or unique suffixes (f_c).
        #[arg(long, value_name = "NAMES", value_delimiter = ',')]
        free: Vec<String>,
        /// Parameters fitted separately for each record, comma-separated
        /// (an initial state or preload, e.g. f0): reported per record; the
        /// fitted spec keeps their starting values.
        #[arg(long, value_name = "NAMES", value_delimiter = ',')]
        own: Vec<String>,
        /// Seconds at the start of each record that the model runs but the
        /// residual does not count (warm-up from the initial state); needs
        /// --dt or --time-column.
        #[arg(long, value_name = "SECONDS", allow_hyphen_values = true)]
        skip: Option<f64>,
        /// Hard bound on the work: at most N model runs over the records in
        /// the search (trial steps and Jacobian columns alike; the report
        /// at the end adds 2·free + 1). The fit then ends at its best point,
        /// not converged (exit code 3).
        #[arg(long, value_name = "N", value_parser = args::at_least_1, allow_negative_numbers = true)]
        max_evaluations: Option<usize>,
        /// Wall-time limit of the search in seconds: no new model run starts
        /// after it (the Jacobian under way finishes). The fit then ends at
        /// its best point, not converged (exit code 3).
        #[arg(long, value_name = "SECONDS", value_parser = args::positive_f64, allow_hyphen_values = true)]
        max_seconds: Option<f64>,
        /// Where to write the fitted spec (JSON, written atomically; may
        /// not be the model or data file).
        #[arg(long, value_name = "FITTED.json")]
        output: PathBuf,
        /// Also draw measured and fitted output (over the input and over
        /// the sample index) and the residual as an SVG figure.
        #[arg(long, value_name = "FIT.svg")]
        plot: Option<PathBuf>,
        /// Levenberg-Marquardt's patience: at most PATIENCE·(free + 1) trial
        /// steps; each accepted step also runs 2·free simulations for its
        /// Jacobian, so at most PATIENCE·(free + 1)·(2·free + 1) model runs
        /// (at least 1; for a hard bound use --max-evaluations or
        /// --max-seconds).
        #[arg(long, value_name = "N", default_value_t = 200, value_parser = args::at_least_1, allow_negative_numbers = true)]
        patience: usize,
        /// How the Jacobian is computed: `exact` (forward-mode derivatives
        /// through the model over dual numbers, one simulation per 8
        /// parameters; see the guide's docs/derivatives.md) or `fd` (central finite
        /// differences, two simulations per parameter).
        #[arg(long, value_enum, default_value_t = JacobianArg::Exact)]
        jacobian: JacobianArg,
        /// Fit from N starting points: the spec's own and N − 1 from a Latin
        /// hypercube around it (see --spread), in parallel; the best is
        /// kept and the report says how many starts reached its cost
        /// (within 1 %).
        #[arg(long, value_name = "N", default_value_t = 1, value_parser = args::at_least_1, allow_negative_numbers = true)]
        starts: usize,
        /// Half-width of the hypercube in the fit's internal parameters: a
        /// positive parameter starts within a factor e^S of its value, one
        /// in [0, 1] within ±S in its logit, an unbounded one within
        /// ±S·max(|p|, 1). Default ln 4.
        #[arg(long, value_name = "S", default_value_t = 4f64.ln(), value_parser = args::positive_f64, allow_hyphen_values = true)]
        spread: f64,
        /// Seed of the hypercube (the same seed, the same starts).
        #[arg(long, value_name = "K", default_value_t = 0)]
        seed: u64,
        /// Do not draw the progress line (it is only drawn when stderr is
        /// a terminal anyway).
        #[arg(long)]
        no_progress: bool,
        #[command(flatten)]
        period: SamplePeriodArgs,
    },
    /// Score a model spec (JSON) against measured records: simulate it over
    /// each record's input column (a fresh model per record, from its
    /// initial state) and print one table row per record plus a mean row:
    /// | record | samples | RMS | max |err| | NRMSE | low-passed NRMSE |.
    /// RMS and max are of F_model − F_meas over the scored samples;
    /// NRMSE = RMS(F_model − F_meas) / RMS(F_meas), where RMS is about
    /// zero (√(Σ F²/n)), not the standard deviation. The mean row averages
    /// each figure over the records (unweighted) and sums the samples.
    Validate {
        /// The model spec (JSON, see hysteron::models::Spec).
        #[arg(long, value_name = "SPEC.json")]
        model: PathBuf,
        /// A record: a CSV file with a header row of distinct column names
        /// (repeat for several records; every record needs the input,
        /// output and time columns, matched by name).
        #[arg(long, value_name = "DATA.csv", required = true)]
        data: Vec<PathBuf>,
        #[command(flatten)]
        columns: ScoredColumns,
        /// Also score both signals after a 4th-order Butterworth low-pass
        /// at HZ run forward and backward (zero phase; the whole record is
        /// filtered, then scored): the "low-passed NRMSE" column. Needs
        /// --time-column or --dt; HZ must be below Nyquist (half the
        /// sample rate).
        #[arg(long, value_name = "HZ", value_parser = args::positive_f64, allow_hyphen_values = true)]
        lowpass: Option<f64>,
        // Also the low-pass's sample rate and the length of --skip; the
        // help lists the registry's rate-dependent kinds.
        #[arg(
            long,
            value_name = "SECONDS",
            conflicts_with = "time_column",
            value_parser = args::positive_f64,
            allow_hyphen_values = true,
            help = period::dt_help() + "; also the low-pass's sample rate and the length of --skip"
        )]
        dt: Option<f64>,
        #[arg(long, value_name = "NAME", help = period::TIME_COLUMN_HELP)]
        time_column: Option<String>,
        /// Simulate but do not score the first SECONDS of each record
        /// (the samples i with i·dt < SECONDS; a warm-up). Needs
        /// --time-column or --dt; a record not longer is an error.
        #[arg(long, value_name = "SECONDS", value_parser = args::non_negative_f64, allow_hyphen_values = true)]
        skip: Option<f64>,
        /// Also write DIR/STEM.svg per record, STEM its file stem (DIR created if
        /// missing): the loop (output over input) and the output over
        /// time, the measurement as a thin sky-blue line (low-passed when
        /// --lowpass is given) under the model as a thick vermillion line.
        #[arg(long, value_name = "DIR")]
        plot: Option<PathBuf>,
        /// Also write the table as CSV (one row per record, no mean row;
        /// columns record,samples,rms,max_abs_err,nrmse and
        /// lowpassed_nrmse with --lowpass; written atomically, may not be
        /// an input).
        #[arg(long, value_name = "OUT.csv")]
        csv: Option<PathBuf>,
    },
    /// Drive a model spec (JSON) by sines x = A sin θ, one per amplitude,
    /// until its output is periodic, and print per amplitude the describing
    /// function (first-harmonic gain |N| and phase in degrees, negative =
    /// lag), the energy dissipated per loop (the loop's area |∮ y dx|,
    /// trapezoid rule: > 0 for every hysteresis loop, the usual
    /// counterclockwise one of a lagging output such as a PI bank's as well
    /// as a clockwise friction loop) and the signed work ∮ y dx (< 0 for a
    /// counterclockwise loop, > 0 for a clockwise one).
    Analyze {
        /// The model spec (JSON, see hysteron::models::Spec).
        #[arg(long, value_name = "SPEC.json")]
        model: PathBuf,
        /// Amplitudes, comma-separated (each finite and > 0).
        #[arg(
            long,
            value_name = "A1,A2,...",
            value_delimiter = ',',
            required = true,
            allow_hyphen_values = true
        )]
        amplitudes: Vec<f64>,
        /// Samples per period (a multiple of 4, at least 8).
        #[arg(long, value_name = "N", default_value_t = 1024, value_parser = args::samples_per_period, allow_negative_numbers = true)]
        samples_per_period: usize,
        /// Periods run before the analysed one (at least 2: the last is
        /// compared with the one before).
        #[arg(long, value_name = "P", default_value_t = 20, value_parser = args::settle_periods, allow_negative_numbers = true)]
        settle_periods: usize,
        /// Largest accepted change of the first harmonic over the last
        /// period, relative to max|y|.
        #[arg(
            long,
            value_name = "TOL",
            default_value_t = 1e-9,
            allow_negative_numbers = true
        )]
        steady_tol: f64,
        // The help lists the registry's rate-dependent kinds.
        #[arg(
            long,
            value_name = "SECONDS",
            value_parser = args::positive_f64,
            allow_hyphen_values = true,
            help = period::dt_help()
        )]
        dt: Option<f64>,
        /// Significant digits of the printed table (1 to 17; --output
        /// writes every digit).
        #[arg(long, value_name = "DIGITS", default_value_t = analyze::PRECISION, value_parser = args::precision)]
        precision: usize,
        /// Also write the table as CSV (atomically; may not be the model).
        #[arg(long, value_name = "OUT.csv")]
        output: Option<PathBuf>,
    },
    /// The two-stage identification of Ruderman & Bertram (2015): the
    /// spring's shape from a major loop (knots through points of its last
    /// increasing branch), then the bedstop (backlash, F_c, K) from a
    /// down-chirp; then a joint refinement of all parameters on both
    /// records (stage 3, from the stage-1 spring and the backlash and F_c
    /// of the loop's plateau). Writes the identified model as a
    /// `transmission` spec (JSON) and prints the stage reports. Exit code 3
    /// when a stage did not converge.
    IdentifyPaper {
        /// The major-loop record (CSV with a header row): one sine, whose
        /// whole record stage 1 fits and whose last increasing branch gives
        /// the knots, e.g. the `paper` job's sine-5hz-I.csv (its sines.csv
        /// holds three sines of different frequencies in a row: cut one out
        /// first).
        #[arg(long = "loop", value_name = "LOOP.csv")]
        loop_record: PathBuf,
        /// The down-chirp record (CSV with a header row; e.g. the `paper`
        /// job's chirp.csv).
        #[arg(long, value_name = "CHIRP.csv")]
        chirp: PathBuf,
        /// The input column of both records.
        #[arg(long, value_name = "NAME", default_value = "x")]
        input_column: String,
        /// The force column of both records.
        #[arg(long, value_name = "NAME", default_value = "F")]
        output_column: String,
        /// Starting values: a `transmission` spec (default: the
        /// illustrative defaults of the `paper` job).
        #[arg(long, value_name = "START.json")]
        start: Option<PathBuf>,
        /// Where to write the identified model: a `transmission` spec
        /// (JSON, written atomically).
        #[arg(long, value_name = "FITTED.json")]
        output: PathBuf,
        /// Also write the figures loop.svg and chirp.svg into DIR (created
        /// if missing).
        #[arg(long, value_name = "DIR")]
        plot: Option<PathBuf>,
        /// Points picked on the loop's increasing branch (the knots of the
        /// stiffness map; 2 to 999).
        #[arg(long, value_name = "N", default_value_t = 12, value_parser = args::points, allow_negative_numbers = true)]
        points: usize,
        /// Levenberg-Marquardt's patience in each stage: at most
        /// PATIENCE·(free + 1) trial steps, each accepted one followed by a
        /// Jacobian of 2·free runs (at least 1).
        #[arg(long, value_name = "N", default_value_t = 200, value_parser = args::at_least_1, allow_negative_numbers = true)]
        patience: usize,
        /// Do not draw the progress line (it is only drawn when stderr is
        /// a terminal anyway).
        #[arg(long)]
        no_progress: bool,
    },
    /// Write a model spec (JSON) as an FMI 2.0 co-simulation FMU: input x,
    /// output y, every parameter a tunable Real named by its path, for
    /// Simulink, OpenModelica, Dymola, FMPy and other FMI hosts (Linux
    /// x86-64 binary).
    ExportFmu {
        /// The model spec (JSON, see hysteron::models::Spec).
        #[arg(long, value_name = "SPEC.json")]
        model: PathBuf,
        /// The FMU to write (a zip archive, written atomically).
        #[arg(long, value_name = "MODEL.fmu")]
        output: PathBuf,
        /// The model's name and identifier (letters, digits and `_`;
        /// default: the output's file name).
        #[arg(long, value_name = "NAME")]
        name: Option<String>,
        /// The FMU binary (default: libhysteron_c.so next to this program,
        /// built by `cargo build --release`).
        #[arg(long, value_name = "libhysteron_c.so")]
        library: Option<PathBuf>,
    },
    /// Compare candidate structures: fit each (a spec and the parameters
    /// to free, listed in a JSON file) on the training records as `fit`
    /// does, score it on the held-out records as `validate` does, and
    /// rank the candidates by their held-out mean NRMSE (low-passed with
    /// --lowpass). Prints one table: k, training cost, AIC and BIC on
    /// training, held-out NRMSE mean and worst (full band and low-passed),
    /// the rank, and a sign test against the next rank. A candidate that
    /// fails is reported in its row; the others go on.
    Compare {
        /// The candidates: {"candidates": [{"name": "...", "model":
        /// "SPEC.json", "free": ["f_c", ...], "own": [...]}]}, model paths
        /// relative to this file; at least two.
        #[arg(long, value_name = "CANDIDATES.json")]
        candidates: PathBuf,
        /// A training record (CSV or .csv.gz); repeat for several.
        #[arg(long, value_name = "DATA.csv", required = true)]
        train: Vec<PathBuf>,
        /// A held-out record; repeat for several (or --cross-validate).
        #[arg(
            long,
            value_name = "DATA.csv",
            required_unless_present = "cross_validate"
        )]
        validate: Vec<PathBuf>,
        /// Instead of --validate: K-fold cross-validation over the --train
        /// records (record i held out in fold i mod K, scored by the fit on
        /// the other folds; the training figures come from the fit on all).
        #[arg(long, value_name = "K", value_parser = args::at_least_1, allow_negative_numbers = true)]
        cross_validate: Option<usize>,
        #[command(flatten)]
        columns: ScoredColumns,
        /// Also score after `validate`'s zero-phase low-pass at HZ, and
        /// rank by it. Needs --time-column or --dt.
        #[arg(long, value_name = "HZ", value_parser = args::positive_f64, allow_hyphen_values = true)]
        lowpass: Option<f64>,
        #[command(flatten)]
        period: SamplePeriodArgs,
        /// Simulate but do not score the first SECONDS of each record.
        #[arg(long, value_name = "SECONDS", value_parser = args::non_negative_f64, allow_hyphen_values = true)]
        skip: Option<f64>,
        /// Fit each candidate from N starting points (as `fit --starts`).
        #[arg(long, value_name = "N", default_value_t = 1, value_parser = args::at_least_1, allow_negative_numbers = true)]
        starts: usize,
        /// Seed of the starting points.
        #[arg(long, value_name = "K", default_value_t = 0)]
        seed: u64,
        /// Wall-time limit of each candidate's search, in seconds.
        #[arg(long, value_name = "SECONDS", value_parser = args::positive_f64, allow_hyphen_values = true)]
        max_seconds: Option<f64>,
        /// Where the fitted specs go, one NAME.json per candidate (created
        /// if missing).
        #[arg(long, value_name = "DIR")]
        work_dir: PathBuf,
        /// Also write the table as CSV (written atomically).
        #[arg(long, value_name = "OUT.csv")]
        csv: Option<PathBuf>,
        /// Also draw each candidate's held-out NRMSE per record (SVG).
        #[arg(long, value_name = "OUT.svg")]
        plot: Option<PathBuf>,
        /// Do not draw the progress bar (it is only drawn when stderr is a
        /// terminal anyway).
        #[arg(long)]
        no_progress: bool,
    },
    /// List every operator a spec can name: its spec type, equation, and
    /// each parameter with its domain, default and documentation; then the
    /// combinators.
    Operators {
        /// Also draw each operator's and combinator's example spec over a
        /// decaying sine, one loop figure per `type`, into DIR/TYPE.svg
        /// (the guide's reference pages show them).
        #[arg(long, value_name = "DIR")]
        figures: Option<PathBuf>,
    },
    /// Time the operator kernels (play, 64-play PI, Bouc-Wen n = 1 and
    /// 1.5, MMS, the paper's model static and boxed from JSON, rayon
    /// batches on 1 and 2 threads) on the input
    /// x_i = 2.5 sin(2πi/2000) + 0.3 sin(2πi/97.3); prints one table row
    /// per kernel: | hysteron | kernel | runs | samples/s | ns/sample | min..max |.
    /// Build with --release.
    Bench {
        /// Samples of the kernel input per run (1 to 10^9).
        #[arg(long, value_name = "N", default_value_t = 10_000_000, value_parser = args::bench_samples, allow_negative_numbers = true)]
        samples: usize,
        /// Timed runs per kernel, after one untimed run (1 to 1000).
        #[arg(long, value_name = "R", default_value_t = 5, value_parser = args::bench_runs, allow_negative_numbers = true)]
        runs: usize,
        /// Only the kernels whose name contains this.
        #[arg(long, value_name = "NAME")]
        kernel: Option<String>,
    },
}

/// Prints a command's report on stdout, and gives the exit code of a fit
/// that ended not converged
/// ([`EXIT_NOT_CONVERGED`](fitting::EXIT_NOT_CONVERGED)), else `None`.
fn printed(report: impl std::fmt::Display, converged: bool) -> Option<ExitCode> {
    println!("{report}");
    (!converged).then(|| ExitCode::from(fitting::EXIT_NOT_CONVERGED))
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // clap's message (help and version on stdout, errors on stderr);
            // any error in the arguments is bad input: exit code 1, not
            // clap's 2.
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::FAILURE
            } else {
                ExitCode::SUCCESS
            };
        }
    };
    let result = match cli.command {
        Command::Paper { out } => paper::run(&paper::PaperOptions { out })
            .map(|report| printed(report, true))
            .map_err(|e| e.to_string()),
        Command::Fit {
            model,
            data,
            input_column,
            output_column,
            free,
            own,
            skip,
            max_evaluations,
            max_seconds,
            output,
            plot,
            patience,
            jacobian,
            starts,
            spread,
            seed,
            no_progress,
            period,
        } => fit_cmd::run(&fit_cmd::FitCmdOptions {
            model,
            data,
            input_column,
            output_column,
            free,
            own,
            skip,
            max_evaluations,
            max_seconds,
            output,
            plot,
            patience,
            jacobian: match jacobian {
                JacobianArg::Exact => Jacobian::Exact,
                JacobianArg::Fd => Jacobian::FiniteDifferences,
            },
            starts: MultiStart {
                starts,
                spread,
                seed,
            },
            progress: !no_progress,
            dt: period.source(),
        })
        .map(|report| printed(&report, report.converged()))
        .map_err(|e| e.to_string()),
        Command::IdentifyPaper {
            loop_record,
            chirp,
            input_column,
            output_column,
            start,
            output,
            plot,
            points,
            patience,
            no_progress,
        } => identify_paper::run(&identify_paper::IdentifyPaperOptions {
            loop_record,
            chirp,
            input_column,
            output_column,
            start,
            output,
            plot,
            points,
            patience,
            progress: !no_progress,
        })
        .map(|report| printed(&report, report.converged()))
        .map_err(|e| e.to_string()),
        Command::Analyze {
            model,
            amplitudes,
            samples_per_period,
            settle_periods,
            steady_tol,
            dt,
            precision,
            output,
        } => analyze::run(&analyze::AnalyzeOptions {
            model,
            amplitudes,
            sine: SineOptions {
                samples_per_period,
                settle_periods,
                steady_tol,
                ..SineOptions::default()
            },
            dt,
            precision,
            output,
        })
        .map(|report| printed(report, true))
        .map_err(|e| e.to_string()),
        Command::Validate {
            model,
            data,
            columns,
            lowpass,
            dt,
            time_column,
            skip,
            plot,
            csv,
        } => validate::run(&validate::ValidateOptions {
            model,
            data,
            input_column: columns.input_column,
            output_column: columns.output_column,
            lowpass,
            dt: period::DtSource::from_options(dt, time_column),
            skip,
            plot,
            csv,
        })
        .map(|report| printed(report, true))
        .map_err(|e| e.to_string()),
        Command::Simulate {
            model,
            input,
            column,
            output,
            plot,
            output_column,
            period,
        } => simulate::run(&simulate::SimulateOptions {
            model,
            input,
            column,
            output,
            plot,
            output_column,
            dt: period.source(),
        })
        .map(|report| printed(report, true))
        .map_err(|e| e.to_string()),
        Command::Sensitivity {
            model,
            input,
            column,
            params,
            output,
            output_column,
            period,
        } => sensitivity::run(&sensitivity::SensitivityOptions {
            model,
            input,
            column,
            params,
            output,
            output_column,
            dt: period.source(),
        })
        .map(|report| printed(report, true))
        .map_err(|e| e.to_string()),
        Command::ExportFmu {
            model,
            output,
            name,
            library,
        } => export_fmu::run(&export_fmu::ExportFmuOptions {
            model,
            output,
            name,
            library,
        })
        .map(|report| printed(report, true))
        .map_err(|e| e.to_string()),
        Command::Compare {
            candidates,
            train,
            validate,
            cross_validate,
            columns,
            lowpass,
            period,
            skip,
            starts,
            seed,
            max_seconds,
            work_dir,
            csv,
            plot,
            no_progress,
        } => compare::run(&compare::CompareOptions {
            candidates,
            train,
            validate,
            cross_validate,
            input_column: columns.input_column,
            output_column: columns.output_column,
            lowpass,
            skip,
            dt: period.source(),
            starts: MultiStart {
                starts,
                spread: 4f64.ln(),
                seed,
            },
            max_seconds,
            patience: 200,
            jacobian: Jacobian::Exact,
            work_dir,
            csv,
            plot,
            progress: !no_progress,
        })
        .map(|report| printed(report, true))
        .map_err(|e| e.to_string()),
        Command::Operators { figures } => {
            print!("{}", hysteron_cli::models::spec::reference::listing());
            match figures {
                None => Ok(None),
                Some(dir) => hysteron_cli::reference_figures::write_figures(&dir).map(|written| {
                    eprintln!("{} figures written to {}", written.len(), dir.display());
                    None
                }),
            }
        }
        Command::Bench {
            samples,
            runs,
            kernel,
        } => bench::run(&bench::BenchOptions {
            samples,
            runs,
            filter: kernel,
        })
        .map(|report| {
            print!("{report}");
            None
        }),
    };
    match result {
        Ok(code) => code.unwrap_or(ExitCode::SUCCESS),
        Err(e) => {
            eprintln!("error: {}", csvio::one_line(&e));
            ExitCode::FAILURE
        }
    }
}
