//! What a fit gives back: the fitted model, its report, and the report's
//! parts.

use crate::options::Jacobian;
use hysteron_operators::Operator;
use serde::Serialize;
use std::fmt;
use std::time::Duration;

/// A fitted model and its report.
#[derive(Debug, Clone)]
pub struct Fit {
    /// The model with the fitted parameters (reset).
    pub model: Box<dyn Operator<f64>>,
    /// What the fit did.
    pub report: FitReport,
}

/// The outcome of a fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FitReport {
    /// The free parameters: the shared ones, then each record's own
    /// ([`FittedParam::record`]).
    pub params: Vec<FittedParam>,
    /// The model's full parameter vector after the fit: the shared
    /// parameters fitted, a per-record parameter at its starting value (it
    /// belongs to its record, see `params`).
    pub all_params: Vec<f64>,
    /// Final cost `½ Σ r_i²`.
    pub cost: f64,
    /// Root-mean-square residual over every scored sample.
    pub rms: f64,
    /// `rms / RMS(y)` over every scored sample, `y`'s root mean square
    /// taken about zero ([`metrics::errors`](crate::metrics::errors)'s
    /// NRMSE); `None` for an output that is zero throughout.
    pub nrmse: Option<f64>,
    /// The same figures per record, in the order given.
    pub records: Vec<RecordFit>,
    /// Levenberg-Marquardt iterations (Jacobian evaluations).
    pub iterations: usize,
    /// Model simulations over all records (residuals and Jacobian; a pass
    /// of the dual model counts as one).
    pub evaluations: usize,
    /// How the Jacobian was computed ([`Jacobian::FiniteDifferences`] where
    /// exact derivatives were asked for but the model has no dual twin).
    pub jacobian: Jacobian,
    /// Wall time of the fit.
    #[serde(serialize_with = "seconds")]
    pub wall_time: Duration,
    /// How it ended.
    pub status: FitStatus,
    /// Correlation matrix of the free parameters (in the order of
    /// `params`), `ρ_ij = C_ij / √(C_ii C_jj)` from the Gauss-Newton
    /// covariance `C = σ² (JᵀJ)⁻¹`; `None` where `JᵀJ` is singular, NaN in
    /// the row and column of a parameter whose Jacobian column vanishes
    /// ([`diagnostics::inverse_of_determined`](crate::diagnostics::inverse_of_determined)).
    /// The reparametrization of bounded parameters is monotone and
    /// increasing, so to first order it leaves the correlations unchanged.
    pub correlation: Option<Vec<Vec<f64>>>,
    /// Condition number `κ = λ_max/λ_min` of `JᵀJ` in the internal
    /// parameters ([`diagnostics::conditioning`](crate::diagnostics::conditioning));
    /// `None` where `JᵀJ` is singular.
    pub condition_number: Option<f64>,
    /// Parameters the data do not pin down: parameters the output does not
    /// depend on at the solution, wide intervals, correlated
    /// pairs, a singular `JᵀJ` ([`diagnostics::warnings`](crate::diagnostics::warnings)).
    pub warnings: Vec<IdentifiabilityWarning>,
    /// The costs of every start of a multi-start search and how many
    /// reached the best ([`fit_multistart`](crate::fit_multistart));
    /// `None` for a single start.
    pub starts: Option<StartsSummary>,
}

impl FitReport {
    /// The covariance of the free parameters in the model's own (external)
    /// parameters, in the order of [`params`](Self::params):
    ///
    /// `C_ij = ρ_ij σ_i σ_j`
    ///
    /// from [`correlation`](Self::correlation) and each parameter's
    /// [`std_error`](FittedParam::std_error) (the delta method through the
    /// reparametrization: to first order, `C = D C_int D` with `D` the
    /// diagonal of the maps' slopes). A parameter without a standard error
    /// (its Jacobian column vanishes) has a zero row and column: it is held
    /// at its value. `ρ` is symmetrized (`(ρ_ij + ρ_ji)/2`, a difference
    /// in the last bits from the inverse's rounding), so `C` is exactly
    /// symmetric. `None` where the fit gives no correlation (`JᵀJ`
    /// singular).
    pub fn covariance(&self) -> Option<Vec<Vec<f64>>> {
        let rho = self.correlation.as_ref()?;
        let sd: Vec<Option<f64>> = self
            .params
            .iter()
            .map(|p| p.std_error.filter(|s| s.is_finite()))
            .collect();
        let cov = sd
            .iter()
            .enumerate()
            .map(|(i, si)| {
                sd.iter()
                    .enumerate()
                    .map(|(j, sj)| {
                        let at = |a: usize, b: usize| {
                            rho.get(a)
                                .and_then(|row| row.get(b))
                                .copied()
                                .unwrap_or(0.0)
                        };
                        // (ρ_ij + ρ_ji)/2: the inverse's rounding leaves ρ
                        // asymmetric in the last bits, C is made exactly
                        // symmetric
                        let r = if i == j {
                            1.0
                        } else {
                            0.5 * (at(i, j) + at(j, i))
                        };
                        match (si, sj) {
                            (Some(a), Some(b)) if r.is_finite() => r * (a * b),
                            _ => 0.0,
                        }
                    })
                    .collect()
            })
            .collect();
        Some(cov)
    }
}

