//! The relay with hysteresis: a two-valued output that switches at two
//! thresholds `h` apart.

use crate::{check, declare_params, Float, Result, StepLaw, Stepped, Trial};

declare_params! {
    /// Parameters of the [`Relay`].
    pub struct RelayParams<T>: Copy {
        /// Hysteresis width `h ≥ 0`: the output switches up at `x ≥ h/2` and down at `x ≤ −h/2`.
        h: T => NonNegative = 0.5,
        /// Output level `a` (finite): the output is `+a` or `−a` (default 1).
        #[serde(default)]
        a: T => Real = 1.0,
        /// The switch's position `s0 ∈ {−1, 1}` at input `x = 0` before the first sample (default −1).
        #[serde(default)]
        s0: T => Real = -1.0,
    }
    check = RelayParams::two_positions;
    law: "relay", "y = a s, s = +1 once x ≥ h/2, −1 once x ≤ −h/2, held in between (from s0)";
}

impl<T: Float> RelayParams<T> {
    /// The switch has two positions, `s0 = ±1`.
    fn two_positions(&self) -> Result<()> {
        check::require(
            self.s0 == T::one() || self.s0 == -T::one(),
            "s0",
            self.s0,
            "must be −1 or 1",
        )
    }
}

/// Relay with hysteresis (the elementary hysteron of the Preisach model,
/// a thermostat, a Schmitt trigger):
///
/// `y = a s`,  `s = +1` once `x ≥ h/2`, `s = −1` once `x ≤ −h/2`, held in
/// between (from `s0`).
///
/// Rate-independent, and flat between its switches: the tangent is 0
/// everywhere (at a switch the output jumps). With `h = 0` it is the sign
/// of the input, `+a` at `x = 0`. Thresholds off 0 and
/// other levels compose: an `offset` before it moves the thresholds, one
/// after it moves the levels.
///
/// ```
/// use hysteron_operators::{Operator, Relay};
/// let mut r = Relay::new(1.0_f64).unwrap(); // switches at ±0.5, from −1
/// assert_eq!(r.run(&[0.4, 0.6, 0.0, -0.4, -0.6]).unwrap(), vec![-1.0, 1.0, 1.0, 1.0, -1.0]);
/// ```
pub type Relay<T> = Stepped<RelayParams<T>, T>;

impl<T: Float> Relay<T> {
    /// A relay of width `h ≥ 0` between `−1` and `1`, starting at `−1`.
    pub fn new(h: T) -> Result<Self> {
        Self::from_params(RelayParams {
            h,
            a: T::one(),
            s0: -T::one(),
        })
    }
}

impl<T: Float> StepLaw<T> for RelayParams<T> {
    /// The switch's position `s = ±1`.
    type State = T;
    const RESTS_WHEN_HELD: bool = true;

    fn initial(&self) -> T {
        self.s0
    }

    fn step(&self, s: &T, x: T) -> Result<(T, Trial<T>)> {
        let half = self.h * T::lit(0.5);
        let s = if x >= half {
            T::one()
        } else if x <= -half {
            -T::one()
        } else {
            *s
        };
        Ok((
            s,
            Trial {
                output: self.a * s,
                tangent: T::zero(),
            },
        ))
    }
}
