//! The `fit` job: fits chosen parameters of a model spec (JSON, see
//! [`Spec`]) to a record (two columns of a CSV file, input and measured
//! output) with Levenberg-Marquardt ([`fit_with_progress`]), prints a
//! report and writes the fitted spec, optionally with a figure of measured
//! and fitted output.
//!
//! * The free parameters are named as the built model's
//!   [`param_names`](crate::Operator::param_names) (`left.mms.f_c`) or by a
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
//! Nothing is written unless everything before succeeded: model and data
//! are read and checked, the fit run, the fitted spec built and simulated
//! over the record, and the figure drawn in memory first; then the files are
//! written atomically. No output may be the data or the model file, nor
//! the other output (compared after canonicalization).
//!
//! # Exit status
//!
//! A fit that ran to the end but did not converge (the evaluation budget,
//! `--patience`, ran out, or the solver stopped on a numerical problem) is
//! not an error: the report is printed with a `NOT CONVERGED` line and the
//! last iterate is written like a converged fit, and the program exits with
//! code [`EXIT_NOT_CONVERGED`] (3) so that scripts can tell. A converged
//! fit exits with 0; errors (nothing written) with 1.

use crate::csvio::{self, CsvIoError};
use crate::identify::{
    fit_with_progress, free_by_names, FitError, FitOptions, FitReport, FitStatus, Progress,
};
use crate::models::{Spec, SpecError};
use crate::plot::{self, Panel, PlotError, Series, Style};
use crate::simulate::DtSource;
use crate::Operator;
use indicatif::{ProgressBar, ProgressStyle};
use std::fmt;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Exit code of a fit that ran but did not converge (see the module docs).
pub const EXIT_NOT_CONVERGED: u8 = 3;

/// Options of the fit job.
#[derive(Debug, Clone, PartialEq)]
pub struct FitCmdOptions {
    /// The model spec (JSON); its parameters are the starting values.
    pub model: PathBuf,
    /// The record: a CSV file with a header row.
    pub data: PathBuf,
    /// The input column of `data`.
    pub input_column: String,
    /// The measured output column of `data`.
    pub output_column: String,
    /// Names of the parameters to fit (full names or unique suffixes).
    pub free: Vec<String>,
    /// Where to write the fitted spec (JSON).
    pub output: PathBuf,
    /// Optional SVG figure of measured and fitted output.
    pub plot: Option<PathBuf>,
    /// Evaluation budget per free parameter and iteration
    /// ([`FitOptions::patience`]).
    pub patience: usize,
    /// Draw the progress display (only ever on a terminal).
    pub progress: bool,
    /// Where the sample period of the rate-dependent nodes comes from (a
    /// time column is read from `data`); the fitted spec keeps it.
    pub dt: DtSource,
}

/// An error of the fit job (one-line message naming file, row and column
/// where relevant).
#[derive(Debug)]
pub enum FitCmdError {
    /// An output path names an input file or the other output.
    SameFile {
        /// Which output (`output` or `plot`).
        what: &'static str,
        /// The output path.
        output: PathBuf,
        /// Which file it collides with (`data`, `model` or `output`).
        other_what: &'static str,
        /// That file.
        other: PathBuf,
    },
    /// `--input-column` and `--output-column` name the same column.
    SameColumn(String),
    /// The model spec could not be read, parsed or built.
    Model(PathBuf, SpecError),
    /// The data could not be read or is invalid.
    Data(CsvIoError),
    /// `--free` names no parameter.
    NoFree {
        /// The model spec.
        model: PathBuf,
        /// The model's parameter names.
        available: String,
    },
    /// A `--free` name is unknown or ambiguous.
    Free(PathBuf, FitError),
    /// A `--free` parameter that the spec cannot hold on its own (the
    /// slider's `limits.r0` or the spring's `z0` of a `transmission`
    /// spec, tied by `z0 = −slider0`).
    Tied {
        /// The model spec.
        model: PathBuf,
        /// The parameter's full name.
        name: String,
    },
    /// Two `--free` names give the same parameter.
    DuplicateFree {
        /// The model spec.
        model: PathBuf,
        /// The parameter's full name.
        name: String,
    },
    /// The model cannot be simulated over the record with the starting
    /// parameters.
    Start(Box<csvio::SampleFailure>),
    /// The fit could not run.
    Fit(FitError),
    /// The fitted parameters could not be written into the spec, or the
    /// fitted spec cannot be simulated over the record.
    Fitted(PathBuf, String),
    /// Writing an output failed.
    Write(CsvIoError),
    /// Drawing the figure failed.
    Plot(PathBuf, PlotError),
}

