//! The `analyze` job: the describing function and the work per loop of a
//! model spec (JSON, see [`Spec`](crate::models::Spec)) driven by sines of
//! given amplitudes.
//!
//! For every amplitude `A` the model (built once, reset for each
//! amplitude) runs `settle_periods` periods of `x = A sin θ` with
//! `samples_per_period` samples each; the last period must be steady (its
//! first harmonic within `steady_tol · max|y|` of the period before's,
//! otherwise an error). From it come the describing function
//! `N(A) = (b_1 + i a_1)/A` ([`crate::models::describing`]) and the loop
//! energy by the trapezoid rule ([`crate::models::energy`]):
//!
//! * `dissipated`: the energy dissipated per loop, the loop's area
//!   `|∮ y dx|` ([`LoopEnergy::area`]), positive for every hysteresis loop
//!   whichever way it runs: the usual counterclockwise one of an output
//!   that lags its input (play, Prandtl-Ishlinskii bank, Preisach) and the
//!   clockwise one of a force over a displacement (stop, MMS friction,
//!   Bouc-Wen spring);
//! * `work`: the signed `∮ y dx` of the library
//!   ([`LoopEnergy::work`]), which tells the orientation: negative for a
//!   counterclockwise loop, positive for a clockwise one.
//!
//! The table is printed; with an output path it is also written as CSV
//! (atomically, after every amplitude succeeded; columns `amplitude, gain,
//! phase_deg, re, im, work, dissipated`).
//!
//! [`LoopEnergy::area`]: crate::models::energy::LoopEnergy::area
//! [`LoopEnergy::work`]: crate::models::energy::LoopEnergy::work

use crate::args;
use crate::csvio;
use crate::identify::report::fmt_g;
use crate::model_file::{self, ModelFileError};
use crate::models::describing::{AnalysisError, DescribingFunction, SineOptions, SteadyCycle};
use crate::output::OutputError;
use crate::period::{self, Origin, Period};
use std::fmt;
use std::path::PathBuf;

/// Drive a model spec (JSON) by sines x = A sin θ, one per amplitude,
/// until its output is periodic, and print per amplitude the describing
/// function (first-harmonic gain |N| and phase in degrees, negative =
/// lag), the energy dissipated per loop (the loop's area |∮ y dx|,
/// trapezoid rule: > 0 for every hysteresis loop, the usual
/// counterclockwise one of a lagging output such as a PI bank's as well
/// as a clockwise friction loop) and the signed work ∮ y dx (< 0 for a
/// counterclockwise loop, > 0 for a clockwise one).
#[derive(Debug, Clone, PartialEq, clap::Args)]
pub struct AnalyzeOptions {
    /// The model spec (JSON, see hysteron::models::Spec).
    #[arg(long, value_name = "SPEC.json")]
    pub model: PathBuf,
    /// Amplitudes, comma-separated (each finite and > 0).
    #[arg(
        long,
        value_name = "A1,A2,...",
        value_delimiter = ',',
        required = true,
        allow_hyphen_values = true
    )]
    pub amplitudes: Vec<f64>,
    /// Samples per period (a multiple of 4, at least 8).
    #[arg(long, value_name = "N", default_value_t = 1024, value_parser = args::samples_per_period, allow_negative_numbers = true)]
    pub samples_per_period: usize,
    /// Periods run before the analysed one (at least 2: the last is
    /// compared with the one before).
    #[arg(long, value_name = "P", default_value_t = 20, value_parser = args::settle_periods, allow_negative_numbers = true)]
    pub settle_periods: usize,
    /// Largest accepted change of the first harmonic over the last
    /// period, relative to max|y|.
    #[arg(
        long,
        value_name = "TOL",
        default_value_t = 1e-9,
        allow_negative_numbers = true
    )]
    pub steady_tol: f64,
    // Sample period (s) of the spec's rate-dependent nodes, overriding
    // their `dt` (default: the spec's); the help lists the registry's
    // rate-dependent kinds.
    #[arg(
        long,
        value_name = "SECONDS",
        value_parser = args::positive_f64,
        allow_hyphen_values = true,
        help = period::dt_help()
    )]
    pub dt: Option<f64>,
    /// Significant digits of the printed table (1 to 17; --output
    /// writes every digit).
    #[arg(long, value_name = "DIGITS", default_value_t = PRECISION, value_parser = args::precision)]
    pub precision: usize,
    /// Also write the table as CSV (atomically; may not be the model).
    #[arg(long, value_name = "OUT.csv")]
    pub output: Option<PathBuf>,
}

impl AnalyzeOptions {
    /// The sines: `--samples-per-period`, `--settle-periods` and
    /// `--steady-tol`, and the default harmonics ([`SineOptions`]).
    pub fn sine(&self) -> SineOptions {
        SineOptions {
            samples_per_period: self.samples_per_period,
            settle_periods: self.settle_periods,
            steady_tol: self.steady_tol,
            ..SineOptions::default()
        }
    }
}

/// The default of [`AnalyzeOptions::precision`].
pub const PRECISION: usize = 6;

