//! The scalar root finder behind every implicit combinator: Newton steps
//! from a start (and from a predicted root, where the caller has one),
//! then, if they stall, a bracket search followed by a safeguarded Newton
//! iteration with bisection fallback.
//!
//! A combinator's root moves little between samples, so the search first
//! takes plain Newton steps from the start, each of which must halve the
//! residual and stay inside the bounds; the first one that changes the
//! residual's sign gives the bracket. Only where they stall (a zero or
//! non-finite tangent, a step that does not halve the residual) does the
//! bracket search begin.
//!
//! Hysteresis operators have kinks, so their tangents are only hints: in a
//! bracket, a Newton step is taken when it lands strictly inside it and the
//! previous Newton step at least halved the residual; otherwise a
//! regula falsi step with the Illinois modification (the residual kept at
//! an end that survives twice in a row is halved), which converges
//! superlinearly across kinks, kept at least one tolerance inside the
//! bracket (so an end that already is the root gets its bracket closed),
//! and every fourth such step a bisection, counted since the last Newton
//! step that halved the residual (a Newton step that did not is followed by
//! a fallback, so the bracket at least halves every eight steps).
//!
//! The iteration stops at an evaluated point `x` whose Newton step `|r/d|`
//! is at most `abs_tol + rel_tol · |x|` (the root to that tolerance of
//! itself, without evaluating the step's end), when a Newton step or the
//! bracket is smaller than `abs_tol + rel_tol · max(|x|, scale)`, or where
//! the residual is exactly zero, and otherwise fails with
//! [`Error::NotConverged`].

use hysteron_operators::{CastScalar, Error, Float, Operator, Result};
use serde::{Deserialize, Serialize};

/// Tolerances and limits of an implicit solve.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SolverOptions<T> {
    /// Relative tolerance on the root.
    pub rel_tol: T,
    /// Absolute tolerance on the root.
    pub abs_tol: T,
    /// Maximum Newton/bisection iterations once the root is bracketed.
    pub max_iter: usize,
    /// Maximum widenings of the search interval: ×4 each for the first
    /// 16, then by factors that square up to `1e16` (16, 256, 65 536,
    /// 4.3e9, then 1e16 each), so that 64 reach any finite distance from a
    /// first step as small as the smallest normal number (×4 alone reaches
    /// 38 decades: an inverse at a target of `1e-300` whose root lies at
    /// unit scale found no bracket).
    pub max_expansions: usize,
}

impl<T: Float> Default for SolverOptions<T> {
    /// `rel_tol = 16 ε` (≈ 3.6e-15 for `f64`), `abs_tol` = the smallest
    /// positive normal number, 200 iterations, 64 expansions.
    fn default() -> Self {
        Self {
            rel_tol: T::epsilon() * T::lit(16.0),
            abs_tol: T::min_positive_value(),
            max_iter: 200,
            max_expansions: 64,
        }
    }
}

/// The same tolerances over the scalar `U` (see [`CastScalar`]).
impl<T: Float, U: Float> CastScalar<U> for SolverOptions<T> {
    type Out = SolverOptions<U>;
    fn cast_scalar(&self) -> SolverOptions<U> {
        SolverOptions {
            rel_tol: self.rel_tol.cast_scalar(),
            abs_tol: self.abs_tol.cast_scalar(),
            max_iter: self.max_iter,
            max_expansions: self.max_expansions,
        }
    }
}

impl<T: Float> SolverOptions<T> {
    pub(crate) fn tol(&self, x: T, scale: T) -> T {
        self.abs_tol + self.rel_tol * x.abs().max(scale.abs())
    }
}

/// One evaluation of the residual: value and derivative.
pub(crate) type Eval<T> = (T, T);

/// A residual function: at `x`, the residual and its slope there (or the
/// error of a child's trial), what the solver's steps evaluate.
pub(crate) trait ResidualFn<T>: FnMut(T) -> Result<Eval<T>> {}

impl<T, F: FnMut(T) -> Result<Eval<T>>> ResidualFn<T> for F {}

/// A residual function that remembers where it was last evaluated, so the
/// solver can leave the children's pending trials at the returned root.
struct Tracked<F, T> {
    f: F,
    last: Option<T>,
    /// The residual and its slope at `last`.
    last_eval: Option<Eval<T>>,
    solver: &'static str,
}

impl<T: Float, F: ResidualFn<T>> Tracked<F, T> {
    /// `f`, not evaluated yet, for the solver named `solver`.
    fn new(f: F, solver: &'static str) -> Self {
        Tracked {
            f,
            last: None,
            last_eval: None,
            solver,
        }
    }

    #[inline(always)]
    fn eval(&mut self, x: T) -> Result<Eval<T>> {
        self.last = Some(x);
        // A child rejecting a non-finite input here was handed an
        // overflowed probe, not the user's input: say so.
        let (r, d) = (self.f)(x).map_err(|e| match e {
            Error::NonFiniteInput { value } => Error::NonFiniteOutput {
                operator: self.solver,
                input: value,
            },
            other => other,
        })?;
        if r.is_nan() {
            return Err(Error::NoBracket {
                solver: self.solver,
                around: x.as_f64(),
                expansions: 0,
            });
        }
        self.last_eval = Some((r, d));
        Ok((r, d))
    }

