//! The `sobol` job: which parameters of a model spec (JSON, see
//! [`Spec`](crate::models::Spec)) matter for a scalar statistic of its
//! output over one input column: the Sobol first-order and total indices
//! ([`sobol`]), each factor uniform within its bounds, the other
//! parameters at the spec's values.
//!
//! * The factors (`--factor NAME=LOW:HIGH`, repeated) name parameters as
//!   the built model's
//!   [`param_names`](hysteron::Parameters::param_names) (`left.mms.f_c`) or
//!   by a unique suffix after a dot (`f_c`), as `fit --free` takes them.
//! * The statistic (`--statistic`): the loop energy `|∮ y dx|` over the
//!   record (closed polygon, trapezoid rule), the signed work `∮ y dx`,
//!   the peak `max |y|`, the RMS or the mean of `y`.
//! * `N` base samples (`--samples`, a power of two) make `N (k + 2)` runs
//!   of the model over the whole input, through one ensemble (play and MMS
//!   leaves, PI banks of fewer than 64 plays not a multiple of eight,
//!   Bouc-Wen springs with `n = 1` and the Bouc-Wen benchmark system eight
//!   per vector instruction).
//!
//! The table is printed; with `--output` it is also written as CSV
//! (`factor,low,high,first,total`, one row per factor), atomically, and
//! may not be the input or the model file.

use crate::csvio::{self, csv_write_error};
use crate::identify::sobol::{sobol, Factor, SobolError, SobolIndices, SobolOptions, Statistic};
use crate::output::OutputError;
use crate::period::{Period, SamplePeriodArgs};
use crate::simulate::{RecordInput, SimulateError};
use std::fmt;
use std::path::PathBuf;

/// The statistic of a run, by name on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum StatisticArg {
    /// The loop energy |∮ y dx| over the record (its closed polygon,
    /// trapezoid rule).
    Energy,
    /// The signed work ∮ y dx (> 0 for clockwise loops).
    Work,
    /// The peak max |y|.
    Peak,
    /// The root mean square of y.
    Rms,
    /// The mean of y.
    Mean,
}

impl StatisticArg {
    /// The library's statistic.
    pub fn statistic(self) -> Statistic {
        match self {
            StatisticArg::Energy => Statistic::Energy,
            StatisticArg::Work => Statistic::Work,
            StatisticArg::Peak => Statistic::Peak,
            StatisticArg::Rms => Statistic::Rms,
            StatisticArg::Mean => Statistic::Mean,
        }
    }

    fn describe(self) -> &'static str {
        match self {
            StatisticArg::Energy => "the loop energy |∮ y dx|",
            StatisticArg::Work => "the work ∮ y dx",
            StatisticArg::Peak => "the peak max |y|",
            StatisticArg::Rms => "the RMS of y",
            StatisticArg::Mean => "the mean of y",
        }
    }
}

/// Global sensitivity of a model spec (JSON): which parameters matter
/// for a scalar statistic of its output over one column of a CSV file
/// (the loop energy |∮ y dx|, the work, the peak |y|, the RMS or the
/// mean of y). Each factor (--factor NAME=LOW:HIGH) is uniform within
/// its bounds, the others keep the spec's values; prints the Sobol
/// first-order index S_i (the share of the statistic's variance the
/// factor explains alone) and total index S_Ti (with its
/// interactions), from N (k + 2) runs on a scrambled Sobol sequence
/// (Saltelli design and estimators).
#[derive(Debug, Clone, PartialEq, clap::Args)]
pub struct SobolCmdOptions {
    /// The model, and the input column it runs over.
    #[command(flatten)]
    pub record: RecordInput,
    /// A factor and its bounds, NAME=LOW:HIGH (full name, left.mms.f_c, or
    /// unique suffix, f_c), uniform between the bounds; repeat for each
    /// factor. The other parameters keep the spec's values.
    #[arg(
        long = "factor",
        value_name = "NAME=LOW:HIGH",
        required = true,
        value_parser = parse_factor,
        allow_hyphen_values = true
    )]
    pub factors: Vec<Factor>,
    /// The statistic of each run's output.
    #[arg(long, value_enum, default_value_t = StatisticArg::Energy)]
    pub statistic: StatisticArg,
    /// Base samples N, a power of two from 16 to 65536: the model runs
    /// N (k + 2) times for k factors.
    #[arg(long, value_name = "N", default_value_t = 1024, value_parser = crate::args::sobol_samples)]
    pub samples: usize,
    /// The scramble of the Sobol sequence (another seed, another
    /// independent estimate).
    #[arg(long, value_name = "S", default_value_t = 0)]
    pub seed: u32,
    /// Also write the table as CSV: factor,low,high,first,total.
    #[arg(long, value_name = "OUT.csv")]
    pub output: Option<PathBuf>,
    /// The sample period of a rate-dependent model.
    #[command(flatten)]
    pub period: SamplePeriodArgs,
}

