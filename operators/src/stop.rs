//! The stop operator (Prandtl-Ishlinskii stop).

use crate::{declare_params, play_step, play_tangent, Float, Result, StepLaw, Stepped, Trial};

declare_params! {
    /// Parameters of the [`Stop`] operator.
    pub struct StopParams<T>: Copy {
        /// Threshold `r ≥ 0`: the output stays in `[−r, r]`.
        r: T => NonNegative = 0.5,
        /// Output at input `x = 0` before the first sample (default 0).
        #[serde(default)]
        s0: T => Real = 0.25,
    }
    law: "stop", "s = x − play_r[x] ∈ [−r, r], from s0";
}

/// Stop operator with threshold `r`: `s_r[x] = x − p_r[x]`, with `p_r` the
/// [`Play`](crate::Play). In exact arithmetic equivalently
/// `s_k = clamp(s_{k−1} + Δx, −r, r)`; in floating point `s = x − p` carries
/// the rounding of `x`, so for `|x|` so large that `ulp(x) > r` the output
/// is resolved only to `ulp(x)`.
///
/// The state kept is the play position `q = x − s`, advanced by the play's
/// own step; this makes the operator exactly rate-independent in floating
/// point. The output `s` lies in `[−r, r]` from
/// the first sample on (an initial `s0` outside is clipped there). Tangent:
/// 1 inside, 0 at saturation.
///
/// ```
/// use hysteron_operators::{Operator, Stop};
/// let mut s = Stop::new(1.0_f64).unwrap();
/// assert_eq!(s.run(&[0.5, 2.0, 1.5]).unwrap(), vec![0.5, 1.0, 0.5]);
/// ```
pub type Stop<T> = Stepped<StopParams<T>, T>;

/// One stop step from play position `q`: returns `(s, q_new, tangent)`.
///
/// The play position is advanced exactly as the [`Play`](crate::Play)
/// advances its output (so the stop inherits its exact rate independence and
/// wiping-out), and the output is `clamp(x − q_new, −r, r)`.
#[inline(always)]
pub fn stop_step<T: Float>(r: T, q: T, x: T) -> (T, T, T) {
    let q_new = play_step(r, q, x);
    let tangent = T::one() - play_tangent(r, q, x);
    let e = x - q_new;
    let s = if e > r {
        r
    } else if e < -r {
        -r
    } else {
        e
    };
    (s, q_new, tangent)
}

impl<T: Float> Stop<T> {
    /// A stop with threshold `r`, starting at output 0.
    pub fn new(r: T) -> Result<Self> {
        Self::from_params(StopParams { r, s0: T::zero() })
    }
}

impl<T: Float> StepLaw<T> for StopParams<T> {
    type State = T;

    fn initial(&self) -> T {
        -self.s0
    }

    #[inline(always)]
    fn step(&self, q: &T, x: T) -> Result<(T, Trial<T>)> {
        let (s, q, tangent) = stop_step(self.r, *q, x);
        Ok((q, Trial { output: s, tangent }))
    }
}
