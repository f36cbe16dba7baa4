//! The Bouc-Wen hysteretic state equation in the input domain, and its
//! integration over one input step.
//!
//! With `d = sgn(ż)`, travel `s = |Δz|` and the state seen in the direction
//! of motion `g = d·h`, the state equation
//! `dh/dz = α − |h|^n (β sgn(ż h) + γ)` becomes the autonomous scalar ODE
//!
//! `dg/ds = f(g) = α − |g|^n (β sgn(g) + γ)`,
//!
//! the same for both directions. Its solutions are monotone in `s`, so `g`
//! crosses zero at most once per step.
//!
//! * `n = 1`: `f` is linear on each side of zero (`f = α − c g`, with
//!   `c = β + γ` for `g > 0` and `c = β − γ` for `g < 0`), and each branch is
//!   integrated **in closed form**, `g(s) = g + f(g) (1 − e^{−c s}) / c`,
//!   splitting the step exactly where `g` reaches zero.
//! * other `n`: an adaptive **Dormand–Prince 5(4)** Runge–Kutta pair. Each
//!   accepted sub-step has an estimated local error
//!   `≤ rtol · max(|g|, |g_new|, |g_new − g|)`. No sub-step crosses `g = 0`
//!   (where `f` is not smooth and the error estimate fails): sub-steps
//!   approach zero from one side and the state is set to zero once
//!   `|g| ≤ rtol · max(|g_start|, |α| s)`, then integration goes on from
//!   there. The embedded error estimate misjudges long steps (it can
//!   vanish by cancellation), so each sub-step also changes `g` by at most
//!   `max(|g|, g_floor) / (10 max(n − 1, 1))`, a tenth of the distance
//!   over which the solution can blow up (`SubstepCap`); `g_floor` is the
//!   scale `(α/(|β|+|γ|))^{1/n}` of the nonlinearity for integer `n`, and
//!   for non-integer `n`, where `|g|^n` is not analytic at zero, the radius
//!   within which `f` is constant to `rtol`. For non-integer
//!   `n` and `α > 0` the region around zero, `|β ± γ| |g|^n ≤ α/8`, is not
//!   integrated at all but solved by the series of [`NearZero`] (the
//!   travel to reach `g` is a convergent power series in `|g|^n`), so a
//!   zero crossing costs one series inversion instead of ~100 capped
//!   sub-steps. The resulting
//!   global error is measured in this module's tests and the crate's
//!   property tests.
//!
//! The spring uses this integration sample by sample only with
//! `StateSolver::Adaptive` (or outside the tabulated range); by default it
//! integrates the knots of the tabulated flow (`flow_table`) with it, once
//! per parameter set.

use crate::{Error, Float, Result};

/// `|g|^n` evaluated without `powf` for integer and half-integer `n`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Power<T> {
    One,
    Two,
    Int(i32),
    /// `n = k + 1/2`.
    HalfInt(i32),
    Real(T),
}

impl<T: Float> Power<T> {
    pub(crate) fn new(n: T) -> Self {
        let two = T::lit(2.0);
        if n.has_derivatives() {
            // ∂/∂n needs `|g|^n ln |g|`: the general power, even at n = 1.
            Power::Real(n)
        } else if n == T::one() {
            Power::One
        } else if n == two {
            Power::Two
        } else if n.fract() == T::zero() && n <= T::lit(64.0) {
            Power::Int(n.to_i32().unwrap_or(1))
        } else if (n * two).fract() == T::zero() && n <= T::lit(64.0) {
            Power::HalfInt(n.floor().to_i32().unwrap_or(1))
        } else {
            Power::Real(n)
        }
    }

    /// The exponent `n`.
    pub(crate) fn exponent(self) -> T {
        match self {
            Power::One => T::one(),
            Power::Two => T::lit(2.0),
            Power::Int(k) => T::lit(f64::from(k)),
            Power::HalfInt(k) => T::lit(f64::from(k) + 0.5),
            Power::Real(n) => n,
        }
    }

    /// `a^n` for `a ≥ 0`.
    #[inline(always)]
    pub(crate) fn pow(self, a: T) -> T {
        match self {
            Power::One => a,
            Power::Two => a * a,
            Power::Int(k) => a.powi(k),
            // Over dual numbers at a = 0, `√a` has an infinite derivative
            // and `a^{k+½}` (k ≥ 1) a zero one: the product would make it
            // 0·∞ = NaN.
            Power::HalfInt(_) if T::CARRIES_DERIVATIVES && a == T::zero() => T::zero(),
            Power::HalfInt(1) => a * a.sqrt(),
            Power::HalfInt(k) => a.powi(k) * a.sqrt(),
            Power::Real(n) => a.powf(n),
        }
    }
}

/// Shape parameters of the state equation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct StateEquation<T> {
    pub alpha: T,
    pub beta: T,
    pub gamma: T,
    pub power: Power<T>,
    /// Relative local error per adaptive sub-step (`n ≠ 1`).
    pub rtol: T,
    /// The largest change of `g` per adaptive sub-step, cached
    /// ([`StateEquation::substep_cap`]).
    pub cap: Option<SubstepCap<T>>,
    /// The series solution around `g = 0` (non-integer `n`, `α > 0`).
    pub near_zero: Option<NearZero<T>>,
}