    /// Leaves the last evaluation at `x`: evaluates there unless it was
    /// there already.
    #[inline(always)]
    fn end_at(&mut self, x: T) -> Result<()> {
        if self.last != Some(x) {
            self.eval(x)?;
        }
        Ok(())
    }
}

/// The outcome of a bounded solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Root<T> {
    /// A root inside the bounds.
    Inside(T),
    /// No root inside the bounds; the residual keeps its sign up to this
    /// bound, where the solution is clamped.
    AtBound(T),
}

impl<T: Copy> Root<T> {
    pub(crate) fn value(self) -> T {
        match self {
            Root::Inside(x) | Root::AtBound(x) => x,
        }
    }
}

/// Where and how to look for a root.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Start<T> {
    /// The starting point (typically the committed solution).
    pub x0: T,
    /// A typical distance to the root (for example the input increment);
    /// the search starts from the Newton step where available.
    pub step: T,
    /// A second point expected to bracket the root with `x0`.
    pub hint: Option<T>,
    /// A prediction of the root (for example extrapolated from the
    /// committed solution's tangents), tried first: Newton steps from it
    /// are taken before anything is evaluated at `x0`, and only if they
    /// stall does the search start again from `x0`.
    pub guess: Option<T>,
    /// The residual and its slope at `guess`, where the caller has
    /// evaluated it last (its children's pending trials are there), so
    /// that the search does not evaluate there again. Only for a guess
    /// that is finite and inside the bounds.
    pub evaluated: Option<Eval<T>>,
    /// Optional `[lo, hi]`; a root beyond a bound is reported as
    /// [`Root::AtBound`] (the residual is assumed increasing there).
    pub bounds: Option<(T, T)>,
    /// Magnitude used for the relative tolerance near zero.
    pub scale: T,
}

impl<T: Float> Start<T> {
    /// A start at the committed solution `x0` of a loop whose input moved
    /// from `x_prev` to `x`: the step is the input increment `|x − x_prev|`,
    /// the scale `max(|x|, |x0|)`; no hint and no bounds.
    pub(crate) fn at_committed(x0: T, x_prev: T, x: T) -> Self {
        Start {
            x0,
            step: (x - x_prev).abs(),
            hint: None,
            guess: None,
            evaluated: None,
            bounds: None,
            scale: x.abs().max(x0.abs()),
        }
    }

    /// This start with the prediction `guess` of the root.
    pub(crate) fn with_guess(self, guess: T) -> Self {
        Start {
            guess: Some(guess),
            evaluated: None,
            ..self
        }
    }
}

/// Solves `f(x) = 0` from `start`.
///
/// On success the last evaluation of `f` was at the returned point.
///
/// # Derivatives
/// Over a scalar that carries derivatives ([`Differentiable`](hysteron_operators::Differentiable)), the
/// root's derivatives are set by the implicit function theorem at the
/// root, not carried through the iterations: with `r(x, p) = 0`,
/// `∂x/∂p = −(∂r/∂p) / (∂r/∂x)`. The residual's derivative parts at the
/// root are `r_x ∂x/∂p + r_p` for whatever `∂x/∂p` the iterate carried,
/// so one step `x − (r − value(r)) / value(r_x)` gives the theorem's value
/// without moving the root's value; `f` is then evaluated there once more,
/// so the children's pending trials carry the same derivatives. Where
/// `r_x` is zero or not finite (a flat residual) the iterate's derivatives
/// are kept. A root held at a bound takes the bound's derivatives.
pub(crate) fn solve<T: Float, F: ResidualFn<T>>(
    solver: &'static str,
    f: F,
    start: Start<T>,
    opts: &SolverOptions<T>,
) -> Result<Root<T>> {
    let mut f = Tracked::new(f, solver);
    let root = search(&mut f, start, opts)?;
    if !T::CARRIES_DERIVATIVES {
        return Ok(root);
    }
    Ok(match root {
        Root::Inside(x) => {
            let x = match f.last_eval {
                Some((r, d)) if d != T::zero() && d.is_finite() => {
                    x - (r - r.without_derivatives()) / d.without_derivatives()
                }
                _ => x,
            };
            f.eval(x)?;
            Root::Inside(x)
        }
        Root::AtBound(x) => {
            f.eval(x)?;
            Root::AtBound(x)
        }
    })
}

