//! A mass-spring-damper in a feedback loop with a Bouc-Wen spring (the
//! Bouc-Wen benchmark system), [`WIDTH`] instances stepped together.

// The lane loops index every lane array by the lane `j`, the form that
// compiles to one vector operation per line.
#![allow(clippy::needless_range_loop)]

use crate::solve::{newton_done, solve, SolverOptions, Start, NEWTON_STEPS};
use hysteron_operators::lanes::{select, LaneLaw, WIDTH};
use hysteron_operators::{
    checked_step, AlongTrial, BoucWenLanes, BoucWenParams, MassSpringDamperParams, MsdState,
    NewmarkTerms,
};

/// One instance of `oversample(q, feedback(mass_spring_damper,
/// bouc_wen))`: the oscillator `m ÿ + c ẏ + k y = u − H` with the
/// Bouc-Wen spring's force `H[y]` fed back
/// ([`Oversample`](crate::Oversample) of a [`Feedback`](crate::Feedback)),
/// the law of the lane kernel [`MsdFeedbackLanes`].
///
/// # Requirements
/// Every instance of a block has the same `q` and `solver` (they are the
/// structure, not parameters); a lane whose `q` or `solver` differs from
/// the first lane's gives NaN (a failed lane); one whose parameters are
/// out of their domains is flagged by [`check`](LaneLaw::check).
///
/// ```
/// use hysteron_composition::{MsdFeedback, OperatorExt, Oversample};
/// use hysteron_operators::{lanes::run_lanes, BoucWen, BoucWenParams, Leaf};
/// use hysteron_operators::{MassSpringDamper, MassSpringDamperParams, Operator, StiffnessMap};
/// let forward = MassSpringDamperParams { m: 2.0, c: 10.0, k: 5e4, dt: 1.0 / 15000.0 };
/// let back = |beta: f64| BoucWenParams {
///     w: 0.0, alpha: 5e4, beta, gamma: -1100.0, n: 1.0, h0: 0.0, z0: 0.0,
///     stiffness: StiffnessMap::constant(1.0).unwrap(),
/// };
/// let laws: Vec<MsdFeedback> = [700.0, 800.0, 900.0]
///     .map(|beta| MsdFeedback::new(forward, back(beta), 20))
///     .to_vec();
/// let u: Vec<f64> = (0..300).map(|i| 40.0 * (0.05 * i as f64).sin()).collect();
/// let mut y = vec![0.0; 3 * u.len()];
/// run_lanes(&laws, &u, &mut y)?;
/// // each row is that instance run alone, bit for bit
/// let mut alone = Oversample::new(
///     MassSpringDamper::from_params(forward)?.feedback(BoucWen::from_params(back(900.0))?),
///     20,
/// )?;
/// assert_eq!(&y[600..], &alone.run(&u)?[..]);
/// # Ok::<(), hysteron_operators::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct MsdFeedback {
    /// The forward path, the oscillator (its `dt` the sub-step).
    pub forward: MassSpringDamperParams<f64>,
    /// The return path, the spring (`n = 1` and a constant stiffness map
    /// for the vector form; any other steps its lane alone).
    pub back: BoucWenParams<f64>,
    /// Sub-steps per sample (`q ≥ 1`; 1 is the feedback alone).
    pub q: usize,
    /// The feedback's solver.
    pub solver: SolverOptions<f64>,
}

impl MsdFeedback {
    /// The loop of `forward` and `back` at `q` sub-steps per sample, with
    /// the default solver.
    pub fn new(
        forward: MassSpringDamperParams<f64>,
        back: BoucWenParams<f64>,
        q: usize,
    ) -> MsdFeedback {
        MsdFeedback {
            forward,
            back,
            q,
            solver: SolverOptions::default(),
        }
    }
}

