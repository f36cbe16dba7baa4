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
//! code [`EXIT_NOT_CONVERGED`](crate::fitting::EXIT_NOT_CONVERGED) (3) so that scripts can tell. A converged
//! fit exits with 0; errors (nothing written) with 1.

use crate::csvio::{self, CsvIoError};
use crate::fitting::{not_converged_note, Display};
use crate::identify::{fit_with_progress, free_by_names, FitError, FitOptions, FitReport};
use crate::model_file::ModelFileError;
use crate::models::Spec;
use crate::period::DtSource;
use crate::plot::{self, Panel, PlotError, Series, Style};
use crate::Operator;
use std::fmt;
use std::path::{Path, PathBuf};

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
    /// `--free` names no parameter.
    #[error("--free names no parameter of model `{}` (the model has: {available})", model.display())]
    NoFree {
        /// The model spec.
        model: PathBuf,
        /// The model's parameter names.
        available: String,
    },
    /// A `--free` name is unknown or ambiguous.
    #[error("--free: model `{}`: {}", .0.display(), .1)]
    Free(PathBuf, FitError),
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
    /// Two `--free` names give the same parameter.
    #[error("--free: parameter `{name}` of model `{}` is named twice", model.display())]
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
    /// Writing an output failed.
    #[error("output {0}")]
    Write(CsvIoError),
    /// Drawing the figure failed.
    #[error("plot `{}`: {}", .0.display(), .1)]
    Plot(PathBuf, PlotError),
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
    /// [`EXIT_NOT_CONVERGED`](crate::fitting::EXIT_NOT_CONVERGED)).
    pub fn converged(&self) -> bool {
        self.report.status.converged()
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

/// Runs the fit; see the module docs.
pub fn run(opts: &FitCmdOptions) -> Result<FitCmdReport, FitCmdError> {
    let inputs = [
        ("data", opts.data.as_path()),
        ("model", opts.model.as_path()),
    ];
    csvio::refuse_same("output", &opts.output, &inputs).map_err(FitCmdError::SameFile)?;
    if let Some(p) = &opts.plot {
        csvio::refuse_same("plot", p, &inputs).map_err(FitCmdError::SameFile)?;
        csvio::refuse_same("plot", p, &[("output", opts.output.as_path())])
            .map_err(FitCmdError::SameFile)?;
    }
    if opts.input_column.trim() == opts.output_column.trim() {
        return Err(FitCmdError::SameColumn(opts.input_column.clone()));
    }

    let model_err = |e| ModelFileError::new(&opts.model, e);
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
    let (index_scale, index_label) = plot::power_of_ten(x.len().saturating_sub(1) as f64, "sample");
    let index: Vec<f64> = (0..x.len()).map(|i| i as f64 / index_scale).collect();
    let residual: Vec<f64> = y_fit.iter().zip(y).map(|(f, m)| f - m).collect();
    let largest = residual.iter().fold(0.0_f64, |a, r| a.max(r.abs()));
    let (res_scale, res_label) = plot::power_of_ten(largest, &format!("{output} residual"));
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

fn file_name(p: &Path) -> String {
    p.file_name()
        .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into())
}
