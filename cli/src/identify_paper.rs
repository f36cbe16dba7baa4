//! The `identify-paper` job: the two-stage identification of Ruderman &
//! Bertram (2015) ([`identify_paper`]) from two records, a major loop and
//! a down-chirp, each a CSV file with input and force columns (`x` and `F`
//! by default, like the CSV files the `paper` job writes).
//!
//! * Stage 1 fits the spring's shape to the loop record, with the
//!   stiffness knots derived from points on its last complete increasing
//!   branch; stage 2 fits the bedstop (`limits.b`, `f_c`, `k`) of the full
//!   model to the chirp record with that spring; stage 3 fits all
//!   parameters on both records together, from the stage-1 spring and the
//!   bedstop read off the loop's plateau. They start from the
//!   illustrative [`TransmissionParams::default`], or from `--start`, a
//!   `transmission` spec.
//! * The result is written as a **model spec** of type `transmission`:
//!   `{"type": "transmission", "backlash": …, "slider0": …, "friction":
//!   {…}, "spring": {…}}`, i.e. the identified [`TransmissionParams`] with
//!   a `type` tag, which `simulate` (and `fit`, and `--start`) accept as it
//!   is.
//! * `--plot DIR` (created if missing) adds `DIR/loop.svg` (the measured
//!   loop, the stage-1 spring alone, the identified model and the picked
//!   points; the identified stiffness map) and `DIR/chirp.svg` (measured
//!   and identified force over the sample index and over the input).
//!
//! All stage reports are printed. As for `fit`, nothing is written unless
//! everything before succeeded, files are written atomically, no output may
//! be an input, errors are one line with exit code 1, and an
//! identification whose stages ran but did not both converge exits with
//! code [`EXIT_NOT_CONVERGED`](crate::fitting::EXIT_NOT_CONVERGED) (3) after writing its result.

use crate::args;
use crate::csvio::join_paths;
use crate::csvio::{self, CsvIoError};
use crate::fitting::{not_converged_note, ProgressArgs};
use crate::identify::paper::{identify_paper, PaperError, PaperIdentification, PaperOptions};
use crate::identify::report::fmt_g;
use crate::models::{Spec, SpecError, TransmissionParams};
use crate::operators::BoucWen;
use crate::output::OutputError;
use crate::plot::{self, file_name, pairs, Panel, PlotError, Series, Style};
use crate::Operator;
use std::fmt;
use std::path::{Path, PathBuf};

/// The two-stage identification of Ruderman & Bertram (2015): the
/// spring's shape from a major loop (knots through points of its last
/// increasing branch), then the bedstop (backlash, F_c, K) from a
/// down-chirp; then a joint refinement of all parameters on both
/// records (stage 3, from the stage-1 spring and the backlash and F_c
/// of the loop's plateau). Writes the identified model as a
/// `transmission` spec (JSON) and prints the stage reports. Exit code 3
/// when a stage did not converge.
#[derive(Debug, Clone, PartialEq, clap::Args)]
pub struct IdentifyPaperOptions {
    /// The major-loop record (CSV with a header row): one sine, whose
    /// whole record stage 1 fits and whose last increasing branch gives
    /// the knots, e.g. the `paper` job's sine-5hz-I.csv (its sines.csv
    /// holds three sines of different frequencies in a row: cut one out
    /// first).
    #[arg(long = "loop", value_name = "LOOP.csv")]
    pub loop_record: PathBuf,
    /// The down-chirp record (CSV with a header row; e.g. the `paper`
    /// job's chirp.csv).
    #[arg(long, value_name = "CHIRP.csv")]
    pub chirp: PathBuf,
    /// The input column of both records.
    #[arg(long, value_name = "NAME", default_value = "x")]
    pub input_column: String,
    /// The force column of both records.
    #[arg(long, value_name = "NAME", default_value = "F")]
    pub output_column: String,
    /// Starting values: a `transmission` spec (default: the
    /// illustrative defaults of the `paper` job).
    #[arg(long, value_name = "START.json")]
    pub start: Option<PathBuf>,
    /// Where to write the identified model: a `transmission` spec
    /// (JSON, written atomically).
    #[arg(long, value_name = "FITTED.json")]
    pub output: PathBuf,
    /// Also write the figures loop.svg and chirp.svg into DIR (created
    /// if missing).
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
    /// Points picked on the loop's increasing branch (the knots of the
    /// stiffness map; 2 to 999).
    #[arg(long, value_name = "N", default_value_t = 12, value_parser = args::points, allow_negative_numbers = true)]
    pub points: usize,
    /// Levenberg-Marquardt's patience in each stage: at most
    /// PATIENCE·(free + 1) trial steps, each accepted one followed by a
    /// Jacobian of 2·free runs (at least 1).
    #[arg(long, value_name = "N", default_value_t = 200, value_parser = args::at_least_1, allow_negative_numbers = true)]
    pub patience: usize,
    /// Whether to draw the progress line.
    #[command(flatten)]
    pub progress: ProgressArgs,
}

