//! Mechanical series connection: equal force, displacements add.

use crate::pair::{pair_domains, pair_names, set_pair};
use crate::solve::{
    params_probe_free, root_at_guess, root_from_values, solve, Residual, Root, SolverOptions, Start,
};
use crate::Child;
use hysteron_operators::{
    check, check_input, check_lengths, process_while, process_while_beyond, Beyond, CastScalar,
    Derivatives, Domain, Dual, Error, Float, Hints, Operator, Parameters, Result, SamplePeriod,
    Staged, Trial,
};
use serde::{Deserialize, Serialize};

/// Travel limits on the left element of a [`MechanicalSeries`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum TravelLimits<T> {
    /// No limits.
    None,
    /// `x_left ∈ [lo, hi]` with `lo ≤ 0 ≤ hi`, `lo < hi`. Parameters `[lo, hi]`.
    Range {
        /// Lower stop.
        lo: T,
        /// Upper stop.
        hi: T,
    },
    /// A gap of total size `b > 0` in which the left element starts at
    /// position `r0 ∈ [−b/2, b/2]` (measured from the gap's centre). The
    /// left element is driven by its displacement since the start,
    /// `r − r0 ∈ [−b/2 − r0, b/2 − r0]`, and the right element by
    /// `x − r` (so at `x = 0` it sees `−r0`). Parameters `[b, r0]`.
    Gap {
        /// Gap size.
        b: T,
        /// Initial position in the gap (0: centred).
        #[serde(default)]
        r0: T,
    },
}

/// The same limits over the scalar `U` (see [`CastScalar`]).
impl<T: Float, U: Float> CastScalar<U> for TravelLimits<T> {
    type Out = TravelLimits<U>;
    fn cast_scalar(&self) -> TravelLimits<U> {
        match *self {
            TravelLimits::None => TravelLimits::None,
            TravelLimits::Range { lo, hi } => TravelLimits::Range {
                lo: lo.cast_scalar(),
                hi: hi.cast_scalar(),
            },
            TravelLimits::Gap { b, r0 } => TravelLimits::Gap {
                b: b.cast_scalar(),
                r0: r0.cast_scalar(),
            },
        }
    }
}

impl<T: Float> TravelLimits<T> {
    /// Checks the limits (see the variants).
    pub fn validate(&self) -> Result<()> {
        match *self {
            TravelLimits::None => Ok(()),
            TravelLimits::Range { lo, hi } => {
                check::non_positive("limits.lo", lo)?;
                check::non_negative("limits.hi", hi)?;
                check::ordered("limits.lo", lo, "limits.hi", hi)
            }
            TravelLimits::Gap { b, r0 } => {
                check::positive("limits.b", b)?;
                check::finite("limits.r0", r0)?;
                if r0.abs() <= b * T::lit(0.5) {
                    Ok(())
                } else {
                    Err(Error::InvalidParameter {
                        name: "limits.r0".into(),
                        value: r0.as_f64(),
                        reason: "must lie in the gap [−b/2, b/2]",
                    })
                }
            }
        }
    }

    /// The left element's travel bounds `(lo, hi)` relative to its start:
    /// `(lo, hi)` for a range, `(−b/2 − r0, b/2 − r0)` for a gap (the slider
    /// starts at `r0` in `[−b/2, b/2]`), `None` without limits.
    pub fn bounds(&self) -> Option<(T, T)> {
        match *self {
            TravelLimits::None => None,
            TravelLimits::Range { lo, hi } => Some((lo, hi)),
            TravelLimits::Gap { b, r0 } => {
                let half = b * T::lit(0.5);
                Some((-half - r0, half - r0))
            }
        }
    }

    /// Where the left element starts (`r0` of a gap, else 0).
    fn start(&self) -> T {
        match *self {
            TravelLimits::Gap { r0, .. } => r0,
            _ => T::zero(),
        }
    }

    fn values(&self) -> Vec<T> {
        match *self {
            TravelLimits::None => vec![],
            TravelLimits::Range { lo, hi } => vec![lo, hi],
            TravelLimits::Gap { b, r0 } => vec![b, r0],
        }
    }

    fn domains(&self) -> Vec<Domain> {
        match self {
            TravelLimits::None => vec![],
            TravelLimits::Range { .. } => vec![Domain::NonPositive, Domain::NonNegative],
            TravelLimits::Gap { .. } => vec![Domain::Positive, Domain::Real],
        }
    }

