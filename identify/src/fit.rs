//! Fitting any model's parameters to a record with Levenberg-Marquardt.

use crate::transform::Reparam;
use hysteron_operators::{Error, Operator};
use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt, TerminationReason};
use nalgebra::{DMatrix, DVector, Dyn, Owned};
use rayon::prelude::*;
use serde::Serialize;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// Why a fit could not start.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FitError {
    /// The record is empty, the columns differ in length, or a value is not
    /// finite.
    #[error("data: {0}")]
    Data(String),
    /// A requested free parameter is not among the model's.
    #[error("unknown parameter `{name}` (the model has: {available})")]
    UnknownParameter {
        /// The requested name.
        name: String,
        /// The model's parameter names.
        available: String,
    },
    /// A requested name matches several parameters.
    #[error("parameter name `{name}` is ambiguous: {matches}")]
    AmbiguousParameter {
        /// The requested name.
        name: String,
        /// The matching parameter names.
        matches: String,
    },
    /// Nothing to fit.
    #[error("no free parameters")]
    NoFreeParameters,
    /// A parameter index is out of range.
    #[error("parameter index {index} out of range (the model has {len})")]
    BadIndex {
        /// The index.
        index: usize,
        /// Number of parameters.
        len: usize,
    },
    /// The model cannot be simulated with the starting parameters.
    #[error("the model fails at the starting parameters: {0}")]
    Start(#[source] Error),
    /// An option is out of range.
    #[error("option `{name}`: {reason}")]
    Option {
        /// The option.
        name: &'static str,
        /// What it must satisfy.
        reason: &'static str,
    },
}

/// Settings of a fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FitOptions {
    /// Relative reduction of the cost below which the fit has converged
    /// (`ftol` of MINPACK).
    pub ftol: f64,
    /// Relative change of the (internal) parameters below which the fit has
    /// converged (`xtol`).
    pub xtol: f64,
    /// Orthogonality of residuals and Jacobian columns (`gtol`).
    pub gtol: f64,
    /// Budget of model evaluations per free parameter and iteration
    /// (MINPACK's `patience`: at most `patience·(k + 1)` residual evaluations).
    pub patience: usize,
    /// Relative step of the central finite differences in the internal
    /// parameters, `h = step · max(1, |θ|)`.
    pub step: f64,
    /// Compute the Jacobian's columns in parallel (rayon).
    pub parallel: bool,
    /// Compare every `stride`-th model output with the record: the model
    /// runs on `x` (for example an input upsampled `stride` times for a
    /// rate-dependent model) and its output at index `j · stride` is
    /// compared with `y[j]`, so `x.len() = stride · y.len()`. Default 1.
    pub stride: usize,
}

impl Default for FitOptions {
    /// `ftol = xtol = 1e-12`, `gtol = 0`, `patience = 200`,
    /// `step = ε^{1/3} ≈ 6e-6`, parallel.
    fn default() -> Self {
        Self {
            ftol: 1e-12,
            xtol: 1e-12,
            gtol: 0.0,
            patience: 200,
            step: f64::EPSILON.cbrt(),
            parallel: true,
            stride: 1,
        }
    }
}

/// How a fit ended.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum FitStatus {
    /// A convergence criterion was met (the text says which).
    Converged(String),
    /// The evaluation budget ran out before convergence.
    NotConverged(String),
    /// The solver stopped on a numerical problem.
    Failed(String),
}

impl FitStatus {
    /// True for [`FitStatus::Converged`].
    pub fn converged(&self) -> bool {
        matches!(self, FitStatus::Converged(_))
    }
}

/// One fitted parameter.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FittedParam {
    /// Parameter name (as in `param_names`).
    pub name: String,
    /// Index in the model's flat parameter vector.
    pub index: usize,
    /// Starting value.
    pub start: f64,
    /// Fitted value.
    pub value: f64,
    /// Standard error from the Gauss-Newton covariance (delta method
    /// through the reparametrization); `None` where `JᵀJ` is singular.
    pub std_error: Option<f64>,
    /// 95 % confidence interval: `θ ± 1.96 σ_θ` mapped through the
    /// reparametrization (so it respects the parameter's bounds).
    pub ci95: Option<(f64, f64)>,
}

