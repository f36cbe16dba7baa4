//! The settings of a fit, and the progress it reports.

use serde::Serialize;

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
    /// MINPACK's `patience`: at most `patience·(k + 1)` trial steps
    /// (residual evaluations at a proposed point). Each accepted step also
    /// costs a Jacobian, `2k` simulations, so the simulations are bounded by
    /// `patience·(k + 1)·(2k + 1)`; for a hard bound on the work use
    /// [`max_evaluations`](FitOptions::max_evaluations) or
    /// [`max_seconds`](FitOptions::max_seconds).
    pub patience: usize,
    /// At most this many simulations of the model over all records (trial
    /// steps and Jacobian columns alike); `None`: no bound beyond
    /// `patience`. When it is reached the fit ends
    /// [`NotConverged`](crate::FitStatus::NotConverged) at the best accepted point.
    pub max_evaluations: Option<usize>,
    /// Wall time after which no new simulation starts (seconds, positive);
    /// the fit ends [`NotConverged`](crate::FitStatus::NotConverged) at the best
    /// accepted point. A simulation under way finishes, so the fit may
    /// overrun by the time of one Jacobian.
    pub max_seconds: Option<f64>,
    /// Relative step of the central finite differences in the internal
    /// parameters, `h = step · max(1, |θ|)` (where they are used).
    pub step: f64,
    /// How the Jacobian is computed; [`Jacobian::Exact`] by default.
    pub jacobian: Jacobian,
    /// Use a second core: the finite-difference columns and several
    /// records' dual passes run in parallel (rayon), and a fit of one
    /// record whose exact Jacobian is one dual pass starts that pass at
    /// each trial point beside its simulation, in rayon's pool (stopped
    /// when the point is rejected; the results are the same bit
    /// for bit, see `speculation`), unless the fit itself runs in rayon's
    /// pool (the starts of a multistart fit).
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
            max_evaluations: None,
            max_seconds: None,
            step: f64::EPSILON.cbrt(),
            jacobian: Jacobian::Exact,
            parallel: true,
            stride: 1,
        }
    }
}

/// How a fit computes its Jacobian `∂r/∂θ`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub enum Jacobian {
    /// Forward-mode derivatives through the model's twin over dual numbers
    /// ([`Derivatives::to_dual`](hysteron_operators::Derivatives::to_dual)): exact to rounding, one simulation per
    /// [`DUAL_WIDTH`](hysteron_operators::DUAL_WIDTH) parameters. A model
    /// without a twin (an operator of your own that does not implement
    /// `to_dual`, as stage 1 of the paper's identification), or one whose
    /// derivatives are not finite at some sample, gets finite differences.
    /// At a kink the derivative is that of the branch the model takes
    /// ([`DualN`](hysteron_operators::DualN)).
    #[default]
    Exact,
    /// Central finite differences, two simulations per parameter
    /// ([`FitOptions::step`]).
    FiniteDifferences,
}

/// Progress of a running fit, passed to the callback of [`fit_with_progress`](crate::fit_with_progress)
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
