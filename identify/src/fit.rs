//! Fitting any model's parameters to one record or several with
//! Levenberg-Marquardt.

use crate::compressed::Compressed;
use crate::diagnostics;
use crate::error::{option, FitError};
use crate::metrics;
use crate::options::{FitOptions, Progress};
use crate::outcome::{Fit, FitReport, FitStatus, FittedParam, IdentifiabilityWarning, RecordFit};
use crate::problem::{Layout, Problem};
use crate::record::Record;
use hysteron_operators::Operator;
use levenberg_marquardt::{LevenbergMarquardt, TerminationReason};
use nalgebra::{DMatrix, DVector};
use std::sync::atomic::Ordering;
use std::time::Instant;

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

fn check_records(records: &[Record<'_>], stride: usize) -> Result<(), FitError> {
    if records.is_empty() {
        return Err(FitError::Data("no records".into()));
    }
    let several = records.len() > 1;
    for (r, record) in records.iter().enumerate() {
        let which = if several {
            format!("record {r}: ")
        } else {
            String::new()
        };
        let (x, y) = (record.x, record.y);
        if x.is_empty() || y.is_empty() {
            return Err(FitError::Data(format!("{which}the record is empty")));
        }
        if stride == 0 || x.len() != y.len().saturating_mul(stride) {
            return Err(FitError::Data(format!(
                "{which}input has {} samples, output {} (stride {stride})",
                x.len(),
                y.len()
            )));
        }
        if record.skip >= y.len() {
            return Err(FitError::Data(format!(
                "{which}the warm-up skips {} of its {} samples: nothing is left to compare",
                record.skip,
                y.len()
            )));
        }
        if let Some(i) = x.iter().chain(y).position(|v| !v.is_finite()) {
            let (col, row) = if i < x.len() {
                ("input", i)
            } else {
                ("output", i - x.len())
            };
            return Err(FitError::Data(format!(
                "{which}{col} sample {row} is not finite"
            )));
        }
    }
    Ok(())
}

/// Fits the parameters at `free` (indices into `model.params()`) of `model`
/// to the record `(x, y)`, starting from the model's current parameters;
/// the others stay fixed. Bounded parameters are fitted through the
/// reparametrization of [`Reparam`](crate::Reparam) (from [`Parameters::param_domains`](hysteron_operators::Parameters::param_domains)).
///
/// Residuals are `model(x) − y` over the whole record, simulated from the
/// model's initial state; the Jacobian is central finite differences in the
/// internal parameters (columns in parallel). Standard errors come from
/// `σ² (JᵀJ)⁻¹` with `σ² = Σ r² / (m − k)`. One record of
/// [`fit_records`].
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
    fit_records(model, &[Record::new(x, y)], free, &[], opts, on_iteration)
}