/// The largest change of `g` one adaptive sub-step may make:
/// `fraction · max(|g|, floor)` (see [`StateEquation::substep_cap`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SubstepCap<T> {
    pub floor: T,
    pub fraction: T,
}

/// A branch of the `n = 1` state equation from its start `g_a`: on each
/// side of zero `f = α − c g` is linear, so
///
/// `g(s) = g_a + f(g_a) (1 − e^{−c_a s}) / c_a` for `s ≤ s0`, and
/// `g(s) = α (1 − e^{−c_0 (s − s0)}) / c_0` beyond the zero crossing at
/// travel `s0` (`g + f s` where a `c` is 0). Each piece is evaluated as
/// `g∞ − (f/c) e^{−c s}` ([`closed_form`]) with its asymptote
/// `g∞ = g + f/c` (`= α/c`) cached: one `exp`, of shorter latency than
/// `expm1`, which a single step through a series waits for. The absolute
/// rounding error is a few ulps of `max(|g_a|, |g(s)|, α/|β + γ|)`, the
/// state's scale. Only on the lower side, where `|β − γ|` is less than a
/// sixteenth of `|β + γ|`, `|f/c|` would exceed that scale many times
/// (at `β ≈ γ` it loses every digit of a short travel); such a piece is
/// evaluated as `g − (f/c) expm1(−c s)` ([`closed_form_near`]), whose error
/// is a few ulps of `|g_a| + |g(s) − g_a|`. The choice is made once per
/// branch, so it costs the upper side nothing.
///
/// Evaluating every sample from the branch start (not step by step) makes
/// the `n = 1` spring exactly rate-independent: the output at an input does
/// not depend on how many samples led there along the branch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Branch<T> {
    g_a: T,
    f_a: T,
    c_a: T,
    /// `f_a / c_a`, cached.
    fc_a: T,
    /// The asymptote `g_a + f_a / c_a`, cached.
    inf_a: T,
    /// Travel to the zero crossing (`+∞` if the branch does not cross).
    s0: T,
    /// Whether the first piece is on a side whose `|f/c|` is far above the
    /// state's scale, and so is evaluated by [`closed_form_near`].
    near_a: bool,
    f_0: T,
    c_0: T,
    /// `f_0 / c_0` (also the asymptote, from `g = 0`), cached.
    fc_0: T,
}

impl<T: Float> Branch<T> {
    /// Folds the probe slot of every term ([`Hints::fold_probe`](crate::Hints::fold_probe)).
    pub(crate) fn fold_probe(&mut self, along: &T) {
        for v in [
            &mut self.g_a,
            &mut self.f_a,
            &mut self.c_a,
            &mut self.fc_a,
            &mut self.inf_a,
            &mut self.s0,
            &mut self.f_0,
            &mut self.c_0,
            &mut self.fc_0,
        ] {
            v.fold_probe(along);
        }
    }

    /// The branch's values (its terms without their derivatives): over
    /// `f64`, [`at`](Self::at) gives the values of `at` over `T`, bit for
    /// bit.
    pub(crate) fn value(&self) -> Branch<f64> {
        let v = |t: T| t.as_f64();
        Branch {
            g_a: v(self.g_a),
            f_a: v(self.f_a),
            c_a: v(self.c_a),
            fc_a: v(self.fc_a),
            inf_a: v(self.inf_a),
            s0: v(self.s0),
            near_a: self.near_a,
            f_0: v(self.f_0),
            c_0: v(self.c_0),
            fc_0: v(self.fc_0),
        }
    }

    /// The state after travel `s ≥ 0` along the branch.
    #[inline(always)]
    pub(crate) fn at(&self, s: T) -> T {
        if self.s0 < s {
            closed_form(
                T::zero(),
                self.f_0,
                self.c_0,
                self.fc_0,
                self.fc_0,
                s - self.s0,
            )
        } else if self.near_a {
            closed_form_near(self.g_a, self.f_a, self.c_a, self.fc_a, s)
        } else {
            closed_form(self.g_a, self.f_a, self.c_a, self.fc_a, self.inf_a, s)
        }
    }
}

/// The terms of a branch both of whose pieces [`Branch::at`] evaluates in
/// the general form `g∞ − (f/c) e^{−c s}` ([`closed_form`] with `c ≠ 0`),
/// for the lane kernel of the Bouc-Wen spring: `at(s)` is
/// `fc_0 − fc_0 e^{(−c_0)(s − s0)}` where `s0 < s`, else
/// `inf_a − fc_a e^{(−c_a) s}`, the same operations on the same values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ExpForm {
    pub s0: f64,
    pub c_a: f64,
    pub fc_a: f64,
    pub inf_a: f64,
    pub c_0: f64,
    pub fc_0: f64,
}