    fn names(&self) -> Vec<String> {
        match self {
            TravelLimits::None => vec![],
            TravelLimits::Range { .. } => vec!["limits.lo".into(), "limits.hi".into()],
            TravelLimits::Gap { .. } => vec!["limits.b".into(), "limits.r0".into()],
        }
    }

    // `p.len() == self.values().len()` (2 for `Range` and `Gap`) by
    // `check::count`.
    #[allow(clippy::indexing_slicing)]
    fn with_values(&self, p: &[T]) -> Result<Self> {
        check::count(self.values().len(), p)?;
        let next = match self {
            TravelLimits::None => TravelLimits::None,
            TravelLimits::Range { .. } => TravelLimits::Range { lo: p[0], hi: p[1] },
            TravelLimits::Gap { .. } => TravelLimits::Gap { b: p[0], r0: p[1] },
        };
        next.validate()?;
        Ok(next)
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct State<T> {
    x: T,
    x_left: T,
    /// How the split follows the input here, where it was a root inside
    /// the limits (`None` at a limit, before any motion, or where the
    /// tangents gave no finite share).
    share: Option<Share<T>>,
}

/// How the split `x_L` of a [`MechanicalSeries`] follows its input at a
/// committed root, for a first guess of the next root: the cubic
/// `x_L + w Δx + a Δx² + b Δx³` that has the split and its slope
/// `w = dx_L/dx` at this root and at the one before (cubic Hermite
/// extrapolation, error `O(h⁴)` in the increments `h`), where the increment
/// before went the same way (else the tangent line, `a = b = 0`).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Share<T> {
    /// `w = dx_L/dx = R'/(L' + R')` from the tangents at the root.
    w: T,
    /// The quadratic coefficient `a`.
    a: T,
    /// The cubic coefficient `b`.
    b: T,
    /// The increment that led here.
    dx: T,
}

impl<T: Float> State<T> {
    /// At input `x` with the left element at `x_left`, no share known.
    fn at(x: T, x_left: T) -> Self {
        State {
            x,
            x_left,
            share: None,
        }
    }
}

impl<T: Float> Share<T> {
    /// The share at a root with tangents `l` and `r`, reached by the
    /// increment `h = dx` of the input that moved the split by `dxl`, from
    /// a state whose share was `prev` (slope `w₀`). With `Δ = dxl`, the
    /// cubic through both roots with both slopes has
    /// `b = (w₀ + w − 2Δ/h)/h²` and `a = (w h − Δ)/h² + b h`; terms that are
    /// not finite leave the tangent line.
    fn new(l: T, r: T, dx: T, dxl: T, prev: Option<Share<T>>) -> Option<Self> {
        let w = r / (l + r);
        if !w.is_finite() {
            return None;
        }
        let (a, b) = match prev {
            Some(p) if p.dx * dx > T::zero() => {
                let h2 = dx * dx;
                let b = (p.w + w - T::lit(2.0) * dxl / dx) / h2;
                let a = (w * dx - dxl) / h2 + b * dx;
                if a.is_finite() && b.is_finite() {
                    (a, b)
                } else {
                    (T::zero(), T::zero())
                }
            }
            _ => (T::zero(), T::zero()),
        };
        Some(Share { w, a, b, dx })
    }