/// The root `root` of `f`'s values, found by [`solve`] over `f64` on them
/// (the children's [`trial_value`](hysteron_operators::Hints::trial_value)),
/// over the scalar `T` with its derivatives: `f` is evaluated at the root
/// with no derivatives, which gives `∂r/∂p` there, then once more at the
/// root with the implicit function theorem's `∂x/∂p = −(∂r/∂p)/(∂r/∂x)`,
/// so the children's pending trials carry them (what [`solve`] does after
/// its own search). A root at a bound takes the bound's derivatives
/// (`bounds` over `T`, whose values the search was given). `None` where
/// `∂r/∂x` at the root is zero or not finite: there [`solve`] keeps the
/// derivatives its iterates carried, which a search on values has not
/// got, so the caller solves over `T`.
///
/// With `probe` (the caller has checked that nothing it is given carries
/// anything in the probe slot, [`Differentiable::probe`](hysteron_operators::Differentiable::probe)),
/// the first evaluation inside the bounds is at the root seeded in the
/// probe slot, and there is no second: the answer is then
/// [`AtRoot::Probed`], and the caller folds the children's pending trials
/// ([`Hints::fold_probe`](hysteron_operators::Hints::fold_probe))
/// or, where one cannot fold, asks again without `probe`. The other slots
/// of that evaluation are those of the evaluation without the probe, bit
/// for bit (each slot is computed from the values and itself only).
pub(crate) fn at_root<T: Float, F: ResidualFn<T>>(
    solver: &'static str,
    f: F,
    root: Root<f64>,
    bounds: Option<(T, T)>,
    probe: bool,
) -> Result<Option<AtRoot<T>>> {
    let mut f = Tracked::new(f, solver);
    Ok(Some(match root {
        Root::Inside(x) => {
            let x = T::lit(x);
            let (r, d) = f.eval(if probe { x.probe() } else { x })?;
            if !(d != T::zero() && d.is_finite()) {
                return Ok(None);
            }
            let mut dr = r - r.without_derivatives();
            if probe {
                // (the probe slot holds ∂r/∂x; the theorem takes `d`'s value)
                dr.fold_probe(&T::zero());
            }
            let x = x - dr / d.without_derivatives();
            if probe {
                return Ok(Some(AtRoot::Probed(x)));
            }
            f.eval(x)?;
            AtRoot::Evaluated(Root::Inside(x))
        }
        Root::AtBound(x) => {
            let x = match bounds {
                Some((_, hi)) if hi.as_f64() == x => hi,
                Some((lo, _)) if lo.as_f64() == x => lo,
                _ => return Ok(None),
            };
            f.eval(x)?;
            AtRoot::Evaluated(Root::AtBound(x))
        }
    }))
}

/// An implicit combinator's residual over its children, for
/// [`root_from_values`].
pub(crate) trait Residual<T> {
    /// The residual and its derivative at `x`, each child trialled there.
    fn eval(&mut self, x: T) -> Result<Eval<T>>;
    /// Folds the probe slot of the children's pending trials and of what
    /// [`eval`](Self::eval) keeps ([`Hints::fold_probe`](hysteron_operators::Hints::fold_probe));
    /// `false` where a child cannot.
    fn fold_probe(&mut self, along: &T) -> bool;
}

/// The root over `T` of a residual whose values' root `by_value` a search
/// on values found ([`at_root`], probing where `probe` says the probe slot
/// is free, and folding; where a child cannot fold, the two evaluations
/// without the probe); `None` where there is none or [`at_root`] has none.
pub(crate) fn root_from_values<T: Float, R: Residual<T>>(
    solver: &'static str,
    residual: &mut R,
    by_value: Option<Root<f64>>,
    bounds: Option<(T, T)>,
    probe: bool,
) -> Result<Option<Root<T>>> {
    let Some(root) = by_value else {
        return Ok(None);
    };
    match at_root(solver, |x| residual.eval(x), root, bounds, probe)? {
        None => Ok(None),
        Some(AtRoot::Evaluated(root)) => Ok(Some(root)),
        Some(AtRoot::Probed(x)) if residual.fold_probe(&x) => Ok(Some(Root::Inside(x))),
        Some(AtRoot::Probed(_)) => Ok(
            match at_root(solver, |x| residual.eval(x), root, bounds, false)? {
                Some(AtRoot::Evaluated(root)) => Some(root),
                _ => None,
            },
        ),
    }
}

/// Whether no parameter of `op` carries anything in the probe slot
/// ([`Differentiable::probe_free`](hysteron_operators::Differentiable::probe_free)),
/// `known` where the combinator has found it already for its parameter set.
pub(crate) fn params_probe_free<T: Float, O: Operator<T> + ?Sized>(
    known: Option<bool>,
    op: &O,
) -> bool {
    known.unwrap_or_else(|| op.params().iter().all(|p| p.probe_free()))
}

/// What [`at_root`] found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum AtRoot<T> {
    /// The root with its derivatives, where `f` was evaluated last.
    Evaluated(Root<T>),
    /// The root (inside the bounds) with its derivatives; `f` was
    /// evaluated last at its value seeded in the probe slot.
    Probed(T),
}

