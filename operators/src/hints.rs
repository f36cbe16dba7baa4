//! Solver hints: fast paths an implicit combinator may take through its
//! children, each with a default that is always correct.

use crate::{Float, Operator, Result, Trial};

/// Fast paths of an operator that combinators may take: a batch loop that
/// runs while a condition holds, and four hints to implicit solvers.
///
/// Every method has a default that is always correct (a loop of trials,
/// `false`, `None`); an operator overrides what it can do faster. A
/// combinator forwards them from its children where its own equation
/// allows, so that a model keeps its fast paths however it is composed; the
/// contract test checks every registered leaf inside every combinator.
///
/// Consumers: `MechanicalSeries` of the composition crate runs an
/// element with [`process_while_beyond`] at a travel limit, skips its
/// trials where it [`rests_when_held`](Hints::rests_when_held), and takes a Halley step
/// with [`trial_curvature`](Hints::trial_curvature); `Feedback` searches
/// its root on values with [`trial_value`](Hints::trial_value) and folds
/// the root's derivatives into its children's states with
/// [`fold_probe`](Hints::fold_probe).
pub trait Hints<T: Float> {
    /// The operator's own loop for [`process_while`]: the same samples,
    /// outputs and state, bit for bit, or `None` (the default) where it has
    /// none and the function runs trials.
    fn batch_while(&mut self, xs: &[T], ys: &mut [T], keep: &mut Keep<'_, T>) -> Option<usize> {
        let _ = (xs, ys, keep);
        None
    }

    /// The operator's own loop for [`process_while_beyond`], testing the
    /// bound inside the loop without a call through `keep` per sample; the
    /// same samples, outputs and state as [`process_while`] with
    /// [`Beyond::admits`] as `keep`, bit for bit, or `None` (the default).
    fn batch_while_beyond(&mut self, xs: &[T], ys: &mut [T], beyond: Beyond<T>) -> Option<usize> {
        let _ = (xs, ys, beyond);
        None
    }

    /// Whether holding the input still changes nothing: after `trial(x)`
    /// and `commit()`, every later `trial(x)` at the same `x` returns the
    /// same output, bit for bit, and committing it leaves the state as it
    /// is. Rate-independent operators whose step at an unchanged input
    /// keeps their state have it; anything that integrates over time (a
    /// damper, LuGre) does not. The default, `false`, is always safe.
    ///
    /// A combinator may then skip a child's trials while that child's
    /// input stays put: a `MechanicalSeries` of the composition crate,
    /// holding its left element at a travel limit, trials it once per
    /// stretch instead of once per sample.
    ///
    /// ```
    /// use hysteron_operators::{Hints, Mms, ViscousDamper};
    /// assert!(Mms::new(1.0_f64, 5.0).unwrap().rests_when_held());
    /// assert!(!ViscousDamper::new(2.0_f64, 0.1).unwrap().rests_when_held());
    /// ```
    fn rests_when_held(&self) -> bool {
        false
    }

    /// The second derivative `d²y/dx²` of the output at the pending trial,
    /// on the branch that trial took (the derivative of its tangent), or
    /// `None` where the operator does not give it (the default) or there
    /// is no pending trial.
    ///
    /// An implicit combinator may take a third-order (Halley) step with it
    /// from its predicted root: a `MechanicalSeries` of the composition
    /// crate does, from its predicted split, where both its elements give
    /// it.
    ///
    /// # Requirements
    /// * where the tangent is differentiable at the pending trial's input,
    ///   the derivative of the tangent along the branch that trial took
    ///   (to rounding); at a kink, a one-sided one;
    /// * it changes nothing: no state, no pending trial.
    ///
    /// ```
    /// use hysteron_operators::{Hints, Mms, Operator};
    /// let mut f = Mms::new(2.0_f64, 50.0).unwrap();
    /// let (x, h) = (0.01, 1e-6);
    /// let c = { f.trial(x).unwrap(); f.trial_curvature().unwrap() };
    /// let fd = (f.trial(x + h).unwrap().tangent - f.trial(x - h).unwrap().tangent) / (2.0 * h);
    /// assert!((c - fd).abs() < 1e-6 * c.abs());
    /// ```
    fn trial_curvature(&self) -> Option<T> {
        None
    }

