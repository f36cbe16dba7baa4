//! Python bindings of hysteron: the `hysteron_rs._native` extension
//! module, wrapped by the `hysteron_rs` package (`python/hysteron_rs/`).
//!
//! Every function and method checks its arguments and returns a Python
//! exception (a subclass of `HysteronError`, itself a `ValueError`)
//! instead of panicking; long runs release the GIL.

mod analysis;
mod array;
mod batch;
mod ensemble;
mod errors;
mod fitting;
mod leaves;
mod model;
mod period;
mod selection;
mod sensitivity;

use pyo3::prelude::*;

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    m.add_class::<model::Model>()?;
    m.add_class::<fitting::FitResult>()?;
    m.add_class::<fitting::Band>()?;
    m.add_class::<analysis::DescribingFunction>()?;
    m.add_class::<analysis::LoopEnergy>()?;
    m.add_class::<ensemble::Ensemble>()?;
    m.add_function(wrap_pyfunction!(leaves::leaf_kinds, m)?)?;
    m.add_function(wrap_pyfunction!(leaves::leaf, m)?)?;
    m.add_function(wrap_pyfunction!(leaves::paper_model, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::describing_function, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::loop_energy, m)?)?;
    m.add_function(wrap_pyfunction!(fitting::fit, m)?)?;
    m.add_function(wrap_pyfunction!(fitting::fit_records, m)?)?;
    m.add_function(wrap_pyfunction!(batch::run_batch, m)?)?;
    m.add_function(wrap_pyfunction!(batch::run_parameter_sets, m)?)?;
    m.add_function(wrap_pyfunction!(sensitivity::sensitivity, m)?)?;
    m.add_function(wrap_pyfunction!(selection::compare, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
