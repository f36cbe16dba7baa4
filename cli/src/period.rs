//! Where the sample period of a model's rate-dependent nodes comes from,
//! for the commands that run models over CSV records (`simulate`, `fit`,
//! `validate`, `sensitivity`), and the rule that it is never silent.
//!
//! For a rate-dependent model (one with a `mass_spring_damper`,
//! `viscous_damper`, `lugre` or `gms` node) the period of a record is, in
//! this order:
//!
//! 1. `--dt SECONDS`;
//! 2. the step of the time column named by `--time-column NAME`;
//! 3. otherwise the spec's own `dt` and the data's own time column (one
//!    named `t` or `time`, found by its name) must agree: where the spec
//!    gives a period and the data have such a column, they must be equal
//!    within [`TIME_STEP_REL_TOL`] (the rounding of written stamps), or the
//!    command refuses with [`PeriodError::Mismatch`], naming both and the
//!    two ways to choose; where only one of them gives a period, that one
//!    is used; where neither does, the model does not build
//!    ([`SpecError::MissingPeriod`](crate::models::SpecError)).
//!
//! The period used is part of every report ([`Period`]'s `Display`). A
//! rate-independent model ignores the period: no column is looked for and
//! nothing is said, though `--dt` and `--time-column` still give the
//! seconds of `--skip` and `--lowpass`.

use crate::csvio::{self, CsvIoError, TIME_STEP_REL_TOL};
use crate::models::Spec;
use std::fmt;
use std::path::{Path, PathBuf};

/// The names (compared without case, after trimming) of a time column
/// that is found without `--time-column`.
pub const TIME_COLUMNS: [&str; 2] = ["t", "time"];

/// What the command line says about the sample period.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum DtSource {
    /// Nothing: the spec's own `dt` and the data's time column, if any
    /// (see the module docs).
    #[default]
    Spec,
    /// `--dt`: this value (seconds), for every rate-dependent node.
    Value(f64),
    /// `--time-column`: the step of this time column of each record
    /// (uniformly spaced up to the rounding of written stamps, see
    /// [`csvio::read_time_step`]).
    TimeColumn(String),
}

impl DtSource {
    /// From the CLI options `--dt` and `--time-column` (at most one given).
    pub fn from_options(dt: Option<f64>, time_column: Option<String>) -> Self {
        match (dt, time_column) {
            (Some(dt), _) => DtSource::Value(dt),
            (None, Some(c)) => DtSource::TimeColumn(c),
            (None, None) => DtSource::Spec,
        }
    }

    /// The time column this source reads, if it names one.
    pub fn time_column(&self) -> Option<&str> {
        match self {
            DtSource::TimeColumn(c) => Some(c),
            _ => None,
        }
    }
}

/// `--dt` or `--time-column`, the sample period of the rate-dependent
/// nodes, as most commands take it (flattened into their options;
/// `validate` words its `--dt` for the low-pass too).
#[derive(Debug, Clone, PartialEq, Default, clap::Args)]
pub struct SamplePeriodArgs {
    // `--dt`; its help lists the registry's rate-dependent kinds.
    #[arg(
        long,
        value_name = "SECONDS",
        conflicts_with = "time_column",
        value_parser = crate::args::positive_f64,
        allow_hyphen_values = true,
        help = dt_help()
    )]
    pub dt: Option<f64>,
    // `--time-column`.
    #[arg(long, value_name = "NAME", help = TIME_COLUMN_HELP)]
    pub time_column: Option<String>,
}

impl SamplePeriodArgs {
    /// What the two options say ([`DtSource::from_options`]).
    pub fn source(&self) -> DtSource {
        DtSource::from_options(self.dt, self.time_column.clone())
    }
}

/// The sample period a record is run at, and where it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Period {
    /// Seconds per sample (of the data; the nodes inside an `oversample`
    /// of `q` sub-steps run at `dt / q`).
    pub dt: f64,
    /// Where it came from.
    pub origin: Origin,
}

/// Where a [`Period`] came from.
#[derive(Debug, Clone, PartialEq)]
pub enum Origin {
    /// `--dt`.
    Option,
    /// The time column named by `--time-column`.
    TimeColumn(String),
    /// The spec's own `dt`; the data's time column of this name, if any,
    /// agrees with it.
    Spec(Option<String>),
    /// A time column of the data found by its name ([`TIME_COLUMNS`]), for
    /// a spec that leaves its `dt` out.
    FoundColumn(String),
}

impl fmt::Display for Period {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} s ", csvio::fmt_f64(self.dt))?;
        match &self.origin {
            Origin::Option => write!(f, "(--dt)"),
            Origin::TimeColumn(c) => write!(f, "(--time-column {c})"),
            Origin::Spec(None) => write!(f, "(the spec's dt)"),
            Origin::Spec(Some(c)) => {
                write!(f, "(the spec's dt; the data's time column `{c}` agrees)")
            }
            Origin::FoundColumn(c) => write!(f, "(the data's time column `{c}`)"),
        }
    }
}

impl Period {
    /// The spec run at this period: every rate-dependent node at `dt`
    /// (`dt / q` inside an `oversample`), except where the period is the
    /// spec's own, which is kept as written.
    pub fn apply(&self, spec: &Spec) -> Spec {
        match self.origin {
            Origin::Spec(_) => spec.clone(),
            _ => spec.with_dt(self.dt),
        }
    }
}

