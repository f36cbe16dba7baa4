//! Simulating many parameter sets or many records in parallel (rayon).

use hysteron_operators::{Operator, Result};
use rayon::prelude::*;

/// Runs `model` with each parameter vector in `sets` over `x` (each from
/// the initial state), in parallel. Each entry is that run's output or
/// error.
pub fn simulate_parameter_sets(
    model: &(dyn Operator<f64> + 'static),
    sets: &[Vec<f64>],
    x: &[f64],
) -> Vec<Result<Vec<f64>>> {
    sets.par_iter()
        .map(|p| {
            let mut m = dyn_clone::clone_box(model);
            m.set_params(p)?;
            m.run(x)
        })
        .collect()
}

/// Runs `model` (from its initial state) over each record, in parallel.
pub fn simulate_records(
    model: &(dyn Operator<f64> + 'static),
    records: &[Vec<f64>],
) -> Vec<Result<Vec<f64>>> {
    records
        .par_iter()
        .map(|x| {
            let mut m = dyn_clone::clone_box(model);
            m.reset();
            m.run(x)
        })
        .collect()
}
