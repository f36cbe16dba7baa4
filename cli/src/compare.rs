//! `hysteron compare`: fits candidate structures on training records,
//! scores each on held-out records with the metrics of `validate`, and
//! ranks them.
//!
//! Each candidate is a spec and the parameters to free (a JSON file of
//! candidates, paths relative to it). A candidate is fitted exactly as
//! `hysteron fit` fits it ([`fit_cmd::run`]: multi-start, the budget, the
//! sample period), its fitted spec written to the work folder, then
//! validated exactly as `hysteron validate` does ([`validate::run`]). The
//! candidates run in parallel. A candidate that fails (a spec that does not
//! build, a name that matches no parameter, a model error at some sample)
//! gets its error in its row; the others go on.
//!
//! The table gives, per candidate:
//! * `k`, the free parameters, and the training cost `½ Σ r²` over the `n`
//!   scored training samples;
//! * `AIC = n ln(RSS/n) + 2k` and `BIC = n ln(RSS/n) + k ln n` with
//!   `RSS = 2 · cost` (Gaussian residuals of unknown variance; `RSS/n` is
//!   floored at the smallest positive normal number, so an exact fit has a
//!   finite criterion);
//! * the held-out NRMSE (`validate`'s: RMS error over the RMS of the data),
//!   full band and low-passed, mean and worst over the validation records;
//! * the rank, by the held-out mean (low-passed where `--lowpass` is
//!   given), and a two-sided sign test of each candidate against the next
//!   one in the ranking over the per-record held-out errors: `p` is the
//!   probability of a split at least as uneven if neither were better.
//!
//! The criteria, the folds, the ranking and the test are the library's
//! ([`crate::identify::selection`]), which Python's `compare` uses too.

use crate::args;
use crate::band::BandArgs;
use crate::csvio;
use crate::fit_cmd::{self, FitCmdOptions, JACOBIAN, PATIENCE, SPREAD};
use crate::fitting::ProgressArgs;
use crate::identify::selection::{self, rank, Outcome};
use crate::output::OutputError;
use crate::period::SamplePeriodArgs;
use crate::plot::{self, Panel, Series, Style};
use crate::validate::{self, ScoredColumns, ValidateOptions};
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;
use serde::Deserialize;
use std::fmt;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

/// One candidate structure: a spec and what to fit; an entry of the
/// candidates file.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Candidate {
    /// Its name in the table (letters, digits, `-`, `_`; unique).
    pub name: String,
    /// The spec; its values are the start. In the file, relative to the
    /// file's folder.
    pub model: PathBuf,
    /// The parameters to fit (full names or unique suffixes).
    pub free: Vec<String>,
    /// Parameters fitted per record (`fit --own`; none if left out).
    #[serde(default)]
    pub own: Vec<String>,
}

/// The candidates file: `{"candidates": [{"name", "model", "free", "own"?}]}`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct CandidatesFile {
    candidates: Vec<Candidate>,
}

