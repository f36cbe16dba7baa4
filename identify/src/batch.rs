//! Simulating many parameter sets or many records in parallel (rayon).

use hysteron_operators::{Error, Operator, Result};
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

/// Runs `model` (from its initial state) over each input into the output
/// buffer of the same index, in parallel, allocating nothing but one model
/// clone per record. Each entry is that record's result; an input without
/// an output buffer of its length (or an output without an input) is an
/// [`Error::LengthMismatch`].
pub fn process_records(
    model: &(dyn Operator<f64> + 'static),
    inputs: &[&[f64]],
    outputs: &mut [&mut [f64]],
) -> Vec<Result<()>> {
    let n = inputs.len().max(outputs.len());
    let mut results: Vec<Result<()>> = inputs
        .par_iter()
        .zip(outputs.par_iter_mut())
        .map(|(x, y)| {
            let mut m = dyn_clone::clone_box(model);
            m.reset();
            m.process(x, y)
        })
        .collect();
    for i in results.len()..n {
        results.push(Err(Error::LengthMismatch {
            input: inputs.get(i).map_or(0, |x| x.len()),
            output: outputs.get(i).map_or(0, |y| y.len()),
        }));
    }
    results
}