impl Branch<f64> {
    /// The branch's [`ExpForm`], or `None` where a piece takes another form
    /// (the first evaluated by [`closed_form_near`], or a side with `c = 0`).
    pub(crate) fn exp_form(&self) -> Option<ExpForm> {
        if self.near_a || self.c_a == 0.0 || self.c_0 == 0.0 {
            return None;
        }
        Some(ExpForm {
            s0: self.s0,
            c_a: self.c_a,
            fc_a: self.fc_a,
            inf_a: self.inf_a,
            c_0: self.c_0,
            fc_0: self.fc_0,
        })
    }
}

/// `g + (f/c) (1 − e^{−c s})` as `g∞ − (f/c) e^{−c s}` with
/// `g∞ = g + f/c` (one `exp`, whose latency is shorter than `expm1`'s), or
/// `g + f s` for `c = 0`. Its error is a few ulps of
/// `|g∞| + |f/c| e^{−c s}`.
///
/// Over `f64` the exponential is the branch-free kernel
/// [`crate::exp_kernel::exp`] (within one ulp of the C library's), which
/// the lanes of an ensemble run four or eight at a time with the same
/// bits; over dual numbers its value is the kernel's too
/// ([`crate::exp_kernel::with_kernel_value`]).
#[inline(always)]
fn closed_form<T: Float>(g: T, f: T, c: T, f_over_c: T, asymptote: T, s: T) -> T {
    if c == T::zero() {
        flat_side(g, f, c, s)
    } else {
        asymptote
            - f_over_c
                * crate::exp_kernel::with_kernel_value(-c * s, crate::exp_kernel::exp, T::exp)
    }
}

/// The same as `g − (f/c) expm1(−c s)`, whose error is a few ulps of
/// `|g| + |g(s) − g|` however large `f/c` is (for a side whose decay rate
/// `c` is tiny, see [`Branch`]).
#[inline(always)]
fn closed_form_near<T: Float>(g: T, f: T, c: T, f_over_c: T, s: T) -> T {
    if c == T::zero() {
        flat_side(g, f, c, s)
    } else {
        g - f_over_c * (-c * s).exp_m1()
    }
}

/// `g + f s` on a side with `c = 0`; over dual numbers with `c` carrying
/// derivatives, the first order in `c` of the general form,
/// `g + f s (1 − c s/2)`, so that `∂/∂c` is its limit.
#[inline(always)]
fn flat_side<T: Float>(g: T, f: T, c: T, s: T) -> T {
    if c.has_derivatives() {
        g + f * s * (T::one() - c * s / T::lit(2.0))
    } else {
        g + f * s
    }
}

/// The travel `−g/f` to zero on a side with `c = 0`; over dual numbers
/// with `c` carrying derivatives, the first order in `c` of
/// `−ln(1 + g c/f)/c`: `−g/f + c g²/(2 f²)`.
#[inline(always)]
fn flat_crossing<T: Float>(g: T, f: T, c: T) -> T {
    if c.has_derivatives() {
        -g / f + c * g * g / (T::lit(2.0) * f * f)
    } else {
        -g / f
    }
}

/// The solution of `dg/ds = f(g)` around `g = 0` in closed series form,
/// for non-integer `n` (where `|g|^n` is not analytic at zero and
/// Runge-Kutta error estimates fail) and `α > 0`.
///
/// On each side `f = α − c u^n` with `u = |g|` (`c₊ = β + γ` above zero,
/// `c₋ = γ − β` below), and the travel from `0` to `u` is
///
/// `Φ(u; c) = ∫_0^u du'/(α − c u'^n) = (u/α) Σ_k q^k/(k n + 1)`,
/// `q = c u^n/α`,
///
/// so the position `σ(g) = ±Φ(|g|; c_±)` is the travel from zero, and a
/// step of travel `s` moves `σ` to `σ + s`. The region is `|q| ≤ 1/8`
/// (`f` stays within `α (1 ± 1/8)`, positive), where the series converges
/// geometrically: it is summed until the next term is below `rtol/10`
/// relative (the remainder is at most `q/(1−q) < 0.15` of that term), and
/// `σ ↦ g` is inverted by Newton's method (`Φ' = 1/f`) to `rtol/10`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct NearZero<T> {
    alpha: T,
    power: Power<T>,
    c_pos: T,
    c_neg: T,
    /// The region is `−g_neg ≤ g < g_pos`.
    g_neg: T,
    g_pos: T,
    /// `σ(g_pos)`, where the region ends.
    top: T,
    tol: T,
    /// `1/(k n + 1)`, `k = 0..MAX_TERMS`.
    inv: [T; MAX_TERMS],
}

/// `|q|` at the edge of the [`NearZero`] region.
const Q_MAX: f64 = 0.125;
/// Terms of the series at most (`(1/8)^24 < 1e-21`).
const MAX_TERMS: usize = 24;