impl fmt::Display for FitCmdError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FitCmdError::SameFile {
                what,
                output,
                other_what,
                other,
            } => write!(
                f,
                "{what} `{}` is the same file as the {other_what} `{}`: refusing to overwrite it",
                output.display(),
                other.display()
            ),
            FitCmdError::SameColumn(c) => write!(
                f,
                "--input-column and --output-column both name the column `{c}`"
            ),
            FitCmdError::Model(p, e) => match e {
                // The I/O error already names the file; don't repeat it.
                SpecError::Io { message, .. } => {
                    write!(f, "model `{}`: {message}", p.display())
                }
                e => write!(f, "model `{}`: {e}", p.display()),
            },
            FitCmdError::Data(e) => write!(f, "data {e}"),
            FitCmdError::NoFree { model, available } => write!(
                f,
                "--free names no parameter of model `{}` (the model has: {available})",
                model.display()
            ),
            FitCmdError::Free(p, e) => write!(f, "--free: model `{}`: {e}", p.display()),
            FitCmdError::Tied { model, name } => write!(
                f,
                "--free: parameter `{name}` of model `{}` cannot be fitted on its own: \
                 a spring in a gap starts at rest, its z0 is -r0 of the gap (-slider0 in a \
                 `transmission` spec); keep both fixed",
                model.display()
            ),
            FitCmdError::DuplicateFree { model, name } => write!(
                f,
                "--free: parameter `{name}` of model `{}` is named twice",
                model.display()
            ),
            FitCmdError::Start(s) => {
                write!(
                    f,
                    "model `{}` fails at the starting parameters",
                    s.model.display()
                )?;
                s.fmt_location(f)
            }
            FitCmdError::Fit(e) => write!(f, "fit: {e}"),
            FitCmdError::Fitted(p, e) => {
                write!(f, "fitted parameters of model `{}`: {e}", p.display())
            }
            FitCmdError::Write(e) => write!(f, "output {e}"),
            FitCmdError::Plot(p, e) => write!(f, "plot `{}`: {e}", p.display()),
        }
    }
}

impl std::error::Error for FitCmdError {}

/// What the fit job did: the library's report plus where.
#[derive(Debug, Clone, PartialEq)]
pub struct FitCmdReport {
    /// The model spec.
    pub model: PathBuf,
    /// The root node of the spec (`"series"`).
    pub kind: &'static str,
    /// Number of model parameters.
    pub n_params: usize,
    /// The data file.
    pub data: PathBuf,
    /// Input and output column.
    pub columns: (String, String),
    /// Samples in the record.
    pub samples: usize,
    /// The fit.
    pub report: FitReport,
    /// Files written.
    pub files: Vec<PathBuf>,
}

impl FitCmdReport {
    /// Whether the fit converged (exit code 0, otherwise
    /// [`EXIT_NOT_CONVERGED`]).
    pub fn converged(&self) -> bool {
        self.report.status.converged()
    }
}

/// `v` with `sig` significant digits, fixed notation for moderate
/// magnitudes and scientific otherwise (like C's `%g`, trailing zeros
/// dropped).
pub fn fmt_g(v: f64, sig: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let sig = sig.max(1);
    let exp = v.abs().log10().floor() as i32;
    let trim = |s: String| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if (-4..sig as i32).contains(&exp) {
        let decimals = (sig as i32 - 1 - exp).max(0) as usize;
        trim(format!("{v:.decimals$}"))
    } else {
        let s = format!("{v:.*e}", sig - 1);
        match s.split_once('e') {
            Some((m, e)) => format!("{}e{e}", trim(m.to_string())),
            None => s,
        }
    }
}

/// A [`FitReport`] as text: a table of the free parameters (name, start,
/// value, standard error, 95 % confidence interval), then cost, RMS,
/// NRMSE, iterations, evaluations, wall time and status; a fit that did not
/// converge gets a `NOT CONVERGED` status and a line saying so. Ends with
/// a newline.
#[derive(Debug, Clone, Copy)]
pub struct ReportTable<'a>(pub &'a FitReport);

