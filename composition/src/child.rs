//! What a combinator holds.

use hysteron_operators::{Float, Operator};

/// An operator a combinator can hold: any [`Operator`] that clones (a
/// trial of an implicit combinator works on copies of its children). Every
/// operator of the library is one, boxed ones included.
pub trait Child<T: Float>: Operator<T> + Clone {}

impl<T: Float, O: Operator<T> + Clone> Child<T> for O {}
