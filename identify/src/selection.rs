//! Choosing among candidate structures: each fitted on training records,
//! scored on held-out ones, ranked, with the information criteria of the
//! training fit and a paired sign test of each candidate against the next.
//!
//! * `AIC = n ln(RSS/n) + 2k` and `BIC = n ln(RSS/n) + k ln n` with
//!   `RSS = 2 · cost` over the `n` scored training samples and `k` free
//!   parameters (Gaussian residuals of unknown variance; `RSS/n` floored at
//!   the smallest positive normal number, so that an exact fit has a
//!   finite criterion) ([`information_criteria`]);
//! * the held-out NRMSE, `RMS(ŷ − y) / RMS(y)` over the scored samples,
//!   and the same after a zero-phase low-pass of both signals
//!   ([`held_out_figures`]);
//! * the ranking by the mean held-out error, failed candidates last, and
//!   the two-sided sign test of each ranked candidate against the next
//!   over the per-record errors ([`rank`], [`sign_test`]).
//!
//! [`compare`] runs all of it on records in memory (the Python face's
//! `compare`); the command line's `hysteron compare` fits and scores files
//! as `fit` and `validate` do, and ranks with the same functions.
//!
//! # Reference
//! K. P. Burnham, D. R. Anderson, *Model Selection and Multimodel
//! Inference*, 2nd ed., Springer, 2002, §2.2 (AIC and BIC for least
//! squares); W. J. Conover, *Practical Nonparametric Statistics*, 3rd ed.,
//! Wiley, 1999, §3.4 (the sign test).

use crate::metrics::{self, ErrorFigures, Lowpass, MetricsError};
use crate::multistart::{fit_multistart, MultiStart};
use crate::options::FitOptions;
use crate::outcome::{Fit, FitReport};
use crate::record::Record;
use hysteron_operators::Operator;
use rayon::prelude::*;

/// `(AIC, BIC)` of a least-squares fit of `k` parameters whose cost
/// `½ Σ r²` is `cost` over `n` samples (see the module documentation).
pub fn information_criteria(cost: f64, n: usize, k: usize) -> (f64, f64) {
    let n_f = n.max(1) as f64;
    let fit = n_f * ((2.0 * cost / n_f).max(f64::MIN_POSITIVE)).ln();
    let k_f = k as f64;
    (fit + 2.0 * k_f, fit + k_f * n_f.ln())
}

/// The two-sided sign test of paired errors `a` against `b`: ties are
/// dropped; `p = min(1, 2 P(X ≤ min(wins, losses)))`, `X ~ Bin(m, 1/2)`
/// over the `m` untied pairs. `None` without an untied pair.
pub fn sign_test(a: &[f64], b: &[f64]) -> Option<f64> {
    let (mut wins, mut losses) = (0u32, 0u32);
    for (x, y) in a.iter().zip(b) {
        if x < y {
            wins += 1;
        } else if x > y {
            losses += 1;
        }
    }
    let m = wins + losses;
    if m == 0 {
        return None;
    }
    // P(X ≤ s) = Σ_{j ≤ s} C(m, j) / 2^m, each term from the one before by
    // C(m, j+1) = C(m, j) (m − j)/(j + 1)
    let mut term = 0.5_f64.powi(i32::try_from(m).unwrap_or(i32::MAX));
    let mut tail = 0.0;
    for j in 0..=wins.min(losses) {
        tail += term;
        term *= f64::from(m - j) / f64::from(j + 1);
    }
    Some((2.0 * tail).min(1.0))
}

/// The columns of a comparison's table, as the command line's `--csv` and
/// Python's `compare` name them.
pub const COLUMNS: [&str; 14] = [
    "rank",
    "candidate",
    "k",
    "n",
    "training_cost",
    "aic",
    "bic",
    "heldout_nrmse_mean",
    "heldout_nrmse_worst",
    "heldout_lowpassed_mean",
    "heldout_lowpassed_worst",
    "p_vs_next",
    "converged",
    "error",
];

/// `(mean, worst)` of per-record errors (`(NaN, −∞)` for none).
pub fn mean_and_worst(v: &[f64]) -> (f64, f64) {
    (
        v.iter().sum::<f64>() / v.len() as f64,
        v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    )
}