/// The search of [`solve`].
fn search<T: Float, F: ResidualFn<T>>(
    f: &mut Tracked<F, T>,
    start: Start<T>,
    opts: &SolverOptions<T>,
) -> Result<Root<T>> {
    let Start {
        x0,
        step,
        hint,
        bounds,
        guess,
        evaluated,
        scale,
    } = start;
    let clamp = |x: T| match bounds {
        Some((lo, hi)) => x.max(lo).min(hi),
        None => x,
    };
    if let Some(g) = guess.map(clamp).filter(|g| g.is_finite()) {
        // (the caller's evaluation counts where it was at this very point)
        let evaluated = evaluated.filter(|_| guess == Some(g)).map(|e| {
            f.last = Some(g);
            f.last_eval = Some(e);
            e
        });
        if let Some(root) = from(f, g, evaluated, bounds, scale, opts)? {
            return Ok(root);
        }
    }
    let x0 = clamp(x0);
    let (r0, d0) = f.eval(x0)?;
    if r0 == T::zero() {
        return Ok(Root::Inside(x0));
    }
    // Already at a bound and pushed beyond it: stay there.
    if held_at_bound(x0, r0, bounds) {
        return Ok(Root::AtBound(x0));
    }
    let (x0, r0, d0) = match newton(f, (x0, r0, d0), bounds, scale, opts)? {
        Newton::Root(x) => return Ok(Root::Inside(x)),
        Newton::AtBound(x) => return Ok(Root::AtBound(x)),
        Newton::Bracket(b) => return finish(f, b, scale, opts),
        Newton::Stalled(best) => best,
    };
    let bracket = match find_bracket(f, x0, r0, d0, step, hint, bounds, scale, opts)? {
        Found::Bracket(b) => b,
        Found::AtBound(x) => {
            f.end_at(x)?;
            return Ok(Root::AtBound(x));
        }
    };
    finish(f, bracket, scale, opts)
}

/// The root found by Newton steps from the guess `g` (inside the bounds),
/// or `None` if they stall; `evaluated`: the residual and slope at `g`
/// where they are known already.
#[inline(always)]
fn from<T: Float, F: ResidualFn<T>>(
    f: &mut Tracked<F, T>,
    g: T,
    evaluated: Option<Eval<T>>,
    bounds: Option<(T, T)>,
    scale: T,
    opts: &SolverOptions<T>,
) -> Result<Option<Root<T>>> {
    let (r, d) = match evaluated {
        Some(e) => e,
        None => f.eval(g)?,
    };
    if r == T::zero() {
        return Ok(Some(Root::Inside(g)));
    }
    if held_at_bound(g, r, bounds) {
        return Ok(Some(Root::AtBound(g)));
    }
    Ok(match newton(f, (g, r, d), bounds, scale, opts)? {
        Newton::Root(x) => Some(Root::Inside(x)),
        Newton::AtBound(x) => Some(Root::AtBound(x)),
        Newton::Bracket(b) => Some(finish(f, b, scale, opts)?),
        Newton::Stalled(_) => None,
    })
}

/// Refines `bracket` and leaves the last evaluation at the root.
#[inline(always)]
fn finish<T: Float, F: ResidualFn<T>>(
    f: &mut Tracked<F, T>,
    bracket: Bracket<T>,
    scale: T,
    opts: &SolverOptions<T>,
) -> Result<Root<T>> {
    let x = refine(f, bracket, scale, opts)?;
    f.end_at(x)?;
    Ok(Root::Inside(x))
}

/// Newton steps taken from the start, before any bracket, at most this
/// many.
pub(crate) const NEWTON_STEPS: usize = 12;

/// How the Newton steps of [`newton`] ended.
enum Newton<T> {
    /// A root inside the bounds, where the last evaluation was.
    Root(T),
    /// A bound beyond which the residual keeps its sign, where the last
    /// evaluation was.
    AtBound(T),
    /// Two evaluated points with residuals of opposite signs.
    Bracket(Bracket<T>),
    /// No usable step: the tangent is zero or not finite, a step did not
    /// halve the residual, or the steps ran out. The point with the
    /// smallest residual so far, `(x, r, d)`, from which the bracket
    /// search goes on.
    Stalled((T, T, T)),
}

/// Newton steps `x ← x − r/d` from the start `(x, r, d)`, before any
/// bracket: where the residual is smooth near the start (a combinator's
/// root moves little from the committed one between samples) they
/// converge without the evaluations a bracket costs.
///
/// Each step must halve the residual and stay inside the bounds; the first
/// step that changes the residual's sign gives a bracket (refined by
/// [`refine`]), and one that would cross a bound is evaluated at the
/// bound, which either brackets the root or holds it there. The root is
/// the current point once its Newton step is within `abs_tol + rel_tol ·
/// |x|` (the refinement's stopping rule), or a point where the residual
/// is exactly zero, reached by a step no longer than `max(|x|, scale)` or
/// else confirmed by a sign change around it (as in the bracket search).
#[inline(always)]
fn newton<T: Float, F: ResidualFn<T>>(
    f: &mut Tracked<F, T>,
    start: (T, T, T),
    bounds: Option<(T, T)>,
    scale: T,
    opts: &SolverOptions<T>,
) -> Result<Newton<T>> {
    let (mut x, mut r, mut d) = start;
    for _ in 0..NEWTON_STEPS {
        if !(d.is_finite() && d != T::zero()) {
            break;
        }
        let step = r / d;
        if newton_done(x, step, opts) {
            return Ok(Newton::Root(x));
        }
        let mut next = x - step;
        let mut at_bound = false;
        if let Some((lo, hi)) = bounds {
            if !(next > lo && next < hi) {
                next = if next >= hi { hi } else { lo };
                at_bound = true;
            }
        }
        if !next.is_finite() || next == x {
            break;
        }
        let (rn, dn) = f.eval(next)?;
        if rn == T::zero() {
            // A residual that only rounds to zero needs terms far beyond
            // the problem's magnitude (see `genuine_zero`); a step within
            // it cannot have reached such a point.
            let small = step.abs() <= x.abs().max(scale.abs());
            if small || genuine_zero(f, next, scale, opts)? {
                f.end_at(next)?;
                return Ok(Newton::Root(next));
            }
            break;
        }
        if rn.signum() != r.signum() {
            return Ok(Newton::Bracket(Bracket::new((x, r, d), (next, rn, dn))));
        }
        if at_bound {
            if held_at_bound(next, rn, bounds) {
                return Ok(Newton::AtBound(next));
            }
            break;
        }
        if rn.abs() > r.abs() * T::lit(0.5) {
            break;
        }
        (x, r, d) = (next, rn, dn);
    }
    Ok(Newton::Stalled((x, r, d)))
}

