//! `fit`: Levenberg-Marquardt identification of a model's free parameters.

use crate::array::samples;
use crate::errors::{band_error, fit_error, spec_error, HysteronError, ParameterError};
use crate::model::Model;
use hysteron::identify::band::{self, BandMethod, Covariance};
use hysteron::identify::{
    fit_multistart, FitOptions, FitReport, FitStatus, FittedParam, Jacobian, MultiStart, Progress,
    Record,
};
use hysteron::Operator;
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::Mutex;

/// The outcome of `fit`: the fitted model and what the fit found.
///
/// Standard errors come from the Gauss-Newton covariance
/// `C = σ² (JᵀJ)⁻¹`, `σ² = Σ r² / (m − k)` (delta method through the
/// reparametrization of bounded parameters); 95 % intervals are
/// `θ ± 1.96 σ_θ` mapped back, so they respect the bounds.
#[pyclass(module = "hysteron_rs", frozen)]
pub struct FitResult {
    model: Py<Model>,
    /// The fitted model as the fit ran it (at its sample period), for
    /// bands.
    fitted: Box<dyn Operator<f64>>,
    report: FitReport,
    history: Vec<Progress>,
    /// The sample period (s) the model ran at in the fit, `None` for a
    /// rate-independent model.
    #[pyo3(get)]
    dt: Option<f64>,
    /// Final cost `½ Σ r²`.
    #[pyo3(get)]
    cost: f64,
    /// Root-mean-square residual.
    #[pyo3(get)]
    rms: f64,
    /// `rms / RMS(y)`, `y`'s root mean square about zero (as `validate`
    /// and `compare` score); `None` for an output that is zero throughout.
    #[pyo3(get)]
    nrmse: Option<f64>,
    /// `"converged"`, `"not_converged"` (the budget ran out) or `"failed"`.
    #[pyo3(get)]
    status: &'static str,
    /// Why the fit stopped.
    #[pyo3(get)]
    message: String,
    /// True when a convergence criterion was met.
    #[pyo3(get)]
    converged: bool,
    /// Levenberg-Marquardt iterations.
    #[pyo3(get)]
    iterations: usize,
    /// Model simulations over the whole record.
    #[pyo3(get)]
    evaluations: usize,
    /// Wall time of the fit (s).
    #[pyo3(get)]
    wall_time: f64,
    /// How the Jacobian was computed: `"exact"` (forward-mode derivatives)
    /// or `"fd"` (central finite differences, also where exact ones were
    /// asked for but the model has no dual twin).
    #[pyo3(get)]
    jacobian: &'static str,
}

/// The `jacobian` keyword: `"exact"` or `"fd"` (as the CLI's `--jacobian`).
fn jacobian_kind(name: &str) -> PyResult<Jacobian> {
    match name {
        "exact" => Ok(Jacobian::Exact),
        "fd" => Ok(Jacobian::FiniteDifferences),
        other => Err(pyo3::exceptions::PyValueError::new_err(format!(
            "jacobian: expected \"exact\" or \"fd\", got {other:?}"
        ))),
    }
}

fn jacobian_name(j: Jacobian) -> &'static str {
    match j {
        Jacobian::Exact => "exact",
        Jacobian::FiniteDifferences => "fd",
    }
}

/// A free parameter's key: its path, with `[record i]` for a per-record
/// one (as the report prints it).
fn key(p: &FittedParam) -> String {
    match p.record {
        Some(i) => format!("{}[record {i}]", p.name),
        None => p.name.clone(),
    }
}

fn status_text(s: &FitStatus) -> (&'static str, &str) {
    match s {
        FitStatus::Converged(why) => ("converged", why),
        FitStatus::NotConverged(why) => ("not_converged", why),
        FitStatus::Failed(why) => ("failed", why),
    }
}

impl FitResult {
    /// A dict keyed by parameter path of `value` of each free parameter.
    fn per_param<'py, V: IntoPyObject<'py> + Copy>(
        &self,
        py: Python<'py>,
        value: impl Fn(&FittedParam) -> V,
    ) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for p in &self.report.params {
            d.set_item(key(p), value(p))?;
        }
        Ok(d)
    }
}

