//! The core trait: a scalar operator with memory, driven sample by sample
//! through a trial/commit protocol.

use crate::{Domain, Dual, Error, Float, Result};
use core::fmt::Debug;
use dyn_clone::DynClone;

/// The result of a trial step: the output and its tangent `dy/dx`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Trial<T> {
    /// Output `y` for the trial input.
    pub output: T,
    /// Tangent `dy/dx` at the trial input, given the committed state.
    ///
    /// Hysteresis operators have kinks (play at a reversal, saturation at a
    /// limit): there the tangent is one-sided, taken in the direction of the
    /// current motion. It may be `0` (a flat region) or, for an inverse of a
    /// flat operator, `+∞`; solvers use it only as a hint inside a bracket.
    pub tangent: T,
}

/// A scalar-in, scalar-out operator with memory.
///
/// # Protocol
/// * [`trial`](Operator::trial) evaluates the output for an input sample
///   from the **committed** state only. It may be called any number of times
///   (an implicit solver probes several inputs); only the last one is kept as
///   pending, and a trial that is not committed leaves no trace.
/// * [`commit`](Operator::commit) accepts the last successful trial as the new
///   committed state. Without a pending trial it does nothing.
/// * [`reset`](Operator::reset) returns to the initial state (which is given
///   by the parameters) and drops any pending trial.
/// * [`process`](Operator::process) runs a batch as a trial + commit loop;
///   operators may override it for speed, with bit-identical results.
///
/// # Initial state convention
/// Every operator starts in a state defined at input `x = 0`: its initial
/// state parameters (for example the play's `y0` or the Bouc-Wen `h0`)
/// describe the operator there, and the first sample is a transition from
/// `x = 0` like any other.
///
/// # Parameters
/// [`params`](Operator::params) gives a flat vector, depth-first through
/// combinators, that [`set_params`](Operator::set_params) accepts back.
/// `set_params` validates the whole vector first (on error nothing changes),
/// then replaces the parameters and resets the operator.
///
/// # Errors
/// A non-finite input sample is an [`Error::NonFiniteInput`]; a finite
/// input that would produce a non-finite output is an
/// [`Error::NonFiniteOutput`]. Operators never return NaN silently and never
/// panic on user input.
///
/// # Example
/// ```
/// use hysteron_operators::{Operator, Play};
///
/// let mut play = Play::new(0.5_f64).unwrap();
/// let t = play.trial(1.0).unwrap(); // probe: nothing is committed yet
/// assert_eq!((t.output, t.tangent), (0.5, 1.0));
/// play.commit();
/// assert_eq!(play.trial(0.8).unwrap().output, 0.5); // inside the gap
/// ```
pub trait Operator<T: Float>: DynClone + Debug + Send + Sync {
    /// A short lower-case name of the operator kind (`"play"`, `"cascade"`, …).
    fn name(&self) -> &'static str;

    /// Evaluates output and tangent for input `x` from the committed state,
    /// and keeps the result as the pending state.
    fn trial(&mut self, x: T) -> Result<Trial<T>>;

    /// Accepts the last successful trial as the committed state.
    fn commit(&mut self);

    /// Returns to the initial state and drops any pending trial.
    fn reset(&mut self);

    /// Runs `xs` through the operator from its current state, writing `ys`.
    ///
    /// Equivalent to `trial` + `commit` per sample, bit for bit. On an error
    /// at sample `i` the samples before `i` are committed, the error is an
    /// [`Error::AtSample`] naming `i`, and the contents of `ys` are
    /// unspecified.
    fn process(&mut self, xs: &[T], ys: &mut [T]) -> Result<()> {
        process_by_trials(self, xs, ys)
    }

    /// Runs `xs` through the operator like [`process`](Operator::process)
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
    /// use hysteron_operators::{Operator, Play};
    /// let mut play = Play::new(0.5_f64).unwrap();
    /// let mut ys = [0.0; 4];
    /// // run while the output stays below 0.9: sample 2 (output 1.0) is refused
    /// let n = play.process_while(&[1.0, 1.25, 1.5, 0.0], &mut ys, &mut |_, y| y < 0.9);
    /// assert_eq!((n, ys[0], ys[1]), (2, 0.5, 0.75));
    /// assert_eq!(play.trial(1.0).unwrap().output, 0.75); // the state after sample 1
    /// ```
    fn process_while(&mut self, xs: &[T], ys: &mut [T], keep: &mut Keep<'_, T>) -> usize {
        process_while_by_trials(self, xs, ys, keep)
    }