fn seconds<S: serde::Serializer>(d: &Duration, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_f64(d.as_secs_f64())
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
    /// through the reparametrization); `None` where `JᵀJ` is singular, and
    /// for a parameter whose Jacobian column vanishes
    /// ([`diagnostics::determined`](crate::diagnostics::determined)).
    pub std_error: Option<f64>,
    /// 95 % confidence interval: `θ ± 1.96 σ_θ` mapped through the
    /// reparametrization (so it respects the parameter's bounds).
    pub ci95: Option<(f64, f64)>,
    /// The record whose own value this is (a per-record parameter of
    /// [`fit_records`](crate::fit_records), such as an initial state); `None` for a parameter
    /// shared by all records.
    pub record: Option<usize>,
}

impl FittedParam {
    /// The name, with `[record i]` appended for a per-record parameter.
    pub fn label(&self) -> String {
        match self.record {
            Some(i) => format!("{}[record {i}]", self.name),
            None => self.name.clone(),
        }
    }
}

/// The fit's figures on one record (over its scored samples, after the
/// warm-up).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RecordFit {
    /// Output samples compared (the record's length minus its skip).
    pub samples: usize,
    /// Root-mean-square residual.
    pub rms: f64,
    /// `rms / RMS(y)` over the scored samples (RMS about zero); `None` for
    /// an output that is zero throughout.
    pub nrmse: Option<f64>,
}

/// A sign that the data do not determine a parameter, or a pair of them.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum IdentifiabilityWarning {
    /// `JᵀJ` is singular (or not positive definite): some combination of
    /// the free parameters does not change the output at all, and no
    /// standard errors, intervals or correlations exist. `names` are the
    /// parameters in that combination: those with a component of at least
    /// [`IN_NULL_DIRECTION`](crate::diagnostics::IN_NULL_DIRECTION) in the unit eigenvector of the smallest
    /// eigenvalue.
    Singular {
        /// The parameters of the combination ([`FittedParam::label`]).
        names: Vec<String>,
    },
    /// The parameter's column of `J` vanishes ([`determined`](crate::diagnostics::determined)): at this
    /// point the output does not depend on it (typically a non-negative
    /// parameter driven to 0). It has no standard error, and the others'
    /// are computed with it held at its value.
    Undetermined {
        /// The parameter ([`FittedParam::label`]).
        name: String,
        /// Its fitted value.
        value: f64,
    },
    /// The 95 % interval of the parameter is wider than `|value|`.
    WideInterval {
        /// The parameter ([`FittedParam::label`]).
        name: String,
        /// Its fitted value.
        value: f64,
        /// Its 95 % interval.
        interval: (f64, f64),
    },
    /// Two parameters are correlated beyond [`CORRELATED`](crate::diagnostics::CORRELATED): the data
    /// determine a combination of them, not each one.
    Correlated {
        /// The first parameter.
        first: String,
        /// The second.
        second: String,
        /// Their correlation `ρ`.
        rho: f64,
    },
}

impl fmt::Display for IdentifiabilityWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Singular { names } => {
                let quoted: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
                let what = match quoted.as_slice() {
                    [one] => one.clone(),
                    [] => "the free parameters".to_string(),
                    many => format!("a combination of {}", many.join(", ")),
                };
                write!(
                    f,
                    "JᵀJ is singular: {what} does not change the output (no standard errors)"
                )
            }
            Self::Undetermined { name, value } => write!(
                f,
                "`{name}` = {value:.4e} does not change the output here (its Jacobian column \
                 vanishes): no standard error; the others' are computed with it held"
            ),
            Self::WideInterval {
                name,
                value,
                interval: (a, b),
            } => write!(
                f,
                "`{name}`: its 95 % interval [{a:.4e}, {b:.4e}] is wider than |value| = {:.4e}",
                value.abs()
            ),
            Self::Correlated { first, second, rho } => write!(
                f,
                "`{first}` and `{second}` are correlated (ρ = {rho:.6}): the data fix a \
                 combination of the two"
            ),
        }
    }
}

/// What a multi-start search found, beside its best fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StartsSummary {
    /// The final cost of every start, in start order (`None`: that start
    /// failed, for example a vector the model refuses).
    pub costs: Vec<Option<f64>>,
    /// The start that gave the best fit.
    pub best: usize,
    /// Starts whose cost is within [`REACHED`](crate::multistart::REACHED) of the best (the best
    /// included).
    pub reached: usize,
}