/// An uncertainty band around a fitted model's output
/// (`FitResult.predict_band`): per input sample, the fitted output and
/// the band's edges.
#[pyclass(module = "hysteron_rs", frozen)]
pub struct Band {
    output: Vec<f64>,
    lower: Vec<f64>,
    upper: Vec<f64>,
    /// The band's probability content, in (0, 1).
    #[pyo3(get)]
    level: f64,
    /// `"linearized"` or `"monte_carlo"`.
    #[pyo3(get)]
    method: &'static str,
    /// Monte-Carlo draws that did not run (a parameter out of its domain,
    /// a model error), left out of the quantiles; 0 for `"linearized"`.
    #[pyo3(get)]
    failed_draws: usize,
}

#[pymethods]
impl Band {
    /// The fitted model's output, one value per input sample.
    #[getter]
    fn output<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.output)
    }

    /// The band's lower edge, per sample.
    #[getter]
    fn lower<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.lower)
    }

    /// The band's upper edge, per sample.
    #[getter]
    fn upper<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.upper)
    }

    fn __repr__(&self) -> String {
        format!(
            "Band(level={}, method={:?}, samples={}, failed_draws={})",
            self.level,
            self.method,
            self.output.len(),
            self.failed_draws
        )
    }
}

#[pymethods]
impl FitResult {
    /// The band of probability content `level` around the fitted model's
    /// output along `x` (from its initial state), from the covariance of
    /// the fitted shared parameters `C_ij = ρ_ij σ_i σ_j`.
    ///
    /// `method="linearized"`: `y_k ± z·√(g_kᵀ C g_k)`, `g_k = ∂y_k/∂θ`
    /// (exact, forward-mode), `z = Φ⁻¹((1 + level)/2)`.
    /// `method="monte_carlo"`: `draws` parameter vectors from `N(θ̂, C)`
    /// (generator seeded by `seed`) simulated, and the empirical quantiles
    /// `(1 ∓ level)/2` per sample of those that ran (`Band.failed_draws`
    /// counts the others). Per-record parameters and parameters without a
    /// standard error are held at their values. The GIL is released while
    /// it runs.
    #[pyo3(signature = (x, level=0.95, method="linearized", draws=1000, seed=0))]
    fn predict_band(
        &self,
        py: Python<'_>,
        x: &Bound<'_, PyAny>,
        level: f64,
        method: &str,
        draws: i64,
        seed: u64,
    ) -> PyResult<Band> {
        let x = samples(x, "x")?;
        let method = match method {
            "linearized" => BandMethod::Linearized,
            "monte_carlo" => BandMethod::MonteCarlo {
                draws: usize::try_from(draws).map_err(|_| {
                    HysteronError::new_err(format!("draws: must be at least 1 (got {draws})"))
                })?,
                seed,
            },
            other => {
                return Err(HysteronError::new_err(format!(
                    "method: expected \"linearized\" or \"monte_carlo\", got {other:?}"
                )))
            }
        };
        let model = &self.fitted;
        let report = &self.report;
        let band = py
            .detach(|| {
                let cov = Covariance::of_report(report)?;
                band::predict_band(model.as_ref(), &cov, &x, level, method)
            })
            .map_err(|e| band_error(py, e))?;
        Ok(Band {
            method: band.method.name(),
            output: band.output,
            lower: band.lower,
            upper: band.upper,
            level: band.level,
            failed_draws: band.failed_draws,
        })
    }

    /// The model with the fitted parameters, in its initial state.
    #[getter]
    fn model(&self, py: Python<'_>) -> Py<Model> {
        self.model.clone_ref(py)
    }

    /// The free parameters' paths, in the order of every per-parameter
    /// field.
    #[getter]
    fn free(&self) -> Vec<String> {
        self.report.params.iter().map(key).collect()
    }