/// The outcome of a fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FitReport {
    /// The free parameters.
    pub params: Vec<FittedParam>,
    /// The model's full parameter vector after the fit.
    pub all_params: Vec<f64>,
    /// Final cost `½ Σ r_i²`.
    pub cost: f64,
    /// Root-mean-square residual.
    pub rms: f64,
    /// `rms / std(y)`; `None` for a constant record.
    pub nrmse: Option<f64>,
    /// Levenberg-Marquardt iterations (Jacobian evaluations).
    pub iterations: usize,
    /// Model simulations over the whole record (residuals and Jacobian).
    pub evaluations: usize,
    /// Wall time of the fit.
    #[serde(serialize_with = "seconds")]
    pub wall_time: Duration,
    /// How it ended.
    pub status: FitStatus,
    /// Correlation matrix of the free parameters (in the order of
    /// `params`), `ρ_ij = C_ij / √(C_ii C_jj)` from the Gauss-Newton
    /// covariance `C = σ² (JᵀJ)⁻¹`; `None` where `JᵀJ` is singular. The
    /// reparametrization of bounded parameters is monotone and increasing,
    /// so to first order it leaves the correlations unchanged.
    pub correlation: Option<Vec<Vec<f64>>>,
}

fn seconds<S: serde::Serializer>(d: &Duration, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_f64(d.as_secs_f64())
}

/// A fitted model and its report.
#[derive(Debug, Clone)]
pub struct Fit {
    /// The model with the fitted parameters (reset).
    pub model: Box<dyn Operator<f64>>,
    /// What the fit did.
    pub report: FitReport,
}

/// Resolves parameter names to indices. A name matches a parameter whose
/// full name equals it or ends with `.name` (so `f_c` finds
/// `left.mms.f_c` when that is the only match).
pub fn free_by_names(
    model: &(dyn Operator<f64> + 'static),
    names: &[&str],
) -> Result<Vec<usize>, FitError> {
    let all = model.param_names();
    names
        .iter()
        .map(|name| {
            if let Some(i) = all.iter().position(|n| n == name) {
                return Ok(i);
            }
            let suffix = format!(".{name}");
            let hits: Vec<(usize, &String)> = all
                .iter()
                .enumerate()
                .filter(|(_, n)| n.ends_with(&suffix))
                .collect();
            match hits.as_slice() {
                [(i, _)] => Ok(*i),
                [] => Err(FitError::UnknownParameter {
                    name: name.to_string(),
                    available: all.join(", "),
                }),
                _ => Err(FitError::AmbiguousParameter {
                    name: name.to_string(),
                    matches: hits
                        .iter()
                        .map(|(_, n)| n.as_str())
                        .collect::<Vec<_>>()
                        .join(", "),
                }),
            }
        })
        .collect()
}

fn check_record(x: &[f64], y: &[f64], stride: usize) -> Result<(), FitError> {
    if x.is_empty() || y.is_empty() {
        return Err(FitError::Data("the record is empty".into()));
    }
    if stride == 0 || x.len() != y.len().saturating_mul(stride) {
        return Err(FitError::Data(format!(
            "input has {} samples, output {} (stride {stride})",
            x.len(),
            y.len()
        )));
    }
    if let Some(i) = x.iter().chain(y).position(|v| !v.is_finite()) {
        let (col, row) = if i < x.len() {
            ("input", i)
        } else {
            ("output", i - x.len())
        };
        return Err(FitError::Data(format!("{col} sample {row} is not finite")));
    }
    Ok(())
}

/// Progress of a running fit, passed to the callback of [`fit_with_progress`]
/// once per iteration (Jacobian evaluation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// Iterations so far.
    pub iteration: usize,
    /// Model simulations so far.
    pub evaluations: usize,
    /// Current cost `½ Σ r²`.
    pub cost: f64,
}

