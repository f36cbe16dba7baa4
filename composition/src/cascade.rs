//! Cascade: the output of one operator drives the next.

use crate::Child;
use hysteron_operators::{Dual, Float, Operator, Result, Trial};

/// Cascade `y = B[A[x]]` (signal-flow composition, `a.then(b)`).
///
/// Tangent: `B'(A[x]) · A'(x)`. Not to be confused with
/// [`MechanicalSeries`](crate::MechanicalSeries), where forces are equal
/// and displacements add.
///
/// ```
/// use hysteron_composition::OperatorExt;
/// use hysteron_operators::{DeadZone, Operator, Play};
/// let mut m = Play::new(0.5_f64).unwrap().then(DeadZone::symmetric(1.0).unwrap());
/// assert_eq!(m.run(&[3.0]).unwrap(), vec![1.5]); // play → 2.5, dead-zone → 1.5
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Cascade<A, B> {
    first: A,
    second: B,
    pending: bool,
}

impl<A, B> Cascade<A, B> {
    /// `y = second[first[x]]`.
    pub fn new(first: A, second: B) -> Self {
        Self {
            first,
            second,
            pending: false,
        }
    }

    /// The inner (first) operator.
    pub fn first(&self) -> &A {
        &self.first
    }

    /// The outer (second) operator.
    pub fn second(&self) -> &B {
        &self.second
    }
}

impl<T: Float, A: Child<T>, B: Child<T>> Operator<T> for Cascade<A, B> {
    fn name(&self) -> &'static str {
        "cascade"
    }

    fn to_dual(&self) -> Option<Box<dyn Operator<Dual>>> {
        let (a, b) = (self.first.to_dual()?, self.second.to_dual()?);
        Some(Box::new(Cascade::new(a, b)))
    }

    #[inline]
    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        self.pending = false;
        let a = self.first.trial(x)?;
        let b = self.second.trial(a.output)?;
        self.pending = true;
        // Chain rule; where `first` is flat its output does not move, so
        // neither does the cascade's, even where `second` is vertical (an
        // inverse of a flat operator: 0 · ∞ would be NaN). Where `first` is
        // vertical (its output jumps) and `second` is flat, the slope is
        // not defined by the two tangents; the flat stage's 0 is reported
        // (a hint for solvers, never NaN).
        let tangent = if a.tangent == T::zero() || b.tangent == T::zero() {
            T::zero()
        } else {
            b.tangent * a.tangent
        };
        Ok(Trial {
            output: b.output,
            tangent,
        })
    }

    #[inline]
    fn commit(&mut self) {
        if std::mem::take(&mut self.pending) {
            self.first.commit();
            self.second.commit();
        }
    }

    fn reset(&mut self) {
        self.pending = false;
        self.first.reset();
        self.second.reset();
    }

    crate::pair::pair_methods!(first, second);
}