/// Why no sample period could be chosen for a record.
#[derive(Debug, thiserror::Error)]
pub enum PeriodError {
    /// A time column could not be read, or is not uniformly spaced.
    #[error(transparent)]
    Data(#[from] CsvIoError),
    /// A time column found by its name is not uniformly spaced, so it
    /// gives no period to check the spec's against.
    #[error(
        "{source} (`{column}` was taken for the data's time: give --dt SECONDS to choose the \
         sample period)"
    )]
    FoundNotUniform {
        /// The column.
        column: String,
        /// What is wrong with it.
        source: Box<CsvIoError>,
    },
    /// The spec's period and the data's time column disagree.
    #[error(
        "data `{}`: its time column `{column}` steps {} s, but the model's spec gives the \
         sample period {} s: choose one with --time-column {column} (the data's) or \
         --dt SECONDS",
        path.display(),
        csvio::fmt_f64(*data),
        csvio::fmt_f64(*spec)
    )]
    Mismatch {
        /// The record.
        path: PathBuf,
        /// Its time column.
        column: String,
        /// The column's step (s).
        data: f64,
        /// The spec's period at the data's rate (s).
        spec: f64,
    },
}

/// The sample period of the record at `data` for `spec`, as the module
/// docs say: `None` when nothing gives one (a rate-independent model with
/// neither `--dt` nor `--time-column`, or a rate-dependent spec that
/// leaves its `dt` out, with data that have no time column: its build
/// then says what is missing).
pub fn resolve(spec: &Spec, source: &DtSource, data: &Path) -> Result<Option<Period>, PeriodError> {
    let period = |dt, origin| Ok(Some(Period { dt, origin }));
    match source {
        DtSource::Value(dt) => return period(*dt, Origin::Option),
        DtSource::TimeColumn(c) => {
            return period(
                csvio::read_time_step(data, c)?,
                Origin::TimeColumn(c.clone()),
            )
        }
        DtSource::Spec => {}
    }
    if !spec.is_rate_dependent() {
        return Ok(None);
    }
    let stated = spec.stated_periods();
    let Some(column) = found_time_column(data)? else {
        return match stated.first() {
            Some(&dt) => period(dt, Origin::Spec(None)),
            None => Ok(None),
        };
    };
    let step = csvio::read_time_step(data, &column).map_err(|source| match source {
        e @ CsvIoError::NotUniform { .. } => PeriodError::FoundNotUniform {
            column: column.clone(),
            source: Box::new(e),
        },
        e => PeriodError::Data(e),
    })?;
    if let Some(&spec_dt) = stated
        .iter()
        .find(|&&p| (p - step).abs() > TIME_STEP_REL_TOL * step)
    {
        return Err(PeriodError::Mismatch {
            path: data.to_path_buf(),
            column,
            data: step,
            spec: spec_dt,
        });
    }
    match stated.first() {
        Some(&dt) if spec.missing_period().is_none() => period(dt, Origin::Spec(Some(column))),
        // A spec that leaves some period out takes the data's for all.
        _ => period(step, Origin::FoundColumn(column)),
    }
}

/// The spec as it runs over the record at `data` ([`resolve`], then
/// [`Period::apply`]), and the period to report: `None` for a
/// rate-independent model, which ignores it.
pub fn for_record(
    spec: &Spec,
    source: &DtSource,
    data: &Path,
) -> Result<(Spec, Option<Period>), PeriodError> {
    let period = resolve(spec, source, data)?;
    let run = period
        .as_ref()
        .map_or_else(|| spec.clone(), |p| p.apply(spec));
    Ok((run, period.filter(|_| spec.is_rate_dependent())))
}

/// The header of the record's time column found by its name
/// ([`TIME_COLUMNS`]), if it has one.
fn found_time_column(data: &Path) -> Result<Option<String>, CsvIoError> {
    let reader = csvio::CsvReader::open(data)?;
    Ok(reader
        .headers()
        .iter()
        .find(|h| {
            let h = h.trim();
            TIME_COLUMNS.iter().any(|t| h.eq_ignore_ascii_case(t))
        })
        .map(|h| h.trim().to_string()))
}

/// The registered leaves that are rate-dependent (they declare a sample
/// period `dt`), as the help of `--dt` lists them.
pub fn rate_dependent_kinds() -> Vec<&'static str> {
    crate::models::spec::registry::LEAVES
        .iter()
        .filter(|l| l.is_rate_dependent())
        .map(|l| l.kind())
        .collect()
}

/// The help of `--dt`, with the rate-dependent kinds of the registry.
pub fn dt_help() -> String {
    format!(
        "Sample period (s, positive and finite) of every rate-dependent node of the model \
         ({}; inside an oversample of q sub-steps, dt/q), overriding the spec's dt and any \
         time column of the data",
        rate_dependent_kinds().join(", ")
    )
}

/// The help of `--time-column`.
pub const TIME_COLUMN_HELP: &str = "Take the sample period (as for --dt) from this time column \
     of the data (uniformly spaced up to 0.1 % of a step, the rounding of written stamps), \
     overriding the spec's dt. Without --dt or --time-column, a rate-dependent model runs at \
     its spec's dt, which a column named t or time must agree with, or else at that column's \
     step";