/// `NAME=LOW:HIGH` as a [`Factor`] (the bounds are checked with the
/// model: finite, `LOW < HIGH`).
pub fn parse_factor(s: &str) -> Result<Factor, String> {
    let (name, bounds) = s
        .split_once('=')
        .ok_or_else(|| format!("`{s}` is not NAME=LOW:HIGH"))?;
    let (low, high) = bounds
        .split_once(':')
        .ok_or_else(|| format!("`{s}` is not NAME=LOW:HIGH"))?;
    let number = |v: &str| {
        v.trim()
            .parse::<f64>()
            .map_err(|_| format!("`{s}`: `{}` is not a number", v.trim()))
    };
    let name = name.trim();
    if name.is_empty() {
        return Err(format!("`{s}`: no parameter name before `=`"));
    }
    Ok(Factor::new(name, number(low)?, number(high)?))
}

/// An error of the sobol job (one line naming the file, the factor or the
/// run).
#[derive(Debug, thiserror::Error)]
pub enum SobolCmdError {
    /// The model, the input or the output (as `simulate` reads and writes
    /// them).
    #[error(transparent)]
    Record(#[from] SimulateError),
    /// The estimate refused a factor, the samples, the input or a run.
    #[error("model `{}`: {error}", model.display())]
    Sobol {
        /// The model file.
        model: PathBuf,
        /// What the estimate said.
        error: SobolError,
    },
}

/// What the sobol job found.
#[derive(Debug, Clone, PartialEq)]
pub struct SobolCmdReport {
    /// The statistic.
    pub statistic: StatisticArg,
    /// The factors as given.
    pub factors: Vec<Factor>,
    /// The indices.
    pub indices: SobolIndices,
    /// Samples of the input.
    pub input_samples: usize,
    /// The sample period (`None` for a rate-independent model).
    pub period: Option<Period>,
    /// Files written.
    pub files: Vec<PathBuf>,
}

impl fmt::Display for SobolCmdReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.indices;
        write!(
            f,
            "Sobol indices of {} over {} input samples: N = {} base samples, {} runs",
            self.statistic.describe(),
            self.input_samples,
            s.samples,
            s.evaluations
        )?;
        if let Some(p) = &self.period {
            write!(f, " at a sample period of {p}")?;
        }
        writeln!(f)?;
        writeln!(
            f,
            "statistic: mean {:.6e}, variance {:.6e}",
            s.mean, s.variance
        )?;
        let width = s.names.iter().map(|n| n.len()).max().unwrap_or(0).max(6);
        writeln!(
            f,
            "| {:<width$} | {:>11} | {:>11} | {:>8} | {:>8} |",
            "factor", "low", "high", "first", "total"
        )?;
        write!(
            f,
            "|{}|{}|{}|{}|{}|",
            "-".repeat(width + 2),
            "-".repeat(13),
            "-".repeat(13),
            "-".repeat(10),
            "-".repeat(10)
        )?;
        for (((name, factor), first), total) in s
            .names
            .iter()
            .zip(&self.factors)
            .zip(&s.first)
            .zip(&s.total)
        {
            write!(
                f,
                "\n| {name:<width$} | {:>11} | {:>11} | {first:>8.4} | {total:>8.4} |",
                csvio::fmt_f64(factor.low),
                csvio::fmt_f64(factor.high)
            )?;
        }
        if !self.files.is_empty() {
            write!(f, "\nwrote {}", csvio::join_paths(&self.files))?;
        }
        Ok(())
    }
}

/// Runs the estimate; see the module docs.
pub fn run(opts: &SobolCmdOptions) -> Result<SobolCmdReport, SobolCmdError> {
    let record = &opts.record;
    if let Some(out) = &opts.output {
        record.refuse_overwrite(out, None)?;
    }
    let loaded = record.load_model(&opts.period)?;
    let columns =
        csvio::read_columns(&record.input, &[&record.column]).map_err(SimulateError::Input)?;
    let x = columns.values.first().map_or(&[][..], |c| &c[..]);
    let options = SobolOptions {
        samples: opts.samples,
        seed: opts.seed,
    };
    let indices = sobol(
        &loaded.spec,
        x,
        &opts.factors,
        &opts.statistic.statistic(),
        &options,
    )
    .map_err(|error| SobolCmdError::Sobol {
        model: record.model.clone(),
        error,
    })?;
    let mut files = Vec::new();
    if let Some(out) = &opts.output {
        write_table(out, &opts.factors, &indices)?;
        files.push(out.clone());
    }
    Ok(SobolCmdReport {
        statistic: opts.statistic,
        factors: opts.factors.clone(),
        indices,
        input_samples: x.len(),
        period: loaded.period,
        files,
    })
}

/// `factor,low,high,first,total`, one row per factor (full names).
fn write_table(
    path: &std::path::Path,
    factors: &[Factor],
    s: &SobolIndices,
) -> Result<(), SimulateError> {
    let wrap = |e| SimulateError::Output(OutputError::Write(e));
    csvio::write_csv_atomic_with(path, wrap, |out| {
        let row = |out: &mut csv::Writer<_>, fields: &[String]| {
            out.write_record(fields)
                .map_err(|e| wrap(csv_write_error(path, e)))
        };
        row(
            out,
            &["factor", "low", "high", "first", "total"].map(String::from),
        )?;
        for (((name, factor), first), total) in
            s.names.iter().zip(factors).zip(&s.first).zip(&s.total)
        {
            row(
                out,
                &[
                    name.clone(),
                    csvio::fmt_f64(factor.low),
                    csvio::fmt_f64(factor.high),
                    csvio::fmt_f64(*first),
                    csvio::fmt_f64(*total),
                ],
            )?;
        }
        Ok(())
    })
}
