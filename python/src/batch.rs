//! Many records or parameter sets through one model, in parallel (rayon),
//! with the GIL released.

use crate::array::samples;
use crate::errors::{operator_error, HysteronError, InputError};
use crate::model::Model;
use hysteron::identify::batch::{simulate_parameter_sets, simulate_records};
use hysteron::Result as RustResult;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Runs `work` on a pool of `threads` threads, or rayon's global pool
/// (one thread per core) for `None`.
pub(crate) fn on_pool<R: Send>(
    threads: Option<usize>,
    work: impl FnOnce() -> R + Send,
) -> PyResult<R> {
    match threads {
        None => Ok(work()),
        Some(0) => Err(InputError::new_err("threads: must be at least 1")),
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map(|pool| pool.install(work))
            .map_err(|e| HysteronError::new_err(format!("threads: {e}"))),
    }
}

/// The outputs as arrays, or the first error naming its entry.
fn arrays<'py>(
    py: Python<'py>,
    results: Vec<RustResult<Vec<f64>>>,
    what: &str,
) -> PyResult<Vec<Bound<'py, PyArray1<f64>>>> {
    results
        .into_iter()
        .enumerate()
        .map(|(i, r)| match r {
            Ok(y) => Ok(PyArray1::from_vec(py, y)),
            Err(e) => Err(indexed_error(py, what, i, e)),
        })
        .collect()
}

/// The typed error of entry `i` (`what i: message`), with its `index`
/// and, where the error has one, its `sample`.
pub fn indexed_error(py: Python<'_>, what: &str, i: usize, e: hysteron::Error) -> PyErr {
    let err = operator_error(py, e);
    let message = format!("{what} {i}: {}", err.value(py));
    let typed = PyErr::from_type(err.get_type(py), message);
    if let Ok(sample) = err.value(py).getattr("sample") {
        let _ = typed.value(py).setattr("sample", sample);
    }
    let _ = typed.value(py).setattr("index", i);
    typed
}

/// Runs `model` from its initial state over each record (a list of 1-D
/// float arrays), in parallel on `threads` threads (default: one per
/// core); returns the outputs in order. An error names the record
/// (`index`) and the sample.
#[pyfunction]
#[pyo3(signature = (model, records, *, threads=None))]
pub fn run_batch<'py>(
    py: Python<'py>,
    model: &Model,
    records: Vec<Bound<'py, PyAny>>,
    threads: Option<usize>,
) -> PyResult<Vec<Bound<'py, PyArray1<f64>>>> {
    let xs = records
        .iter()
        .enumerate()
        .map(|(i, r)| samples(r, &format!("record {i}")))
        .collect::<PyResult<Vec<Vec<f64>>>>()?;
    let op = model.operator()?;
    let results = py.detach(|| on_pool(threads, || simulate_records(op, &xs)))?;
    arrays(py, results, "record")
}

/// Runs `model` over `x` once per parameter set (each a dict of changed
/// values keyed by path or unique suffix, the rest as in `model`), from
/// the initial state, in parallel; returns the outputs in order.
#[pyfunction]
#[pyo3(signature = (model, sets, x, *, threads=None))]
pub fn run_parameter_sets<'py>(
    py: Python<'py>,
    model: &Model,
    sets: Vec<Bound<'py, PyDict>>,
    x: &Bound<'py, PyAny>,
    threads: Option<usize>,
) -> PyResult<Vec<Bound<'py, PyArray1<f64>>>> {
    let xs = samples(x, "x")?;
    let base = model.values();
    let mut vectors = Vec::with_capacity(sets.len());
    for (i, set) in sets.iter().enumerate() {
        let mut p = base.clone();
        model.change(&mut p, set, &format!("set {i}: "))?;
        vectors.push(p);
    }
    let op = model.operator()?;
    let results = py.detach(|| on_pool(threads, || simulate_parameter_sets(op, &vectors, &xs)))?;
    arrays(py, results, "set")
}
