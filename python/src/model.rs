//! `Model`: a spec and the operator built from it, with its running state.

use crate::array::readonly;
use crate::errors::{operator_error, spec_error, ParameterError, SpecError as PySpecError};
use hysteron::composition::{SolverOptions, TravelLimits};
use hysteron::identify::free_by_names;
use hysteron::models::Spec;
use hysteron::{Error, Operator};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

/// A hysteresis model: a spec (the tree of operators and its parameters)
/// and the operator built from it, which holds the running state.
///
/// * `run(x)` runs a float64 array from the current state and commits every
///   sample; `step(x)` does one sample; `trial(x)` evaluates one sample
///   without committing it, `commit()` keeps the last trial, `reset()`
///   returns to the initial state.
/// * `params` (a dict keyed by parameter path) and `with_params(...)`
///   read and change parameters; `to_spec()` gives the spec as a dict.
/// * `then`, `plus`, `scaled`, `series`, `feedback`, `inverse` and
///   `oversample` compose models into new ones (from their initial states).
///
/// Copies (`copy.copy`, `copy.deepcopy`) keep the running state and are
/// independent; pickling goes through the spec, so an unpickled model
/// starts from its initial state.
#[pyclass(module = "hysteron_rs", name = "Model")]
pub struct Model {
    spec: Spec,
    op: Box<dyn Operator<f64>>,
}

impl Model {
    /// Builds the operator of `spec`. A spec that leaves the sample period
    /// of a rate-dependent node out ([`Spec::missing_period`]) is built
    /// with a stand-in period, for its parameters and composition only:
    /// it runs once [`set_period`](Self::set_period) has given the period.
    pub fn from_rust_spec(spec: Spec) -> PyResult<Self> {
        let op = match spec.missing_period() {
            Some(_) => spec.or_dt(Spec::STAND_IN_DT).build(),
            None => spec.build(),
        }
        .map_err(spec_error)?;
        Ok(Model { spec, op })
    }

    /// The spec.
    pub fn spec(&self) -> &Spec {
        &self.spec
    }

    /// The operator in its current state, to run: an error if the spec
    /// leaves a sample period out and none was given
    /// ([`SpecError::MissingPeriod`](hysteron::models::SpecError)).
    pub fn operator(&self) -> PyResult<&(dyn Operator<f64> + 'static)> {
        self.require_period()?;
        Ok(self.op.as_ref())
    }

    /// The parameter paths, in the order of the flat parameter vector.
    pub fn names(&self) -> Vec<String> {
        self.op.param_names()
    }

    /// The flat parameter vector.
    pub fn values(&self) -> Vec<f64> {
        self.op.params()
    }

    /// An error naming the first rate-dependent node without a sample
    /// period, if there is one.
    fn require_period(&self) -> PyResult<()> {
        match self.spec.missing_period() {
            Some(node) => Err(spec_error(hysteron::models::SpecError::MissingPeriod {
                path: format!("{node}.dt"),
            })),
            None => Ok(()),
        }
    }

    /// Gives every rate-dependent node the sample period `dt` (s; `dt / q`
    /// inside an `oversample`), in the running operator and in the spec,
    /// keeping the state. A rate-independent model is left as it is.
    pub fn set_period(&mut self, dt: f64) -> PyResult<()> {
        if !self.spec.is_rate_dependent() {
            return Ok(());
        }
        self.op
            .set_sample_period(dt)
            .map_err(|e| ParameterError::new_err(format!("dt: {e}")))?;
        self.spec = self.spec.with_dt(dt);
        Ok(())
    }

    /// The sample period (s) of a rate-dependent model, as the data see
    /// it (`None` for a rate-independent model, and for one whose spec
    /// leaves it out).
    pub fn period(&self) -> Option<f64> {
        if self.spec.missing_period().is_some() {
            return None;
        }
        self.spec.stated_periods().first().copied()
    }

    /// Writes the values of `changes` (a dict keyed by full path or unique
    /// suffix) into the flat parameter vector `p`; `context` starts every
    /// message (`"set 3: "`).
    pub fn change(
        &self,
        p: &mut [f64],
        changes: &Bound<'_, PyDict>,
        context: &str,
    ) -> PyResult<()> {
        for (k, v) in changes.iter() {
            let name: String = k.extract().map_err(|_| {
                ParameterError::new_err(format!(
                    "{context}parameter names must be strings, got {k}"
                ))
            })?;
            let value: f64 = v.extract().map_err(|_| {
                ParameterError::new_err(format!("{context}parameter `{name}`: {v} is not a number"))
            })?;
            let refs = [name.as_str()];
            let i = free_by_names(self.op.as_ref(), &refs)
                .map_err(|e| ParameterError::new_err(format!("{context}{e}")))?[0];
            p[i] = value;
        }
        Ok(())
    }

