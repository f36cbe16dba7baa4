//! Multi-start fitting: the same least-squares problem solved from several
//! starting points spread over the parameter domains, the best kept.
//!
//! Start 0 is the model's own parameter vector. Starts `1..N` are a Latin
//! hypercube in the internal parameters `θ` of the fit ([`Reparam`]): each
//! free parameter's range `[θ₀ − s, θ₀ + s]` (`s` =
//! [`MultiStart::spread`]) is cut into `N − 1` equal strata, each stratum
//! is used once per parameter, at a uniform point inside it, and the
//! strata are paired across parameters by independent random
//! permutations. So a positive parameter starts within a factor `e^s` of
//! its value (`e^{1.386} = 4` by default), a parameter in `[0, 1]` within
//! `±s` in its logit, and an unbounded one within `±s · max(|p₀|, 1)`.
//! Only the shared parameters (`free`) are spread; per-record ones (`own`)
//! start from the model's values. The starts run in parallel (rayon).
//!
//! # Reference
//! McKay, Beckman & Conover, "A comparison of three methods for selecting
//! values of input variables in the analysis of output from a computer
//! code", *Technometrics* 21 (1979) 239–245 (Latin hypercube sampling).

pub use crate::outcome::StartsSummary;

use crate::error::{option, FitError};
use crate::fit::fit_records;
use crate::options::{FitOptions, Progress};
use crate::outcome::Fit;
use crate::record::Record;
use crate::transform::Reparam;
use hysteron_operators::{Domain, Operator};
use rand::rngs::StdRng;
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rayon::prelude::*;

/// A start reached the best fit if its cost is within this fraction of the
/// best cost (or within [`REACHED_FLOOR`] of it).
pub const REACHED: f64 = 0.01;

/// The absolute part of the reached test, relative to the data's own
/// "cost" `½ Σ y²`: a start whose cost is below `1e-20 · ½ Σ y²` (a
/// residual RMS of 1e-10 of the signal's, rounding) fits as well as a
/// best cost of zero, which no fraction of zero can include.
pub const REACHED_FLOOR: f64 = 1e-20;

/// How many starts, how far apart, from which random seed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MultiStart {
    /// Number of starts, the model's own included (at least 1; 1 is a
    /// plain fit).
    pub starts: usize,
    /// Half-width `s` of each parameter's range in internal coordinates
    /// (positive and finite).
    pub spread: f64,
    /// Seed of the Latin hypercube (the same seed, the same starts).
    pub seed: u64,
}

impl Default for MultiStart {
    /// One start, `spread = ln 4`, seed 0.
    fn default() -> Self {
        Self {
            starts: 1,
            spread: 4f64.ln(),
            seed: 0,
        }
    }
}

/// The starting parameter vectors: the model's own, then `starts − 1`
/// Latin-hypercube points (see the module documentation).
pub fn starting_points(
    base: &[f64],
    domains: &[Domain],
    free: &[usize],
    ms: &MultiStart,
) -> Vec<Vec<f64>> {
    let n = ms.starts.saturating_sub(1);
    let mut rng = StdRng::seed_from_u64(ms.seed);
    let mut points = vec![base.to_vec(); n];
    for &i in free {
        let (Some(&p0), Some(&domain)) = (base.get(i), domains.get(i)) else {
            continue;
        };
        let mut strata: Vec<usize> = (0..n).collect();
        strata.shuffle(&mut rng);
        for (point, stratum) in points.iter_mut().zip(strata) {
            let u = (stratum as f64 + rng.random::<f64>()) / n as f64;
            let offset = ms.spread * (2.0 * u - 1.0);
            let value = match domain {
                Domain::Real => p0 + offset * p0.abs().max(1.0),
                _ => {
                    let map = Reparam(domain);
                    map.to_external(map.to_internal(p0) + offset)
                }
            };
            if let Some(v) = point.get_mut(i) {
                *v = value;
            }
        }
    }
    let mut all = vec![base.to_vec()];
    all.extend(points);
    all
}

