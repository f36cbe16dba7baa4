//! Identification of the Bouc-Wen benchmark system (Noël & Schoukens) from
//! a measured record, with the composed model of
//! `hysteron_models::benchmark`, from starting values taken from the record
//! itself ([`start_from_data`]).

use crate::error::FitError;
use crate::fit::{fit, free_by_names};
use crate::multistart::{starting_points, summarize, MultiStart};
use crate::options::FitOptions;
use crate::outcome::FitReport;
use hysteron_models::benchmark::{boucwen_system, BoucWenBenchmarkParams};
use hysteron_models::composition::OperatorExt;
use hysteron_models::signal::Upsampling;
use hysteron_operators::Error;
use hysteron_operators::Parameters;

use rayon::prelude::*;

/// The seven physical parameters, as named in the composed system
/// (`forward.mass-spring-damper.*`, `back.bouc_wen.*`; unique suffixes).
pub const FREE: [&str; 7] = ["m", "c", "k", "alpha", "beta", "gamma", "n"];

/// Why the benchmark identification failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BenchmarkError {
    /// The start parameters or the record are invalid.
    #[error("{0}")]
    Model(#[from] Error),
    /// The fit could not run.
    #[error("fit: {0}")]
    Fit(#[from] FitError),
    /// The record does not determine a physical linear estimate: `name`
    /// came out as `value` (not positive), for example for a record whose
    /// input excites nothing or whose output is noise.
    #[error("the record does not determine a starting value: the linear estimate of {name} is {value:e}, not positive")]
    NoLinearEstimate {
        /// `m`, `c` or `k_total`.
        name: &'static str,
        /// The estimate.
        value: f64,
    },
}

/// [`identify_boucwen`] from [`MultiStart::starts`] starting points: `start`
/// itself, then a Latin hypercube around it in the fit's internal
/// coordinates ([`starting_points`] over the seven [`FREE`] parameters),
/// run in parallel; the best identification (lowest cost) is returned, with
/// every start's cost and how many reached the best within 1 % in its
/// report's [`starts`](crate::FitReport::starts). One start is exactly
/// [`identify_boucwen`] (no summary).
///
/// Errors: those of [`identify_boucwen`] for a bad request; a start that
/// fails on its own counts with no cost, and if every start fails the first
/// one's error is returned.
pub fn identify_boucwen_multistart(
    u: &[f64],
    y: &[f64],
    start: &BoucWenBenchmarkParams,
    upsampling: Upsampling,
    opts: &FitOptions,
    ms: &MultiStart,
) -> Result<BenchmarkIdentification, BenchmarkError> {
    crate::error::option(ms.starts > 0, "starts", "must be ≥ 1")?;
    let model = boucwen_system(start)?;
    let free = free_by_names(&model, &FREE)?;
    let points = starting_points(&model.params(), &model.param_domains(), &free, ms);
    let value = |point: &[f64], i: usize| {
        free.get(i)
            .and_then(|&at| point.get(at))
            .copied()
            .unwrap_or(f64::NAN)
    };
    let run = |point: &Vec<f64>| {
        let from = BoucWenBenchmarkParams {
            m: value(point, 0),
            c: value(point, 1),
            k: value(point, 2),
            a: value(point, 3),
            beta: value(point, 4),
            gamma: value(point, 5),
            n: value(point, 6),
            ..*start
        };
        identify_boucwen(u, y, &from, upsampling, opts)
    };
    if let [only] = points.as_slice() {
        return run(only);
    }
    let mut results: Vec<_> = points.par_iter().map(run).collect();
    let costs = results
        .iter()
        .map(|r| r.as_ref().ok().map(|id| id.report.cost))
        .collect();
    let scale: f64 = y.iter().map(|v| 0.5 * v * v).sum();
    let Some(summary) = summarize(costs, scale) else {
        return results.swap_remove(0);
    };
    let mut best = results.swap_remove(summary.best)?;
    best.report.starts = Some(summary);
    Ok(best)
}

/// Fraction of the largest input bin above which a frequency bin counts as
/// excited in [`linear_estimate`].
pub const EXCITED: f64 = 0.1;

/// `β' · rms(y)` of [`start_from_data`]'s Bouc-Wen start: the hysteretic
/// term `β' |ẏ| z` is then half of `A ẏ` at the record's typical
/// displacement, a loop neither linear nor saturated.
pub const BETA_TIMES_RMS: f64 = 0.5;

/// A linear second-order model `m ÿ + c ẏ + k_total y = u` of a record.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct LinearEstimate {
    /// Mass (kg).
    pub m: f64,
    /// Viscous damping (N s/m): the system's own and the hysteresis's
    /// equivalent at the record's amplitude.
    pub c: f64,
    /// Total stiffness (N/m): `k + A` for the benchmark system at small
    /// amplitude.
    pub k_total: f64,
}

