//! The inverse of the [`Envelope`](crate::Envelope), in closed form
//! (memoryless).

use crate::{declare_params, Float, Memoryless, Stepped, Trial};

declare_params! {
    /// Parameters of the [`EnvelopeInverse`]: those of the envelope it
    /// inverts.
    pub struct EnvelopeInverseParams<T>: Copy {
        /// The envelope's saturation rate `b ≥ 0`.
        b: T => NonNegative = 0.1,
        /// The envelope's asymmetry `s`, `|s| < 1`.
        s: T => Real = 0.2,
    }
    check = |p| crate::EnvelopeParams { b: p.b, s: p.s }.asymmetry_below_one();
    law: "envelope_inverse", "x = φ⁻¹(y) = atanh(b y / (1 − b s y)) / b, x = y for b = 0 (the envelope's inverse)";
}

/// The inverse `x = φ⁻¹(y) = atanh(b y / (1 − b s y)) / b` of the
/// [`Envelope`](crate::Envelope) with the same `b` and `s` (`b = 0`: the
/// identity). Memoryless; tangent `1/φ'(x)`. Its input must lie in the
/// envelope's range `(−1/(b (1 − s)), 1/(b (1 + s)))`: outside it no input
/// reaches that output, and the sample's error says the output is not
/// finite.
///
/// After a PI bank's analytic inverse, `cascade(pi_inverse,
/// envelope_inverse)` inverts the generalized Prandtl-Ishlinskii model
/// `cascade(envelope, pi_bank)` exactly: the compensator of a saturating,
/// asymmetric actuator.
///
/// ```
/// use hysteron_operators::{Envelope, EnvelopeInverse, EnvelopeInverseParams, EnvelopeParams, Operator};
/// let (b, s) = (1.0_f64, 0.5);
/// let mut forward = Envelope::from_params(EnvelopeParams { b, s }).unwrap();
/// let mut inverse = EnvelopeInverse::from_params(EnvelopeInverseParams { b, s }).unwrap();
/// let x = [0.3, -1.2, 2.0];
/// let back = inverse.run(&forward.run(&x).unwrap()).unwrap();
/// assert!(back.iter().zip(&x).all(|(a, b)| (a - b).abs() < 1e-14));
/// assert!(inverse.run(&[1.0]).is_err()); // above the range's top, 1/1.5
/// ```
pub type EnvelopeInverse<T> = Stepped<EnvelopeInverseParams<T>, T>;

crate::memoryless_step_law!(EnvelopeInverseParams);

impl<T: Float> Memoryless<T> for EnvelopeInverseParams<T> {
    #[inline(always)]
    fn eval(&self, y: T) -> Trial<T> {
        let (output, tangent) = crate::EnvelopeParams {
            b: self.b,
            s: self.s,
        }
        .inverse(y);
        Trial { output, tangent }
    }
}
