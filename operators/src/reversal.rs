//! The direction of travel and the last reversal point, for the leaves
//! whose branch restarts where the input turns (Dahl, MMS).

use crate::Float;

/// The direction of travel from `x_prev` to `x`: `1` up, `−1` down, and
/// `dir_prev` while the input holds (`0` before any motion).
#[inline(always)]
pub(crate) fn travel<T: Float>(x_prev: T, x: T, dir_prev: i8) -> i8 {
    if x > x_prev {
        1
    } else if x < x_prev {
        -1
    } else {
        dir_prev
    }
}

/// The branch's reversal point: `last` (the previous sample's point) where
/// the direction `dir` differs from `dir_prev`, `current` otherwise.
#[inline(always)]
pub(crate) fn point<P>(dir: i8, dir_prev: i8, last: P, current: P) -> P {
    if dir != dir_prev {
        last
    } else {
        current
    }
}
