//! Uncertainty bands around a fitted model's output: the uncertainty of
//! the fitted parameters ([`FitReport::covariance`](crate::FitReport::covariance))
//! carried to the output along any input, to first order
//! ([`BandMethod::Linearized`]) or by simulating parameter vectors drawn
//! from it ([`BandMethod::MonteCarlo`]).
//!
//! A band is a confidence band for the model's *mean* output (where the
//! noise-free output lies), not a prediction band for a new measurement:
//! it does not add the noise of the record.

use crate::ensemble::Ensemble;
use crate::outcome::{Fit, FitReport, FittedParam};
use hysteron_models::sensitivity::{derivatives, Failure};
use hysteron_operators::{Error, Operator};
use nalgebra::DMatrix;
use rand::{rngs::StdRng, SeedableRng};
use rand_distr::{Distribution, StandardNormal};
use statrs::distribution::{ContinuousCDF, Normal};

/// How a band carries the parameters' covariance to the output.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BandMethod {
    /// First order: `y_k ± z·√(g_kᵀ C g_k)`, with the exact sensitivities
    /// `g_k = ∂y_k/∂θ` of the model's dual twin.
    Linearized,
    /// `draws` parameter vectors from `N(θ̂, C)` (a seeded generator), all
    /// simulated, and the empirical quantiles of the outputs per sample.
    MonteCarlo {
        /// How many parameter vectors to draw (at least 1).
        draws: usize,
        /// The generator's seed (the same seed, the same band).
        seed: u64,
    },
}

impl BandMethod {
    /// The method's name: `linearized` or `monte_carlo`.
    pub fn name(&self) -> &'static str {
        match self {
            BandMethod::Linearized => "linearized",
            BandMethod::MonteCarlo { .. } => "monte_carlo",
        }
    }
}

/// A band around a fitted model's output: per input sample, the fitted
/// model's output and the band's lower and upper edges.
#[derive(Debug, Clone, PartialEq)]
pub struct Band {
    /// The fitted model's output `y_k(θ̂)`.
    pub output: Vec<f64>,
    /// The lower edge, per sample.
    pub lower: Vec<f64>,
    /// The upper edge, per sample.
    pub upper: Vec<f64>,
    /// The band's probability content, in (0, 1).
    pub level: f64,
    /// How it was computed.
    pub method: BandMethod,
    /// Monte-Carlo draws that did not run (a parameter out of its domain,
    /// a model error, an output that is not finite) and so are not in the
    /// quantiles; 0 for the linearized band.
    pub failed_draws: usize,
}

impl Band {
    /// Half the band's width per sample, `(upper − lower)/2`.
    pub fn half_widths(&self) -> Vec<f64> {
        self.lower
            .iter()
            .zip(&self.upper)
            .map(|(l, u)| 0.5 * (u - l))
            .collect()
    }
}

/// Why a band could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BandError {
    /// The level is not in the open interval (0, 1).
    #[error("level: {level} is not in (0, 1) (the band's probability content, such as 0.95)")]
    Level {
        /// The level given.
        level: f64,
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
    /// A Monte-Carlo band with no draws.
    #[error("draws: 0; a Monte-Carlo band needs at least one draw")]
    NoDraws,
    /// The fit has no covariance: `JᵀJ` was singular.
    #[error("the fit has no parameter covariance (JᵀJ is singular, see its warnings): no band")]
    Singular,
    /// The linearized band needs the model's dual twin.
    #[error(
        "the model has no dual twin (exact sensitivities) for a linearized band: use monte_carlo"
    )]
    NoDualTwin,
    /// The fitted model fails on the input (its error names the sample).
    #[error("model: {0}")]
    Model(Error),
    /// A sensitivity is not finite (an infinite slope).
    #[error("∂y/∂{param} is not finite at sample {sample}")]
    NonFiniteSensitivity {
        /// The sample (0-based).
        sample: usize,
        /// The parameter.
        param: String,
    },
    /// Too few Monte-Carlo draws ran for the quantiles of the level.
    #[error(
        "only {succeeded} of {draws} draws ran ({failed} failed, for example out of a \
         parameter's domain); a band at level {level} needs at least {needed}"
    )]
    TooFewDraws {
        /// The draws that ran.
        succeeded: usize,
        /// The draws that failed.
        failed: usize,
        /// The draws asked for.
        draws: usize,
        /// The draws the level needs: `max(2, ⌈2/(1 − level)⌉)`.
        needed: usize,
        /// The level.
        level: f64,
    },
    /// A covariance that does not fit the model.
    #[error("covariance: {0}")]
    Covariance(String),
    /// The ensemble of draws could not run at all.
    #[error("ensemble: {0}")]
    Ensemble(String),
}

