//! # hysteron-cli
//!
//! The `hysteron` program's commands as a library (the binary is
//! `src/main.rs`): each command is a module with its options (its
//! command-line flags, a clap `Args` struct whose doc comment is the
//! command's about text and whose fields' doc comments are their help),
//! its run function and its report; `args`, `csvio`, `plot`,
//! `output`, `period` and `fitting` are what they share. The library facade `hysteron` depends on none of this
//! (no clap, plotters, indicatif or csv).

pub use hysteron::{composition, identify, models, operators};
pub use hysteron::{Error, Float, Operator, Result, Trial};

pub mod analyze;
pub mod args;
pub mod band;
pub mod bench;
pub mod compare;
pub mod csvio;
pub mod export_fmu;
pub mod fit_cmd;
pub mod fitting;
pub mod fmu_compat;
pub mod identify_paper;
pub mod model_file;
pub mod output;
pub mod paper;
pub mod parquet_file;
pub mod period;
pub mod plot;
pub mod reference_figures;
pub mod sensitivity;
pub mod simulate;
pub mod sobol;
pub mod sweep;
pub mod validate;