/// Fits one parameter set to several records at once.
///
/// The parameters at `free` are shared by all records; those at `own` are
/// fitted separately for each record (an initial state, a preload): record
/// `r` runs with its own value of each. Every record is simulated from the
/// model's initial state; its first `skip` outputs are simulated but not
/// compared. The least-squares problem stacks the residuals
///
/// `r = [ model_r(x_r; φ(θ_shared, θ_r))[skip_r..] − y_r[skip_r..] ]_r`
///
/// and is solved as in [`fit`] (Levenberg-Marquardt, central
/// finite-difference Jacobian, bounded parameters reparametrized). The
/// report gives the shared parameters, then each record's own
/// ([`FittedParam::record`]), and the figures per record
/// ([`FitReport::records`]).
///
/// # Requirements
/// * at least one record; in each, `x.len() = stride · y.len()`, finite
///   samples, and `skip < y.len()`;
/// * `free ∪ own` non-empty, without repeats, no index in both.
///
/// # Budget
/// [`FitOptions::max_evaluations`] and [`FitOptions::max_seconds`] end the
/// search at the last accepted point, [`FitStatus::NotConverged`] with the
/// reason; the standard errors at the end cost one more simulation and one
/// Jacobian (`2k` simulations) beyond the budget.
pub fn fit_records(
    model: &(dyn Operator<f64> + 'static),
    records: &[Record<'_>],
    free: &[usize],
    own: &[usize],
    opts: &FitOptions,
    on_iteration: &(dyn Fn(Progress) + Sync),
) -> Result<Fit, FitError> {
    let started = Instant::now();
    check_request(model, records, free, own, opts)?;
    let layout = Layout {
        shared: free.to_vec(),
        own: own.to_vec(),
        records: records.len(),
    };
    let entries = layout.entries();
    let problem = start(model, records, layout, opts, on_iteration)?;
    let (mut problem, theta, status) = search(problem, opts);
    let at = Solution::at(&mut problem, &theta, entries.len());
    let base = model.params();
    let (params, all_params) = fitted_params(model, &problem, &theta, &entries, &base, &at);
    let correlation = correlation(&at, entries.len());
    let (rms, nrmse, per_record) = record_figures(records, at.residuals.as_slice());
    let warnings = identifiability(&params, &at, correlation.as_deref());
    let mut fitted = dyn_clone::clone_box(model);
    fitted.set_params(&all_params).map_err(FitError::Start)?;
    let report = FitReport {
        params,
        all_params,
        cost: 0.5 * at.ssr,
        rms,
        nrmse,
        records: per_record,
        iterations: problem.jacobians.load(Ordering::Relaxed).saturating_sub(1),
        evaluations: problem.evaluations.load(Ordering::Relaxed),
        jacobian: problem.jacobian_kind(),
        wall_time: started.elapsed(),
        status,
        correlation,
        condition_number: at.condition_number,
        warnings,
        starts: None,
    };
    Ok(Fit {
        model: fitted,
        report,
    })
}

/// Step 1: the records, the indices of the free parameters and the
/// options are valid.
fn check_request(
    model: &(dyn Operator<f64> + 'static),
    records: &[Record<'_>],
    free: &[usize],
    own: &[usize],
    opts: &FitOptions,
) -> Result<(), FitError> {
    check_records(records, opts.stride)?;
    if free.is_empty() && own.is_empty() {
        return Err(FitError::NoFreeParameters);
    }
    // (names and domains too: a foreign `Operator` may list fewer of them)
    let len = model
        .params()
        .len()
        .min(model.param_names().len())
        .min(model.param_domains().len());
    if let Some(&index) = free.iter().chain(own).find(|&&i| i >= len) {
        return Err(FitError::BadIndex { index, len });
    }
    let all: Vec<usize> = free.iter().chain(own).copied().collect();
    if let Some((_, &index)) = all
        .iter()
        .enumerate()
        .find(|&(j, i)| all.get(..j).is_some_and(|seen| seen.contains(i)))
    {
        return Err(FitError::Repeated { index });
    }
    option(
        opts.step > 0.0 && opts.step < 0.1,
        "step",
        "must lie in (0, 0.1)",
    )?;
    option(opts.patience > 0, "patience", "must be ≥ 1")?;
    option(
        opts.max_evaluations != Some(0),
        "max_evaluations",
        "must be ≥ 1",
    )?;
    let seconds_ok = opts
        .max_seconds
        .is_none_or(|s| s > 0.0 && s.is_finite() && s <= 1e9);
    option(
        seconds_ok,
        "max_seconds",
        "must be positive and finite (at most 1e9)",
    )
}

/// Step 2: the problem at the model's parameters, its first simulation
/// run (an error there names the record).
fn start<'a>(
    model: &'a (dyn Operator<f64> + 'static),
    records: &'a [Record<'a>],
    layout: Layout,
    opts: &FitOptions,
    on_iteration: &'a (dyn Fn(Progress) + Sync),
) -> Result<Problem<'a>, FitError> {
    Problem::new(model, records, layout, opts, on_iteration).map_err(|(r, e)| {
        if records.len() > 1 {
            FitError::RecordStart {
                record: r,
                source: e,
            }
        } else {
            FitError::Start(e)
        }
    })
}

/// Step 3: Levenberg-Marquardt's search; the point it ends at (the last
/// accepted one where the budget ended it) and why it ended.
fn search<'a>(problem: Problem<'a>, opts: &FitOptions) -> (Problem<'a>, DVector<f64>, FitStatus) {
    let lm = LevenbergMarquardt::new()
        .with_ftol(opts.ftol)
        .with_xtol(opts.xtol)
        .with_gtol(opts.gtol)
        .with_patience(opts.patience);
    let (compressed, lm_report) = lm.minimize(Compressed::new(problem));
    let problem = compressed.into_inner();
    let (theta, status) = match problem.stopped() {
        Some(why) => (problem.accepted(), FitStatus::NotConverged(why)),
        None => (problem.theta.clone(), status_of(&lm_report.termination)),
    };
    (problem, theta, status)
}

/// Step 4: the linearization at the solution: `JᵀJ`, its conditioning,
/// the determined parameters and the covariance `σ² (JᵀJ)⁻¹`.
struct Solution {
    residuals: DVector<f64>,
    ssr: f64,
    condition_number: Option<f64>,
    weakest: Vec<f64>,
    determined: Vec<bool>,
    inverse: Option<DMatrix<f64>>,
    cov: Option<DMatrix<f64>>,
}

