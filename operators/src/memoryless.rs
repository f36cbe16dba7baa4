//! Memoryless laws: an output that depends on the present input alone.

use crate::{check_lengths, Declared, Error, Float, Result, Trial};

/// A law without memory, `y = f(x)` with the tangent `f'(x)`: a
/// [`StepLaw`](crate::StepLaw) whose state is `()` (dead-zone, saturation, gain, offset,
/// a backlash contact). [`memoryless_step_law!`](crate::memoryless_step_law)
/// makes it a step law from [`eval`](Memoryless::eval), whose batch loop
/// runs [`value`](Memoryless::value).
pub trait Memoryless<T: Float>: Declared<T> {
    /// The output `f(x)` and the tangent `f'(x)` (a one-sided derivative
    /// at a kink).
    fn eval(&self, x: T) -> Trial<T>;

    /// The output `f(x)` alone, for the batch loop (default: `eval`'s).
    #[inline(always)]
    fn value(&self, x: T) -> T {
        self.eval(x).output
    }
}

/// Implements [`StepLaw`](crate::StepLaw) for a [`Memoryless`] law: the
/// state `()`, the step `eval`, the batch loop `value` sample by sample
/// with the driver's checks.
#[macro_export]
macro_rules! memoryless_step_law {
    ($name:ident) => {
        impl<T: $crate::Float> $crate::StepLaw<T> for $name<T> {
            type State = ();

            fn initial(&self) {}

            #[inline(always)]
            fn step(&self, _: &(), x: T) -> $crate::Result<((), $crate::Trial<T>)> {
                Ok(((), $crate::Memoryless::eval(self, x)))
            }

            fn run(&self, _: &mut (), xs: &[T], ys: &mut [T]) -> $crate::Result<()> {
                $crate::memoryless::map_samples(<Self as $crate::Declared<T>>::KIND, xs, ys, |x| {
                    $crate::Memoryless::value(self, x)
                })
            }
        }
    };
}

/// Applies `f` sample by sample. A non-finite input, or a non-finite
/// output of `operator` (a huge gain overflows), is an error at its sample:
/// the first failing sample, as the trial/commit loop would report it.
#[inline(always)]
pub fn map_samples<T: Float>(
    operator: &'static str,
    xs: &[T],
    ys: &mut [T],
    f: impl Fn(T) -> T,
) -> Result<()> {
    check_lengths(xs, ys)?;
    for (i, (&x, y)) in xs.iter().zip(ys.iter_mut()).enumerate() {
        if !x.is_finite() {
            return Err(Error::NonFiniteInput { value: x.as_f64() }.at_sample(i));
        }
        let v = f(x);
        if !v.is_finite() {
            return Err(Error::NonFiniteOutput {
                operator,
                input: x.as_f64(),
            }
            .at_sample(i));
        }
        *y = v;
    }
    Ok(())
}
