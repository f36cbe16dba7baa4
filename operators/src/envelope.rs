//! A saturating, asymmetric envelope `φ(x) = tanh(b x) / (b (1 + s tanh(b x)))`
//! (memoryless): before a PI bank, the generalized Prandtl-Ishlinskii
//! model.

use crate::{check, declare_params, Float, Memoryless, Result, Stepped, Trial};

declare_params! {
    /// Parameters of the [`Envelope`] (and of its inverse,
    /// [`EnvelopeInverse`](crate::EnvelopeInverse)).
    pub struct EnvelopeParams<T>: Copy {
        /// Saturation rate `b ≥ 0` (per input unit): `φ` saturates at
        /// `1/(b (1 + s))` above and `−1/(b (1 − s))` below; `b = 0` is the
        /// identity.
        b: T => NonNegative = 0.1,
        /// Asymmetry `s`, `|s| < 1`: `s > 0` saturates sooner above, `s < 0`
        /// below; `s = 0` is symmetric.
        s: T => Real = 0.2,
    }
    check = EnvelopeParams::asymmetry_below_one;
    law: "envelope", "y = tanh(b x) / (b (1 + s tanh(b x))), y = x for b = 0";
}

impl<T: Float> EnvelopeParams<T> {
    /// `|s| < 1`: both saturation levels finite.
    pub(crate) fn asymmetry_below_one(&self) -> Result<()> {
        check::finite("s", self.s)?;
        check::require(self.s.abs() < T::one(), "s", self.s, "must be in (−1, 1)")
    }

    /// `φ(x)` and `φ'(x) = (1 − T²)/(1 + s T)²`, `T = tanh(b x)`.
    #[inline(always)]
    pub(crate) fn forward(&self, x: T) -> (T, T) {
        if self.b == T::zero() {
            return (x, T::one());
        }
        let t = (self.b * x).tanh();
        let d = T::one() + self.s * t;
        (t / (self.b * d), (T::one() - t * t) / (d * d))
    }

    /// `φ⁻¹(y) = atanh(b y / (1 − b s y)) / b` and its slope `1/φ'`; an
    /// infinite or NaN value outside `φ`'s range `(−1/(b (1 − s)),
    /// 1/(b (1 + s)))`.
    #[inline(always)]
    pub(crate) fn inverse(&self, y: T) -> (T, T) {
        if self.b == T::zero() {
            return (y, T::one());
        }
        let by = self.b * y;
        let t = by / (T::one() - self.s * by);
        let x = t.atanh() / self.b;
        let d = T::one() + self.s * t;
        (x, d * d / (T::one() - t * t))
    }
}

/// The envelope `φ(x) = tanh(b x) / (b (1 + s tanh(b x)))`: `φ(0) = 0`,
/// `φ'(0) = 1`, strictly increasing, saturating at `1/(b (1 + s))` above
/// and `−1/(b (1 − s))` below (asymmetric for `s ≠ 0`); `b = 0` is the
/// identity. Memoryless; tangent `φ'(x) = (1 − T²)/(1 + s T)²`,
/// `T = tanh(b x)`.
///
/// Before a PI bank, `cascade(envelope, pi_bank)` is the generalized
/// Prandtl-Ishlinskii model `y = a0 φ(x) + Σ_j w_j play_{r_j}[φ(x)]`
/// (Al Janaideh, Rakheja & Su 2009, with one envelope for both branches):
/// saturating, asymmetric loops whose inverse is analytic,
/// `cascade(pi_inverse, envelope_inverse)`.
///
/// ```
/// use hysteron_operators::{Envelope, EnvelopeParams, Operator};
/// let mut e = Envelope::<f64>::from_params(EnvelopeParams { b: 1.0, s: 0.5 }).unwrap();
/// let y = e.run(&[0.0, 1e-9, 50.0, -50.0]).unwrap();
/// assert_eq!(y[0], 0.0);
/// assert!((y[1] / 1e-9 - 1.0).abs() < 1e-8); // φ(x) = x − s b x² + …
/// assert!((y[2] - 1.0 / 1.5).abs() < 1e-15 && (y[3] + 1.0 / 0.5).abs() < 1e-15);
/// ```
///
/// Reference: M. Al Janaideh, S. Rakheja and C.-Y. Su, "A generalized
/// Prandtl-Ishlinskii model for characterizing the hysteresis and
/// saturation nonlinearities of smart actuators", Smart Mater. Struct. 18
/// (2009) 045001.
pub type Envelope<T> = Stepped<EnvelopeParams<T>, T>;

crate::memoryless_step_law!(EnvelopeParams);

impl<T: Float> Memoryless<T> for EnvelopeParams<T> {
    #[inline(always)]
    fn eval(&self, x: T) -> Trial<T> {
        let (output, tangent) = self.forward(x);
        Trial { output, tangent }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::Error;

    /// `φ(φ⁻¹(y)) = y` over the range and `φ⁻¹(φ(x)) = x` where `φ` is
    /// not saturated to rounding, and the slopes are reciprocal.
    #[test]
    fn the_inverse_undoes_the_envelope() {
        for (b, s) in [(0.8, 0.3), (2.0, -0.7), (0.0, 0.5), (1e-3, 0.9)] {
            let p = EnvelopeParams { b, s };
            for i in -200..=200 {
                let x = i as f64 * 0.02;
                let (y, dy) = p.forward(x);
                let (back, dx) = p.inverse(y);
                if dy > 1e-3 {
                    assert!(
                        (back - x).abs() < 1e-11 * x.abs().max(1.0),
                        "b={b} s={s} x={x}: {back}"
                    );
                    assert!((dx * dy - 1.0).abs() < 1e-9, "b={b} s={s} x={x}: {dx} {dy}");
                }
                let (f, _) = p.forward(p.inverse(y).0);
                assert!((f - y).abs() <= 4.0 * f64::EPSILON * y.abs().max(1.0 / b.max(1.0)));
            }
        }
    }

    /// The tangent is the derivative of `φ`.
    #[test]
    fn tangent_matches_a_central_difference() {
        let p = EnvelopeParams { b: 1.3, s: -0.4 };
        for i in -40..=40 {
            let x = i as f64 * 0.1;
            let fd = (p.forward(x + 1e-6).0 - p.forward(x - 1e-6).0) / 2e-6;
            assert!((p.forward(x).1 - fd).abs() < 1e-8, "x = {x}");
        }
    }

    #[test]
    fn asymmetry_must_be_inside_minus_one_one() {
        for s in [1.0, -1.0, f64::NAN] {
            let err = Envelope::from_params(EnvelopeParams { b: 1.0, s }).unwrap_err();
            assert!(
                matches!(err, Error::InvalidParameter { ref name, .. } if name == "s"),
                "{err}"
            );
        }
    }
}