    /// The indices of `names` (full paths or unique suffixes).
    pub fn indices(&self, names: &[String]) -> PyResult<Vec<usize>> {
        let refs: Vec<&str> = names.iter().map(String::as_str).collect();
        free_by_names(self.op.as_ref(), &refs).map_err(|e| ParameterError::new_err(e.to_string()))
    }
}

/// Samples per GIL release in [`Model::run`].
const RUN_CHUNK: usize = 1 << 15;

/// An error at sample `i` of a chunk as the error at sample `start + i`.
fn shift_sample(e: Error, start: usize) -> Error {
    match e {
        Error::AtSample { index, source } => Error::AtSample {
            index: index + start,
            source,
        },
        other => other,
    }
}

/// Deepest nesting of dicts and lists a spec object may have.
const MAX_DEPTH: usize = 256;

/// The path and value of the first float in `obj` (dicts and lists,
/// depth-first) that is NaN or infinite, which JSON cannot hold.
fn non_finite(obj: &Bound<'_, PyAny>, path: &str, depth: usize) -> PyResult<Option<(String, f64)>> {
    if depth > MAX_DEPTH {
        return Err(PySpecError::new_err(format!(
            "{path}: nested deeper than {MAX_DEPTH} levels"
        )));
    }
    let join = |key: &str| {
        if path.is_empty() {
            key.to_string()
        } else {
            format!("{path}.{key}")
        }
    };
    if let Ok(d) = obj.cast::<PyDict>() {
        for (k, v) in d.iter() {
            if let Some(hit) = non_finite(&v, &join(&k.str()?.to_string()), depth + 1)? {
                return Ok(Some(hit));
            }
        }
    } else if let Ok(l) = obj.cast::<pyo3::types::PyList>() {
        for (i, v) in l.iter().enumerate() {
            if let Some(hit) = non_finite(&v, &format!("{path}[{i}]"), depth + 1)? {
                return Ok(Some(hit));
            }
        }
    } else if let Ok(f) = obj.cast::<pyo3::types::PyFloat>() {
        let v = f.value();
        if !v.is_finite() {
            return Ok(Some((path.to_string(), v)));
        }
    }
    Ok(None)
}

/// A spec from a dict (or anything `json.dumps` takes) or JSON text.
fn spec_of(obj: &Bound<'_, PyAny>) -> PyResult<Spec> {
    let text = if let Ok(s) = obj.cast::<PyString>() {
        s.to_string()
    } else {
        if let Some((path, v)) = non_finite(obj, "", 0)? {
            return Err(ParameterError::new_err(format!(
                "{path}: must be finite (got {v})"
            )));
        }
        let json = obj.py().import("json")?;
        json.call_method1("dumps", (obj,))
            .map_err(|e| {
                PySpecError::new_err(format!(
                    "the spec cannot be written as JSON: {}",
                    e.value(obj.py())
                ))
            })?
            .extract::<String>()?
    };
    Spec::from_json(&text).map_err(spec_error)
}

/// A spec's JSON text as Python objects (`json.loads`).
fn to_python<'py>(py: Python<'py>, spec: &Spec) -> PyResult<Bound<'py, PyAny>> {
    let text = spec.to_json_pretty().map_err(spec_error)?;
    py.import("json")?.call_method1("loads", (text,))
}

/// Travel limits from `None`, `{"type": "range", "lo", "hi"}` or
/// `{"type": "gap", "b", "r0"}` (as in a spec).
fn limits_of(obj: Option<&Bound<'_, PyAny>>) -> PyResult<TravelLimits<f64>> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(TravelLimits::None);
    };
    let probe = PyDict::new(obj.py());
    probe.set_item("type", "series")?;
    probe.set_item("left", gain_spec(obj.py())?)?;
    probe.set_item("right", gain_spec(obj.py())?)?;
    probe.set_item("limits", obj)?;
    match spec_of(probe.as_any())? {
        Spec::Series { limits, .. } => Ok(limits),
        _ => Err(PySpecError::new_err("limits: not travel limits")),
    }
}

fn gain_spec(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("type", "gain")?;
    d.set_item("k", 1.0)?;
    Ok(d)
}

