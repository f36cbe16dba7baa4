//! # hysteron-models
//!
//! Composed models built from `hysteron-operators` and
//! `hysteron-composition`. The paper's transmission model (damped bedstop
//! in series with the Bouc-Wen-like spring) and the JSON model specs are
//! planned here; see the repository README for what is done.

pub use hysteron_composition as composition;
pub use hysteron_operators as operators;
