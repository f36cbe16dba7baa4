//! Builder methods that compose any two operators.

use crate::{Cascade, Feedback, Inverse, MechanicalSeries, Parallel, Scaled};
use hysteron_operators::{Float, Operator, Result};

/// Composition methods for every operator (`use hysteron::prelude::*`).
///
/// ```
/// use hysteron_composition::OperatorExt;
/// use hysteron_operators::{Gain, Mms, Operator, Play};
/// // A boxed model built from parts: friction in series with a spring,
/// // behind a backlash.
/// let mut model = Play::new(0.1_f64).unwrap()
///     .then(Mms::new(1.0, 20.0).unwrap().series(Gain::new(50.0).unwrap()))
///     .boxed();
/// let f = model.run(&[0.0, 0.5, 1.0]).unwrap();
/// assert!(f[2] > f[1] && f[2] <= 1.0 + 1e-12);
/// ```
pub trait OperatorExt<T: Float>: Operator<T> + Clone + Sized + 'static {
    /// Cascade: `y = next[self[x]]`.
    fn then<B: Operator<T> + Clone>(self, next: B) -> Cascade<T, Self, B> {
        Cascade::new(self, next)
    }

    /// Parallel: `y = self[x] + other[x]`.
    fn plus<B: Operator<T> + Clone>(self, other: B) -> Parallel<Self, B> {
        Parallel::new(self, other)
    }

    /// Weighted: `y = w · self[x]` (`w` must be finite).
    fn scaled(self, w: T) -> Result<Scaled<T, Self>> {
        Scaled::new(w, self)
    }

    /// Negative feedback: `y = self[x − back[y]]`.
    fn feedback<B: Operator<T> + Clone>(self, back: B) -> Feedback<T, Self, B> {
        Feedback::new(self, back)
    }

    /// Mechanical series: equal force, `x = x_self + x_other`.
    fn series<B: Operator<T> + Clone>(self, other: B) -> MechanicalSeries<T, Self, B> {
        MechanicalSeries::new(self, other)
    }

    /// Numerical inverse of a non-decreasing operator.
    fn inverse(self) -> Inverse<T, Self> {
        Inverse::new(self)
    }

    /// Boxes the operator as a trait object.
    fn boxed(self) -> Box<dyn Operator<T>> {
        Box::new(self)
    }
}

impl<T: Float, O: Operator<T> + Clone + 'static> OperatorExt<T> for O {}
