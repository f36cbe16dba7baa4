//! A memoryless backlash (a gap with zero force) whose contact stiffens
//! with penetration.

use crate::{declare_params, Float, Memoryless, Result, Stepped, Trial};

declare_params! {
    /// Parameters of the [`BacklashContact`].
    pub struct BacklashContactParams<T>: Copy {
        /// Gap width `b ≥ 0`: no force while `|x − c| ≤ b/2`.
        b: T => NonNegative = 0.6,
        /// Linear contact stiffness `k1 > 0`.
        k1: T => Positive = 2.0,
        /// Quadratic contact stiffness `k2 ≥ 0`.
        k2: T => NonNegative = 0.5,
        /// Cubic contact stiffness `k3 ≥ 0` (default 0).
        #[serde(default)]
        k3: T => NonNegative = 0.25,
        /// Centre of the gap `c` (default 0).
        #[serde(default)]
        c: T => Real = 0.1,
    }
    law: "backlash_contact", "u = x − c, d = max(|u| − b/2, 0), F = sgn(u)·(k1 d + k2 d² + k3 d³)";
}

/// Backlash with a stiffening contact (memoryless): no force inside a gap
/// of width `b` centred at `c`, and beyond it the polynomial stiffness
/// map of Ruderman & Bertram (2015) as the contact law,
///
/// `u = x − c`,  `d = max(|u| − b/2, 0)`,  `F = sgn(u) · (k1 d + k2 d² + k3 d³)`,
///
/// evaluated as `d (k1 + d (k2 + d k3))`. Monotone non-decreasing in `x`
/// (also in floating point: every operation is monotone in `d`), odd about
/// `c`, 0 (positive zero) inside the gap. Tangent: 0 inside the gap
/// (`|u| < b/2`), `k1 + 2 k2 d + 3 k3 d²` from its edge on (`k1` at the edge, as
/// the [`DeadZone`](crate::DeadZone) takes the outside slope there). In a
/// mechanical `series` after a friction element it makes a backlash
/// whose driven part is held by friction.
///
/// ```
/// use hysteron_operators::{BacklashContact, BacklashContactParams, Operator};
/// let p = BacklashContactParams { b: 1.0, k1: 2.0, k2: 1.0, k3: 0.0, c: 0.0 };
/// let mut g = BacklashContact::from_params(p).unwrap();
/// // d = 0 inside, d = 1 at x = ±1.5: F = ±(2 + 1)
/// assert_eq!(g.run(&[0.25, 1.5, -1.5]).unwrap(), vec![0.0, 3.0, -3.0]);
/// ```
pub type BacklashContact<T> = Stepped<BacklashContactParams<T>, T>;

impl<T: Float> BacklashContact<T> {
    /// A linear contact: gap `b` centred at 0, stiffness `k1` beyond it.
    pub fn new(b: T, k1: T) -> Result<Self> {
        Self::from_params(BacklashContactParams {
            b,
            k1,
            k2: T::zero(),
            k3: T::zero(),
            c: T::zero(),
        })
    }
}

crate::memoryless_step_law!(BacklashContactParams);

impl<T: Float> Memoryless<T> for BacklashContactParams<T> {
    #[inline(always)]
    fn eval(&self, x: T) -> Trial<T> {
        let u = x - self.c;
        // `|u| − b/2` is 0 exactly when `|u| = b/2` (gradual underflow)
        let d = u.abs() - self.b * T::lit(0.5);
        let (output, tangent) = if d > T::zero() {
            let (k1, k2, k3) = (self.k1, self.k2, self.k3);
            let f = d * (k1 + d * (k2 + d * k3));
            // no `0 · ∞` here: d > 0, and the sums add non-negative terms
            let t = k1 + d * (k2 * T::lit(2.0) + d * (k3 * T::lit(3.0)));
            (if u < T::zero() { -f } else { f }, t)
        } else if d == T::zero() {
            (T::zero(), self.k1)
        } else {
            (T::zero(), T::zero())
        };
        Trial { output, tangent }
    }
}
