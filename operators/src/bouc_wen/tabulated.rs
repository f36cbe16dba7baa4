//! Over `f32`/`f64`: each sample on the flow of the state equation,
//! tabulated once per parameter set, from the start of its branch.

use super::state::{BranchStart, State};
use crate::flow_table::{FlowTable, Hint};
use crate::Float;

/// The state after input `z` from the committed state `c`, moving in
/// direction `dir` (sign `sign`): at position `σ_a + travel` of the table,
/// from the start of the branch (a new one starts on a reversal, or where
/// the last state was outside the table); `None` where the state or the
/// position is outside the table (the caller integrates).
#[inline(always)]
pub(super) fn step<T: Float>(
    table: &mut FlowTable<T>,
    hint: &mut Hint,
    c: &State<T>,
    z: T,
    dir: i64,
    sign: T,
) -> Option<State<T>> {
    let (z_a, sigma_a) = match c.branch {
        BranchStart::Flow(sa) if dir == c.dir => (c.z_a, Some(sa)),
        _ if dir == 0 => return Some(*c),
        _ => (c.z, table.position_growing(sign * c.h, hint)),
    };
    let sa = sigma_a?;
    let g = table.state_at_growing(sa + sign * (z - z_a), hint)?;
    Some(State {
        z,
        h: sign * g,
        dir,
        z_a,
        branch: BranchStart::Flow(sa),
    })
}