/// The least-squares problem handed to the solver: residuals
/// `model(x; φ(θ)) − y` over the whole record.
struct Problem<'a> {
    on_iteration: &'a (dyn Fn(Progress) + Sync),
    template: Box<dyn Operator<f64>>,
    base: Vec<f64>,
    free: Vec<usize>,
    maps: Vec<Reparam>,
    theta: DVector<f64>,
    x: &'a [f64],
    y: &'a [f64],
    current: Option<DVector<f64>>,
    penalty: f64,
    step: f64,
    parallel: bool,
    stride: usize,
    evaluations: AtomicUsize,
    jacobians: AtomicUsize,
}

impl Problem<'_> {
    // Every `free` index is `< base.len()` (checked in `fit_with_progress`).
    #[allow(clippy::indexing_slicing)]
    fn full_params(&self, theta: &[f64]) -> Vec<f64> {
        let mut p = self.base.clone();
        for ((&i, map), &t) in self.free.iter().zip(&self.maps).zip(theta) {
            p[i] = map.to_external(t);
        }
        p
    }

    /// Residuals at `theta`, or the model's error there.
    fn simulate(&self, theta: &[f64]) -> Result<DVector<f64>, Error> {
        self.evaluations.fetch_add(1, Ordering::Relaxed);
        let mut model = self.template.clone();
        model.set_params(&self.full_params(theta))?;
        let mut out = vec![0.0; self.x.len()];
        model.process(self.x, &mut out)?;
        Ok(DVector::from_iterator(
            self.y.len(),
            out.iter()
                .step_by(self.stride)
                .zip(self.y)
                .map(|(m, d)| m - d),
        ))
    }

    /// Central difference of the residuals along `θ_j` (one-sided where
    /// one side is outside the model's valid set, zero where both are).
    // `j < self.theta.len()`: the callers iterate `0..self.theta.len()`.
    #[allow(clippy::indexing_slicing)]
    fn column(&self, j: usize) -> DVector<f64> {
        let t = self.theta.as_slice();
        let h = self.step * t[j].abs().max(1.0);
        let shifted = |d: f64| {
            let mut v = t.to_vec();
            v[j] += d;
            self.simulate(&v).ok()
        };
        match (shifted(h), shifted(-h), &self.current) {
            (Some(p), Some(m), _) => (p - m) / (2.0 * h),
            (Some(p), None, Some(c)) => (p - c) / h,
            (None, Some(m), Some(c)) => (c - m) / h,
            _ => DVector::zeros(self.y.len()),
        }
    }

    fn jacobian_matrix(&self) -> DMatrix<f64> {
        self.jacobians.fetch_add(1, Ordering::Relaxed);
        let k = self.theta.len();
        let cols: Vec<DVector<f64>> = if self.parallel {
            (0..k).into_par_iter().map(|j| self.column(j)).collect()
        } else {
            (0..k).map(|j| self.column(j)).collect()
        };
        DMatrix::from_columns(&cols)
    }
}

impl<'a> Problem<'a> {
    // Every `free` index is `< base.len()` and `< domains.len()` (checked in
    // `fit_with_progress`; the test passes indices from `free_by_names`).
    #[allow(clippy::indexing_slicing)]
    fn new(
        model: &(dyn Operator<f64> + 'static),
        x: &'a [f64],
        y: &'a [f64],
        free: &[usize],
        opts: &FitOptions,
        on_iteration: &'a (dyn Fn(Progress) + Sync),
    ) -> Result<Self, FitError> {
        let base = model.params();
        let domains = model.param_domains();
        let maps: Vec<Reparam> = free.iter().map(|&i| Reparam(domains[i])).collect();
        let theta0 = DVector::from_iterator(
            free.len(),
            free.iter().zip(&maps).map(|(&i, m)| m.to_internal(base[i])),
        );
        let scale = y.iter().fold(1.0_f64, |a, v| a.max(v.abs()));
        let mut problem = Problem {
            on_iteration,
            template: dyn_clone::clone_box(model),
            base: base.clone(),
            free: free.to_vec(),
            maps,
            theta: theta0.clone(),
            x,
            y,
            current: None,
            penalty: 1e3 * scale,
            step: opts.step,
            parallel: opts.parallel,
            stride: opts.stride.max(1),
            evaluations: AtomicUsize::new(0),
            jacobians: AtomicUsize::new(0),
        };
        problem.current = Some(
            problem
                .simulate(theta0.as_slice())
                .map_err(FitError::Start)?,
        );
        Ok(problem)
    }
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, theta: &DVector<f64>) {
        self.theta.copy_from(theta);
        self.current = self.simulate(theta.as_slice()).ok();
    }