/// An error of the identify-paper job (one-line message).
#[derive(Debug, thiserror::Error)]
pub enum IdentifyPaperError {
    /// An output names an input or the other output.
    #[error(transparent)]
    SameFile(#[from] csvio::SameFile),
    /// Input and output columns are the same.
    #[error("--input-column and --output-column both name the column `{0}`")]
    SameColumn(String),
    /// The start spec could not be read, is invalid, or is not a
    /// `transmission` spec.
    #[error("start `{}`: {}", .0.display(), .1)]
    Start(PathBuf, String),
    /// A record could not be read or is invalid.
    #[error("record {0}")]
    Data(CsvIoError),
    /// The identification failed.
    #[error("identification{}: {error}", record_named(error, loop_record, chirp))]
    Paper {
        /// The loop record.
        loop_record: PathBuf,
        /// The chirp record.
        chirp: PathBuf,
        /// What failed.
        error: PaperError,
    },
    /// The identified parameters do not give a usable model.
    #[error("identified model: {0}")]
    Identified(String),
    /// Writing an output or drawing a figure failed.
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// ` (loop `FILE`)` or ` (chirp `FILE`)` when `error` belongs to one
/// record, else nothing.
fn record_named(error: &PaperError, loop_record: &Path, chirp: &Path) -> String {
    let record = match error {
        PaperError::Data { record, .. } | PaperError::NoIncreasingBranch { record } => {
            Some(*record)
        }
        PaperError::TooFewPoints { .. } | PaperError::Fit { stage: 1, .. } => Some("loop"),
        PaperError::Fit { stage: 2, .. } => Some("chirp"),
        _ => None,
    };
    match record {
        Some("loop") => format!(" (loop `{}`)", loop_record.display()),
        Some("chirp") => format!(" (chirp `{}`)", chirp.display()),
        _ => String::new(),
    }
}

/// What the job did.
#[derive(Debug, Clone, PartialEq)]
pub struct IdentifyPaperReport {
    /// The loop record and its length.
    pub loop_record: (PathBuf, usize),
    /// The chirp record and its length.
    pub chirp: (PathBuf, usize),
    /// Input and force column.
    pub columns: (String, String),
    /// Both stages.
    pub result: PaperIdentification,
    /// RMS error of the identified model on the loop and on the chirp.
    pub rms: (f64, f64),
    /// Files written.
    pub files: Vec<PathBuf>,
}

impl IdentifyPaperReport {
    /// Whether both stages converged (exit code 0, otherwise
    /// [`EXIT_NOT_CONVERGED`](crate::fitting::EXIT_NOT_CONVERGED)).
    pub fn converged(&self) -> bool {
        self.result.spring.report.status.converged()
            && self.result.bedstop.status.converged()
            && self
                .result
                .joint
                .as_ref()
                .is_none_or(|j| j.report.status.converged())
    }
}

fn list(v: &[f64]) -> String {
    v.iter()
        .map(|v| fmt_g(*v, 6))
        .collect::<Vec<_>>()
        .join(", ")
}

impl fmt::Display for IdentifyPaperReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = &self.result;
        writeln!(
            f,
            "identify-paper: loop `{}` ({} samples), chirp `{}` ({} samples), {} -> {}",
            self.loop_record.0.display(),
            self.loop_record.1,
            self.chirp.0.display(),
            self.chirp.1,
            self.columns.0,
            self.columns.1
        )?;
        writeln!(
            f,
            "\nstage 1: the spring's shape on the loop, knots through {} points of its last increasing branch",
            r.spring.points.len()
        )?;
        write!(f, "{}", r.spring.report)?;
        not_converged_note(f, &r.spring.report)?;
        let map = &r.spring.spring.stiffness;
        writeln!(f, "knots z      [{}]", list(map.knots_z()))?;
        writeln!(f, "knots S      [{}]", list(map.knots_s()))?;
        writeln!(f, "\nstage 2: the bedstop on the chirp, spring fixed")?;
        write!(f, "{}", r.bedstop)?;
        not_converged_note(f, &r.bedstop)?;
        if let Some(j) = &r.joint {
            writeln!(
                f,
                "\nstage 3: all parameters on the loop and the chirp together (record 0: loop, 1: chirp)"
            )?;
            if let Some(p) = &j.plateau {
                writeln!(
                    f,
                    "start: backlash {} and f_c {} from the loop's plateau",
                    fmt_g(p.width, 6),
                    fmt_g(p.level, 6)
                )?;
            }
            write!(f, "{}", j.report)?;
            not_converged_note(f, &j.report)?;
        }
        let p = &r.params;
        writeln!(
            f,
            "\nidentified: backlash {}, f_c {}, k {}, w {}, beta {}, gamma {}, n {}, h0 {}",
            fmt_g(p.backlash, 7),
            fmt_g(p.friction.f_c, 7),
            fmt_g(p.friction.k, 7),
            fmt_g(p.spring.w, 7),
            fmt_g(p.spring.beta, 7),
            fmt_g(p.spring.gamma, 7),
            fmt_g(p.spring.n, 7),
            fmt_g(p.spring.h0, 7),
        )?;
        writeln!(
            f,
            "RMS error of the identified model: loop {:.6e}, chirp {:.6e}",
            self.rms.0, self.rms.1
        )?;
        write!(f, "wrote {}", join_paths(&self.files))
    }
}

