//! The linear gain (a linear spring in force-displacement terms).

use crate::{declare_params, Float, Memoryless, Result, Stepped, Trial};

declare_params! {
    /// Parameters of the [`Gain`].
    pub struct GainParams<T>: Copy {
        /// The gain (finite).
        k: T => Real = -2.5,
    }
    law: "gain", "y = k x";
}

/// Linear gain `y = k x` (memoryless), any finite `k`. As a mechanical
/// element it is a linear spring of stiffness `k`.
///
/// ```
/// use hysteron_operators::{Gain, Operator};
/// let mut g = Gain::new(3.0_f64).unwrap();
/// assert_eq!(g.trial(2.0).unwrap().output, 6.0);
/// ```
pub type Gain<T> = Stepped<GainParams<T>, T>;

impl<T: Float> Gain<T> {
    /// A gain `k` (finite).
    pub fn new(k: T) -> Result<Self> {
        Self::from_params(GainParams { k })
    }

    /// The gain.
    pub fn gain(&self) -> T {
        self.parameters().k
    }
}

crate::memoryless_step_law!(GainParams);

impl<T: Float> Memoryless<T> for GainParams<T> {
    #[inline(always)]
    fn eval(&self, x: T) -> Trial<T> {
        Trial {
            output: self.k * x,
            tangent: self.k,
        }
    }
}
