//! Energy per closed loop: the work `∮ y dx` of an operator's steady
//! response to a sine.
//!
//! With `x` a displacement and `y` the force the operator answers with,
//! `W = ∮ y dx` over one steady cycle is the work the input does on the
//! operator per loop, i.e. the energy it dissipates. Its magnitude is the
//! area of the hysteresis loop; its sign is the loop's orientation:
//! **clockwise loops** (the branch traversed with `dx > 0` lies above the
//! one traversed back: stop, elastic-plastic, MMS friction, Bouc-Wen
//! springs of the bounded class) give `W ≥ 0`; a **play** (backlash) lags
//! its input (its rising branch `y = x − r` lies below the falling one), so
//! its loop, and that of a PI bank of plays with positive weights, runs
//! counterclockwise and `∮ y dx ≤ 0`. Since `∮ d(xy) = 0`,
//! `∮ x dy = −∮ y dx` is then the non-negative dissipation of the dual
//! pairing (the play's input as a force, its output as a displacement).
//!
//! **Quadrature.** [`loop_energy`] drives the operator like
//! [`describing_function`](crate::describing::describing_function) (same
//! settling and steadiness check, [`SteadyCycle`]) and applies the
//! trapezoid rule to the closed polygon of the last period's samples,
//!
//! `W ≈ Σ_n (y_n + y_{n+1})/2 · (x_{n+1} − x_n)`  (indices mod `N`).
//!
//! The samples include the reversal points `±A` exactly. On a segment
//! between two samples where `y(x)` is linear the rule is exact; where `y`
//! is smooth its error is `−Δx³ y''/12` (so `O(N⁻²)` in total); a kink of
//! `y(x)` inside a segment (a play starting to move at `x = A − 2r`, not a
//! sample in general) with a slope jump `s` costs at most `|s| Δx²/8`.
//! For a PI bank this gives
//! `|W_trap − W| ≤ Σ_j 2 |w_j| Δx_max²/8`, `Δx_max = A · 2 sin(π/N)`,
//! and `W_trap` is exact up to rounding when every kink is a sample.

use crate::describing::{AnalysisError, SineOptions, SteadyCycle};
use hysteron_composition::PiBankParams;
use hysteron_operators::Operator;

/// The loop work of one steady cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct LoopEnergy {
    /// The input amplitude `A`.
    pub amplitude: f64,
    /// `W = ∮ y dx` by the trapezoid rule (see the
    /// [module documentation](self) for the sign).
    pub work: f64,
    /// The steadiness measure of the cycle ([`SteadyCycle::change`]).
    pub change: f64,
}

impl LoopEnergy {
    /// The loop area `|∮ y dx|`: the energy dissipated per loop whatever
    /// the loop's orientation (for a play-type PI bank with positive
    /// weights, `Σ_{r_j < A} 4 w_j r_j (A − r_j)`).
    pub fn area(&self) -> f64 {
        self.work.abs()
    }
}

/// `∮ y dx` around the closed polygon through the points `(x_i, y_i)` (the
/// last joined to the first), by the trapezoid rule: the signed work of a
/// recorded loop (negative counterclockwise). Samples past the shorter of
/// `x` and `y` are left out.
///
/// ```
/// use hysteron_models::energy::closed_loop_work;
/// // the unit square, counterclockwise: −1
/// assert_eq!(closed_loop_work(&[0.0, 1.0, 1.0, 0.0], &[0.0, 0.0, 1.0, 1.0]), -1.0);
/// ```
pub fn closed_loop_work(x: &[f64], y: &[f64]) -> f64 {
    let points = x.iter().zip(y);
    points
        .clone()
        .zip(points.cycle().skip(1))
        .map(|((xi, yi), (xj, yj))| 0.5 * (yi + yj) * (xj - xi))
        .sum()
}

impl SteadyCycle {
    /// `∮ y dx` over the cycle by the trapezoid rule on its closed polygon
    /// ([`closed_loop_work`]).
    pub fn loop_work(&self) -> f64 {
        closed_loop_work(&self.x, &self.y)
    }

    /// The [`LoopEnergy`] of the cycle.
    pub fn loop_energy(&self) -> LoopEnergy {
        LoopEnergy {
            amplitude: self.amplitude,
            work: self.loop_work(),
            change: self.change,
        }
    }
}