/// Fits `m ÿ + c ẏ + k_total y = u` to a record `(u, y)` sampled at `fs` by
/// linear least squares in the frequency domain: with `U_j`, `Y_j` the
/// discrete Fourier transforms of the record and `ω_j = 2π j fs / N`, it
/// minimises `Σ_j |U_j − (k_total − m ω_j² + i c ω_j) Y_j|²` over the
/// excited bins (`0 < ω_j < π fs`, `|U_j| ≥` [`EXCITED`] `· max |U|`).
/// The residual is linear in `(k_total, m, c)`; the 3 × 3 normal equations
/// are solved with the columns scaled to unit norm.
///
/// For a record of whole periods the bins are exact; for any other, the
/// leakage of the record's ends enters the estimate, which is meant as a
/// starting value, not a result.
///
/// Errors: records of different lengths, shorter than 4 samples or with a
/// non-finite sample, and a non-positive `fs` are
/// [`BenchmarkError::Model`]; an estimate that is not positive is
/// [`BenchmarkError::NoLinearEstimate`].
// Every index is in 0..3, into a 3 × 3 matrix or a 3-vector.
#[allow(clippy::indexing_slicing)]
pub fn linear_estimate(u: &[f64], y: &[f64], fs: f64) -> Result<LinearEstimate, BenchmarkError> {
    use nalgebra::{Matrix3, Vector3};
    use rustfft::num_complex::Complex;
    check_pair(u, y)?;
    hysteron_operators::check::positive("fs", fs)?;
    let n = u.len();
    let spectrum = |x: &[f64]| {
        let mut buf: Vec<Complex<f64>> = x.iter().map(|&v| Complex::new(v, 0.0)).collect();
        rustfft::FftPlanner::new()
            .plan_fft_forward(n)
            .process(&mut buf);
        buf
    };
    let (uu, yy) = (spectrum(u), spectrum(y));
    // bins strictly between 0 and the Nyquist frequency
    let bins = || (1..n.div_ceil(2)).filter_map(|j| Some((j, *uu.get(j)?, *yy.get(j)?)));
    let peak = bins().map(|(_, uj, _)| uj.norm()).fold(0.0, f64::max);
    let mut g = Matrix3::<f64>::zeros();
    let mut h = Vector3::<f64>::zeros();
    for (j, uj, yj) in bins().filter(|(_, uj, _)| uj.norm() >= EXCITED * peak && peak > 0.0) {
        let w = std::f64::consts::TAU * j as f64 * fs / n as f64;
        let cols = [yj, -w * w * yj, Complex::new(0.0, w) * yj];
        for (a, ca) in cols.iter().enumerate() {
            h[a] += (ca.conj() * uj).re;
            for (b, cb) in cols.iter().enumerate() {
                g[(a, b)] += (ca.conj() * cb).re;
            }
        }
    }
    let scale = Vector3::from_fn(|i, _| g[(i, i)].sqrt().max(f64::MIN_POSITIVE));
    let gs = Matrix3::from_fn(|i, j| g[(i, j)] / (scale[i] * scale[j]));
    let hs = Vector3::from_fn(|i, _| h[i] / scale[i]);
    let theta = gs.lu().solve(&hs).unwrap_or_else(Vector3::zeros);
    let [k_total, m, c] = [0, 1, 2].map(|i| theta[i] / scale[i]);
    for (name, value) in [("m", m), ("c", c), ("k_total", k_total)] {
        if !(value > 0.0 && value.is_finite()) {
            return Err(BenchmarkError::NoLinearEstimate { name, value });
        }
    }
    Ok(LinearEstimate { m, c, k_total })
}

/// The exponent `n` of [`start_from_data`]'s start: between the common
/// choices 1 and 2.
pub const START_N: f64 = 1.5;

