//! Reparametrization: each bounded parameter is fitted through an
//! unconstrained internal variable `θ`, so the solver never steps outside
//! its domain.

use hysteron_operators::Domain;

/// Smallest distance a starting value keeps from an open bound (relative to
/// `max(1, |bound|)`): a start exactly on the bound is moved inside by this.
pub const BOUNDARY_NUDGE: f64 = 1e-9;

/// The map `p = φ(θ)` for one domain:
///
/// | domain | `p = φ(θ)` |
/// |---|---|
/// | `Real` | `θ` |
/// | `Positive`, `NonNegative` | `e^θ` |
/// | `NonPositive` | `−e^θ` |
/// | `AtLeast(a)` | `a + e^θ` |
/// | `UnitInterval` | `1 / (1 + e^{−θ})` |
///
/// Closed bounds (`≥ 0`, `n ≥ 1`, `w ∈ [0, 1]`) are reached only in the
/// limit; a start on such a bound is nudged inside by [`BOUNDARY_NUDGE`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reparam(pub Domain);

impl Reparam {
    /// `θ = φ⁻¹(p)` (with starts on a bound nudged inside).
    pub fn to_internal(&self, p: f64) -> f64 {
        let nudge = |bound: f64| BOUNDARY_NUDGE * bound.abs().max(1.0);
        match self.0 {
            Domain::Real => p,
            Domain::Positive | Domain::NonNegative => p.max(nudge(0.0)).ln(),
            Domain::NonPositive => (-p).max(nudge(0.0)).ln(),
            Domain::AtLeast(a) => (p - a).max(nudge(a)).ln(),
            Domain::UnitInterval => {
                let q = p.clamp(nudge(0.0), 1.0 - nudge(1.0));
                (q / (1.0 - q)).ln()
            }
        }
    }

    /// `p = φ(θ)`.
    pub fn to_external(&self, t: f64) -> f64 {
        match self.0 {
            Domain::Real => t,
            Domain::Positive | Domain::NonNegative => t.exp(),
            Domain::NonPositive => -t.exp(),
            Domain::AtLeast(a) => a + t.exp(),
            Domain::UnitInterval => 1.0 / (1.0 + (-t).exp()),
        }
    }

    /// `dp/dθ` at `θ`.
    pub fn derivative(&self, t: f64) -> f64 {
        match self.0 {
            Domain::Real => 1.0,
            Domain::Positive | Domain::NonNegative | Domain::AtLeast(_) => t.exp(),
            Domain::NonPositive => -t.exp(),
            Domain::UnitInterval => {
                let s = 1.0 / (1.0 + (-t).exp());
                s * (1.0 - s)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_and_derivatives() {
        let cases = [
            (Domain::Real, -3.5),
            (Domain::Positive, 0.02),
            (Domain::NonNegative, 7.0),
            (Domain::NonPositive, -0.3),
            (Domain::AtLeast(1.0), 1.7),
            (Domain::UnitInterval, 0.25),
        ];
        for (d, p) in cases {
            let r = Reparam(d);
            let t = r.to_internal(p);
            assert!(
                (r.to_external(t) - p).abs() <= 1e-12 * p.abs().max(1.0),
                "{d:?}"
            );
            let h = 1e-6;
            let fd = (r.to_external(t + h) - r.to_external(t - h)) / (2.0 * h);
            assert!(
                (fd - r.derivative(t)).abs() <= 1e-6 * fd.abs().max(1e-3),
                "{d:?}"
            );
            assert!(d.contains(r.to_external(t + 30.0)) && d.contains(r.to_external(t - 30.0)));
        }
    }

    #[test]
    fn starts_on_a_bound_are_nudged_inside() {
        let r = Reparam(Domain::AtLeast(1.0));
        assert!(r.to_external(r.to_internal(1.0)) > 1.0);
        let u = Reparam(Domain::UnitInterval);
        assert!(u.to_external(u.to_internal(0.0)) > 0.0);
        assert!(u.to_external(u.to_internal(1.0)) < 1.0);
    }
}