/// [`WIDTH`] loops of [`MsdFeedback`] with one input: the oscillators'
/// parameters and states lane by lane, the springs' in a
/// [`BoucWenLanes`], and each loop's committed outputs.
pub struct MsdFeedbackLanes {
    m: [f64; WIDTH],
    c: [f64; WIDTH],
    k: [f64; WIDTH],
    dt: [f64; WIDTH],
    /// The oscillators' step constants ([`NewmarkTerms`]), and their
    /// tangents `1/k_eff`.
    q_n: [f64; WIDTH],
    q2_n: [f64; WIDTH],
    k_eff: [f64; WIDTH],
    tangent_m: [f64; WIDTH],
    /// The oscillators' displacement, velocity and acceleration.
    y_m: [f64; WIDTH],
    v_m: [f64; WIDTH],
    a_m: [f64; WIDTH],
    back: BoucWenLanes,
    q: usize,
    solver: SolverOptions<f64>,
    /// The committed input (of the oversampling and of the loop, the same
    /// after every sample).
    x: f64,
    /// Each loop's committed output, and the three before it, newest first.
    y: [f64; WIDTH],
    before: [[f64; WIDTH]; 3],
    /// The lanes whose loop failed (their outputs are NaN from then on).
    failed: [bool; WIDTH],
}

/// The residual `R(y) = y − A[x − B[y]]` of every lane at its own `y`,
/// and the trials behind it.
#[derive(Clone, Copy)]
struct LoopEval {
    r: [f64; WIDTH],
    d: [f64; WIDTH],
    spring: AlongTrial,
    msd: [MsdState<f64>; WIDTH],
    /// Whether the lane's evaluation is the vector form's and succeeded.
    ok: [bool; WIDTH],
}

/// The feedback of [`Feedback::trial`](crate::Feedback) over `f64` in
/// every lane, its steps in lockstep: the root predicted from the last four
/// outputs, then the Newton steps of the crate's solver from it, each lane
/// stopping at the solver's test (`|r/d| ≤ abs_tol + rel_tol · |y|`, or the
/// first refinement test of a bracket that a step closed). A lane whose
/// search leaves that path (its spring reverses, or the steps stall, or a
/// bracket needs refining) is solved alone by the solver itself from the
/// same state and prediction, so every lane's outputs are the bits of its
/// instance alone. Each sample is `q` such sub-steps on the input
/// interpolated linearly, as [`Oversample`](crate::Oversample) steps.
impl LaneLaw for MsdFeedback {
    type Block = MsdFeedbackLanes;

    /// The oscillator's and the spring's parameters, and `q ≥ 1`.
    fn check(&self) -> hysteron_operators::Result<()> {
        self.forward.validate()?;
        self.back.validate()?;
        if self.q == 0 {
            return Err(hysteron_operators::check::invalid("q", 0.0, "must be ≥ 1"));
        }
        Ok(())
    }

    fn block(laws: &[Self]) -> MsdFeedbackLanes {
        let lane_of = |j: usize| laws.get(j).or(laws.last());
        let field = |f: fn(&MassSpringDamperParams<f64>) -> f64| -> [f64; WIDTH] {
            core::array::from_fn(|j| lane_of(j).map_or(f64::NAN, |l| f(&l.forward)))
        };
        let backs: Vec<BoucWenParams<f64>> = (0..WIDTH)
            .filter_map(|j| lane_of(j).map(|l| l.back.clone()))
            .collect();
        let first = laws.first();
        let q = first.map_or(1, |l| l.q.max(1));
        let solver = first.map_or_else(SolverOptions::default, |l| l.solver);
        // (a lane whose parameters its leaves refuse is not solved:
        // `run_lanes` flags it by `check`)
        let failed = core::array::from_fn(|j| {
            lane_of(j).is_none_or(|l| l.q != q || l.solver != solver || l.check().is_err())
        });
        let y0 = [0.0; WIDTH];
        let terms: [NewmarkTerms<f64>; WIDTH] = core::array::from_fn(|j| {
            lane_of(j).map_or(
                NewmarkTerms {
                    q: f64::NAN,
                    q2: f64::NAN,
                    k_eff: f64::NAN,
                },
                |l| l.forward.newmark_terms(),
            )
        });
        MsdFeedbackLanes {
            q_n: terms.map(|t| t.q),
            q2_n: terms.map(|t| t.q2),
            k_eff: terms.map(|t| t.k_eff),
            // (the oscillator's tangent, as its `step` computes it)
            tangent_m: terms.map(|t| 1.0 / t.k_eff),
            m: field(|p| p.m),
            c: field(|p| p.c),
            k: field(|p| p.k),
            dt: field(|p| p.dt),
            y_m: y0,
            v_m: y0,
            a_m: y0,
            back: <BoucWenParams<f64> as LaneLaw>::block(&backs),
            q,
            solver,
            x: 0.0,
            y: y0,
            before: [y0; 3],
            failed,
        }
    }