/// Whether the residual `r` at `x`, one of the `bounds`, pushes beyond it:
/// an increasing residual still negative at `hi`, or still positive at
/// `lo`, means the root lies beyond the bound, and is held there.
#[inline(always)]
fn held_at_bound<T: Float>(x: T, r: T, bounds: Option<(T, T)>) -> bool {
    bounds.is_some_and(|(lo, hi)| (x == hi && r < T::zero()) || (x == lo && r > T::zero()))
}

/// The stopping rule of [`newton`] at `x`, whose Newton step is `step`:
/// `|step| ≤ abs_tol + rel_tol · |x|`.
#[inline(always)]
pub(crate) fn newton_done<T: Float>(x: T, step: T, opts: &SolverOptions<T>) -> bool {
    step.abs() <= opts.tol(x, T::zero())
}

/// Whether a search from the guess `x` (inside the bounds, not at one),
/// where the residual and its slope are `(r, d)`, returns `x` as the root
/// at once: the residual is zero there, or the slope is finite and
/// non-zero and the Newton step is within the tolerance ([`newton`]'s
/// rule). A caller that evaluated its guess can skip the search then.
#[inline(always)]
pub(crate) fn root_at_guess<T: Float>(x: T, (r, d): Eval<T>, opts: &SolverOptions<T>) -> bool {
    r == T::zero() || (d.is_finite() && d != T::zero() && newton_done(x, r / d, opts))
}

/// A bracket: points with negative and positive residual, and the one of
/// them with the smaller residual as the starting point.
#[derive(Debug, Clone, Copy)]
struct Bracket<T> {
    neg: T,
    pos: T,
    /// The residuals at `neg` (`≤ 0`) and `pos` (`≥ 0`).
    r_neg: T,
    r_pos: T,
    start: (T, T, T),
}

impl<T: Float> Bracket<T> {
    /// The bracket of two evaluated points `(x, r, d)` whose residuals
    /// have opposite signs (or one is zero), starting at the one with the
    /// smaller residual.
    fn new(a: (T, T, T), b: (T, T, T)) -> Self {
        let start = if a.1.abs() <= b.1.abs() { a } else { b };
        let (neg, pos) = if a.1 < T::zero() { (a, b) } else { (b, a) };
        Bracket {
            neg: neg.0,
            pos: pos.0,
            r_neg: neg.1,
            r_pos: pos.1,
            start,
        }
    }
}

enum Found<T> {
    Bracket(Bracket<T>),
    AtBound(T),
}

#[allow(clippy::too_many_arguments)]
fn find_bracket<T: Float, F: ResidualFn<T>>(
    f: &mut Tracked<F, T>,
    x0: T,
    r0: T,
    d0: T,
    step: T,
    hint: Option<T>,
    bounds: Option<(T, T)>,
    scale: T,
    opts: &SolverOptions<T>,
) -> Result<Found<T>> {
    let clamp = |x: T| match bounds {
        Some((lo, hi)) => x.max(lo).min(hi),
        None => x,
    };
    if let Some(h) = hint.map(clamp) {
        if h != x0 {
            let (rh, dh) = f.eval(h)?;
            if rh == T::zero() || rh.signum() != r0.signum() {
                return Ok(Found::Bracket(Bracket::new((x0, r0, d0), (h, rh, dh))));
            }
        }
    }
    // Preferred direction: downhill along the (assumed increasing) residual.
    let newton = if d0.is_finite() && d0 > T::zero() {
        (r0 / d0).abs()
    } else {
        T::zero()
    };
    let mut h = newton * T::lit(1.25);
    if !(h.is_finite() && h > T::zero()) {
        h = step.abs();
    }
    let floor = opts.tol(x0, scale) * T::lit(16.0);
    if !(h.is_finite() && h > floor) {
        h = floor;
    }
    let preferred = if r0 > T::zero() { -T::one() } else { T::one() };
    // Side 0 is downhill for an increasing residual; side 1 (uphill) is
    // searched too from the third widening on, for residuals that decrease.
    let mut blocked = [false, false];
    let mut growth = T::lit(4.0);
    for i in 0..opts.max_expansions {
        let sides = [preferred, -preferred].into_iter().zip(&mut blocked);
        for (k, (side, blocked)) in sides.enumerate() {
            if *blocked || (k == 1 && i < 2) {
                continue;
            }
            let x = clamp(x0 + side * h);
            if x == x0 {
                *blocked = true;
                continue;
            }
            let (r, d) = f.eval(x)?;
            if r == T::zero() && !genuine_zero(f, x, scale, opts)? {
                // A residual that only rounds to zero (a loop with no
                // solution evaluated where its terms swamp each other):
                // not a root; keep searching, and fail if nothing else is.
                continue;
            }
            if r == T::zero() || r.signum() != r0.signum() {
                return Ok(Found::Bracket(Bracket::new((x0, r0, d0), (x, r, d))));
            }
            if let Some((lo, hi)) = bounds {
                if x == lo || x == hi {
                    *blocked = true;
                    // Increasing residual: still negative at hi, or still
                    // positive at lo, means the root lies beyond the bound.
                    if (x == hi && r < T::zero()) || (x == lo && r > T::zero()) {
                        return Ok(Found::AtBound(x));
                    }
                }
            }
        }
        if blocked[0] && blocked[1] {
            break;
        }
        h = h * growth;
        if i >= 15 {
            growth = (growth * growth).min(T::lit(1e16));
        }
        if !h.is_finite() {
            break;
        }
    }
    Err(Error::NoBracket {
        solver: f.solver,
        around: x0.as_f64(),
        expansions: opts.max_expansions,
    })
}

