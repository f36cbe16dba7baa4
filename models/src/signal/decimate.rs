//! FIR decimation as MATLAB's `decimate(x, r, 'fir')` computes it, stage
//! by stage after a [`DecimationPlan`].
//!
//! One stage of factor `r` filters with `b = fir1(30, 1/r)` (31 taps,
//! symmetric, so its delay of 15 samples is compensated exactly) and keeps
//! every `r`-th filtered sample, starting with the first:
//!
//! `y[j] = Σ_{k=0}^{30} b[k] · x̄[j·r + 15 − k]`, `j = 0 … ⌈N/r⌉ − 1`,
//!
//! where `x̄` is the record continued past its ends. MATLAB continues a
//! record by odd reflection about its end samples,
//! `x̄[−i] = 2 x[0] − x[i]` and `x̄[N−1+i] = 2 x[N−1] − x[N−1−i]`
//! ([`decimate_fir`]); one period of a periodic record continues
//! periodically ([`decimate_fir_periodic`]).

use super::{check_record, invalid};
use hysteron_operators::Result;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// The FIR order of MATLAB's `decimate(…, 'fir')`: 31 taps, a delay of 15
/// samples.
pub const DECIMATE_ORDER: usize = 30;
const DELAY: usize = DECIMATE_ORDER / 2;

/// The taps of MATLAB's `fir1(order, wn)` low-pass: the ideal low-pass of
/// cutoff `wn` (a fraction of the Nyquist frequency) windowed by a Hamming
/// window of `order + 1` points and scaled to unit gain at DC.
pub fn fir1_lowpass(order: usize, wn: f64) -> Result<Vec<f64>> {
    if !(wn > 0.0 && wn < 1.0) {
        return Err(invalid("wn", wn, "must lie in (0, 1)"));
    }
    if order == 0 {
        return Err(invalid("order", 0.0, "must be ≥ 1"));
    }
    let len = order + 1;
    let centre = order as f64 / 2.0;
    let pi = std::f64::consts::PI;
    let taps: Vec<f64> = (0..len)
        .map(|i| {
            let m = i as f64 - centre;
            let ideal = if m == 0.0 {
                wn
            } else {
                (pi * wn * m).sin() / (pi * m)
            };
            let window = 0.54 - 0.46 * (2.0 * pi * i as f64 / order as f64).cos();
            ideal * window
        })
        .collect();
    let sum: f64 = taps.iter().sum();
    Ok(taps.into_iter().map(|b| b / sum).collect())
}

/// The factors of successive decimation stages, applied in order: a plan
/// `[2, 2, 5]` decimates by 20 in three calls of MATLAB's `decimate`
/// (how the Bouc-Wen benchmark's multisine records were made), `[20]` in
/// one (its sine-sweep record). The stages differ: each filters with
/// `fir1(30, 1/r)` at its own rate, so the overall response depends on the
/// plan, not only on the product.
///
/// Written and parsed as the factors joined by `,` (`"2,2,5"`, `"20"`);
/// `x` and `·` are accepted as separators too.
///
/// ```
/// use hysteron_models::signal::DecimationPlan;
/// let plan: DecimationPlan = "2,2,5".parse().unwrap();
/// assert_eq!(plan, DecimationPlan::prime_stages(20).unwrap());
/// assert_eq!(plan.factor(), 20);
/// assert_eq!(DecimationPlan::single(20).unwrap().stages(), &[20]);
/// assert!("2,0".parse::<DecimationPlan>().is_err());
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "Vec<usize>", into = "Vec<usize>")]
pub struct DecimationPlan {
    stages: Vec<usize>,
}

/// Why a [`DecimationPlan`] could not be made.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PlanError {
    /// A plan needs at least one stage.
    #[error("a decimation plan needs at least one stage")]
    Empty,
    /// Stage `index` (from 0) is not a whole number.
    #[error("decimation stage {index} ('{text}') is not a whole number")]
    NotAFactor {
        /// The stage's position.
        index: usize,
        /// What was written there.
        text: String,
    },
    /// Stage `index` (from 0) is zero.
    #[error("decimation stage {index} is 0; every factor must be ≥ 1")]
    Zero {
        /// The stage's position.
        index: usize,
    },
    /// The product of the factors does not fit in `usize`.
    #[error("the product of the decimation factors overflows")]
    Overflow,
}

