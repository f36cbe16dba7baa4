//! Cascade: the output of one operator drives the next.

use crate::Child;
use hysteron_operators::{Derivatives, Dual, Float, Hints, Operator, Result, Trial};

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
pub struct Cascade<T, A, B> {
    first: A,
    second: B,
    /// The tangents of the pending trial: the first stage's, the second's.
    pending: Option<(T, T)>,
}

impl<T, A, B> Cascade<T, A, B> {
    /// `y = second[first[x]]`.
    pub fn new(first: A, second: B) -> Self {
        Self {
            first,
            second,
            pending: None,
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

impl<T: Float, A: Child<T>, B: Child<T>> Operator<T> for Cascade<T, A, B> {
    fn name(&self) -> &'static str {
        "cascade"
    }

    #[inline]
    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        self.pending = None;
        let a = self.first.trial(x)?;
        let b = self.second.trial(a.output)?;
        self.pending = Some((a.tangent, b.tangent));
        Ok(Trial {
            output: b.output,
            tangent: chain(a.tangent, b.tangent),
        })
    }

    crate::pair::commit_reset_children!(first, second);
}

/// The chain rule `dy/dx = B' · A'`. Where `first` is flat its output does
/// not move, so neither does the cascade's, even where `second` is vertical
/// (an inverse of a flat operator: 0 · ∞ would be NaN). Where `first` is
/// vertical (its output jumps) and `second` is flat, the slope is not
/// defined by the two tangents; the flat stage's 0 is reported (a hint for
/// solvers, never NaN).
#[inline(always)]
fn chain<T: Float>(a: T, b: T) -> T {
    if a == T::zero() || b == T::zero() {
        T::zero()
    } else {
        b * a
    }
}

/// Each hint where both stages give it.
impl<T: Float, A: Child<T>, B: Child<T>> Hints<T> for Cascade<T, A, B> {
    /// Both stages rest: the first's output, held, holds the second's input.
    fn rests_when_held(&self) -> bool {
        self.first.rests_when_held() && self.second.rests_when_held()
    }

    /// `y'' = B''(A(x)) · A'² + B' · A''`.
    fn trial_curvature(&self) -> Option<T> {
        let (a, b) = self.pending?;
        let (a2, b2) = (
            self.first.trial_curvature()?,
            self.second.trial_curvature()?,
        );
        Some(b2 * a * a + b * a2)
    }

    fn trial_value(&mut self, x: f64) -> Option<Result<Trial<f64>>> {
        self.pending = None;
        let a = match self.first.trial_value(x)? {
            Ok(a) => a,
            Err(e) => return Some(Err(e)),
        };
        let b = self.second.trial_value(a.output)?;
        Some(b.map(|b| Trial {
            output: b.output,
            tangent: chain(a.tangent, b.tangent),
        }))
    }

    /// Both stages' probe slots hold derivatives with respect to the same
    /// root: both fold with its `along`.
    fn fold_probe(&mut self, along: &T) -> bool {
        self.pending.is_some() && self.first.fold_probe(along) && self.second.fold_probe(along)
    }
}

impl<T: Float, A: Child<T>, B: Child<T>> Derivatives<T> for Cascade<T, A, B> {
    fn to_dual(&self) -> Option<Box<dyn Operator<Dual>>> {
        let (a, b) = (self.first.to_dual()?, self.second.to_dual()?);
        Some(Box::new(Cascade::<Dual, _, _>::new(a, b)))
    }
}

crate::pair::pair_traits!(Cascade<T, A, B>, [T: Float, A: Child<T>, B: Child<T>], first, second);
