//! The elastoplastic (Prandtl / Maxwell-slip) element with different
//! sliding levels in the two directions.

use crate::{check, declare_params, Float, Result, StepLaw, Stepped, Trial};

declare_params! {
    /// Parameters of the [`AsymmetricFriction`] element.
    pub struct AsymmetricFrictionParams<T>: Copy {
        /// Spring stiffness `k > 0`.
        k: T => Positive = 4.0,
        /// Sliding level in the positive direction, `f_pos ≥ 0`: `F ≤ f_pos`.
        f_pos: T => NonNegative = 1.5,
        /// Sliding level in the negative direction, `f_neg ≥ 0`: `F ≥ −f_neg`.
        f_neg: T => NonNegative = 0.5,
        /// Force at input `x = 0` before the first sample, in `[−f_neg, f_pos]` (default 0).
        #[serde(default)]
        f0: T => Real = -0.25,
    }
    check = AsymmetricFrictionParams::consistent;
    law: "asymmetric_friction", "F = k · (x − x_p), x_p moving only to keep −f_neg ≤ F ≤ f_pos: slope k while sticking, sliding at f_pos or −f_neg";
}

impl<T: Float> AsymmetricFrictionParams<T> {
    /// `f0` must lie in `[−f_neg, f_pos]`, and the element works in
    /// displacements `f_pos/k`, `f_neg/k`, `f0/k`, which must be
    /// representable (finite, and not rounded to 0 from a positive level).
    fn consistent(&self) -> Result<()> {
        if self.f0 > self.f_pos || self.f0 < -self.f_neg {
            return Err(check::invalid(
                "f0",
                self.f0,
                "must lie in [−f_neg, f_pos] (a force the element can hold)",
            ));
        }
        check::level_over_stiffness("f_pos", self.f_pos, self.k)?;
        check::level_over_stiffness("f_neg", self.f_neg, self.k)?;
        check::start_over_stiffness(self.f0, self.k)?;
        Ok(())
    }
}

/// Elastoplastic element whose sliding levels differ by direction: a
/// massless block pulled through a linear spring over a surface that
/// holds up to `f_pos` one way and `f_neg` the other (a self-energizing
/// brake, a one-way clutch, a ratchet with a soft pawl),
///
/// `F = k · (x − x_p)`,  `−f_neg ≤ F ≤ f_pos`,
///
/// where the slip `x_p` moves only as far as needed to keep the force in
/// that interval: `x_p ← clamp(x_p, x − f_pos/k, x + f_neg/k)`, a play
/// with thresholds `f_pos/k` above and `f_neg/k` below (the
/// [`Play`](crate::Play) when they are equal), and `F = k · clamp(x − x_p,
/// −f_neg/k, f_pos/k)`. Starting slip: `x_p = −f0/k`.
///
/// With `f_pos = f_neg = F_b` it is the [`ElastoPlastic`](crate::ElastoPlastic)
/// element, bit for bit (the same operations in the same order).
/// Rate-independent, exactly in floating point: on a monotone stretch of
/// input the slip is a running maximum (or minimum) of `x − f_pos/k`
/// (`x + f_neg/k`), which intermediate samples do not change. Tangent: `k`
/// while sticking, 0 while sliding (also on reaching a level, as the
/// [`Stop`](crate::Stop)).
///
/// ```
/// use hysteron_operators::{AsymmetricFriction, Operator};
/// // k = 2, holds 1 forwards and 0.5 backwards
/// let mut f = AsymmetricFriction::new(2.0_f64, 1.0, 0.5).unwrap();
/// assert_eq!(
///     f.run(&[0.25, 1.0, 0.75, 0.0, 0.5]).unwrap(),
///     vec![0.5, 1.0, 0.5, -0.5, 0.5]
/// );
/// ```
pub type AsymmetricFriction<T> = Stepped<AsymmetricFrictionParams<T>, T>;

impl<T: Float> AsymmetricFriction<T> {
    /// An element with stiffness `k` and levels `f_pos`, `f_neg`, unloaded.
    pub fn new(k: T, f_pos: T, f_neg: T) -> Result<Self> {
        Self::from_params(AsymmetricFrictionParams {
            k,
            f_pos,
            f_neg,
            f0: T::zero(),
        })
    }
}

/// One step of the slip `q` (the play position) with thresholds `r_pos`
/// above and `r_neg` below: returns `(s, q_new, tangent)` with
/// `s = clamp(x − q_new, −r_neg, r_pos)` and the tangent `ds/dx` (1
/// sticking, 0 sliding). With `r_pos = r_neg = r` this is
/// [`stop_step`](crate::stop_step) operation for operation.
#[inline(always)]
fn slip_step<T: Float>(r_pos: T, r_neg: T, q: T, x: T) -> (T, T, T) {
    let (lo, hi) = (x - r_pos, x + r_neg);
    let clipped = if q < hi { q } else { hi };
    let q_new = if clipped > lo { clipped } else { lo };
    let sliding = lo >= q || hi <= q;
    let tangent = if sliding { T::zero() } else { T::one() };
    let e = x - q_new;
    let s = if e > r_pos {
        r_pos
    } else if e < -r_neg {
        -r_neg
    } else {
        e
    };
    (s, q_new, tangent)
}

impl<T: Float> StepLaw<T> for AsymmetricFrictionParams<T> {
    // At an unchanged input the clamp that moves the state leaves it.
    const RESTS_WHEN_HELD: bool = true;
    type State = T;

    fn initial(&self) -> T {
        -(self.f0 / self.k)
    }

    #[inline(always)]
    fn step(&self, q: &T, x: T) -> Result<(T, Trial<T>)> {
        let k = self.k;
        let (s, q, tangent) = slip_step(self.f_pos / k, self.f_neg / k, *q, x);
        Ok((
            q,
            Trial {
                output: k * s,
                tangent: k * tangent,
            },
        ))
    }
}