impl DecimationPlan {
    /// A plan of the given stages, each `≥ 1` (a factor 1 leaves the
    /// record as it is, as in MATLAB).
    pub fn new(stages: Vec<usize>) -> std::result::Result<Self, PlanError> {
        if stages.is_empty() {
            return Err(PlanError::Empty);
        }
        if let Some(index) = stages.iter().position(|&r| r == 0) {
            return Err(PlanError::Zero { index });
        }
        stages
            .iter()
            .try_fold(1usize, |acc, &r| acc.checked_mul(r))
            .ok_or(PlanError::Overflow)?;
        Ok(Self { stages })
    }

    /// One stage of factor `r`.
    pub fn single(r: usize) -> std::result::Result<Self, PlanError> {
        Self::new(vec![r])
    }

    /// The prime factors of `r` in increasing order, one stage each
    /// (`20` → `2, 2, 5`); `r = 1` is the single stage 1.
    pub fn prime_stages(r: usize) -> std::result::Result<Self, PlanError> {
        if r == 0 {
            return Err(PlanError::Zero { index: 0 });
        }
        let mut stages = prime_factors(r);
        if stages.is_empty() {
            stages.push(1);
        }
        Self::new(stages)
    }

    /// The factors, in the order they are applied.
    pub fn stages(&self) -> &[usize] {
        &self.stages
    }

    /// The overall factor, the product of the stages.
    pub fn factor(&self) -> usize {
        // `new` checked that the product does not overflow.
        self.stages.iter().product()
    }
}

impl TryFrom<Vec<usize>> for DecimationPlan {
    type Error = PlanError;
    fn try_from(stages: Vec<usize>) -> std::result::Result<Self, PlanError> {
        Self::new(stages)
    }
}

impl From<DecimationPlan> for Vec<usize> {
    fn from(plan: DecimationPlan) -> Self {
        plan.stages
    }
}

impl FromStr for DecimationPlan {
    type Err = PlanError;
    fn from_str(s: &str) -> std::result::Result<Self, PlanError> {
        let stages = s
            .split([',', 'x', '·'])
            .enumerate()
            .map(|(index, text)| {
                text.trim()
                    .parse::<usize>()
                    .map_err(|_| PlanError::NotAFactor {
                        index,
                        text: text.trim().to_string(),
                    })
            })
            .collect::<std::result::Result<Vec<_>, _>>()?;
        Self::new(stages)
    }
}

impl fmt::Display for DecimationPlan {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let parts: Vec<String> = self.stages.iter().map(usize::to_string).collect();
        f.write_str(&parts.join(","))
    }
}

/// Decimates a record `x` with two ends after `plan`, as MATLAB's
/// `decimate(x, r, 'fir')` does for each stage `r` in turn (see the
/// [module](self) for the formula and the odd reflection at the ends).
/// Each stage leaves `⌈N/r⌉` samples, the first at `x[0]`'s time.
///
/// The odd reflection keeps a straight line straight up to the ends: a
/// record that is linear in time passes every stage unchanged (the taps
/// sum to one and are symmetric).
///
/// Errors: an empty record is an [`Error::InvalidParameter`] naming `x`, a
/// non-finite sample an [`Error::NonFiniteInput`] at its index; every
/// stage with `r ≥ 2` needs at least 16 samples (the filter reaches 15
/// samples past each end; MATLAB itself refuses records shorter than 63),
/// otherwise an [`Error::InvalidParameter`] naming `x`.
///
/// [`Error::InvalidParameter`]: hysteron_operators::Error::InvalidParameter
/// [`Error::NonFiniteInput`]: hysteron_operators::Error::NonFiniteInput
///
/// ```
/// use hysteron_models::signal::{decimate_fir, DecimationPlan};
/// let ramp: Vec<f64> = (0..1000).map(|i| 0.5 + 0.01 * i as f64).collect();
/// let y = decimate_fir(&ramp, &DecimationPlan::single(20).unwrap()).unwrap();
/// assert_eq!(y.len(), 50);
/// assert!(y.iter().enumerate().all(|(j, v)| (v - ramp[20 * j]).abs() < 1e-12));
/// ```
pub fn decimate_fir(x: &[f64], plan: &DecimationPlan) -> Result<Vec<f64>> {
    check_record(x)?;
    let mut y = x.to_vec();
    for &r in plan.stages() {
        if r == 1 {
            continue;
        }
        if y.len() <= DELAY {
            return Err(invalid(
                "x",
                x.len() as f64,
                "is too short for the decimation plan: each stage needs at least 16 samples",
            ));
        }
        y = stage(&y, r, &fir1_lowpass(DECIMATE_ORDER, 1.0 / r as f64)?);
    }
    Ok(y)
}

