//! The flow of the Bouc-Wen state equation (for `n ≠ 1`, and for `n = 1`
//! held as a general power where `∂/∂n` is wanted), tabulated once per
//! parameter set, so that each sample is one polynomial evaluation.
//!
//! In the direction frame the state equation is the autonomous ODE
//! `dg/ds = f(g) = α − |g|^n (β sgn(g) + γ)` (see `hysteretic_state`). Its
//! solutions are the level sets of the **position**
//!
//! `σ(g) = ∫_0^g dg'/f(g')`,
//!
//! the travel from `g = 0` to `g`: a step of travel `s` moves the position
//! from `σ` to `σ + s`, so the state after travel `s` from the branch start
//! `g_a` is `G(σ(g_a) + s)`, with `G` the inverse of `σ`. Each side of zero
//! is a scalar ODE `du/dτ = α − c u^n` from `u(0) = 0` (`u = |g|`,
//! `τ = |σ|`): `c₊ = β + γ` above zero and, below zero, `c₋ = γ − β`
//! (travel runs backwards there, towards zero).
//!
//! [`FlowTable`] holds `u(τ)` of both sides as piecewise quintic Hermite
//! polynomials (values, first and second derivatives `u' = f(u)`,
//! `u'' = f'(u) f(u)` exact at the knots). The knot values are integrated
//! at a tolerance a thousand times tighter than the table's (`rtol/1000`,
//! at least `64 ε`): by the Taylor series of `u` at the piece's start,
//! summed until its terms fall below that tolerance (its coefficients come
//! from a recurrence, with one `pow` per knot), and where the series does
//! not settle (the first pieces from `u = 0`, where `u^n` is not analytic)
//! by the adaptive Dormand–Prince scheme, six `pow` calls a sub-step. Each
//! interval is accepted only when the polynomial matches that integration
//! at three interior points (`θ = 1/4, 1/2, 3/4`) to `rtol/4` relative,
//! and halved otherwise. The series' stopping rule (two consecutive terms
//! below the tolerance) is the usual estimate of its remainder, not a
//! bound; the test `taylor_pieces_match_the_adaptive_integration` measures
//! it. Around `g = 0`, where `|g|^n` is not analytic (`u(τ)` has a
//! `τ^{n+1}` term), the checks grade the knots geometrically. Interpolation
//! error of a quintic Hermite piece is `O(Δ^6 u⁽⁶⁾)`, so checking interior
//! points bounds it in practice (not rigorously; the tests measure it
//! against closed forms and the tight integration).
//!
//! The upper side saturates at `u* = (α/c₊)^{1/n}`. Beyond the last knot,
//! where `v = u* − u ≤ v_T`, the tail is the linearised decay
//! `u = u* − v_T e^{−λ(τ − τ_T)}`, `λ = c₊ n u*^{n−1}`. The neglected
//! quadratic term of `v' = −λ v + a v² + …` (`a = −f''(u*)/2`) changes `v`
//! by at most `(a/λ) v_T²` relative to `v_T`, so `v_T` is chosen with
//! `(a/λ) v_T² ≤ rtol u*/8` and `v_T ≤ u* √rtol`, and the tail is checked
//! like an interval.
//!
//! A growing side (`c ≤ 0`: the lower side for `β ≥ γ`, and the upper one
//! too for hardening sets `β + γ ≤ 0`) has no end: it is tabulated first up
//! to a scale (`u*`, or where `|c| u^n = α`) and extended piece by piece
//! when a state or a travel beyond it is asked for. Each piece depends only
//! on the one before, so the pieces do not depend on the order of the
//! requests. Each piece's travel is capped at half the travel to the
//! blow-up, `(u + scale)/(2 max(n − 1, 1) f(u))`; past the blow-up there is
//! no state (the step-by-step integration reports the divergence).
//!
//! Tabulated: `α > 0`, `β ≥ γ` (the lower side does not saturate), `n ≤ 64`,
//! `rtol ≥ 6400 ε` (so the knots can be integrated a hundred times more
//! accurately), states up to `u*` above zero where the upper side
//! saturates, any state reached otherwise. Other parameter sets and states
//! are integrated step by step (see `BoucWen`).
//!
//! Each thread keeps the last [`RECENT`] tables it built, keyed by the bits
//! of `(α, β, γ, n, rtol)`, and hands out copies of them: a fit simulates a
//! parameter set and then takes its derivatives there, which tabulates the
//! same flow again for the derivative tables (`flow_sensitivity`). A table
//! depends on nothing but those five numbers, and a copy is extended on
//! demand exactly as the original would be (see above), so the memo changes
//! no result, only the time.

use crate::hysteretic_state::{Power, StateEquation};
use crate::Float;
use std::any::{Any, TypeId};
use std::cell::RefCell;
use std::collections::VecDeque;

/// Knots per side at most; a parameter set needing more is not tabulated.
const MAX_PIECES: usize = 4096;

/// Terms of the Taylor series a piece is integrated by at most (see
/// [`Builder::taylor`]).
const TAYLOR_TERMS: usize = 24;

/// `1/k` for `k < TAYLOR_TERMS` (`1/0` unused).
// Evaluated at compile time: an index out of range would fail the build.
#[allow(clippy::indexing_slicing)]
const INVERSES: [f64; TAYLOR_TERMS] = {
    let mut v = [0.0; TAYLOR_TERMS];
    let mut k = 1;
    while k < TAYLOR_TERMS {
        v[k] = 1.0 / k as f64;
        k += 1;
    }
    v
};

/// Tables each thread keeps of those it built last (see the module).
const RECENT: usize = 4;

/// A table built before: its scalar type, the bits of `(α, β, γ, n, rtol)`,
/// and the table as built (not extended).
type Remembered = (TypeId, [u64; 5], Box<dyn Any>);