/// The work per loop `∮ y dx` of `op` driven by `A sin θ` in steady state
/// (see the [module documentation](self)).
///
/// ```
/// use hysteron_models::describing::SineOptions;
/// use hysteron_models::energy::loop_energy;
/// use hysteron_operators::Stop;
/// // a stop's loop is a parallelogram of height 2r and width 2(A − r),
/// // clockwise: 4 r (A − r), to the trapezoid rule's error at the two kinks
/// // between samples, ≤ 2 Δx²/8 with Δx ≤ 2A sin(π/1024) (9.4e-6)
/// let e = loop_energy(&Stop::new(0.25_f64).unwrap(), 1.0, &SineOptions::default()).unwrap();
/// assert!((e.work - 4.0 * 0.25 * (1.0 - 0.25)).abs() < 1e-5);
/// ```
pub fn loop_energy<O: Operator<f64> + Clone>(
    op: &O,
    amplitude: f64,
    opts: &SineOptions,
) -> Result<LoopEnergy, AnalysisError> {
    Ok(SteadyCycle::compute(op, amplitude, opts)?.loop_energy())
}

/// The exact loop work of a play-type PI bank (`y = a0 x + Σ w_j
/// play_{r_j}[x]`) driven between `±A`:
///
/// `∮ y dx = −Σ_{r_j < A} 4 w_j r_j (A − r_j)`.
///
/// Each play's steady loop is a parallelogram with horizontal sides of
/// length `2 r_j` at `y = ±(A − r_j)` and sides `y = x ∓ r_j`: area
/// `2 r_j · 2 (A − r_j)`, traversed counterclockwise (hence the sign); the
/// linear term and the plays with `r_j ≥ A` (constant in steady state)
/// enclose nothing. The initial states do not matter (wiped out by the
/// first extremum).
pub fn pi_bank_loop_work(p: &PiBankParams<f64>, amplitude: f64) -> f64 {
    -p.r.iter()
        .zip(&p.w)
        .filter(|(&r, _)| r < amplitude)
        .map(|(&r, &w)| 4.0 * w * r * (amplitude - r))
        .sum::<f64>()
}

/// The steady loop of a Bouc-Wen spring with `n = 1` and constant
/// stiffness, from [`bouc_wen_n1_loop`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoucWenLoop {
    /// The hysteretic state at the reversal points: `h(±A) = ±h_m`.
    pub h_turn: f64,
    /// The input travel from the reversal `−A` to the zero crossing of `h`.
    pub d1: f64,
    /// `∮ h dz`.
    pub h_area: f64,
    /// `∮ H dz = (1 − w) k ∮ h dz`.
    pub work: f64,
}

