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
// its module); the variant's doc comment is the command's about text.
#[derive(Debug, Subcommand)]
enum Command {
    /// Run the experiments of Ruderman & Bertram (2015): one CSV per
    /// experiment (t,x,F,z,slider,friction,h) and the figures loops.svg,
    /// chirp.svg and stiffness.svg; prints a summary.
    Paper(paper::PaperOptions),
    /// Run a model spec (JSON) over one column of a CSV file (with a
    /// header); the output holds all input columns plus `y`.
    Simulate(simulate::SimulateOptions),
    /// Run a model spec (JSON) over one column of a CSV file (with a
    /// header) and compute the derivatives of its output with respect to
    /// chosen parameters, ∂y_k/∂p, by forward-mode automatic
    /// differentiation (dual numbers, no step size to choose; at a
    /// kink, the derivative of the branch the model takes). The output
    /// holds all input columns, `y`, then one column `dy/d<path>` per
    /// parameter (e.g. dy/dleft.mms.f_c), in the order given.
    Sensitivity(sensitivity::SensitivityOptions),
    /// Run a model spec (JSON) once per parameter set (rows of a CSV file
    /// whose header names parameters) over one column of a CSV file, all
    /// sets together (play, MMS and Bouc-Wen n = 1 leaves eight per vector
    /// instruction);
    /// writes the input column and one output column per set, set_1,
    /// set_2, … (NaN for a set that failed, which the report names with
    /// its error).
    Sweep(sweep::SweepOptions),
    /// Global sensitivity of a model spec (JSON): which parameters matter
    /// for a scalar statistic of its output over one column of a CSV file
    /// (the loop energy |∮ y dx|, the work, the peak |y|, the RMS or the
    /// mean of y). Each factor (--factor NAME=LOW:HIGH) is uniform within
    /// its bounds, the others keep the spec's values; prints the Sobol
    /// first-order index S_i (the share of the statistic's variance the
    /// factor explains alone) and total index S_Ti (with its
    /// interactions), from N (k + 2) runs on a scrambled Sobol sequence
    /// (Saltelli design and estimators).
    Sobol(sobol::SobolCmdOptions),
    /// Fit parameters of a model spec (JSON) to one record or several
    /// (input and measured output columns of CSV files) with
    /// Levenberg-Marquardt, starting from the spec's values; prints a
    /// report (per record too) and writes the fitted spec. Exit code 3 when
    /// the fit ran but did not converge.
    Fit(fit_cmd::FitCmdOptions),
    /// Score a model spec (JSON) against measured records: simulate it over
    /// each record's input column (a fresh model per record, from its
    /// initial state) and print one table row per record plus a mean row:
    /// | record | samples | RMS | max |err| | NRMSE | low-passed NRMSE |.
    /// RMS and max are of F_model − F_meas over the scored samples;
    /// NRMSE = RMS(F_model − F_meas) / RMS(F_meas), where RMS is about
    /// zero (√(Σ F²/n)), not the standard deviation. The mean row averages
    /// each figure over the records (unweighted) and sums the samples.
    Validate(validate::ValidateOptions),
    /// Drive a model spec (JSON) by sines x = A sin θ, one per amplitude,
    /// until its output is periodic, and print per amplitude the describing
    /// function (first-harmonic gain |N| and phase in degrees, negative =
    /// lag), the energy dissipated per loop (the loop's area |∮ y dx|,
    /// trapezoid rule: > 0 for every hysteresis loop, the usual
    /// counterclockwise one of a lagging output such as a PI bank's as well
    /// as a clockwise friction loop) and the signed work ∮ y dx (< 0 for a
    /// counterclockwise loop, > 0 for a clockwise one).
    Analyze(analyze::AnalyzeOptions),
    /// The two-stage identification of Ruderman & Bertram (2015): the
    /// spring's shape from a major loop (knots through points of its last
    /// increasing branch), then the bedstop (backlash, F_c, K) from a
    /// down-chirp; then a joint refinement of all parameters on both
    /// records (stage 3, from the stage-1 spring and the backlash and F_c
    /// of the loop's plateau). Writes the identified model as a
    /// `transmission` spec (JSON) and prints the stage reports. Exit code 3
    /// when a stage did not converge.
    IdentifyPaper(identify_paper::IdentifyPaperOptions),
    /// Write a model spec (JSON) as an FMI 2.0 co-simulation FMU: input x,
    /// output y, every parameter a tunable Real named by its path, for
    /// Simulink, OpenModelica, Dymola, FMPy and other FMI hosts (Linux
    /// x86-64 binary).
    ExportFmu(export_fmu::ExportFmuOptions),
    /// Write the compatibility information of the FMU export into a
    /// folder, in the FMI Cross-Check layout
    /// (`fmus/<2.0|3.0>/cs/<platform>/hysteron/<version>/<Model>/`): for
    /// the paper model and the Bouc-Wen benchmark, per FMI version, the
    /// FMU, `<Model>_in.csv`, `<Model>_ref.csv` (computed by the library),
    /// `<Model>_ref.opt` and a `ReadMe.md`.
    FmuCompat(fmu_compat::FmuCompatOptions),
    /// Compare candidate structures: fit each (a spec and the parameters
    /// to free, listed in a JSON file) on the training records as `fit`
    /// does, score it on the held-out records as `validate` does, and
    /// rank the candidates by their held-out mean NRMSE (low-passed with
    /// --lowpass). Prints one table: k, training cost, AIC and BIC on
    /// training, held-out NRMSE mean and worst (full band and low-passed),
    /// the rank, and a sign test against the next rank. A candidate that
    /// fails is reported in its row; the others go on.
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
    /// Time the operator kernels (play, 64-play PI, Bouc-Wen n = 1 and
    /// 1.5, MMS, BWBN and Jiles-Atherton, the paper's model static and
    /// boxed from JSON, rayon batches on 1 and 2 threads) on the input
    /// x_i = 2.5 sin(2πi/2000) + 0.3 sin(2πi/97.3); prints one table row
    /// per kernel: | hysteron | kernel | runs | samples/s | ns/sample | min..max |.
    /// Build with --release.
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
