//! The `paper` job: runs the experiments of Ruderman & Bertram (2015) with
//! the illustrative default parameters, writes one CSV per experiment and
//! the figures, and summarises what it did.
//!
//! Files written into the output directory (each atomically):
//!
//! * `<name>.csv` for every experiment of
//!   [`paper_experiments`](crate::models::experiments::paper_experiments),
//!   columns `t,x,F,z,slider,friction,h`: time (s), input (deg), force
//!   (Nm), spring deflection (deg), slider position (deg), friction force
//!   (Nm), spring state `h`; and `<name>-<part>.csv` for each part of an
//!   experiment that joins several (`sines-0.05Hz.csv`, `sines-0.5Hz.csv`,
//!   `sines-5Hz.csv`: one frequency's loops each);
//! * `loops.svg`: force over input like the paper's Figure 3, left the
//!   0.05, 0.5 and 5 Hz parts of the `sines` run, right the two 5 Hz runs
//!   from the initial states I and II (with the 5 Hz part of `sines` in
//!   grey), each panel on the scale of its own data;
//! * `chirp.svg`: force and input over time for the chirp (Figure 10);
//! * `stiffness.svg`: the stiffness map `S(|z|)` with its knots (Figure 8).
//!
//! # Splitting the `sines` run
//!
//! The `sines` signal is one record; the summary rows and the left panel
//! of `loops.svg` take its stretches from the experiment's own
//! [`parts`](crate::models::experiments::Experiment::parts), which
//! [`paper_experiments`](crate::models::experiments::paper_experiments)
//! records while it joins the pieces.
//!
//! # Loop width
//!
//! The summary's *loop width* of a run is the vertical width of its
//! hysteresis at zero input: at every zero crossing of `x` (a sign change
//! between consecutive samples, `x = 0` counted as positive) the force is
//! interpolated linearly to `x = 0`; the width is the spread (max − min)
//! of these forces over the run, i.e. the width at `x = 0` of the widest
//! loop traversed. *Last* is the width of the final cycle alone:
//! `|F(last falling crossing) − F(last rising crossing)|`, which shows
//! whether runs from different initial states ended on the same loop.

use crate::csvio::{self, CsvIoError};
use crate::models::experiments::{self, Experiment, Part, Record};
use crate::models::TransmissionParams;
use crate::plot::{self, pairs, Panel, PlotError, Series, Style};
use std::fmt;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// An error of the paper job (one-line message).
#[derive(Debug, thiserror::Error)]
pub enum PaperError {
    /// The output directory could not be created.
    #[error("cannot create output directory `{}`: {}", .0.display(), csvio::one_line(&.1.to_string()))]
    OutDir(PathBuf, std::io::Error),
    /// Building the experiments failed.
    #[error("building the experiments: {0}")]
    Experiments(crate::Error),
    /// A simulation failed.
    #[error("experiment `{0}`: {1}")]
    Simulation(String, crate::Error),
    /// An experiment the figures need is missing.
    #[error("no experiment named `{0}`")]
    Missing(String),
    /// Writing a file failed.
    #[error("writing {0}")]
    Write(#[from] CsvIoError),
    /// Drawing a figure failed.
    #[error("figure `{0}`: {1}")]
    Plot(String, PlotError),
}

/// Run the experiments of Ruderman & Bertram (2015): one CSV per
/// experiment (t,x,F,z,slider,friction,h) and the figures loops.svg,
/// chirp.svg and stiffness.svg; prints a summary.
#[derive(Debug, Clone, PartialEq, clap::Args)]
pub struct PaperOptions {
    /// Output directory (created if missing).
    #[arg(long, value_name = "DIR", default_value = "out")]
    pub out: PathBuf,
}

/// Figures of one run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSummary {
    /// Experiment (or part) name.
    pub name: String,
    /// Samples simulated.
    pub samples: usize,
    /// Peak `|F|` (Nm).
    pub peak_force: f64,
    /// Loop width at `x = 0` over the run, Nm (see the module docs);
    /// `None` without zero crossings.
    pub loop_width: Option<f64>,
    /// Loop width of the last cycle, Nm; `None` without a rising and a
    /// falling crossing.
    pub last_width: Option<f64>,
}

/// What the paper job did.
#[derive(Debug, Clone, PartialEq)]
pub struct PaperReport {
    /// One entry per experiment.
    pub runs: Vec<RunSummary>,
    /// The parts of the `sines` run.
    pub parts: Vec<RunSummary>,
    /// Files written.
    pub files: Vec<PathBuf>,
    /// Time spent simulating.
    pub simulation: Duration,
    /// Wall time of the whole job (simulation, files, figures).
    pub wall: Duration,
}

