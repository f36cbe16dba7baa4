//! Parallel connection: outputs add.

use crate::Child;
use hysteron_operators::{Dual, Float, Operator, Result, Trial};

/// Parallel connection `y = A[x] + B[x]` (`a.plus(b)`). As mechanical
/// elements: equal displacement, forces add. Tangent `A' + B'`.
///
/// ```
/// use hysteron_composition::OperatorExt;
/// use hysteron_operators::{Operator, Play, Stop};
/// // play + stop = identity
/// let mut m = Play::new(0.5_f64).unwrap().plus(Stop::new(0.5).unwrap());
/// assert_eq!(m.run(&[1.0, -0.25]).unwrap(), vec![1.0, -0.25]);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Parallel<A, B> {
    left: A,
    right: B,
    pending: bool,
}

impl<A, B> Parallel<A, B> {
    /// `y = left[x] + right[x]`.
    pub fn new(left: A, right: B) -> Self {
        Self {
            left,
            right,
            pending: false,
        }
    }
}

impl<T: Float, A: Child<T>, B: Child<T>> Operator<T> for Parallel<A, B> {
    fn name(&self) -> &'static str {
        "parallel"
    }

    fn to_dual(&self) -> Option<Box<dyn Operator<Dual>>> {
        let (a, b) = (self.left.to_dual()?, self.right.to_dual()?);
        Some(Box::new(Parallel::new(a, b)))
    }

    #[inline]
    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        self.pending = false;
        let a = self.left.trial(x)?;
        let b = self.right.trial(x)?;
        let t = hysteron_operators::check_output(
            "parallel",
            x,
            Trial {
                output: a.output + b.output,
                tangent: a.tangent + b.tangent,
            },
        )?;
        self.pending = true;
        Ok(t)
    }

    #[inline]
    fn commit(&mut self) {
        if std::mem::take(&mut self.pending) {
            self.left.commit();
            self.right.commit();
        }
    }

    fn reset(&mut self) {
        self.pending = false;
        self.left.reset();
        self.right.reset();
    }

    crate::pair::pair_methods!(left, right);
}
