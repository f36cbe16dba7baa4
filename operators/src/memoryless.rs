//! Shared batch loop for memoryless operators.

use crate::{check_lengths, Error, Float, Result};

/// Applies `f` sample by sample. A non-finite input, or a non-finite
/// output of `operator` (a huge gain overflows), is an error at its sample:
/// the first failing sample, as the trial/commit loop would report it.
#[inline(always)]
pub(crate) fn map_samples<T: Float>(
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