impl Fit {
    /// The band of probability content `level` around the fitted model's
    /// output along `x` (from the model's initial state), from the
    /// covariance of the fitted parameters.
    ///
    /// With `θ` the shared free parameters, `θ̂` their fitted values and
    /// `C = [ρ_ij σ_i σ_j]` their covariance ([`FitReport::covariance`](crate::FitReport::covariance),
    /// the Gauss-Newton `σ² (JᵀJ)⁻¹` with `σ² = Σ r²/(m − p)`):
    ///
    /// * [`BandMethod::Linearized`]: `y_k(θ̂) ± z·√(g_kᵀ C g_k)`, with
    ///   `g_k = ∂y_k/∂θ` at `θ̂` (forward-mode dual numbers through the
    ///   model's dual twin, [`Derivatives::to_dual`](hysteron_operators::Derivatives::to_dual))
    ///   and `z = Φ⁻¹((1 + level)/2)` the standard normal quantile;
    /// * [`BandMethod::MonteCarlo`]: `θ⁽ʲ⁾ = θ̂ + L ξ⁽ʲ⁾`, `ξ⁽ʲ⁾ ~ N(0, I)`,
    ///   `L Lᵀ = C` (Cholesky; where `C` is only semi-definite, the
    ///   eigen-factor `V √max(Λ, 0)`), every draw simulated
    ///   ([`Ensemble::of_model`]), and per sample the empirical quantiles
    ///   `(1 − level)/2` and `(1 + level)/2` (linear interpolation between
    ///   order statistics) of the draws that ran. A draw out of a
    ///   parameter's domain fails and is counted in [`Band::failed_draws`].
    ///
    /// The two agree where the output is close to linear in `θ` over a few
    /// standard errors; the Monte-Carlo band follows curvature and bounds
    /// (an asymmetric band), the linearized one is symmetric and exact
    /// for a model linear in its parameters.
    ///
    /// Held at their values (zero variance): a free parameter without a
    /// standard error (its Jacobian column vanished), every parameter the
    /// fit did not free, and every per-record parameter
    /// ([`FittedParam::record`](crate::FittedParam::record)), which belongs
    /// to its record, not to a new input: the model keeps its own value.
    ///
    /// # Requirements
    /// * `level` in (0, 1);
    /// * `x` non-empty and finite (an error names the first bad sample);
    /// * for Monte Carlo, `draws ≥ 1`, and at least `max(2, ⌈2/(1 −
    ///   level)⌉)` of them must run (40 at 0.95), so that each tail holds
    ///   a draw;
    /// * a fit with a covariance ([`BandError::Singular`] otherwise), and
    ///   for the linearized band a model with a dual twin
    ///   ([`BandError::NoDualTwin`] otherwise: every model of the library
    ///   has one, an operator of your own may not; its Monte-Carlo band
    ///   needs none).
    ///
    /// # Example
    /// ```
    /// use hysteron_identify::band::BandMethod;
    /// use hysteron_identify::{fit, FitOptions};
    /// use hysteron_operators::Gain;
    ///
    /// let x: Vec<f64> = (0..50).map(|i| (0.2 * i as f64).sin()).collect();
    /// // y = 2x and a small, sign-alternating error
    /// let y: Vec<f64> = x.iter().enumerate()
    ///     .map(|(i, v)| 2.0 * v + if i % 2 == 0 { 0.01 } else { -0.01 }).collect();
    /// let f = fit(&Gain::new(1.0)?, &x, &y, &[0], &FitOptions::default())?;
    /// let band = f.predict_band(&x, 0.95, BandMethod::Linearized)?;
    /// // the gain's output is linear in k: y_k ± z·σ_k·|x_k|
    /// let (z, sk) = (1.959963984540054, f.report.params[0].std_error.unwrap());
    /// for k in 0..x.len() {
    ///     let half = 0.5 * (band.upper[k] - band.lower[k]);
    ///     assert!((half - z * sk * x[k].abs()).abs() <= 1e-9 * (1.0 + half));
    /// }
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Reference
    /// G. A. F. Seber, C. J. Wild, *Nonlinear Regression*, Wiley 1989,
    /// §5.1 (the linearized confidence band of the mean response, with the
    /// normal quantile in place of Student's `t`, a difference below 1 %
    /// past 200 degrees of freedom at 0.95).
    pub fn predict_band(
        &self,
        x: &[f64],
        level: f64,
        method: BandMethod,
    ) -> Result<Band, BandError> {
        check(x, level, method)?;
        let cov = Covariance::of_fit(self)?;
        predict_band(self.model.as_ref(), &cov, x, level, method)
    }
}