    /// The guess for the split after the increment `dx` from `x_left`:
    /// `x_left + dx (w + bend)` with the cubic's `bend = dx (a + b dx)`.
    /// For non-decreasing elements the split's mean slope over the step,
    /// `w + bend`, lies in `[0, 1]`, so a bend beyond `±1` is extrapolation
    /// of rounding (coefficients from tiny increments, then a large one),
    /// and the guess is the tangent line's.
    fn guess(&self, x_left: T, dx: T) -> T {
        let bend = dx * (self.a + self.b * dx);
        let bend = if bend.abs() <= T::one() {
            bend
        } else {
            T::zero()
        };
        x_left + dx * (self.w + bend)
    }
}

/// Mechanical series connection of two elements (`a.series(b)`): the same
/// force passes through both, their displacements add,
///
/// `x = x_L + x_R`,  `F = L[x_L] = R[x_R]`,
///
/// with optional travel limits on the left element, `x_L ∈ [lo, hi]` (for a
/// [`TravelLimits::Gap`] with start `r0`, `x_R = x − r0 − x_L`). At a
/// limit the left element stops (its input is held at the limit, so its
/// state stops evolving) and a contact force `N = R[x_R] − L[x_L]` makes up
/// the difference; the contact only pushes (into the stop). The output is
/// `F = R[x_R]` at a limit; when free, the force of the softer element
/// (smaller tangent), whose error from the solver tolerance `δ` on the split
/// is the smaller, `|F'| δ`.
///
/// Every sample solves `L[x_L] − R[x − x_L] = 0` for `x_L` from the
/// committed states. For non-decreasing elements the residual is
/// increasing, the root lies between the previous split and the previous
/// split plus the input increment, and is found by the safeguarded
/// Newton/bisection of this crate to the tolerance of [`SolverOptions`];
/// beyond a limit the split is clamped there. After a sample whose split
/// was a root inside the limits, the solver starts from a predicted split,
/// the cubic in `Δx` with the split and its slope `w = R'/(L' + R')`
/// (from the tangents) at that root and at the one before (the same
/// direction only; else the tangent line), which leaves two or three
/// Newton steps to the tolerance on a smooth input; where both elements
/// give their second derivatives ([`Hints::trial_curvature`]) and the
/// predicted split lies inside the limits, one Halley step from it
/// (both elements trialled there) leaves one or two; where the contact at
/// a limit lets go, the Halley step is taken from just inside the limit
/// (`2^-30` of the travel), where the left element's tangent is the one
/// away from it. Where both elements are flat
/// (two saturated friction elements) the split is not unique and the solver
/// returns one point of the flat set.
///
/// Tangent: `L'R'/(L' + R')` when free, `R'` at a limit.
///
/// Not to be confused with [`Cascade`](crate::Cascade) (signal flow).
///
/// ```
/// use hysteron_composition::OperatorExt;
/// use hysteron_operators::{Gain, Operator};
/// // Two linear springs: k1 k2 / (k1 + k2).
/// let mut m = Gain::new(2.0_f64).unwrap().series(Gain::new(3.0).unwrap());
/// let f = m.run(&[1.0]).unwrap();
/// assert!((f[0] - 1.2).abs() < 1e-14);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct MechanicalSeries<T, L, R> {
    left: L,
    right: R,
    limits: TravelLimits<T>,
    opts: SolverOptions<T>,
    /// The committed split and the pending one of a trial.
    s: Staged<State<T>>,
    /// Whether no parameter carries anything in the probe slot (found at
    /// the first trial after construction, new limits or `reset`, which
    /// `set_params` calls).
    params_probe_free: Option<bool>,
    /// Whether both elements give their second derivative
    /// ([`Hints::trial_curvature`]), found at the first predicted split
    /// after construction or `reset`.
    curvature: Option<bool>,
}

impl<T: Float, L, R> MechanicalSeries<T, L, R> {
    /// `left` and `right` in series, without travel limits.
    pub fn new(left: L, right: R) -> Self {
        Self {
            left,
            right,
            limits: TravelLimits::None,
            opts: SolverOptions::default(),
            s: Staged::new(State::at(T::zero(), T::zero())),
            params_probe_free: None,
            curvature: None,
        }
    }

    /// Limits the travel of the left element.
    pub fn with_limits(mut self, limits: TravelLimits<T>) -> Result<Self> {
        limits.validate()?;
        self.limits = limits;
        self.params_probe_free = None;
        Ok(self)
    }

    /// Uses the given solver tolerances.
    pub fn with_solver(mut self, opts: SolverOptions<T>) -> Self {
        self.opts = opts;
        self
    }

    /// The committed displacement of the left element.
    pub fn left_displacement(&self) -> T {
        self.s.committed().x_left
    }

    /// The left element.
    pub fn left(&self) -> &L {
        &self.left
    }

    /// The right element.
    pub fn right(&self) -> &R {
        &self.right
    }

    /// The travel limits.
    pub fn limits(&self) -> TravelLimits<T> {
        self.limits
    }
}

/// The series' residual `L[x_l] − R[x − r0 − x_l]` with both elements
/// trialled, and their trials at the last evaluation.
struct SplitResidual<'a, T, L, R> {
    left: &'a mut L,
    right: &'a mut R,
    x: T,
    r0: T,
    last: (Trial<T>, Trial<T>),
}

/// The residual `L − R` and its slope at a split, and the left and right
/// elements' trials there.
type SplitEval<T> = ((T, T), (Trial<T>, Trial<T>));