    // `j < WIDTH`, the length of every lane array.
    #[allow(clippy::indexing_slicing)]
    #[inline(always)]
    fn step_lanes(b: &mut MsdFeedbackLanes, x: f64, y: &mut [f64; WIDTH]) {
        let (x0, dx) = (b.x, x - b.x);
        let q = b.q as f64;
        let mut x_prev = b.x;
        for i in 1..=b.q {
            let xi = if i == b.q {
                x
            } else {
                x0 + dx * (i as f64 / q)
            };
            b.substep(x_prev, xi);
            x_prev = xi;
        }
        b.x = x;
        for j in 0..WIDTH {
            y[j] = if b.failed[j] { f64::NAN } else { b.y[j] };
        }
    }
}

impl MsdFeedbackLanes {
    /// The oscillator of lane `j`.
    // `j < WIDTH`, the length of every lane array.
    #[allow(clippy::indexing_slicing)]
    #[inline(always)]
    fn forward(&self, j: usize) -> MassSpringDamperParams<f64> {
        MassSpringDamperParams {
            m: self.m[j],
            c: self.c[j],
            k: self.k[j],
            dt: self.dt[j],
        }
    }

    /// Every lane's residual at its own `y` for the loop input `x`, where
    /// the spring goes on along its branch (elsewhere not `ok`).
    // `j < WIDTH`, the length of every lane array.
    #[allow(clippy::indexing_slicing)]
    #[inline(always)]
    fn eval(&self, x: f64, y: &[f64; WIDTH]) -> LoopEval {
        let spring = self.back.trial_along(y);
        let mut e = LoopEval {
            r: [0.0; WIDTH],
            d: [0.0; WIDTH],
            spring,
            msd: [MsdState {
                y: 0.0,
                v: 0.0,
                a: 0.0,
            }; WIDTH],
            ok: [false; WIDTH],
        };
        for j in 0..WIDTH {
            let u = x - spring.output[j];
            let s = MsdState {
                y: self.y_m[j],
                v: self.v_m[j],
                a: self.a_m[j],
            };
            let terms = NewmarkTerms {
                q: self.q_n[j],
                q2: self.q2_n[j],
                k_eff: self.k_eff[j],
            };
            let next = self.forward(j).newmark(&terms, &s, u);
            // (the oscillator's `checked_step`: its input, state, output
            // and tangent finite)
            let tangent = self.tangent_m[j];
            let fine = u.is_finite()
                & next.a.is_finite()
                & next.v.is_finite()
                & next.y.is_finite()
                & !tangent.is_nan();
            e.r[j] = y[j] - next.y;
            e.d[j] = 1.0 + tangent * spring.tangent[j];
            e.msd[j] = next;
            e.ok[j] = spring.along[j] & fine & !e.r[j].is_nan();
        }
        e
    }

