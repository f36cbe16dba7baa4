//! An adaptive Dormand–Prince 5(4) integrator for small autonomous
//! systems `dy/ds = f(y)`, used by laws whose state follows an ODE in the
//! input's travel (degrading and pinched Bouc-Wen).
//!
//! The fifth-order solution is propagated (local extrapolation); each
//! sub-step's error is estimated by the embedded fourth-order one and
//! held below `rtol` in the weighted norm `max_i |err_i| / scale_i`, with
//! the caller's scales. Step sizes are chosen on values alone, so a
//! scalar carrying derivatives differentiates the accepted steps: the
//! derivative of the numerical solution, within the tolerance of the
//! exact one. The global error is `O(rtol)` per unit travel of smooth
//! flow. A right-hand side that is continuous but not smooth across a
//! surface (`|z|^n` with `sgn z` at `z = 0`) is integrated side by side:
//! the caller gives the flow of each side, `flow(y, side)`, the side a state
//! is on (`side(y)`, which at the surface is the side the flow enters),
//! and a switching function `switch(y)` whose sign marks the side. A
//! sub-step keeps the side of its start for all its stages, and one that
//! would end across the surface is shortened to end on it (by secant
//! steps). Without that, the values would still meet the tolerance (their
//! local error across a kink is second order in the sub-step) but the
//! derivatives would not: the variational equation's coefficient jumps
//! at the surface, and a stage evaluated on the wrong side, even by a
//! rounding error, makes the sub-step's derivative first order.

use crate::{Error, Float, Result};

/// Sub-steps per call before giving up with [`Error::NotConverged`].
const MAX_SUBSTEPS: usize = 100_000;