thread_local! {
    static RECENT_TABLES: RefCell<VecDeque<Remembered>> =
        const { RefCell::new(VecDeque::new()) };
}

/// Integrations of a candidate piece that may fail (run into the blow-up
/// beyond a growing side's end) per side before the side is given up:
/// each failure costs the integrator's whole sub-step budget.
const MAX_FAILURES: usize = 8;

/// The largest tabulated exponent (as for the integer powers of
/// `hysteretic_state`); a fit's trial step can reach absurd exponents
/// (`n ~ 1e16` seen), whose state equation is a step function.
const MAX_N: f64 = 64.0;

/// One quintic Hermite piece on `[τ_k, τ_k + Δ]`, in `θ = (τ − τ_k)/Δ`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Piece<T> {
    /// `τ_k`.
    pub start: T,
    inv_width: T,
    /// Coefficients in `θ`; `b[0]` is the value at `τ_k`.
    pub b: [T; 6],
}

impl<T: Float> Piece<T> {
    /// The quintic with values `u`, slopes `d1` and second derivatives
    /// `d2` at both ends of an interval of width `w`.
    pub(crate) fn hermite(start: T, w: T, left: [T; 3], right: [T; 3]) -> Self {
        let l = T::lit;
        let [u0, d0, e0] = left;
        let [u1, d1, e1] = right;
        let (a0, a1, a2) = (u0, d0 * w, e0 * w * w * l(0.5));
        let r = u1 - (a0 + a1 + a2);
        let s = d1 * w - (a1 + l(2.0) * a2);
        let q = e1 * w * w - l(2.0) * a2;
        Piece {
            start,
            inv_width: T::one() / w,
            b: [
                a0,
                a1,
                a2,
                l(10.0) * r - l(4.0) * s + l(0.5) * q,
                l(-15.0) * r + l(7.0) * s - q,
                l(6.0) * r - l(3.0) * s + l(0.5) * q,
            ],
        }
    }

    #[inline(always)]
    pub(crate) fn eval(&self, tau: T) -> T {
        let t = (tau - self.start) * self.inv_width;
        let b = &self.b;
        b[0] + t * (b[1] + t * (b[2] + t * (b[3] + t * (b[4] + t * b[5]))))
    }

    /// `1/Δ`, the piece's inverse width.
    pub(crate) fn inv_width(&self) -> T {
        self.inv_width
    }

    /// `du/dτ` of the piece.
    fn slope(&self, tau: T) -> T {
        let l = T::lit;
        let t = (tau - self.start) * self.inv_width;
        let b = &self.b;
        (b[1] + t * (l(2.0) * b[2] + t * (l(3.0) * b[3] + t * (l(4.0) * b[4] + t * l(5.0) * b[5]))))
            * self.inv_width
    }
}

/// The saturating tail `u = u* − v_T e^{−λ(τ − τ_T)}` beyond the last knot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Tail<T> {
    pub u_star: T,
    pub v_t: T,
    lambda: T,
}

/// `u(τ)` on one side of zero: `du/dτ = α − c u^n`, `u(0) = 0`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Side<T> {
    pieces: Vec<Piece<T>>,
    /// `τ` and `u` at the end of the last piece.
    end: T,
    u_end: T,
    tail: Option<Tail<T>>,
    /// A growing side's builder, to extend it on demand (`None` for a
    /// saturating side, and once the side cannot grow further).
    grow: Option<Box<Builder<T>>>,
}

impl<T: Float> Side<T> {
    /// The pieces, in `τ`.
    pub(crate) fn pieces(&self) -> &[Piece<T>] {
        &self.pieces
    }

    /// `τ` at the end of the last piece.
    pub(crate) fn end(&self) -> T {
        self.end
    }

    /// `u` at the end of the last piece.
    pub(crate) fn u_end(&self) -> T {
        self.u_end
    }

    /// The saturating tail beyond the last piece, if the side has one.
    pub(crate) fn tail(&self) -> Option<Tail<T>> {
        self.tail
    }

    /// The piece holding `τ ≥ 0` (`None` beyond the last piece), searched
    /// from `hint` forwards and backwards one piece, then by bisection.
    // Hot path, kept free of extra checks: `holds(j)` is called only for
    // `j < p.len()`, and looks at `p[j + 1]` only when `j + 1 < p.len()`.
    #[allow(clippy::indexing_slicing)]
    #[inline(always)]
    pub(crate) fn locate(&self, tau: T, hint: &mut usize) -> Option<usize> {
        let p = &self.pieces;
        // Piece j covers [start_j, start_{j+1}), the last one [start, end].
        let holds = |j: usize| {
            p[j].start <= tau
                && if j + 1 < p.len() {
                    tau < p[j + 1].start
                } else {
                    tau <= self.end
                }
        };
        let k = *hint;
        for j in [k, k.wrapping_add(1), k.wrapping_sub(1)] {
            if j < p.len() && holds(j) {
                *hint = j;
                return Some(j);
            }
        }
        if tau > self.end || tau.is_nan() {
            return None;
        }
        let j = p.partition_point(|q| q.start <= tau).max(1) - 1;
        if j >= p.len() {
            return None; // no pieces
        }
        *hint = j;
        Some(j)
    }

    /// `u(τ)` for `τ ≥ 0` (`None` beyond the tabulated range of a side
    /// without a tail).
    // `locate` returns only indices `< self.pieces.len()`.
    #[allow(clippy::indexing_slicing)]
    #[inline(always)]
    fn at(&self, tau: T, hint: &mut usize) -> Option<T> {
        match self.locate(tau, hint) {
            Some(k) => Some(self.pieces[k].eval(tau)),
            None => self
                .tail
                .map(|t| t.u_star - t.v_t * (-(t.lambda * (tau - self.end))).exp()),
        }
    }