/// One stage of [`decimate_fir`] on `x` with `x.len() > DELAY`, `r ≥ 2`.
// Every index is in `0..n`: with `i = j·r + DELAY − k` and
// `(⌈n/r⌉ − 1)·r ≤ n − 1`, `i` lies in `[−DELAY, n − 1 + DELAY]`, so a
// reflected index `−i` or `2(n − 1) − i` lies in `[n − 1 − DELAY, DELAY]`
// ∩ `[0, n)` because `n > DELAY`.
#[allow(clippy::indexing_slicing)]
fn stage(x: &[f64], r: usize, taps: &[f64]) -> Vec<f64> {
    let n = x.len();
    let last = n - 1;
    let at = |i: isize| -> f64 {
        if i < 0 {
            2.0 * x[0] - x[i.unsigned_abs()]
        } else if i as usize > last {
            2.0 * x[last] - x[2 * last - i as usize]
        } else {
            x[i as usize]
        }
    };
    (0..n.div_ceil(r))
        .map(|j| {
            let centre = (j * r + DELAY) as isize;
            taps.iter()
                .enumerate()
                .map(|(k, b)| b * at(centre - k as isize))
                .sum()
        })
        .collect()
}

/// Decimates one period `x` of a periodic record after `plan`: each stage
/// is MATLAB's `decimate(x, r, 'fir')` in the interior of a long periodic
/// record (the same formula as [`decimate_fir`], the record continued
/// periodically), keeping samples `0, r, 2r, …` of the period.
/// `x.len()` must be a multiple of `plan.factor()`.
///
/// This is the decimation of the Bouc-Wen benchmark's multisine records
/// (Noël & Schoukens 2016: integrated at 15 kHz, decimated by the plan
/// `2,2,5` to 750 Hz).
pub fn decimate_fir_periodic(x: &[f64], plan: &DecimationPlan) -> Result<Vec<f64>> {
    check_record(x)?;
    if !x.len().is_multiple_of(plan.factor()) {
        return Err(invalid(
            "x",
            x.len() as f64,
            "length must be a multiple of the decimation factor",
        ));
    }
    let mut y = x.to_vec();
    for &p in plan.stages() {
        if p == 1 {
            continue;
        }
        let taps = fir1_lowpass(DECIMATE_ORDER, 1.0 / p as f64)?;
        let n = y.len();
        // y[(at + delay − k) mod n], without going below 0 when the period
        // is shorter than the filter (always `< n = y.len()`).
        let circ = |i: usize, k: usize| (i % n + n - k % n) % n;
        y = (0..n / p)
            .map(|j| {
                let at = j * p;
                taps.iter()
                    .enumerate()
                    .map(|(k, b)| b * y.get(circ(at + DELAY, k)).copied().unwrap_or(0.0))
                    .sum()
            })
            .collect();
    }
    Ok(y)
}