/// Reads the starting values: a `transmission` spec.
fn read_start(path: &Path) -> Result<TransmissionParams, IdentifyPaperError> {
    let err = |e: String| IdentifyPaperError::Start(path.to_path_buf(), e);
    let spec = Spec::from_json_file(path).map_err(|e| match e {
        SpecError::Io { message, .. } => err(message),
        e => err(e.to_string()),
    })?;
    spec.build().map_err(|e| err(e.to_string()))?;
    match spec {
        Spec::Transmission(p) => Ok(p),
        other => Err(err(format!(
            "must be a `transmission` spec (got `{}`)",
            other.kind()
        ))),
    }
}

fn rms(a: &[f64], b: &[f64]) -> f64 {
    (a.iter().zip(b).map(|(u, v)| (u - v).powi(2)).sum::<f64>() / a.len().max(1) as f64).sqrt()
}

/// Runs both stages; see the module docs.
pub fn run(opts: &IdentifyPaperOptions) -> Result<IdentifyPaperReport, IdentifyPaperError> {
    let mut inputs = vec![
        ("loop record", opts.loop_record.as_path()),
        ("chirp record", opts.chirp.as_path()),
    ];
    if let Some(s) = &opts.start {
        inputs.push(("start spec", s.as_path()));
    }
    csvio::refuse_same("output", &opts.output, &inputs).map_err(IdentifyPaperError::SameFile)?;
    let figures: Vec<(&str, PathBuf)> = match &opts.plot {
        Some(dir) => vec![
            ("loop", dir.join("loop.svg")),
            ("chirp", dir.join("chirp.svg")),
        ],
        None => Vec::new(),
    };
    for (_, p) in &figures {
        csvio::refuse_same("plot", p, &inputs).map_err(IdentifyPaperError::SameFile)?;
        csvio::refuse_same("plot", p, &[("output", opts.output.as_path())])
            .map_err(IdentifyPaperError::SameFile)?;
    }
    if opts.input_column.trim() == opts.output_column.trim() {
        return Err(IdentifyPaperError::SameColumn(opts.input_column.clone()));
    }

    let start = match &opts.start {
        Some(p) => read_start(p)?,
        None => TransmissionParams::default(),
    };
    let columns = [opts.input_column.as_str(), opts.output_column.as_str()];
    let lp = csvio::read_columns(&opts.loop_record, &columns).map_err(IdentifyPaperError::Data)?;
    let ch = csvio::read_columns(&opts.chirp, &columns).map_err(IdentifyPaperError::Data)?;
    let (loop_x, loop_f) = (&lp.values[0], &lp.values[1]);
    let (chirp_x, chirp_f) = (&ch.values[0], &ch.values[1]);

    let paper_opts = PaperOptions {
        points: opts.points,
        fit: crate::identify::FitOptions {
            patience: opts.patience,
            ..crate::identify::FitOptions::default()
        },
        ..PaperOptions::default()
    };
    let result = {
        let display = opts.progress.display();
        display.message(
            "stages 1 (spring, loop), 2 (bedstop, chirp) and 3 (all, both records)".into(),
        );
        identify_paper(loop_x, loop_f, chirp_x, chirp_f, &start, &paper_opts)
    }
    .map_err(|error| IdentifyPaperError::Paper {
        loop_record: opts.loop_record.clone(),
        chirp: opts.chirp.clone(),
        error,
    })?;

    // The identified model as a spec, checked to build and to simulate
    // both records.
    let spec = Spec::Transmission(result.params.clone());
    let identified = |e: String| IdentifyPaperError::Identified(e);
    let model = spec.build().map_err(|e| identified(e.to_string()))?;
    let loop_fit = model
        .clone()
        .run(loop_x)
        .map_err(|e| identified(format!("on the loop record: {e}")))?;
    let chirp_fit = model
        .clone()
        .run(chirp_x)
        .map_err(|e| identified(format!("on the chirp record: {e}")))?;
    let json = spec
        .to_json_pretty()
        .map_err(|e| identified(e.to_string()))?;

    let mut svgs = Vec::new();
    for (which, path) in &figures {
        let plot_err = |e| OutputError::Plot(path.clone(), e);
        let svg = if *which == "loop" {
            let spring_only = BoucWen::from_params(result.spring.spring.clone())
                .and_then(|mut s| s.run(loop_x))
                .map_err(|e| identified(format!("the stage-1 spring on the loop record: {e}")))?;
            loop_figure(opts, &result, loop_x, loop_f, &spring_only, &loop_fit).map_err(plot_err)?
        } else {
            chirp_figure(opts, chirp_x, chirp_f, &chirp_fit).map_err(plot_err)?
        };
        svgs.push((path.clone(), svg));
    }

    csvio::target_dir(&opts.output).map_err(OutputError::Write)?;
    if let Some(dir) = &opts.plot {
        std::fs::create_dir_all(dir).map_err(|e| OutputError::PlotDir(dir.clone(), e))?;
    }
    csvio::write_string_atomic(&opts.output, &(json + "\n")).map_err(OutputError::Write)?;
    let mut files = vec![opts.output.clone()];
    for (path, svg) in svgs {
        csvio::write_string_atomic(&path, &svg).map_err(OutputError::Write)?;
        files.push(path);
    }
    Ok(IdentifyPaperReport {
        loop_record: (opts.loop_record.clone(), loop_x.len()),
        chirp: (opts.chirp.clone(), chirp_x.len()),
        columns: (
            lp.headers[lp.indices[0]].trim().to_string(),
            lp.headers[lp.indices[1]].trim().to_string(),
        ),
        rms: (rms(&loop_fit, loop_f), rms(&chirp_fit, chirp_f)),
        result,
        files,
    })
}