impl PaperReport {
    /// Total samples simulated.
    pub fn total_samples(&self) -> usize {
        self.runs.iter().map(|r| r.samples).sum()
    }

    /// Simulated samples per second of simulation time.
    pub fn throughput(&self) -> f64 {
        self.total_samples() as f64 / self.simulation.as_secs_f64().max(1e-12)
    }
}

fn opt(v: Option<f64>) -> String {
    v.map_or_else(|| "-".to_string(), |v| format!("{v:.3}"))
}

impl fmt::Display for PaperReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{:<16} {:>8} {:>12} {:>15} {:>13}",
            "experiment", "samples", "peak |F| Nm", "loop width Nm", "last cycle Nm"
        )?;
        let row = |f: &mut fmt::Formatter<'_>, r: &RunSummary, indent: &str| {
            writeln!(
                f,
                "{:<16} {:>8} {:>12.3} {:>15} {:>13}",
                format!("{indent}{}", r.name),
                r.samples,
                r.peak_force,
                opt(r.loop_width),
                opt(r.last_width)
            )
        };
        for r in &self.runs {
            row(f, r, "")?;
            if r.name == "sines" {
                for p in &self.parts {
                    row(f, p, "  ")?;
                }
            }
        }
        writeln!(
            f,
            "total: {} samples simulated in {:.3} s ({:.0} samples/s); wall time {:.3} s",
            self.total_samples(),
            self.simulation.as_secs_f64(),
            self.throughput(),
            self.wall.as_secs_f64()
        )?;
        write!(
            f,
            "wrote {} files to {}",
            self.files.len(),
            self.files
                .first()
                .and_then(|p| p.parent())
                .map_or_else(|| ".".into(), |d| d.display().to_string())
        )
    }
}

/// The forces at the zero crossings of `x`, interpolated to `x = 0`, with
/// `true` for a rising crossing.
pub fn zero_crossings(x: &[f64], f: &[f64]) -> Vec<(f64, bool)> {
    let mut out = Vec::new();
    for k in 1..x.len().min(f.len()) {
        let (a, b) = (x[k - 1], x[k]);
        if (a < 0.0) != (b < 0.0) {
            let s = if b == a { 1.0 } else { -a / (b - a) };
            out.push((f[k - 1] + s * (f[k] - f[k - 1]), b >= 0.0));
        }
    }
    out
}

/// Summarises a run (see the module docs for the loop widths).
pub fn summarise(name: &str, x: &[f64], f: &[f64]) -> RunSummary {
    let crossings = zero_crossings(x, f);
    let loop_width = crossings
        .iter()
        .map(|c| c.0)
        .fold(None, |acc: Option<(f64, f64)>, v| {
            Some(acc.map_or((v, v), |(lo, hi)| (lo.min(v), hi.max(v))))
        })
        .map(|(lo, hi)| hi - lo);
    let last_up = crossings.iter().rev().find(|c| c.1).map(|c| c.0);
    let last_down = crossings.iter().rev().find(|c| !c.1).map(|c| c.0);
    RunSummary {
        name: name.to_string(),
        samples: x.len(),
        peak_force: f.iter().fold(0.0, |m, v| m.max(v.abs())),
        loop_width,
        last_width: last_up.zip(last_down).map(|(u, d)| (d - u).abs()),
    }
}

/// Runs the paper job.
pub fn run(opts: &PaperOptions) -> Result<PaperReport, PaperError> {
    let start = Instant::now();
    std::fs::create_dir_all(&opts.out).map_err(|e| PaperError::OutDir(opts.out.clone(), e))?;
    let params = TransmissionParams::default();
    let experiments = experiments::paper_experiments(&params).map_err(PaperError::Experiments)?;

    let sim_start = Instant::now();
    let records = experiments
        .iter()
        .map(|e| {
            experiments::simulate(&e.params, &e.signal)
                .map_err(|err| PaperError::Simulation(e.name.clone(), err))
        })
        .collect::<Result<Vec<Record>, _>>()?;
    let simulation = sim_start.elapsed();

    let mut files = Vec::new();
    let mut runs = Vec::new();
    for (e, r) in experiments.iter().zip(&records) {
        let path = opts.out.join(format!("{}.csv", e.name));
        write_record(&path, r)?;
        files.push(path);
        runs.push(summarise(&e.name, &r.x, &r.force));
        // Each part on its own too (`sines-0.5Hz.csv`: one frequency's
        // loops, as `identify-paper --loop` takes them).
        for part in e.parts.iter().filter(|_| e.parts.len() > 1) {
            let label: String = part
                .label
                .chars()
                .filter(|c| c.is_ascii_alphanumeric() || matches!(c, '.' | '_'))
                .collect();
            let path = opts.out.join(format!("{}-{label}.csv", e.name));
            write_record(&path, &slice(r, part.range.clone()))?;
            files.push(path);
        }
    }

    let find = |name: &str| {
        experiments
            .iter()
            .position(|e| e.name == name)
            .map(|i| (&experiments[i], &records[i]))
            .ok_or_else(|| PaperError::Missing(name.into()))
    };
    let (sines_experiment, sines) = find("sines")?;
    let ranges = &sines_experiment.parts;
    let parts: Vec<RunSummary> = ranges
        .iter()
        .map(|p| {
            summarise(
                &p.label,
                &sines.x[p.range.clone()],
                &sines.force[p.range.clone()],
            )
        })
        .collect();

    let figures: [(&str, String); 3] = [
        (
            "loops.svg",
            loops_figure(ranges, sines, find("sine-5hz-I")?, find("sine-5hz-II")?)?,
        ),
        ("chirp.svg", chirp_figure(find("chirp")?)?),
        ("stiffness.svg", stiffness_figure(&params)?),
    ];
    for (name, svg) in figures {
        let path = opts.out.join(name);
        csvio::write_string_atomic(&path, &svg)?;
        files.push(path);
    }

    Ok(PaperReport {
        runs,
        parts,
        files,
        simulation,
        wall: start.elapsed(),
    })
}