/// The left element trialled at the split `xl` and the right one at
/// `x_r − xl` (`x_r = x − r0`): their trials, and the residual `L − R`
/// with its slope `L' + R'`.
///
/// The two trials are independent; the right element (in the paper's
/// model the spring, with the longer chain of dependent operations) is
/// trialled first so that the left one's instructions fit in the
/// processor's window while it waits: Bouc-Wen then MMS in a Newton loop
/// took 36.8 ns per step, MMS then Bouc-Wen 48.9 ns (Zen 5, scratch loop).
/// Inlined, so that the trials' values stay in registers: returned through
/// memory, they were written as two 8-byte stores and read back as one
/// 16-byte load, which the processor cannot forward (it waits for the
/// stores to reach the cache).
#[inline(always)]
fn trial_split<T: Float, L: Operator<T>, R: Operator<T>>(
    left: &mut L,
    right: &mut R,
    x_r: T,
    xl: T,
) -> Result<SplitEval<T>> {
    let r = right.trial(x_r - xl)?;
    let l = left.trial(xl)?;
    Ok(((l.output - r.output, l.tangent + r.tangent), (l, r)))
}

/// The split for the right element's share `x_r = x − r0` searched on the
/// elements' values ([`Hints::trial_value`]) from `from` (over `T`, taken
/// as values), with the steps a search over `T` takes; `None` where an
/// element has no value path or the search fails.
fn split_on_values<T: Float, L: Operator<T>, R: Operator<T>>(
    left: &mut L,
    right: &mut R,
    x_r: f64,
    from: &Start<T>,
    opts: &SolverOptions<T>,
) -> Option<Root<f64>> {
    let values = |xl: f64| -> Result<(f64, f64)> {
        let no_path = || Error::NonFiniteInput { value: xl };
        let l = left.trial_value(xl).ok_or_else(no_path)??;
        let r = right.trial_value(x_r - xl).ok_or_else(no_path)??;
        Ok((l.output - r.output, l.tangent + r.tangent))
    };
    let v = |t: T| t.as_f64();
    let from = Start {
        x0: v(from.x0),
        step: v(from.step),
        hint: from.hint.map(v),
        bounds: from.bounds.map(|(lo, hi)| (v(lo), v(hi))),
        guess: from.guess.map(v),
        evaluated: None,
        scale: v(from.scale),
    };
    solve("series", values, from, &opts.cast_scalar()).ok()
}

/// The series' force and tangent at its split `root` from the elements'
/// trials `l` and `r` there: at a travel limit the right element's; inside,
/// the compliances add, and the force is that of the element with the
/// smaller stiffness.
fn force_at<T: Float>(root: &Root<T>, l: Trial<T>, r: Trial<T>) -> (T, T) {
    match root {
        Root::AtBound(_) => (r.output, r.tangent),
        Root::Inside(_) => {
            let sum = l.tangent + r.tangent;
            // A rigid element (tangent ±∞) adds no compliance: the
            // stiffness is the other one's (∞/∞ = NaN otherwise).
            let tangent = if l.tangent.is_infinite() {
                r.tangent
            } else if r.tangent.is_infinite() {
                l.tangent
            } else if sum == T::zero() {
                T::zero()
            } else {
                l.tangent * r.tangent / sum
            };
            // The split is exact to the solver tolerance δ; the element
            // with the smaller stiffness carries the smaller force
            // error (|F'| δ), so its force is reported.
            let force = if l.tangent.abs() <= r.tangent.abs() {
                l.output
            } else {
                r.output
            };
            (force, tangent)
        }
    }
}

impl<T: Float, L: Child<T>, R: Child<T>> Residual<T> for SplitResidual<'_, T, L, R> {
    fn eval(&mut self, xl: T) -> Result<(T, T)> {
        let (e, last) = trial_split(self.left, self.right, self.x - self.r0, xl)?;
        self.last = last;
        Ok(e)
    }

    fn fold_probe(&mut self, along: &T) -> bool {
        let folded = self.left.fold_probe(along) && self.right.fold_probe(along);
        if folded {
            let (l, r) = &mut self.last;
            for v in [&mut l.output, &mut l.tangent, &mut r.output, &mut r.tangent] {
                v.fold_probe(along);
            }
        }
        folded
    }
}

