//! The admissible range of each parameter, for optimizers.

use crate::{check, Error, Float, Result};
use serde::{Deserialize, Serialize};

/// Where a parameter may lie, as reported by
/// [`Parameters::param_domains`](crate::Parameters::param_domains).
///
/// This is the per-parameter part of the validation; constraints that tie
/// parameters together (a saturation's `lo < hi`, increasing knot
/// positions, a gap start within the gap) are only checked by
/// `set_params`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Domain {
    /// Any finite value.
    Real,
    /// `≥ 0`.
    NonNegative,
    /// `> 0`.
    Positive,
    /// `≤ 0`.
    NonPositive,
    /// `≥` the given value.
    AtLeast(f64),
    /// `[0, 1]`.
    UnitInterval,
}

/// The domain as a constraint on its value: `≥ 0`, `> 0`, `∈ [0, 1]`,
/// `real` (any finite value).
///
/// ```
/// use hysteron_operators::Domain;
/// assert_eq!(Domain::NonNegative.to_string(), "≥ 0");
/// assert_eq!(Domain::AtLeast(1.0).to_string(), "≥ 1");
/// ```
impl std::fmt::Display for Domain {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Domain::Real => write!(f, "real"),
            Domain::NonNegative => write!(f, "≥ 0"),
            Domain::Positive => write!(f, "> 0"),
            Domain::NonPositive => write!(f, "≤ 0"),
            Domain::AtLeast(a) => write!(f, "≥ {a}"),
            Domain::UnitInterval => write!(f, "∈ [0, 1]"),
        }
    }
}

impl Domain {
    /// Whether `v` lies in the domain (finite values only).
    pub fn contains(&self, v: f64) -> bool {
        v.is_finite()
            && match *self {
                Domain::Real => true,
                Domain::NonNegative => v >= 0.0,
                Domain::Positive => v > 0.0,
                Domain::NonPositive => v <= 0.0,
                Domain::AtLeast(a) => v >= a,
                Domain::UnitInterval => (0.0..=1.0).contains(&v),
            }
    }

    /// Checks `v` against the domain, as an [`Error::InvalidParameter`]
    /// naming `name` (the messages of [`check`](crate::check)).
    pub fn check<T: Float>(&self, name: &str, v: T) -> Result<()> {
        match *self {
            Domain::Real => check::finite(name, v),
            Domain::NonNegative => check::non_negative(name, v),
            Domain::Positive => check::positive(name, v),
            Domain::NonPositive => check::non_positive(name, v),
            Domain::UnitInterval => check::unit_interval(name, v),
            Domain::AtLeast(1.0) => check::at_least_one(name, v),
            Domain::AtLeast(a) => {
                check::finite(name, v)?;
                if v.as_f64() >= a {
                    Ok(())
                } else {
                    Err(Error::InvalidParameter {
                        name: name.to_string(),
                        value: v.as_f64(),
                        reason: "must be ≥ its lower bound",
                    })
                }
            }
        }
    }
}