impl<T: Float> NearZero<T> {
    fn new(eq: &StateEquation<T>) -> Option<Self> {
        let n = match eq.power {
            Power::HalfInt(k) => T::lit(k as f64 + 0.5),
            Power::Real(n) => n,
            _ => return None,
        };
        if eq.alpha <= T::zero() {
            return None;
        }
        let (c_pos, c_neg) = (eq.beta + eq.gamma, eq.gamma - eq.beta);
        // |c| u^n / α = Q_MAX; unbounded (capped) where c = 0.
        let edge = |c: T| {
            let u = (T::lit(Q_MAX) * eq.alpha / c.abs()).powf(T::one() / n);
            if u.is_finite() {
                u.min(T::lit(1e6))
            } else {
                T::lit(1e6)
            }
        };
        let mut nz = NearZero {
            alpha: eq.alpha,
            power: eq.power,
            c_pos,
            c_neg,
            g_neg: edge(c_neg),
            g_pos: edge(c_pos),
            top: T::zero(),
            tol: eq.rtol * T::lit(0.1),
            inv: core::array::from_fn(|k| T::one() / (T::lit(k as f64) * n + T::one())),
        };
        nz.top = nz.phi(|a| nz.power.pow(a), nz.g_pos, c_pos);
        Some(nz)
    }

    #[inline]
    fn contains(&self, g: T) -> bool {
        g >= -self.g_neg && g < self.g_pos
    }

    /// `Φ(u; c)` for `0 ≤ u` inside the region.
    fn phi(&self, pow: impl Fn(T) -> T, u: T, c: T) -> T {
        let q = c * pow(u) / self.alpha;
        let (mut sum, mut qk) = (T::zero(), T::one());
        for &inv in &self.inv {
            let term = qk * inv;
            sum = sum + term;
            if term.abs() <= self.tol * sum.abs() {
                break;
            }
            qk = qk * q;
        }
        u / self.alpha * sum
    }

    /// `σ(g)`, the signed travel from zero.
    fn position(&self, pow: impl Fn(T) -> T + Copy, g: T) -> T {
        if g < T::zero() {
            -self.phi(pow, -g, self.c_neg)
        } else {
            self.phi(pow, g, self.c_pos)
        }
    }

    /// The state at position `σ` (inside the region).
    fn state_at(&self, pow: impl Fn(T) -> T + Copy, sigma: T) -> T {
        let (c, target, sign) = if sigma < T::zero() {
            (self.c_neg, -sigma, -T::one())
        } else {
            (self.c_pos, sigma, T::one())
        };
        // Newton on Φ(u) = target, Φ' = 1/f, from the first-order guess.
        let mut u = self.alpha * target;
        for _ in 0..16 {
            let f = self.alpha - c * pow(u);
            let next = (u - (self.phi(pow, u, c) - target) * f).max(T::zero());
            let done = (next - u).abs() <= self.tol * next;
            u = next;
            if done {
                break;
            }
        }
        sign * u
    }
}

/// Sub-steps one input step may take before the integration gives up
/// (only reached by a state that diverges).
const MAX_SUBSTEPS: usize = 100_000;

impl<T: Float> StateEquation<T> {
    /// The state equation with shape `α, β, γ, n` and tolerance `rtol`.
    pub(crate) fn new(alpha: T, beta: T, gamma: T, n: T, rtol: T) -> Self {
        Self::with_power(alpha, beta, gamma, Power::new(n), rtol)
    }

    /// [`new`](Self::new) with `|g|^n` computed as `power` says (the
    /// general power at `n = 1`, for a table whose derivatives include
    /// `∂/∂n`).
    pub(crate) fn with_power(alpha: T, beta: T, gamma: T, power: Power<T>, rtol: T) -> Self {
        let mut eq = StateEquation {
            alpha,
            beta,
            gamma,
            power,
            rtol,
            cap: None,
            near_zero: None,
        };
        eq.cap = eq.substep_cap();
        eq.near_zero = NearZero::new(&eq);
        eq
    }

    /// `f(g) = α − |g|^n (β sgn(g) + γ)`.
    #[inline(always)]
    pub(crate) fn rate(&self, g: T) -> T {
        let c = if g < T::zero() {
            self.gamma - self.beta
        } else {
            self.beta + self.gamma
        };
        self.alpha - self.power.pow(g.abs()) * c
    }

    /// Advances `g` over travel `s ≥ 0`.
    #[inline]
    pub(crate) fn advance(&self, g: T, s: T) -> Result<T> {
        let mut step = s;
        self.advance_from(g, s, &mut step)
    }

    /// [`advance`](Self::advance), trying `step` as the first sub-step of
    /// the adaptive integration (the whole travel where `step ≥ s`; `step ≤
    /// 0`: the whole travel) and leaving there, when the travel ends on an
    /// accepted Dormand–Prince sub-step, the size proposed for it before it
    /// was cut to the travel left (unchanged when it ends in the series
    /// around zero or on a final Euler step): for a run of consecutive
    /// travels (the flow table's knots), whose restarts then cost few
    /// rejected sub-steps. The result is within the tolerance whatever
    /// `step` is.
    pub(crate) fn advance_from(&self, g: T, s: T, step: &mut T) -> Result<T> {
        if s == T::zero() {
            // (over dual numbers, a travel of 0 that carries derivatives
            // moves g by the rate: dg/ds = f(g))
            return Ok(if s.has_derivatives() {
                g + s * self.rate(g)
            } else {
                g
            });
        }
        let g = match self.power {
            Power::One => self.advance_linear(g, s),
            _ => self.advance_adaptive(g, s, step)?,
        };
        if g.is_finite() {
            Ok(g)
        } else {
            Err(Error::NonFiniteOutput {
                operator: "bouc_wen",
                input: s.as_f64(),
            })
        }
    }