/// The per-record errors a ranking uses, from `(NRMSE, low-passed NRMSE)`
/// per record: low-passed where every record has one, else full band.
pub fn ranking_errors(held_out: &[(f64, Option<f64>)]) -> Vec<f64> {
    let low: Option<Vec<f64>> = held_out.iter().map(|h| h.1).collect();
    low.unwrap_or_else(|| held_out.iter().map(|h| h.0).collect())
}

/// The folds of `k`-fold cross-validation over `n` records: record `i` is
/// held out in fold `i mod k`.
pub fn folds(n: usize, k: usize) -> Vec<Vec<usize>> {
    (0..k)
        .map(|f| (0..n).filter(|i| i % k.max(1) == f).collect())
        .collect()
}

/// `k`-fold cross-validation over `n` records: `score_fold(rest, held)`
/// fits on the records `rest` and scores the records `held` (one score
/// each, in order), for each of the [`folds`]; returns every record's
/// score, in record order. A fold's error is returned with its number
/// (`fold F: …`, from 1).
pub fn cross_validated<S>(
    n: usize,
    k: usize,
    mut score_fold: impl FnMut(&[usize], &[usize]) -> Result<Vec<S>, String>,
) -> Result<Vec<S>, String> {
    let mut by_record: Vec<Option<S>> = (0..n).map(|_| None).collect();
    for (f, held) in folds(n, k).iter().enumerate() {
        let rest: Vec<usize> = (0..n).filter(|i| !held.contains(i)).collect();
        let scores = score_fold(&rest, held).map_err(|e| format!("fold {}: {e}", f + 1))?;
        for (&i, s) in held.iter().zip(scores) {
            if let Some(slot) = by_record.get_mut(i) {
                *slot = Some(s);
            }
        }
    }
    Ok(by_record.into_iter().flatten().collect())
}

/// The ranking of candidates by their per-record held-out errors (`None`:
/// the candidate failed), each list in the same record order.
#[derive(Debug, Clone, PartialEq)]
pub struct Ranking {
    /// The candidates' indices, best mean error first, failed ones last
    /// (in their given order).
    pub order: Vec<usize>,
    /// Each candidate's rank (1 = best), `None` for a failed one; indexed
    /// like the input.
    pub rank: Vec<Option<usize>>,
    /// Each ranked candidate's [`sign_test`] against the next rank;
    /// indexed like the input.
    pub p_next: Vec<Option<f64>>,
}

/// Ranks candidates by their mean held-out error (see [`Ranking`]).
pub fn rank(errors: &[Option<Vec<f64>>]) -> Ranking {
    let mean = |i: usize| match errors.get(i) {
        Some(Some(e)) if !e.is_empty() => e.iter().sum::<f64>() / e.len() as f64,
        _ => f64::INFINITY,
    };
    let mut order: Vec<usize> = (0..errors.len()).collect();
    // stable: failed candidates keep their order
    order.sort_by(|&a, &b| mean(a).total_cmp(&mean(b)));
    let mut rank = vec![None; errors.len()];
    let mut p_next = vec![None; errors.len()];
    let ranked: Vec<(usize, &Vec<f64>)> = order
        .iter()
        .filter_map(|&i| errors.get(i).and_then(Option::as_ref).map(|e| (i, e)))
        .collect();
    for (r, (i, a)) in ranked.iter().enumerate() {
        if let Some(slot) = rank.get_mut(*i) {
            *slot = Some(r + 1);
        }
        if let (Some((_, b)), Some(slot)) = (ranked.get(r + 1), p_next.get_mut(*i)) {
            *slot = sign_test(a, b);
        }
    }
    Ranking {
        order,
        rank,
        p_next,
    }
}

