//! Global sensitivity: the Sobol indices of a scalar statistic of a model's
//! output over one input, with respect to chosen parameters (the
//! *factors*), each uniform within its bounds, the others held at the
//! model's values.
//!
//! With `Y = g(X_1, …, X_k)` the statistic as a function of the factors
//! (independent, `X_i` uniform on `[low_i, high_i]`) and `V = Var Y`:
//!
//! * the **first-order index** `S_i = Var(E[Y | X_i]) / V` is the share of
//!   the variance that `X_i` explains alone;
//! * the **total index** `S_Ti = E[Var(Y | X_~i)] / V = 1 − Var(E[Y | X_~i]) / V`
//!   adds every interaction `X_i` takes part in (`X_~i`: all factors but
//!   `X_i`). `S_Ti − S_i` measures its interactions; `S_Ti ≈ 0` means the
//!   factor can be fixed anywhere in its bounds.
//!
//! **Design (Saltelli sampling).** Two base matrices `A` and `B` (`N × k`)
//! take their rows from one scrambled Sobol low-discrepancy sequence of
//! dimension `2k` (columns `0..k` for `A`, `k..2k` for `B`; Owen-scrambled
//! and seeded, from the `sobol_burley` crate), mapped uniformly into the
//! bounds; `A_B^(i)` is `A` with its column `i` taken from `B`. The model
//! runs once per row of `A`, `B` and the `k` matrices `A_B^(i)`:
//! `N (k + 2)` runs, all through the [`Ensemble`] of the design's
//! parameter matrix (split into chunks of whole lane blocks when the
//! outputs would pass 2²² values, to bound memory), in parallel.
//!
//! **Estimators** (the pair Saltelli et al. 2010 recommend), with
//! `f_A`, `f_B`, `f_{A_B^i}` the statistic's values row by row, `V` the
//! variance of the `2N` values of `f_A` and `f_B` together:
//!
//! `S_i ≈ (1/N) Σ_j f_B,j (f_{A_B^i},j − f_A,j) / V`  
//! `S_Ti ≈ (1/(2N)) Σ_j (f_A,j − f_{A_B^i},j)² / V`  (Jansen).
//!
//! Their error falls roughly as `1/N` for a smooth statistic (a Sobol
//! sequence; `1/√N` at worst). An estimate can fall slightly below 0 or
//! above 1: it is reported as computed.
//!
//! # Reference
//! A. Saltelli, P. Annoni, I. Azzini, F. Campolongo, M. Ratto, S. Tarantola,
//! "Variance based sensitivity analysis of model output. Design and
//! estimator for the total sensitivity index", *Comput. Phys. Commun.*
//! 181 (2010) 259–270.

use crate::ensemble::{Ensemble, EnsembleError};
use crate::fit::free_by_names;
use hysteron_models::energy::closed_loop_work;
use hysteron_models::Spec;
use hysteron_operators::lanes::WIDTH;
use hysteron_operators::{Error, Operator};
use nalgebra::DMatrix;
use rayon::prelude::*;
use std::fmt;
use std::sync::Arc;

/// The most factors: the Sobol sequence has `2 · MAX_FACTORS` dimensions.
pub const MAX_FACTORS: usize = (sobol_burley::NUM_DIMENSIONS / 2) as usize;
/// The fewest base samples `N`.
pub const MIN_SAMPLES: usize = 16;
/// The most base samples `N` (the length of the Sobol sequence, `2¹⁶`).
pub const MAX_SAMPLES: usize = 1 << 16;
/// Outputs held at once: the ensemble runs in chunks of about this many
/// values (whole lane blocks of instances).
const CHUNK_VALUES: usize = 1 << 22;

/// A factor: a parameter named as the model lists it (`left.mms.f_c`) or
/// by a unique suffix after a dot (`f_c`), uniform on `[low, high]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Factor {
    /// The parameter's name or unique suffix.
    pub name: String,
    /// The lower bound (finite).
    pub low: f64,
    /// The upper bound (finite, `> low`).
    pub high: f64,
}

impl Factor {
    /// The factor `name` uniform on `[low, high]`.
    pub fn new(name: impl Into<String>, low: f64, high: f64) -> Factor {
        Factor {
            name: name.into(),
            low,
            high,
        }
    }
}

/// A caller's statistic of the input `x` and one run's output `y`.
pub type StatisticFn = Arc<dyn Fn(&[f64], &[f64]) -> f64 + Send + Sync>;