    /// The output and tangent of [`trial`](crate::Operator::trial) at an input of
    /// value `x`, computed on values alone, or `None` where the operator has
    /// no such path (the default) or not at this input.
    ///
    /// Over a scalar that carries derivatives ([`Dual`](crate::Dual)) a trial computes
    /// every derivative along with the value. An implicit combinator
    /// (`feedback` of the composition crate) searches its root with this
    /// method and evaluates its children over dual numbers only at the
    /// root, where the implicit function theorem gives the root's
    /// derivatives: two trials over dual numbers per sample instead of one
    /// per step of the search and one more.
    ///
    /// # Requirements
    /// * `Some(Ok(t))`: `t.output` and `t.tangent` are the values of the
    ///   output and tangent of `trial(x')` for every `x'` of value `x`, bit
    ///   for bit (so a search on them takes the steps a search over `T`
    ///   takes);
    /// * `Some(Err(_))` where `trial` fails, and `None`: the caller goes
    ///   back to `trial`;
    /// * it leaves no pending trial: a [`commit`](crate::Operator::commit) right
    ///   after it changes nothing.
    ///
    /// ```
    /// use hysteron_operators::{Dual, Hints, MassSpringDamper, Operator};
    /// let mut msd = MassSpringDamper::new(Dual::variable(2.0, 0), Dual::constant(10.0),
    ///     Dual::constant(5e4), Dual::constant(1e-3)).unwrap();
    /// let v = msd.trial_value(3.0).unwrap().unwrap();
    /// let t = msd.trial(Dual::constant(3.0)).unwrap();
    /// assert_eq!((v.output, v.tangent), (t.output.re, t.tangent.re));
    /// ```
    fn trial_value(&mut self, x: f64) -> Option<Result<Trial<f64>>> {
        let _ = x;
        None
    }

    /// Folds the probe slot of the pending trial's state into its other
    /// derivative slots ([`Differentiable::fold_probe`](crate::Differentiable::fold_probe)
    /// on every scalar of it, with `along` the input's derivatives), and
    /// says whether it did; `false` (the default) where the operator cannot
    /// or there is no pending trial.
    ///
    /// An implicit combinator over dual numbers evaluates its children at
    /// the root once, with the root seeded in the probe slot (the last
    /// derivative slot, where no parameter and no input carries anything),
    /// so the pending states carry their derivatives at the root held
    /// fixed and with respect to the root. Once the implicit function
    /// theorem gives the root's derivatives `along`, folding gives the
    /// states those of a trial at the root with them, without a second
    /// trial. Where a child answers `false`, the combinator trials it again.
    ///
    /// # Requirements
    /// * every scalar the pending state holds is folded, so a
    ///   [`commit`](crate::Operator::commit) after it commits what a trial at an
    ///   input carrying `along`'s derivatives would have left, to rounding
    ///   (the chain rule applied after the step instead of within it);
    /// * the values are not changed.
    ///
    /// ```
    /// use hysteron_operators::{Differentiable, DualN, Hints, MassSpringDamper, Operator};
    /// type D = DualN<2>;
    /// let msd = |m| MassSpringDamper::new(m, D::constant(10.0), D::constant(5e4),
    ///     D::constant(1e-3)).unwrap();
    /// // a trial at an input seeded in slot 0, and one at a probed input folded
    /// let mut direct = msd(D::variable(2.0, 0));
    /// let along = D { re: 3.0, eps: [0.5, 0.0] };
    /// let y = direct.trial(along).unwrap().output;
    /// let mut probed = msd(D::variable(2.0, 0));
    /// probed.trial(D::constant(3.0).probe()).unwrap();
    /// assert!(probed.fold_probe(&along));
    /// probed.commit();
    /// direct.commit();
    /// let (a, b) = (direct.trial(D::constant(3.0)).unwrap().output,
    ///               probed.trial(D::constant(3.0)).unwrap().output);
    /// assert_eq!(a.re, b.re);
    /// assert!((a.eps[0] - b.eps[0]).abs() <= 1e-15 * a.eps[0].abs());
    /// assert_eq!(b.eps[1], 0.0);
    /// # let _ = y;
    /// ```
    fn fold_probe(&mut self, along: &T) -> bool {
        let _ = along;
        false
    }
}

/// Runs `xs` through the operator like [`process`](crate::Operator::process)
/// while `keep(i, y_i)` accepts each output `y_i`, and returns how many
/// samples `n` were committed (their outputs are in `ys[..n]`).
///
/// Sample by sample equivalent to `trial`, then `keep`, then `commit`,
/// bit for bit: the first sample whose trial fails or whose output
/// `keep` rejects is not committed and ends the run (it may be left as
/// the pending trial, as a `trial` there leaves it; the next `trial`
/// replaces it), so `n < xs.len()` says that sample `n` was refused; the
/// error itself is not returned (a `trial` at that sample reproduces
/// it). `keep` is called once per evaluated sample, in order.
/// The contents of `ys[n..]` are unspecified; `xs` and `ys` of different
/// lengths run over the shorter.
///
/// Combinators use it to run a child over a stretch of samples that
/// lasts while a condition on its output holds (a `MechanicalSeries` of
/// the composition crate, at a travel limit, runs its spring until the
/// contact lets go).
///
/// ```
/// use hysteron_operators::{process_while, Operator, Play};
/// let mut play = Play::new(0.5_f64).unwrap();
/// let mut ys = [0.0; 4];
/// // run while the output stays below 0.9: sample 2 (output 1.0) is refused
/// let n = process_while(&mut play, &[1.0, 1.25, 1.5, 0.0], &mut ys, &mut |_, y| y < 0.9);
/// assert_eq!((n, ys[0], ys[1]), (2, 0.5, 0.75));
/// assert_eq!(play.trial(1.0).unwrap().output, 0.75); // the state after sample 1
/// ```
pub fn process_while<T: Float, O: Operator<T> + ?Sized>(
    op: &mut O,
    xs: &[T],
    ys: &mut [T],
    keep: &mut Keep<'_, T>,
) -> usize {
    match op.batch_while(xs, ys, keep) {
        Some(n) => n,
        None => process_while_by_trials(op, xs, ys, keep),
    }
}

