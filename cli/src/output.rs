//! The error of writing a command's outputs: result files, figure
//! directories and figures. Every command that writes reports it through
//! this one type, so the messages read the same everywhere.

use crate::csvio::{self, CsvIoError};
use crate::plot::PlotError;
use std::path::PathBuf;

/// Writing an output file or drawing a figure failed.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The figure directory could not be created.
    #[error("cannot create figure directory `{}`: {}", .0.display(), csvio::one_line(&.1.to_string()))]
    PlotDir(PathBuf, std::io::Error),
    /// Writing an output failed.
    #[error("output {0}")]
    Write(CsvIoError),
    /// Drawing a figure failed.
    #[error("plot `{}`: {}", .0.display(), .1)]
    Plot(PathBuf, PlotError),
}