/// The scalar a run is summed up by, from the input `x` and the output `y`
/// (`n` samples).
#[derive(Clone)]
pub enum Statistic {
    /// The loop energy `|∮ y dx|`: the magnitude of the work over the
    /// record's closed polygon by the trapezoid rule
    /// ([`closed_loop_work`]), the energy dissipated over it when the
    /// input is whole periods (it ends where it starts).
    Energy,
    /// The signed work `∮ y dx` ([`closed_loop_work`]: `> 0` for clockwise
    /// loops).
    Work,
    /// The peak `max_n |y_n|`.
    Peak,
    /// The root mean square `√(Σ y_n² / n)`.
    Rms,
    /// The mean `Σ y_n / n`.
    Mean,
    /// A caller's function of `(x, y)`.
    Custom(StatisticFn),
}

impl Statistic {
    /// A caller's statistic.
    pub fn custom(f: impl Fn(&[f64], &[f64]) -> f64 + Send + Sync + 'static) -> Statistic {
        Statistic::Custom(Arc::new(f))
    }

    /// Its name (`energy`, `work`, `peak`, `rms`, `mean`, `custom`).
    pub fn name(&self) -> &'static str {
        match self {
            Statistic::Energy => "energy",
            Statistic::Work => "work",
            Statistic::Peak => "peak",
            Statistic::Rms => "rms",
            Statistic::Mean => "mean",
            Statistic::Custom(_) => "custom",
        }
    }

    /// Its value for the input `x` and the output `y`.
    pub fn eval(&self, x: &[f64], y: &[f64]) -> f64 {
        let n = y.len().max(1) as f64;
        match self {
            Statistic::Energy => closed_loop_work(x, y).abs(),
            Statistic::Work => closed_loop_work(x, y),
            Statistic::Peak => y.iter().fold(0.0, |m: f64, v| m.max(v.abs())),
            Statistic::Rms => (y.iter().map(|v| v * v).sum::<f64>() / n).sqrt(),
            Statistic::Mean => y.iter().sum::<f64>() / n,
            Statistic::Custom(f) => f(x, y),
        }
    }
}

impl fmt::Debug for Statistic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Statistic::{}", self.name())
    }
}

/// How many runs, and which sequence.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SobolOptions {
    /// The base samples `N` (rows of `A` and `B`): a power of two from
    /// [`MIN_SAMPLES`] to [`MAX_SAMPLES`]. The model runs `N (k + 2)` times.
    pub samples: usize,
    /// The scramble of the Sobol sequence (another seed, another
    /// independent randomization).
    pub seed: u32,
}

impl Default for SobolOptions {
    /// `N = 1024`, seed 0.
    fn default() -> Self {
        SobolOptions {
            samples: 1024,
            seed: 0,
        }
    }
}

/// The Sobol indices of a statistic.
#[derive(Debug, Clone, PartialEq)]
pub struct SobolIndices {
    /// The factors' full parameter names, in the order given.
    pub names: Vec<String>,
    /// The first-order indices `S_i`.
    pub first: Vec<f64>,
    /// The total indices `S_Ti`.
    pub total: Vec<f64>,
    /// The statistic's mean over `A` and `B`.
    pub mean: f64,
    /// The statistic's variance `V` over `A` and `B` (`2N` runs).
    pub variance: f64,
    /// The base samples `N`.
    pub samples: usize,
    /// The model runs, `N (k + 2)`.
    pub evaluations: usize,
}