impl fmt::Display for ReportTable<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = self.0;
        let w = r
            .params
            .iter()
            .map(|p| p.name.len())
            .max()
            .unwrap_or(0)
            .max("parameter".len());
        writeln!(
            f,
            "{:<w$}  {:>13}  {:>13}  {:>10}  95% CI",
            "parameter", "start", "value", "std error"
        )?;
        for p in &r.params {
            let se = p.std_error.map_or("-".to_string(), |s| fmt_g(s, 3));
            let ci = p.ci95.map_or("-".to_string(), |(a, b)| {
                format!("[{}, {}]", fmt_g(a, 7), fmt_g(b, 7))
            });
            writeln!(
                f,
                "{:<w$}  {:>13}  {:>13}  {:>10}  {ci}",
                p.name,
                fmt_g(p.start, 7),
                fmt_g(p.value, 7),
                se
            )?;
        }
        writeln!(f, "cost         {:.6e}", r.cost)?;
        writeln!(f, "RMS          {:.6e}", r.rms)?;
        match r.nrmse {
            Some(v) => writeln!(f, "NRMSE        {v:.6e}")?,
            None => writeln!(f, "NRMSE        - (constant output)")?,
        }
        writeln!(f, "iterations   {}", r.iterations)?;
        writeln!(f, "evaluations  {}", r.evaluations)?;
        writeln!(f, "wall time    {:.3} s", r.wall_time.as_secs_f64())?;
        match &r.status {
            FitStatus::Converged(why) => writeln!(f, "status       converged ({why})"),
            FitStatus::NotConverged(why) | FitStatus::Failed(why) => {
                writeln!(f, "status       NOT CONVERGED: {why}")?;
                writeln!(
                    f,
                    "the fit did not converge: the parameters written are its last iterate \
                     (exit code {EXIT_NOT_CONVERGED})"
                )
            }
        }
    }
}

impl fmt::Display for FitCmdReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "fit of `{}` ({}, {} parameters, {} free) to `{}`: {} samples, {} -> {}",
            self.model.display(),
            self.kind,
            self.n_params,
            self.report.params.len(),
            self.data.display(),
            self.samples,
            self.columns.0,
            self.columns.1
        )?;
        write!(f, "{}", ReportTable(&self.report))?;
        write!(f, "wrote {}", csvio::join_paths(&self.files))
    }
}