/// Whether an exact zero of the residual met while bracketing is a root:
/// the residual just below and just above `x` must have opposite signs.
/// (A zero that is only rounding, or the inside of a flat set of roots, is
/// passed over; the search goes on to a sign change beyond it, which
/// brackets the flat set for the refinement.)
fn genuine_zero<T: Float, F: ResidualFn<T>>(
    f: &mut Tracked<F, T>,
    x: T,
    scale: T,
    opts: &SolverOptions<T>,
) -> Result<bool> {
    let d = opts.tol(x, scale).max(x.abs() * T::epsilon() * T::lit(4.0));
    let (below, _) = f.eval(x - d)?;
    let (above, _) = f.eval(x + d)?;
    let zero = T::zero();
    Ok((below < zero && above > zero) || (below > zero && above < zero))
}

#[inline(always)]
fn refine<T: Float, F: ResidualFn<T>>(
    f: &mut Tracked<F, T>,
    b: Bracket<T>,
    scale: T,
    opts: &SolverOptions<T>,
) -> Result<T> {
    let (mut neg, mut pos) = (b.neg, b.pos);
    let (mut r_neg, mut r_pos) = (b.r_neg, b.r_pos);
    let (mut x, mut r, mut d) = b.start;
    let mut r_prev = T::infinity();
    // The end replaced last (-1: neg, 1: pos), and how many steps in a row
    // were not Newton steps.
    let (mut last_end, mut fallbacks) = (0i8, 0u32);
    let half = T::lit(0.5);
    for _ in 0..opts.max_iter {
        let (lo, hi) = if neg < pos { (neg, pos) } else { (pos, neg) };
        let tol = opts.tol(x, scale);
        if hi - lo <= tol {
            return Ok(x);
        }
        let smooth = d.is_finite() && d != T::zero();
        if smooth && (r / d).abs() <= opts.tol(x, T::zero()) {
            // The Newton step from `x` is within the tolerance of `x`
            // itself: `x` is the root to it, without evaluating the step's
            // end.
            return Ok(x);
        }
        let newton = x - r / d;
        let use_newton = smooth && newton > lo && newton < hi && r.abs() <= r_prev * half;
        let x_next = if use_newton {
            newton
        } else {
            fallbacks += 1;
            let secant = neg - r_neg * (pos - neg) / (r_pos - r_neg);
            if fallbacks % 4 != 0 && secant.is_finite() {
                // At least `tol` inside the bracket: a secant point on top
                // of an end that already is the root to rounding then
                // probes just beyond it, closing the bracket.
                secant.max(lo + tol).min(hi - tol)
            } else {
                lo + (hi - lo) * half
            }
        };
        r_prev = if use_newton { r.abs() } else { T::infinity() };
        let (r_next, d_next) = f.eval(x_next)?;
        if r_next == T::zero() {
            return Ok(x_next);
        }
        // Only a Newton step that halved the residual ends a run of
        // fallbacks: one that did not is followed by a fallback anyway, and
        // resetting the count there let Newton and secant steps alternate
        // at a stick-slip kink without a bisection ever coming due (the
        // bracket barely shrank for 200 iterations).
        if use_newton && r_next.abs() <= r.abs() * half {
            fallbacks = 0;
        }
        if r_next < T::zero() {
            if last_end == -1 {
                r_pos = r_pos * half;
            }
            (neg, r_neg, last_end) = (x_next, r_next, -1);
        } else {
            if last_end == 1 {
                r_neg = r_neg * half;
            }
            (pos, r_pos, last_end) = (x_next, r_next, 1);
        }
        let moved = (x_next - x).abs();
        x = x_next;
        r = r_next;
        d = d_next;
        if use_newton && moved <= tol {
            return Ok(x);
        }
    }
    Err(Error::NotConverged {
        solver: f.solver,
        iterations: opts.max_iter,
        width: (pos - neg).abs().as_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn opts() -> SolverOptions<f64> {
        SolverOptions::default()
    }

    fn st(x0: f64, step: f64, hint: Option<f64>, bounds: Option<(f64, f64)>) -> Start<f64> {
        Start {
            x0,
            step,
            hint,
            bounds,
            guess: None,
            evaluated: None,
            scale: 1.0,
        }
    }

    /// `solve` with the default options.
    fn solve_t(f: impl FnMut(f64) -> Result<Eval<f64>>, start: Start<f64>) -> Result<Root<f64>> {
        solve("t", f, start, &opts())
    }

    /// `solve` with the default options, and where it evaluated, in order.
    fn solve_recording(
        f: impl Fn(f64) -> Result<Eval<f64>>,
        start: Start<f64>,
    ) -> (Root<f64>, Vec<f64>) {
        let mut evals = Vec::new();
        let recording = |x: f64| {
            evals.push(x);
            f(x)
        };
        let root = solve_t(recording, start).unwrap();
        (root, evals)
    }

    /// The root's derivatives come from the implicit function theorem, not
    /// from the iterate: a start already at the root (in value) whose
    /// derivative is stale (as a committed solution's is when a parameter
    /// moved) gets `∂x/∂p = −r_p/r_x`, and so does a root found by
    /// iterating.
    #[test]
    fn root_derivatives_are_those_of_the_implicit_function_theorem() {
        use hysteron_operators::DualN;
        type D = DualN<1>;
        // r(x, p) = x³ − p at p = 8: x = 2, ∂x/∂p = 1/(3x²) = 1/12
        let p = D::variable(8.0, 0);
        let residual = |x: D| Ok((x * x * x - p, D::constant(3.0) * x * x));
        let opts = SolverOptions::<D>::default();
        for x0 in [
            D {
                re: 2.0,
                eps: [5.0],
            }, // at the root, stale derivative
            D {
                re: 3.0,
                eps: [0.0],
            }, // found by iterating
        ] {
            let start = Start {
                x0,
                step: D::constant(0.5),
                hint: None,
                bounds: None,
                guess: None,
                evaluated: None,
                scale: D::constant(1.0),
            };
            let root = solve("test", residual, start, &opts).unwrap().value();
            assert!((root.re - 2.0).abs() < 1e-14);
            assert!((root.eps[0] - 1.0 / 12.0).abs() < 1e-15, "{:?}", root);
        }
    }

    #[test]
    fn finds_smooth_root() {
        let root = solve_t(
            |x: f64| Ok((x * x * x - 2.0, 3.0 * x * x)),
            st(0.0, 1.0, None, None),
        )
        .unwrap();
        assert!((root.value() - 2f64.cbrt()).abs() < 1e-14);
    }

    /// Without usable tangents, a kinked residual is solved by Illinois
    /// steps in far fewer evaluations than bisection needs (about 50 to
    /// shrink a unit bracket to 16 ε).
    #[test]
    fn kinked_residual_without_tangents_converges_superlinearly() {
        let kinked = |x: f64| {
            if x < 0.2 {
                x - 0.3
            } else {
                30.0 * (x - 0.2) - 0.1
            }
        };
        let root_at = 0.2 + 0.1 / 30.0;
        let mut evals = 0;
        let root = solve_t(
            |x: f64| {
                evals += 1;
                Ok((kinked(x), f64::NAN))
            },
            st(-1.0, 2.0, None, None),
        )
        .unwrap();
        assert!((root.value() - root_at).abs() < 1e-14, "{root:?}");
        assert!(evals <= 20, "{evals} evaluations");
    }

    #[test]
    fn survives_useless_tangents() {
        // Piecewise-constant tangent of zero: pure bisection must still converge.
        let root = solve_t(|x: f64| Ok((x - 0.3, 0.0)), st(5.0, 1.0, None, None)).unwrap();
        assert!((root.value() - 0.3).abs() < 1e-14);
        // NaN tangent.
        let root = solve_t(
            |x: f64| Ok((x.powi(3) + x, f64::NAN)),
            st(2.0, 1.0, None, None),
        )
        .unwrap();
        assert!(root.value().abs() < 1e-14);
    }

    #[test]
    fn decreasing_residual_is_bracketed_too() {
        let root = solve_t(|x: f64| Ok((4.0 - x, -1.0)), st(0.0, 0.1, None, None)).unwrap();
        assert!((root.value() - 4.0).abs() < 1e-13);
    }

    #[test]
    fn bounds_clamp_the_root() {
        let b = Some((-1.0, 1.0));
        // residual x − a: a root beyond each bound, and one inside
        for (a, want) in [
            (3.0, Root::AtBound(1.0)),
            (-3.0, Root::AtBound(-1.0)),
            (0.5, Root::Inside(0.5)),
        ] {
            let r = solve_t(|x: f64| Ok((x - a, 1.0)), st(0.0, 0.1, None, b)).unwrap();
            assert_eq!(r, want);
        }
    }

    #[test]
    fn a_residual_that_only_rounds_to_zero_is_not_a_root() {
        // y − (1 + y): −1 everywhere, but 0 in floating point once y ≥ 2^53.
        let e = solve_t(|y: f64| Ok((y - (1.0 + y), 0.0)), st(0.0, 1.0, None, None));
        assert!(matches!(e, Err(Error::NoBracket { .. })), "{e:?}");
    }

    #[test]
    fn no_root_is_an_error() {
        let e = solve_t(
            |x: f64| Ok((x * x + 1.0, 2.0 * x)),
            st(0.0, 1.0, None, None),
        );
        assert!(matches!(e, Err(Error::NoBracket { .. })));
    }

    /// From a start near the root, Newton steps converge without a
    /// bracket: `x³ − 2` from 1.3 takes the start and four steps, the last
    /// of which is within the tolerance of its own point (the old search
    /// spent a bracket end and a confirming evaluation more).
    #[test]
    fn newton_from_a_close_start_needs_no_bracket() {
        let mut evals = 0;
        let root = solve_t(
            |x: f64| {
                evals += 1;
                Ok((x * x * x - 2.0, 3.0 * x * x))
            },
            st(1.3, 0.1, Some(1.4), None),
        )
        .unwrap();
        assert!((root.value() - 2f64.cbrt()).abs() <= 4.0 * f64::EPSILON);
        assert!(evals <= 5, "{evals} evaluations");
    }

    /// A guess is tried first; where Newton steps from it stall (here on a
    /// flat stretch of the residual) the search starts again from `x0`.
    #[test]
    fn a_guess_is_tried_first_and_a_bad_one_is_survived() {
        let residual = |x: f64| {
            Ok((
                (x - 0.3).clamp(-1.0, 1.0),
                if x.abs() < 1.3 { 1.0 } else { 0.0 },
            ))
        };
        let from = |guess: f64| {
            let start = Start {
                guess: Some(guess),
                ..st(0.0, 0.1, None, None)
            };
            let (root, evals) = solve_recording(residual, start);
            (root.value(), evals)
        };
        // a good guess: the first evaluation, then the root
        let (root, evals) = from(0.31);
        assert!((root - 0.3).abs() < 1e-15, "{root}");
        assert_eq!(evals.first(), Some(&0.31));
        assert!(evals.len() <= 2, "{evals:?}");
        // a guess on the flat stretch: Newton cannot start there
        let (root, evals) = from(5.0);
        assert!((root - 0.3).abs() < 1e-15, "{root}");
        assert_eq!(evals.get(..2), Some(&[5.0, 0.0][..]));
    }

    /// A guess the caller evaluated is not evaluated again: the search
    /// goes on from the given residual (the same root as without it), and
    /// [`root_at_guess`] says when the guess is the root already.
    #[test]
    fn an_evaluated_guess_is_not_evaluated_again() {
        let residual = |x: f64| Ok((x * x * x + x - 0.5, 3.0 * x * x + 1.0));
        let run = |guess: f64, evaluated: Option<Eval<f64>>| {
            let start = Start {
                guess: Some(guess),
                evaluated,
                ..st(0.0, 0.1, None, Some((-1.0, 1.0)))
            };
            solve_recording(residual, start)
        };
        let guess = 0.45;
        let at_guess = residual(guess).unwrap();
        let (plain, plain_evals) = run(guess, None);
        let (given, given_evals) = run(guess, Some(at_guess));
        assert_eq!(plain, given);
        assert_eq!(plain_evals.first(), Some(&guess));
        assert_eq!(given_evals, plain_evals[1..]);
        assert!(!root_at_guess(guess, at_guess, &opts()));
        // at the root (to the tolerance), the guess is the answer
        let root = plain.value();
        assert!(root_at_guess(root, residual(root).unwrap(), &opts()));
        assert!(root_at_guess(0.7, (0.0, 0.0), &opts())); // a zero residual
        assert!(!root_at_guess(root, (1e-300, 0.0), &opts())); // no slope
        assert!(!root_at_guess(root, (f64::NAN, 1.0), &opts()));
    }

    /// A Newton step that would cross a bound is evaluated at the bound,
    /// which holds the root when the residual keeps its sign there.
    #[test]
    fn a_newton_step_across_a_bound_stops_at_it() {
        let b = Some((-1.0, 1.0));
        let mut evals = 0;
        let r = solve_t(
            |x: f64| {
                evals += 1;
                Ok((x - 3.0, 1.0))
            },
            Start {
                guess: Some(0.5),
                evaluated: None,
                ..st(0.0, 0.1, None, b)
            },
        )
        .unwrap();
        assert_eq!(r, Root::AtBound(1.0));
        assert_eq!(evals, 2);
    }

    #[test]
    fn last_evaluation_is_at_the_root() {
        let mut last = f64::NAN;
        let root = solve_t(
            |x: f64| {
                last = x;
                Ok(((x - 0.7).tanh(), 1.0))
            },
            st(0.0, 0.1, Some(2.0), None),
        )
        .unwrap();
        assert_eq!(last, root.value());
    }
}
