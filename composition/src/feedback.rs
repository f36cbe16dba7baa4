//! Feedback: `y = A[x − B[y]]`, solved implicitly every sample.

use crate::solve::{
    params_probe_free, root_from_values, solve, Residual, Root, SolverOptions, Start,
};
use crate::Child;
use hysteron_operators::{
    check_input, CastScalar, Derivatives, Dual, Error, Float, Hints, Operator, Result, Trial,
};

/// Negative feedback loop `y = A[x − B[y]]` (`a.feedback(b)`), with `A`
/// in the forward path and `B` in the return path.
///
/// Every sample solves `R(y) = y − A[x − B[y]] = 0` from the committed
/// states with the safeguarded Newton/bisection of this crate (the
/// residual derivative is `1 + A'·B'`, so for non-decreasing `A` and `B`
/// the root is unique and is bracketed). The tolerance is that of
/// [`SolverOptions`]; a loop without a solution is an error, never a guess.
/// The Newton steps start from the root extrapolated from the last four
/// committed outputs (a cubic), then, if they stall, from the committed
/// root.
/// Tangent: `dy/dx = A' / (1 + A'·B')`.
///
/// Over dual numbers, where both children have a value path
/// ([`Hints::trial_value`]), the root is searched on values (the steps
/// the search over dual numbers would take, bit for bit) and the children
/// are evaluated over dual numbers twice, at the root: once for `∂R/∂p`,
/// once with the implicit function theorem's `∂y/∂p = −(∂R/∂p)/(∂R/∂y)`.
/// Elsewhere the search runs over dual numbers (one evaluation per step and
/// one more at the root).
///
/// ```
/// use hysteron_composition::OperatorExt;
/// use hysteron_operators::{Gain, Operator};
/// // a/(1 + a b) with a = 4, b = 0.5
/// let mut m = Gain::new(4.0_f64).unwrap().feedback(Gain::new(0.5).unwrap());
/// let y = m.run(&[3.0]).unwrap();
/// assert!((y[0] - 3.0 * 4.0 / 3.0).abs() < 1e-14);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Feedback<T, A, B> {
    forward: A,
    back: B,
    opts: SolverOptions<T>,
    x: T,
    y: T,
    /// The three committed outputs before `y`, newest first, for the
    /// prediction of the next root.
    before: [T; 3],
    /// Whether no parameter carries anything in the probe slot (found at
    /// the first trial after construction or `reset`, which `set_params`
    /// calls).
    params_probe_free: Option<bool>,
    pending: Option<(T, T)>,
}

impl<T: Float, A, B> Feedback<T, A, B> {
    /// `y = forward[x − back[y]]`.
    pub fn new(forward: A, back: B) -> Self {
        Self {
            forward,
            back,
            opts: SolverOptions::default(),
            x: T::zero(),
            y: T::zero(),
            before: [T::zero(); 3],
            params_probe_free: None,
            pending: None,
        }
    }

    /// Uses the given solver tolerances.
    pub fn with_solver(mut self, opts: SolverOptions<T>) -> Self {
        self.opts = opts;
        self
    }
}

impl<T: Float, A, B> Feedback<T, A, B> {
    /// The next root predicted by the cubic through the last four
    /// committed outputs, `4 y_k − 6 y_{k−1} + 4 y_{k−2} − y_{k−3}`: for a
    /// smooth response its error is `O(Δt⁴)`, so the Newton steps from it
    /// converge in two evaluations where the committed root took three (the
    /// Bouc-Wen benchmark system at 15 kHz: 3.0 → 2.0 per sample). A poor
    /// prediction (a reversal, a jump of the input) costs Newton steps from
    /// it; where they stall, the search starts again from the committed
    /// root.
    fn guess(&self) -> T {
        let [y1, y2, y3] = self.before;
        T::lit(4.0) * (self.y + y2) - T::lit(6.0) * y1 - y3
    }
}

impl<T: Float, A: Child<T>, B: Child<T>> Feedback<T, A, B> {
    /// The root for input `x` searched on the children's values
    /// ([`Hints::trial_value`]) from the committed root and the prediction
    /// `guess`, with the steps a search over `T` takes; `None` where a
    /// child has no value path or the search fails.
    fn root_on_values(&mut self, x: f64, guess: T) -> Option<Root<f64>> {
        let (forward, back) = (&mut self.forward, &mut self.back);
        let values = |y: f64| -> Result<(f64, f64)> {
            let no_path = || Error::NonFiniteInput { value: y };
            let b = back.trial_value(y).ok_or_else(no_path)??;
            let a = forward.trial_value(x - b.output).ok_or_else(no_path)??;
            Ok((y - a.output, 1.0 + a.tangent * b.tangent))
        };
        let start =
            Start::at_committed(self.y.as_f64(), self.x.as_f64(), x).with_guess(guess.as_f64());
        solve("feedback", values, start, &self.opts.cast_scalar()).ok()
    }
}

/// The loop's tangent `A'/(1 + A'B')` from the children's tangents `ta`,
/// `tb` at the root.
fn loop_tangent<T: Float>(ta: T, tb: T) -> T {
    let loop_gain = T::one() + ta * tb;
    if ta.is_infinite() {
        // a vertical forward path: the limit of A'/(1 + A'B') is 1/B',
        // or A' itself where B' = 0 (∞/∞ or ∞·0 would be NaN)
        if tb == T::zero() {
            ta
        } else {
            T::one() / tb
        }
    } else if tb.is_infinite() {
        // a vertical back path: A'/(1 + A'B') → 0 as B' → ∞, and it is
        // 0 for a flat forward path too (where 0·∞ would be NaN)
        T::zero()
    } else if loop_gain == T::zero() {
        T::infinity()
    } else {
        ta / loop_gain
    }
}