/// [`process_while`] with the condition
/// `beyond` ([`Beyond::admits`]): runs while each output is finite and
/// strictly beyond a bound. The same samples and bits as
/// `process_while` with that condition as `keep`; an operator with a
/// batch loop tests the bound inside it ([`Hints::batch_while_beyond`]).
///
/// A `MechanicalSeries` of the composition crate runs its right element
/// with it while the left one rests at a travel limit: the contact holds
/// while the force stays beyond the left element's force.
///
/// ```
/// use hysteron_operators::{process_while_beyond, Beyond, Play};
/// let mut play = Play::new(0.5_f64).unwrap();
/// let mut ys = [0.0; 4];
/// let n = process_while_beyond(&mut play, &[1.0, 1.25, 1.5, 0.0], &mut ys, Beyond::Below(0.9));
/// assert_eq!((n, ys[0], ys[1]), (2, 0.5, 0.75));
/// ```
pub fn process_while_beyond<T: Float, O: Operator<T> + ?Sized>(
    op: &mut O,
    xs: &[T],
    ys: &mut [T],
    beyond: Beyond<T>,
) -> usize {
    match op.batch_while_beyond(xs, ys, beyond) {
        Some(n) => n,
        None => process_while(op, xs, ys, &mut |_, y| beyond.admits(y)),
    }
}

/// The condition of [`process_while`]: called with the sample
/// index and the trial output, it says whether to commit the sample.
pub type Keep<'a, T> = dyn FnMut(usize, T) -> bool + 'a;

/// The condition of [`process_while_beyond`]: an output strictly
/// beyond a bound, and finite.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Beyond<T> {
    /// `y > bound`.
    Above(T),
    /// `y < bound`.
    Below(T),
}

impl<T: Float> Beyond<T> {
    /// Whether `y` is finite and strictly beyond the bound (never where the
    /// bound is NaN).
    ///
    /// ```
    /// use hysteron_operators::Beyond;
    /// assert!(Beyond::Above(1.0).admits(1.5) && !Beyond::Above(1.0).admits(1.0));
    /// assert!(Beyond::Below(1.0).admits(-3.0) && !Beyond::Below(1.0).admits(1.0));
    /// assert!(!Beyond::Above(1.0).admits(f64::INFINITY) && !Beyond::Below(1.0).admits(f64::NAN));
    /// assert!(!Beyond::Above(f64::NAN).admits(2.0) && Beyond::Above(f64::NEG_INFINITY).admits(2.0));
    /// ```
    #[inline(always)]
    pub fn admits(self, y: T) -> bool {
        y.is_finite()
            && match self {
                Beyond::Above(bound) => y > bound,
                Beyond::Below(bound) => y < bound,
            }
    }
}

/// The default [`process_while`](crate::process_while): `trial`, `keep`, `commit` per
/// sample (for overrides that fall back to it).
pub fn process_while_by_trials<T: Float, O: Operator<T> + ?Sized>(
    op: &mut O,
    xs: &[T],
    ys: &mut [T],
    keep: &mut Keep<'_, T>,
) -> usize {
    for (i, (x, y)) in xs.iter().zip(ys.iter_mut()).enumerate() {
        match op.trial(*x) {
            Ok(t) if keep(i, t.output) => {
                op.commit();
                *y = t.output;
            }
            _ => return i,
        }
    }
    xs.len().min(ys.len())
}

/// A boxed operator takes its operator's fast paths.
impl<T: Float> Hints<T> for Box<dyn Operator<T>> {
    fn batch_while(&mut self, xs: &[T], ys: &mut [T], keep: &mut Keep<'_, T>) -> Option<usize> {
        (**self).batch_while(xs, ys, keep)
    }
    fn batch_while_beyond(&mut self, xs: &[T], ys: &mut [T], beyond: Beyond<T>) -> Option<usize> {
        (**self).batch_while_beyond(xs, ys, beyond)
    }
    fn rests_when_held(&self) -> bool {
        (**self).rests_when_held()
    }
    #[inline]
    fn trial_curvature(&self) -> Option<T> {
        (**self).trial_curvature()
    }
    #[inline]
    fn trial_value(&mut self, x: f64) -> Option<Result<Trial<f64>>> {
        (**self).trial_value(x)
    }
    #[inline]
    fn fold_probe(&mut self, along: &T) -> bool {
        (**self).fold_probe(along)
    }
}