/// The split after one Halley step from the predicted split `g` on the
/// residual `r(x_L) = L[x_L] − R[x_r − x_L]` (`x_r = x − r0`), with both
/// elements trialled at `g`:
///
/// `g − 2 r r' / (2 r'² − r r'')`,  `r' = L' + R'`,  `r'' = L'' − R''`,
///
/// whose error is `O(e³)` for a guess `e` off (Newton's is `O(e²)`), so
/// that the root finder, started there, mostly stops after one more
/// evaluation. Where the step is not finite, its denominator not
/// positive, or it is longer than twice Newton's, Newton's; where a trial
/// fails, `g` (the root finder reports it). The second value says whether
/// both elements gave their second derivatives (`None`: not known, a
/// trial failed).
///
/// # Reference
/// J. F. Traub, *Iterative Methods for the Solution of Equations*,
/// Prentice-Hall 1964, §5.2 (Halley's iteration).
#[inline(always)]
fn halley<T: Float, L: Operator<T>, R: Operator<T>>(
    left: &mut L,
    right: &mut R,
    x_r: T,
    g: T,
) -> (T, Option<bool>) {
    let Ok(((res, d), _)) = trial_split(left, right, x_r, g) else {
        return (g, None);
    };
    let (Some(lc), Some(rc)) = (left.trial_curvature(), right.trial_curvature()) else {
        return (g, Some(false));
    };
    let two = T::lit(2.0);
    let c = lc - rc;
    let newton = res / d;
    let denominator = two * d * d - res * c;
    let step = two * res * d / denominator;
    let halley_ok = step.is_finite() && denominator > T::zero() && step.abs() <= two * newton.abs();
    let next = g - if halley_ok { step } else { newton };
    (if next.is_finite() { next } else { g }, Some(true))
}

/// How far inside a travel limit, as a fraction of the travel, the
/// series starts its search where the contact there lets go.
const LEAVING: f64 = 1.0 / (1u64 << 30) as f64;

/// Samples per stretch that [`MechanicalSeries::process`] hands to the
/// right element at a travel limit.
const HOLD_CHUNK: usize = 256;

impl<T: Float, L: Operator<T>, R: Operator<T>> MechanicalSeries<T, L, R> {
    /// Runs `xs` (at most [`HOLD_CHUNK`] samples) with the left element held
    /// at its committed split `xl`, which lies at the limit `lo` or `hi`,
    /// for as long as the contact pushes into that limit, and returns how
    /// many samples were committed (outputs in `ys`).
    ///
    /// Per sample this is what `trial` + `commit` do there: the solver's
    /// first evaluation is at the committed split (clamped: `xl`), the
    /// left element at `xl` and the right one at `x − r0 − xl`; if the
    /// residual `L − R` keeps its sign into the limit (negative at `hi`,
    /// positive at `lo`) the root is [`Root::AtBound`] there and the force
    /// is `R`. The right element runs the stretch in its batch loop, which
    /// tests before each commit whether the contact holds: through
    /// [`process_while_beyond`] with the left element's force
    /// where that element rests when held (trialled once), else through
    /// [`process_while`], which trials and commits the left
    /// element per sample. The first sample where the contact does not
    /// hold (or any error) is left uncommitted for `trial` to take over.
    // `xs.len() ≤ HOLD_CHUNK`: the only caller, `process`, passes at most
    // `HOLD_CHUNK` samples.
    #[allow(clippy::indexing_slicing)]
    #[inline]
    fn hold_run(&mut self, xs: &[T], ys: &mut [T], xl: T, lo: T, hi: T, r0: T) -> usize {
        let mut zs = [T::zero(); HOLD_CHUNK];
        let zs = &mut zs[..xs.len()];
        for (z, &x) in zs.iter_mut().zip(xs) {
            *z = x - r0 - xl;
        }
        let (left, right) = (&mut self.left, &mut self.right);
        // A left element that rests when held is trialled at `xl` once (and
        // committed if the contact holds for a sample): its output there
        // stands for every sample of the stretch (the same bits a trial
        // would give), and the contact holds while the force stays beyond
        // it, which the right element tests in its batch loop.
        let rests = left.rests_when_held();
        let n = if rests {
            let Ok(l) = left.trial(xl) else {
                return 0;
            };
            let beyond = if xl == hi {
                Beyond::Above(l.output)
            } else {
                Beyond::Below(l.output)
            };
            // (`min`: the contract of `process_while_beyond`, which a
            // foreign operator may break)
            let n = process_while_beyond(right, zs, ys, beyond).min(xs.len());
            if n > 0 {
                left.commit();
            }
            n
        } else {
            Self::hold_by_trials(left, right, zs, ys, xl, lo, hi)
        };
        if let Some(&x) = n.checked_sub(1).and_then(|k| xs.get(k)) {
            self.s.set(State::at(x, xl));
        }
        n
    }