    /// Per record (in the order given): a dict of `samples` (compared),
    /// `rms` and `nrmse` (`rms / RMS(y)`, RMS about zero; `None` for an
    /// output that is zero throughout).
    #[getter]
    fn records<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.report
            .records
            .iter()
            .map(|r| {
                let d = PyDict::new(py);
                d.set_item("samples", r.samples)?;
                d.set_item("rms", r.rms)?;
                d.set_item("nrmse", r.nrmse)?;
                Ok(d)
            })
            .collect()
    }

    /// Fitted values, keyed by parameter path.
    #[getter]
    fn values<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.per_param(py, |p| p.value)
    }

    /// Starting values, keyed by parameter path.
    #[getter]
    fn start<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.per_param(py, |p| p.start)
    }

    /// Standard errors keyed by path (`None` where `JᵀJ` is singular, and
    /// for a parameter the output does not depend on at the solution).
    #[getter]
    fn std_errors<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.per_param(py, |p| p.std_error)
    }

    /// 95 % confidence intervals `(lo, hi)` keyed by path (`None` where
    /// `JᵀJ` is singular, and for a parameter the output does not depend on
    /// at the solution).
    #[getter]
    fn ci95<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.per_param(py, |p| p.ci95)
    }

    /// The free parameters' correlation matrix (rows and columns in the
    /// order of `free`) as a 2-D array, or `None` where `JᵀJ` is singular
    /// (NaN in the row and column of a parameter the output does not
    /// depend on at the solution).
    #[getter]
    fn correlation<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        match &self.report.correlation {
            Some(rows) => Ok(Some(PyArray2::from_vec2(py, rows).map_err(|e| {
                ParameterError::new_err(format!("correlation matrix: {e}"))
            })?)),
            None => Ok(None),
        }
    }

    /// The condition number `λ_max/λ_min` of `JᵀJ` in the fit's internal
    /// parameters, or `None` where `JᵀJ` is singular.
    #[getter]
    fn condition_number(&self) -> Option<f64> {
        self.report.condition_number
    }

    /// With `starts > 1`: a dict of `costs` (every start's final cost, in
    /// start order, `None` for a start that failed), `best` (the start
    /// kept) and `reached` (starts within 1 % of the best cost, or within
    /// 1e-20 · ½Σy² of it, rounding: so a best cost of 0 counts too); else
    /// `None`.
    #[getter]
    fn starts<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(st) = &self.report.starts else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        d.set_item("costs", st.costs.clone())?;
        d.set_item("best", st.best)?;
        d.set_item("reached", st.reached)?;
        Ok(Some(d))
    }

    /// Identifiability warnings, one sentence each: every parameter the
    /// output does not depend on at the solution (a vanishing Jacobian
    /// column, such as a non-negative parameter driven to 0: no standard
    /// error), every parameter whose 95 % interval is wider than
    /// `|value|`, every pair correlated beyond 0.99, or a singular `JᵀJ`
    /// (empty when the data pin every free parameter down).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.report.warnings.iter().map(|w| w.to_string()).collect()
    }

    /// One dict per iteration: `iteration`, `evaluations` (so far) and
    /// `cost` at the start of that iteration.
    #[getter]
    fn history<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.history
            .iter()
            .map(|p| {
                let d = PyDict::new(py);
                d.set_item("iteration", p.iteration)?;
                d.set_item("evaluations", p.evaluations)?;
                d.set_item("cost", p.cost)?;
                Ok(d)
            })
            .collect()
    }

    /// The report as the CLI prints it (with the sample period of a
    /// rate-dependent model).
    fn __str__(&self) -> String {
        match self.dt {
            Some(dt) => format!("sample period: {dt} s\n{}", self.report),
            None => self.report.to_string(),
        }
    }

    fn __repr__(&self) -> String {
        format!(
            "FitResult(status={:?}, rms={}, free={:?})",
            self.status,
            self.report.rms,
            self.free()
        )
    }
}