    /// [`process_while`](Operator::process_while) with the condition
    /// `beyond` ([`Beyond::admits`]): runs while each output is finite and
    /// strictly beyond a bound. The same samples and bits as
    /// `process_while` with that condition as `keep` (the default does just
    /// that); an operator with a batch loop overrides it to test the bound
    /// inside the loop, without a call through `keep` per sample.
    ///
    /// A `MechanicalSeries` of the composition crate runs its right element
    /// with it while the left one rests at a travel limit: the contact holds
    /// while the force stays beyond the left element's force.
    ///
    /// ```
    /// use hysteron_operators::{Beyond, Operator, Play};
    /// let mut play = Play::new(0.5_f64).unwrap();
    /// let mut ys = [0.0; 4];
    /// let n = play.process_while_beyond(&[1.0, 1.25, 1.5, 0.0], &mut ys, Beyond::Below(0.9));
    /// assert_eq!((n, ys[0], ys[1]), (2, 0.5, 0.75));
    /// ```
    fn process_while_beyond(&mut self, xs: &[T], ys: &mut [T], beyond: Beyond<T>) -> usize {
        self.process_while(xs, ys, &mut |_, y| beyond.admits(y))
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
    /// use hysteron_operators::{Mms, Operator, ViscousDamper};
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
    /// use hysteron_operators::{Mms, Operator};
    /// let mut f = Mms::new(2.0_f64, 50.0).unwrap();
    /// let (x, h) = (0.01, 1e-6);
    /// let c = { f.trial(x).unwrap(); f.trial_curvature().unwrap() };
    /// let fd = (f.trial(x + h).unwrap().tangent - f.trial(x - h).unwrap().tangent) / (2.0 * h);
    /// assert!((c - fd).abs() < 1e-6 * c.abs());
    /// ```
    fn trial_curvature(&self) -> Option<T> {
        None
    }

    /// The output and tangent of [`trial`](Operator::trial) at an input of
    /// value `x`, computed on values alone, or `None` where the operator has
    /// no such path (the default) or not at this input.
    ///
    /// Over a scalar that carries derivatives ([`Dual`]) a trial computes
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
    /// * it leaves no pending trial: a [`commit`](Operator::commit) right
    ///   after it changes nothing.
    ///
    /// ```
    /// use hysteron_operators::{Dual, MassSpringDamper, Operator};
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
    ///   [`commit`](Operator::commit) after it commits what a trial at an
    ///   input carrying `along`'s derivatives would have left, to rounding
    ///   (the chain rule applied after the step instead of within it);
    /// * the values are not changed.
    ///
    /// ```
    /// use hysteron_operators::{Differentiable, DualN, MassSpringDamper, Operator};
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

    /// Runs `xs` through the operator from its current state and returns the
    /// outputs in a new vector.
    fn run(&mut self, xs: &[T]) -> Result<Vec<T>> {
        let mut ys = vec![T::zero(); xs.len()];
        self.process(xs, &mut ys)?;
        Ok(ys)
    }

    /// Sets the sample period `dt > 0` (s) from the structure above: every
    /// rate-dependent node of the tree takes it as the time between the
    /// previous sample and the next; combinators forward it to their
    /// children, and an oversampling node forwards `dt / q`. It may change
    /// between samples (non-uniform records, a variable communication step
    /// in co-simulation). Rate-independent operators only check it.
    ///
    /// ```
    /// use hysteron_operators::{Operator, ViscousDamper};
    /// let mut d = ViscousDamper::new(2.0_f64, 0.1).unwrap();
    /// d.set_sample_period(0.5).unwrap();
    /// assert_eq!(d.run(&[1.0]).unwrap(), vec![4.0]); // 2 · (1 − 0) / 0.5
    /// assert!(d.set_sample_period(-1.0).is_err());
    /// ```
    fn set_sample_period(&mut self, dt: T) -> Result<()> {
        crate::check::positive("dt", dt)
    }

    /// The number of parameters.
    fn n_params(&self) -> usize;

    /// Appends the parameters, depth-first, to `out`.
    fn params_into(&self, out: &mut Vec<T>);

    /// The parameters as a flat vector, depth-first through combinators.
    fn params(&self) -> Vec<T> {
        let mut v = Vec::with_capacity(self.n_params());
        self.params_into(&mut v);
        v
    }

    /// The parameter names, in the order of [`params`](Operator::params);
    /// combinators prefix their children's names with a path.
    fn param_names(&self) -> Vec<String>;

    /// Validates and sets all parameters, then resets the operator.
    /// On error the operator is unchanged.
    fn set_params(&mut self, p: &[T]) -> Result<()>;

    /// The admissible range of each parameter, in the order of
    /// [`params`](Operator::params) (for optimizers that must stay inside
    /// it). The default says every parameter is [`Domain::Real`].
    fn param_domains(&self) -> Vec<Domain> {
        vec![Domain::Real; self.n_params()]
    }

    /// The same operator over the dual scalar [`Dual`], with the same
    /// parameters (as constants: seed them with
    /// [`set_params`](Operator::set_params)) and settings, at its initial
    /// state; `None` where the operator cannot build one.
    ///
    /// Fits use it for exact Jacobians (forward-mode derivatives) and fall
    /// back to finite differences without it. Every leaf
    /// ([`Leaf::cast_leaf`](crate::Leaf::cast_leaf)) and combinator of the
    /// library has one, built from its children's, and so does a model
    /// built from a spec; the default, for an operator of your own, says
    /// `None`.
    fn to_dual(&self) -> Option<Box<dyn Operator<Dual>>> {
        None
    }
}

dyn_clone::clone_trait_object!(<T> Operator<T> where T: Float);

/// The default [`Operator::process`]: `trial` + `commit` per sample (for
/// overrides that fall back to it).
pub fn process_by_trials<T: Float, O: Operator<T> + ?Sized>(
    op: &mut O,
    xs: &[T],
    ys: &mut [T],
) -> Result<()> {
    check_lengths(xs, ys)?;
    for (i, (x, y)) in xs.iter().zip(ys.iter_mut()).enumerate() {
        let t = op.trial(*x).map_err(|e| e.at_sample(i))?;
        op.commit();
        *y = t.output;
    }
    Ok(())
}

/// The condition of [`Operator::process_while`]: called with the sample
/// index and the trial output, it says whether to commit the sample.
pub type Keep<'a, T> = dyn FnMut(usize, T) -> bool + 'a;

/// The condition of [`Operator::process_while_beyond`]: an output strictly
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

/// The default [`Operator::process_while`]: `trial`, `keep`, `commit` per
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

/// A boxed operator is an operator: boxed models built at run time compose
/// with static ones.
impl<T: Float> Operator<T> for Box<dyn Operator<T>> {
    fn name(&self) -> &'static str {
        (**self).name()
    }
    #[inline]
    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        (**self).trial(x)
    }
    #[inline]
    fn commit(&mut self) {
        (**self).commit()
    }
    fn reset(&mut self) {
        (**self).reset()
    }
    fn process(&mut self, xs: &[T], ys: &mut [T]) -> Result<()> {
        (**self).process(xs, ys)
    }
    fn process_while(&mut self, xs: &[T], ys: &mut [T], keep: &mut Keep<'_, T>) -> usize {
        (**self).process_while(xs, ys, keep)
    }
    fn process_while_beyond(&mut self, xs: &[T], ys: &mut [T], beyond: Beyond<T>) -> usize {
        (**self).process_while_beyond(xs, ys, beyond)
    }
    fn run(&mut self, xs: &[T]) -> Result<Vec<T>> {
        (**self).run(xs)
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
    fn set_sample_period(&mut self, dt: T) -> Result<()> {
        (**self).set_sample_period(dt)
    }
    fn n_params(&self) -> usize {
        (**self).n_params()
    }
    fn params_into(&self, out: &mut Vec<T>) {
        (**self).params_into(out)
    }
    fn params(&self) -> Vec<T> {
        (**self).params()
    }
    fn param_names(&self) -> Vec<String> {
        (**self).param_names()
    }
    fn set_params(&mut self, p: &[T]) -> Result<()> {
        (**self).set_params(p)
    }
    fn param_domains(&self) -> Vec<Domain> {
        (**self).param_domains()
    }
    fn to_dual(&self) -> Option<Box<dyn Operator<Dual>>> {
        (**self).to_dual()
    }
}

/// Checks that input and output buffers of a batch have equal length.
#[inline]
pub fn check_lengths<T>(xs: &[T], ys: &[T]) -> Result<()> {
    if xs.len() == ys.len() {
        Ok(())
    } else {
        Err(Error::LengthMismatch {
            input: xs.len(),
            output: ys.len(),
        })
    }
}

/// Returns `Ok(x)` if `x` is finite, else [`Error::NonFiniteInput`].
#[inline(always)]
pub fn check_input<T: Float>(x: T) -> Result<T> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(Error::NonFiniteInput { value: x.as_f64() })
    }
}

/// Returns `Ok(t)` if output and tangent are usable, else
/// [`Error::NonFiniteOutput`] naming `operator` and the input `x`.
///
/// The output must be finite; the tangent must not be NaN (it may be `+∞`
/// where an inverse meets a flat region).
#[inline(always)]
pub fn check_output<T: Float>(operator: &'static str, x: T, t: Trial<T>) -> Result<Trial<T>> {
    if t.output.is_finite() && !t.tangent.is_nan() {
        Ok(t)
    } else {
        Err(Error::NonFiniteOutput {
            operator,
            input: x.as_f64(),
        })
    }
}
