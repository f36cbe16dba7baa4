//! The offset `y = x + c` (memoryless).

use crate::{declare_params, Float, Memoryless, Result, Stepped, Trial};

declare_params! {
    /// Parameters of the [`Offset`].
    pub struct OffsetParams<T>: Copy {
        /// The constant added to the input (finite).
        c: T => Real = -0.75,
    }
    law: "offset", "y = x + c";
}

/// Offset `y = x + c` (memoryless): in a cascade after a model it shifts
/// the model's output, a preload or a sensor bias; in parallel with a
/// `gain` of 0 it is a constant. Tangent: 1.
///
/// ```
/// use hysteron_operators::{Offset, Operator};
/// let mut o = Offset::new(0.25_f64).unwrap();
/// assert_eq!(o.run(&[1.0, -1.0]).unwrap(), vec![1.25, -0.75]);
/// ```
pub type Offset<T> = Stepped<OffsetParams<T>, T>;

impl<T: Float> Offset<T> {
    /// An offset `c` (finite).
    pub fn new(c: T) -> Result<Self> {
        Self::from_params(OffsetParams { c })
    }
}

crate::memoryless_step_law!(OffsetParams);

impl<T: Float> Memoryless<T> for OffsetParams<T> {
    fn eval(&self, x: T) -> Trial<T> {
        Trial {
            output: x + self.c,
            tangent: T::one(),
        }
    }
}