/// What both fit functions take besides the model and the records.
struct Request {
    free: Vec<String>,
    own: Vec<String>,
    opts: FitOptions,
    starts: MultiStart,
    /// The sample period given (`dt=` or `time=`), which overrides the
    /// spec's.
    period: Option<f64>,
}

/// Resolves the names, checks ties and repeats, runs [`fit_records`] with
/// the GIL released, and wraps the outcome.
fn run_fit(
    py: Python<'_>,
    model: &Model,
    data: &[(Vec<f64>, Vec<f64>, usize)],
    request: Request,
) -> PyResult<FitResult> {
    let spec = match request.period {
        Some(dt) => model.spec().with_dt(dt),
        None => model.spec().clone(),
    };
    let model = &Model::from_rust_spec(spec)?;
    let shared = model.indices(&request.free)?;
    let own = model.indices(&request.own)?;
    let names = model.names();
    let tied = model.spec().tied_params();
    let all: Vec<usize> = shared.iter().chain(&own).copied().collect();
    if let Some(name) = all.iter().map(|&i| &names[i]).find(|n| tied.contains(n)) {
        return Err(ParameterError::new_err(format!(
            "parameter `{name}` cannot be fitted on its own: it is tied to another (a gap's r0 \
             and its spring's z0 = -r0); keep both fixed"
        )));
    }
    for (i, a) in all.iter().enumerate() {
        if all[..i].contains(a) {
            return Err(ParameterError::new_err(format!(
                "parameter `{}` is named twice in `free`/`own`",
                names[*a]
            )));
        }
    }
    let start = dyn_clone::clone_box(model.operator()?);
    let history = Mutex::new(Vec::new());
    let record = |p: Progress| {
        if let Ok(mut h) = history.lock() {
            h.push(p);
        }
    };
    let records: Vec<Record<'_>> = data
        .iter()
        .map(|(x, y, skip)| Record { x, y, skip: *skip })
        .collect();
    let fitted = py
        .detach(|| {
            let mut m = start;
            m.reset();
            fit_multistart(
                m.as_ref(),
                &records,
                &shared,
                &own,
                &request.opts,
                &request.starts,
                &record,
            )
        })
        .map_err(|e| fit_error(py, e))?;
    let spec = model
        .spec()
        .with_params(&fitted.report.all_params)
        .map_err(spec_error)?;
    let report = fitted.report;
    let (status, why) = status_text(&report.status);
    Ok(FitResult {
        dt: model.period(),
        model: Py::new(py, Model::from_rust_spec(spec)?)?,
        cost: report.cost,
        rms: report.rms,
        nrmse: report.nrmse,
        status,
        message: why.to_string(),
        converged: report.status.converged(),
        iterations: report.iterations,
        evaluations: report.evaluations,
        wall_time: report.wall_time.as_secs_f64(),
        jacobian: jacobian_name(report.jacobian),
        fitted: fitted.model,
        report,
        history: history.into_inner().unwrap_or_default(),
    })
}