/// The covariance of a fit's shared free parameters in the model's own
/// parameters, `C_ij = ρ_ij σ_i σ_j` ([`FitReport::covariance`](crate::FitReport::covariance)),
/// with their names, indices and fitted values: what a band needs beside
/// the model (`hysteron fit --covariance` writes it as JSON, and
/// `hysteron validate --covariance` reads it to draw a band on other
/// records).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Covariance {
    /// The parameters, as the model names them.
    pub names: Vec<String>,
    /// Their indices in the model's parameter vector.
    pub indices: Vec<usize>,
    /// Their fitted values.
    pub values: Vec<f64>,
    /// `C`, row by row, in the order of `names`.
    pub matrix: Vec<Vec<f64>>,
}

impl Covariance {
    /// The covariance of `fit`'s shared free parameters (the per-record
    /// ones left out: they belong to their records).
    ///
    /// # Errors
    /// [`BandError::Singular`] where the fit has no correlation matrix.
    pub fn of_fit(fit: &Fit) -> Result<Covariance, BandError> {
        Covariance::of_report(&fit.report)
    }

    /// [`of_fit`](Self::of_fit) from the fit's report alone.
    ///
    /// # Errors
    /// [`BandError::Singular`] where the report has no correlation matrix.
    pub fn of_report(report: &FitReport) -> Result<Covariance, BandError> {
        let cov = report.covariance().ok_or(BandError::Singular)?;
        let shared: Vec<(usize, &FittedParam)> = report
            .params
            .iter()
            .enumerate()
            .filter(|(_, p)| p.record.is_none())
            .collect();
        Ok(Covariance {
            names: shared.iter().map(|(_, p)| p.name.clone()).collect(),
            indices: shared.iter().map(|(_, p)| p.index).collect(),
            values: shared.iter().map(|(_, p)| p.value).collect(),
            matrix: shared
                .iter()
                .map(|&(a, _)| {
                    let row = cov.get(a);
                    shared
                        .iter()
                        .map(|&(b, _)| row.and_then(|r| r.get(b)).copied().unwrap_or(0.0))
                        .collect()
                })
                .collect(),
        })
    }
}

