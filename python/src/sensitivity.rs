//! `sensitivity`: the derivatives of a model's output with respect to its
//! parameters, by forward-mode automatic differentiation.

use crate::array::samples;
use crate::errors::{
    operator_error, spec_error, HysteronError, InputError, ParameterError, SolverError,
};
use crate::model::Model;
use hysteron::models::sensitivity::{sensitivity as rust_sensitivity, SensitivityError};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;

/// The output and the derivatives, `(y, dydp)`.
type Output<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray2<f64>>);

/// Runs `model` from its initial state over `x` and returns `(y, dydp)`:
/// the output (1-D float64 array) and its derivatives with respect to the
/// parameters `params` (full paths or unique suffixes, each at most once),
/// a 2-D float64 array of shape `(len(x), len(params))` whose column `i`
/// is `∂y/∂params[i]`. The derivatives are forward-mode automatic
/// differentiation (dual numbers: no step size; at a kink, the derivative
/// of the branch the model takes). The GIL is released while it runs.
#[pyfunction]
#[pyo3(signature = (model, x, params))]
pub fn sensitivity<'py>(
    py: Python<'py>,
    model: &Model,
    x: &Bound<'py, PyAny>,
    params: Vec<String>,
) -> PyResult<Output<'py>> {
    let xs = samples(x, "x")?;
    if params.is_empty() {
        return Err(ParameterError::new_err(format!(
            "params: no parameter given (the model has: {})",
            model.names().join(", ")
        )));
    }
    let all = model.names();
    let full: Vec<String> = model
        .indices(&params)?
        .into_iter()
        .zip(&params)
        .map(|(i, asked)| all.get(i).cloned().unwrap_or_else(|| asked.clone()))
        .collect();
    let refs: Vec<&str> = full.iter().map(String::as_str).collect();
    let spec = model.spec();
    let result = py
        .detach(|| rust_sensitivity(spec, &xs, &refs))
        .map_err(|e| error(py, e))?;
    let n = result.output.len();
    let k = result.columns.len();
    let mut flat = Vec::with_capacity(n * k);
    for s in 0..n {
        flat.extend(
            result
                .columns
                .iter()
                .map(|c| c.get(s).copied().unwrap_or(f64::NAN)),
        );
    }
    let dydp = PyArray1::from_vec(py, flat)
        .reshape([n, k])
        .map_err(|e| HysteronError::new_err(format!("sensitivity: {e}")))?;
    Ok((PyArray1::from_vec(py, result.output), dydp))
}

/// The exception of a sensitivity error.
fn error(py: Python<'_>, e: SensitivityError) -> PyErr {
    match e {
        SensitivityError::Spec(e) => spec_error(e),
        SensitivityError::EmptyInput => InputError::new_err("x: is empty"),
        e @ (SensitivityError::NoParameters { .. }
        | SensitivityError::UnknownParameter { .. }
        | SensitivityError::Repeated { .. }) => ParameterError::new_err(e.to_string()),
        SensitivityError::Model(e) => operator_error(py, e),
        e @ SensitivityError::NonFiniteDerivative { sample, .. } => {
            let err = SolverError::new_err(e.to_string());
            let _ = err.value(py).setattr("sample", sample);
            err
        }
    }
}