impl Solution {
    /// At `theta` (`k` entries), where `problem` is simulated again first.
    fn at(problem: &mut Problem<'_>, theta: &DVector<f64>, k: usize) -> Self {
        problem.evaluate_at(theta);
        let residuals = problem.current_residuals();
        let m = problem.len();
        // `JᵀJ` and the column norms of `J` are all the report needs: the
        // compressed Jacobian has them (and is the one the search kept).
        let jac = if m > k + 1 {
            problem.compressed_jacobian()
        } else {
            problem.jacobian_matrix()
        };
        let ssr = residuals.norm_squared();
        let dof = m.saturating_sub(k).max(1) as f64;
        let jtj = jac.transpose() * &jac;
        let (condition_number, weakest) = diagnostics::conditioning(&jtj);
        let determined = diagnostics::determined(&jac);
        let inverse = diagnostics::inverse_of_determined(&jtj, &determined);
        let cov = inverse.as_ref().map(|inv| inv * (ssr / dof));
        Self {
            residuals,
            ssr,
            condition_number,
            weakest,
            determined,
            inverse,
            cov,
        }
    }
}

/// Step 5: each fitted parameter with its standard error and interval,
/// and the model's whole vector: the shared parameters fitted, the
/// per-record ones at their start.
fn fitted_params(
    model: &(dyn Operator<f64> + 'static),
    problem: &Problem<'_>,
    theta: &DVector<f64>,
    entries: &[(usize, Option<usize>)],
    base: &[f64],
    at: &Solution,
) -> (Vec<FittedParam>, Vec<f64>) {
    let names = model.param_names();
    let mut all_params = problem.full_params(theta.as_slice(), 0);
    // `j < k = theta.len() = maps.len()`, and every index `i` is `< len`
    // (checked in `check_request`) `≤ names.len(), base.len()`;
    // `full_params` has `base.len()` entries.
    #[allow(clippy::indexing_slicing)]
    let params: Vec<FittedParam> = entries
        .iter()
        .enumerate()
        .map(|(j, &(i, record))| {
            let map = problem.maps[j];
            let t = theta[j];
            let var = at
                .cov
                .as_ref()
                .map(|c| c[(j, j)])
                .filter(|v| v.is_finite() && *v >= 0.0);
            let sd_t = var.map(f64::sqrt);
            let (a, b) = match sd_t {
                Some(s) => (map.to_external(t - 1.96 * s), map.to_external(t + 1.96 * s)),
                None => (f64::NAN, f64::NAN),
            };
            if record.is_some() {
                all_params[i] = base[i];
            }
            FittedParam {
                name: names[i].clone(),
                index: i,
                start: base[i],
                value: map.to_external(t),
                std_error: sd_t.map(|s| s * map.derivative(t).abs()),
                ci95: sd_t.map(|_| (a.min(b), a.max(b))),
                record,
            }
        })
        .collect();
    (params, all_params)
}

/// Step 6: the correlations of the `k` fitted parameters, from `(JᵀJ)⁻¹`
/// itself (σ² cancels), so that a fit with zero residuals still has them;
/// NaN only in the rows and columns of undetermined parameters.
// `i, j < k`: `sd` has `k` entries.
#[allow(clippy::indexing_slicing)]
fn correlation(at: &Solution, k: usize) -> Option<Vec<Vec<f64>>> {
    at.inverse.as_ref().and_then(|c| {
        let sd: Vec<f64> = (0..k).map(|j| c[(j, j)].sqrt()).collect();
        let rows: Vec<Vec<f64>> = (0..k)
            .map(|i| (0..k).map(|j| c[(i, j)] / (sd[i] * sd[j])).collect())
            .collect();
        let finite = |i: usize| at.determined.get(i).copied().unwrap_or(false);
        (0..k)
            .all(|i| (0..k).all(|j| !(finite(i) && finite(j)) || rows[i][j].is_finite()))
            .then_some(rows)
    })
}

/// Step 7: RMS and NRMSE over all records and per record, from the
/// residuals of the scored samples, record after record.
fn record_figures(records: &[Record<'_>], residuals: &[f64]) -> (f64, Option<f64>, Vec<RecordFit>) {
    fn scored<'a>(r: &Record<'a>) -> &'a [f64] {
        r.y.get(r.skip..).unwrap_or_default()
    }
    let all_y: Vec<f64> = records.iter().flat_map(|r| scored(r).to_vec()).collect();
    let (rms, nrmse) = figures(residuals, &all_y);
    let mut at = 0;
    let per_record = records
        .iter()
        .map(|r| {
            let y = scored(r);
            let res = residuals.get(at..at + y.len()).unwrap_or_default();
            at += y.len();
            let (rms, nrmse) = figures(res, y);
            RecordFit {
                samples: y.len(),
                rms,
                nrmse,
            }
        })
        .collect();
    (rms, nrmse, per_record)
}

