//! Describing function and loop energy of a model under a sine.

use crate::errors::analysis_error;
use crate::model::Model;
use hysteron::models::describing::{self, AnalysisError, SineOptions};
use hysteron::models::energy;
use hysteron::Operator;
use pyo3::prelude::*;

/// The first-harmonic gain of a model driven by `x = A sin θ` in its
/// steady cycle: `N(A) = (b1 + i a1) / A` with `b1 = (1/π)∮ y sin θ dθ`,
/// `a1 = (1/π)∮ y cos θ dθ`.
#[pyclass(module = "hysteron_rs", frozen, get_all)]
pub struct DescribingFunction {
    /// The sine's amplitude `A`.
    pub amplitude: f64,
    /// `Re N = b1 / A`.
    pub re: f64,
    /// `Im N = a1 / A` (negative for a lagging loop).
    pub im: f64,
    /// `|N|`.
    pub gain: f64,
    /// `arg N` (rad).
    pub phase: f64,
    /// `(a_k, b_k)` for `k = 0..harmonics` (cosine and sine coefficients).
    pub harmonics: Vec<(f64, f64)>,
    /// Relative change of the first harmonic over the last period.
    pub change: f64,
}

#[pymethods]
impl DescribingFunction {
    fn __repr__(&self) -> String {
        format!(
            "DescribingFunction(amplitude={}, re={}, im={}, gain={}, phase={})",
            self.amplitude, self.re, self.im, self.gain, self.phase
        )
    }
}

/// The work a model's steady loop takes per cycle under `x = A sin θ`.
#[pyclass(module = "hysteron_rs", frozen, get_all)]
pub struct LoopEnergy {
    /// The sine's amplitude `A`.
    pub amplitude: f64,
    /// `W = ∮ y dx` over one steady cycle (trapezoid rule): positive for a
    /// clockwise loop (stop, elastoplastic, MMS, Bouc-Wen), negative for a
    /// counterclockwise one (play, PI bank); `area` is `|W|`.
    pub work: f64,
    /// Relative change of the first harmonic over the last period.
    pub change: f64,
}

#[pymethods]
impl LoopEnergy {
    /// The loop area `|W|`, the energy dissipated per cycle whatever the
    /// loop's orientation.
    #[getter]
    fn area(&self) -> f64 {
        self.work.abs()
    }

    fn __repr__(&self) -> String {
        format!(
            "LoopEnergy(amplitude={}, work={})",
            self.amplitude, self.work
        )
    }
}

fn options(
    samples_per_period: usize,
    settle_periods: usize,
    steady_tol: f64,
    harmonics: usize,
) -> SineOptions {
    SineOptions {
        samples_per_period,
        settle_periods,
        steady_tol,
        harmonics,
    }
}

/// Runs `analysis` on a copy of `model`'s operator with the GIL released.
fn analyse<R: Send>(
    py: Python<'_>,
    model: &Model,
    analysis: impl FnOnce(&Box<dyn Operator<f64>>) -> Result<R, AnalysisError> + Send,
) -> PyResult<R> {
    let op = dyn_clone::clone_box(model.operator()?);
    py.detach(move || analysis(&op)).map_err(analysis_error)
}

/// The describing function of `model` (from its initial state) at
/// amplitude `amplitude`: the sine is run until its cycle is periodic to
/// `steady_tol`, at most `settle_periods` periods.
#[pyfunction]
#[pyo3(signature = (model, amplitude, *, samples_per_period=1024, settle_periods=20, steady_tol=1e-9, harmonics=5))]
pub fn describing_function(
    py: Python<'_>,
    model: &Model,
    amplitude: f64,
    samples_per_period: usize,
    settle_periods: usize,
    steady_tol: f64,
    harmonics: usize,
) -> PyResult<DescribingFunction> {
    let opts = options(samples_per_period, settle_periods, steady_tol, harmonics);
    let n = analyse(py, model, |op| {
        describing::describing_function(op, amplitude, &opts)
    })?;
    Ok(DescribingFunction {
        amplitude: n.amplitude,
        re: n.re,
        im: n.im,
        gain: n.gain,
        phase: n.phase,
        harmonics: n.harmonics,
        change: n.change,
    })
}

/// The loop work of `model` (from its initial state) under a sine of
/// amplitude `amplitude` in its steady cycle (options as for
/// `describing_function`).
#[pyfunction]
#[pyo3(signature = (model, amplitude, *, samples_per_period=1024, settle_periods=20, steady_tol=1e-9))]
pub fn loop_energy(
    py: Python<'_>,
    model: &Model,
    amplitude: f64,
    samples_per_period: usize,
    settle_periods: usize,
    steady_tol: f64,
) -> PyResult<LoopEnergy> {
    let opts = options(samples_per_period, settle_periods, steady_tol, 1);
    let e = analyse(py, model, |op| energy::loop_energy(op, amplitude, &opts))?;
    Ok(LoopEnergy {
        amplitude: e.amplitude,
        work: e.work,
        change: e.change,
    })
}