/// [`Fit::predict_band`] for any model and a covariance of some of its
/// parameters (`cov.indices` into its parameter vector, at the model's
/// own values): the parameters not in `cov` are held.
///
/// # Errors
/// As [`Fit::predict_band`], and [`BandError::Covariance`] where `cov` is
/// not square over its parameters, names an index past the model's
/// parameters, or has a value that is not finite.
pub fn predict_band(
    model: &(dyn Operator<f64> + 'static),
    cov: &Covariance,
    x: &[f64],
    level: f64,
    method: BandMethod,
) -> Result<Band, BandError> {
    check(x, level, method)?;
    let k = cov.indices.len();
    let n = model.params().len();
    if let Some(&i) = cov.indices.iter().find(|&&i| i >= n) {
        return Err(BandError::Covariance(format!(
            "parameter index {i} is past the model's {n} parameters"
        )));
    }
    if cov.matrix.len() != k || cov.matrix.iter().any(|row| row.len() != k) {
        return Err(BandError::Covariance(format!(
            "the matrix must be {k} × {k}, one row and column per parameter"
        )));
    }
    if let Some((i, j)) = (0..k)
        .flat_map(|i| (0..k).map(move |j| (i, j)))
        .find(|&(i, j)| {
            !cov.matrix
                .get(i)
                .and_then(|r| r.get(j))
                .is_some_and(|v| v.is_finite())
        })
    {
        return Err(BandError::Covariance(format!(
            "entry ({i}, {j}) is not finite"
        )));
    }
    let c = DMatrix::from_fn(k, k, |a, b| {
        cov.matrix
            .get(a)
            .and_then(|r| r.get(b))
            .copied()
            .unwrap_or(0.0)
    });
    let mut run = dyn_clone::clone_box(model);
    run.reset();
    let output = run.run(x).map_err(BandError::Model)?;
    let spread = Spread {
        model,
        x,
        indices: &cov.indices,
        c: &c,
        level,
    };
    let (lower, upper, failed_draws) = match method {
        BandMethod::Linearized => {
            let half = spread.linearized_half_widths()?;
            (
                output.iter().zip(&half).map(|(y, h)| y - h).collect(),
                output.iter().zip(&half).map(|(y, h)| y + h).collect(),
                0,
            )
        }
        BandMethod::MonteCarlo { draws, seed } => spread.monte_carlo(draws, seed)?,
    };
    Ok(Band {
        output,
        lower,
        upper,
        level,
        method,
        failed_draws,
    })
}

/// The level, the input and the draws are valid.
fn check(x: &[f64], level: f64, method: BandMethod) -> Result<(), BandError> {
    if !(level > 0.0 && level < 1.0) {
        return Err(BandError::Level { level });
    }
    if x.is_empty() {
        return Err(BandError::EmptyInput);
    }
    if let Some((sample, &value)) = x.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(BandError::NonFiniteInput { sample, value });
    }
    if let BandMethod::MonteCarlo { draws: 0, .. } = method {
        return Err(BandError::NoDraws);
    }
    Ok(())
}

/// What both methods carry to the output: the model, the input, the
/// indices of the parameters that vary, their covariance `C` and the
/// band's level.
struct Spread<'a> {
    model: &'a (dyn Operator<f64> + 'static),
    x: &'a [f64],
    indices: &'a [usize],
    c: &'a DMatrix<f64>,
    level: f64,
}