/// The closed-form steady loop of the Bouc-Wen spring
/// (`H = w k z + (1 − w) k h`, constant stiffness `k`) for `n = 1`, driven
/// between `±A`, in the bounded class `α > 0`, `a = β + γ > 0`,
/// `b = β − γ ≥ 0`.
///
/// In the input domain, `dh/dz = α − |h| (β sgn(ż h) + γ)`; on the
/// increasing branch that is `α − b h` while `h < 0` and `α − a h` while
/// `h ≥ 0` (the decreasing branch is its point reflection). Starting the
/// branch at the reversal `(−A, −h_m)`:
///
/// * `h < 0`: `h = α/b − (h_m + α/b) e^{−b s}` (`s` the travel), zero after
///   `d1 = ln(1 + b h_m/α) / b` (`h_m/α` for `b = 0`);
/// * `h ≥ 0`: `h = (α/a)(1 − e^{−a (s − d1)})`, which must reach `h_m` at
///   `s = 2A`.
///
/// So the turning value solves the fixed-point equation
///
/// `h_m = (α/a) (1 − e^{−2aA} (1 + b h_m/α)^{a/b})`,
///
/// whose right side decreases in `h_m`: a unique root in `(0, α/a)`,
/// found by bisection to the last bit. For `γ = 0` (`a = b = β`) it is
/// explicit: `β h_m/α = tanh(βA)`. Integrating the two exponential
/// pieces, `∫_{−A}^{A} h_up dz = (α d1 − h_m)/b + (α (2A − d1) − h_m)/a`
/// (the first term `−h_m²/(2α)` for `b = 0`), and as the decreasing branch
/// is the reflection, `∮ h dz = 2 ∫_{−A}^{A} h_up dz`. The elastic term
/// encloses nothing: `∮ H dz = (1 − w) k ∮ h dz`, `> 0` (clockwise).
///
/// Errors: `A`, `k` not finite and `> 0`, `w ∉ [0, 1]`, or parameters
/// outside the bounded class ([`AnalysisError::InvalidArgument`]).
///
/// ```
/// use hysteron_models::energy::bouc_wen_n1_loop;
/// // γ = 0: h_m = (α/β) tanh(βA), ∮ H dz = 4 (1−w) k α (A − tanh(βA)/β) / β
/// let l = bouc_wen_n1_loop(1.0, 0.8, 0.0, 0.3, 2.0, 1.5).unwrap();
/// let hm = (0.8_f64 * 1.5).tanh() / 0.8;
/// assert!((l.h_turn - hm).abs() < 1e-15);
/// let w = 4.0 * 0.7 * 2.0 * (1.5 - (0.8_f64 * 1.5).tanh() / 0.8) / 0.8;
/// assert!((l.work - w).abs() < 1e-14 * w);
/// ```
pub fn bouc_wen_n1_loop(
    alpha: f64,
    beta: f64,
    gamma: f64,
    w: f64,
    k: f64,
    amplitude: f64,
) -> Result<BoucWenLoop, AnalysisError> {
    let bad = |name, value, reason| {
        Err(AnalysisError::InvalidArgument {
            name,
            value,
            reason,
        })
    };
    if !(amplitude.is_finite() && amplitude > 0.0) {
        return bad("amplitude", amplitude, "must be finite and > 0");
    }
    if !(k.is_finite() && k > 0.0) {
        return bad("k", k, "must be finite and > 0");
    }
    if !(0.0..=1.0).contains(&w) {
        return bad("w", w, "must lie in [0, 1]");
    }
    if !(alpha.is_finite() && alpha > 0.0) {
        return bad("alpha", alpha, "must be finite and > 0 (bounded class)");
    }
    let (a, b) = (beta + gamma, beta - gamma);
    if !(beta.is_finite() && gamma.is_finite() && a > 0.0 && b >= 0.0) {
        return bad(
            "beta",
            beta,
            "needs β + γ > 0 and β − γ ≥ 0 (bounded class)",
        );
    }
    // travel from the reversal to h = 0
    let d1 = |h: f64| {
        if b == 0.0 {
            h / alpha
        } else {
            (b * h / alpha).ln_1p() / b
        }
    };
    let rhs = |h: f64| -(alpha / a) * (-a * (2.0 * amplitude - d1(h))).exp_m1();
    let (mut lo, mut hi) = (0.0_f64, alpha / a);
    loop {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if rhs(mid) - mid > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let h = if (rhs(lo) - lo).abs() <= (rhs(hi) - hi).abs() {
        lo
    } else {
        hi
    };
    let d = d1(h);
    // (α d1 − h)/b = (α/b²)(ln(1+u) − u), u = b h/α; a series for small u
    // (no cancellation), 10 terms: error < u¹⁰ ≤ 1e-20 relative.
    let u = b * h / alpha;
    let first = if u < 1e-2 {
        let mut sum = 0.0;
        let mut pow = 1.0;
        for j in 2..12 {
            let sign = if j % 2 == 0 { -1.0 } else { 1.0 };
            sum += sign * pow / j as f64;
            pow *= u;
        }
        h * h / alpha * sum
    } else {
        (alpha * d - h) / b
    };
    let second = (alpha * (2.0 * amplitude - d) - h) / a;
    let h_area = 2.0 * (first + second);
    Ok(BoucWenLoop {
        h_turn: h,
        d1: d,
        h_area,
        work: (1.0 - w) * k * h_area,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `SteadyCycle`'s fields are public: a `y` shorter than `x` was
    /// indexed past its end (a panic).
    #[test]
    fn loop_work_of_unequal_lengths() {
        let square = |y: Vec<f64>| SteadyCycle {
            amplitude: 1.0,
            x: vec![0.0, 1.0, 1.0, 0.0],
            y,
            change: 0.0,
            periods: 1,
        };
        // the unit square, counterclockwise in (x, y): ∮ y dx = −1
        assert_eq!(square(vec![0.0, 0.0, 1.0, 1.0]).loop_work(), -1.0);
        let _ = square(vec![0.0, 0.0]).loop_work();
        assert_eq!(square(vec![]).loop_work(), 0.0);
    }
}
