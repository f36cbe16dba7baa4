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
//! * `hysteron sobol --model SPEC.json --input IN.csv [--column x]
//!   --factor NAME=LOW:HIGH ... [--statistic energy|work|peak|rms|mean]
//!   [--samples N] [--seed S] [--output OUT.csv]`: the Sobol first-order
//!   and total indices of a statistic of the output with respect to chosen
//!   parameters (see [`hysteron_cli::sobol`]);
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
//!   NAME] [--library libhysteron_c.so] [--fmi 2|3]`: the spec as an FMI
//!   2.0 (default) or 3.0 co-simulation FMU (see
//!   [`hysteron_cli::export_fmu`]).
//! * `hysteron fmu-compat OUT_DIR [--fmi 2|3] [--library
//!   libhysteron_c.so]`: the FMUs of the paper model and the Bouc-Wen
//!   benchmark with their compatibility information (input, reference,
//!   options, ReadMe; see [`hysteron_cli::fmu_compat`]).
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
//! * `hysteron bench [--samples N] [--runs R] [--kernel NAME]`: times
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

use clap::{Parser, Subcommand};
use hysteron_cli::{
    analyze, bench, compare, csvio, export_fmu, fit_cmd, fitting, fmu_compat, identify_paper,
    paper, sensitivity, simulate, sobol, sweep, validate,
};
use std::fmt;
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

// Each command's flags are its options struct's fields (clap `Args`, in
// its module), and that struct's doc comment is the command's about text.
#[derive(Debug, Subcommand)]
enum Command {
    Paper(paper::PaperOptions),
    Simulate(simulate::SimulateOptions),
    Sensitivity(sensitivity::SensitivityOptions),
    Sweep(sweep::SweepOptions),
    Sobol(sobol::SobolCmdOptions),
    Fit(fit_cmd::FitCmdOptions),
    Validate(validate::ValidateOptions),
    Analyze(analyze::AnalyzeOptions),
    IdentifyPaper(identify_paper::IdentifyPaperOptions),
    ExportFmu(export_fmu::ExportFmuOptions),
    FmuCompat(fmu_compat::FmuCompatOptions),
    Compare(compare::CompareOptions),
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
    Bench(bench::BenchOptions),
}

/// A command's outcome: its report printed on stdout, and the exit code of
/// a fit that ended not converged, as `converged` tells from the report
/// ([`EXIT_NOT_CONVERGED`](fitting::EXIT_NOT_CONVERGED)), else `None`; or
/// its error's message.
fn reported<R: fmt::Display, E: fmt::Display>(
    result: Result<R, E>,
    converged: fn(&R) -> bool,
) -> Result<Option<ExitCode>, String> {
    let report = result.map_err(|e| e.to_string())?;
    println!("{report}");
    Ok((!converged(&report)).then(|| ExitCode::from(fitting::EXIT_NOT_CONVERGED)))
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
        Command::Paper(opts) => reported(paper::run(&opts), |_| true),
        Command::Simulate(opts) => reported(simulate::run(&opts), |_| true),
        Command::Sensitivity(opts) => reported(sensitivity::run(&opts), |_| true),
        Command::Sweep(opts) => reported(sweep::run(&opts), |_| true),
        Command::Sobol(opts) => reported(sobol::run(&opts), |_| true),
        Command::Fit(opts) => reported(fit_cmd::run(&opts), fit_cmd::FitCmdReport::converged),
        Command::Validate(opts) => reported(validate::run(&opts), |_| true),
        Command::Analyze(opts) => reported(analyze::run(&opts), |_| true),
        Command::IdentifyPaper(opts) => reported(
            identify_paper::run(&opts),
            identify_paper::IdentifyPaperReport::converged,
        ),
        Command::ExportFmu(opts) => reported(export_fmu::run(&opts), |_| true),
        Command::FmuCompat(opts) => reported(fmu_compat::run(&opts), |_| true),
        Command::Compare(opts) => reported(compare::run(&opts), |_| true),
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
        Command::Bench(opts) => bench::run(&opts).map(|report| {
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
