//! Trials of the lanes' springs, each at its own input, for a kernel that
//! solves an implicit loop around them (the spring in the return path of a
//! feedback): a trial moves no state until it is committed, as
//! [`Operator::trial`] and [`Operator::commit`] of the spring alone.

use super::{BoucWenLanes, LaneState};
use crate::lanes::{select, WIDTH};
use crate::{check_input, check_output, Error, Operator, Result, Trial};

/// The trials of [`BoucWenLanes::trial_along`]: lane `j`'s output,
/// tangent and state `h` at its input, valid where `along[j]`.
#[derive(Debug, Clone, Copy)]
pub struct AlongTrial {
    /// `H = w S z + (1 − w) S h`.
    pub output: [f64; WIDTH],
    /// `dH/dz = w S + (1 − w) S (α − |g| (β sgn g + γ))`, `g = sgn(ż) h`
    /// (a constant stiffness map: `dS/dz = 0`).
    pub tangent: [f64; WIDTH],
    /// The state `h` at the input.
    pub h: [f64; WIDTH],
    /// Whether the lane's trial is the vector form's: it has moved, goes
    /// on along its branch (no reversal), which is in the common form, its
    /// stiffness map is constant, and its output and tangent are finite
    /// (not NaN). Elsewhere [`BoucWenLanes::trial_lane`] gives the lane's
    /// trial, or its error.
    pub along: [bool; WIDTH],
}

impl BoucWenLanes {
    /// Every lane's trial at its own input `z[j]`, where it goes on along
    /// its branch, [`WIDTH`] lanes per instruction: the bits of the
    /// spring's own [`trial`](Operator::trial) at `z[j]`, from the state the
    /// lane has committed, for every lane marked
    /// [`along`](AlongTrial::along). No state moves; commit a lane's trial
    /// by [`commit_along`](Self::commit_along).
    // `j < WIDTH`, the length of every lane array.
    #[allow(clippy::indexing_slicing)]
    #[inline(always)]
    pub fn trial_along(&self, z: &[f64; WIDTH]) -> AlongTrial {
        let constant = self.stiffness.is_some();
        let stiffness = self.stiffness.unwrap_or([f64::NAN; WIDTH]);
        let mut arg = [0.0; WIDTH];
        let mut asym = [0.0; WIDTH];
        let mut fc = [0.0; WIDTH];
        let mut along = [false; WIDTH];
        for j in 0..WIDTH {
            along[j] = constant & self.common[j] & (self.sign[j] * (z[j] - self.z[j]) >= 0.0);
            (_, arg[j], asym[j], fc[j]) = self.piece(j, z[j]);
        }
        let e = arg.map(crate::exp_kernel::exp);
        let mut t = AlongTrial {
            output: [0.0; WIDTH],
            tangent: [0.0; WIDTH],
            h: [0.0; WIDTH],
            along,
        };
        for j in 0..WIDTH {
            let (w, one_w, s, sign) = (self.w[j], self.one_w[j], stiffness[j], self.sign[j]);
            let h = sign * (asym[j] - fc[j] * e[j]);
            // (`trial_closed_form`'s output and tangent, `dS/dz = 0`)
            let ds = 0.0;
            let g = sign * h;
            let c_g = select(g < 0.0, self.c_down[j], self.c_up[j]);
            let slope = self.alpha[j] - g.abs() * c_g;
            let output = w * s * z[j] + one_w * s * h;
            let tangent = w * (s + ds * z[j]) + one_w * (ds * h + s * slope);
            t.h[j] = h;
            t.output[j] = output;
            t.tangent[j] = tangent;
            t.along[j] &= output.is_finite() & !tangent.is_nan();
        }
        t
    }

    /// Commits the trials `t` of [`trial_along`](Self::trial_along) at the
    /// inputs `z` in the lanes where `take[j]` (each of them marked
    /// [`along`](AlongTrial::along)).
    #[inline(always)]
    pub fn commit_along(&mut self, take: &[bool; WIDTH], z: &[f64; WIDTH], t: &AlongTrial) {
        for (j, &take) in take.iter().enumerate() {
            let (Some(lz), Some(lh), Some(&z), Some(&h)) =
                (self.z.get_mut(j), self.h.get_mut(j), z.get(j), t.h.get(j))
            else {
                continue;
            };
            *lz = select(take, z, *lz);
            *lh = select(take, h, *lh);
        }
    }