    /// Extends a growing side until it reaches `u ≥ u_min` and `τ ≥ tau_min`;
    /// `false` where it cannot (a saturating side, the blow-up, or the
    /// piece limit; a side that could not grow once is not tried again).
    fn extend(&mut self, u_min: T, tau_min: T) -> bool {
        let Some(b) = self.grow.as_mut() else {
            return false;
        };
        while b.left[0] < u_min || b.tau < tau_min {
            match b.next_piece() {
                Some(piece) => self.pieces.push(piece),
                None => {
                    self.grow = None;
                    return false;
                }
            }
            self.end = b.tau;
            self.u_end = b.left[0];
        }
        true
    }

    /// `τ(u)`, the inverse of [`at`](Self::at), for `0 ≤ u` within the
    /// side's range (`None` outside); the piece found is left in `hint`,
    /// where the lookups along the branch that starts there begin (and the
    /// piece in `hint`, and the one after it, are tried first).
    fn position(&self, u: T, hint: &mut usize) -> Option<T> {
        if u <= T::zero() {
            return (u == T::zero()).then_some(T::zero());
        }
        if u > self.u_end {
            let t = self.tail?;
            if u > t.u_star {
                return None;
            }
            if u == t.u_star {
                return Some(T::infinity());
            }
            return Some(self.end + (t.v_t / (t.u_star - u)).ln() / t.lambda);
        }
        // The pieces are increasing: the last piece starting at or below u
        // (0 < u ≤ u_end here).
        let p = &self.pieces;
        let holds = |j: usize| {
            p.get(j).is_some_and(|q| q.b[0] <= u) && p.get(j + 1).is_none_or(|next| u < next.b[0])
        };
        let next = hint.wrapping_add(1);
        let k = if holds(*hint) {
            *hint
        } else if holds(next) {
            next
        } else {
            p.partition_point(|q| q.b[0] <= u)
                .max(1)
                .min(p.len())
                .checked_sub(1)?
        };
        *hint = k;
        let piece = self.pieces.get(k)?;
        let hi = self.pieces.get(k + 1).map_or(self.end, |q| q.start);
        // Newton on the piece, kept inside it, from the secant guess.
        let (lo, u_lo, u_hi) = (piece.start, piece.b[0], piece.eval(hi));
        let mut tau = if u_hi > u_lo {
            lo + (hi - lo) * (u - u_lo) / (u_hi - u_lo)
        } else {
            lo
        };
        for _ in 0..8 {
            let d = piece.slope(tau);
            if d <= T::zero() {
                break;
            }
            let next = (tau - (piece.eval(tau) - u) / d).max(lo).min(hi);
            let done = (next - tau).abs() <= T::epsilon() * T::lit(4.0) * next.abs();
            tau = next;
            if done {
                break;
            }
        }
        Some(tau)
    }
}

/// The tabulated flow of the state equation: `g = G(σ)` and its inverse
/// `σ(g)` for `−u* ≤ g ≤ u*` (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FlowTable<T> {
    upper: Side<T>,
    lower: Side<T>,
}

/// Hints of the last pieces used, so samples moving along a branch find
/// their piece in one comparison.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Hint {
    upper: usize,
    lower: usize,
}

/// Hints are a cache: lookups give the same piece whatever the hint, so
/// two springs that differ only in their hints are equal.
impl PartialEq for Hint {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl<T: Float> FlowTable<T> {
    /// The table of `eq`'s flow, or `None` where the parameter set is not
    /// tabulated (`α ≤ 0`, `β < γ`, `n = 1` held as [`Power::One`] (closed
    /// form), `n > 64`, or a table that would
    /// need more than 4096 pieces per side).
    ///
    /// A copy of the table this thread built last for the same `α, β, γ,
    /// n, rtol`, where it keeps one (see the module).
    pub(crate) fn new(eq: &StateEquation<T>) -> Option<Self> {
        if eq.power == Power::One {
            return None;
        }
        if T::CARRIES_DERIVATIVES {
            // (the key holds values only; no such table is built)
            return Self::build(eq);
        }
        let key = [eq.alpha, eq.beta, eq.gamma, eq.power.exponent(), eq.rtol]
            .map(|v| v.as_f64().to_bits());
        let id = TypeId::of::<T>();
        let known = RECENT_TABLES.with(|recent| {
            let recent = recent.borrow();
            recent
                .iter()
                .find(|(t, k, _)| *t == id && *k == key)
                .and_then(|(_, _, table)| table.downcast_ref::<Self>().cloned())
        });
        if known.is_some() {
            return known;
        }
        let table = Self::build(eq)?;
        RECENT_TABLES.with(|recent| {
            let mut recent = recent.borrow_mut();
            if recent.len() == RECENT {
                recent.pop_front();
            }
            recent.push_back((id, key, Box::new(table.clone())));
        });
        Some(table)
    }

    /// Tabulates `eq`'s flow (see [`new`](Self::new)).
    fn build(eq: &StateEquation<T>) -> Option<Self> {
        let n = eq.power.exponent();
        if n > T::lit(MAX_N) {
            return None;
        }
        let (alpha, c_up, c_low) = (eq.alpha, eq.beta + eq.gamma, eq.gamma - eq.beta);
        // The lower side must not saturate (a state beyond its equilibrium
        // would run away from zero).
        if !(alpha > T::zero() && c_low <= T::zero()) {
            return None;
        }
        let (upper, reach) = if c_up > T::zero() {
            let upper = saturating_side(alpha, c_up, n, eq.rtol)?;
            // A margin below −u*, for states rounded just beyond it.
            let reach = upper.tail.map(|t| t.u_star)? * T::lit(1.001);
            (upper, reach)
        } else {
            // Hardening: both sides grow; first up to where |c| u^n = α.
            let reach = if c_up < T::zero() {
                (alpha / -c_up).powf(T::one() / n)
            } else {
                T::one()
            };
            (growing_side(alpha, c_up, n, eq.rtol, reach)?, reach)
        };
        let lower = growing_side(alpha, c_low, n, eq.rtol, reach)?;
        Some(FlowTable { upper, lower })
    }