/// Starting values for [`identify_boucwen`] from the record alone (no
/// published value is used): `m` and `c` from [`linear_estimate`], its
/// total stiffness split evenly between the linear spring and the
/// hysteretic one (`k = A = k_total / 2`), `n =` [`START_N`], `γ' = 0` and
/// `β' =` [`BETA_TIMES_RMS`]` / rms(y − ȳ)`, for a record sampled at `fs`
/// and simulated `upsample` times finer.
///
/// Errors: those of [`linear_estimate`], a constant `y`, and `upsample = 0`.
pub fn start_from_data(
    u: &[f64],
    y: &[f64],
    fs: f64,
    upsample: usize,
) -> Result<BoucWenBenchmarkParams, BenchmarkError> {
    let lin = linear_estimate(u, y, fs)?;
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let centred: Vec<f64> = y.iter().map(|v| v - mean).collect();
    let rms = crate::metrics::rms(&centred);
    hysteron_operators::check::positive("rms(y)", rms)?;
    Ok(BoucWenBenchmarkParams {
        m: lin.m,
        c: lin.c,
        k: lin.k_total / 2.0,
        a: lin.k_total / 2.0,
        beta: BETA_TIMES_RMS / rms,
        gamma: 0.0,
        n: START_N,
        fs,
        upsample,
    })
    .and_then(|p| {
        p.validate()?;
        Ok(p)
    })
}

/// Equal lengths, at least 4 samples, all finite.
fn check_pair(u: &[f64], y: &[f64]) -> Result<(), Error> {
    if y.len() != u.len() || u.len() < 4 {
        let short = u.len() < 4;
        return Err(Error::InvalidParameter {
            name: if short { "u" } else { "y" }.into(),
            value: if short { u.len() } else { y.len() } as f64,
            reason: "records need as many samples of y as of u, at least 4",
        });
    }
    for x in [u, y] {
        if let Some((i, &value)) = x.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(Error::NonFiniteInput { value }.at_sample(i));
        }
    }
    Ok(())
}

/// The result of [`identify_boucwen`].
#[derive(Debug, Clone, PartialEq)]
pub struct BenchmarkIdentification {
    /// The identified system.
    pub params: BoucWenBenchmarkParams,
    /// The fit report (parameters with standard errors and intervals).
    pub report: FitReport,
}