    fn params(&self) -> DVector<f64> {
        self.theta.clone()
    }

    /// Outside the model's valid set (a rejected parameter combination, a
    /// loop without solution) the residuals are a large constant, so the
    /// solver rejects the step and shrinks its trust region.
    fn residuals(&self) -> Option<DVector<f64>> {
        Some(
            self.current
                .clone()
                .unwrap_or_else(|| DVector::from_element(self.y.len(), self.penalty)),
        )
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        (self.on_iteration)(Progress {
            iteration: self.jacobians.load(Ordering::Relaxed),
            evaluations: self.evaluations.load(Ordering::Relaxed),
            cost: self
                .current
                .as_ref()
                .map_or(f64::INFINITY, |r| 0.5 * r.norm_squared()),
        });
        Some(self.jacobian_matrix())
    }
}

/// Fits the parameters at `free` (indices into `model.params()`) of `model`
/// to the record `(x, y)`, starting from the model's current parameters;
/// the others stay fixed. Bounded parameters are fitted through the
/// reparametrization of [`Reparam`] (from [`Operator::param_domains`]).
///
/// Residuals are `model(x) − y` over the whole record, simulated from the
/// model's initial state; the Jacobian is central finite differences in the
/// internal parameters (columns in parallel). Standard errors come from
/// `σ² (JᵀJ)⁻¹` with `σ² = Σ r² / (m − k)`.
pub fn fit(
    model: &(dyn Operator<f64> + 'static),
    x: &[f64],
    y: &[f64],
    free: &[usize],
    opts: &FitOptions,
) -> Result<Fit, FitError> {
    fit_with_progress(model, x, y, free, opts, &|_| {})
}

/// [`fit`], calling `on_iteration` once per iteration (for a progress
/// display).
pub fn fit_with_progress(
    model: &(dyn Operator<f64> + 'static),
    x: &[f64],
    y: &[f64],
    free: &[usize],
    opts: &FitOptions,
    on_iteration: &(dyn Fn(Progress) + Sync),
) -> Result<Fit, FitError> {
    let started = Instant::now();
    check_record(x, y, opts.stride)?;
    if free.is_empty() {
        return Err(FitError::NoFreeParameters);
    }
    let base = model.params();
    // (names and domains too: a foreign `Operator` may list fewer of them)
    let len = base
        .len()
        .min(model.param_names().len())
        .min(model.param_domains().len());
    if let Some(&index) = free.iter().find(|&&i| i >= len) {
        return Err(FitError::BadIndex { index, len });
    }
    if !(opts.step > 0.0 && opts.step < 0.1) {
        return Err(FitError::Option {
            name: "step",
            reason: "must lie in (0, 0.1)",
        });
    }
    if opts.patience == 0 {
        return Err(FitError::Option {
            name: "patience",
            reason: "must be ≥ 1",
        });
    }
    let problem = Problem::new(model, x, y, free, opts, on_iteration)?;

    let lm = LevenbergMarquardt::new()
        .with_ftol(opts.ftol)
        .with_xtol(opts.xtol)
        .with_gtol(opts.gtol)
        .with_patience(opts.patience);
    let (mut problem, lm_report) = lm.minimize(problem);
    let status = status_of(&lm_report.termination);

    // Make sure the state is at the returned parameters, then evaluate the
    // covariance there.
    let theta = problem.theta.clone();
    problem.set_params(&theta);
    let residuals = problem
        .residuals()
        .unwrap_or_else(|| DVector::zeros(y.len()));
    let jac = problem.jacobian_matrix();
    let m = y.len();
    let k = free.len();
    let ssr = residuals.norm_squared();
    let dof = m.saturating_sub(k).max(1) as f64;
    let cov = (jac.transpose() * &jac)
        .try_inverse()
        .map(|inv| inv * (ssr / dof));

    let all_params = problem.full_params(theta.as_slice());
    let names = model.param_names();
    // `j < free.len() = theta.len() = maps.len()`, and every `free` index
    // `i` is `< len` (checked above) `≤ names.len(), base.len()`,
    // `all_params.len() = base.len()`.
    #[allow(clippy::indexing_slicing)]
    let params = free
        .iter()
        .enumerate()
        .map(|(j, &i)| {
            let map = problem.maps[j];
            let t = theta[j];
            let var = cov
                .as_ref()
                .map(|c| c[(j, j)])
                .filter(|v| v.is_finite() && *v >= 0.0);
            let sd_t = var.map(f64::sqrt);
            let (a, b) = match sd_t {
                Some(s) => (map.to_external(t - 1.96 * s), map.to_external(t + 1.96 * s)),
                None => (f64::NAN, f64::NAN),
            };
            FittedParam {
                name: names[i].clone(),
                index: i,
                start: base[i],
                value: all_params[i],
                std_error: sd_t.map(|s| s * map.derivative(t).abs()),
                ci95: sd_t.map(|_| (a.min(b), a.max(b))),
            }
        })
        .collect();

    // `i, j < k`: `sd` has `k` entries.
    #[allow(clippy::indexing_slicing)]
    let correlation = cov.as_ref().and_then(|c| {
        let sd: Vec<f64> = (0..k).map(|j| c[(j, j)].sqrt()).collect();
        let rows: Vec<Vec<f64>> = (0..k)
            .map(|i| (0..k).map(|j| c[(i, j)] / (sd[i] * sd[j])).collect())
            .collect();
        rows.iter().flatten().all(|v| v.is_finite()).then_some(rows)
    });
    let rms = (ssr / m as f64).sqrt();
    let mean = y.iter().sum::<f64>() / m as f64;
    let sd_y = (y.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / m as f64).sqrt();
    let mut fitted = dyn_clone::clone_box(model);
    fitted.set_params(&all_params).map_err(FitError::Start)?;
    let report = FitReport {
        params,
        all_params,
        cost: 0.5 * ssr,
        rms,
        nrmse: (sd_y > 0.0).then(|| rms / sd_y),
        iterations: problem.jacobians.load(Ordering::Relaxed).saturating_sub(1),
        evaluations: problem.evaluations.load(Ordering::Relaxed),
        wall_time: started.elapsed(),
        status,
        correlation,
    };
    Ok(Fit {
        model: fitted,
        report,
    })
}

fn status_of(t: &TerminationReason) -> FitStatus {
    match t {
        TerminationReason::Converged { ftol, xtol } => FitStatus::Converged(
            match (ftol, xtol) {
                (true, true) => "cost and parameters converged",
                (true, false) => "cost converged",
                _ => "parameters converged",
            }
            .into(),
        ),
        TerminationReason::ResidualsZero => FitStatus::Converged("residuals are zero".into()),
        TerminationReason::Orthogonal => {
            FitStatus::Converged("residuals orthogonal to the Jacobian (gtol)".into())
        }
        TerminationReason::NoImprovementPossible(what) => FitStatus::Converged(format!(
            "no further improvement possible at machine precision ({what})"
        )),
        TerminationReason::LostPatience => {
            FitStatus::NotConverged("evaluation budget exhausted (patience)".into())
        }
        other => FitStatus::Failed(format!("{other:?}")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hysteron_composition::{OperatorExt, TravelLimits};
    use hysteron_operators::{BoucWen, Mms};

    /// The parallel central-difference Jacobian agrees with the
    /// levenberg-marquardt crate's own numerical differentiation.
    #[test]
    fn jacobian_matches_differentiate_numerically() {
        let model = Mms::new(1.5, 30.0)
            .unwrap()
            .series(BoucWen::constant(10.0, 0.6, 1.0, 2.5, 1.5, 1.0).unwrap())
            .with_limits(TravelLimits::Gap { b: 0.3, r0: 0.0 })
            .unwrap()
            .boxed();
        let x: Vec<f64> = (0..60).map(|i| 1.2 * (i as f64 * 0.2).sin()).collect();
        let y: Vec<f64> = model
            .clone()
            .run(&x)
            .unwrap()
            .iter()
            .map(|v| v * 1.01)
            .collect();
        let free = free_by_names(
            model.as_ref(),
            &["f_c", "k", "w", "beta", "gamma", "limits.b"],
        )
        .unwrap();
        let mut problem = Problem::new(
            model.as_ref(),
            &x,
            &y,
            &free,
            &FitOptions::default(),
            &|_| {},
        )
        .unwrap();
        let ours = problem.jacobian().unwrap();
        // (the reference takes ~10⁴ model evaluations: keep the record short)
        let reference = levenberg_marquardt::differentiate_numerically(&mut problem).unwrap();
        let scale = reference.amax();
        let worst = (&ours - &reference).amax();
        assert!(
            worst <= 1e-5 * scale,
            "max difference {worst:e} (scale {scale:e})"
        );
        // and the serial path gives the same matrix bit for bit
        problem.parallel = false;
        assert_eq!(problem.jacobian().unwrap(), ours);
    }

    #[test]
    fn stride_compares_every_stride_th_output() {
        use hysteron_operators::Gain;
        let model: Box<dyn Operator<f64>> = Gain::new(1.0).unwrap().boxed();
        let x: Vec<f64> = (0..42).map(|i| (i as f64 * 0.3).sin()).collect();
        // y[j] = 2.5 x[3 j]; the samples in between are left out
        let y: Vec<f64> = x.iter().step_by(3).map(|v| 2.5 * v).collect();
        let x = &x[..3 * y.len()];
        let opts = FitOptions {
            stride: 3,
            ..FitOptions::default()
        };
        let f = fit(model.as_ref(), x, &y, &[0], &opts).unwrap();
        assert!((f.report.params[0].value - 2.5).abs() < 1e-12);
        assert!(fit(model.as_ref(), &x[1..], &y, &[0], &opts).is_err());
    }

    #[test]
    fn bad_requests_are_errors() {
        let model: Box<dyn Operator<f64>> = Mms::new(1.0, 5.0).unwrap().boxed();
        let x = [0.1, 0.2];
        let opts = FitOptions::default();
        assert!(matches!(
            fit(model.as_ref(), &[], &[], &[0], &opts),
            Err(FitError::Data(_))
        ));
        assert!(matches!(
            fit(model.as_ref(), &x, &[0.0], &[0], &opts),
            Err(FitError::Data(_))
        ));
        assert!(matches!(
            fit(model.as_ref(), &x, &[0.0, f64::NAN], &[0], &opts),
            Err(FitError::Data(_))
        ));
        assert!(matches!(
            fit(model.as_ref(), &x, &x, &[], &opts),
            Err(FitError::NoFreeParameters)
        ));
        assert!(matches!(
            fit(model.as_ref(), &x, &x, &[7], &opts),
            Err(FitError::BadIndex { .. })
        ));
        assert!(matches!(
            free_by_names(model.as_ref(), &["nope"]),
            Err(FitError::UnknownParameter { .. })
        ));
        let bad = FitOptions {
            step: 0.0,
            ..FitOptions::default()
        };
        assert!(matches!(
            fit(model.as_ref(), &x, &x, &[0], &bad),
            Err(FitError::Option { .. })
        ));
    }
}