    /// The stretch of [`hold_run`](Self::hold_run) for a left element that
    /// does not rest when held: trialled at `xl` for each sample, and
    /// committed while the contact pushes into the limit.
    fn hold_by_trials(
        left: &mut L,
        right: &mut R,
        zs: &[T],
        ys: &mut [T],
        xl: T,
        lo: T,
        hi: T,
    ) -> usize {
        let zero = T::zero();
        let mut keep = |_: usize, force: T| {
            let Ok(l) = left.trial(xl) else {
                return false;
            };
            let res = l.output - force;
            let holds = ((xl == hi && res < zero) || (xl == lo && res > zero)) && force.is_finite();
            if holds {
                left.commit();
            }
            holds
        };
        // (`min`: `n ≤ zs.len()` is the contract of `process_while`, which a
        // foreign operator may break)
        process_while(right, zs, ys, &mut keep).min(zs.len())
    }
}

impl<T: Float, L: Child<T>, R: Child<T>> Operator<T> for MechanicalSeries<T, L, R> {
    fn name(&self) -> &'static str {
        "series"
    }

    /// Solves `L[x_L] = R[x − r0 − x_L]` for the split `x_L` from the
    /// committed one. While the left element rests at a travel limit and
    /// the contact still pushes into it, the solver would return after its
    /// first evaluation, at the committed split: that evaluation is made
    /// directly (the same calls on the same arguments), which is what
    /// makes single steps at a stop cheap; anything else goes to the
    /// solver, which starts with that same evaluation.
    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        self.s.discard();
        let x = check_input(x)?;
        // (see `Feedback`)
        let probe_free = T::CARRIES_DERIVATIVES && x.probe_free() && {
            let free = params_probe_free(self.params_probe_free, &*self);
            self.params_probe_free = Some(free);
            free
        };
        let (left, right) = (&mut self.left, &mut self.right);
        let r0 = self.limits.start();
        // Where the contact at a limit lets go: a point just inside it,
        // on the branch the left element takes away from the limit.
        let mut leaving = None;
        if let Some((lo, hi)) = self.limits.bounds() {
            // The solver's start, clamped as it clamps it.
            let xl = self.s.committed().x_left.max(lo).min(hi);
            if xl == hi || xl == lo {
                if let (Ok(l), Ok(r)) = (left.trial(xl), right.trial(x - r0 - xl)) {
                    let res = l.output - r.output;
                    let holds = (xl == hi && res < T::zero()) || (xl == lo && res > T::zero());
                    if holds && r.output.is_finite() {
                        self.s.stage(State::at(x, xl));
                        return Ok(r);
                    }
                    let inside = (hi - lo) * T::lit(LEAVING);
                    leaving = Some(if xl == hi { xl - inside } else { xl + inside });
                }
            }
        }
        let s = *self.s.committed();
        let dx = x - s.x;
        let start = s.x_left;
        let scale = x.abs().max(start.abs());
        let bounds = self.limits.bounds();
        // The committed split moved as its share says (cubic in `dx`),
        // refined by one third-order step where the elements give their
        // second derivatives.
        let guess = s.share.map(|w| w.guess(start, dx));
        // Where the Halley step starts: the predicted split strictly inside
        // the limits (one at or beyond a limit is left to the root finder,
        // which holds the split there in one evaluation if the contact
        // pushes), or, leaving a limit, just inside it, where the left
        // element's tangent is the one away from the limit (at the limit
        // it is the one into it).
        let halley_from = match guess {
            Some(g) => Some(g).filter(|&g| bounds.is_none_or(|(lo, hi)| g > lo && g < hi)),
            None => leaving,
        };
        // The evaluation at the Halley step's end, made here: where it is
        // the root by the root finder's rule, the root finder is skipped,
        // else it starts from that evaluation.
        let mut evaluated = None;
        let guess = match halley_from {
            Some(p) if !T::CARRIES_DERIVATIVES && self.curvature != Some(false) => {
                let (g, known) = halley(left, right, x - r0, p);
                self.curvature = known.or(self.curvature);
                let inside = g.is_finite() && bounds.is_none_or(|(lo, hi)| g > lo && g < hi);
                if known == Some(true) && inside {
                    // (a failed trial or a NaN residual is left to the
                    // root finder, which reports it)
                    evaluated = trial_split(left, right, x - r0, g)
                        .ok()
                        .filter(|(e, _)| !e.0.is_nan());
                }
                Some(g)
            }
            _ => guess,
        };
        let from = Start {
            x0: start,
            step: dx,
            hint: Some(start + dx),
            bounds,
            guess,
            evaluated: evaluated.map(|(e, _)| e),
            scale,
        };
        // Over dual numbers, the split is searched on values where both
        // elements have a value path (see `Feedback`), and any failure of
        // that search leaves it to the dual numbers from the start.
        let by_value = if T::CARRIES_DERIVATIVES {
            split_on_values(left, right, x.as_f64() - r0.as_f64(), &from, &self.opts)
        } else {
            None
        };
        let mut residual = SplitResidual {
            left: &mut self.left,
            right: &mut self.right,
            x,
            r0,
            last: evaluated.map_or((Trial::default(), Trial::default()), |(_, last)| last),
        };
        let root = match (evaluated, from.guess) {
            (Some((e, _)), Some(g)) if root_at_guess(g, e, &self.opts) => Some(Root::Inside(g)),
            _ => root_from_values("series", &mut residual, by_value, bounds, probe_free)?,
        };
        let root = match root {
            Some(root) => root,
            None => solve("series", |xl| residual.eval(xl), from, &self.opts)?,
        };
        let (l, r) = residual.last;
        let (force, tangent) = force_at(&root, l, r);
        if !force.is_finite() {
            return Err(Error::NonFiniteOutput {
                operator: "series",
                input: x.as_f64(),
            });
        }
        let share = match root {
            Root::Inside(xl) => Share::new(l.tangent, r.tangent, dx, xl - start, s.share),
            Root::AtBound(_) => None,
        };
        self.s.stage(State {
            x,
            x_left: root.value(),
            share,
        });
        Ok(Trial {
            output: force,
            tangent,
        })
    }

    /// The trial + commit loop, with a shortcut while the left element
    /// rests at a travel limit and the contact holds: there `trial`'s
    /// solver returns after its first evaluation, at the committed split,
    /// so that evaluation is made directly (the same calls on the same
    /// arguments) over a stretch of samples, without setting up the
    /// solver: the right element runs the stretch in its batch loop
    /// ([`process_while`]), asked before each commit whether the
    /// contact still holds, which trials and commits the left element at
    /// the limit. The first sample where the contact lets go (or the
    /// residual is exactly zero, or an error occurs) is left to `trial`,
    /// which starts from the same committed state, so the results are
    /// bit-identical to the trial + commit loop.
    // `ys.len() == xs.len()` (`check_lengths`); `i < xs.len()` by the loop
    // condition, `i + m ≤ xs.len()` by the choice of `m`, and `hold_run`
    // returns `n ≤ m`, so `i` stays `< xs.len()` unless `n == m` (continue).
    #[allow(clippy::indexing_slicing)]
    fn process(&mut self, xs: &[T], ys: &mut [T]) -> Result<()> {
        check_lengths(xs, ys)?;
        self.s.discard();
        let bounds = self.limits.bounds();
        let r0 = self.limits.start();
        let mut i = 0;
        while i < xs.len() {
            if let Some((lo, hi)) = bounds {
                // The solver's start, clamped as it clamps it.
                let xl = self.s.committed().x_left.max(lo).min(hi);
                if xl == hi || xl == lo {
                    let m = (xs.len() - i).min(HOLD_CHUNK);
                    let n = self.hold_run(&xs[i..i + m], &mut ys[i..i + m], xl, lo, hi, r0);
                    i += n;
                    if n == m {
                        continue;
                    }
                }
            }
            let t = self.trial(xs[i]).map_err(|e| e.at_sample(i))?;
            self.commit();
            ys[i] = t.output;
            i += 1;
        }
        Ok(())
    }

    fn commit(&mut self) {
        if self.s.commit() {
            self.left.commit();
            self.right.commit();
        }
    }

    fn reset(&mut self) {
        self.left.reset();
        self.right.reset();
        self.s.set(State::at(T::zero(), T::zero()));
        self.params_probe_free = None;
        self.curvature = None;
    }
}

