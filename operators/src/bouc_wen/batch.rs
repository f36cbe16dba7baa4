//! The batch loop: the first sample of each monotone run through `step`,
//! the rest of the run on the same branch from its start.

use super::evaluation::Evaluation;
use super::exp_run::ExpRun;
use super::sensitive::{sensitive_state, Lookahead};
use super::state::{BranchStart, Run};
use super::BoucWen;
use crate::{check_input, process_while_by_trials, Float, Leaf, Result};

impl<T: Float> BoucWen<T> {
    /// [`force`](Self::force) at sample `i`, an error if not finite; the
    /// stiffness map's segment tried first is `*segment` (see
    /// [`StiffnessMap::eval_from`]).
    #[inline(always)]
    fn checked_force(&self, z: T, h: T, i: usize, segment: &mut usize) -> Result<T> {
        let s = self.p.stiffness.eval_from(&self.slopes, z, segment).0;
        let y = self.force(s, z, h);
        if y.is_finite() {
            Ok(y)
        } else {
            Err(crate::Error::NonFiniteOutput {
                operator: Self::KIND,
                input: z.as_f64(),
            }
            .at_sample(i))
        }
    }

    /// Outputs of `zs[i..]` along the committed branch, while the input
    /// keeps its direction (or stands still) and `at(travel, z)` gives the
    /// state in the direction frame, and `keep(i, y_i)` accepts each output;
    /// stops before the first other sample.
    // Hot loop, kept free of checks: `i < zs.len() ≤ ys.len()` (the only
    // caller, `run_batch`, passes its slices on).
    #[allow(clippy::indexing_slicing)]
    #[inline(always)]
    fn run_branch(
        &self,
        zs: &[T],
        ys: &mut [T],
        mut i: usize,
        mut at: impl FnMut(T, T) -> Option<T>,
        keep: &mut impl FnMut(usize, T) -> bool,
        segment: &mut usize,
    ) -> Run<T> {
        let c = &self.s;
        let sign = if c.dir < 0 { -T::one() } else { T::one() };
        let (z_a, mut z_prev, mut h_prev) = (c.z_a, c.z, c.h);
        while i < zs.len() {
            let z = zs[i];
            // A non-finite sample ends the run here and is reported by
            // `step`.
            if !goes_on(sign, z_prev, z) {
                break;
            }
            let Some(g) = at(sign * (z - z_a), z) else {
                break;
            };
            let h = sign * g;
            match self.checked_force(z, h, i, segment) {
                Ok(y) if keep(i, y) => ys[i] = y,
                y => {
                    return Run {
                        end: i,
                        z: z_prev,
                        h: h_prev,
                        refused: y.is_ok(),
                        error: y.err(),
                    }
                }
            }
            (z_prev, h_prev) = (z, h);
            i += 1;
        }
        Run {
            end: i,
            z: z_prev,
            h: h_prev,
            error: None,
            refused: false,
        }
    }

    /// [`process_while`] with any condition `keep`: the batch
    /// loop where there is one (inlining `keep` where it is a closure),
    /// else trial by trial.
    // `n` is the shorter of the two lengths.
    #[allow(clippy::indexing_slicing)]
    #[inline(always)]
    pub(super) fn run_while(
        &mut self,
        zs: &[T],
        ys: &mut [T],
        mut keep: impl FnMut(usize, T) -> bool,
    ) -> usize {
        self.pending = None;
        if let Evaluation::Adaptive = self.evaluation {
            return process_while_by_trials(self, zs, ys, &mut keep);
        }
        let n = zs.len().min(ys.len());
        self.run_batch(&zs[..n], &mut ys[..n], keep).0
    }

