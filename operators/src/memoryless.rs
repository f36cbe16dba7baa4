//! Shared batch loop for memoryless operators.

use crate::{check_lengths, Error, Float, Result};

/// Applies `f` sample by sample, rejecting non-finite inputs.
#[inline(always)]
pub(crate) fn map_samples<T: Float>(xs: &[T], ys: &mut [T], f: impl Fn(T) -> T) -> Result<()> {
    check_lengths(xs, ys)?;
    for (i, (&x, y)) in xs.iter().zip(ys.iter_mut()).enumerate() {
        if !x.is_finite() {
            return Err(Error::NonFiniteInput { value: x.as_f64() }.at_sample(i));
        }
        *y = f(x);
    }
    Ok(())
}

/// Checks a batch's outputs are finite (a huge gain can overflow).
pub(crate) fn check_finite_outputs<T: Float>(
    operator: &'static str,
    xs: &[T],
    ys: &[T],
) -> Result<()> {
    match ys.iter().position(|y| !y.is_finite()) {
        None => Ok(()),
        Some(i) => Err(Error::NonFiniteOutput {
            operator,
            input: xs.get(i).map_or(f64::NAN, |x| x.as_f64()),
        }
        .at_sample(i)),
    }
}