    /// Lane `j`'s trial at `z` alone, in every case (a reversal starts a
    /// branch at the committed state, a lane before any motion at its own
    /// `z` stays at rest, a branch outside the common form or a lane with
    /// `n ≠ 1`): the spring's own [`trial`](Operator::trial), the same
    /// operations on the same values. The lane's state moves only when
    /// [`commit_lane`](Self::commit_lane) commits its last trial.
    ///
    /// # Errors
    /// As the spring's trial: [`Error::NonFiniteInput`] for a `z` that is
    /// not finite, [`Error::NonFiniteOutput`] where the state, output or
    /// tangent is not finite, [`Error::LengthMismatch`] for `j ≥`
    /// [`WIDTH`], and [`Error::NonFiniteOutput`] for a lane whose
    /// parameters its spring refused.
    pub fn trial_lane(&mut self, j: usize, z: f64) -> Result<Trial<f64>> {
        let refused = Error::NonFiniteOutput {
            operator: "bouc_wen",
            input: z,
        };
        if let Some(spring) = self.flow.spring_mut(j) {
            return spring.as_mut().ok_or(refused)?.trial(z);
        }
        let (Some(lane), Some(&cz), Some(&ch), Some(&csign), Some(&moving)) = (
            self.lanes.get_mut(j),
            self.z.get(j),
            self.h.get(j),
            self.sign.get(j),
            self.moving.get(j),
        ) else {
            return Err(Error::LengthMismatch {
                input: j,
                output: WIDTH,
            });
        };
        lane.pending = None;
        let z = check_input(z)?;
        // `direction`: the sign of the motion, the committed one where the
        // input holds (0, at rest, before any motion).
        let dz = z - cz;
        let (dir_moving, sign) = if dz > 0.0 {
            (true, 1.0)
        } else if dz < 0.0 {
            (true, -1.0)
        } else {
            (moving, csign)
        };
        let next = match lane.branch {
            Some(b) if moving && sign == csign => {
                let z_a = self.z_a.get(j).copied().unwrap_or(f64::NAN);
                LaneState {
                    z,
                    h: sign * b.at(sign * (z - z_a)),
                    sign,
                    started: None,
                }
            }
            _ if !dir_moving => LaneState {
                z: cz,
                h: ch,
                sign: 1.0,
                started: None,
            },
            _ => {
                let b = lane.eq.branch(sign * ch);
                LaneState {
                    z,
                    h: sign * b.at(sign * (z - cz)),
                    sign,
                    started: Some((cz, b)),
                }
            }
        };
        let h = next.h;
        if !h.is_finite() {
            return Err(refused);
        }
        let (s, ds) = lane.map.eval_with(&lane.slopes, z);
        let w = self.w.get(j).copied().unwrap_or(f64::NAN);
        let one_w = 1.0 - w;
        let output = w * s * z + one_w * s * h;
        let g = next.sign * h;
        let eq = &lane.eq;
        let c_g = if g < 0.0 {
            eq.gamma - eq.beta
        } else {
            eq.beta + eq.gamma
        };
        let slope = eq.alpha - g.abs() * c_g;
        let tangent = w * (s + ds * z) + one_w * (ds * h + s * slope);
        let t = check_output("bouc_wen", z, Trial { output, tangent })?;
        lane.pending = Some(next);
        Ok(t)
    }

    /// Commits lane `j`'s last trial of [`trial_lane`](Self::trial_lane)
    /// (nothing where there is none).
    pub fn commit_lane(&mut self, j: usize) {
        if let Some(spring) = self.flow.spring_mut(j) {
            if let Some(spring) = spring {
                spring.commit();
            }
            self.flow.refresh(j);
            return;
        }
        let Some(next) = self.lanes.get_mut(j).and_then(|l| l.pending.take()) else {
            return;
        };
        if let Some((z_a, branch)) = next.started {
            self.start_branch(j, next.sign, z_a, branch);
        }
        for (v, value) in [(&mut self.z, next.z), (&mut self.h, next.h)] {
            if let Some(v) = v.get_mut(j) {
                *v = value;
            }
        }
    }
}