/// Fits the parameters `free` (full paths or unique suffixes) of `model`
/// to the record `(x, y)`: residuals `model(x) − y` from the model's
/// initial state, Levenberg-Marquardt with exact Jacobians (forward-mode
/// derivatives; `jacobian="fd"` for central finite differences), bounded
/// parameters through a reparametrization that keeps them inside
/// their domains. The other parameters stay at the model's values. The
/// GIL is released while it runs.
///
/// `patience` bounds the trial steps (`patience · (k + 1)`, each accepted
/// one followed by a Jacobian: one pass over dual numbers per 8 parameters,
/// or `2k` simulations by finite differences); `max_evaluations` and
/// `max_seconds` bound the work for real (the fit then ends not converged
/// at its best point); `stride` compares every `stride`-th output with `y`
/// (`len(x) = stride · len(y)`). `starts > 1` fits from the model's values
/// and `starts − 1` Latin-hypercube points around them (within a factor
/// `e^spread` for a positive parameter; `seed` fixes them), in parallel,
/// and keeps the best (`FitResult.starts` says how many reached it).
///
/// A rate-dependent model runs at its spec's sample period, or at `dt`
/// (seconds) or the step of `time` (uniformly spaced stamps, one per
/// sample of `x`) where one is given; `FitResult.dt` says which.
#[pyfunction]
#[pyo3(signature = (model, x, y, free, *, dt=None, time=None, patience=200, stride=1, ftol=1e-12, xtol=1e-12, gtol=0.0, max_evaluations=None, max_seconds=None, starts=1, spread=1.3862943611198906, seed=0, jacobian="exact"))]
#[allow(clippy::too_many_arguments)] // the Python keyword arguments
pub fn fit(
    py: Python<'_>,
    model: &Model,
    x: &Bound<'_, PyAny>,
    y: &Bound<'_, PyAny>,
    free: Vec<String>,
    dt: Option<f64>,
    time: Option<&Bound<'_, PyAny>>,
    patience: usize,
    stride: usize,
    ftol: f64,
    xtol: f64,
    gtol: f64,
    max_evaluations: Option<usize>,
    max_seconds: Option<f64>,
    starts: usize,
    spread: f64,
    seed: u64,
    jacobian: &str,
) -> PyResult<FitResult> {
    let data = [(samples(x, "x")?, samples(y, "y")?, 0)];
    let period = crate::period::period(dt, time, data[0].0.len())?;
    let opts = FitOptions {
        ftol,
        xtol,
        gtol,
        patience,
        stride,
        max_evaluations,
        max_seconds,
        jacobian: jacobian_kind(jacobian)?,
        ..FitOptions::default()
    };
    let request = Request {
        free,
        own: vec![],
        opts,
        starts: MultiStart {
            starts,
            spread,
            seed,
        },
        period,
    };
    run_fit(py, model, &data, request)
}

/// Fits one parameter set to several records `[(x, y), …]`, each simulated
/// from the model's initial state; `own` names parameters fitted
/// separately for each record (an initial state, a preload: keyed
/// `"path[record i]"` in the result), `skip` leading output samples of
/// each record are simulated but not compared (a warm-up); `dt` gives
/// the sample period of every record (seconds). Otherwise as `fit`.
#[pyfunction]
#[pyo3(signature = (model, records, free, *, own=Vec::new(), skip=0, dt=None, patience=200, stride=1, ftol=1e-12, xtol=1e-12, gtol=0.0, max_evaluations=None, max_seconds=None, starts=1, spread=1.3862943611198906, seed=0, jacobian="exact"))]
#[allow(clippy::too_many_arguments)] // the Python keyword arguments
pub fn fit_records(
    py: Python<'_>,
    model: &Model,
    records: Vec<(Bound<'_, PyAny>, Bound<'_, PyAny>)>,
    free: Vec<String>,
    own: Vec<String>,
    skip: usize,
    dt: Option<f64>,
    patience: usize,
    stride: usize,
    ftol: f64,
    xtol: f64,
    gtol: f64,
    max_evaluations: Option<usize>,
    max_seconds: Option<f64>,
    starts: usize,
    spread: f64,
    seed: u64,
    jacobian: &str,
) -> PyResult<FitResult> {
    let data = records
        .iter()
        .enumerate()
        .map(|(i, (x, y))| {
            Ok((
                samples(x, &format!("records[{i}].x"))?,
                samples(y, &format!("records[{i}].y"))?,
                skip,
            ))
        })
        .collect::<PyResult<Vec<_>>>()?;
    let period = crate::period::period(dt, None, 0)?;
    let opts = FitOptions {
        ftol,
        xtol,
        gtol,
        patience,
        stride,
        max_evaluations,
        max_seconds,
        jacobian: jacobian_kind(jacobian)?,
        ..FitOptions::default()
    };
    let starts = MultiStart {
        starts,
        spread,
        seed,
    };
    run_fit(
        py,
        model,
        &data,
        Request {
            free,
            own,
            opts,
            starts,
            period,
        },
    )
}