    /// One sub-step of every loop to the input `x` from `x_prev`: the
    /// lanes in lockstep, any lane that leaves the common path by the
    /// solver alone, then every root committed.
    // `j < WIDTH`, the length of every lane array.
    #[allow(clippy::indexing_slicing)]
    #[inline(always)]
    fn substep(&mut self, x_prev: f64, x: f64) {
        let opts = self.solver;
        let mut guess = [0.0; WIDTH];
        for (j, g) in guess.iter_mut().enumerate() {
            let [y1, y2, y3] = [self.before[0][j], self.before[1][j], self.before[2][j]];
            *g = 4.0 * (self.y[j] + y2) - 6.0 * y1 - y3;
        }
        // The point each lane is at, its evaluation, and whether it is
        // still on the common path (`fast`), at its root (`done`).
        let mut at = guess;
        let mut cur = self.eval(x, &at);
        let mut fast = [false; WIDTH];
        let mut done = [false; WIDTH];
        for j in 0..WIDTH {
            fast[j] = !self.failed[j] & at[j].is_finite() & cur.ok[j];
            // (an evaluation exactly at the root)
            done[j] = fast[j] & (cur.r[j] == 0.0);
        }
        let scale: [f64; WIDTH] = core::array::from_fn(|j| x.abs().max(self.y[j].abs()));
        for _ in 0..NEWTON_STEPS {
            // Every live lane's test and step, without a branch per lane.
            let mut next = at;
            let mut steps = [0.0; WIDTH];
            let mut stepping = [false; WIDTH];
            for j in 0..WIDTH {
                let live = fast[j] & !done[j];
                let (x_j, r, d) = (at[j], cur.r[j], cur.d[j]);
                let smooth = d.is_finite() & (d != 0.0);
                let step = r / d;
                let converged = newton_done(x_j, step, &opts);
                let to = x_j - step;
                let moves = to.is_finite() & (to != x_j);
                done[j] |= live & smooth & converged;
                // (stalled: no usable step)
                fast[j] &= !(live & !(smooth & (converged | moves)));
                stepping[j] = live & smooth & !converged & moves;
                next[j] = select(stepping[j], to, x_j);
                steps[j] = step;
            }
            if !stepping.contains(&true) {
                break;
            }
            let new = self.eval(x, &next);
            let mut take = [false; WIDTH];
            for j in 0..WIDTH {
                let (r, d, rn, dn) = (cur.r[j], cur.d[j], new.r[j], new.d[j]);
                let ok = stepping[j] & new.ok[j];
                // A zero reached by a step no longer than the scale is the
                // root; one beyond it is confirmed alone.
                let zero = rn == 0.0;
                let small = steps[j].abs() <= at[j].abs().max(scale[j]);
                // A bracket: the refinement's first tests at its start
                // (the end with the smaller residual), else alone.
                let flips = rn.signum() != r.signum();
                let start_new = r.abs() > rn.abs();
                let xs = select(start_new, next[j], at[j]);
                let rs = select(start_new, rn, r);
                let ds = select(start_new, dn, d);
                let r_neg = r < 0.0;
                let neg = select(r_neg, at[j], next[j]);
                let pos = select(r_neg, next[j], at[j]);
                let ordered = neg < pos;
                let (lo, hi) = (select(ordered, neg, pos), select(ordered, pos, neg));
                let closed = (hi - lo <= opts.tol(xs, scale[j]))
                    | (ds.is_finite() & (ds != 0.0) & ((rs / ds).abs() <= opts.tol(xs, 0.0)));
                let at_zero = ok & zero & small;
                let bracketed = ok & !zero & flips & closed;
                // (a step that at least halved the residual goes on)
                let halved = ok & !zero & !flips & (rn.abs() <= r.abs() * 0.5);
                done[j] |= at_zero | bracketed;
                take[j] = at_zero | (bracketed & start_new) | halved;
                fast[j] &= !stepping[j] | at_zero | bracketed | halved;
            }
            cur = merge(&take, &new, &cur);
            for j in 0..WIDTH {
                at[j] = select(take[j], next[j], at[j]);
            }
        }
        // The lanes at their roots commit their last evaluations there.
        for j in 0..WIDTH {
            done[j] &= fast[j];
        }
        self.back.commit_along(&done, &at, &cur.spring);
        let mut root = [f64::NAN; WIDTH];
        for j in 0..WIDTH {
            if done[j] {
                (self.y_m[j], self.v_m[j], self.a_m[j]) =
                    (cur.msd[j].y, cur.msd[j].v, cur.msd[j].a);
                root[j] = at[j];
            }
        }
        for j in 0..WIDTH {
            if !done[j] && !self.failed[j] {
                match self.solve_alone(j, x_prev, x, guess[j]) {
                    Some(y) => root[j] = y,
                    None => self.failed[j] = true,
                }
            }
        }
        for j in 0..WIDTH {
            self.before[2][j] = self.before[1][j];
            self.before[1][j] = self.before[0][j];
            self.before[0][j] = self.y[j];
            self.y[j] = root[j];
        }
    }

