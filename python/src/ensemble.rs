//! `Ensemble`: many instances of one model, one parameter vector each, run
//! together ([`hysteron::identify::ensemble`]), the GIL released.

use crate::array::{matrix, samples};
use crate::batch::{indexed_error, on_pool};
use crate::errors::{InputError, SpecError};
use crate::model::Model;
use hysteron::identify::ensemble::{
    Ensemble as RustEnsemble, EnsembleError, InstanceFailure, Kernel,
};
use nalgebra::DMatrix;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;

/// `N` instances of a model's structure, instance `i` with the parameter
/// vector `params[i]` (columns in the order of `model.param_names`): play and MMS
/// leaves, PI banks of fewer than 64 plays not a multiple of eight, a
/// Bouc-Wen spring whose rows all have `n = 1`, and the
/// Bouc-Wen benchmark system (a mass-spring-damper with such a spring fed
/// back, oversampled or not) step eight instances per vector instruction,
/// any other model
/// one instance at a time, in parallel. Every instance gives the bits the
/// model gives alone with its parameters.
#[pyclass(module = "hysteron_rs._native", frozen)]
pub struct Ensemble {
    inner: RustEnsemble,
    names: Vec<String>,
}

#[pymethods]
impl Ensemble {
    /// `model` with one instance per row of `params` (a 2-D float array of
    /// `len(model.param_names)` columns). A row out of the parameters' domains
    /// is that instance's error when run, not an error here.
    #[new]
    fn new(model: &Model, params: &Bound<'_, PyAny>) -> PyResult<Self> {
        model.operator()?;
        let (rows, columns, values) = matrix(params, "params")?;
        let params = DMatrix::from_row_slice(rows, columns, &values);
        let inner = RustEnsemble::new(model.spec(), &params).map_err(ensemble_error)?;
        Ok(Ensemble {
            names: inner.param_names(),
            inner,
        })
    }

    /// The number of instances.
    fn __len__(&self) -> usize {
        self.inner.len()
    }

    /// The parameter names: the columns of `params`.
    #[getter]
    fn names(&self) -> Vec<String> {
        self.names.clone()
    }

    /// How the instances are stepped: the leaf of the lane kernel
    /// (`"play"`, `"mms"`, `"bouc_wen"`, `"msd_feedback"`), or `"instances"`
    /// (one at a time).
    #[getter]
    fn kernel(&self) -> &'static str {
        match self.inner.kernel() {
            Kernel::Lanes(leaf) => leaf,
            Kernel::Instances => "instances",
        }
    }

    /// Runs every instance from its initial state over `x` (1-D) and
    /// returns the outputs, shape `(len(self), len(x))`. With
    /// `errors="raise"` the first failing instance raises its typed error
    /// (its `index` the instance); with `errors="nan"` a failing
    /// instance's row is NaN and the others are returned. The instances
    /// run on `threads` threads (default: one per core); the GIL is
    /// released while they run.
    #[pyo3(signature = (x, *, errors = "raise", threads = None))]
    fn run<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        errors: &str,
        threads: Option<usize>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let raise = match errors {
            "raise" => true,
            "nan" => false,
            other => {
                return Err(InputError::new_err(format!(
                    "errors: must be \"raise\" or \"nan\", got {other:?}"
                )))
            }
        };
        let x = samples(x, "x")?;
        let run = py
            .detach(|| on_pool(threads, || self.inner.run(&x)))?
            .map_err(ensemble_error)?;
        if raise {
            if let Some(InstanceFailure { instance, error }) = run.failures.into_iter().next() {
                return Err(indexed_error(py, "instance", instance, error));
            }
        }
        let shape = [self.inner.len(), run.samples];
        PyArray1::from_vec(py, run.outputs).reshape(shape)
    }

    fn __repr__(&self) -> String {
        format!(
            "Ensemble({} instances, {} parameters, kernel {:?})",
            self.inner.len(),
            self.names.len(),
            self.kernel()
        )
    }
}

/// The ensemble's refusal as the package's typed errors.
fn ensemble_error(e: EnsembleError) -> PyErr {
    match e {
        EnsembleError::Model(m) => SpecError::new_err(m),
        e => InputError::new_err(e.to_string()),
    }
}