/// The value-only trial, where both elements give theirs: the steps of
/// `trial` over dual numbers, on values. The split is found to a
/// tolerance, so a second search at a held input may move it within that
/// tolerance (no rest); a curvature or a fold would be implicit
/// derivatives of their own (not derived).
impl<T: Float, L: Child<T>, R: Child<T>> Hints<T> for MechanicalSeries<T, L, R> {
    /// The values `trial` computes over dual numbers: at a travel limit
    /// where the contact holds, the right element's; else the split the
    /// search on values finds (which `trial` keeps as its split's value)
    /// and the force and tangent from the elements' values there. `None`
    /// where `trial` would search over dual numbers instead (no value path,
    /// a failed search, a split inside the limits where `∂R/∂x_L` is 0 or
    /// not finite).
    fn trial_value(&mut self, x: f64) -> Option<Result<Trial<f64>>> {
        self.s.discard();
        if !(T::CARRIES_DERIVATIVES && x.is_finite()) {
            return None;
        }
        let value = |t: Trial<f64>| Some(Ok(t));
        let r0 = self.limits.start();
        let x_r = x - r0.as_f64();
        let bounds = self.limits.bounds();
        if let Some((lo, hi)) = bounds {
            let xl = self.s.committed().x_left.max(lo).min(hi);
            if xl == hi || xl == lo {
                let xl = xl.as_f64();
                let (l, r) = (
                    self.left.trial_value(xl)?,
                    self.right.trial_value(x_r - xl)?,
                );
                if let (Ok(l), Ok(r)) = (l, r) {
                    let res = l.output - r.output;
                    let holds =
                        (xl == hi.as_f64() && res < 0.0) || (xl == lo.as_f64() && res > 0.0);
                    if holds && r.output.is_finite() {
                        return value(r);
                    }
                }
            }
        }
        let s = *self.s.committed();
        let dx = T::lit(x) - s.x;
        let start = s.x_left;
        let from = Start {
            x0: start,
            step: dx,
            hint: Some(start + dx),
            bounds,
            guess: s.share.map(|w| w.guess(start, dx)),
            evaluated: None,
            scale: T::lit(x).abs().max(start.abs()),
        };
        let root = split_on_values(&mut self.left, &mut self.right, x_r, &from, &self.opts)?;
        let xl = root.value();
        if let Root::AtBound(b) = root {
            // (`trial` takes a bound's derivatives from the bound itself)
            bounds.filter(|&(lo, hi)| lo.as_f64() == b || hi.as_f64() == b)?;
        }
        let l = match self.left.trial_value(xl)? {
            Ok(l) => l,
            Err(e) => return Some(Err(e)),
        };
        let r = match self.right.trial_value(x_r - xl)? {
            Ok(r) => r,
            Err(e) => return Some(Err(e)),
        };
        if let Root::Inside(_) = root {
            let d = l.tangent + r.tangent;
            if !(d != 0.0 && d.is_finite()) {
                return None;
            }
        }
        let (force, tangent) = force_at(&root, l, r);
        if !force.is_finite() {
            return Some(Err(Error::NonFiniteOutput {
                operator: "series",
                input: x,
            }));
        }
        value(Trial {
            output: force,
            tangent,
        })
    }
}