/// The held-out figures of a model output `model_y` against the measured
/// `measured`, over the samples from `skip` on, and the NRMSE of the two
/// after `lowpass` (each whole signal filtered, then scored from `skip`).
pub fn held_out_figures(
    model_y: &[f64],
    measured: &[f64],
    skip: usize,
    lowpass: Option<&Lowpass>,
) -> Result<(ErrorFigures, Option<f64>), MetricsError> {
    let tail = |v: &[f64]| v.get(skip..).unwrap_or(&[]).to_vec();
    let figures = metrics::errors(&tail(model_y), &tail(measured))?;
    let lowpassed = match lowpass {
        Some(lp) => {
            let m = lp.filtfilt(model_y)?;
            let r = lp.filtfilt(measured)?;
            Some(metrics::errors(&tail(&m), &tail(&r))?.nrmse)
        }
        None => None,
    };
    Ok((figures, lowpassed))
}

/// One candidate structure: a model (its values are the start) and the
/// indices of the parameters to fit.
pub struct Candidate<'a> {
    /// The model.
    pub model: &'a (dyn Operator<f64> + 'static),
    /// Parameters fitted for all records.
    pub free: Vec<usize>,
    /// Parameters fitted separately for each training record (scored
    /// records run at the model's values of them).
    pub own: Vec<usize>,
}

/// How [`compare`] fits and scores.
#[derive(Debug, Clone, Default)]
pub struct SelectionOptions {
    /// The options of every fit.
    pub fit: FitOptions,
    /// The starting points of every fit.
    pub starts: MultiStart,
    /// The low-pass of the held-out scores, if any.
    pub lowpass: Option<Lowpass>,
    /// `K`-fold cross-validation over the training records instead of
    /// held-out records.
    pub cross_validate: Option<usize>,
}

/// What [`compare`] found for one candidate.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// Free parameters (shared and per record).
    pub k: usize,
    /// Scored training samples.
    pub n: usize,
    /// Training cost `½ Σ r²` of the fit on every training record.
    pub cost: f64,
    /// Whether that fit converged.
    pub converged: bool,
    /// Akaike's criterion of that fit.
    pub aic: f64,
    /// The Bayesian (Schwarz) criterion of that fit.
    pub bic: f64,
    /// The model's full parameter vector after that fit.
    pub params: Vec<f64>,
    /// Per held-out record (or per training record, cross-validated): the
    /// NRMSE and the low-passed NRMSE.
    pub held_out: Vec<(f64, Option<f64>)>,
}

impl Outcome {
    /// The training figures of `report` (k, n, cost, convergence, AIC and
    /// BIC, the parameters) with the held-out scores `held_out`.
    pub fn of_fit(report: &FitReport, held_out: Vec<(f64, Option<f64>)>) -> Outcome {
        let n: usize = report.records.iter().map(|r| r.samples).sum();
        let k = report.params.len();
        let (aic, bic) = information_criteria(report.cost, n, k);
        Outcome {
            k,
            n,
            cost: report.cost,
            converged: report.status.converged(),
            aic,
            bic,
            params: report.all_params.clone(),
            held_out,
        }
    }

    /// The per-record errors a ranking uses: low-passed where every record
    /// has one, else full band.
    pub fn ranking_errors(&self) -> Vec<f64> {
        ranking_errors(&self.held_out)
    }

    /// Mean and worst of the held-out NRMSE, full band.
    pub fn full_band(&self) -> (f64, f64) {
        let v: Vec<f64> = self.held_out.iter().map(|h| h.0).collect();
        mean_and_worst(&v)
    }

    /// Mean and worst of the low-passed held-out NRMSE, where every record
    /// has one.
    pub fn lowpassed(&self) -> Option<(f64, f64)> {
        let low: Option<Vec<f64>> = self.held_out.iter().map(|h| h.1).collect();
        low.map(|v| mean_and_worst(&v))
    }
}

