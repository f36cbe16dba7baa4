//! Parallel connection: outputs add.

use crate::Child;
use hysteron_operators::{check_output, Derivatives, Dual, Float, Hints, Operator, Result, Trial};

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

    #[inline]
    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        self.pending = false;
        let a = self.left.trial(x)?;
        let b = self.right.trial(x)?;
        let t = check_output("parallel", x, sum(a, b))?;
        self.pending = true;
        Ok(t)
    }

    crate::pair::commit_reset_children!(left, right);
}

/// `y = A + B`, `y' = A' + B'`.
#[inline(always)]
fn sum<T: Float>(a: Trial<T>, b: Trial<T>) -> Trial<T> {
    Trial {
        output: a.output + b.output,
        tangent: a.tangent + b.tangent,
    }
}

/// Each hint where both branches give it.
impl<T: Float, A: Child<T>, B: Child<T>> Hints<T> for Parallel<A, B> {
    fn rests_when_held(&self) -> bool {
        self.left.rests_when_held() && self.right.rests_when_held()
    }

    /// `y'' = A'' + B''`.
    fn trial_curvature(&self) -> Option<T> {
        if !self.pending {
            return None;
        }
        Some(self.left.trial_curvature()? + self.right.trial_curvature()?)
    }

    fn trial_value(&mut self, x: f64) -> Option<Result<Trial<f64>>> {
        self.pending = false;
        let a = match self.left.trial_value(x)? {
            Ok(a) => a,
            Err(e) => return Some(Err(e)),
        };
        let b = self.right.trial_value(x)?;
        Some(b.and_then(|b| check_output("parallel", x, sum(a, b))))
    }

    fn fold_probe(&mut self, along: &T) -> bool {
        self.pending && self.left.fold_probe(along) && self.right.fold_probe(along)
    }
}

impl<T: Float, A: Child<T>, B: Child<T>> Derivatives<T> for Parallel<A, B> {
    fn to_dual(&self) -> Option<Box<dyn Operator<Dual>>> {
        let (a, b) = (self.left.to_dual()?, self.right.to_dual()?);
        Some(Box::new(Parallel::new(a, b)))
    }
}

crate::pair::pair_traits!(Parallel<A, B>, [T: Float, A: Child<T>, B: Child<T>], left, right);
