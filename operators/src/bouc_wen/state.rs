//! The spring's state between samples, and the branch it moves on.

use super::BoucWenParams;
use crate::hysteretic_state::Branch;
use crate::Float;

#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct State<T> {
    pub(super) z: T,
    pub(super) h: T,
    /// The direction of motion, −1, 0 (before any) or 1. A full word: a
    /// byte and its padding were copied by `commit` in pieces that the
    /// next trial's 8-byte load could not be forwarded from (a stall of
    /// about 10 ns per trial and commit, measured on Zen 4: 31.9 → 20.7–24.5
    /// ns for the paper's spring in a trial-and-commit loop).
    pub(super) dir: i64,
    /// The input where the current branch started.
    pub(super) z_a: T,
    pub(super) branch: BranchStart<T>,
}

/// The branch the state moves on, from its start at `z_a` (in the
/// direction frame `g = sgn(ż) h`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum BranchStart<T> {
    /// None yet, or integrated step by step.
    Unknown,
    /// `n = 1`: the branch in closed form.
    Linear(Branch<T>),
    /// Tabulated flow: the position `σ(g_a)` of the branch start.
    Flow(T),
    /// Tabulated flow over dual numbers: the position of the branch start
    /// and what its derivatives contribute along the branch,
    /// `(dg_a − A(σ_a))/f(g_a) − sgn(ż) dz_a` (see
    /// [`BoucWen::step_sensitive`]).
    Sensitive { position: f64, carry: T },
}

impl<T: Float> State<T> {
    /// Folds the probe slot of every scalar ([`Hints::fold_probe`]).
    pub(super) fn fold_probe(&mut self, along: &T) {
        for v in [&mut self.z, &mut self.h, &mut self.z_a] {
            v.fold_probe(along);
        }
        match &mut self.branch {
            BranchStart::Unknown => {}
            BranchStart::Flow(position) => position.fold_probe(along),
            BranchStart::Linear(b) => b.fold_probe(along),
            BranchStart::Sensitive { carry, .. } => carry.fold_probe(along),
        }
    }

    pub(super) fn initial(p: &BoucWenParams<T>) -> Self {
        State {
            z: p.z0,
            h: p.h0,
            dir: 0,
            z_a: p.z0,
            branch: BranchStart::Unknown,
        }
    }
}

/// A step on the derivatives' table ([`BoucWen::step_sensitive`]): the
/// parts of the new state it computes, and the rate `f(g)` there.
#[derive(Debug, Clone, Copy)]
pub(super) struct SensitiveStep<T> {
    pub(super) h: T,
    pub(super) z_a: T,
    pub(super) position: f64,
    pub(super) carry: T,
    pub(super) rate: f64,
}

impl<T: Float> SensitiveStep<T> {
    /// The state at input `z`, moving in direction `dir`.
    #[inline(always)]
    pub(super) fn state(self, z: T, dir: i64) -> State<T> {
        State {
            z,
            h: self.h,
            dir,
            z_a: self.z_a,
            branch: BranchStart::Sensitive {
                position: self.position,
                carry: self.carry,
            },
        }
    }
}

/// Where [`BoucWen::run_branch`] stopped: the next sample, the last state,
/// and the error of the sample it stopped at, if any, or whether `keep`
/// refused that sample.
pub(super) struct Run<T> {
    pub(super) end: usize,
    pub(super) z: T,
    pub(super) h: T,
    pub(super) error: Option<crate::Error>,
    pub(super) refused: bool,
}