/// The loop's residual `R(y) = y − A[x − B[y]]` with both children
/// trialled, and their tangents at the last evaluation.
struct LoopResidual<'a, T, A, B> {
    forward: &'a mut A,
    back: &'a mut B,
    x: T,
    tangents: (T, T),
}

impl<T: Float, A: Child<T>, B: Child<T>> Residual<T> for LoopResidual<'_, T, A, B> {
    fn eval(&mut self, y: T) -> Result<(T, T)> {
        let b = self.back.trial(y)?;
        let a = self.forward.trial(self.x - b.output)?;
        self.tangents = (a.tangent, b.tangent);
        Ok((y - a.output, T::one() + a.tangent * b.tangent))
    }

    fn fold_probe(&mut self, along: &T) -> bool {
        let folded = self.back.fold_probe(along) && self.forward.fold_probe(along);
        if folded {
            self.tangents.0.fold_probe(along);
            self.tangents.1.fold_probe(along);
        }
        folded
    }
}

impl<T: Float, A: Child<T>, B: Child<T>> Operator<T> for Feedback<T, A, B> {
    fn name(&self) -> &'static str {
        "feedback"
    }

    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        self.pending = None;
        let x = check_input(x)?;
        let guess = self.guess();
        // (the probe slot is free where the input and the parameters carry
        // nothing in it; a child with a scalar of its own there refuses to
        // fold)
        let probe_free = T::CARRIES_DERIVATIVES && x.probe_free() && {
            let free = params_probe_free(self.params_probe_free, &*self);
            self.params_probe_free = Some(free);
            free
        };
        // Over dual numbers, the root is searched on values where both
        // children have a value path (`trial_value`), and the children are
        // evaluated over dual numbers at the root only; any failure of
        // that search leaves the solve to the dual numbers from the start.
        let by_value = if T::CARRIES_DERIVATIVES {
            self.root_on_values(x.as_f64(), guess)
        } else {
            None
        };
        let mut residual = LoopResidual {
            forward: &mut self.forward,
            back: &mut self.back,
            x,
            tangents: (T::zero(), T::zero()),
        };
        let root = root_from_values("feedback", &mut residual, by_value, None, probe_free)?;
        let y = match root {
            Some(root) => root.value(),
            None => {
                let start = Start::at_committed(self.y, self.x, x).with_guess(guess);
                solve("feedback", |y| residual.eval(y), start, &self.opts)?.value()
            }
        };
        let (ta, tb) = residual.tangents;
        let tangent = loop_tangent(ta, tb);
        self.pending = Some((x, y));
        Ok(Trial { output: y, tangent })
    }

    fn commit(&mut self) {
        if let Some((x, y)) = self.pending.take() {
            self.forward.commit();
            self.back.commit();
            self.x = x;
            let [y1, y2, _] = self.before;
            self.before = [self.y, y1, y2];
            self.y = y;
        }
    }

    fn reset(&mut self) {
        self.forward.reset();
        self.back.reset();
        self.x = T::zero();
        self.y = T::zero();
        self.before = [T::zero(); 3];
        self.params_probe_free = None;
        self.pending = None;
    }
}

/// The value-only trial, where both children give theirs: the search on
/// values that `trial` makes over dual numbers, and the children's values
/// at its root. The loop's root is found to a tolerance, so a second search
/// at a held input may move it within that tolerance (no rest); a
/// curvature or a fold would be implicit derivatives of their own (not
/// derived).
impl<T: Float, A: Child<T>, B: Child<T>> Hints<T> for Feedback<T, A, B> {
    /// The values `trial` computes over dual numbers: the root of the
    /// search on values (which `trial` keeps as its output's value), and
    /// the tangent from the children's values there; `None` where `trial`
    /// would search over dual numbers instead (no value path, a failed
    /// search, a root where `∂R/∂y` is 0 or not finite).
    fn trial_value(&mut self, x: f64) -> Option<Result<Trial<f64>>> {
        self.pending = None;
        if !(T::CARRIES_DERIVATIVES && x.is_finite()) {
            return None;
        }
        let Root::Inside(y) = self.root_on_values(x, self.guess())? else {
            return None;
        };
        let b = match self.back.trial_value(y)? {
            Ok(b) => b,
            Err(e) => return Some(Err(e)),
        };
        let a = match self.forward.trial_value(x - b.output)? {
            Ok(a) => a,
            Err(e) => return Some(Err(e)),
        };
        let d = 1.0 + a.tangent * b.tangent;
        if !(d != 0.0 && d.is_finite()) {
            return None;
        }
        Some(Ok(Trial {
            output: y,
            tangent: loop_tangent(a.tangent, b.tangent),
        }))
    }
}

impl<T: Float, A: Child<T>, B: Child<T>> Derivatives<T> for Feedback<T, A, B> {
    fn to_dual(&self) -> Option<Box<dyn Operator<Dual>>> {
        let (a, b) = (self.forward.to_dual()?, self.back.to_dual()?);
        Some(Box::new(
            Feedback::new(a, b).with_solver(self.opts.cast_scalar()),
        ))
    }
}

crate::pair::pair_traits!(Feedback<T, A, B>, [T: Float, A: Child<T>, B: Child<T>], forward, back);