/// Fails with [`FitCmdError::SameFile`] when `output` names one of
/// `others`.
fn refuse_same(
    what: &'static str,
    output: &Path,
    others: &[(&'static str, &Path)],
) -> Result<(), FitCmdError> {
    if let Some((other_what, other)) = csvio::clash(output, others) {
        return Err(FitCmdError::SameFile {
            what,
            output: output.to_path_buf(),
            other_what,
            other: other.to_path_buf(),
        });
    }
    Ok(())
}

/// The progress display: a spinner line on stderr, drawn only when asked
/// for and stderr is a terminal; cleared when dropped.
pub(crate) struct Display(ProgressBar);

impl Display {
    pub(crate) fn new(wanted: bool) -> Self {
        if !(wanted && std::io::stderr().is_terminal()) {
            return Display(ProgressBar::hidden());
        }
        let bar = ProgressBar::new_spinner();
        if let Ok(style) = ProgressStyle::with_template("{spinner} fitting [{elapsed}] {msg}") {
            bar.set_style(style);
        }
        bar.set_message("starting");
        bar.enable_steady_tick(Duration::from_millis(120));
        Display(bar)
    }

    pub(crate) fn update(&self, p: Progress) {
        self.message(format!(
            "iteration {}, {} evaluations, cost {:.6e}",
            p.iteration, p.evaluations, p.cost
        ));
    }

    pub(crate) fn message(&self, message: String) {
        self.0.set_message(message);
    }
}

impl Drop for Display {
    fn drop(&mut self) {
        self.0.finish_and_clear();
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

/// Runs the fit; see the module docs.
pub fn run(opts: &FitCmdOptions) -> Result<FitCmdReport, FitCmdError> {
    let inputs = [
        ("data", opts.data.as_path()),
        ("model", opts.model.as_path()),
    ];
    refuse_same("output", &opts.output, &inputs)?;
    if let Some(p) = &opts.plot {
        refuse_same("plot", p, &inputs)?;
        refuse_same("plot", p, &[("output", opts.output.as_path())])?;
    }
    if opts.input_column.trim() == opts.output_column.trim() {
        return Err(FitCmdError::SameColumn(opts.input_column.clone()));
    }

    let model_err = |e| FitCmdError::Model(opts.model.clone(), e);
    let spec = Spec::from_json_file(&opts.model).map_err(model_err)?;
    let spec = opts.dt.apply(spec, &opts.data).map_err(FitCmdError::Data)?;
    let model = spec.build().map_err(model_err)?;

    let names: Vec<&str> = opts
        .free
        .iter()
        .map(|s| s.trim())
        .filter(|s| !s.is_empty())
        .collect();
    if names.is_empty() {
        return Err(FitCmdError::NoFree {
            model: opts.model.clone(),
            available: model.param_names().join(", "),
        });
    }
    let free = free_by_names(model.as_ref(), &names)
        .map_err(|e| FitCmdError::Free(opts.model.clone(), e))?;
    for (j, &i) in free.iter().enumerate() {
        if free[..j].contains(&i) {
            return Err(FitCmdError::DuplicateFree {
                model: opts.model.clone(),
                name: model.param_names()[i].clone(),
            });
        }
    }

    refuse_tied(opts, &spec, model.as_ref(), &free)?;

    let columns = csvio::read_columns(&opts.data, &[&opts.input_column, &opts.output_column])
        .map_err(FitCmdError::Data)?;
    let (x, y) = (&columns.values[0], &columns.values[1]);
    let input_name = columns.headers[columns.indices[0]].trim().to_string();
    let output_name = columns.headers[columns.indices[1]].trim().to_string();
    if columns.indices[0] == columns.indices[1] {
        return Err(FitCmdError::SameColumn(input_name));
    }

    let fit_opts = FitOptions {
        patience: opts.patience,
        ..FitOptions::default()
    };
    let fit = {
        let display = Display::new(opts.progress);
        fit_with_progress(model.as_ref(), x, y, &free, &fit_opts, &|p| {
            display.update(p)
        })
    }
    .map_err(|e| match e {
        FitError::Start(error) => FitCmdError::Start(Box::new(csvio::SampleFailure::locate(
            &opts.model,
            &opts.data,
            "data",
            &input_name,
            x,
            &columns.lines,
            error,
        ))),
        other => FitCmdError::Fit(other),
    })?;
    let report = fit.report;

    // The fitted spec, checked to build to exactly the fitted parameters
    // and simulated over the record (what `simulate` will do with it).
    let fitted_err = |e: String| FitCmdError::Fitted(opts.model.clone(), e);
    let fitted = spec
        .with_params(&report.all_params)
        .map_err(|e| fitted_err(e.to_string()))?;
    let mut fitted_model = fitted.build().map_err(|e| fitted_err(e.to_string()))?;
    let bits = |p: &[f64]| p.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    if bits(&fitted_model.params()) != bits(&report.all_params) {
        return Err(fitted_err(
            "the fitted spec does not hold the fitted parameters".into(),
        ));
    }
    let y_fit = fitted_model
        .run(x)
        .map_err(|e| fitted_err(format!("simulating the record: {e}")))?;
    let json = fitted
        .to_json_pretty()
        .map_err(|e| fitted_err(e.to_string()))?;

    let svg = match &opts.plot {
        Some(p) => Some(
            figure(opts, &input_name, &output_name, x, y, &y_fit)
                .map_err(|e| FitCmdError::Plot(p.clone(), e))?,
        ),
        None => None,
    };

    // Both destinations must be writable before either is written.
    csvio::target_dir(&opts.output).map_err(FitCmdError::Write)?;
    if let Some(p) = &opts.plot {
        csvio::target_dir(p).map_err(FitCmdError::Write)?;
    }
    csvio::write_string_atomic(&opts.output, &(json + "\n")).map_err(FitCmdError::Write)?;
    let mut files = vec![opts.output.clone()];
    if let (Some(p), Some(svg)) = (&opts.plot, svg) {
        csvio::write_string_atomic(p, &svg).map_err(FitCmdError::Write)?;
        files.push(p.clone());
    }
    Ok(FitCmdReport {
        model: opts.model.clone(),
        kind: spec.kind(),
        n_params: model.n_params(),
        data: opts.data.clone(),
        columns: (input_name, output_name),
        samples: x.len(),
        report,
        files,
    })
}

/// Measured and fitted output over the input (the loop), over the sample
/// index, and the residual over the sample index.
fn figure(
    opts: &FitCmdOptions,
    input: &str,
    output: &str,
    x: &[f64],
    y: &[f64],
    y_fit: &[f64],
) -> Result<String, PlotError> {
    let title = format!(
        "{} fitted to {}",
        file_name(&opts.model),
        file_name(&opts.data)
    );
    let pairs = |a: &[f64], b: &[f64]| -> Vec<(f64, f64)> {
        a.iter().copied().zip(b.iter().copied()).collect()
    };
    // plotters labels ticks with a fixed format: keep the numbers on the
    // axes short by scaling the sample index and the residual by a power
    // of ten named in the axis label.
    let (index_scale, index_label) = power_of_ten(x.len().saturating_sub(1) as f64, "sample");
    let index: Vec<f64> = (0..x.len()).map(|i| i as f64 / index_scale).collect();
    let residual: Vec<f64> = y_fit.iter().zip(y).map(|(f, m)| f - m).collect();
    let largest = residual.iter().fold(0.0_f64, |a, r| a.max(r.abs()));
    let (res_scale, res_label) = power_of_ten(largest, &format!("{output} residual"));
    let residual: Vec<f64> = residual.iter().map(|r| r / res_scale).collect();

    let mut loop_panel = Panel::new(&title, input, output);
    loop_panel
        .series
        .push(Series::line("measured", pairs(x, y), 7).with_style(Style::Band));
    loop_panel
        .series
        .push(Series::line("fitted", pairs(x, y_fit), 1));

    let mut time_panel = Panel::new(&format!("{output} over sample"), &index_label, output);
    time_panel
        .series
        .push(Series::line("measured", pairs(&index, y), 7).with_style(Style::Band));
    time_panel
        .series
        .push(Series::line("fitted", pairs(&index, y_fit), 1));

    let mut res_panel = Panel::new("residual (fitted - measured)", &index_label, &res_label);
    res_panel
        .series
        .push(Series::line("", pairs(&index, &residual), 0));

    plot::render(&[loop_panel, time_panel, res_panel], 1, 3, (1500, 480))
}

/// For values up to `largest` in magnitude: the power of ten to divide
/// them by so that axis labels stay short (1 when they already are), and
/// the axis label naming it (`sample / 1e3`).
pub(crate) fn power_of_ten(largest: f64, label: &str) -> (f64, String) {
    if !(largest.is_finite() && largest > 0.0) {
        return (1.0, label.to_string());
    }
    let exp = largest.log10().floor() as i32;
    if (-2..3).contains(&exp) {
        (1.0, label.to_string())
    } else {
        (10f64.powi(exp), format!("{label} / 1e{exp}"))
    }
}

fn file_name(p: &Path) -> String {
    p.file_name()
        .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fmt_g_is_short_and_exact_enough() {
        assert_eq!(fmt_g(1.5, 7), "1.5");
        assert_eq!(fmt_g(0.0, 7), "0");
        assert_eq!(fmt_g(-2.0, 7), "-2");
        assert_eq!(fmt_g(1.0 / 3.0, 7), "0.3333333");
        assert_eq!(fmt_g(12345.678, 7), "12345.68");
        assert_eq!(fmt_g(1.23456789e-7, 4), "1.235e-7");
        assert_eq!(fmt_g(2.5e9, 7), "2.5e9");
        assert_eq!(fmt_g(f64::NAN, 7), "NaN");
    }

    #[test]
    fn axis_scales_are_powers_of_ten() {
        assert_eq!(
            power_of_ten(19999.0, "sample"),
            (1e4, "sample / 1e4".into())
        );
        assert_eq!(power_of_ten(999.0, "sample"), (1.0, "sample".into()));
        assert_eq!(power_of_ten(3.2e-15, "r"), (1e-15, "r / 1e-15".into()));
        assert_eq!(power_of_ten(0.0, "r"), (1.0, "r".into()));
    }
}
