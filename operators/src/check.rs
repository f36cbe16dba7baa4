//! Parameter validation helpers shared by all operators and combinators.
//!
//! Each returns an [`Error::InvalidParameter`] naming the field.

use crate::{Error, Float, Result};

fn invalid<T: Float>(name: &str, value: T, reason: &'static str) -> Error {
    Error::InvalidParameter {
        name: name.to_string(),
        value: value.as_f64(),
        reason,
    }
}

/// `value` must be finite.
pub fn finite<T: Float>(name: &str, value: T) -> Result<()> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(invalid(name, value, "must be finite"))
    }
}

/// `value` must be finite and `≥ 0`.
pub fn non_negative<T: Float>(name: &str, value: T) -> Result<()> {
    finite(name, value)?;
    if value >= T::zero() {
        Ok(())
    } else {
        Err(invalid(name, value, "must be ≥ 0"))
    }
}

/// `value` must be finite and `> 0`.
pub fn positive<T: Float>(name: &str, value: T) -> Result<()> {
    finite(name, value)?;
    if value > T::zero() {
        Ok(())
    } else {
        Err(invalid(name, value, "must be > 0"))
    }
}

/// `value` must be finite and `≤ 0`.
pub fn non_positive<T: Float>(name: &str, value: T) -> Result<()> {
    finite(name, value)?;
    if value <= T::zero() {
        Ok(())
    } else {
        Err(invalid(name, value, "must be ≤ 0"))
    }
}

/// `value` must be finite and `≥ 1`.
pub fn at_least_one<T: Float>(name: &str, value: T) -> Result<()> {
    finite(name, value)?;
    if value >= T::one() {
        Ok(())
    } else {
        Err(invalid(name, value, "must be ≥ 1"))
    }
}

/// `value` must be finite and in `[0, 1]`.
pub fn unit_interval<T: Float>(name: &str, value: T) -> Result<()> {
    finite(name, value)?;
    if value >= T::zero() && value <= T::one() {
        Ok(())
    } else {
        Err(invalid(name, value, "must lie in [0, 1]"))
    }
}

/// `hi` must be strictly greater than `lo` (both finite).
pub fn ordered<T: Float>(lo_name: &str, lo: T, hi_name: &str, hi: T) -> Result<()> {
    finite(lo_name, lo)?;
    finite(hi_name, hi)?;
    if hi > lo {
        Ok(())
    } else {
        Err(invalid(hi_name, hi, "must be greater than the lower limit"))
    }
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