/// The samples `range` of a record (clamped to its length).
fn slice(r: &Record, range: std::ops::Range<usize>) -> Record {
    let n = r.t.len();
    let range = range.start.min(n)..range.end.min(n);
    Record {
        t: r.t[range.clone()].to_vec(),
        x: r.x[range.clone()].to_vec(),
        force: r.force[range.clone()].to_vec(),
        state: r.state.get(range).map(<[_]>::to_vec).unwrap_or_default(),
    }
}

/// Writes a record as CSV with columns `t,x,F,z,slider,friction,h`.
pub fn write_record(path: &Path, r: &Record) -> Result<(), CsvIoError> {
    let col = |g: fn(&crate::models::TransmissionState) -> f64| -> Vec<f64> {
        r.state.iter().map(g).collect()
    };
    let (z, slider, friction, h) = (
        col(|s| s.z),
        col(|s| s.slider),
        col(|s| s.friction),
        col(|s| s.h),
    );
    csvio::write_columns(
        path,
        &[
            ("t", &r.t),
            ("x", &r.x),
            ("F", &r.force),
            ("z", &z),
            ("slider", &slider),
            ("friction", &friction),
            ("h", &h),
        ],
    )
}

fn loops_figure(
    ranges: &[Part],
    sines: &Record,
    one: (&Experiment, &Record),
    two: (&Experiment, &Record),
) -> Result<String, PaperError> {
    plot::render(&loop_panels(ranges, sines, one, two), 1, 2, (1200, 540))
        .map_err(|e| PaperError::Plot("loops.svg".into(), e))
}

/// The two panels of `loops.svg`: the sines' loops (left), and the 5 Hz
/// runs from initial states I and II (right), each on its own scale.
fn loop_panels(
    ranges: &[Part],
    sines: &Record,
    one: (&Experiment, &Record),
    two: (&Experiment, &Record),
) -> [Panel; 2] {
    let mut left = Panel::new(
        "sines: 0.05, 0.5 and 5 Hz (Fig. 3)",
        "input x [deg]",
        "force F [Nm]",
    );
    // The 0.05 and 0.5 Hz loops nearly coincide (the model is
    // rate-independent and the drive reaches almost the same amplitude):
    // the slowest is drawn as a wide band under the others.
    for (i, p) in ranges.iter().enumerate() {
        let r = p.range.clone();
        let s = Series::line(&p.label, pairs(&sines.x[r.clone()], &sines.force[r]), i);
        left.series
            .push(if i == 0 { s.with_style(Style::Band) } else { s });
    }
    let mut right = Panel::new(
        "5 Hz from initial states I and II",
        "input x [deg]",
        "force F [Nm]",
    );
    if let Some(five) = ranges.iter().find(|p| p.label == "5 Hz") {
        let r = five.range.clone();
        right.series.push(
            Series::line(
                "5 Hz in sines",
                pairs(&sines.x[r.clone()], &sines.force[r]),
                7,
            )
            .with_style(Style::Band),
        );
    }
    // Wide, under the thin line of state II, which ends on the same loop.
    right.series.push(
        Series::line("initial state I", pairs(&one.1.x, &one.1.force), 1)
            .with_style(Style::ThickLine),
    );
    right.series.push(Series::line(
        "initial state II",
        pairs(&two.1.x, &two.1.force),
        0,
    ));
    // Start markers: where each run begins (x = 0, the initial force).
    let starts: Vec<Series> = [(one.1, 1usize), (two.1, 0usize)]
        .iter()
        .filter_map(|(r, c)| {
            Some(
                Series::line("", vec![(*r.x.first()?, *r.force.first()?)], *c)
                    .with_style(Style::Markers),
            )
        })
        .collect();
    right.series.extend(starts);
    // Each panel on its own scale (no fixed ranges: each fits its data):
    // the 5 Hz loops are a small part of the major loop, and on its axes
    // would fill a corner.
    [left, right]
}