    /// The batch loop of [`process`](Operator::process) (closed form, or
    /// tabulated flow, with or without its derivatives): the first sample
    /// of each monotone run goes through [`step`](Self::step) (which starts
    /// a new branch on a reversal); the
    /// rest of the run evaluates the same branch from its start (closed form
    /// for n = 1, the tabulated flow otherwise), sample by sample
    /// independent, which is what `step` computes for them too. Each output
    /// is offered to `keep` before it is committed; the first it refuses, or
    /// an error, ends the loop there uncommitted. Returns the number of
    /// samples committed and the error (`at_sample`) if one ended it.
    // Hot loop, kept free of checks: `i < zs.len() ≤ ys.len()` (`process`
    // checks equal lengths, `process_while` cuts both to the shorter).
    #[allow(clippy::indexing_slicing)]
    #[inline(always)]
    pub(super) fn run_batch(
        &mut self,
        zs: &[T],
        ys: &mut [T],
        mut keep: impl FnMut(usize, T) -> bool,
    ) -> (usize, Result<()>) {
        let mut i = 0;
        // The stiffness map's segment at the last sample.
        let mut segment = 0;
        while i < zs.len() {
            let z = zs[i];
            let next = check_input(z).and_then(|z| self.step(z));
            let next = match next {
                Ok(next) => next,
                Err(e) => return (i, Err(e.at_sample(i))),
            };
            let y = match self.checked_force(next.z, next.h, i, &mut segment) {
                Ok(y) => y,
                Err(e) => return (i, Err(e)),
            };
            if !keep(i, y) {
                return (i, Ok(()));
            }
            ys[i] = y;
            self.s = next;
            i += 1;
            let run = match (self.s.branch, &self.evaluation) {
                (BranchStart::Linear(branch), _) => {
                    // Over `f64` a branch in the general form takes its
                    // exponentials a block ahead, vectorised; the states
                    // are `branch.at(s)`'s bits either way.
                    let form = branch.value().exp_form();
                    match (crate::simd::as_f64(zs), form) {
                        (Some(zs_f64), Some(form)) => {
                            let c = &self.s;
                            let sign = if c.dir < 0 { -1.0 } else { 1.0 };
                            let mut run = ExpRun::new(form, sign, c.z_a.as_f64(), zs_f64, i);
                            self.run_branch(
                                zs,
                                ys,
                                i,
                                |s, _| Some(T::lit(run.at(s.as_f64()))),
                                &mut keep,
                                &mut segment,
                            )
                        }
                        _ => self.run_branch(
                            zs,
                            ys,
                            i,
                            |s, _| Some(branch.at(s)),
                            &mut keep,
                            &mut segment,
                        ),
                    }
                }
                (BranchStart::Flow(sa), Evaluation::Table(table, hint)) => {
                    let mut hint = *hint;
                    let run = self.run_branch(
                        zs,
                        ys,
                        i,
                        |s, _| table.state_at(sa + s, &mut hint),
                        &mut keep,
                        &mut segment,
                    );
                    if let Evaluation::Table(_, h) = &mut self.evaluation {
                        *h = hint;
                    }
                    run
                }
                (BranchStart::Sensitive { position, carry }, Evaluation::Sensitive(flow, hint)) => {
                    // (`step`'s formula along the branch, on the table as
                    // it is: a lookup beyond it ends the run, and `step`
                    // extends a growing side)
                    let (d, seeded) = (self.d_params, self.seeded);
                    let sign = if self.s.dir < 0 { -T::one() } else { T::one() };
                    let mut hint = *hint;
                    let mut ahead = Lookahead::new(position, sign, self.s.z_a, i);
                    let run = self.run_branch(
                        zs,
                        ys,
                        i,
                        |s, z| {
                            let p = ahead.next(flow, &mut hint, zs, s)?;
                            Some(sensitive_state(p, carry, sign, z, &d, seeded))
                        },
                        &mut keep,
                        &mut segment,
                    );
                    if let Evaluation::Sensitive(_, h) = &mut self.evaluation {
                        *h = hint;
                    }
                    run
                }
                _ => continue,
            };
            (i, self.s.z, self.s.h) = (run.end, run.z, run.h);
            if let Some(e) = run.error {
                return (i, Err(e));
            }
            if run.refused {
                return (i, Ok(()));
            }
        }
        (zs.len(), Ok(()))
    }
}

/// Whether a run along a branch of direction `sign` goes on from input
/// `before` to `z`: `z` finite and not moving back (standing still goes on).
/// `run_branch` and [`Lookahead`] share it, so that the points looked up
/// ahead are those of the samples the run takes.
#[inline(always)]
pub(super) fn goes_on<T: Float>(sign: T, before: T, z: T) -> bool {
    sign * (z - before) >= T::zero() && z.is_finite()
}
