//! The linear gain (a linear spring in force-displacement terms).

use crate::memoryless::map_samples;
use crate::{check, check_input, Float, Operator, Result, Trial};

/// Linear gain `y = k x` (memoryless), any finite `k`. As a mechanical
/// element it is a linear spring of stiffness `k`.
///
/// ```
/// use hysteron_operators::{Gain, Operator};
/// let mut g = Gain::new(3.0_f64).unwrap();
/// assert_eq!(g.trial(2.0).unwrap().output, 6.0);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Gain<T> {
    k: T,
}

impl<T: Float> Gain<T> {
    /// A gain `k` (finite).
    pub fn new(k: T) -> Result<Self> {
        check::finite("k", k)?;
        Ok(Self { k })
    }

    /// The gain.
    pub fn gain(&self) -> T {
        self.k
    }
}

impl<T: Float> Operator<T> for Gain<T> {
    fn name(&self) -> &'static str {
        "gain"
    }

    #[inline]
    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        let x = check_input(x)?;
        crate::check_output(
            "gain",
            x,
            Trial {
                output: self.k * x,
                tangent: self.k,
            },
        )
    }

    fn commit(&mut self) {}

    fn reset(&mut self) {}

    fn process(&mut self, xs: &[T], ys: &mut [T]) -> Result<()> {
        let k = self.k;
        map_samples(xs, ys, |x| k * x)?;
        crate::memoryless::check_finite_outputs("gain", xs, ys)
    }

    fn n_params(&self) -> usize {
        1
    }

    fn params_into(&self, out: &mut Vec<T>) {
        out.push(self.k);
    }

    fn param_names(&self) -> Vec<String> {
        vec!["k".into()]
    }

    fn set_params(&mut self, p: &[T]) -> Result<()> {
        check::count(1, p)?;
        *self = Self::new(p[0])?;
        Ok(())
    }
}