fn chirp_figure((e, r): (&Experiment, &Record)) -> Result<String, PaperError> {
    let mut force = Panel::new(
        &format!("{}: force (Fig. 10)", e.name),
        "time t [s]",
        "force F [Nm]",
    );
    force
        .series
        .push(Series::line("", pairs(&r.t, &r.force), 0));
    let mut input = Panel::new(&format!("{}: input", e.name), "time t [s]", "input x [deg]");
    input.series.push(Series::line("", pairs(&r.t, &r.x), 1));
    plot::render(&[force, input], 2, 1, (1000, 720))
        .map_err(|e| PaperError::Plot("chirp.svg".into(), e))
}

fn stiffness_figure(params: &TransmissionParams) -> Result<String, PaperError> {
    let map = &params.spring.stiffness;
    let z_last = map.knots_z().last().copied().unwrap_or(0.0);
    let z_max = if z_last > 0.0 { 1.25 * z_last } else { 1.0 };
    let n = 801;
    let curve: Vec<(f64, f64)> = (0..n)
        .map(|i| {
            let z = -z_max + 2.0 * z_max * i as f64 / (n - 1) as f64;
            (z, map.eval(z).0)
        })
        .collect();
    let knots: Vec<(f64, f64)> = map
        .knots_z()
        .iter()
        .zip(map.knots_s())
        .flat_map(|(&z, &s)| [(-z, s), (z, s)])
        .collect();
    let mut p = Panel::new(
        "stiffness map S(|z|) of the spring (Fig. 8)",
        "deflection z [deg]",
        "stiffness S [Nm/deg]",
    );
    p.series
        .push(Series::line("S(|z|), piecewise linear", curve, 0).with_style(Style::ThickLine));
    p.series
        .push(Series::line("knots", knots, 1).with_style(Style::Markers));
    p.legend = plot::Legend::LowerMiddle;
    let (_, _, lo, hi) = p.data_bounds().unwrap_or((0.0, 1.0, 0.0, 1.0));
    p.y_range = Some((0.0, hi + 0.1 * (hi - lo).max(hi.abs() * 0.1).max(1e-9)));
    plot::render(&[p], 1, 1, (760, 520)).map_err(|e| PaperError::Plot("stiffness.svg".into(), e))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The right panel of loops.svg is drawn to the 5 Hz runs' own range,
    /// far smaller than the major loop's (19 Nm against about 4 Nm).
    #[test]
    fn each_loop_panel_has_its_own_scale() {
        let params = TransmissionParams::default();
        let experiments = experiments::paper_experiments(&params).unwrap();
        let run = |name: &str| {
            let e = experiments.iter().find(|e| e.name == name).unwrap();
            (e, experiments::simulate(&e.params, &e.signal).unwrap())
        };
        let (sines_e, sines) = run("sines");
        let (one_e, one) = run("sine-5hz-I");
        let (two_e, two) = run("sine-5hz-II");
        let [left, right] = loop_panels(&sines_e.parts, &sines, (one_e, &one), (two_e, &two));
        let span = |p: &Panel| {
            let b = p.data_bounds().unwrap();
            let (lo, hi) = p.y_range.unwrap_or_else(|| plot::padded(b.2, b.3));
            hi - lo
        };
        let peak_5hz = one
            .force
            .iter()
            .chain(&two.force)
            .fold(0.0_f64, |m, f| m.max(f.abs()));
        assert!(
            span(&right) < 2.5 * peak_5hz * 1.1,
            "{} vs {peak_5hz}",
            span(&right)
        );
        assert!(
            span(&right) < 0.5 * span(&left),
            "{} vs {}",
            span(&right),
            span(&left)
        );
    }

    #[test]
    fn loop_width_of_a_known_loop() {
        // One cycle of a loop whose branches meet x = 0 at F = 1 (falling)
        // and F = -1 (rising).
        let x = [0.0, 1.0, 0.0, -1.0, 0.0, 1.0];
        let f = [0.0, 2.0, 1.0, -2.0, -1.0, 2.0];
        // Crossings: 0 -> -1 falling at index 3 (x=0 exactly at index 2
        // counts as non-negative) and -1 -> 0 rising.
        let s = summarise("t", &x, &f);
        assert_eq!(s.peak_force, 2.0);
        assert_eq!(s.loop_width, Some(2.0));
        assert_eq!(s.last_width, Some(2.0));
    }
}