/// The loop: measured, the stage-1 spring alone, the identified model, the
/// picked points; and the identified stiffness map with its knots.
fn loop_figure(
    opts: &IdentifyPaperOptions,
    result: &PaperIdentification,
    x: &[f64],
    f: &[f64],
    spring_only: &[f64],
    model: &[f64],
) -> Result<String, PlotError> {
    let (xl, fl) = (&opts.input_column, &opts.output_column);
    let mut loops = Panel::new(&format!("loop: {}", file_name(&opts.loop_record)), xl, fl);
    loops
        .series
        .push(Series::line("measured", pairs(x, f), 7).with_style(Style::Band));
    loops.series.push(Series::line(
        "stage 1: spring alone",
        pairs(x, spring_only),
        0,
    ));
    loops
        .series
        .push(Series::line("identified model", pairs(x, model), 1));
    loops.series.push(
        Series::line("knot points", result.spring.points.clone(), 2).with_style(Style::Markers),
    );

    let map = &result.params.spring.stiffness;
    let z_max = map.knots_z().last().copied().unwrap_or(1.0).max(1e-9) * 1.1;
    let curve: Vec<(f64, f64)> = (0..=200)
        .map(|i| {
            let z = z_max * i as f64 / 200.0;
            (z, map.eval(z).0)
        })
        .collect();
    let mut stiffness = Panel::new("identified stiffness map", "|z|", "S(|z|)");
    stiffness.series.push(Series::line("S", curve, 0));
    stiffness.series.push(
        Series::line("knots", pairs(map.knots_z(), map.knots_s()), 1).with_style(Style::Markers),
    );
    stiffness.legend = plot::Legend::LowerRight;
    plot::render(&[loops, stiffness], 1, 2, (1200, 500))
}

/// The chirp: measured and identified force over the sample index and
/// over the input.
fn chirp_figure(
    opts: &IdentifyPaperOptions,
    x: &[f64],
    f: &[f64],
    model: &[f64],
) -> Result<String, PlotError> {
    let (xl, fl) = (&opts.input_column, &opts.output_column);
    let (scale, index_label) =
        crate::plot::power_of_ten(x.len().saturating_sub(1) as f64, "sample");
    let index: Vec<f64> = (0..x.len()).map(|i| i as f64 / scale).collect();
    let mut over_time = Panel::new(
        &format!("chirp: {}", file_name(&opts.chirp)),
        &index_label,
        fl,
    );
    over_time
        .series
        .push(Series::line("measured", pairs(&index, f), 7).with_style(Style::Band));
    over_time
        .series
        .push(Series::line("identified model", pairs(&index, model), 1));
    let mut loops = Panel::new("chirp loops", xl, fl);
    loops
        .series
        .push(Series::line("measured", pairs(x, f), 7).with_style(Style::Band));
    loops
        .series
        .push(Series::line("identified model", pairs(x, model), 1));
    plot::render(&[over_time, loops], 1, 2, (1200, 500))
}
