//! Parameter validation helpers shared by all operators and combinators.
//!
//! Each returns an [`Error::InvalidParameter`] naming the field.

use crate::{Error, Float, Result};

/// The error naming parameter `name`, its `value` and the `reason` it is
/// refused.
pub fn invalid<T: Float>(name: &str, value: T, reason: &'static str) -> Error {
    Error::InvalidParameter {
        name: name.to_string(),
        value: value.as_f64(),
        reason,
    }
}

/// `Ok` where `holds`, else the error naming `name`, `value` and `reason`.
pub fn require<T: Float>(holds: bool, name: &str, value: T, reason: &'static str) -> Result<()> {
    if holds {
        Ok(())
    } else {
        Err(invalid(name, value, reason))
    }
}

/// `level / k` must be a finite displacement, and not rounded to 0 from a
/// positive `level`: an element that works in `level / k` (a friction
/// level over its spring's stiffness) needs it.
pub fn level_over_stiffness<T: Float>(name: &str, level: T, k: T) -> Result<()> {
    let r = level / k;
    require(
        r.is_finite() && !(level > T::zero() && r == T::zero()),
        name,
        level,
        "the level / k must be a finite, non-zero number when the level is > 0",
    )
}

/// The initial force `f0` over the stiffness `k` must be finite.
pub fn start_over_stiffness<T: Float>(f0: T, k: T) -> Result<()> {
    require((f0 / k).is_finite(), "f0", f0, "f0 / k must be finite")
}

/// `value` must be finite.
pub fn finite<T: Float>(name: &str, value: T) -> Result<()> {
    require(value.is_finite(), name, value, "must be finite")
}

/// `value` must be finite and `≥ 0`.
pub fn non_negative<T: Float>(name: &str, value: T) -> Result<()> {
    finite(name, value)?;
    require(value >= T::zero(), name, value, "must be ≥ 0")
}

/// `value` must be finite and `> 0`.
pub fn positive<T: Float>(name: &str, value: T) -> Result<()> {
    finite(name, value)?;
    require(value > T::zero(), name, value, "must be > 0")
}

/// Stores `value` in `slot` once it is finite and `> 0` (a sample period,
/// for example); `slot` keeps its value on error.
pub fn set_positive<T: Float>(name: &str, slot: &mut T, value: T) -> Result<()> {
    positive(name, value)?;
    *slot = value;
    Ok(())
}

/// `value` must be finite and `≤ 0`.
pub fn non_positive<T: Float>(name: &str, value: T) -> Result<()> {
    finite(name, value)?;
    require(value <= T::zero(), name, value, "must be ≤ 0")
}

/// `value` must be finite and `≥ 1`.
pub fn at_least_one<T: Float>(name: &str, value: T) -> Result<()> {
    finite(name, value)?;
    require(value >= T::one(), name, value, "must be ≥ 1")
}

/// `value` must be finite and in `[0, 1]`.
pub fn unit_interval<T: Float>(name: &str, value: T) -> Result<()> {
    finite(name, value)?;
    require(
        value >= T::zero() && value <= T::one(),
        name,
        value,
        "must lie in [0, 1]",
    )
}

/// `hi` must be strictly greater than `lo` (both finite).
pub fn ordered<T: Float>(lo_name: &str, lo: T, hi_name: &str, hi: T) -> Result<()> {
    finite(lo_name, lo)?;
    finite(hi_name, hi)?;
    require(hi > lo, hi_name, hi, "must be greater than the lower limit")
}

/// A parameter slice must have exactly `expected` entries.
pub fn count<T>(expected: usize, p: &[T]) -> Result<()> {
    if p.len() == expected {
        Ok(())
    } else {
        Err(Error::ParamCount {
            expected,
            got: p.len(),
        })
    }
}

/// The lengths of a bank of elements: `k` has at least one entry, the
/// other per-element parameter `(name, len)` as many, and `f0` none or as
/// many (the error names `k` or `name`).
pub fn element_lengths(k: usize, (name, len): (&str, usize), f0: usize) -> Result<()> {
    require(k > 0, "k", 0.0, "needs at least one element")?;
    let same = len == k && (f0 == 0 || f0 == k);
    require(
        same,
        name,
        len as f64,
        "must have one entry per element of k, as must f0 if given",
    )
}