    /// Lane `j`'s sub-step by the solver alone (what
    /// [`Feedback::trial`](crate::Feedback) does, on this lane's state),
    /// committed; its root, or `None` where the loop fails there.
    // `j < WIDTH` (from `substep`), the length of every lane array.
    #[allow(clippy::indexing_slicing)]
    #[cold]
    #[inline(never)]
    fn solve_alone(&mut self, j: usize, x_prev: f64, x: f64, guess: f64) -> Option<f64> {
        let law = self.forward(j);
        let committed = MsdState {
            y: self.y_m[j],
            v: self.v_m[j],
            a: self.a_m[j],
        };
        let y_j = self.y[j];
        let back = &mut self.back;
        let mut pending = committed;
        let residual = |y: f64| {
            let b = back.trial_lane(j, y)?;
            let (next, a) = checked_step(&law, &committed, x - b.output)?;
            pending = next;
            Ok((y - a.output, 1.0 + a.tangent * b.tangent))
        };
        let start = Start::at_committed(y_j, x_prev, x).with_guess(guess);
        let root = solve("feedback", residual, start, &self.solver).ok()?;
        self.back.commit_lane(j);
        (self.y_m[j], self.v_m[j], self.a_m[j]) = (pending.y, pending.v, pending.a);
        Some(root.value())
    }
}