/// An error of the analyze job (one-line message).
#[derive(Debug, thiserror::Error)]
pub enum AnalyzeError {
    /// The output path names the model file.
    #[error("output `{}` is the same file as the model: refusing to overwrite it", .0.display())]
    SameFile(PathBuf),
    /// No amplitudes were given.
    #[error("no amplitudes given")]
    NoAmplitudes,
    /// The model spec could not be read, parsed or built.
    #[error(transparent)]
    Model(#[from] ModelFileError),
    /// An amplitude or option is outside its range.
    #[error(transparent)]
    Argument(AnalysisError),
    /// The analysis of the model at one amplitude failed (operator error,
    /// no steady state).
    #[error("model `{}`: {}", .0.display(), .1)]
    Analysis(PathBuf, AnalysisError),
    /// Writing an output or drawing a figure failed.
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// One row of the table.
#[derive(Debug, Clone, PartialEq)]
pub struct AnalyzeRow {
    /// The describing function at this amplitude.
    pub describing: DescribingFunction,
    /// `∮ y dx` over the steady loop (negative for a counterclockwise
    /// loop, positive for a clockwise one).
    pub work: f64,
    /// The energy dissipated per loop: the loop's area `|∮ y dx|` (≥ 0
    /// whatever the orientation).
    pub dissipated: f64,
}

/// What the analyze job computed.
#[derive(Debug, Clone, PartialEq)]
pub struct AnalyzeReport {
    /// The model's operator name.
    pub model: &'static str,
    /// The options used.
    pub sine: SineOptions,
    /// The sample period the model ran at: `--dt` or the spec's own
    /// (`None` for a rate-independent model).
    pub period: Option<Period>,
    /// Significant digits of the printed table.
    pub precision: usize,
    /// One row per amplitude, in the order given.
    pub rows: Vec<AnalyzeRow>,
    /// Files written.
    pub files: Vec<PathBuf>,
}

impl fmt::Display for AnalyzeReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "analyzed a `{}` model driven by A sin θ ({} samples per period, {} settle periods)",
            self.model, self.sine.samples_per_period, self.sine.settle_periods
        )?;
        if let Some(p) = &self.period {
            writeln!(f, "sample period: {p}")?;
        }
        let w = (self.precision + 8).max(19);
        writeln!(
            f,
            "{:>w$} {:>w$} {:>w$} {:>w$} {:>w$}",
            "A", "|N|", "phase_deg", "dissipated_per_loop", "work"
        )?;
        let g = |v: f64| fmt_g(v, self.precision);
        for row in &self.rows {
            let d = &row.describing;
            writeln!(
                f,
                "{:>w$} {:>w$} {:>w$} {:>w$} {:>w$}",
                g(d.amplitude),
                g(d.gain),
                g(d.phase.to_degrees()),
                g(row.dissipated),
                g(row.work)
            )?;
        }
        write!(
            f,
            "|N|, phase: first-harmonic gain (negative phase = lag); dissipated_per_loop = loop \
             area |∮ y dx| (> 0 for any hysteresis loop); work = ∮ y dx (< 0 counterclockwise \
             loop, output lagging input: play, PI; > 0 clockwise: stop, friction)"
        )?;
        if !self.files.is_empty() {
            write!(f, "\nwrote {}", csvio::join_paths(&self.files))?;
        }
        Ok(())
    }
}

/// Runs the analysis; see the module docs.
pub fn run(opts: &AnalyzeOptions) -> Result<AnalyzeReport, AnalyzeError> {
    if let Some(out) = &opts.output {
        if csvio::same_file(out, &opts.model) {
            return Err(AnalyzeError::SameFile(out.clone()));
        }
    }
    if opts.amplitudes.is_empty() {
        return Err(AnalyzeError::NoAmplitudes);
    }
    let sine = opts.sine();
    sine.validate().map_err(AnalyzeError::Argument)?;
    for &a in &opts.amplitudes {
        if !(a.is_finite() && a > 0.0) {
            return Err(AnalyzeError::Argument(AnalysisError::InvalidArgument {
                name: "amplitude",
                value: a,
                reason: "must be finite and > 0",
            }));
        }
    }
    if !(1..=17).contains(&opts.precision) {
        return Err(AnalyzeError::Argument(AnalysisError::InvalidArgument {
            name: "precision",
            value: opts.precision as f64,
            reason: "must be 1 to 17 significant digits",
        }));
    }
    let mut spec = model_file::read(&opts.model)?;
    if let Some(dt) = opts.dt {
        spec = spec.with_dt(dt);
    }
    let model = model_file::build(&opts.model, &spec)?;
    let period = match (spec.is_rate_dependent(), opts.dt) {
        (false, _) => None,
        (true, Some(dt)) => Some(Period {
            dt,
            origin: Origin::Option,
        }),
        (true, None) => spec.stated_periods().first().map(|&dt| Period {
            dt,
            origin: Origin::Spec(None),
        }),
    };
    let analysis_err = |e| AnalyzeError::Analysis(opts.model.clone(), e);
    let mut rows = Vec::with_capacity(opts.amplitudes.len());
    for &a in &opts.amplitudes {
        let cycle = SteadyCycle::compute(&model, a, &sine).map_err(analysis_err)?;
        let energy = cycle.loop_energy();
        rows.push(AnalyzeRow {
            describing: cycle.describing_function(sine.harmonics),
            work: energy.work,
            dissipated: energy.area(),
        });
    }
    let mut files = Vec::new();
    if let Some(out) = &opts.output {
        let col = |f: fn(&AnalyzeRow) -> f64| rows.iter().map(f).collect::<Vec<f64>>();
        let amplitude = col(|r| r.describing.amplitude);
        let gain = col(|r| r.describing.gain);
        let phase = col(|r| r.describing.phase.to_degrees());
        let re = col(|r| r.describing.re);
        let im = col(|r| r.describing.im);
        let work = col(|r| r.work);
        let dissipated = col(|r| r.dissipated);
        csvio::write_columns(
            out,
            &[
                ("amplitude", &amplitude),
                ("gain", &gain),
                ("phase_deg", &phase),
                ("re", &re),
                ("im", &im),
                ("work", &work),
                ("dissipated", &dissipated),
            ],
        )
        .map_err(OutputError::Write)?;
        files.push(out.clone());
    }
    Ok(AnalyzeReport {
        model: model.name(),
        sine,
        period,
        precision: opts.precision,
        rows,
        files,
    })
}