    /// The sub-step cap for `n ≠ 1` (`None` for `n = 1`, integrated in
    /// closed form). Each sub-step changes `g` by at most
    /// `max(|g|, g_floor) / (10 max(n − 1, 1))`: a tenth of the distance
    /// over which the solution of `dg/ds = α + |c| |g|^n` can blow up from
    /// `g` (`~ |g| / (n − 1)` for large `|g|`), so that every sub-step stays
    /// where the embedded error estimate follows its `h⁵` model. Beyond
    /// that distance the estimate can vanish by cancellation: seen for
    /// `n = 2` at `rtol = 1e-9`, an estimate of 4.4e-10 for a true error of
    /// 2.2e-6 on a step changing `g` by 27 %. The floor is
    /// * for integer `n`, the scale `g* = (|α| / (|β| + |γ|))^{1/n}` at which
    ///   the nonlinearity matters (`f` is a polynomial on each side of 0);
    /// * for non-integer `n`, the radius `(rtol |α| / (|β| + |γ|))^{1/n}` of
    ///   the core around `g = 0` in which `f` differs from `α` by at most
    ///   `rtol |α|` (`|g|^n` is not analytic at 0).
    fn substep_cap(&self) -> Option<SubstepCap<T>> {
        let c = self.beta.abs() + self.gamma.abs();
        let (n, relative) = match self.power {
            Power::One => return None,
            Power::Two => (T::lit(2.0), T::one()),
            Power::Int(k) => (T::lit(f64::from(k)), T::one()),
            Power::HalfInt(k) => (T::lit(f64::from(k) + 0.5), self.rtol),
            Power::Real(n) => (n, self.rtol),
        };
        let floor = (relative * self.alpha.abs() / c).powf(T::one() / n);
        if floor == T::infinity() {
            // β = γ = 0: f = α is constant, every step is exact.
            return None;
        }
        Some(SubstepCap {
            floor: if floor > T::zero() {
                floor
            } else {
                T::min_positive_value()
            },
            fraction: T::lit(0.1) / (n - T::one()).max(T::one()),
        })
    }

    /// For `n = 1`: the branch of solutions starting at `g_a` (travel 0),
    /// with its zero crossing precomputed, so that every point of the branch
    /// is one closed-form evaluation from the branch's start (see
    /// [`Branch::at`]).
    pub(crate) fn branch(&self, g_a: T) -> Branch<T> {
        let zero = T::zero();
        let f_a = self.rate(g_a);
        let c_a = self.side_coefficient(g_a, f_a);
        let toward_zero = (g_a > zero && f_a < zero) || (g_a < zero && f_a > zero);
        let mut s0 = T::infinity();
        if toward_zero {
            // g(s0) = 0  ⇔  e^{−c s0} = 1 + g c / f  (s0 = −g/f for c = 0).
            let s = if c_a == zero {
                flat_crossing(g_a, f_a, c_a)
            } else {
                -(g_a * c_a / f_a).ln_1p() / c_a
            };
            if s.is_finite() {
                s0 = s;
            }
        }
        let c_0 = self.side_coefficient(zero, self.alpha);
        // the lower side (`c_a` is not the upper side's `c_0`) with a decay
        // rate far below the upper side's
        let near_a = c_a != c_0 && c_a.abs() * T::lit(16.0) < c_0.abs();
        Branch {
            g_a,
            f_a,
            c_a,
            fc_a: f_a / c_a,
            inf_a: g_a + f_a / c_a,
            s0,
            near_a,
            f_0: self.alpha,
            c_0,
            fc_0: self.alpha / c_0,
        }
    }

    /// `β + γ` on the upper side (`g > 0`, or `g = 0` moving up), else
    /// `β − γ`: the decay rate of `f` there for `n = 1`.
    #[inline(always)]
    fn side_coefficient(&self, g: T, f: T) -> T {
        if g > T::zero() || (g == T::zero() && f > T::zero()) {
            self.beta + self.gamma
        } else {
            self.beta - self.gamma
        }
    }

    /// Closed form for `n = 1`: exact on each side of zero, with the step
    /// split where `g` reaches zero.
    fn advance_linear(&self, mut g: T, mut s: T) -> T {
        let zero = T::zero();
        // At most one zero crossing per step (solutions are monotone).
        for _ in 0..2 {
            let f = self.rate(g);
            let upper = g > zero || (g == zero && f > zero);
            let c = if upper {
                self.beta + self.gamma
            } else {
                self.beta - self.gamma
            };
            let toward_zero = (g > zero && f < zero) || (g < zero && f > zero);
            if toward_zero {
                // g(s0) = 0  ⇔  e^{−c s0} = 1 + g c / f  (s0 = −g/f for c = 0).
                let s0 = if c == zero {
                    flat_crossing(g, f, c)
                } else {
                    -(g * c / f).ln_1p() / c
                };
                if s0.is_finite() && s0 < s {
                    g = zero;
                    s = s - s0;
                    continue;
                }
            }
            // Stay on this side: g + f (1 − e^{−c s}) / c  (g + f s for c = 0).
            return if c == zero {
                flat_side(g, f, c, s)
            } else {
                g - f * (-c * s).exp_m1() / c
            };
        }
        g
    }