    /// The position `σ(g)`, or `None` for a state outside the table; the
    /// piece is looked for first at `hint` and left there (the same
    /// position whatever the hint).
    pub(crate) fn position(&self, g: T, hint: &mut Hint) -> Option<T> {
        if g < T::zero() {
            self.lower.position(-g, &mut hint.lower).map(|t| -t)
        } else {
            self.upper.position(g, &mut hint.upper)
        }
    }

    /// The piece that [`state_at`](Self::state_at) evaluates at `σ`, in
    /// `τ = |σ|` on the side of `σ`'s sign (`G(σ) = ±piece.eval(τ)`, `−`
    /// below zero), with the end of the `τ` it holds and whether that end
    /// is its own (the side's last piece: `τ ≤ end`; else `τ < end`);
    /// `None` where `state_at` finds no piece (the tail beyond the last
    /// knot, or outside the table). `hint` as for `state_at`.
    pub(crate) fn piece_at(&self, sigma: T, hint: &mut Hint) -> Option<(Piece<T>, T, bool)> {
        let (side, tau, k) = if sigma < T::zero() {
            (&self.lower, -sigma, &mut hint.lower)
        } else {
            (&self.upper, sigma, &mut hint.upper)
        };
        let k = side.locate(tau, k)?;
        let piece = *side.pieces.get(k)?;
        Some(match side.pieces.get(k + 1) {
            Some(next) => (piece, next.start, false),
            None => (piece, side.end, true),
        })
    }

    /// The state `G(σ)` at position `σ`, or `None` below the table.
    #[inline(always)]
    pub(crate) fn state_at(&self, sigma: T, hint: &mut Hint) -> Option<T> {
        if sigma < T::zero() {
            self.lower.at(-sigma, &mut hint.lower).map(|u| -u)
        } else {
            self.upper.at(sigma, &mut hint.upper)
        }
    }

    /// [`position`](Self::position), a growing side extended first to
    /// hold `g` (on demand, so hardening springs need no range up front);
    /// `hint` as for [`state_at`](Self::state_at), left at the piece found.
    pub(crate) fn position_growing(&mut self, g: T, hint: &mut Hint) -> Option<T> {
        let side = if g < T::zero() {
            &mut self.lower
        } else {
            &mut self.upper
        };
        if g.abs() > side.u_end {
            side.extend(g.abs(), T::zero());
        }
        self.position(g, hint)
    }

    /// [`state_at`](Self::state_at), a growing side extended first to reach
    /// `σ`.
    #[inline(always)]
    pub(crate) fn state_at_growing(&mut self, sigma: T, hint: &mut Hint) -> Option<T> {
        let (side, tau) = if sigma < T::zero() {
            (&mut self.lower, -sigma)
        } else {
            (&mut self.upper, sigma)
        };
        if tau > side.end {
            side.extend(T::zero(), tau);
        }
        self.state_at(sigma, hint)
    }

    /// The side above zero (`σ ≥ 0`, `u = g`).
    pub(crate) fn upper(&self) -> &Side<T> {
        &self.upper
    }

    /// The side below zero (`σ < 0`, `u = −g`).
    pub(crate) fn lower(&self) -> &Side<T> {
        &self.lower
    }

    /// Pieces of the upper and the lower side.
    #[cfg(test)]
    pub(crate) fn pieces(&self) -> (usize, usize) {
        (self.upper.pieces.len(), self.lower.pieces.len())
    }
}

/// Makes the pieces of one side, one after the other: each piece depends
/// only on the one before it, so a side extended in several steps has the
/// same pieces as one built in one go.
#[derive(Debug, Clone, PartialEq)]
struct Builder<T> {
    /// The side's equation in the frame `u ≥ 0` (rate `α − c u^n`), at the
    /// knots' tolerance.
    eq: StateEquation<T>,
    alpha: T,
    c: T,
    n: T,
    /// Relative error allowed at the checked interior points.
    tol: T,
    /// For a growing side (`c < 0`): each piece's travel stays below half
    /// the travel to the blow-up, `(u + scale)/(2 max(n − 1, 1) f(u))`.
    scale: T,
    /// `τ` and the jet `[u, u', u'']` at the end of the last piece.
    tau: T,
    left: [T; 3],
    /// `u^n` there.
    left_pow: T,
    /// The width to try next.
    w: T,
    /// The integrator's sub-step to try first in the next piece (0: none
    /// yet).
    step: T,
    failures: usize,
    pieces: usize,
}

impl<T: Float> Builder<T> {
    /// A builder for `du/dτ = α − c u^n` from `u(0) = 0` at tolerance
    /// `rtol`, with a first width `w0`; `None` where `rtol < 6400 ε`.
    fn new(alpha: T, c: T, n: T, rtol: T, w0: T) -> Option<Self> {
        let l = T::lit;
        let fine = (rtol * l(1e-3)).max(T::epsilon() * l(64.0));
        if fine > rtol * l(0.01) {
            // The knots could not be integrated well below the table's
            // tolerance (rtol < 6400 ε).
            return None;
        }
        let mut b = Builder {
            eq: StateEquation::new(alpha, T::zero(), c, n, fine),
            alpha,
            c,
            n,
            tol: rtol * l(0.25),
            scale: (alpha / c.abs()).powf(T::one() / n),
            tau: T::zero(),
            left: [T::zero(); 3],
            left_pow: T::zero(),
            w: w0,
            step: T::zero(),
            failures: 0,
            pieces: 0,
        };
        (b.left, b.left_pow) = b.jet(T::zero());
        Some(b)
    }