impl<T: Float, L: Child<T>, R: Child<T>> Derivatives<T> for MechanicalSeries<T, L, R> {
    fn to_dual(&self) -> Option<Box<dyn Operator<Dual>>> {
        let (a, b) = (self.left.to_dual()?, self.right.to_dual()?);
        let series = MechanicalSeries::new(a, b)
            .with_limits(self.limits.cast_scalar())
            .ok()?
            .with_solver(self.opts.cast_scalar());
        Some(Box::new(series))
    }
}

impl<T: Float, L: Child<T>, R: Child<T>> SamplePeriod<T> for MechanicalSeries<T, L, R> {
    fn set_sample_period(&mut self, dt: T) -> Result<()> {
        self.left.set_sample_period(dt)?;
        self.right.set_sample_period(dt)
    }
}

impl<T: Float, L: Child<T>, R: Child<T>> Parameters<T> for MechanicalSeries<T, L, R> {
    fn n_params(&self) -> usize {
        self.limits.values().len() + self.left.n_params() + self.right.n_params()
    }

    fn params_into(&self, out: &mut Vec<T>) {
        out.extend(self.limits.values());
        self.left.params_into(out);
        self.right.params_into(out);
    }

    fn param_domains(&self) -> Vec<Domain> {
        let mut d = self.limits.domains();
        d.extend(pair_domains(&self.left, &self.right));
        d
    }

    fn param_names(&self) -> Vec<String> {
        let mut names = self.limits.names();
        names.extend(pair_names(&self.left, &self.right, ["left", "right"]));
        names
    }

    // `p.len() == self.n_params() ≥ k` (`check::count`; the limits' values
    // are the first `k` parameters).
    #[allow(clippy::indexing_slicing)]
    fn set_params(&mut self, p: &[T]) -> Result<()> {
        check::count(self.n_params(), p)?;
        let k = self.limits.values().len();
        let limits = self.limits.with_values(&p[..k])?;
        set_pair(&mut self.left, &mut self.right, &p[k..], ["left", "right"])?;
        self.limits = limits;
        self.reset();
        Ok(())
    }
}