/// Step 8: the warnings: every undetermined parameter, then those of
/// [`diagnostics::warnings`].
fn identifiability(
    params: &[FittedParam],
    at: &Solution,
    correlation: Option<&[Vec<f64>]>,
) -> Vec<IdentifiabilityWarning> {
    let mut warnings: Vec<_> = params
        .iter()
        .zip(&at.determined)
        .filter(|(_, &d)| !d)
        .map(|(p, _)| IdentifiabilityWarning::Undetermined {
            name: p.label(),
            value: p.value,
        })
        .collect();
    warnings.extend(diagnostics::warnings(params, correlation, &at.weakest));
    warnings
}

/// `(RMS(res), RMS(res) / RMS(y))` of residuals `res` against the data
/// `y`, with the root mean squares of [`metrics::rms`] (about zero, as
/// `hysteron validate` scores); the second `None` where `y` is zero
/// throughout.
fn figures(res: &[f64], y: &[f64]) -> (f64, Option<f64>) {
    let rms = metrics::rms(res);
    let reference = metrics::rms(y);
    (rms, (reference > 0.0).then(|| rms / reference))
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
    use hysteron_operators::{BoucWen, ElastoPlastic, Mms};
    use levenberg_marquardt::LeastSquaresProblem;
    use std::sync::atomic::Ordering;

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
        let records = [Record::new(&x, &y)];
        let mut problem =
            one_record_problem(model.as_ref(), &records, &free, &FitOptions::default());
        let ours = problem.jacobian().unwrap();
        // (the reference takes ~10⁴ model evaluations: keep the record short)
        let reference = levenberg_marquardt::differentiate_numerically(&mut problem).unwrap();
        let scale = reference.amax();
        let worst = (&ours - &reference).amax();
        assert!(
            worst <= 1e-5 * scale,
            "max difference {worst:e} (scale {scale:e})"
        );
        // and the serial path gives the same matrix bit for bit (a new
        // problem: this one would hand back the Jacobian it keeps)
        let serial = FitOptions {
            parallel: false,
            ..FitOptions::default()
        };
        let problem = one_record_problem(model.as_ref(), &records, &free, &serial);
        assert!(!problem.parallel);
        assert_eq!(problem.jacobian().unwrap(), ours);
    }

    /// The problem of fitting the `shared` parameters of `model` to one
    /// record, with `opts`.
    fn one_record_problem<'a>(
        model: &(dyn Operator<f64> + 'static),
        records: &'a [Record<'a>],
        shared: &[usize],
        opts: &FitOptions,
    ) -> Problem<'a> {
        let layout = Layout {
            shared: shared.to_vec(),
            own: vec![],
            records: 1,
        };
        Problem::new(model, records, layout, opts, &|_| {}).unwrap()
    }

    /// A Bouc-Wen spring with `n = 1.5`, and `f` of its response to
    /// `x_i = a sin(w i)` (`len` samples).
    fn spring_record(
        len: usize,
        a: f64,
        w: f64,
        f: impl Fn(f64) -> f64,
    ) -> (Box<dyn Operator<f64>>, Vec<f64>, Vec<f64>) {
        let model = BoucWen::constant(10.0, 0.6, 1.0, 2.5, 1.5, 1.5)
            .unwrap()
            .boxed();
        let x: Vec<f64> = (0..len).map(|i| a * (i as f64 * w).sin()).collect();
        let y = model.clone().run(&x).unwrap().into_iter().map(f).collect();
        (model, x, y)
    }

    /// A fit of one record with the dual pass started beside each trial
    /// simulation (`parallel`, the default) and without it: the same report,
    /// bit for bit, with a stride and a skip; and a problem's speculated
    /// compressed Jacobian is the one computed on the caller's thread.
    #[test]
    fn the_pass_beside_the_simulation_changes_no_bit() {
        let (model, x, y) = spring_record(3000, 1.2, 0.011, |v| v * 1.03 + 0.002);
        let free = free_by_names(model.as_ref(), &["w", "beta", "gamma", "n"]).unwrap();
        let y3: Vec<f64> = y.iter().step_by(3).copied().collect();
        let x3 = &x[..3 * y3.len()];
        let record = [Record {
            x: x3,
            y: &y3,
            skip: 40,
        }];
        let opts = |parallel| FitOptions {
            parallel,
            stride: 3,
            ..FitOptions::default()
        };
        let with = fit_records(model.as_ref(), &record, &free, &[], &opts(true), &|_| {}).unwrap();
        let without =
            fit_records(model.as_ref(), &record, &free, &[], &opts(false), &|_| {}).unwrap();
        assert!(with.report.iterations > 2, "{}", with.report.iterations);
        // (all but the wall time)
        let mut with = with.report;
        with.wall_time = without.report.wall_time;
        assert_eq!(with, without.report);
        let mut problem = one_record_problem(model.as_ref(), &record, &free, &opts(true));
        assert!(problem.speculator.is_some());
        let theta = problem.theta.map(|t| t * 1.01 + 0.001);
        problem.set_params(&theta);
        let speculated = problem.compressed_jacobian();
        let taken = problem
            .speculator
            .as_ref()
            .map(|s| s.taken.load(Ordering::Relaxed));
        assert_eq!(taken, Some(1));
        let mut serial = one_record_problem(model.as_ref(), &record, &free, &opts(false));
        assert!(serial.speculator.is_none());
        serial.set_params(&theta);
        assert_eq!(speculated, serial.compressed_jacobian());
    }

    /// The compressed Jacobian folded from the dual passes keeps `JᵀJ`
    /// and `Jᵀr` of the full one, for one record and for two with a
    /// parameter of their own (folded in parallel, then together), and is
    /// what folding the full Jacobian gives.
    #[test]
    fn streamed_compression_keeps_the_normal_equations() {
        let (model, x, y) = spring_record(1500, 1.2, 0.013, |v| v * 1.02);
        let (_, x2, y2) = spring_record(900, 0.8, 0.021, |v| v + 0.01);
        let shared = free_by_names(model.as_ref(), &["w", "beta", "n"]).unwrap();
        let own = free_by_names(model.as_ref(), &["h0"]).unwrap();
        for (records, own) in [
            (vec![Record::new(&x, &y)], vec![]),
            (vec![Record::new(&x, &y), Record::new(&x2, &y2)], own),
        ] {
            let layout = Layout {
                shared: shared.clone(),
                records: records.len(),
                own,
            };
            let problem = Problem::new(
                model.as_ref(),
                &records,
                layout,
                &FitOptions::default(),
                &|_| {},
            )
            .unwrap();
            let before = problem.evaluations.load(Ordering::Relaxed);
            let jc = problem.compressed_jacobian();
            // one dual pass per record, nothing else
            assert_eq!(
                problem.evaluations.load(Ordering::Relaxed) - before,
                problem.jacobian_cost()
            );
            let (j, r) = (problem.jacobian_matrix(), problem.current_residuals());
            let k = j.ncols();
            assert_eq!((jc.nrows(), jc.ncols()), (k + 1, k));
            let (a, b) = (jc.transpose() * &jc, j.transpose() * &j);
            assert!((&a - &b).amax() <= 1e-12 * b.amax(), "JᵀJ");
            let mut rc = nalgebra::DVector::zeros(k + 1);
            rc[0] = r.norm();
            let (ga, gb) = (jc.transpose() * rc, j.transpose() * &r);
            assert!((&ga - &gb).amax() <= 1e-12 * gb.amax(), "Jᵀr");
            let folded = crate::triangular::compress_jacobian(&r, &j);
            assert!((&folded - &jc).amax() <= 1e-12 * jc.amax(), "{folded} {jc}");
        }
    }

    /// A gain whose dual twin reports a NaN derivative at every sample.
    #[derive(Debug, Clone)]
    struct NanTwin<T: hysteron_operators::Float> {
        gain: hysteron_operators::Gain<T>,
    }

    /// The traits of `NanTwin` other than its trial, from its gain.
    macro_rules! nan_twin_traits {
        ($t:ty) => {
            impl hysteron_operators::Parameters<$t> for NanTwin<$t> {
                fn n_params(&self) -> usize {
                    self.gain.n_params()
                }
                fn params_into(&self, out: &mut Vec<$t>) {
                    self.gain.params_into(out)
                }
                fn param_names(&self) -> Vec<String> {
                    self.gain.param_names()
                }
                fn set_params(&mut self, p: &[$t]) -> hysteron_operators::Result<()> {
                    self.gain.set_params(p)
                }
            }
            impl hysteron_operators::SamplePeriod<$t> for NanTwin<$t> {}
            impl hysteron_operators::Hints<$t> for NanTwin<$t> {}
        };
    }
    nan_twin_traits!(f64);
    nan_twin_traits!(hysteron_operators::Dual);

    impl Operator<f64> for NanTwin<f64> {
        hysteron_composition::delegate_stepping!(f64, gain);
    }

    impl hysteron_operators::Derivatives<f64> for NanTwin<f64> {
        fn to_dual(&self) -> Option<Box<dyn Operator<hysteron_operators::Dual>>> {
            let k = hysteron_operators::Dual::constant(self.gain.gain());
            Some(Box::new(NanTwin {
                gain: hysteron_operators::Gain::new(k).ok()?,
            }))
        }
    }

    impl Operator<hysteron_operators::Dual> for NanTwin<hysteron_operators::Dual> {
        fn trial(
            &mut self,
            x: hysteron_operators::Dual,
        ) -> hysteron_operators::Result<hysteron_operators::Trial<hysteron_operators::Dual>>
        {
            let mut t = self.gain.trial(x)?;
            t.output.eps[0] = f64::NAN;
            Ok(t)
        }
        fn commit(&mut self) {
            self.gain.commit()
        }
        fn reset(&mut self) {
            self.gain.reset()
        }
    }

    impl hysteron_operators::Derivatives<hysteron_operators::Dual>
        for NanTwin<hysteron_operators::Dual>
    {
    }

    /// Where the dual pass gives a derivative that is not finite, the
    /// compressed Jacobian is that of central differences, and the failed
    /// pass is not run a second time: one pass and two simulations.
    #[test]
    fn a_failed_dual_pass_falls_back_to_differences_once() {
        let model: Box<dyn Operator<f64>> = Box::new(NanTwin {
            gain: hysteron_operators::Gain::new(2.0).unwrap(),
        });
        let x: Vec<f64> = (0..50).map(|i| (i as f64 * 0.3).sin()).collect();
        let y: Vec<f64> = x.iter().map(|v| 2.5 * v).collect();
        let records = [Record::new(&x, &y)];
        let free = free_by_names(model.as_ref(), &["k"]).unwrap();
        let problem = one_record_problem(model.as_ref(), &records, &free, &FitOptions::default());
        let before = problem.evaluations.load(Ordering::Relaxed);
        let jc = problem.compressed_jacobian();
        assert_eq!(problem.evaluations.load(Ordering::Relaxed) - before, 1 + 2);
        let fd = crate::triangular::compress_jacobian(
            &problem.current_residuals(),
            &problem.fd_jacobian(),
        );
        assert_eq!(jc, fd);
        // and a fit through it finds the gain
        let f = fit(model.as_ref(), &x, &y, &free, &FitOptions::default()).unwrap();
        assert!(
            (f.report.params[0].value - 2.5).abs() < 1e-8,
            "{}",
            f.report
        );
    }

    /// Coming back to the accepted point (after a rejected step, and for
    /// the report) costs no simulation and no dual pass: the residuals and
    /// the Jacobian there are those computed before, bit for bit, and a
    /// new point is simulated.
    #[test]
    fn the_accepted_point_is_not_simulated_twice() {
        let (model, x, y) = spring_record(400, 1.2, 0.05, |v| v * 1.02);
        let free = free_by_names(model.as_ref(), &["w", "beta", "n"]).unwrap();
        let records = [Record::new(&x, &y)];
        let mut problem =
            one_record_problem(model.as_ref(), &records, &free, &FitOptions::default());
        let runs = |p: &Problem| p.evaluations.load(Ordering::Relaxed);
        let accepted = problem.params();
        let (r0, j0) = (problem.residuals().unwrap(), problem.jacobian().unwrap());
        let after_jacobian = runs(&problem);
        // a trial step elsewhere is simulated
        let mut trial = accepted.clone();
        trial[1] += 0.01;
        problem.set_params(&trial);
        assert_eq!(runs(&problem), after_jacobian + 1);
        assert_ne!(problem.residuals().unwrap(), r0);
        // back at the accepted point: nothing runs, the same bits
        problem.set_params(&accepted);
        problem.evaluate_at(&accepted);
        assert_eq!(runs(&problem), after_jacobian + 1);
        assert_eq!(problem.residuals().unwrap(), r0);
        assert_eq!(problem.jacobian_matrix(), j0);
        assert_eq!(runs(&problem), after_jacobian + 1);
        // and they are what a simulation there gives
        let fresh = problem.simulate(accepted.as_slice()).unwrap();
        assert_eq!(fresh, r0);
        // a Jacobian at another point is computed
        problem.set_params(&trial);
        let before = runs(&problem);
        assert_ne!(problem.jacobian().unwrap(), j0);
        assert!(runs(&problem) > before);
    }

    /// `scored_in` picks, block by block, exactly the samples the plain
    /// rule picks: every `stride`-th input sample, from output `skip` on,
    /// up to `y.len()` (blocks of several lengths, including ones that
    /// split a stride and ones past the end).
    #[test]
    fn scored_samples_are_those_of_the_plain_rule() {
        let y = [0.0; 11];
        for stride in 1..5 {
            for skip in [0, 1, 4, 10] {
                let record = Record {
                    x: &[],
                    y: &y,
                    skip,
                };
                let plain: Vec<(usize, usize)> = (0..stride * y.len() + 7)
                    .filter(|k| k % stride == 0 && k / stride >= skip && k / stride < y.len())
                    .map(|k| (k, k / stride))
                    .collect();
                for len in [1, 2, 3, 5, 64] {
                    let mut got = Vec::new();
                    for offset in (0..stride * y.len() + 7).step_by(len) {
                        got.extend(
                            record
                                .scored_in(stride, offset, len)
                                .inspect(|&(i, _)| assert!(i < len))
                                .map(|(i, q)| (offset + i, q)),
                        );
                    }
                    assert_eq!(got, plain, "stride {stride} skip {skip} block {len}");
                }
            }
        }
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

    /// A displacement sweep `A sin(2π f t)` around a centre `c`, `n` samples.
    fn sweep(n: usize, a: f64, f: f64, c: f64) -> Vec<f64> {
        (0..n)
            .map(|i| c + a * (2.0 * std::f64::consts::PI * f * i as f64 / n as f64).sin())
            .collect()
    }

    /// Three synthetic records of one elastoplastic element, each starting
    /// from its own preload `f0`: one shared `k, F_b` and the three `f0`
    /// are recovered to 1e-8 relative (noise-free), and each record's
    /// figures are reported.
    #[test]
    fn several_records_with_their_own_initial_states_recover_the_parameters() {
        let truth = [(4.0, 1.5)];
        let f0s = [0.3, -0.4, 0.0];
        let xs = [
            sweep(300, 1.0, 2.0, 0.1),
            sweep(200, 0.4, 3.0, -0.2),
            sweep(250, 2.0, 1.0, 0.0),
        ];
        let ys: Vec<Vec<f64>> = xs
            .iter()
            .zip(f0s)
            .map(|(x, f0)| {
                let mut op = ElastoPlastic::from_params(hysteron_operators::ElastoPlasticParams {
                    k: truth[0].0,
                    f_b: truth[0].1,
                    f0,
                })
                .unwrap();
                op.run(x).unwrap()
            })
            .collect();
        let records: Vec<Record<'_>> = xs.iter().zip(&ys).map(|(x, y)| Record::new(x, y)).collect();
        let start: Box<dyn Operator<f64>> = ElastoPlastic::new(2.0, 0.8).unwrap().boxed();
        let free = free_by_names(start.as_ref(), &["k", "f_b"]).unwrap();
        let own = free_by_names(start.as_ref(), &["f0"]).unwrap();
        let f = fit_records(
            start.as_ref(),
            &records,
            &free,
            &own,
            &FitOptions::default(),
            &|_| {},
        )
        .unwrap();
        let r = &f.report;
        assert!(r.status.converged(), "{:?}", r.status);
        assert_eq!(r.params.len(), 2 + 3);
        let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(1.0);
        assert!(rel(r.params[0].value, 4.0) < 1e-8, "{:?}", r.params[0]);
        assert!(rel(r.params[1].value, 1.5) < 1e-8, "{:?}", r.params[1]);
        for (j, f0) in f0s.iter().enumerate() {
            let p = &r.params[2 + j];
            assert_eq!(p.record, Some(j));
            assert_eq!(p.name, "f0");
            assert!(rel(p.value, *f0) < 1e-8, "{p:?}");
        }
        // the shared model keeps the starting f0; the fitted k, F_b
        assert_eq!(r.all_params[2], 0.0);
        assert_eq!(r.records.len(), 3);
        assert_eq!(r.records[1].samples, 200);
        assert!(r.records.iter().all(|rf| rf.rms < 1e-8), "{:?}", r.records);
        // one shared f0 cannot fit all three: the records disagree
        let all = free_by_names(start.as_ref(), &["k", "f_b", "f0"]).unwrap();
        let one = fit_records(
            start.as_ref(),
            &records,
            &all,
            &[],
            &FitOptions::default(),
            &|_| {},
        )
        .unwrap();
        assert!(one.report.rms > 1e-2, "{}", one.report.rms);
    }

    /// The warm-up is simulated but not compared: a record whose first
    /// samples disagree with the model fits exactly once they are skipped.
    #[test]
    fn skip_leaves_the_warm_up_out_of_the_residuals() {
        let x = sweep(400, 1.0, 2.0, 0.0);
        let mut y = ElastoPlastic::new(4.0, 1.5).unwrap().run(&x).unwrap();
        for v in &mut y[..50] {
            *v += 0.7;
        }
        let start: Box<dyn Operator<f64>> = ElastoPlastic::new(3.0, 1.0).unwrap().boxed();
        let free = free_by_names(start.as_ref(), &["k", "f_b"]).unwrap();
        let opts = FitOptions::default();
        let run = |skip| {
            let rec = [Record { x: &x, y: &y, skip }];
            fit_records(start.as_ref(), &rec, &free, &[], &opts, &|_| {}).unwrap()
        };
        let skipped = run(50);
        assert_eq!(skipped.report.records[0].samples, 350);
        assert!(skipped.report.rms < 1e-9, "{}", skipped.report.rms);
        assert!((skipped.report.params[0].value - 4.0).abs() < 1e-8);
        assert!(run(0).report.rms > 0.05);
    }

    /// `max_evaluations` bounds the simulations of the search (the report
    /// at the end adds one simulation and one Jacobian, `2k`), ending at
    /// the last accepted point, not converged; `max_seconds` ends it too.
    #[test]
    fn the_budget_really_bounds_the_work() {
        let x = sweep(2000, 1.2, 3.0, 0.0);
        let truth = BoucWen::constant(10.0, 0.6, 1.0, 2.5, 1.5, 1.0).unwrap();
        let y = truth.clone().run(&x).unwrap();
        let start: Box<dyn Operator<f64>> = BoucWen::constant(5.0, 0.3, 2.0, 1.0, 1.2, 1.0)
            .unwrap()
            .boxed();
        let free = free_by_names(start.as_ref(), &["w", "alpha", "beta", "gamma"]).unwrap();
        let k = free.len();
        let unbounded = fit(start.as_ref(), &x, &y, &free, &FitOptions::default()).unwrap();
        assert!(
            unbounded.report.evaluations > 60,
            "{}",
            unbounded.report.evaluations
        );
        for max in [1, 10, 30, 60] {
            let opts = FitOptions {
                max_evaluations: Some(max),
                ..FitOptions::default()
            };
            let f = fit(start.as_ref(), &x, &y, &free, &opts).unwrap();
            let r = &f.report;
            assert!(
                r.evaluations <= max.max(1) + 2 * k + 1,
                "max {max}: {} evaluations",
                r.evaluations
            );
            assert!(
                matches!(&r.status, FitStatus::NotConverged(why) if why.contains("max_evaluations")),
                "{:?}",
                r.status
            );
            // never worse than the start
            let start_rms = {
                let y0 = start.clone().run(&x).unwrap();
                (y0.iter().zip(&y).map(|(a, b)| (a - b).powi(2)).sum::<f64>() / y.len() as f64)
                    .sqrt()
            };
            assert!(r.rms <= start_rms, "{} > {start_rms}", r.rms);
        }
        let opts = FitOptions {
            max_seconds: Some(1e-9),
            ..FitOptions::default()
        };
        let f = fit(start.as_ref(), &x, &y, &free, &opts).unwrap();
        assert!(
            matches!(&f.report.status, FitStatus::NotConverged(why) if why.contains("max_seconds")),
            "{:?}",
            f.report.status
        );
        assert!(f.report.evaluations <= 1 + 2 * k + 1);
    }

    #[test]
    fn bad_records_and_lists_are_errors() {
        let model: Box<dyn Operator<f64>> = Mms::new(1.0, 5.0).unwrap().boxed();
        let x = [0.1, 0.2, 0.3];
        let opts = FitOptions::default();
        let go = |recs: &[Record<'_>], free: &[usize], own: &[usize], opts: &FitOptions| {
            fit_records(model.as_ref(), recs, free, own, opts, &|_| {})
        };
        let e = go(&[], &[0], &[], &opts).unwrap_err();
        assert_eq!(e.to_string(), "data: no records");
        let two = [Record::new(&x, &x), Record::new(&x, &x[..2])];
        let e = go(&two, &[0], &[], &opts).unwrap_err();
        assert_eq!(
            e.to_string(),
            "data: record 1: input has 3 samples, output 2 (stride 1)"
        );
        let skip = [Record {
            x: &x,
            y: &x,
            skip: 3,
        }];
        let e = go(&skip, &[0], &[], &opts).unwrap_err();
        assert!(e.to_string().contains("skips 3 of its 3 samples"), "{e}");
        assert!(matches!(
            go(&[Record::new(&x, &x)], &[0], &[0], &opts),
            Err(FitError::Repeated { index: 0 })
        ));
        assert!(matches!(
            go(&[Record::new(&x, &x)], &[], &[], &opts),
            Err(FitError::NoFreeParameters)
        ));
        for bad in [
            FitOptions {
                max_evaluations: Some(0),
                ..FitOptions::default()
            },
            FitOptions {
                max_seconds: Some(f64::NAN),
                ..FitOptions::default()
            },
            FitOptions {
                max_seconds: Some(-1.0),
                ..FitOptions::default()
            },
        ] {
            assert!(matches!(
                go(&[Record::new(&x, &x)], &[0], &[], &bad),
                Err(FitError::Option { .. })
            ));
        }
    }
}
