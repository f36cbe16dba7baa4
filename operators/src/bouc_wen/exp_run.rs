//! The exponentials of a run along a branch, evaluated a block of samples
//! ahead, four or eight per instruction.

use crate::exp_kernel::exp_in_place;
use crate::hysteretic_state::ExpForm;

/// Samples whose exponentials are evaluated together.
const BLOCK: usize = 64;

/// A branch in the general form ([`ExpForm`]) evaluated along a monotone
/// run of the input `zs` from sample `next`:
///
/// `g(s) = g∞ − (f/c) e^{−c s}`, `s = sign (z − z_a)`,
///
/// with the piece from `g = 0` past the zero crossing `s0`. The arguments
/// of the next [`BLOCK`] samples are formed and their exponentials taken
/// in one vectorised pass ([`exp_in_place`]); [`at`](Self::at) then gives
/// the samples' states in order. Every state is the bits of the branch's
/// own `at(s)` (the same operations on the same values, the exponential
/// being one kernel), so a run may stop anywhere; the exponentials
/// computed past its end are dropped.
pub(super) struct ExpRun<'a> {
    form: ExpForm,
    sign: f64,
    z_a: f64,
    zs: &'a [f64],
    /// The sample the next call of [`at`](Self::at) is for.
    next: usize,
    /// The first sample of the block in `e`.
    start: usize,
    /// The block's exponentials (`len` of them).
    e: [f64; BLOCK],
    len: usize,
}

impl<'a> ExpRun<'a> {
    /// The run along `form` over `zs` from sample `next`, in direction
    /// `sign` from the branch start `z_a`.
    pub(super) fn new(form: ExpForm, sign: f64, z_a: f64, zs: &'a [f64], next: usize) -> Self {
        ExpRun {
            form,
            sign,
            z_a,
            zs,
            next,
            start: next,
            e: [0.0; BLOCK],
            len: 0,
        }
    }

    /// `e^{−c_0 (s − s0)}` past the zero crossing, else `e^{−c_a s}`.
    #[inline(always)]
    fn argument(&self, s: f64) -> f64 {
        let f = &self.form;
        if f.s0 < s {
            -f.c_0 * (s - f.s0)
        } else {
            -f.c_a * s
        }
    }

    /// The state `g(s)` of the next sample, whose travel from the branch
    /// start is `s` (`sign (z − z_a)` of that sample).
    #[inline(always)]
    pub(super) fn at(&mut self, s: f64) -> f64 {
        if self.next >= self.start + self.len {
            self.fill();
        }
        let e = self.e.get(self.next - self.start).copied().unwrap_or(f64::NAN);
        self.next += 1;
        let f = &self.form;
        if f.s0 < s {
            f.fc_0 - f.fc_0 * e
        } else {
            f.inf_a - f.fc_a * e
        }
    }

    /// The exponentials of the block from `next`.
    #[cold]
    fn fill(&mut self) {
        let end = self.zs.len().min(self.next + BLOCK);
        self.start = self.next;
        self.len = end.saturating_sub(self.next);
        let zs = self.zs.get(self.start..end).unwrap_or(&[]);
        let mut e = [0.0; BLOCK];
        for (e, &z) in e.iter_mut().zip(zs) {
            *e = self.argument(self.sign * (z - self.z_a));
        }
        if let Some(e) = e.get_mut(..self.len) {
            exp_in_place(e);
        }
        self.e = e;
    }
}
