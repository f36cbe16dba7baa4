//! The core trait: a scalar operator with memory, driven sample by sample
//! through a trial/commit protocol.

use crate::{Derivatives, Error, Float, Hints, Parameters, Result, SamplePeriod};
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
/// Three methods are required; the rest of what an operator offers sits
/// behind its own small trait, each a supertrait so that a boxed operator
/// keeps it:
/// * [`Parameters`]: the flat parameter vector (derived from the
///   declaration for every leaf);
/// * [`SamplePeriod`]: the sample period of rate-dependent nodes;
/// * [`Derivatives`]: the same operator over dual numbers;
/// * [`Hints`]: fast paths that implicit combinators may take (every one
///   has a default that is always correct).
///
/// # Initial state convention
/// Every operator starts in a state defined at input `x = 0`: its initial
/// state parameters (for example the play's `y0` or the Bouc-Wen `h0`)
/// describe the operator there, and the first sample is a transition from
/// `x = 0` like any other.
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
pub trait Operator<T: Float>:
    Parameters<T> + SamplePeriod<T> + Derivatives<T> + Hints<T> + DynClone + Debug + Send + Sync
{
    /// Evaluates output and tangent for input `x` from the committed state,
    /// and keeps the result as the pending state.
    fn trial(&mut self, x: T) -> Result<Trial<T>>;

    /// Accepts the last successful trial as the committed state.
    fn commit(&mut self);

    /// Returns to the initial state and drops any pending trial.
    fn reset(&mut self);

    /// A short lower-case name of the operator kind (`"play"`, `"cascade"`,
    /// …): the spec `type`, and the segment that names its parameters in
    /// a combinator's paths. The default is the Rust type's name, without
    /// its path and generics.
    fn name(&self) -> &'static str {
        let full = core::any::type_name::<Self>();
        let base = full.split('<').next().unwrap_or(full);
        base.rsplit("::").next().unwrap_or(base)
    }

    /// Runs `xs` through the operator from its current state, writing `ys`.
    ///
    /// Equivalent to `trial` + `commit` per sample, bit for bit. On an error
    /// at sample `i` the samples before `i` are committed, the error is an
    /// [`Error::AtSample`] naming `i`, and the contents of `ys` are
    /// unspecified.
    fn process(&mut self, xs: &[T], ys: &mut [T]) -> Result<()> {
        process_by_trials(self, xs, ys)
    }

    /// Runs `xs` through the operator from its current state and returns the
    /// outputs in a new vector ([`process`](Operator::process)).
    fn run(&mut self, xs: &[T]) -> Result<Vec<T>> {
        let mut ys = vec![T::zero(); xs.len()];
        self.process(xs, &mut ys)?;
        Ok(ys)
    }

    // End of interface.
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

/// A boxed operator is an operator: boxed models built at run time compose
/// with static ones. (Its other traits forward in their own modules.)
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
    fn run(&mut self, xs: &[T]) -> Result<Vec<T>> {
        (**self).run(xs)
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
