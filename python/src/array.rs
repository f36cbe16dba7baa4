//! Reading numpy arrays (or anything numpy can turn into one) as samples.

use crate::errors::InputError;
use numpy::{PyArray1, PyArrayDyn, PyArrayMethods, PyReadonlyArray1, PyUntypedArrayMethods};
use pyo3::prelude::*;

/// The samples of `obj`, `np.asarray(obj, dtype=float64)`, which must be
/// 1-D and non-empty; any memory layout (a strided view is copied in
/// order). `what` names the argument in messages. Finiteness is left to
/// the library, which names the sample.
pub fn samples(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<f64>> {
    let read = readonly(obj, what)?;
    // One memcpy for a contiguous array, element by element otherwise.
    Ok(match read.as_slice() {
        Ok(slice) => slice.to_vec(),
        Err(_) => read.as_array().iter().copied().collect(),
    })
}

/// `obj` as a 1-D, non-empty float64 array, checked as for [`samples`],
/// borrowed read-only (no copy when it already is one).
pub fn readonly<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<PyReadonlyArray1<'py, f64>> {
    let array = float64_array(obj, what, 1)?;
    let array = array.cast::<PyArray1<f64>>().map_err(|_| {
        InputError::new_err(format!("{what}: numpy did not return a 1-D float64 array"))
    })?;
    array
        .try_readonly()
        .map_err(|e| InputError::new_err(format!("{what}: cannot be read ({e})")))
}

/// The rows of `obj`, a 2-D float64 array (as `np.asarray` makes it) with
/// at least one row: `(rows, columns, values row by row)`.
pub fn matrix(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<(usize, usize, Vec<f64>)> {
    let array = float64_array(obj, what, 2)?;
    let shape = array.shape().to_vec();
    let read = array
        .try_readonly()
        .map_err(|e| InputError::new_err(format!("{what}: cannot be read ({e})")))?;
    // (in row order whatever the memory layout)
    let values: Vec<f64> = read.as_array().iter().copied().collect();
    match shape[..] {
        [rows, columns] => Ok((rows, columns, values)),
        _ => Err(InputError::new_err(format!("{what}: must be 2-D"))),
    }
}

/// `np.asarray(obj)` as a non-empty float64 array of `ndim` dimensions:
/// real numbers only (numpy would cast complex values to their real part,
/// and strings to numbers, without a word).
fn float64_array<'py>(
    obj: &Bound<'py, PyAny>,
    what: &str,
    ndim: usize,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let py = obj.py();
    let np = py.import("numpy")?;
    let unreadable = |e: PyErr| {
        InputError::new_err(format!(
            "{what}: cannot be read as an array of float64: {}",
            e.value(py)
        ))
    };
    let raw = np.call_method1("asarray", (obj,)).map_err(unreadable)?;
    let dtype = raw.getattr("dtype")?;
    let kind: String = dtype.getattr("kind")?.extract()?;
    if !matches!(kind.as_str(), "i" | "u" | "f") {
        return Err(InputError::new_err(format!(
            "{what}: cannot be read as an array of float64: its dtype is {} (real numbers needed)",
            dtype.str()?
        )));
    }
    let no_copy = pyo3::types::PyDict::new(py);
    no_copy.set_item("copy", false)?;
    let converted = raw
        .call_method("astype", (np.getattr("float64")?,), Some(&no_copy))
        .map_err(unreadable)?;
    let array = converted.cast::<PyArrayDyn<f64>>().map_err(|_| {
        InputError::new_err(format!("{what}: numpy did not return a float64 array"))
    })?;
    if array.ndim() != ndim {
        let dims: Vec<String> = array.shape().iter().map(usize::to_string).collect();
        return Err(InputError::new_err(format!(
            "{what}: must be {ndim}-D, got shape ({})",
            dims.join(", ")
        )));
    }
    if array.len() == 0 {
        return Err(InputError::new_err(format!("{what}: is empty")));
    }
    Ok(array.clone())
}