/// Fits `c` on `records`.
fn fit_on(
    c: &Candidate<'_>,
    records: &[Record<'_>],
    opts: &SelectionOptions,
) -> Result<Fit, String> {
    let mut start = dyn_clone::clone_box(c.model);
    start.reset();
    fit_multistart(
        start.as_ref(),
        records,
        &c.free,
        &c.own,
        &opts.fit,
        &opts.starts,
        &|_| {},
    )
    .map_err(|e| format!("fit: {e}"))
}

/// Runs the fitted model (`params`) over each record from its initial
/// state and scores it.
fn score_on(
    c: &Candidate<'_>,
    params: &[f64],
    records: &[Record<'_>],
    opts: &SelectionOptions,
) -> Result<Vec<(f64, Option<f64>)>, String> {
    let mut model = dyn_clone::clone_box(c.model);
    model
        .set_params(params)
        .map_err(|e| format!("the fitted parameters: {e}"))?;
    records
        .iter()
        .enumerate()
        .map(|(i, r)| {
            model.reset();
            let y = model
                .run(r.x)
                .map_err(|e| format!("held-out record {i}: {e}"))?;
            let (figures, low) = held_out_figures(&y, r.y, r.skip, opts.lowpass.as_ref())
                .map_err(|e| format!("held-out record {i}: {e}"))?;
            if figures.nrmse.is_finite() {
                Ok((figures.nrmse, low))
            } else {
                Err(format!(
                    "held-out record {i}: the measured output has RMS 0 (no NRMSE)"
                ))
            }
        })
        .collect()
}

/// One candidate: the fit on every training record, and its held-out
/// scores (or the cross-validated ones).
fn evaluate(
    c: &Candidate<'_>,
    train: &[Record<'_>],
    held_out: &[Record<'_>],
    opts: &SelectionOptions,
) -> Result<Outcome, String> {
    let fit = fit_on(c, train, opts)?;
    let report = &fit.report;
    let held_out = match opts.cross_validate {
        None => score_on(c, &report.all_params, held_out, opts)?,
        Some(kf) => cross_validated(train.len(), kf, |rest, held| {
            let pick = |ix: &[usize]| -> Vec<Record<'_>> {
                ix.iter().filter_map(|&i| train.get(i).copied()).collect()
            };
            let fold_fit = fit_on(c, &pick(rest), opts)?;
            score_on(c, &fold_fit.report.all_params, &pick(held), opts)
        })?,
    };
    Ok(Outcome::of_fit(report, held_out))
}

/// Fits every candidate on `train` and scores it on `held_out` (or, with
/// [`SelectionOptions::cross_validate`] `= K`, on each training record from
/// the fit on the folds without it; `held_out` must then be empty), in
/// parallel. A candidate's failure is its own `Err`; the others go on.
/// [`rank`] the outcomes' [`Outcome::ranking_errors`] to order them.
pub fn compare(
    candidates: &[Candidate<'_>],
    train: &[Record<'_>],
    held_out: &[Record<'_>],
    opts: &SelectionOptions,
) -> Vec<Result<Outcome, String>> {
    let refused = match opts.cross_validate {
        _ if train.is_empty() => Some("no training record".to_string()),
        None if held_out.is_empty() => Some("no held-out record".to_string()),
        Some(k) if k < 2 || k > train.len() => Some(format!(
            "cross_validate = {k}: K must be at least 2 and at most the {} training records",
            train.len()
        )),
        Some(_) if !held_out.is_empty() => {
            Some("cross-validation folds the training records: give no held-out record".into())
        }
        _ => None,
    };
    if let Some(why) = refused {
        return candidates.iter().map(|_| Err(why.clone())).collect();
    }
    candidates
        .par_iter()
        .map(|c| evaluate(c, train, held_out, opts))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sign_test_matches_the_binomial_tail() {
        // 8 of 8 better: 2 · 2^-8
        assert_eq!(sign_test(&[0.0; 8], &[1.0; 8]), Some(2.0 / 256.0));
        // 7 of 8: 2 · (1 + 8) / 256
        let a = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2.0];
        assert!((sign_test(&a, &[1.0; 8]).unwrap() - 18.0 / 256.0).abs() < 1e-15);
        // an even split, and ties only
        assert_eq!(sign_test(&[0.0, 2.0], &[1.0, 1.0]), Some(1.0));
        assert_eq!(sign_test(&[1.0], &[1.0]), None);
    }

    #[test]
    fn information_criteria_penalize_parameters() {
        let (aic1, bic1) = information_criteria(0.5, 100, 2);
        let (aic2, bic2) = information_criteria(0.5, 100, 3);
        assert!((aic2 - aic1 - 2.0).abs() < 1e-12);
        assert!((bic2 - bic1 - 100f64.ln()).abs() < 1e-12);
        // RSS/n = 0.01: n ln(0.01) + 2k
        assert!((aic1 - (100.0 * 0.01f64.ln() + 4.0)).abs() < 1e-12);
        // an exact fit stays finite
        assert!(information_criteria(0.0, 10, 1).0.is_finite());
    }

    #[test]
    fn folds_hold_out_every_record_once() {
        assert_eq!(folds(5, 2), vec![vec![0, 2, 4], vec![1, 3]]);
        let mut all: Vec<usize> = folds(7, 3).into_iter().flatten().collect();
        all.sort_unstable();
        assert_eq!(all, (0..7).collect::<Vec<_>>());
    }

    #[test]
    fn rank_orders_by_mean_with_failures_last() {
        let errors = vec![
            Some(vec![0.3, 0.3]),
            None,
            Some(vec![0.1, 0.2]),
            Some(vec![0.2, 0.25]),
        ];
        let r = rank(&errors);
        assert_eq!(r.order, vec![2, 3, 0, 1]);
        assert_eq!(r.rank, vec![Some(3), None, Some(1), Some(2)]);
        // 2 beats 3 on both records: p = 2 · 2^-2
        assert_eq!(r.p_next[2], Some(0.5));
        assert_eq!(r.p_next[0], None); // last ranked
        assert_eq!(r.p_next[1], None); // failed
    }

    /// Records of `mms(f_c = 1.5, k = 20)` with a deterministic wiggle of
    /// 0.02 for noise.
    fn records() -> Vec<(Vec<f64>, Vec<f64>)> {
        use hysteron_operators::Mms;
        [(1.0, 2.0), (0.3, 3.0), (0.6, 1.0), (0.8, 2.0)]
            .iter()
            .map(|&(a, c)| {
                let x: Vec<f64> = (0..800)
                    .map(|i| a * (std::f64::consts::TAU * c * f64::from(i) / 800.0).sin())
                    .collect();
                let mut y = Mms::new(1.5, 20.0).unwrap().run(&x).unwrap();
                for (i, v) in y.iter_mut().enumerate() {
                    *v += 0.02 * (i as f64 * 1.7).sin();
                }
                (x, y)
            })
            .collect()
    }

    #[test]
    fn compare_ranks_the_true_structure_first_held_out_and_cross_validated() {
        use hysteron_operators::{ElastoPlastic, Mms};
        let data = records();
        let recs: Vec<Record<'_>> = data.iter().map(|(x, y)| Record::new(x, y)).collect();
        let mms = Mms::new(1.0, 10.0).unwrap();
        let ep = ElastoPlastic::new(10.0, 1.0).unwrap();
        let candidates = [
            Candidate {
                model: &ep,
                free: vec![0, 1],
                own: vec![],
            },
            Candidate {
                model: &mms,
                free: vec![0, 1],
                own: vec![],
            },
        ];
        let opts = SelectionOptions::default();
        let held = compare(&candidates, &recs[..2], &recs[2..], &opts);
        let errors: Vec<Option<Vec<f64>>> = held
            .iter()
            .map(|o| o.as_ref().ok().map(Outcome::ranking_errors))
            .collect();
        assert_eq!(rank(&errors).order, vec![1, 0]);
        let fitted = held[1].as_ref().unwrap();
        assert!((fitted.params[0] - 1.5).abs() < 0.01, "{:?}", fitted.params);
        assert_eq!(fitted.n, 1600);
        let cv = compare(
            &candidates,
            &recs,
            &[],
            &SelectionOptions {
                cross_validate: Some(2),
                ..SelectionOptions::default()
            },
        );
        let cv_mms = cv[1].as_ref().unwrap();
        assert_eq!(cv_mms.held_out.len(), 4);
        assert!(
            cv_mms.held_out.iter().all(|h| h.0 < 0.05),
            "{:?}",
            cv_mms.held_out
        );
        // folds that do not fit the records: every candidate says why
        let bad = compare(
            &candidates,
            &recs,
            &[],
            &SelectionOptions {
                cross_validate: Some(5),
                ..SelectionOptions::default()
            },
        );
        assert!(bad
            .iter()
            .all(|o| o.as_ref().is_err_and(|e| e.contains("at most the 4"))));
    }
}