/// Fits `m, c, k, A, β', γ', n` of the benchmark system to a record `(u, y)`
/// sampled at `start.fs` that starts from rest: the input is upsampled
/// `start.upsample` times as `upsampling` says ([`Upsampling::Fft`] when
/// the record holds whole periods of a periodic input, as the benchmark's
/// training multisine does; [`Upsampling::Polyphase`] otherwise), the
/// system runs at the integration rate from rest, and its output at the
/// data samples is compared with `y` (the fit's `stride`). The fit is
/// a continuation: six parameters with `n` held at its start, then all
/// seven; the report is the second fit's.
pub fn identify_boucwen(
    u: &[f64],
    y: &[f64],
    start: &BoucWenBenchmarkParams,
    upsampling: Upsampling,
    opts: &FitOptions,
) -> Result<BenchmarkIdentification, BenchmarkError> {
    let fine = upsampling.upsample(u, start.upsample)?;
    // (its operators' twin over dual numbers gives the fits exact Jacobians)
    let model = boucwen_system(start)?.boxed();
    let opts = FitOptions {
        stride: start.upsample,
        ..opts.clone()
    };
    // Continuation: the exponent changes the units of β' and γ' (1/m^n),
    // so a wrong n makes a long, curved valley. First fit the other six
    // with n held, then all seven from there.
    let six = free_by_names(model.as_ref(), &FREE[..6])?;
    let first = fit(model.as_ref(), &fine, y, &six, &opts)?;
    let all = free_by_names(first.model.as_ref(), &FREE)?;
    let f = fit(first.model.as_ref(), &fine, y, &all, &opts)?;
    // `i < 7`: the report has one entry per name of `FREE` (7).
    #[allow(clippy::indexing_slicing)]
    let v = |i: usize| f.report.params[i].value;
    let params = BoucWenBenchmarkParams {
        m: v(0),
        c: v(1),
        k: v(2),
        a: v(3),
        beta: v(4),
        gamma: v(5),
        n: v(6),
        ..*start
    };
    Ok(BenchmarkIdentification {
        params,
        report: f.report,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use hysteron_models::benchmark::periodic_steady_state;
    use hysteron_models::operators::MassSpringDamper;
    use hysteron_models::signal::fft_upsample;
    use hysteron_operators::Dual;
    use hysteron_operators::{Derivatives, Operator};

    /// One period of a multisine over harmonics 3…60 of 1024 samples at
    /// 750 Hz (2–44 Hz), Schroeder phases.
    fn multisine() -> Vec<f64> {
        let n = 1024;
        (0..n)
            .map(|j| {
                (3..=60)
                    .map(|h| {
                        let phase = std::f64::consts::PI * (h * h) as f64 / 58.0;
                        let t = ((h * j) % n) as f64 / n as f64;
                        10.0 * (std::f64::consts::TAU * t + phase).cos()
                    })
                    .sum()
            })
            .collect()
    }

    /// A linear oscillator's steady-state period gives back its `m, c, k`:
    /// the residual is linear in them and exact on whole periods, up to the
    /// Newmark integration's frequency warping at 15 kHz (about 1e-4
    /// relative at 44 Hz).
    #[test]
    fn linear_estimate_recovers_a_linear_oscillator() {
        let (m, c, k) = (2.0, 200.0, 1e5);
        let u = multisine();
        let fine = fft_upsample(&u, 20).unwrap();
        let mut msd = MassSpringDamper::new(m, c, k, 1.0 / 15000.0).unwrap();
        let r = periodic_steady_state(&mut msd, &fine, 1e-13, 100).unwrap();
        assert!(r.converged);
        let y: Vec<f64> = r.output.iter().step_by(20).copied().collect();
        let est = linear_estimate(&u, &y, 750.0).unwrap();
        let rel = |a: f64, b: f64| (a - b).abs() / b;
        assert!(rel(est.m, m) < 1e-3, "{est:?}");
        assert!(rel(est.c, c) < 1e-3, "{est:?}");
        assert!(rel(est.k_total, k) < 1e-3, "{est:?}");

        let start = start_from_data(&u, &y, 750.0, 20).unwrap();
        assert_eq!(
            (start.k, start.a, start.gamma, start.n),
            (est.k_total / 2.0, est.k_total / 2.0, 0.0, START_N)
        );
        assert_eq!((start.fs, start.upsample), (750.0, 20));
    }

    /// The system the fits run has a twin over dual numbers (exact
    /// Jacobians) with the same parameters and the same outputs.
    #[test]
    fn the_benchmark_system_has_a_dual_twin() {
        let p = BoucWenBenchmarkParams::published();
        let fine = fft_upsample(&multisine(), p.upsample).unwrap();
        let system = boucwen_system(&p).unwrap();
        let mut twin = system.to_dual().unwrap();
        assert_eq!(twin.param_names(), system.param_names());
        let values: Vec<f64> = twin.params().iter().map(|v| v.re).collect();
        assert_eq!(values, system.params());
        let fine_dual: Vec<Dual> = fine.iter().map(|&x| Dual::constant(x)).collect();
        let a = twin.run(&fine_dual).unwrap();
        let b = system.clone().run(&fine).unwrap();
        let scale = b.iter().fold(0.0f64, |m, y| m.max(y.abs()));
        assert!(scale > 0.0);
        assert!(a
            .iter()
            .zip(&b)
            .all(|(x, y)| (x.re - y).abs() <= 1e-12 * scale));
    }

    #[test]
    fn records_that_determine_nothing_are_errors() {
        let u = multisine();
        // an output that does not follow the input: a negative "mass"
        let y: Vec<f64> = u.iter().map(|v| -v * 1e-5).collect();
        assert!(matches!(
            linear_estimate(&u, &y, 750.0),
            Err(BenchmarkError::NoLinearEstimate { .. })
        ));
        assert!(linear_estimate(&u, &y[..10], 750.0).is_err());
        assert!(linear_estimate(&u[..3], &y[..3], 750.0).is_err());
        assert!(linear_estimate(&u, &y, 0.0).is_err());
        let mut bad = y.clone();
        bad[7] = f64::NAN;
        assert!(matches!(
            linear_estimate(&u, &bad, 750.0),
            Err(BenchmarkError::Model(Error::AtSample { index: 7, .. }))
        ));
        assert!(start_from_data(&u, &vec![1.0; u.len()], 750.0, 20).is_err());
        assert!(start_from_data(&u, &y, 750.0, 0).is_err());
    }
}