/// Why the indices could not be estimated (each names its field, factor
/// or run).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SobolError {
    /// The spec does not build.
    #[error("model: {0}")]
    Model(String),
    /// No factor given.
    #[error("factors: none given: name at least one parameter with its bounds")]
    NoFactors,
    /// More factors than the sequence has dimensions for.
    #[error("factors: {got} given, but the Sobol sequence allows at most {max}")]
    TooManyFactors {
        /// The factors given.
        got: usize,
        /// [`MAX_FACTORS`].
        max: usize,
    },
    /// A factor's name matches no parameter, or several.
    #[error("factor `{name}`: {reason}")]
    UnknownFactor {
        /// The name given.
        name: String,
        /// What it matched (with the model's parameters).
        reason: String,
    },
    /// Two factors name one parameter.
    #[error("factor `{name}`: parameter `{path}` is already the factor `{first}`")]
    RepeatedFactor {
        /// The second name given.
        name: String,
        /// The first name given for it.
        first: String,
        /// The parameter's full name.
        path: String,
    },
    /// A factor's bounds are not finite, or `low ≥ high`.
    #[error("factor `{name}`: bounds [{low}, {high}] must be finite with low < high")]
    Bounds {
        /// The factor.
        name: String,
        /// Its lower bound.
        low: f64,
        /// Its upper bound.
        high: f64,
    },
    /// The base samples are not a power of two in range.
    #[error(
        "samples: {got} base samples, but N must be a power of two from {MIN_SAMPLES} to {MAX_SAMPLES}"
    )]
    Samples {
        /// The base samples asked for.
        got: usize,
    },
    /// The input has no samples.
    #[error("input: no samples")]
    EmptyInput,
    /// An input sample is not finite.
    #[error("input: sample {sample} is {value}, not finite")]
    NonFiniteInput {
        /// The sample (0-based).
        sample: usize,
        /// Its value.
        value: f64,
    },
    /// A run failed (its parameters out of their domains, or the model
    /// refused a sample).
    #[error("run {run} ({}): {error}", show(.factors))]
    Run {
        /// The run (row of the design: `A`, `B`, then each `A_B^(i)`).
        run: usize,
        /// Its factors' values.
        factors: Vec<(String, f64)>,
        /// What the model gave.
        error: Error,
    },
    /// A run's statistic is not finite.
    #[error("run {run} ({}): the statistic is {value}, not finite", show(.factors))]
    NonFiniteStatistic {
        /// The run.
        run: usize,
        /// Its factors' values.
        factors: Vec<(String, f64)>,
        /// The statistic's value.
        value: f64,
    },
    /// The statistic does not vary over the factors' bounds: the indices
    /// are undefined.
    #[error(
        "statistic: its variance over the runs is {variance} (mean {mean}): it does not vary with the factors"
    )]
    ZeroVariance {
        /// The variance `V`.
        variance: f64,
        /// The mean.
        mean: f64,
    },
    /// The ensemble refused the design or the input.
    #[error("{0}")]
    Ensemble(String),
}