    /// Dormand–Prince 5(4) with step-size control.
    fn advance_adaptive(&self, g: T, s: T, step: &mut T) -> Result<T> {
        // One instantiation per kind of power, so the hot loop evaluates
        // |g|^n one way only (matching the enum inside the loop let the
        // compiler evaluate the `powf` arm speculatively at every call).
        match self.power {
            Power::One => self.integrate(|a| a, g, s, step),
            Power::Two => self.integrate(|a| a * a, g, s, step),
            Power::Int(k) => self.integrate(move |a: T| a.powi(k), g, s, step),
            Power::HalfInt(1) => self.integrate(|a: T| a * a.sqrt(), g, s, step),
            Power::HalfInt(k) => self.integrate(move |a: T| a.powi(k) * a.sqrt(), g, s, step),
            Power::Real(n) => self.integrate(move |a: T| a.powf(n), g, s, step),
        }
    }

    /// `f(g)` with `|g|^n` computed by `pow`.
    #[inline(always)]
    fn rate_with(&self, pow: impl Fn(T) -> T, g: T) -> T {
        let c = if g < T::zero() {
            self.gamma - self.beta
        } else {
            self.beta + self.gamma
        };
        self.alpha - pow(g.abs()) * c
    }

    /// [`advance_adaptive`](Self::advance_adaptive) with `|g|^n = pow(|g|)`.
    #[inline(always)]
    fn integrate(&self, pow: impl Fn(T) -> T + Copy, mut g: T, s: T, step: &mut T) -> Result<T> {
        let l = T::lit;
        let mut t = T::zero();
        let mut h = if *step > T::zero() { *step } else { s };
        let mut k1 = self.rate_with(pow, g);
        // |g| below which a state about to cross zero is set to zero.
        let snap = (self.rtol * g.abs().max(self.alpha.abs() * s)).max(T::min_positive_value());
        // Travel left below this (rounding noise of the sum of sub-steps, or
        // a subnormal step) is finished with one Euler step, error O(h²).
        let done = (s * T::epsilon() * l(4.0)).max(T::min_positive_value());
        let cap = self.cap;
        for _ in 0..MAX_SUBSTEPS {
            if let Some(nz) = &self.near_zero {
                if nz.contains(g) {
                    // Around zero, where |g|^n is not analytic: the series
                    // solution, to the end of the step or out of the region.
                    let target = nz.position(pow, g) + (s - t);
                    if target <= nz.top {
                        return Ok(nz.state_at(pow, target));
                    }
                    t = t + (nz.top - nz.position(pow, g));
                    g = nz.g_pos;
                    k1 = self.rate_with(pow, g);
                    h = (s - t).min(h);
                    continue;
                }
            }
            if s - t <= done {
                return Ok(g + (s - t) * self.rate_with(pow, g));
            }
            if let Some(cap) = cap {
                // The embedded estimate can miss the error by orders of
                // magnitude on long steps (seen: estimate 9e-11, error
                // 1.8e-6 for a step changing g by 40 % at n = 2.3;
                // estimate 4.4e-10, error 2.2e-6 changing g by 27 % at
                // n = 2): keep each sub-step's change of g within the cap.
                let h_max = cap.fraction * g.abs().max(cap.floor) / k1.abs();
                if h_max.is_finite() && h > h_max {
                    h = h_max;
                }
            }
            h = h.max(done);
            let proposed = h;
            let last = h >= s - t;
            if last {
                h = s - t;
            }
            let k2 = self.rate_with(pow, g + h * l(1.0 / 5.0) * k1);
            let k3 = self.rate_with(pow, g + h * (l(3.0 / 40.0) * k1 + l(9.0 / 40.0) * k2));
            let k4 = self.rate_with(
                pow,
                g + h * (l(44.0 / 45.0) * k1 - l(56.0 / 15.0) * k2 + l(32.0 / 9.0) * k3),
            );
            let k5 = self.rate_with(
                pow,
                g + h
                    * (l(19372.0 / 6561.0) * k1 - l(25360.0 / 2187.0) * k2
                        + l(64448.0 / 6561.0) * k3
                        - l(212.0 / 729.0) * k4),
            );
            let k6 = self.rate_with(
                pow,
                g + h
                    * (l(9017.0 / 3168.0) * k1 - l(355.0 / 33.0) * k2
                        + l(46732.0 / 5247.0) * k3
                        + l(49.0 / 176.0) * k4
                        - l(5103.0 / 18656.0) * k5),
            );
            let g5 = g + h
                * (l(35.0 / 384.0) * k1 + l(500.0 / 1113.0) * k3 + l(125.0 / 192.0) * k4
                    - l(2187.0 / 6784.0) * k5
                    + l(11.0 / 84.0) * k6);
            let k7 = self.rate_with(pow, g5);
            let err = (h
                * (l(71.0 / 57600.0) * k1 - l(71.0 / 16695.0) * k3 + l(71.0 / 1920.0) * k4
                    - l(17253.0 / 339200.0) * k5
                    + l(22.0 / 525.0) * k6
                    - l(1.0 / 40.0) * k7))
                .abs();
            if g != T::zero() && g5 != T::zero() && (g5 < T::zero()) != (g < T::zero()) {
                // The step crosses g = 0, where f is not smooth and the
                // error estimate is unreliable: approach zero from this
                // side (each try lands about 90 % of the way), then snap to
                // zero once |g| is below the tolerance, and go on from
                // there on the other side.
                let approach = h * (l(0.9) * g / (g - g5)).max(l(1e-3));
                if g.abs() <= snap || approach <= done {
                    // Close enough (or too close to step any closer).
                    if T::CARRIES_DERIVATIVES && k1 != T::zero() {
                        // The crossing is where g reaches 0, at travel
                        // t − g/f: its derivatives carry −g'/f into t.
                        t = t - (g - g.without_derivatives()) / k1.without_derivatives();
                    }
                    g = T::zero();
                    k1 = self.rate_with(pow, g);
                } else {
                    h = approach;
                }
                continue;
            }
            if !g5.is_finite() || !err.is_finite() {
                // Shrink and retry; a state that truly diverges ends in the
                // sub-step limit or a non-finite result below.
                if h <= T::min_positive_value() * l(1e6) {
                    return Ok(T::infinity());
                }
                h = h * l(0.1);
                continue;
            }
            let scale =
                self.rtol * g.abs().max(g5.abs()).max((g5 - g).abs()) + T::min_positive_value();
            if err <= scale {
                g = g5;
                k1 = k7;
                if last {
                    *step = proposed;
                    return Ok(g);
                }
                t = t + h;
            }
            let factor = if err == T::zero() {
                l(5.0)
            } else {
                // (scale/err)^{1/4}: a little bolder than the textbook
                // 1/5, without a `powf` per sub-step.
                (l(0.9) * (scale / err).sqrt().sqrt())
                    .max(l(0.2))
                    .min(l(5.0))
            };
            h = h * factor;
        }
        Err(Error::NotConverged {
            solver: "bouc_wen state integration",
            iterations: MAX_SUBSTEPS,
            width: (s - t).as_f64(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eq(n: f64, alpha: f64, beta: f64, gamma: f64) -> StateEquation<f64> {
        StateEquation::new(alpha, beta, gamma, n, 1e-10)
    }

    /// `e.advance(g0, s)` is `want(g0, s)` to `1e-8 max(|want|, 1e-3)` at
    /// every start `g0` and travel `s` of the grids.
    fn assert_advance_matches(
        e: &StateEquation<f64>,
        g0s: &[f64],
        ss: &[f64],
        want: impl Fn(f64, f64) -> f64,
    ) {
        for &g0 in g0s {
            for &s in ss {
                let (got, want) = (e.advance(g0, s).unwrap(), want(g0, s));
                assert!(
                    (got - want).abs() <= 1e-8 * want.abs().max(1e-3),
                    "g0={g0} s={s}: {got} vs {want}"
                );
            }
        }
    }

    #[test]
    fn power_special_cases_match_powf() {
        for n in [1.0, 2.0, 3.0, 1.5, 2.5, 1.37] {
            let p = Power::new(n);
            for a in [0.0, 0.3, 1.0, 2.7] {
                let want = f64::powf(a, n);
                assert!(
                    (p.pow(a) - want).abs() <= 1e-14 * want.max(1.0),
                    "n={n} a={a}"
                );
            }
        }
        assert_eq!(Power::new(1.5), Power::HalfInt(1));
        assert_eq!(Power::new(3.0), Power::Int(3));
    }

    /// The adaptive integrator, run with n = 1 forced through the general
    /// path, against the closed form (both signs, crossing zero).
    #[test]
    fn adaptive_matches_closed_form_for_n1() {
        let closed = eq(1.0, 1.0, 0.7, 0.3);
        let mut general = closed;
        general.power = Power::Real(1.0);
        general.cap = general.substep_cap();
        // The series around zero too (n = 1 through the general path).
        general.near_zero = NearZero::new(&general);
        assert!(general.near_zero.is_some());
        assert_advance_matches(
            &general,
            &[-1.2, -0.5, 0.0, 0.4, 0.99, 1.3],
            &[1e-6, 0.01, 0.3, 1.0, 5.0],
            |g0, s| closed.advance(g0, s).unwrap(),
        );
    }

    /// n = 2 on the positive side has the closed form
    /// g(s) = √(α/c) tanh(√(αc) s + atanh(g0 √(c/α))).
    #[test]
    fn adaptive_matches_tanh_for_n2() {
        let (alpha, c) = (1.5, 0.8);
        let e = eq(2.0, alpha, 0.5, 0.3);
        let a = (alpha / c).sqrt();
        assert_advance_matches(
            &e,
            &[0.0, 0.2, 1.0, 1.3],
            &[1e-4, 0.05, 0.5, 3.0],
            |g0, s| a * ((alpha * c).sqrt() * s + (g0 / a).atanh()).tanh(),
        );
    }

    /// Regression (CI, proptest `bouc_wen_tabulated_flow_matches_adaptive_
    /// integration`): one long step on the growing side, where
    /// `dg/ds = α + k g²` (`g < 0`, `k = β − γ`) has the closed form
    /// `g(s) = √(α/k) tan(√(αk) s + atan(g0 √(k/α)))`. Taken as one
    /// Dormand–Prince step, the embedded estimate cancels to 4.4e-10 while
    /// the true error is 2.2e-6; the sub-step cap keeps it to `rtol`.
    #[test]
    fn adaptive_long_step_matches_tan_for_n2() {
        let (alpha, beta, gamma) = (1.3027467079698523, 0.4694917399574505, -0.2611225388262552);
        let k: f64 = beta - gamma;
        let a = (alpha / k).sqrt();
        let (g0, s) = (-1.39417721911889, 0.16148263444860822);
        let want = a * ((alpha * k).sqrt() * s + (g0 / a).atan()).tan();
        for rtol in [1e-6, 1e-9, 1e-12] {
            let e = StateEquation::new(alpha, beta, gamma, 2.0, rtol);
            let got = e.advance(g0, s).unwrap();
            let err = (got - want).abs() / want.abs();
            assert!(err <= rtol, "rtol {rtol:e}: relative error {err:e}");
        }
    }

    #[test]
    fn closed_form_n1_crossing_is_continuous_in_s() {
        // From g0 < 0 the state crosses zero; the closed form must be
        // continuous across the crossing point.
        let e = eq(1.0, 1.0, 0.6, 0.2);
        let g0 = -0.8;
        let c = 0.6 - 0.2; // lower side: g' = α − c g
        let s0 = ((1.0 - c * g0) / 1.0f64).ln() / c; // where g reaches 0
        let before = e.advance(g0, s0 - 1e-9).unwrap();
        let after = e.advance(g0, s0 + 1e-9).unwrap();
        assert!(before < 0.0 && after > 0.0 && (after - before) < 1e-8);
    }

    /// The branch's `g∞ − (f/c) e^{−c s}` against the step's
    /// `g − (f/c) expm1(−c s)` (each side, crossing zero, softening and
    /// hardening sides, travel from 1e-12 to 20): they differ by at most a
    /// few ulps of the state's scale `max(|g_a|, |g∞|, |g(s)|)`.
    #[test]
    fn branch_matches_expm1_form_to_ulps_of_the_state_scale() {
        let mut worst = 0.0_f64;
        for (alpha, beta, gamma) in [(1.0, 0.6, 0.2), (2.5, 1.5, 1.5), (1.0, 0.3, -0.5)] {
            let e = eq(1.0, alpha, beta, gamma);
            let bound = alpha / (beta + gamma);
            for g_a in [-1.3, -0.4, -1e-9, 0.0, 1e-9, 0.2, 0.999, 1.7].map(|f| f * bound) {
                let b = e.branch(g_a);
                for s in [1e-12, 1e-6, 0.01, 0.3, 1.0, 4.0, 20.0] {
                    let (got, want) = (b.at(s), e.advance_linear(g_a, s));
                    if !want.is_finite() || want.abs() > 1e6 {
                        continue; // the hardening side, blown up
                    }
                    let scale = g_a
                        .abs()
                        .max(want.abs())
                        .max(b.inf_a.abs())
                        .max(b.fc_0.abs());
                    worst = worst.max((got - want).abs() / (f64::EPSILON * scale));
                }
            }
        }
        assert!(worst <= 4.0, "{worst} ulps of the state scale");
    }

    /// Where `β ≈ γ` the lower side's decay rate `c = β − γ` is tiny and
    /// `f/c` huge: the branch still agrees with the step's `expm1` form to
    /// a few ulps of the state's scale, `|g_a| + |g(s) − g_a|` or the
    /// saturation state `α/(β + γ)` if larger (the asymptotic form alone
    /// was up to 5·10¹⁰ ulps off).
    #[test]
    fn branch_keeps_the_states_digits_where_the_decay_rate_is_tiny() {
        let mut worst = 0.0_f64;
        for gamma_minus_beta in [8e-8, -8e-8, 1e-12, 1e-4] {
            let e = eq(1.0, 2.055, 0.05, 0.05 + gamma_minus_beta);
            for g_a in [-20.5, -5.0, -0.1, 0.0, 3.0] {
                let b = e.branch(g_a);
                for s in [1e-9, 1e-3, 0.03, 0.5, 2.0, 9.0, 30.0] {
                    let (got, want) = (b.at(s), e.advance_linear(g_a, s));
                    let scale =
                        (g_a.abs() + (want - g_a).abs()).max(2.055 / (0.1 + gamma_minus_beta));
                    worst = worst.max((got - want).abs() / (f64::EPSILON * scale));
                }
            }
        }
        assert!(worst <= 8.0, "{worst} ulps of the state's scale");
    }

    #[test]
    fn diverging_state_is_an_error_not_nan() {
        // Hardening set β + γ < 0 with n = 2 blows up in finite travel.
        let e = eq(2.0, 1.0, -1.0, -1.0);
        assert!(e.advance(1.0, 10.0).is_err());
        let e1 = eq(1.0, 1.0, -400.0, -400.0);
        assert!(e1.advance(1.0, 10.0).is_err());
    }
}