impl Spread<'_> {
    /// `z·√(g_kᵀ C g_k)` per sample, `g_k` the sensitivities of the output
    /// to the parameters at `indices` from the model's dual twin.
    fn linearized_half_widths(&self) -> Result<Vec<f64>, BandError> {
        if self.indices.is_empty() {
            return Ok(vec![0.0; self.x.len()]);
        }
        let dual = self.model.to_dual().ok_or(BandError::NoDualTwin)?;
        let (_, columns) =
            derivatives(dual.as_ref(), self.x, self.indices).map_err(|e| match e {
                Failure::Model(e) => BandError::Model(e),
                Failure::NonFinite { sample, column } => BandError::NonFiniteSensitivity {
                    sample,
                    param: self
                        .indices
                        .get(column)
                        .and_then(|&i| self.model.param_names().get(i).cloned())
                        .unwrap_or_default(),
                },
                Failure::Empty => BandError::EmptyInput,
            })?;
        let z = normal_quantile(self.level);
        let half = (0..self.x.len())
            .map(|s| {
                let g: Vec<f64> = columns
                    .iter()
                    .map(|col| col.get(s).copied().unwrap_or(0.0))
                    .collect();
                let var: f64 = g
                    .iter()
                    .enumerate()
                    .map(|(a, ga)| {
                        g.iter()
                            .enumerate()
                            .map(|(b, gb)| ga * self.c.get((a, b)).copied().unwrap_or(0.0) * gb)
                            .sum::<f64>()
                    })
                    .sum();
                z * var.max(0.0).sqrt()
            })
            .collect();
        Ok(half)
    }

    /// The Monte-Carlo band's edges and its failed draws.
    fn monte_carlo(
        &self,
        draws: usize,
        seed: u64,
    ) -> Result<(Vec<f64>, Vec<f64>, usize), BandError> {
        let base = self.model.params();
        let l = factor(self.c);
        let mut rng = StdRng::seed_from_u64(seed);
        let k = self.indices.len();
        let mut params = DMatrix::from_fn(draws, base.len(), |_, col| {
            base.get(col).copied().unwrap_or(0.0)
        });
        for mut row in params.row_iter_mut() {
            let xi: Vec<f64> = (0..k).map(|_| StandardNormal.sample(&mut rng)).collect();
            for (a, &i) in self.indices.iter().enumerate() {
                let step: f64 = (0..k)
                    .map(|b| {
                        l.get((a, b)).copied().unwrap_or(0.0) * xi.get(b).copied().unwrap_or(0.0)
                    })
                    .sum();
                if let Some(v) = row.get_mut(i) {
                    *v += step;
                }
            }
        }
        let run = Ensemble::of_model(self.model, &params)
            .and_then(|e| e.run(self.x))
            .map_err(|e| BandError::Ensemble(e.to_string()))?;
        let ran: Vec<&[f64]> = (0..draws)
            .filter_map(|i| run.row(i))
            .filter(|row| row.iter().all(|v| v.is_finite()))
            .collect();
        let failed = draws - ran.len();
        let needed = needed_draws(self.level);
        if ran.len() < needed {
            return Err(BandError::TooFewDraws {
                succeeded: ran.len(),
                failed,
                draws,
                needed,
                level: self.level,
            });
        }
        let (lo_q, hi_q) = (0.5 * (1.0 - self.level), 0.5 * (1.0 + self.level));
        let mut lower = Vec::with_capacity(self.x.len());
        let mut upper = Vec::with_capacity(self.x.len());
        let mut column = Vec::with_capacity(ran.len());
        for s in 0..self.x.len() {
            column.clear();
            column.extend(ran.iter().filter_map(|row| row.get(s).copied()));
            column.sort_by(f64::total_cmp);
            lower.push(quantile(&column, lo_q));
            upper.push(quantile(&column, hi_q));
        }
        Ok((lower, upper, failed))
    }
}

/// `Φ⁻¹((1 + level)/2)`, the two-sided standard normal quantile.
fn normal_quantile(level: f64) -> f64 {
    // `Normal::standard()` cannot fail; `new(0, 1)` is the same law.
    Normal::standard().inverse_cdf(0.5 * (1.0 + level))
}

/// A factor `L` with `L Lᵀ = C`: Cholesky, or where `C` is only
/// semi-definite (a held parameter's zero row, a correlation of ±1 to
/// rounding), `V √max(Λ, 0)` from its symmetric eigen-decomposition.
fn factor(c: &DMatrix<f64>) -> DMatrix<f64> {
    if let Some(ch) = c.clone().cholesky() {
        return ch.l();
    }
    let eig = c.clone().symmetric_eigen();
    let roots = eig.eigenvalues.map(|l| l.max(0.0).sqrt());
    eig.eigenvectors * DMatrix::from_diagonal(&roots)
}

/// The draws that must run for a band at `level`: each tail of
/// `(1 − level)/2` must hold at least one of them.
fn needed_draws(level: f64) -> usize {
    // `level < 1` (checked), so the ratio is finite and ≥ 2.
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let n = (2.0 / (1.0 - level)).ceil().min(1e9) as usize;
    n.max(2)
}

/// The `q` quantile of the sorted, non-empty `sorted`: linear
/// interpolation between the order statistics at `q (n − 1)` (Hyndman &
/// Fan's type 7, NumPy's default).
fn quantile(sorted: &[f64], q: f64) -> f64 {
    let h = q * (sorted.len().saturating_sub(1)) as f64;
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let lo = h.floor() as usize;
    let frac = h - h.floor();
    let a = sorted.get(lo).copied().unwrap_or(f64::NAN);
    let b = sorted.get(lo + 1).copied().unwrap_or(a);
    a + frac * (b - a)
}