/// Compare candidate structures: fit each (a spec and the parameters
/// to free, listed in a JSON file) on the training records as `fit`
/// does, score it on the held-out records as `validate` does, and
/// rank the candidates by their held-out mean NRMSE (low-passed with
/// --lowpass). Prints one table: k, training cost, AIC and BIC on
/// training, held-out NRMSE mean and worst (full band and low-passed),
/// the rank, and a sign test against the next rank. A candidate that
/// fails is reported in its row; the others go on.
#[derive(Debug, Clone, PartialEq, clap::Args)]
pub struct CompareOptions {
    /// The candidates: {"candidates": [{"name": "...", "model":
    /// "SPEC.json", "free": ["f_c", ...], "own": [...]}]}, model paths
    /// relative to this file; at least two.
    #[arg(long, value_name = "CANDIDATES.json")]
    pub candidates: PathBuf,
    /// A training record (CSV or .csv.gz); repeat for several.
    #[arg(long, value_name = "DATA.csv", required = true)]
    pub train: Vec<PathBuf>,
    /// A held-out record; repeat for several (or --cross-validate).
    #[arg(
        long,
        value_name = "DATA.csv",
        required_unless_present = "cross_validate"
    )]
    pub validate: Vec<PathBuf>,
    /// Instead of --validate: K-fold cross-validation over the --train
    /// records (record i held out in fold i mod K, scored by the fit on
    /// the other folds; the training figures come from the fit on all).
    #[arg(long, value_name = "K", value_parser = args::at_least_1, allow_negative_numbers = true)]
    pub cross_validate: Option<usize>,
    /// The input and measured output columns of every record.
    #[command(flatten)]
    pub columns: ScoredColumns,
    /// Also score after `validate`'s zero-phase low-pass at HZ, and
    /// rank by it. Needs --time-column or --dt.
    #[arg(long, value_name = "HZ", value_parser = args::positive_f64, allow_hyphen_values = true)]
    pub lowpass: Option<f64>,
    /// Where the sample period comes from.
    #[command(flatten)]
    pub period: SamplePeriodArgs,
    /// Simulate but do not score the first SECONDS of each record.
    #[arg(long, value_name = "SECONDS", value_parser = args::non_negative_f64, allow_hyphen_values = true)]
    pub skip: Option<f64>,
    /// Fit each candidate from N starting points (as `fit --starts`).
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = args::at_least_1, allow_negative_numbers = true)]
    pub starts: usize,
    /// Seed of the starting points.
    #[arg(long, value_name = "K", default_value_t = 0)]
    pub seed: u64,
    /// Wall-time limit of each candidate's search, in seconds.
    #[arg(long, value_name = "SECONDS", value_parser = args::positive_f64, allow_hyphen_values = true)]
    pub max_seconds: Option<f64>,
    /// Where the fitted specs go, one NAME.json per candidate (created
    /// if missing).
    #[arg(long, value_name = "DIR")]
    pub work_dir: PathBuf,
    /// Also write the table as CSV (written atomically).
    #[arg(long, value_name = "OUT.csv")]
    pub csv: Option<PathBuf>,
    /// Also draw each candidate's held-out NRMSE per record (SVG).
    #[arg(long, value_name = "OUT.svg")]
    pub plot: Option<PathBuf>,
    /// Do not draw the progress bar (it is only drawn when stderr is a
    /// terminal anyway).
    #[arg(long)]
    pub no_progress: bool,
}

/// An error of the compare job as a whole (a candidate's own failure is in
/// its row instead).
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    /// The candidates file could not be read.
    #[error("candidates `{}`: {}", .0.display(), .1)]
    Read(PathBuf, String),
    /// The candidates file is not a valid list of candidates.
    #[error("candidates `{}`: {}", .0.display(), .1)]
    Invalid(PathBuf, String),
    /// No training or no validation record.
    #[error("{0}: give at least one record (or --cross-validate K over the --train records)")]
    NoRecords(&'static str),
    /// `--cross-validate K` outside `2 ≤ K ≤` the training records.
    #[error("--cross-validate {0}: K must be at least 2 and at most the {1} --train records")]
    Folds(usize, usize),
    /// `--cross-validate` with `--validate`.
    #[error("--cross-validate folds the --train records; give no --validate with it")]
    FoldsAndValidate,
    /// The work folder could not be made.
    #[error("cannot create the work folder `{}`: {}", .0.display(), .1)]
    WorkDir(PathBuf, String),
    /// Writing the table or the figure, or drawing the figure, failed.
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// Reads a candidates file; model paths are taken relative to its folder.
pub fn read_candidates(path: &Path) -> Result<Vec<Candidate>, CompareError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| CompareError::Read(path.to_path_buf(), csvio::one_line(&e.to_string())))?;
    let file: CandidatesFile = serde_json::from_str(&text)
        .map_err(|e| CompareError::Invalid(path.to_path_buf(), e.to_string()))?;
    let invalid = |msg: String| CompareError::Invalid(path.to_path_buf(), msg);
    if file.candidates.len() < 2 {
        return Err(invalid(format!(
            "give at least two candidates to compare (got {})",
            file.candidates.len()
        )));
    }
    let base = path.parent().unwrap_or_else(|| Path::new(""));
    let mut out: Vec<Candidate> = Vec::with_capacity(file.candidates.len());
    for (i, c) in file.candidates.into_iter().enumerate() {
        let ok_name = !c.name.is_empty()
            && c.name
                .chars()
                .all(|ch| ch.is_ascii_alphanumeric() || ch == '-' || ch == '_');
        if !ok_name {
            return Err(invalid(format!(
                "candidates[{i}].name: letters, digits, `-` and `_` only, not empty (got {:?})",
                c.name
            )));
        }
        if out.iter().any(|o| o.name == c.name) {
            return Err(invalid(format!(
                "candidates[{i}].name: `{}` is used twice",
                c.name
            )));
        }
        if c.free.is_empty() {
            return Err(invalid(format!(
                "candidates[{i}].free: name at least one parameter"
            )));
        }
        out.push(Candidate {
            model: base.join(&c.model),
            ..c
        });
    }
    Ok(out)
}