/// [`fit_records`] from [`MultiStart::starts`] starting points; the best
/// fit (lowest cost) with a [`StartsSummary`] in its report
/// ([`FitReport::starts`](crate::FitReport::starts)). One start is exactly
/// [`fit_records`] (no summary).
///
/// # Requirements
/// As [`fit_records`]; `starts ≥ 1`, `spread` positive and finite.
///
/// # Errors
/// The errors of [`fit_records`] for a bad request. A start that fails on
/// its own (the model refuses its vector, the fit fails) counts with no
/// cost; if every start fails, the first start's error is returned.
pub fn fit_multistart(
    model: &(dyn Operator<f64> + 'static),
    records: &[Record<'_>],
    free: &[usize],
    own: &[usize],
    opts: &FitOptions,
    ms: &MultiStart,
    on_iteration: &(dyn Fn(Progress) + Sync),
) -> Result<Fit, FitError> {
    option(ms.starts > 0, "starts", "must be ≥ 1")?;
    option(
        ms.spread > 0.0 && ms.spread.is_finite(),
        "spread",
        "must be positive and finite",
    )?;
    let points = starting_points(&model.params(), &model.param_domains(), free, ms);
    let run = |(j, p): (usize, &Vec<f64>)| -> Result<Fit, FitError> {
        let mut start = dyn_clone::clone_box(model);
        start.set_params(p).map_err(FitError::Start)?;
        // Only the first start reports progress (the others run beside it).
        let quiet = |_| {};
        let progress: &(dyn Fn(Progress) + Sync) = if j == 0 { on_iteration } else { &quiet };
        fit_records(start.as_ref(), records, free, own, opts, progress)
    };
    if let [only] = points.as_slice() {
        // a plain fit: no summary
        return run((0, only));
    }
    let mut fits: Vec<Result<Fit, FitError>> = points.par_iter().enumerate().map(run).collect();
    let costs: Vec<Option<f64>> = fits
        .iter()
        .map(|f| f.as_ref().ok().map(|f| f.report.cost))
        .collect();
    let scale: f64 = records
        .iter()
        .flat_map(|r| r.y.iter())
        .map(|y| 0.5 * y * y)
        .sum();
    let Some(summary) = summarize(costs, scale) else {
        // every start failed: the first one's error
        return match fits.swap_remove(0) {
            Ok(fit) => Ok(fit),
            Err(e) => Err(e),
        };
    };
    let mut fit = fits.swap_remove(summary.best)?;
    fit.report.starts = Some(summary);
    Ok(fit)
}

/// The best of the starts' final costs (`None` for a start that failed)
/// and how many reached it within [`REACHED`] of it, or within
/// [`REACHED_FLOOR`] `· scale` (`scale` is the data's `½ Σ y²`); `None` if
/// no start has a finite cost.
pub(crate) fn summarize(costs: Vec<Option<f64>>, scale: f64) -> Option<StartsSummary> {
    let floor = if scale.is_finite() {
        REACHED_FLOOR * scale.abs()
    } else {
        0.0
    };
    let (best, best_cost) = costs
        .iter()
        .enumerate()
        .filter_map(|(j, c)| c.filter(|c| c.is_finite()).map(|c| (j, c)))
        .min_by(|a, b| a.1.total_cmp(&b.1))?;
    let reached = costs
        .iter()
        .flatten()
        .filter(|&&c| c <= best_cost + REACHED * best_cost.abs() + floor)
        .count();
    Some(StartsSummary {
        costs,
        best,
        reached,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A best cost of zero: a start at 5.8e-30 (rounding) reached it, one
    /// at 1e-3 did not; a positive best counts those within 1 %.
    #[test]
    fn zero_cost_starts_count_as_reached() {
        let s = summarize(vec![Some(5.8e-30), Some(0.0), Some(1e-3), None], 2.0).unwrap();
        assert_eq!((s.best, s.reached), (1, 2));
        let s = summarize(vec![Some(1.0), Some(1.005), Some(1.02)], 2.0).unwrap();
        assert_eq!((s.best, s.reached), (0, 2));
        // with no scale, only the fraction of zero: the exact zero alone
        let s = summarize(vec![Some(5.8e-30), Some(0.0)], 0.0).unwrap();
        assert_eq!(s.reached, 1);
    }

    #[test]
    fn starts_are_a_latin_hypercube_around_the_model() {
        let base = [2.0, 0.5, -3.0, 7.0];
        let domains = [
            Domain::Positive,
            Domain::UnitInterval,
            Domain::Real,
            Domain::Positive,
        ];
        let ms = MultiStart {
            starts: 9,
            spread: 4f64.ln(),
            seed: 3,
        };
        let points = starting_points(&base, &domains, &[0, 1, 2], &ms);
        assert_eq!(points.len(), 9);
        assert_eq!(points[0], base);
        // each parameter: one point per stratum of its internal range
        for (i, d) in domains.iter().enumerate().take(3) {
            let map = Reparam(*d);
            let mut strata: Vec<usize> = points[1..]
                .iter()
                .map(|p| {
                    let (lo, width) = match d {
                        Domain::Real => (base[i] - ms.spread * 3.0, 2.0 * ms.spread * 3.0),
                        _ => (map.to_internal(base[i]) - ms.spread, 2.0 * ms.spread),
                    };
                    let t = match d {
                        Domain::Real => p[i],
                        _ => map.to_internal(p[i]),
                    };
                    ((t - lo) / width * 8.0).floor() as usize
                })
                .collect();
            strata.sort();
            assert_eq!(strata, (0..8).collect::<Vec<_>>(), "parameter {i}");
            assert!(points.iter().all(|p| d.contains(p[i])));
        }
        // a parameter that is not free stays
        assert!(points.iter().all(|p| p[3] == 7.0));
        // the same seed, the same starts; another, others
        assert_eq!(starting_points(&base, &domains, &[0, 1, 2], &ms), points);
        let other = MultiStart { seed: 4, ..ms };
        assert_ne!(starting_points(&base, &domains, &[0, 1, 2], &other), points);
        // one start: the model alone
        let one = MultiStart { starts: 1, ..ms };
        assert_eq!(
            starting_points(&base, &domains, &[0], &one),
            vec![base.to_vec()]
        );
    }
}
