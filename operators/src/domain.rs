//! The admissible range of each parameter, for optimizers.

use serde::{Deserialize, Serialize};

/// Where a parameter may lie, as reported by
/// [`Operator::param_domains`](crate::Operator::param_domains).
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
}