    /// `[u, u', u'']` with `u' = f(u)`, `u'' = f'(u) f(u)`, and `u^n`.
    fn jet(&self, u: T) -> ([T; 3], T) {
        let (c, n) = (self.c, self.n);
        let p = u.powf(n);
        let f = self.alpha - c * p;
        // f'(u) = −c n u^{n−1} (0 at u = 0 for n > 1).
        let d = if u > T::zero() {
            -c * n * (p / u)
        } else {
            T::zero()
        };
        ([u, f, d * f], p)
    }

    /// The Taylor series of `u` at the left knot, scaled to the width `w`:
    /// the coefficients `a_k = u_k w^k`, so that `u(τ + θ w) = Σ a_k θ^k`,
    /// and how many of them to sum for `0 ≤ θ ≤ 1`; `None` where the series
    /// does not settle within [`TAYLOR_TERMS`] terms (near `u = 0`, where
    /// `u^n` is not analytic, and near a growing side's blow-up).
    ///
    /// With `W_k` the scaled coefficients of `u^n`, the equation
    /// `u' = α − c u^n` gives `a_{k+1} = w (δ_{k0} α − c W_k)/(k + 1)`, and
    /// `p = u^n` obeys `u p' = n p u'`, whose coefficients give
    /// `W_k = Σ_{j=1}^{k} ((n + 1) j − k) a_j W_{k−j} / (k a_0)`: no `pow`
    /// beyond the knot's own `u^n`. The sum stops once two consecutive
    /// terms together are below half the knots' tolerance, `rtol_fine u/2`.
    fn taylor(&self, w: T, a: &mut [T; TAYLOR_TERMS]) -> Option<usize> {
        let l = T::lit;
        let u = self.left[0];
        if !(u > T::zero() && w.is_finite()) {
            return None;
        }
        let tol = self.eq.rtol * u * l(0.5);
        let mut p = [T::zero(); TAYLOR_TERMS];
        *a = [T::zero(); TAYLOR_TERMS];
        a[0] = u;
        p[0] = self.left_pow;
        a[1] = w * self.left[1];
        let (n1, inv_u) = (self.n + T::one(), T::one() / u);
        for k in 1..TAYLOR_TERMS - 1 {
            let kf = l(k as f64);
            let mut s = T::zero();
            for (j, (aj, pkj)) in a.iter().zip(p.iter().take(k + 1).rev()).enumerate().skip(1) {
                s = s + (n1 * l(j as f64) - kf) * *aj * *pkj;
            }
            let inv = INVERSES.get(k).copied().unwrap_or(f64::NAN);
            let inv_next = INVERSES.get(k + 1).copied().unwrap_or(f64::NAN);
            let pk = s * inv_u * l(inv);
            let next = -(self.c * pk) * w * l(inv_next);
            if let (Some(slot_p), Some(slot_a)) = (p.get_mut(k), a.get_mut(k + 1)) {
                *slot_p = pk;
                *slot_a = next;
            }
            let last = a.get(k).copied().unwrap_or(T::zero());
            if k >= 3 && last.abs() + next.abs() <= tol {
                return next.is_finite().then_some(k + 2);
            }
        }
        None
    }