/// Integrates `dy/ds = flow(y, side)` from `y` over the travel `s ≥ 0`,
/// keeping each sub-step's weighted error `max_i |err_i| / scale(y)_i`
/// below `rtol`. Each sub-step takes `side(y)` at its start for all its
/// stages, and ends where the switching function `switch(y)` changes
/// sign (to within `snap` of zero; the next sub-step then starts on the
/// other side). `solver` names it in an error.
///
/// Errors: [`Error::NotConverged`] after `MAX_SUBSTEPS` sub-steps, and
/// [`Error::NonFiniteOutput`] (`solver`, at travel `s`) if the state
/// leaves the finite numbers.
pub(crate) fn dopri5<T: Float, const N: usize>(
    flow: impl Fn(&[T; N], bool) -> [T; N],
    (side, switch, snap): (impl Fn(&[T; N]) -> bool, impl Fn(&[T; N]) -> f64, f64),
    mut y: [T; N],
    s: T,
    scale: impl Fn(&[T; N]) -> [f64; N],
    rtol: f64,
    solver: &'static str,
) -> Result<[T; N]> {
    let l = T::lit;
    let travel = s.as_f64();
    if travel <= 0.0 {
        return Ok(y);
    }
    let mut t = 0.0_f64;
    let mut h = travel;
    let mut on = side(&y);
    let mut k1 = flow(&y, on);
    let lin = |y: &[T; N], terms: &[(f64, &[T; N])], h: f64| -> [T; N] {
        let mut out = *y;
        for (i, o) in out.iter_mut().enumerate() {
            let mut sum = T::zero();
            for (c, k) in terms {
                sum = sum + l(*c) * k.get(i).copied().unwrap_or_else(T::zero);
            }
            *o = *o + l(h) * sum;
        }
        out
    };
    for _ in 0..MAX_SUBSTEPS {
        let remaining = travel - t;
        if remaining <= travel * 4.0 * f64::EPSILON {
            return Ok(y);
        }
        let last = h >= remaining;
        if last {
            h = remaining;
        }
        let f = |y: &[T; N]| flow(y, on);
        let k2 = f(&lin(&y, &[(1.0 / 5.0, &k1)], h));
        let k3 = f(&lin(&y, &[(3.0 / 40.0, &k1), (9.0 / 40.0, &k2)], h));
        let k4 = f(&lin(
            &y,
            &[(44.0 / 45.0, &k1), (-56.0 / 15.0, &k2), (32.0 / 9.0, &k3)],
            h,
        ));
        let k5 = f(&lin(
            &y,
            &[
                (19372.0 / 6561.0, &k1),
                (-25360.0 / 2187.0, &k2),
                (64448.0 / 6561.0, &k3),
                (-212.0 / 729.0, &k4),
            ],
            h,
        ));
        let k6 = f(&lin(
            &y,
            &[
                (9017.0 / 3168.0, &k1),
                (-355.0 / 33.0, &k2),
                (46732.0 / 5247.0, &k3),
                (49.0 / 176.0, &k4),
                (-5103.0 / 18656.0, &k5),
            ],
            h,
        ));
        let y5 = lin(
            &y,
            &[
                (35.0 / 384.0, &k1),
                (500.0 / 1113.0, &k3),
                (125.0 / 192.0, &k4),
                (-2187.0 / 6784.0, &k5),
                (11.0 / 84.0, &k6),
            ],
            h,
        );
        let k7 = f(&y5);
        let err = lin(
            &[T::zero(); N],
            &[
                (71.0 / 57600.0, &k1),
                (-71.0 / 16695.0, &k3),
                (71.0 / 1920.0, &k4),
                (-17253.0 / 339200.0, &k5),
                (22.0 / 525.0, &k6),
                (-1.0 / 40.0, &k7),
            ],
            h,
        );
        let finite = y5.iter().chain(&err).all(|v| v.is_finite());
        if !finite && h <= travel * 4.0 * f64::EPSILON {
            // not even the shortest sub-step stays finite
            return Err(Error::NonFiniteOutput {
                operator: solver,
                input: travel,
            });
        }
        let weights = scale(&y);
        // A trial sub-step that leaves the finite numbers (a stage far off
        // the flow on a long first try) is rejected like an inaccurate one.
        let norm = if finite {
            err.iter()
                .zip(weights)
                .map(|(e, w)| e.as_f64().abs() / w.max(f64::MIN_POSITIVE))
                .fold(0.0_f64, f64::max)
        } else {
            f64::INFINITY
        };
        let (before, after) = (switch(&y), switch(&y5));
        if norm <= rtol && before.abs() > snap && (before < 0.0) != (after < 0.0) && after != 0.0 {
            // Crossing the switching surface: end the sub-step short of it,
            // where the secant through the two values meets zero.
            let shorter = h * (before / (before - after)) * (1.0 - 1e-9);
            if shorter > travel * 4.0 * f64::EPSILON {
                h = shorter;
                continue;
            }
        }
        if norm <= rtol || (finite && h <= travel * 4.0 * f64::EPSILON) {
            y = y5;
            t = if last { travel } else { t + h };
            if last {
                return Ok(y);
            }
            let next = side(&y);
            k1 = if next == on { k7 } else { flow(&y, next) };
            on = next;
        }
        // The standard controller: safety 0.9, exponent 1/5, change by a
        // factor within [0.2, 5].
        let factor = if norm == 0.0 {
            5.0
        } else {
            (0.9 * (rtol / norm).powf(0.2)).clamp(0.2, 5.0)
        };
        h *= factor;
    }
    Err(Error::NotConverged {
        solver,
        iterations: MAX_SUBSTEPS,
        width: travel - t,
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    type Sides<const N: usize> = (fn(&[f64; N]) -> bool, fn(&[f64; N]) -> f64, f64);

    /// No switching surface: one side everywhere.
    fn one_side<const N: usize>() -> Sides<N> {
        (|_| true, |_| 1.0, 0.0)
    }

    /// `y' = −y` and the harmonic oscillator against their closed forms.
    #[test]
    fn integrates_linear_systems_to_the_tolerance() {
        let decay = |y: &[f64; 1], _| [-y[0]];
        let y = dopri5(decay, one_side(), [1.0], 3.0, |_| [1.0], 1e-12, "test").unwrap();
        assert!((y[0] - (-3.0_f64).exp()).abs() < 1e-11, "{}", y[0]);
        let oscillator = |y: &[f64; 2], _| [y[1], -y[0]];
        let y = dopri5(
            oscillator,
            one_side(),
            [0.0, 1.0],
            10.0,
            |_| [1.0, 1.0],
            1e-12,
            "test",
        )
        .unwrap();
        assert!((y[0] - 10.0_f64.sin()).abs() < 1e-10, "{}", y[0]);
        assert!((y[1] - 10.0_f64.cos()).abs() < 1e-10, "{}", y[1]);
    }

    /// A flow with a kink at `y = 0`, `y' = 1 − |y|` from `y = −0.5`, side
    /// by side: below 0 `y = −1 + 0.5 e^s` reaches 0 at `s0 = ln 2`, above
    /// it `y = 1 − e^{−(s − s0)}`.
    #[test]
    fn integrates_across_a_kink_side_by_side() {
        let flow = |y: &[f64; 1], up: bool| [if up { 1.0 - y[0] } else { 1.0 + y[0] }];
        let sides: Sides<1> = (|y| y[0] >= 0.0, |y| y[0], 1e-12);
        let s = 2.0;
        let y = dopri5(flow, sides, [-0.5], s, |_| [1.0], 1e-12, "test").unwrap();
        let want = 1.0 - (-(s - 2.0_f64.ln())).exp();
        assert!((y[0] - want).abs() < 1e-10, "{} vs {want}", y[0]);
    }

    /// Across the kink the derivative in the start value is the exact
    /// flow's: from `y0 < 0`, `y = −1 + (1 + y0) e^s` crosses 0 at
    /// `s0 = −ln(1 + y0)`, then `y = 1 − e^{−(s − s0)}`, so
    /// `∂y/∂y0 = −e^{−(s − s0)} ∂s0/∂y0 = e^{−(s − s0)} / (1 + y0)`.
    #[test]
    fn the_derivative_across_a_kink_is_the_exact_flows() {
        use crate::Dual;
        let flow = |y: &[Dual; 1], up: bool| {
            let one = Dual::constant(1.0);
            [if up { one - y[0] } else { one + y[0] }]
        };
        let side = |y: &[Dual; 1]| y[0].as_f64() >= 0.0;
        let switch = |y: &[Dual; 1]| y[0].as_f64();
        let (y0, s) = (-0.5, 2.0);
        let start = Dual::variable(y0, 0);
        let y = dopri5(
            flow,
            (side, switch, 1e-12),
            [start],
            Dual::constant(s),
            |_| [1.0],
            1e-12,
            "test",
        )
        .unwrap();
        let s0 = -(1.0_f64 + y0).ln();
        let want = (-(s - s0)).exp() / (1.0 + y0);
        let got = y[0].eps[0];
        assert!((got - want).abs() < 1e-9, "{got} vs {want}");
    }

    #[test]
    fn an_overflowing_state_is_an_error() {
        let square = |y: &[f64; 1], _| [y[0] * y[0]];
        let e = dopri5(square, one_side(), [1.0], 2.0, |_| [1.0], 1e-10, "blow-up").unwrap_err();
        assert!(
            matches!(
                e,
                Error::NonFiniteOutput { .. } | Error::NotConverged { .. }
            ),
            "{e}"
        );
    }
}