/// `new` in the lanes where `take[j]`, else `cur`.
// `j < WIDTH`, the length of every lane array.
#[allow(clippy::indexing_slicing)]
#[inline(always)]
fn merge(take: &[bool; WIDTH], new: &LoopEval, cur: &LoopEval) -> LoopEval {
    let mut out = *cur;
    for j in 0..WIDTH {
        let t = take[j];
        out.r[j] = select(t, new.r[j], cur.r[j]);
        out.d[j] = select(t, new.d[j], cur.d[j]);
        out.spring.output[j] = select(t, new.spring.output[j], cur.spring.output[j]);
        out.spring.tangent[j] = select(t, new.spring.tangent[j], cur.spring.tangent[j]);
        out.spring.h[j] = select(t, new.spring.h[j], cur.spring.h[j]);
        out.msd[j].y = select(t, new.msd[j].y, cur.msd[j].y);
        out.msd[j].v = select(t, new.msd[j].v, cur.msd[j].v);
        out.msd[j].a = select(t, new.msd[j].a, cur.msd[j].a);
        out.ok[j] = if t { new.ok[j] } else { cur.ok[j] };
        out.spring.along[j] = if t {
            new.spring.along[j]
        } else {
            cur.spring.along[j]
        };
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{OperatorExt, Oversample};
    use hysteron_operators::lanes::{check_each_alone, run_lanes};
    use hysteron_operators::{BoucWen, MassSpringDamper, Operator, StiffnessMap};

    /// The benchmark's oscillator and spring, instance `i` with every
    /// parameter moved by a few per cent (and `w` from 0).
    fn law(i: usize, q: usize) -> MsdFeedback {
        let f = i as f64;
        let forward = MassSpringDamperParams {
            m: 2.0 * (1.0 + 0.03 * f),
            c: 10.0 * (1.0 - 0.04 * f),
            k: 5e4 * (1.0 + 0.02 * f),
            dt: 1.0 / (750.0 * q as f64),
        };
        let back = BoucWenParams {
            w: 0.01 * f,
            alpha: 5e4 * (1.0 - 0.02 * f),
            beta: 800.0 * (1.0 + 0.05 * f),
            gamma: -1100.0 * (1.0 - 0.03 * f),
            n: 1.0,
            h0: 0.0,
            z0: 0.0,
            stiffness: StiffnessMap::constant(1.0 + 0.01 * f).unwrap(),
        };
        MsdFeedback::new(forward, back, q)
    }

    /// A force like the benchmark's (a multisine of some 50 N at 750 Hz),
    /// with a step and a hold, so that some sub-steps leave the common
    /// path (reversals inside a search, brackets).
    fn force(n: usize) -> Vec<f64> {
        (0..n)
            .map(|i| {
                let t = i as f64 / 750.0;
                let step = if (300..320).contains(&i) { 150.0 } else { 0.0 };
                let hold = if i % 97 == 13 { 0.0 } else { 1.0 };
                hold * (40.0 * (2.0 * std::f64::consts::PI * 7.0 * t).sin()
                    + 15.0 * (2.0 * std::f64::consts::PI * 53.0 * t).sin()
                    + 5.0 * (2.0 * std::f64::consts::PI * 181.0 * t).sin())
                    + step
            })
            .collect()
    }

    /// Every lane's outputs are the bits of its loop run alone, or it is
    /// flagged where that run fails.
    fn each_alone(laws: &[MsdFeedback], x: &[f64]) {
        check_each_alone(laws, x, |law| {
            let alone = MassSpringDamper::from_params(law.forward)?
                .feedback(BoucWen::from_params(law.back.clone())?)
                .with_solver(law.solver);
            Oversample::new(alone, law.q)?.run(x)
        })
        .unwrap();
    }

    /// Eleven benchmark systems (a full block and a part) at 20 sub-steps
    /// per sample, and at one.
    #[test]
    fn loops_in_lanes_are_each_loop_alone() {
        for q in [20, 1] {
            let laws: Vec<_> = (0..11).map(|i| law(i, q)).collect();
            each_alone(&laws, &force(if q == 1 { 3000 } else { 600 }));
        }
    }

    /// Springs outside the vector form (an exponent of 1.5, a piecewise
    /// stiffness map, `β = γ`) step alone in their lanes, with their bits.
    #[test]
    fn springs_outside_the_vector_form_are_each_alone() {
        let mut laws: Vec<_> = (0..8).map(|i| law(i, 4)).collect();
        laws[1].back.n = 1.5;
        laws[3].back.stiffness = StiffnessMap::new(vec![0.0, 1e-3], vec![1.0, 1.5]).unwrap();
        laws[5].back.gamma = laws[5].back.beta;
        each_alone(&laws, &force(500));
        // every spring with an exponent other than 1 (their lanes held on
        // their tables, each trial and commit by the lane's spring)
        let laws: Vec<_> = (0..8)
            .map(|i| {
                let mut l = law(i, 4);
                l.back.n = 1.2 + 0.1 * i as f64;
                l
            })
            .collect();
        each_alone(&laws, &force(300));
    }

    /// A loop that diverges (a spring that hardens without bound) is
    /// flagged, and the others finish with their own bits; a lane whose
    /// sub-step count differs from the block's is flagged too, and so is
    /// one whose oscillator's stiffness is refused (it would run).
    #[test]
    fn a_failing_lane_is_flagged_and_the_others_finish() {
        let mut laws: Vec<_> = (0..8).map(|i| law(i, 5)).collect();
        laws[2].back.beta = -4e4;
        laws[2].back.gamma = -4e4;
        let x: Vec<f64> = force(400).iter().map(|v| 40.0 * v).collect();
        each_alone(&laws, &x);
        let mut laws: Vec<_> = (0..4).map(|i| law(i, 5)).collect();
        laws[1].q = 4;
        laws[3].forward.k = -1.0;
        let mut out = vec![0.0; 4 * 50];
        assert_eq!(run_lanes(&laws, &force(50), &mut out).unwrap(), vec![1, 3]);
    }
}