fn show(factors: &[(String, f64)]) -> String {
    factors
        .iter()
        .map(|(n, v)| format!("{n} = {v}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The Sobol indices of `statistic` of the model of `spec` over `x` with
/// respect to `factors` (see the [module documentation](self) for the
/// design and the estimators). Play and MMS leaves run eight instances per
/// vector instruction ([`Ensemble::new`]).
///
/// # Requirements
/// * `factors`: 1 to [`MAX_FACTORS`] distinct parameters, bounds finite
///   with `low < high` (and inside the parameters' domains: a run out of
///   them fails);
/// * `opts.samples`: a power of two from [`MIN_SAMPLES`] to [`MAX_SAMPLES`];
/// * `x`: at least one sample, all finite;
/// * every run succeeds, and the statistic is finite and varies.
///
/// # Errors
/// A [`SobolError`] naming the factor, the input sample or the run (with
/// its factors' values).
///
/// # Reference
/// A. Saltelli et al., "Variance based sensitivity analysis of model
/// output. Design and estimator for the total sensitivity index",
/// *Comput. Phys. Commun.* 181 (2010) 259–270.
///
/// ```
/// use hysteron_identify::sobol::{sobol, Factor, SobolOptions, Statistic};
/// use hysteron_models::Spec;
///
/// // a stop (elastic-plastic, level r, from s0) driven by two periods of a
/// // sine: its loop energy, 4 r (A − r) per steady cycle, is set by r; the
/// // initial output s0 only shifts the first rising branch
/// let spec = Spec::from_json(r#"{"type": "stop", "r": 0.5}"#)?;
/// let x: Vec<f64> = (0..=128).map(|i| (i as f64 * std::f64::consts::TAU / 64.0).sin()).collect();
/// let factors = [Factor::new("r", 0.2, 0.8), Factor::new("s0", -0.1, 0.1)];
/// let s = sobol(&spec, &x, &factors, &Statistic::Energy, &SobolOptions { samples: 256, seed: 1 })?;
/// assert_eq!(s.names, ["r", "s0"]);
/// assert_eq!(s.evaluations, 256 * 4);
/// assert!(s.first[0] > 0.9 && s.total[0] > 0.9);
/// assert!(s.total[1] < 0.1);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn sobol(
    spec: &Spec,
    x: &[f64],
    factors: &[Factor],
    statistic: &Statistic,
    opts: &SobolOptions,
) -> Result<SobolIndices, SobolError> {
    let model = spec.build().map_err(|e| SobolError::Model(e.to_string()))?;
    estimate(model.as_ref(), x, factors, statistic, opts, |params| {
        Ensemble::new(spec, params)
    })
}

/// The Sobol indices of `statistic` of a built model (any [`Operator`]:
/// a fitted model, one of the caller's own) over `x`: as [`sobol`], the
/// runs stepped one instance at a time ([`Ensemble::of_model`]), each from
/// the model's initial state.
///
/// # Requirements
/// As [`sobol`].
///
/// # Errors
/// As [`sobol`], without [`SobolError::Model`].
///
/// # Reference
/// As [`sobol`].
pub fn sobol_of_model(
    model: &(dyn Operator<f64> + 'static),
    x: &[f64],
    factors: &[Factor],
    statistic: &Statistic,
    opts: &SobolOptions,
) -> Result<SobolIndices, SobolError> {
    estimate(model, x, factors, statistic, opts, |params| {
        Ensemble::of_model(model, params)
    })
}

/// The checks, the design, the runs (each chunk an ensemble from
/// `ensemble`) and the estimators.
fn estimate(
    model: &(dyn Operator<f64> + 'static),
    x: &[f64],
    factors: &[Factor],
    statistic: &Statistic,
    opts: &SobolOptions,
    ensemble: impl Fn(&DMatrix<f64>) -> Result<Ensemble, EnsembleError>,
) -> Result<SobolIndices, SobolError> {
    let n = opts.samples;
    if !(MIN_SAMPLES..=MAX_SAMPLES).contains(&n) || !n.is_power_of_two() {
        return Err(SobolError::Samples { got: n });
    }
    let columns = resolve(model, factors)?;
    if x.is_empty() {
        return Err(SobolError::EmptyInput);
    }
    if let Some((sample, &value)) = x.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(SobolError::NonFiniteInput { sample, value });
    }
    let names: Vec<String> = {
        let all = model.param_names();
        columns
            .iter()
            .map(|&j| all.get(j).cloned().unwrap_or_default())
            .collect()
    };
    let design = Design::new(factors, n, opts.seed);
    let own = model.params();
    let runs = design.runs();
    let t = x.len();
    let chunk = (CHUNK_VALUES / t / WIDTH).max(1) * WIDTH;
    let mut f = Vec::with_capacity(runs);
    for start in (0..runs).step_by(chunk) {
        let rows = chunk.min(runs - start);
        let mut params = DMatrix::from_fn(rows, own.len(), |_, c| {
            own.get(c).copied().unwrap_or(f64::NAN)
        });
        for r in 0..rows {
            for (i, &c) in columns.iter().enumerate() {
                if let Some(p) = params.get_mut((r, c)) {
                    *p = design.value(start + r, i);
                }
            }
        }
        let run = ensemble(&params)
            .and_then(|e| e.run(x))
            .map_err(|e| SobolError::Ensemble(e.to_string()))?;
        if let Some(failure) = run.failures.first() {
            let r = start + failure.instance;
            return Err(SobolError::Run {
                run: r,
                factors: design.labelled(&names, r),
                error: failure.error.clone(),
            });
        }
        let values: Vec<f64> = run
            .outputs
            .par_chunks(t)
            .map(|y| statistic.eval(x, y))
            .collect();
        if let Some((i, &value)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            let r = start + i;
            return Err(SobolError::NonFiniteStatistic {
                run: r,
                factors: design.labelled(&names, r),
                value,
            });
        }
        f.extend(values);
    }
    indices(&f, n, names)
}

/// The model's parameter index of each factor, after checking the names
/// and bounds.
fn resolve(
    model: &(dyn Operator<f64> + 'static),
    factors: &[Factor],
) -> Result<Vec<usize>, SobolError> {
    if factors.is_empty() {
        return Err(SobolError::NoFactors);
    }
    if factors.len() > MAX_FACTORS {
        return Err(SobolError::TooManyFactors {
            got: factors.len(),
            max: MAX_FACTORS,
        });
    }
    let all = model.param_names();
    let mut columns: Vec<usize> = Vec::with_capacity(factors.len());
    for factor in factors {
        let j = free_by_names(model, &[factor.name.as_str()])
            .map_err(|e| SobolError::UnknownFactor {
                name: factor.name.clone(),
                reason: e.to_string(),
            })?
            .first()
            .copied()
            .ok_or_else(|| SobolError::UnknownFactor {
                name: factor.name.clone(),
                reason: "no parameter".into(),
            })?;
        if let Some(k) = columns.iter().position(|&c| c == j) {
            return Err(SobolError::RepeatedFactor {
                name: factor.name.clone(),
                first: factors.get(k).map(|f| f.name.clone()).unwrap_or_default(),
                path: all.get(j).cloned().unwrap_or_default(),
            });
        }
        let (low, high) = (factor.low, factor.high);
        if !(low.is_finite() && high.is_finite() && low < high) {
            return Err(SobolError::Bounds {
                name: factor.name.clone(),
                low,
                high,
            });
        }
        columns.push(j);
    }
    Ok(columns)
}

/// The Saltelli design: the base matrices `A` and `B` (row-major `N × k`,
/// values inside the bounds) and which row of which matrix each run is.
struct Design {
    a: Vec<f64>,
    b: Vec<f64>,
    n: usize,
    k: usize,
}

impl Design {
    /// `A` from dimensions `0..k` of the Sobol sequence scrambled by
    /// `seed`, `B` from dimensions `k..2k`, point `j` of each in row `j`;
    /// each coordinate `u` (a multiple of `2⁻²⁴` in `[0, 1)`) taken at the
    /// middle of its cell, `u + 2⁻²⁵`, so strictly inside `(0, 1)`, then
    /// mapped to `low + u (high − low)`.
    fn new(factors: &[Factor], n: usize, seed: u32) -> Design {
        let k = factors.len();
        let half_cell = (-25.0_f64).exp2();
        let matrix = |offset: usize| -> Vec<f64> {
            (0..n * k)
                .into_par_iter()
                .map(|e| {
                    let (j, i) = (e / k, e % k);
                    // (j < 2¹⁶ and offset + i < 2k ≤ 256: checked before)
                    let u = f64::from(sobol_burley::sample(j as u32, (offset + i) as u32, seed))
                        + half_cell;
                    factors
                        .get(i)
                        .map_or(f64::NAN, |f| f.low + u * (f.high - f.low))
                })
                .collect()
        };
        Design {
            a: matrix(0),
            b: matrix(k),
            n,
            k,
        }
    }

    /// The runs: `N (k + 2)`.
    fn runs(&self) -> usize {
        self.n * (self.k + 2)
    }

    /// Factor `i` of run `r`: rows `0..N` are `A`, `N..2N` are `B`, then
    /// `N` rows of each `A_B^(m)` (`A` with column `m` from `B`).
    fn value(&self, r: usize, i: usize) -> f64 {
        let (block, j) = (r / self.n, r % self.n);
        let from_b = block == 1 || block == i + 2;
        let m = if from_b { &self.b } else { &self.a };
        m.get(j * self.k + i).copied().unwrap_or(f64::NAN)
    }

    /// Run `r`'s factor values with their names.
    fn labelled(&self, names: &[String], r: usize) -> Vec<(String, f64)> {
        names
            .iter()
            .enumerate()
            .map(|(i, name)| (name.clone(), self.value(r, i)))
            .collect()
    }
}

/// The estimators over the statistic's values `f` (`A`, `B`, then each
/// `A_B^(i)`, `n` values each).
fn indices(f: &[f64], n: usize, names: Vec<String>) -> Result<SobolIndices, SobolError> {
    let block = |b: usize| f.get(b * n..(b + 1) * n).unwrap_or(&[]);
    let (fa, fb) = (block(0), block(1));
    let both = 2.0 * n as f64;
    let mean = fa.iter().chain(fb).sum::<f64>() / both;
    let variance = fa
        .iter()
        .chain(fb)
        .map(|v| (v - mean) * (v - mean))
        .sum::<f64>()
        / both;
    if variance <= f64::EPSILON * mean * mean || !variance.is_normal() {
        return Err(SobolError::ZeroVariance { variance, mean });
    }
    let count = n as f64;
    let (first, total) = (0..names.len())
        .map(|i| {
            let fab = block(i + 2);
            let (mut s, mut st) = (0.0, 0.0);
            for ((a, b), ab) in fa.iter().zip(fb).zip(fab) {
                s += b * (ab - a);
                st += (a - ab) * (a - ab);
            }
            (s / count / variance, st / (2.0 * count) / variance)
        })
        .unzip();
    Ok(SobolIndices {
        names,
        first,
        total,
        mean,
        variance,
        samples: n,
        evaluations: f.len(),
    })
}