/// Solver options from `None` or a dict as in a spec.
fn solver_of(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Option<SolverOptions<f64>>> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(None);
    };
    let probe = PyDict::new(obj.py());
    probe.set_item("type", "inverse")?;
    probe.set_item("inner", gain_spec(obj.py())?)?;
    probe.set_item("solver", obj)?;
    match spec_of(probe.as_any())? {
        Spec::Inverse { solver, .. } => Ok(solver),
        _ => Err(PySpecError::new_err("solver: not solver options")),
    }
}

fn boxed(m: &Model) -> Box<Spec> {
    Box::new(m.spec.clone())
}

#[pymethods]
impl Model {
    /// A model from a spec: a dict (as `to_spec()` gives) or JSON text.
    #[new]
    pub fn py_new(spec: &Bound<'_, PyAny>) -> PyResult<Self> {
        Model::from_rust_spec(spec_of(spec)?)
    }

    /// A model from a spec: a dict (as `to_spec()` gives) or JSON text.
    #[staticmethod]
    fn from_spec(spec: &Bound<'_, PyAny>) -> PyResult<Self> {
        Model::py_new(spec)
    }

    /// The spec as a dict (JSON objects, lists and numbers).
    fn to_spec<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.spec)
    }

    /// The spec as JSON text.
    fn to_json(&self) -> PyResult<String> {
        self.spec.to_json_pretty().map_err(spec_error)
    }

    /// The operator's name (the spec's `type`).
    #[getter]
    fn name(&self) -> &'static str {
        self.op.name()
    }

    /// The parameter paths, in the order of the flat parameter vector.
    #[getter]
    fn param_names(&self) -> Vec<String> {
        self.op.param_names()
    }

    /// The parameters as a dict keyed by parameter path (flat order).
    #[getter]
    fn params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (name, value) in self.op.param_names().into_iter().zip(self.op.params()) {
            d.set_item(name, value)?;
        }
        Ok(d)
    }

    /// The parameters that are tied to another (a gap's `r0` and its
    /// spring's `z0`) and so cannot be changed or fitted on their own.
    #[getter]
    fn tied_params(&self) -> Vec<String> {
        self.spec.tied_params()
    }

    /// A new model (from its initial state) with some parameters changed:
    /// `with_params({"r": 0.2})` or `with_params(r=0.2)`. A name is a full
    /// path or a suffix after a `.` that only one parameter has.
    #[pyo3(signature = (values=None, **kwargs))]
    fn with_params(
        &self,
        values: Option<&Bound<'_, PyDict>>,
        kwargs: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Model> {
        let mut p = self.op.params();
        for dict in [values, kwargs].into_iter().flatten() {
            self.change(&mut p, dict, "")?;
        }
        let spec = self.spec.with_params(&p).map_err(spec_error)?;
        Model::from_rust_spec(spec)
    }

    /// The same model with the sample period of every rate-dependent node
    /// set to `dt` seconds (the nodes inside an `oversample` of `q`
    /// sub-steps get `dt / q`); from the initial state.
    fn with_dt(&self, dt: f64) -> PyResult<Model> {
        Model::from_rust_spec(self.spec.with_dt(dt))
    }

    /// Runs the model over `x` (a 1-D float array, or anything numpy turns
    /// into one) from its current state, committing every sample, and
    /// returns the outputs as a float64 array. The GIL is released while
    /// it runs. On an error the state is that before the failing sample.
    ///
    /// A rate-dependent model runs at the sample period of its spec, or at
    /// `dt` (seconds) or the step of `time` (uniformly spaced stamps, one
    /// per sample of `x`) where one is given: the model then keeps that
    /// period (see `dt`). A rate-independent model ignores both.
    #[pyo3(signature = (x, *, dt=None, time=None))]
    fn run<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        dt: Option<f64>,
        time: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let xs = readonly(x, "x")?;
        let n = xs.len()?;
        if let Some(dt) = crate::period::period(dt, time, n)? {
            self.set_period(dt)?;
        }
        self.require_period()?;
        let mut ys = vec![0.0; n];
        // A strided array is copied once into order; a contiguous one is
        // copied chunk by chunk, small enough to stay in cache. Each chunk
        // is copied with the GIL held (no Python thread can write the
        // array meanwhile) and run with the GIL released.
        let strided: Option<Vec<f64>> = match xs.as_slice() {
            Ok(_) => None,
            Err(_) => Some(xs.as_array().iter().copied().collect()),
        };
        let mut chunk = Vec::with_capacity(RUN_CHUNK.min(n));
        for (k, out) in ys.chunks_mut(RUN_CHUNK).enumerate() {
            let start = k * RUN_CHUNK;
            let range = start..start + out.len();
            chunk.clear();
            match &strided {
                Some(all) => chunk.extend_from_slice(&all[range]),
                None => chunk.extend_from_slice(&xs.as_slice()?[range]),
            }
            let op = &mut self.op;
            let input = &chunk;
            py.detach(move || op.process(input, out))
                .map_err(|e| operator_error(py, shift_sample(e, start)))?;
        }
        Ok(PyArray1::from_vec(py, ys))
    }

    /// The sample period (s) a rate-dependent model runs at (`None` for a
    /// rate-independent model, and for one whose spec leaves it out until
    /// `run(x, dt=...)` or `with_dt` gives it).
    #[getter]
    fn dt(&self) -> Option<f64> {
        self.period()
    }

    /// One sample: `trial(x)` then `commit()`; returns the output.
    fn step(&mut self, py: Python<'_>, x: f64) -> PyResult<f64> {
        self.require_period()?;
        let y = self.op.trial(x).map_err(|e| operator_error(py, e))?.output;
        self.op.commit();
        Ok(y)
    }

    /// The output at input `x` from the committed state, without keeping
    /// it (a later `commit()` keeps the last trial).
    fn trial(&mut self, py: Python<'_>, x: f64) -> PyResult<f64> {
        self.require_period()?;
        Ok(self.op.trial(x).map_err(|e| operator_error(py, e))?.output)
    }

    /// Keeps the state of the last `trial`.
    fn commit(&mut self) {
        self.op.commit();
    }

    /// Returns to the initial state.
    fn reset(&mut self) {
        self.op.reset();
    }

    /// Cascade: `other` applied to this model's output.
    fn then(&self, other: &Model) -> PyResult<Model> {
        Model::from_rust_spec(Spec::Cascade {
            first: boxed(self),
            second: boxed(other),
        })
    }

    /// Parallel: the sum of both outputs.
    fn plus(&self, other: &Model) -> PyResult<Model> {
        Model::from_rust_spec(Spec::Parallel {
            left: boxed(self),
            right: boxed(other),
        })
    }

    /// `w` times the output.
    fn scaled(&self, w: f64) -> PyResult<Model> {
        Model::from_rust_spec(Spec::Scaled {
            w,
            inner: boxed(self),
        })
    }

    /// Mechanical series with `other`: equal force, displacements add.
    /// `limits` bounds this model's displacement: `None`,
    /// `{"type": "range", "lo": .., "hi": ..}` or
    /// `{"type": "gap", "b": .., "r0": ..}`; `solver` as in a spec.
    #[pyo3(signature = (other, limits=None, solver=None))]
    fn series(
        &self,
        other: &Model,
        limits: Option<&Bound<'_, PyAny>>,
        solver: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Model> {
        Model::from_rust_spec(Spec::Series {
            left: boxed(self),
            right: boxed(other),
            limits: limits_of(limits)?,
            solver: solver_of(solver)?,
        })
    }

    /// Negative feedback `y = self[x − back[y]]`, solved at every sample.
    #[pyo3(signature = (back, solver=None))]
    fn feedback(&self, back: &Model, solver: Option<&Bound<'_, PyAny>>) -> PyResult<Model> {
        Model::from_rust_spec(Spec::Feedback {
            forward: boxed(self),
            back: boxed(back),
            solver: solver_of(solver)?,
        })
    }

    /// The numerical inverse of this (non-decreasing) model.
    #[pyo3(signature = (solver=None))]
    fn inverse(&self, solver: Option<&Bound<'_, PyAny>>) -> PyResult<Model> {
        Model::from_rust_spec(Spec::Inverse {
            inner: boxed(self),
            solver: solver_of(solver)?,
        })
    }

    /// This model run at `q ≥ 1` sub-steps per sample (input interpolated
    /// linearly), its rate-dependent nodes at `dt / q`.
    fn oversample(&self, q: usize) -> PyResult<Model> {
        Model::from_rust_spec(Spec::Oversample {
            inner: boxed(self),
            q,
        })
    }

    fn __repr__(&self) -> String {
        format!("Model({})", self.spec.describe())
    }

    fn __copy__(&self) -> Model {
        Model {
            spec: self.spec.clone(),
            op: dyn_clone::clone_box(self.op.as_ref()),
        }
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Model {
        self.__copy__()
    }

    /// Pickles through the spec's JSON text.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, (String,))> {
        let text = slf.borrow().to_json()?;
        Ok((slf.get_type().into_any(), (text,)))
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<Model>()
            .is_ok_and(|o| o.borrow().spec == self.spec)
    }

    /// The spec as a short description (`describe` of the spec tree).
    fn describe(&self) -> String {
        self.spec.describe()
    }
}