    /// The next piece, or `None` where none can be made (too many pieces
    /// or failed integrations, or widths that collapse).
    fn next_piece(&mut self) -> Option<Piece<T>> {
        let l = T::lit;
        loop {
            let (tau, left) = (self.tau, self.left);
            let mut w = self.w;
            if self.pieces >= MAX_PIECES
                || w.is_nan()
                || w <= T::epsilon() * tau.max(T::one()) * l(16.0)
            {
                return None;
            }
            if self.c < T::zero() {
                let cap =
                    l(0.5) * (left[0] + self.scale) / (self.n - T::one()).max(T::one()) / left[1];
                w = w.min(cap);
            }
            // A piece whose integration fails counts as failing its check.
            // The interior points and the end: the series at the left knot
            // (Horner, highest term first), or integrated one quarter after
            // the other (the flow composes: u(τ + a + b) is u(τ + a)
            // advanced by b), so a piece costs one integration of its width.
            let mut worst = T::infinity();
            let (mut right, mut right_pow) = (left, self.left_pow);
            let mut step = self.step;
            let mut a = [T::zero(); TAYLOR_TERMS];
            let quarters = match self.taylor(w, &mut a) {
                Some(terms) => {
                    let at = |theta: f64| {
                        a.iter()
                            .take(terms)
                            .rev()
                            .fold(T::zero(), |s, &c| s * l(theta) + c)
                    };
                    Ok(([at(0.25), at(0.5), at(0.75)], at(1.0)))
                }
                None => (1..=4).try_fold(([T::zero(); 3], left[0]), |(mut at, u), q| {
                    let next = self.eq.advance_from(u, w * l(0.25), &mut step)?;
                    if let Some(slot) = at.get_mut(q - 1) {
                        *slot = next;
                    }
                    Ok::<_, crate::Error>((at, next))
                }),
            };
            match quarters {
                Ok((interior, u1)) => {
                    (right, right_pow) = self.jet(u1);
                    let piece = Piece::hermite(tau, w, left, right);
                    worst = T::zero();
                    for (want, theta) in interior.into_iter().zip([0.25, 0.5, 0.75]) {
                        let err = (piece.eval(tau + w * l(theta)) - want).abs() / want.abs();
                        worst = worst.max(err);
                    }
                }
                Err(_) => {
                    self.failures += 1;
                    if self.failures > MAX_FAILURES {
                        return None;
                    }
                }
            }
            if worst.is_nan() || worst > self.tol {
                self.w = w * l(0.5);
                continue;
            }
            self.tau = tau + w;
            self.left = right;
            self.left_pow = right_pow;
            self.step = step;
            self.pieces += 1;
            // Grow by at most 2, by the sixth-order error model.
            let grow = if worst == T::zero() {
                l(2.0)
            } else {
                (l(0.8) * (self.tol / worst).powf(l(1.0 / 6.0))).min(l(2.0))
            };
            self.w = w * grow.max(l(0.5));
            return Some(Piece::hermite(tau, w, left, right));
        }
    }
}

/// Tabulates the saturating side `du/dτ = α − c u^n`, `c > 0`, from
/// `u(0) = 0` up to `u* − v_T`, `u* = (α/c)^{1/n}`, then the tail.
fn saturating_side<T: Float>(alpha: T, c: T, n: T, rtol: T) -> Option<Side<T>> {
    let l = T::lit;
    let u_star = (alpha / c).powf(T::one() / n);
    if !(u_star.is_finite() && u_star > T::zero()) {
        return None;
    }
    // (a/λ) v_T² ≤ rtol u*/8 with a/λ = (n − 1)/(2 u*), and v_T ≤ u* √rtol
    // (for n near 1, where the tail of the derivatives' table neglects a
    // term ∝ v² that does not vanish with n − 1).
    let v_t = u_star * (rtol / (l(4.0) * (n - T::one())).max(T::one())).sqrt();
    let target = u_star - v_t;
    let mut b = Builder::new(alpha, c, n, rtol, target / alpha * l(1e-3))?;
    let mut pieces = Vec::new();
    while b.left[0] < target {
        pieces.push(b.next_piece()?);
    }
    let u_end = b.left[0];
    let tail = Tail {
        u_star,
        v_t: u_star - u_end,
        lambda: c * n * u_star.powf(n - T::one()),
    };
    // Checked like a piece, out to where v is 1e-3 of v_T.
    let span = l(1e-3).ln().abs() / tail.lambda;
    for theta in [0.05, 0.2, 0.5, 1.0] {
        let s = span * l(theta);
        let want = b.eq.advance(u_end, s).ok()?;
        let got = u_star - tail.v_t * (-(tail.lambda * s)).exp();
        let err = (got - want).abs();
        if err.is_nan() || err > rtol * u_star {
            return None;
        }
    }
    Some(Side {
        pieces,
        end: b.tau,
        u_end,
        tail: Some(tail),
        grow: None,
    })
}

/// Tabulates the growing side `du/dτ = α − c u^n`, `c ≤ 0` (which blows up
/// in finite travel for `c < 0`, `n > 1`), from `u(0) = 0` to at least
/// `reach`; [`Side::extend`] goes on from there on demand.
fn growing_side<T: Float>(alpha: T, c: T, n: T, rtol: T, reach: T) -> Option<Side<T>> {
    let b = Builder::new(alpha, c, n, rtol, reach / alpha * T::lit(1e-3))?;
    let mut side = Side {
        pieces: Vec::new(),
        end: T::zero(),
        u_end: T::zero(),
        tail: None,
        grow: Some(Box::new(b)),
    };
    side.extend(reach, T::zero()).then_some(side)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(alpha: f64, beta: f64, gamma: f64, n: f64, rtol: f64) -> FlowTable<f64> {
        FlowTable::new(&StateEquation::new(alpha, beta, gamma, n, rtol)).unwrap()
    }

    /// n = 2 has closed forms on both sides: above zero
    /// `u = √(α/c) tanh(√(αc) τ)`, below zero (c < 0)
    /// `u = √(α/|c|) tan(√(α|c|) τ)`.
    #[test]
    fn n2_table_matches_tanh_and_tan() {
        let (alpha, beta, gamma) = (1.5, 0.6, 0.2);
        for rtol in [1e-6, 1e-10] {
            let t = table(alpha, beta, gamma, 2.0, rtol);
            let (cu, cl) = (beta + gamma, beta - gamma);
            let u_star = (alpha / cu).sqrt();
            let mut hint = Hint::default();
            let mut worst = 0.0f64;
            for i in 0..=4000 {
                let tau = i as f64 * 2e-3;
                let up = u_star * ((alpha * cu).sqrt() * tau).tanh();
                let got = t.state_at(tau, &mut hint).unwrap();
                worst = worst.max((got - up).abs() / u_star);
                let arg = (alpha * cl).sqrt() * tau;
                let down = (alpha / cl).sqrt() * arg.tan();
                if arg < std::f64::consts::FRAC_PI_2 && down <= u_star {
                    let got = -t.state_at(-tau, &mut hint).unwrap();
                    worst = worst.max((got - down).abs() / u_star);
                }
            }
            println!(
                "n = 2, rtol {rtol:e}: max error {worst:.2e} of u*; pieces {:?}",
                t.pieces()
            );
            assert!(worst <= rtol, "rtol {rtol}: {worst}");
        }
    }

    /// Non-integer n: the table against the tight adaptive integration of
    /// the same state equation, over whole branches from both saturations.
    #[test]
    fn table_matches_tight_integration() {
        for (n, beta, gamma) in [
            (1.5, 0.7, 0.3),
            (2.7, 0.5, 0.5),
            (1.1, 0.9, -0.2),
            (6.0, 0.4, 0.3),
        ] {
            let rtol = 1e-10;
            let t = table(1.0, beta, gamma, n, rtol);
            let fine = StateEquation::new(1.0, beta, gamma, n, 1e-13);
            let u_star = (1.0 / (beta + gamma)).powf(1.0 / n);
            let mut worst = 0.0f64;
            for g_a in [-u_star, -0.5 * u_star, -1e-4, 0.0, 0.3 * u_star] {
                let sigma_a = t.position(g_a, &mut Hint::default()).unwrap();
                let mut hint = Hint::default();
                let (mut g, mut s_prev) = (g_a, 0.0);
                for i in 1..=600 {
                    let s = i as f64 * 0.01;
                    g = fine.advance(g, s - s_prev).unwrap();
                    s_prev = s;
                    let got = t.state_at(sigma_a + s, &mut hint).unwrap();
                    worst = worst.max((got - g).abs() / u_star);
                }
            }
            println!(
                "n = {n}: max error {worst:.2e} of u*; pieces {:?}",
                t.pieces()
            );
            assert!(worst <= 2.0 * rtol, "n = {n}: {worst}");
        }
    }

    /// The pieces' Taylor series (`Builder::taylor`) against the adaptive
    /// integration at the knots' tolerance, on saturating and growing
    /// sides: the series is used for nearly every piece, and its values at
    /// the quarters agree with the integration to the knots' tolerance.
    #[test]
    fn taylor_pieces_match_the_adaptive_integration() {
        for (n, c, rtol) in [
            (1.5, 1.0f64, 1e-10),
            (1.02, 1.0, 1e-10),
            (2.0, 0.8, 1e-8),
            (2.7, 1.0, 1e-10),
            (6.0, 0.7, 1e-10),
            (1.5, -1.0, 1e-10),
            (3.0, -0.4, 1e-10),
        ] {
            let u_stop = if c > 0.0 { 0.999 } else { 3.0 } * (1.0 / c.abs()).powf(1.0 / n);
            let mut b = Builder::new(1.0, c, n, rtol, 1e-4).unwrap();
            let (mut series, mut pieces, mut worst) = (0, 0, 0.0f64);
            while b.left[0] < u_stop && pieces < 1000 {
                let w = b.w;
                let mut a = [0.0; TAYLOR_TERMS];
                if let Some(terms) = b.taylor(w, &mut a) {
                    series += 1;
                    for theta in [0.25, 0.5, 0.75, 1.0] {
                        let sum: f64 = a.iter().take(terms).rev().fold(0.0, |s, &c| s * theta + c);
                        let want = b.eq.advance(b.left[0], theta * w).unwrap();
                        worst = worst.max((sum - want).abs() / want);
                    }
                }
                b.next_piece().unwrap();
                pieces += 1;
            }
            let fine = b.eq.rtol;
            println!(
                "n = {n}, c = {c}: {series} of {pieces} pieces by the series, \
                 worst {worst:.2e} (knots' tolerance {fine:.0e})"
            );
            assert!(
                series * 10 >= pieces * 9,
                "n = {n}, c = {c}: {series}/{pieces}"
            );
            assert!(worst <= 4.0 * fine, "n = {n}, c = {c}: {worst}");
        }
    }

    #[test]
    fn position_inverts_the_state() {
        let t = table(1.0, 0.7, 0.3, 1.5, 1e-10);
        let mut hint = Hint::default();
        for g in [-1.0, -0.73, -1e-3, -1e-9, 0.0, 1e-9, 0.2, 0.9, 0.99999, 1.0] {
            let sigma = t.position(g, &mut Hint::default()).unwrap();
            let back = t.state_at(sigma, &mut hint).unwrap();
            assert!(
                (back - g).abs() <= 8.0 * f64::EPSILON * g.abs(),
                "g = {g}: {back}"
            );
        }
        // Beyond saturation above; far beyond the lower side's range.
        assert_eq!(t.position(1.0 + 1e-9, &mut Hint::default()), None);
        assert_eq!(t.position(-10.0, &mut Hint::default()), None);
    }

    /// The hint only speeds the lookup up: every hint gives the same bits,
    /// at knots, between them and beyond the last one.
    #[test]
    fn lookups_do_not_depend_on_the_hint() {
        let t = table(1.0, 0.7, 0.3, 1.5, 1e-10);
        let side = &t.upper;
        let mut taus: Vec<f64> = side.pieces.iter().map(|p| p.start).collect();
        taus.extend(side.pieces.iter().map(|p| p.start * 1.0001 + 1e-9));
        taus.extend([side.end, side.end * 1.01, 0.0, 1e-12]);
        for &tau in &taus {
            let want = side.at(tau, &mut 0).unwrap().to_bits();
            for hint in [
                0,
                1,
                7,
                side.pieces.len() - 1,
                side.pieces.len(),
                usize::MAX - 1,
            ] {
                let mut h = hint;
                assert_eq!(
                    side.at(tau, &mut h).unwrap().to_bits(),
                    want,
                    "tau {tau}, hint {hint}"
                );
            }
        }
    }

    /// The position of a state is the same bits whatever the hint, and
    /// leaves the hint at the piece holding the state.
    #[test]
    fn positions_do_not_depend_on_the_hint() {
        let t = table(1.0, 0.7, 0.3, 1.5, 1e-10);
        for side in [&t.upper, &t.lower] {
            let mut us: Vec<f64> = side.pieces.iter().map(|p| p.b[0]).collect();
            us.extend(side.pieces.iter().map(|p| p.b[0] * 1.0001 + 1e-12));
            us.extend([side.u_end, side.u_end * (1.0 + 1e-9), 0.0, 1e-12]);
            for &u in &us {
                let mut first = 0;
                let want = side.position(u, &mut first).map(f64::to_bits);
                let n = side.pieces.len();
                for hint in [0, 1, 7, n - 1, n, usize::MAX - 1, usize::MAX] {
                    let mut h = hint;
                    assert_eq!(
                        side.position(u, &mut h).map(f64::to_bits),
                        want,
                        "u {u}, hint {hint}"
                    );
                    if u > 0.0 && u <= side.u_end {
                        assert_eq!(h, first, "u {u}, hint {hint}");
                        let q = &side.pieces[h];
                        assert!(q.b[0] <= u && side.pieces.get(h + 1).is_none_or(|p| u < p.b[0]));
                    }
                }
            }
        }
    }

    /// Hardening (`β + γ < 0`, `n = 2`): both sides grow,
    /// `u = √(α/|c|) tan(√(α|c|) τ)`, and are extended on demand up to
    /// the blow-up at `τ = π/(2√(α|c|))`, beyond which there is no state.
    #[test]
    fn hardening_sides_grow_on_demand_and_match_tan() {
        let (alpha, beta, gamma) = (1.5, 0.4, -0.9);
        let mut t = table(alpha, beta, gamma, 2.0, 1e-10);
        let (cu, cl) = (-(beta + gamma), beta - gamma);
        let mut hint = Hint::default();
        let mut worst = 0.0f64;
        for (c, sign) in [(cu, 1.0), (cl, -1.0)] {
            let blow_up = std::f64::consts::FRAC_PI_2 / (alpha * c).sqrt();
            for i in 1..=1000 {
                let tau = blow_up * 0.9 * i as f64 / 1000.0;
                let want = (alpha / c).sqrt() * ((alpha * c).sqrt() * tau).tan();
                let got = sign * t.state_at_growing(sign * tau, &mut hint).unwrap();
                worst = worst.max((got - want).abs() / want);
            }
            assert_eq!(t.state_at_growing(sign * blow_up * 1.01, &mut hint), None);
        }
        println!(
            "hardening n = 2: max relative error {worst:.2e}, pieces {:?}",
            t.pieces()
        );
        assert!(worst <= 1e-10, "{worst}");
    }

    /// A side extended sample by sample has the very pieces of one built
    /// in one go (so results never depend on the order of extension).
    #[test]
    fn growing_in_steps_equals_growing_at_once() {
        let eq = StateEquation::new(1.0, 0.5, -1.0, 1.7, 1e-10);
        let mut steps = FlowTable::new(&eq).unwrap();
        let mut once = FlowTable::new(&eq).unwrap();
        let mut hint = Hint::default();
        for i in 0..400 {
            steps.state_at_growing(i as f64 * 0.003, &mut hint);
        }
        once.state_at_growing(399.0 * 0.003, &mut hint);
        assert!(steps.upper.pieces.len() > 20);
        assert_eq!(steps.upper.pieces, once.upper.pieces);
    }

    /// The per-thread memo hands out the table a fresh build gives, not
    /// one a copy has extended since, and never one of other parameters
    /// (down to the last bit of `n`).
    #[test]
    fn remembered_tables_are_fresh_builds() {
        let eq = StateEquation::new(1.0, 0.5, -1.0, 1.7, 1e-10);
        let fresh = FlowTable::build(&eq).unwrap();
        let mut first = FlowTable::new(&eq).unwrap();
        let remembered = |eq: &StateEquation<f64>| {
            let key = [eq.alpha, eq.beta, eq.gamma, eq.power.exponent(), eq.rtol].map(f64::to_bits);
            RECENT_TABLES.with(|r| r.borrow().iter().any(|(_, k, _)| *k == key))
        };
        assert!(remembered(&eq));
        // a copy grown far beyond the first scale
        first.state_at_growing(5.0, &mut Hint::default());
        assert!(first.upper.pieces.len() > fresh.upper.pieces.len());
        assert_eq!(FlowTable::new(&eq).unwrap(), fresh);
        let next = StateEquation::new(1.0, 0.5, -1.0, f64::from_bits(1.7f64.to_bits() + 1), 1e-10);
        assert!(!remembered(&next));
        let other = FlowTable::new(&next).unwrap();
        assert_eq!(other, FlowTable::build(&next).unwrap());
        assert_ne!(other.upper.pieces, fresh.upper.pieces);
        // the oldest is forgotten once RECENT others are built
        for i in 0..RECENT {
            FlowTable::new(&StateEquation::new(
                1.0,
                0.5,
                -1.0,
                2.5 + i as f64 * 0.1,
                1e-10,
            ));
        }
        assert!(!remembered(&eq));
        assert_eq!(FlowTable::new(&eq).unwrap(), fresh);
    }

    #[test]
    fn outside_the_bounded_class_is_not_tabulated() {
        let eq = |b, g, n| StateEquation::new(1.0, b, g, n, 1e-10);
        assert!(FlowTable::new(&eq(0.7, 0.3, 1.0)).is_none()); // n = 1: closed form
        assert!(FlowTable::new(&eq(-0.5, -0.5, 1.5)).is_some()); // hardening: both grow
        assert!(FlowTable::new(&eq(0.2, 0.5, 1.5)).is_none()); // lower side saturates too
        assert!(FlowTable::new(&StateEquation::new(0.0, 0.5, 0.2, 1.5, 1e-10)).is_none());
        // Exponents beyond 64 (a fit's trial step once asked for 3e16).
        assert!(FlowTable::new(&eq(0.7, 0.3, 64.0)).is_some());
        assert!(FlowTable::new(&eq(0.7, 0.3, 64.5)).is_none());
        assert!(FlowTable::new(&eq(0.7, 0.3, 3.4e16)).is_none());
        // Too tight to integrate the knots a hundred times more accurately.
        assert!(FlowTable::new(&eq(0.7, 0.3, 1.5)).is_some());
        assert!(FlowTable::new(&StateEquation::new(1.0, 0.7, 0.3, 1.5, 1e-13)).is_none());
    }
}