/// Prime factors of `r ≥ 1` in increasing order, with multiplicity
/// (MATLAB's `factor`).
fn prime_factors(mut r: usize) -> Vec<usize> {
    let mut out = Vec::new();
    let mut p = 2;
    while p * p <= r {
        while r.is_multiple_of(p) {
            out.push(p);
            r /= p;
        }
        p += 1;
    }
    if r > 1 {
        out.push(r);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::signal::test_signals::{max_diff, multisine};
    use std::f64::consts::PI;

    fn primes(r: usize) -> DecimationPlan {
        DecimationPlan::prime_stages(r).unwrap()
    }

    #[test]
    fn fir1_is_a_windowed_half_band_lowpass() {
        // fir1(30, 1/2) in MATLAB: symmetric, unit DC gain, centre 0.5 / sum.
        let b = fir1_lowpass(30, 0.5).unwrap();
        assert_eq!(b.len(), 31);
        assert!((b.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        for i in 0..31 {
            assert!((b[i] - b[30 - i]).abs() < 1e-16);
        }
        // half-band: every other tap (even offsets from the centre) is zero
        assert!(b[15 + 2].abs() < 1e-16 && b[15 - 4].abs() < 1e-16);
        // gain at the cutoff (half the Nyquist frequency) is the centre tap,
        // about one half (−6 dB) for a window design
        assert!((b[15] - 0.5).abs() < 1e-2, "{}", b[15]);
        assert!(fir1_lowpass(30, 1.0).is_err() && fir1_lowpass(0, 0.5).is_err());
    }

    /// Zero-phase gain of symmetric taps at `f` cycles per sample.
    fn gain(taps: &[f64], f: f64) -> f64 {
        let c = (taps.len() - 1) as f64 / 2.0;
        taps.iter()
            .enumerate()
            .map(|(k, b)| b * (2.0 * PI * f * (k as f64 - c)).cos())
            .sum()
    }

    #[test]
    fn decimation_is_the_zero_phase_fir_chain_on_the_coarse_grid() {
        assert_eq!(prime_factors(20), vec![2, 2, 5]);
        assert_eq!(prime_factors(1), Vec::<usize>::new());
        assert_eq!(prime_factors(97), vec![97]);
        assert_eq!(prime_factors(12), vec![2, 2, 3]);
        // A sine of harmonic h over n fine samples comes out on the grid of
        // every 20th sample, scaled by the product of the stages' gains
        // (each at its own rate) and not shifted.
        let n = 4000;
        for h in [1, 37, 80, 150] {
            let x = multisine(&[(h, 1.0, 0.4)], n);
            let y = decimate_fir_periodic(&x, &primes(20)).unwrap();
            assert_eq!(y.len(), n / 20);
            let mut g = 1.0;
            let mut len = n as f64;
            for p in [2, 2, 5] {
                g *= gain(&fir1_lowpass(30, 1.0 / p as f64).unwrap(), h as f64 / len);
                len /= p as f64;
            }
            let expected: Vec<f64> = multisine(&[(h, 1.0, 0.4)], n / 20)
                .iter()
                .map(|v| g * v)
                .collect();
            let e = max_diff(&y, &expected);
            assert!(e < 1e-13, "h = {h}: {e:e}");
        }
        let x = multisine(&[(1, 1.0, 0.0)], 2000);
        assert!(decimate_fir_periodic(&x[..1999], &primes(20)).is_err());
        assert_eq!(decimate_fir_periodic(&x, &primes(1)).unwrap(), x);
    }
    /// A period shorter than the filter's delay (15 samples) wraps the
    /// circular index several times: `at + n + delay − k` underflowed (a
    /// panic in debug builds, a wrong sample in release ones).
    #[test]
    fn decimate_short_period() {
        let x = [1.0, -0.5, 0.25, 2.0];
        let y = decimate_fir_periodic(&x, &primes(2)).unwrap();
        let taps = fir1_lowpass(30, 0.5).unwrap();
        // y[j] = Σ_k b_k x[(2j + 15 − k) mod 4]
        for (j, &v) in y.iter().enumerate() {
            let want: f64 = taps
                .iter()
                .enumerate()
                .map(|(k, b)| b * x[(2 * j + 15 + 4 * 8 - k) % 4])
                .sum();
            assert!((v - want).abs() < 1e-15, "{v} {want}");
        }
        assert_eq!(
            decimate_fir_periodic(&[3.0], &primes(1)).unwrap(),
            vec![3.0]
        );
    }

    /// MATLAB's `decimate(x, r, 'fir')` step by step, as its source does it
    /// (a test oracle independent of the reflection formula): filter the
    /// mirrored head, the record and the mirrored tail as one stream, keep
    /// `list = 16 : r : nd` (one-based) of the record's part, then continue
    /// on the same grid into the tail (`nbeg = r − (nd − list(end))`).
    fn matlab_decimate_fir(x: &[f64], r: usize) -> Vec<f64> {
        let b = fir1_lowpass(30, 1.0 / r as f64).unwrap();
        let nfilt = 31;
        let nd = x.len();
        let nout = nd.div_ceil(r);
        let head = (1..=nfilt).rev().map(|i| 2.0 * x[0] - x[i]);
        let tail = (1..=2 * nfilt).map(|m| 2.0 * x[nd - 1] - x[nd - 1 - m]);
        let stream: Vec<f64> = head.chain(x.iter().copied()).chain(tail).collect();
        let filtered: Vec<f64> = (0..stream.len())
            .map(|n| (0..=n.min(30)).map(|k| b[k] * stream[n - k]).sum())
            .collect();
        let odata = &filtered[nfilt..nfilt + nd];
        let itemp = &filtered[nfilt + nd..];
        let list: Vec<usize> = (16..=nd).step_by(r).collect(); // one-based
        let mut out: Vec<f64> = list.iter().map(|&i| odata[i - 1]).collect();
        let nlen = nout - list.len();
        let nbeg = r - (nd - list[list.len() - 1]); // one-based into itemp
        out.extend((0..nlen).map(|j| itemp[nbeg - 1 + j * r]));
        out
    }

    #[test]
    fn one_stage_is_matlabs_decimate_up_to_both_ends() {
        let mut state = 0.3f64;
        for nd in [63, 64, 100, 101, 1000, 1019] {
            // a rough, non-periodic record: a drift, a sine and a chaotic map
            let x: Vec<f64> = (0..nd)
                .map(|i| {
                    state = 3.9 * state * (1.0 - state);
                    0.02 * i as f64 + (0.3 * i as f64).sin() + state
                })
                .collect();
            for r in [2, 3, 5, 20] {
                let ours = decimate_fir(&x, &DecimationPlan::single(r).unwrap()).unwrap();
                let matlab = matlab_decimate_fir(&x, r);
                assert_eq!(ours.len(), matlab.len(), "nd = {nd}, r = {r}");
                let e = max_diff(&ours, &matlab);
                assert!(e < 1e-12, "nd = {nd}, r = {r}: {e:e}");
            }
        }
    }

    /// A plan applies MATLAB's stages one after the other; `2,2,5` and
    /// `20` differ (each stage filters at its own rate), and in the
    /// interior of a long record the multi-stage result agrees with the
    /// periodic decimation of the same sine.
    #[test]
    fn plans_apply_their_stages_in_order() {
        let n = 4000;
        let x = multisine(&[(37, 1.0, 0.4)], n);
        let twenty = DecimationPlan::single(20).unwrap();
        let stages = primes(20);
        let a = decimate_fir(&x, &stages).unwrap();
        let mut by_hand = x.clone();
        for r in [2, 2, 5] {
            by_hand = decimate_fir(&by_hand, &DecimationPlan::single(r).unwrap()).unwrap();
        }
        assert_eq!(a, by_hand);
        let b = decimate_fir(&x, &twenty).unwrap();
        assert_eq!((a.len(), b.len()), (200, 200));
        assert!(max_diff(&a, &b) > 1e-3, "the two plans should differ");
        let periodic = decimate_fir_periodic(&x, &stages).unwrap();
        let interior = 20..180;
        assert!(max_diff(&a[interior.clone()], &periodic[interior]) < 1e-12);
    }

    #[test]
    fn plans_parse_print_and_refuse_bad_factors() {
        let plan: DecimationPlan = "2, 2 ,5".parse().unwrap();
        assert_eq!(plan.stages(), &[2, 2, 5]);
        assert_eq!(plan.to_string(), "2,2,5");
        assert_eq!("2x2x5".parse::<DecimationPlan>().unwrap(), plan);
        assert_eq!(
            "2,a".parse::<DecimationPlan>(),
            Err(PlanError::NotAFactor {
                index: 1,
                text: "a".into()
            })
        );
        assert_eq!(
            "".parse::<DecimationPlan>().unwrap_err().to_string(),
            "decimation stage 0 ('') is not a whole number"
        );
        assert_eq!(DecimationPlan::new(vec![]), Err(PlanError::Empty));
        assert_eq!(
            DecimationPlan::new(vec![4, 0]),
            Err(PlanError::Zero { index: 1 })
        );
        assert_eq!(
            DecimationPlan::new(vec![usize::MAX, 2]),
            Err(PlanError::Overflow)
        );
        assert_eq!(DecimationPlan::prime_stages(1).unwrap().stages(), &[1]);
        let json = serde_json::to_string(&plan).unwrap();
        assert_eq!(json, "[2,2,5]");
        assert!(serde_json::from_str::<DecimationPlan>("[3,0]").is_err());
    }

    #[test]
    fn bad_records_are_errors() {
        let twenty = DecimationPlan::single(20).unwrap();
        assert!(decimate_fir(&[], &twenty).is_err());
        assert!(decimate_fir(&[1.0; 15], &twenty).is_err());
        let one = decimate_fir(&[1.0; 16], &twenty).unwrap();
        assert!(one.len() == 1 && (one[0] - 1.0).abs() < 1e-15, "{one:?}");
        assert!(matches!(
            decimate_fir(&[0.0, 1.0, f64::NAN], &twenty),
            Err(hysteron_operators::Error::AtSample { index: 2, .. })
        ));
        // a factor of 1 leaves any record as it is
        assert_eq!(decimate_fir(&[7.0], &primes(1)).unwrap(), vec![7.0]);
    }
}
