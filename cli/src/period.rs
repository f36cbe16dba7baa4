//! Where the sample period of a model's rate-dependent nodes comes from,
//! for the commands that run models over CSV records (`simulate`, `fit`).

use crate::csvio::{self, CsvIoError};
use crate::models::Spec;
use std::path::Path;

/// Where the sample period of a model's rate-dependent nodes
/// (`mass_spring_damper`, `viscous_damper`) comes from; it overrides every
/// `dt` of the spec ([`Spec::with_dt`], which gives the nodes inside an
/// `oversample` of `q` sub-steps `dt / q`).
#[derive(Debug, Clone, PartialEq, Default)]
pub enum DtSource {
    /// The spec's own values.
    #[default]
    Spec,
    /// This value (seconds).
    Value(f64),
    /// The step of this time column of the input CSV file (uniformly
    /// spaced up to the rounding of written stamps, see
    /// [`csvio::read_time_step`]).
    TimeColumn(String),
}

impl DtSource {
    /// The spec with the sample period applied (`data` is the CSV file a
    /// time column is read from).
    pub fn apply(&self, spec: Spec, data: &Path) -> Result<Spec, CsvIoError> {
        Ok(match self {
            DtSource::Spec => spec,
            DtSource::Value(dt) => spec.with_dt(*dt),
            DtSource::TimeColumn(column) => spec.with_dt(csvio::read_time_step(data, column)?),
        })
    }

    /// From the CLI options `--dt` and `--time-column` (at most one given).
    pub fn from_options(dt: Option<f64>, time_column: Option<String>) -> Self {
        match (dt, time_column) {
            (Some(dt), _) => DtSource::Value(dt),
            (None, Some(c)) => DtSource::TimeColumn(c),
            (None, None) => DtSource::Spec,
        }
    }
}