/// What a candidate's fit and validation gave: the library's outcome
/// (training figures, held-out NRMSE per record), the records it was
/// scored on, and the fitted spec.
#[derive(Debug, Clone, PartialEq)]
pub struct Scores {
    /// Training figures and held-out scores, one per entry of `records`.
    pub outcome: Outcome,
    /// The scored records, in the order of `outcome.held_out`.
    pub records: Vec<PathBuf>,
    /// The fitted spec.
    pub fitted: PathBuf,
}

/// One row of the table: a candidate and its scores or its error.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// The candidate's name.
    pub name: String,
    /// Its scores, or why it has none.
    pub result: Result<Scores, String>,
    /// Its rank (1 = best held-out mean; `None` for a failed candidate).
    pub rank: Option<usize>,
    /// The sign test against the next candidate in the ranking.
    pub p_next: Option<f64>,
}

/// What the compare job did: the rows in ranking order (failed candidates
/// last).
#[derive(Debug, Clone, PartialEq)]
pub struct CompareReport {
    /// The rows, best first.
    pub rows: Vec<Row>,
    /// Whether the ranking is by the low-passed NRMSE.
    pub by_lowpassed: bool,
    /// Files written.
    pub files: Vec<PathBuf>,
}

/// A bar of the candidates done, drawn when `wanted` and stderr is a
/// terminal (hidden otherwise: then each candidate's line is printed).
fn progress_bar(n: usize, wanted: bool) -> ProgressBar {
    if !(wanted && std::io::stderr().is_terminal()) {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(n as u64);
    if let Ok(style) = ProgressStyle::with_template(
        "{bar:30} {pos}/{len} candidates fitted and scored [{elapsed}]",
    ) {
        bar.set_style(style);
    }
    bar
}

/// Fits a candidate on `records`, writing the fitted spec to `output`
/// (with `fit`'s defaults for what `compare` does not set).
fn fit_on(
    c: &Candidate,
    records: &[PathBuf],
    output: &Path,
    opts: &CompareOptions,
) -> Result<fit_cmd::FitCmdReport, String> {
    fit_cmd::run(&FitCmdOptions {
        model: c.model.clone(),
        data: records.to_vec(),
        input_column: opts.columns.input_column.clone(),
        output_column: opts.columns.output_column.clone(),
        free: c.free.clone(),
        own: c.own.clone(),
        skip: opts.skip,
        max_evaluations: None,
        max_seconds: opts.max_seconds,
        output: output.to_path_buf(),
        plot: None,
        patience: PATIENCE,
        jacobian: JACOBIAN,
        starts: opts.starts,
        spread: SPREAD,
        seed: opts.seed,
        progress: ProgressArgs { no_progress: true },
        period: opts.period.clone(),
        band: None,
        covariance: None,
        band_args: BandArgs::default(),
    })
    .map_err(|e| format!("fit: {e}"))
}

/// Scores the fitted spec `model` on `records` as `validate` does:
/// `(NRMSE, low-passed NRMSE)` per record.
fn held_out_on(
    model: &Path,
    records: &[PathBuf],
    opts: &CompareOptions,
) -> Result<Vec<(f64, Option<f64>)>, String> {
    let validated = validate::run(&ValidateOptions {
        model: model.to_path_buf(),
        data: records.to_vec(),
        columns: opts.columns.clone(),
        lowpass: opts.lowpass,
        dt: opts.period.dt,
        time_column: opts.period.time_column.clone(),
        skip: opts.skip,
        plot: None,
        csv: None,
        covariance: None,
        band_args: BandArgs::default(),
    })
    .map_err(|e| format!("validate: {e}"))?;
    validated
        .rows
        .iter()
        .map(|r| {
            let nrmse = r.figures.nrmse;
            if nrmse.is_finite() {
                Ok((nrmse, r.lowpassed_nrmse))
            } else {
                Err(format!(
                    "validate: `{}` has a measured output of RMS 0 (no NRMSE)",
                    r.record.display()
                ))
            }
        })
        .collect()
}

/// Fits and scores one candidate: fitted on every training record (the
/// training figures and the fitted spec), and scored on the held-out
/// records, or with `--cross-validate K` on each record from the fit on
/// the other folds (`NAME.foldF.json`).
fn score(c: &Candidate, opts: &CompareOptions) -> Result<Scores, String> {
    let fitted = opts.work_dir.join(format!("{}.json", c.name));
    let fit = fit_on(c, &opts.train, &fitted, opts)?;
    let (held_out, records) = match opts.cross_validate {
        None => (
            held_out_on(&fitted, &opts.validate, opts)?,
            opts.validate.clone(),
        ),
        Some(k) => {
            let mut fold = 0;
            let scores = selection::cross_validated(opts.train.len(), k, |rest, held| {
                fold += 1;
                let pick = |ix: &[usize]| -> Vec<PathBuf> {
                    ix.iter()
                        .filter_map(|&i| opts.train.get(i).cloned())
                        .collect()
                };
                let out = opts.work_dir.join(format!("{}.fold{fold}.json", c.name));
                fit_on(c, &pick(rest), &out, opts)?;
                held_out_on(&out, &pick(held), opts)
            })?;
            (scores, opts.train.clone())
        }
    };
    Ok(Scores {
        outcome: Outcome::of_fit(&fit.report, held_out),
        records,
        fitted,
    })
}

/// Runs the job: fits and scores every candidate (in parallel), ranks
/// them, and writes the CSV.
pub fn run(opts: &CompareOptions) -> Result<CompareReport, CompareError> {
    if opts.train.is_empty() {
        return Err(CompareError::NoRecords("--train"));
    }
    match opts.cross_validate {
        None if opts.validate.is_empty() => {
            return Err(CompareError::NoRecords("--validate"));
        }
        Some(k) if k < 2 || k > opts.train.len() => {
            return Err(CompareError::Folds(k, opts.train.len()));
        }
        Some(_) if !opts.validate.is_empty() => return Err(CompareError::FoldsAndValidate),
        _ => {}
    }
    let candidates = read_candidates(&opts.candidates)?;
    std::fs::create_dir_all(&opts.work_dir).map_err(|e| {
        CompareError::WorkDir(opts.work_dir.clone(), csvio::one_line(&e.to_string()))
    })?;
    let bar = progress_bar(candidates.len(), !opts.no_progress);
    let results: Vec<Result<Scores, String>> = candidates
        .par_iter()
        .map(|c| {
            let r = score(c, opts);
            let line = format!(
                "compare: `{}` {}",
                c.name,
                if r.is_ok() { "done" } else { "failed" }
            );
            if bar.is_hidden() {
                eprintln!("{line}");
            } else {
                bar.println(line);
            }
            bar.inc(1);
            r
        })
        .collect();
    bar.finish_and_clear();
    let mut rows: Vec<Row> = candidates
        .iter()
        .zip(results)
        .map(|(c, result)| Row {
            name: c.name.clone(),
            result,
            rank: None,
            p_next: None,
        })
        .collect();
    let by_lowpassed = opts.lowpass.is_some();
    let errors: Vec<Option<Vec<f64>>> = rows
        .iter()
        .map(|r| r.result.as_ref().ok().map(|s| s.outcome.ranking_errors()))
        .collect();
    let ranking = rank(&errors);
    for (i, row) in rows.iter_mut().enumerate() {
        row.rank = ranking.rank.get(i).copied().flatten();
        row.p_next = ranking.p_next.get(i).copied().flatten();
    }
    let mut slots: Vec<Option<Row>> = rows.into_iter().map(Some).collect();
    let rows: Vec<Row> = ranking
        .order
        .iter()
        .filter_map(|&i| slots.get_mut(i).and_then(Option::take))
        .collect();
    let mut files: Vec<PathBuf> = rows
        .iter()
        .filter_map(|r| r.result.as_ref().ok().map(|s| s.fitted.clone()))
        .collect();
    let report = CompareReport {
        rows,
        by_lowpassed,
        files: Vec::new(),
    };
    if let Some(csv) = &opts.csv {
        csvio::write_string_atomic(csv, &report.csv()).map_err(OutputError::Write)?;
        files.push(csv.clone());
    }
    if let Some(path) = &opts.plot {
        let svg = plot::render(&[report.panel()], 1, 1, (900, 520))
            .map_err(|e| OutputError::Plot(path.clone(), e))?;
        csvio::write_string_atomic(path, &svg).map_err(OutputError::Write)?;
        files.push(path.clone());
    }
    Ok(CompareReport { files, ..report })
}

/// The CSV header of `--csv` (the library's column names).
pub const CSV_HEADER: [&str; 14] = selection::COLUMNS;

/// A cell: shortest round-trip, empty for none.
fn num(v: Option<f64>) -> String {
    v.map_or_else(String::new, |v| format!("{v}"))
}

/// A CSV cell: quoted when it holds a comma, a quote or a line break.
fn text_cell(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

impl CompareReport {
    /// The figure's panel: each ranked candidate's held-out error (the
    /// ranking's: low-passed with `--lowpass`) over the validation
    /// records, numbered in the order given.
    pub fn panel(&self) -> Panel {
        let what = if self.by_lowpassed {
            "held-out low-passed NRMSE"
        } else {
            "held-out NRMSE"
        };
        let mut p = Panel::new(
            &format!("{what} per record, candidates by rank"),
            "validation record (in the order given)",
            what,
        );
        for (i, r) in self.rows.iter().enumerate() {
            if let Ok(s) = &r.result {
                let points: Vec<(f64, f64)> = s
                    .outcome
                    .ranking_errors()
                    .into_iter()
                    .enumerate()
                    .map(|(j, e)| ((j + 1) as f64, e))
                    .collect();
                let label = format!("{}. {}", r.rank.unwrap_or(i + 1), r.name);
                p.series
                    .push(Series::line(label.clone(), points.clone(), i));
                p.series
                    .push(Series::line("", points, i).with_style(Style::Markers));
            }
        }
        p
    }

    /// The table as CSV ([`CSV_HEADER`]), one line per candidate.
    pub fn csv(&self) -> String {
        let mut out = CSV_HEADER.join(",");
        out.push('\n');
        for r in &self.rows {
            let cells: Vec<String> = match &r.result {
                Ok(s) => {
                    let (mean, worst) = s.outcome.full_band();
                    let low = s.outcome.lowpassed();
                    vec![
                        r.rank.map_or_else(String::new, |k| k.to_string()),
                        text_cell(&r.name),
                        s.outcome.k.to_string(),
                        s.outcome.n.to_string(),
                        num(Some(s.outcome.cost)),
                        num(Some(s.outcome.aic)),
                        num(Some(s.outcome.bic)),
                        num(Some(mean)),
                        num(Some(worst)),
                        num(low.map(|l| l.0)),
                        num(low.map(|l| l.1)),
                        num(r.p_next),
                        s.outcome.converged.to_string(),
                        String::new(),
                    ]
                }
                Err(e) => {
                    let mut v = vec![String::new(), text_cell(&r.name)];
                    v.extend(std::iter::repeat_n(String::new(), 11));
                    v.push(text_cell(e));
                    v
                }
            };
            out.push_str(&cells.join(","));
            out.push('\n');
        }
        out
    }
}

/// 4 significant digits (scientific notation below 1e-3 and from 1e5).
fn short(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || !a.is_finite() {
        return format!("{v}");
    }
    if !(1e-3..1e5).contains(&a) {
        return format!("{v:.3e}");
    }
    let decimals = (3 - a.log10().floor() as i32).max(0) as usize;
    format!("{v:.decimals$}")
}

impl fmt::Display for CompareReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let by = if self.by_lowpassed {
            "held-out low-passed NRMSE, mean"
        } else {
            "held-out NRMSE, mean"
        };
        writeln!(
            f,
            "ranked by {by}; p: sign test against the next rank over the held-out records"
        )?;
        writeln!(
            f,
            "| rank | candidate | k | training cost | AIC | BIC | held-out NRMSE mean | worst | low-passed mean | worst | p vs next |"
        )?;
        writeln!(f, "|---|---|---|---|---|---|---|---|---|---|---|")?;
        for r in &self.rows {
            match &r.result {
                Ok(s) => {
                    let (mean, worst) = s.outcome.full_band();
                    let (lm, lw) = s
                        .outcome
                        .lowpassed()
                        .map_or(("".into(), "".into()), |(a, b)| (short(a), short(b)));
                    let note = if s.outcome.converged {
                        ""
                    } else {
                        " (not converged)"
                    };
                    writeln!(
                        f,
                        "| {} | {}{note} | {} | {} | {} | {} | {} | {} | {lm} | {lw} | {} |",
                        r.rank.map_or_else(String::new, |k| k.to_string()),
                        r.name,
                        s.outcome.k,
                        short(s.outcome.cost),
                        short(s.outcome.aic),
                        short(s.outcome.bic),
                        short(mean),
                        short(worst),
                        r.p_next.map_or_else(String::new, short),
                    )?;
                }
                Err(e) => writeln!(f, "| | {} | failed: {} |", r.name, e.replace('|', "\\|"))?,
            }
        }
        for file in &self.files {
            writeln!(f, "wrote {}", file.display())?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_keeps_four_significant_digits() {
        assert_eq!(short(-21064.2559), "-21064");
        assert_eq!(short(0.021828), "0.02183");
        assert_eq!(short(1.3371), "1.337");
        assert_eq!(short(2.5e-5), "2.500e-5");
        assert_eq!(short(0.0), "0");
    }
}
