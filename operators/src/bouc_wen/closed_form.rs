//! `n = 1`: every sample in closed form along its branch.

use super::state::{BranchStart, State};
use super::BoucWen;
use crate::{check_input, check_output, Float, Leaf, Result, Trial};

impl<T: Float> BoucWen<T> {
    /// [`step`](BoucWen::step) for `n = 1`: closed form along the branch
    /// that started at the last reversal (a new one starts when the
    /// direction changes).
    #[inline(always)]
    pub(super) fn step_closed_form(&self, z: T, dir: i64, sign: T) -> Result<State<T>> {
        let c = &self.s;
        let (z_a, branch) = match c.branch {
            BranchStart::Linear(b) if dir == c.dir => (c.z_a, b),
            _ if dir == 0 => return Ok(self.at_rest(z)),
            _ => (c.z, self.eq.branch(sign * c.h)),
        };
        let h = sign * branch.at(sign * (z - z_a));
        if !h.is_finite() {
            return Err(crate::Error::NonFiniteOutput {
                operator: Self::KIND,
                input: z.as_f64(),
            });
        }
        Ok(State {
            z,
            h,
            dir,
            z_a,
            branch: BranchStart::Linear(branch),
        })
    }

    /// [`trial`](Operator::trial) for `n = 1`: the same values as
    /// [`step`](Self::step) followed by the output and tangent of `trial`,
    /// computed in place from the committed state (the branch is read where
    /// it is, not copied through intermediate states), with `dh/dz` of the
    /// linear rate `α − c |h|` written out.
    #[inline(always)]
    pub(super) fn trial_closed_form(&mut self, z: T) -> Result<Trial<T>> {
        self.pending = None;
        let z = check_input(z)?;
        let (dir, sign) = self.direction(z);
        let c = &self.s;
        let next = match &c.branch {
            BranchStart::Linear(b) if dir == c.dir => State {
                z,
                h: sign * b.at(sign * (z - c.z_a)),
                dir,
                z_a: c.z_a,
                branch: c.branch,
            },
            // No motion yet: the initial state.
            _ if dir == 0 => self.at_rest(z),
            _ => {
                let b = self.eq.branch(sign * c.h);
                State {
                    z,
                    h: sign * b.at(sign * (z - c.z)),
                    dir,
                    z_a: c.z,
                    branch: BranchStart::Linear(b),
                }
            }
        };
        let h = next.h;
        if !h.is_finite() {
            return Err(crate::Error::NonFiniteOutput {
                operator: Self::KIND,
                input: z.as_f64(),
            });
        }
        let (s, ds) = self.p.stiffness.eval_with(&self.slopes, z);
        let w = self.p.w;
        let one_w = T::one() - w;
        let output = self.force(s, z, h);
        // dh/dz = α − c |g| with g = sgn(ż) h (the state equation's rate
        // for n = 1, without dispatching on the exponent).
        let g = sign * h;
        let eq = &self.eq;
        let c_g = if g < T::zero() {
            eq.gamma - eq.beta
        } else {
            eq.beta + eq.gamma
        };
        let slope = eq.alpha - g.abs() * c_g;
        let tangent = w * (s + ds * z) + one_w * (ds * h + s * slope);
        let t = check_output(Self::KIND, z, Trial { output, tangent })?;
        self.pending = Some(next);
        Ok(t)
    }

    /// [`trial_value`](Hints::trial_value) for `n = 1`: the values of
    /// [`trial_closed_form`](Self::trial_closed_form), the branch's terms
    /// taken as values (a new branch is made over `T` at the value of its
    /// start); `None` before any motion.
    pub(super) fn trial_value_closed_form(&self, z: f64) -> Option<Result<Trial<f64>>> {
        let (dir, sign) = self.direction_value(z);
        let c = &self.s;
        let h = match &c.branch {
            BranchStart::Linear(b) if dir == c.dir => {
                sign * b.value().at(sign * (z - c.z_a.as_f64()))
            }
            _ if dir == 0 => return None,
            _ => {
                let b = self.eq.branch(T::lit(sign * c.h.as_f64())).value();
                sign * b.at(sign * (z - c.z.as_f64()))
            }
        };
        if !h.is_finite() {
            return Some(Err(crate::Error::NonFiniteOutput {
                operator: Self::KIND,
                input: z,
            }));
        }
        // `trial_closed_form`'s rate, on constants
        let g = T::lit(sign * h);
        let eq = &self.eq;
        let c_g = if g < T::zero() {
            eq.gamma - eq.beta
        } else {
            eq.beta + eq.gamma
        };
        Some(self.value_trial(z, h, eq.alpha - g.abs() * c_g))
    }

    /// `direction` on values: the direction of motion to `z` and its sign.
    pub(super) fn direction_value(&self, z: f64) -> (i64, f64) {
        let dz = z - self.s.z.as_f64();
        let dir = if dz > 0.0 {
            1
        } else if dz < 0.0 {
            -1
        } else {
            self.s.dir
        };
        (dir, if dir < 0 { -1.0 } else { 1.0 })
    }

    /// `trial`'s output and tangent at input `z`, state `h` and rate
    /// `slope`, computed over `T` on constants (the same operations on the
    /// same values), as values.
    pub(super) fn value_trial(&self, z: f64, h: f64, slope: T) -> Result<Trial<f64>> {
        let (z, h) = (T::lit(z), T::lit(h));
        let (s, ds) = self.p.stiffness.eval_with(&self.slopes, z);
        let w = self.p.w;
        let output = self.force(s, z, h);
        let tangent = w * (s + ds * z) + (T::one() - w) * (ds * h + s * slope);
        check_output(Self::KIND, z, Trial { output, tangent }).map(|t| Trial {
            output: t.output.as_f64(),
            tangent: t.tangent.as_f64(),
        })
    }
}
