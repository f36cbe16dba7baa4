//! The linear gain (a linear spring in force-displacement terms).

use crate::memoryless::map_samples;
use crate::{declare_params, Float, Result, StepLaw, Stepped, Trial};

declare_params! {
    /// Parameters of the [`Gain`].
    #[derive(Copy)]
    pub struct GainParams<T> {
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

impl<T: Float> StepLaw<T> for GainParams<T> {
    type State = ();

    fn initial(&self) {}

    #[inline(always)]
    fn step(&self, _: &(), x: T) -> Result<((), Trial<T>)> {
        let k = self.k;
        Ok((
            (),
            Trial {
                output: k * x,
                tangent: k,
            },
        ))
    }

    fn run(&self, _: &mut (), xs: &[T], ys: &mut [T]) -> Result<()> {
        let k = self.k;
        map_samples(<Self as crate::Declared<T>>::KIND, xs, ys, |x| k * x)
    }

}
