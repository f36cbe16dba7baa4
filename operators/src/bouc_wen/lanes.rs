//! [`WIDTH`] springs with different parameters stepped together over one
//! input, for `n = 1` (closed form).

use super::BoucWenParams;
use crate::hysteretic_state::{Branch, ExpForm, Power, StateEquation};
use crate::lanes::{select, step_tile_in_runs, LaneLaw, TILE, WIDTH};
use crate::{BoucWen, Operator, ParamSet, StiffnessMap};

mod flow;
mod trial;

use flow::FlowLanes;
pub use trial::AlongTrial;

/// What one lane needs besides its vector terms: its state equation (to
/// start a branch at a reversal), its stiffness map, and the branch itself
/// where the vector form does not cover it.
struct Lane {
    eq: StateEquation<f64>,
    map: StiffnessMap<f64>,
    slopes: Vec<f64>,
    /// The stiffness map's segment at the last sample.
    segment: usize,
    /// The current branch where it is not in [`ExpForm`] (evaluated by
    /// [`Branch::at`] in this lane alone).
    odd: Option<Branch<f64>>,
    /// The current branch (`None` before any motion), for a trial of this
    /// lane alone ([`BoucWenLanes::trial_lane`]).
    branch: Option<Branch<f64>>,
    /// The state of this lane's last trial alone, until committed.
    pending: Option<LaneState>,
}

/// A lane's state after a trial of it alone: its input `z`, state `h`,
/// direction `sign` and, where the trial started a branch, its start and terms.
#[derive(Debug, Clone, Copy)]
struct LaneState {
    z: f64,
    h: f64,
    sign: f64,
    started: Option<(f64, Branch<f64>)>,
}

/// Eight Bouc-Wen springs with one input: for each lane its parameters,
/// state `(z, h)`, direction, branch start `z_a` and the terms of its
/// branch, lane by lane; lanes with `n ≠ 1` on their tabulated flows.
pub struct BoucWenLanes {
    w: [f64; WIDTH],
    /// `1 − w`.
    one_w: [f64; WIDTH],
    /// Each lane's stiffness where every map is constant.
    stiffness: Option<[f64; WIDTH]>,
    z: [f64; WIDTH],
    h: [f64; WIDTH],
    /// The direction of motion `±1` (`+1` before any motion).
    sign: [f64; WIDTH],
    /// Whether the lane has moved (has a branch).
    moving: [bool; WIDTH],
    z_a: [f64; WIDTH],
    s0: [f64; WIDTH],
    c_a: [f64; WIDTH],
    fc_a: [f64; WIDTH],
    inf_a: [f64; WIDTH],
    c_0: [f64; WIDTH],
    fc_0: [f64; WIDTH],
    /// `α`, and the state equation's `β + γ` and `γ − β` (the rate's
    /// coefficient for `g ≥ 0` and `g < 0`), for the tangent.
    alpha: [f64; WIDTH],
    c_up: [f64; WIDTH],
    c_down: [f64; WIDTH],
    /// Whether the lane has moved, its branch is in [`ExpForm`] and its
    /// exponent is 1: where [`trial_along`](BoucWenLanes::trial_along)
    /// covers it.
    common: [bool; WIDTH],
    lanes: Vec<Lane>,
    /// Whether a lane's branch is outside the common form.
    odd: bool,
    /// The lanes with `n ≠ 1`: their springs, and where every lane is one
    /// on its table, their states lane by lane.
    flow: FlowLanes,
}

/// The `n = 1` spring ([`BoucWen`], closed form) in every lane:
///
/// `H = w S(z) z + (1 − w) S(z) h`, `h = sgn(ż) g(sgn(ż) (z − z_a))`,
///
/// each branch `g(s) = g∞ − (f/c) e^{−c s}` from its start (the last
/// reversal `z_a`), with the terms the spring precomputes there. The lanes
/// do the operations of the spring's own loop in the same order, with no
/// fused multiply-add, and the exponential is the spring's own branch-free
/// kernel (`exp_kernel::exp`), so every lane's outputs are the
/// bits of the instance alone, on every instruction set, while the
/// exponentials, comparisons, selects, products and sums run [`WIDTH`]
/// lanes per instruction. A reversal (starting each lane's branch, a
/// logarithm and divisions), a lane at rest before its first motion and a
/// branch outside the common form (a side with `c = 0`, or a first piece
/// evaluated with `expm1`, where `|β − γ|` is below a sixteenth of
/// `β + γ`) are handled lane by lane.
///
/// A block whose springs all have exponents other than 1 steps each lane
/// on its own tabulated flow, `h = sgn(ż) G(σ_a + sgn(ż) (z − z_a))`: the
/// quintic piece of its table that each lane's state is on is held lane by
/// lane and evaluated [`WIDTH`] lanes per instruction, with the spring's
/// operations. A lane that leaves its piece takes the next from its table;
/// a reversal (the branch start's position `σ_a`, a Newton search on the
/// table), a lane at rest, on the saturating tail or off its table
/// (integrated) takes its spring's own step. Each lane gives its spring's
/// bits. In a block mixing exponent 1 with others, each spring with another
/// exponent steps alone, one sample at a time, also with its bits.
impl LaneLaw for BoucWenParams<f64> {
    type Block = BoucWenLanes;

    fn check(&self) -> crate::Result<()> {
        self.validate()
    }

    fn block(laws: &[Self]) -> BoucWenLanes {
        let lane_of = |j: usize| laws.get(j).or(laws.last());
        let field = |f: fn(&Self) -> f64| -> [f64; WIDTH] {
            core::array::from_fn(|j| lane_of(j).map_or(0.0, f))
        };
        let rtol = BoucWen::<f64>::default_tolerance();
        let mut lanes = Vec::with_capacity(WIDTH);
        let mut others = Vec::new();
        for j in 0..WIDTH {
            // (`laws` is not empty: `run_lanes` passes one to WIDTH laws)
            let p = lane_of(j).cloned().unwrap_or_else(BoucWenParams::example);
            let eq = StateEquation::new(p.alpha, p.beta, p.gamma, p.n, rtol);
            let map = p.stiffness.clone();
            if eq.power != Power::One {
                others.push((j, BoucWen::from_params(p).ok()));
            }
            lanes.push(Lane {
                eq,
                slopes: map.slopes(),
                map,
                segment: 0,
                odd: None,
                branch: None,
                pending: None,
            });
        }
        let stiffness = if lanes.iter().all(|l| l.map.len() == 1) {
            let mut s = [0.0; WIDTH];
            for (s, l) in s.iter_mut().zip(&mut lanes) {
                *s = l.map.eval_from(&l.slopes, 0.0, &mut l.segment).0;
            }
            Some(s)
        } else {
            None
        };
        let w = field(|p| p.w);
        let z0 = field(|p| p.z0);
        let eq_field = |f: fn(&StateEquation<f64>) -> f64| -> [f64; WIDTH] {
            core::array::from_fn(|j| lanes.get(j).map_or(0.0, |l| f(&l.eq)))
        };
        BoucWenLanes {
            alpha: eq_field(|eq| eq.alpha),
            c_up: eq_field(|eq| eq.beta + eq.gamma),
            c_down: eq_field(|eq| eq.gamma - eq.beta),
            common: [false; WIDTH],
            w,
            one_w: w.map(|w| 1.0 - w),
            stiffness,
            z: z0,
            h: field(|p| p.h0),
            sign: [1.0; WIDTH],
            moving: [false; WIDTH],
            z_a: z0,
            s0: [f64::INFINITY; WIDTH],
            c_a: [1.0; WIDTH],
            fc_a: [0.0; WIDTH],
            inf_a: [0.0; WIDTH],
            c_0: [1.0; WIDTH],
            fc_0: [0.0; WIDTH],
            lanes,
            odd: false,
            flow: FlowLanes::new(others),
        }
    }

    // `j < WIDTH`, the length of every lane array.
    #[allow(clippy::indexing_slicing)]
    #[inline(always)]
    fn step_lanes(b: &mut BoucWenLanes, x: f64, y: &mut [f64; WIDTH]) {
        if b.flow.lockstep {
            b.step_flow(x, y);
            return;
        }
        // Every lane goes on along its branch (or stands still on it), the
        // common case once the lanes have moved: the input is common.
        let mut goes_on = true;
        for j in 0..WIDTH {
            goes_on &= b.moving[j] & (b.sign[j] * (x - b.z[j]) >= 0.0);
        }
        let mut rest = [false; WIDTH];
        if !goes_on {
            b.turn(x, &mut rest);
        }
        // `Branch::at(s)` in every lane: past the zero crossing `s0` the
        // piece from `g = 0` (asymptote `f_0/c_0`), else the first.
        let mut travel = [0.0; WIDTH];
        let mut arg = [0.0; WIDTH];
        let mut asym = [0.0; WIDTH];
        let mut fc = [0.0; WIDTH];
        // (both pieces' arguments are computed and one is selected; the
        // piece not taken may be infinite or NaN)
        for j in 0..WIDTH {
            (travel[j], arg[j], asym[j], fc[j]) = b.piece(j, x);
        }
        let e = arg.map(crate::exp_kernel::exp);
        let mut h = [0.0; WIDTH];
        for j in 0..WIDTH {
            h[j] = b.sign[j] * (asym[j] - fc[j] * e[j]);
        }
        // The lanes outside the common form, and those at rest (at their
        // own `z`).
        let mut z = [x; WIDTH];
        if !goes_on || b.odd {
            for (j, lane) in b.lanes.iter().enumerate() {
                if rest[j] {
                    (z[j], h[j]) = (b.z[j], b.h[j]);
                } else if let Some(branch) = &lane.odd {
                    h[j] = b.sign[j] * branch.at(travel[j]);
                }
            }
        }
        b.forces(&z, &h, y);
        b.z = z;
        b.h = h;
        for (j, spring) in &mut b.flow.springs {
            let out = spring.as_mut().and_then(|spring| {
                let mut v = [0.0];
                spring.process(&[x], &mut v).ok().map(|()| v[0])
            });
            if let Some(y) = y.get_mut(*j) {
                *y = out.unwrap_or(f64::NAN);
            }
            // (a spring that fails has failed for good, as its run alone
            // ends there: its lane stays NaN and it is not stepped again)
            if out.is_none() {
                *spring = None;
            }
        }
    }

    /// Where every lane is a spring on its table, sample by sample
    /// ([`step_lanes`](LaneLaw::step_lanes)); else in runs along the
    /// branches ([`step_tile_in_runs`]).
    #[inline(always)]
    fn step_tile(b: &mut BoucWenLanes, xs: &[f64; TILE], ys: &mut [[f64; WIDTH]; TILE]) {
        if b.flow.lockstep {
            for (x, y) in xs.iter().zip(ys) {
                b.step_flow(*x, y);
            }
        } else {
            step_tile_in_runs::<Self>(b, xs, ys);
        }
    }

    /// Every lane goes on along its branch (no reversal, no lane at rest
    /// or outside the common form, constant stiffness, every exponent 1:
    /// the common case).
    #[inline(always)]
    fn run_length(b: &BoucWenLanes, xs: &[f64]) -> usize {
        b.run_along_branches(xs)
    }

    /// The operations of [`step_lanes`](LaneLaw::step_lanes) per lane and
    /// sample, in its order, two samples per iteration.
    #[inline(always)]
    fn go_on(b: &mut BoucWenLanes, xs: &[f64], ys: &mut [[f64; WIDTH]]) {
        b.go_on(xs, ys);
    }
}

impl BoucWenLanes {
    /// `H = w S(z) z + (1 − w) S(z) h` in every lane, the spring's
    /// operations (the stiffness map's segment searched from the lane's
    /// last where the maps are not all constant).
    // `j < WIDTH`, the length of every lane array.
    #[allow(clippy::indexing_slicing)]
    #[inline(always)]
    fn forces(&mut self, z: &[f64; WIDTH], h: &[f64; WIDTH], y: &mut [f64; WIDTH]) {
        let s = match self.stiffness {
            Some(s) => s,
            None => {
                let mut s = [0.0; WIDTH];
                for ((s, lane), &z) in s.iter_mut().zip(&mut self.lanes).zip(z) {
                    *s = lane.map.eval_from(&lane.slopes, z, &mut lane.segment).0;
                }
                s
            }
        };
        for j in 0..WIDTH {
            y[j] = self.w[j] * s[j] * z[j] + self.one_w[j] * s[j] * h[j];
        }
    }

    /// Lane `j`'s travel `s = sgn(ż) (x − z_a)` to `x` along its branch,
    /// and the terms of the piece of [`Branch::at`] there: past the zero
    /// crossing `s0` the piece from `g = 0` (asymptote `f_0/c_0`), else
    /// the first; `(s, −c (s − s_start), g∞, f/c)`, so that the state is
    /// `g∞ − (f/c) e^{arg}`. Both pieces' arguments are computed and one
    /// is selected (the piece not taken may be infinite or NaN).
    // `j < WIDTH`, the length of every lane array.
    #[allow(clippy::indexing_slicing)]
    #[inline(always)]
    fn piece(&self, j: usize, x: f64) -> (f64, f64, f64, f64) {
        let s = self.sign[j] * (x - self.z_a[j]);
        let past = self.s0[j] < s;
        (
            s,
            select(past, -self.c_0[j] * (s - self.s0[j]), -self.c_a[j] * s),
            select(past, self.fc_0[j], self.inf_a[j]),
            select(past, self.fc_0[j], self.fc_a[j]),
        )
    }

    /// How many of the samples `xs` every lane steps along its branch from
    /// the state now, all in the common form with a constant stiffness (0
    /// where a lane is outside it).
    #[inline(always)]
    fn run_along_branches(&self, xs: &[f64]) -> usize {
        if self.stiffness.is_none() || self.odd || !self.flow.springs.is_empty() {
            return 0;
        }
        let mut z = self.z;
        let mut run = 0;
        for &x in xs {
            let mut goes_on = true;
            for ((&moving, &sign), &z) in self.moving.iter().zip(&self.sign).zip(&z) {
                goes_on &= moving & (sign * (x - z) >= 0.0);
            }
            if !goes_on {
                break;
            }
            z = [x; WIDTH];
            run += 1;
        }
        run
    }

    /// Steps the samples `xs` (a run of [`run_along_branches`](Self::run_along_branches))
    /// into `ys`, two per iteration so that their exponentials interleave.
    // `j < WIDTH`, the length of every lane array.
    #[allow(clippy::indexing_slicing)]
    #[inline(always)]
    fn go_on(&mut self, xs: &[f64], ys: &mut [[f64; WIDTH]]) {
        // (`run_along_branches` gives a run only with a constant stiffness)
        let stiffness = self.stiffness.unwrap_or([f64::NAN; WIDTH]);
        let b = &*self;
        let piece = |x: f64| {
            let mut arg = [0.0; WIDTH];
            let mut asym = [0.0; WIDTH];
            let mut fc = [0.0; WIDTH];
            for j in 0..WIDTH {
                (_, arg[j], asym[j], fc[j]) = b.piece(j, x);
            }
            (arg, asym, fc)
        };
        let output = |x: f64, h: &[f64; WIDTH], y: &mut [f64; WIDTH]| {
            for j in 0..WIDTH {
                y[j] = b.w[j] * stiffness[j] * x + b.one_w[j] * stiffness[j] * h[j];
            }
        };
        let mut h = self.h;
        let mut pairs = xs.chunks_exact(2);
        let mut pair_ys = ys.chunks_exact_mut(2);
        for (xs, ys) in (&mut pairs).zip(&mut pair_ys) {
            let (x0, x1) = (xs[0], xs[1]);
            let (arg0, asym0, fc0) = piece(x0);
            let (arg1, asym1, fc1) = piece(x1);
            let e0 = arg0.map(crate::exp_kernel::exp);
            let e1 = arg1.map(crate::exp_kernel::exp);
            let mut h0 = [0.0; WIDTH];
            for j in 0..WIDTH {
                h0[j] = b.sign[j] * (asym0[j] - fc0[j] * e0[j]);
                h[j] = b.sign[j] * (asym1[j] - fc1[j] * e1[j]);
            }
            output(x0, &h0, &mut ys[0]);
            output(x1, &h, &mut ys[1]);
        }
        if let (Some(&x), Some(y)) = (pairs.remainder().first(), pair_ys.into_remainder().first_mut()) {
            let (arg, asym, fc) = piece(x);
            let e = arg.map(crate::exp_kernel::exp);
            for j in 0..WIDTH {
                h[j] = b.sign[j] * (asym[j] - fc[j] * e[j]);
            }
            output(x, &h, y);
        }
        if let Some(&x) = xs.last() {
            self.z = [x; WIDTH];
            self.h = h;
        }
    }
}

impl BoucWenLanes {
    /// The lane-by-lane part of a step to `x` where some lane does not go
    /// on along its branch: a lane that reverses (or makes its first
    /// motion) starts its branch at its last state; a lane before any
    /// motion at `x` stays at rest (`rest`).
    #[cold]
    fn turn(&mut self, x: f64, rest: &mut [bool; WIDTH]) {
        for (j, rest) in rest.iter_mut().enumerate() {
            let (Some(&sign), Some(&z), Some(&moving), Some(&h)) = (
                self.sign.get(j),
                self.z.get(j),
                self.moving.get(j),
                self.h.get(j),
            ) else {
                continue;
            };
            let dz = x - z;
            let turns = if dz > 0.0 {
                !moving || sign < 0.0
            } else if dz < 0.0 {
                !moving || sign > 0.0
            } else {
                *rest = !moving;
                false
            };
            if !turns {
                continue;
            }
            let sign = if dz < 0.0 { -1.0 } else { 1.0 };
            let Some(lane) = self.lanes.get(j) else {
                continue;
            };
            let branch = lane.eq.branch(sign * h);
            self.start_branch(j, sign, z, branch);
        }
    }

    /// Starts lane `j`'s branch `branch` at `z_a`, in direction `sign`:
    /// its terms in the vector form where it has one ([`ExpForm`]), else
    /// kept for [`Branch::at`] in that lane alone.
    fn start_branch(&mut self, j: usize, sign: f64, z_a: f64, branch: Branch<f64>) {
        let form = branch.exp_form();
        if let Some(lane) = self.lanes.get_mut(j) {
            lane.odd = form.is_none().then_some(branch);
            lane.branch = Some(branch);
            if let Some(common) = self.common.get_mut(j) {
                *common = form.is_some() && lane.eq.power == Power::One;
            }
        }
        let ExpForm {
            s0,
            c_a,
            fc_a,
            inf_a,
            c_0,
            fc_0,
        } = form.unwrap_or(ExpForm {
            s0: f64::INFINITY,
            c_a: 1.0,
            fc_a: 0.0,
            inf_a: 0.0,
            c_0: 1.0,
            fc_0: 0.0,
        });
        for (v, value) in [
            (&mut self.sign, sign),
            (&mut self.z_a, z_a),
            (&mut self.s0, s0),
            (&mut self.c_a, c_a),
            (&mut self.fc_a, fc_a),
            (&mut self.inf_a, inf_a),
            (&mut self.c_0, c_0),
            (&mut self.fc_0, fc_0),
        ] {
            if let Some(v) = v.get_mut(j) {
                *v = value;
            }
        }
        if let Some(moving) = self.moving.get_mut(j) {
            *moving = true;
        }
        self.odd = self.lanes.iter().any(|l| l.odd.is_some());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lanes::check_each_alone;

    /// Reversals of growing amplitude, holds, and a start at rest.
    fn input(n: usize) -> Vec<f64> {
        (0..n)
            .map(|i| {
                let t = i as f64 / n as f64;
                let hold = if i % 23 == 5 || i < 3 { 0.0 } else { 1.0 };
                (0.2 + 3.0 * t) * (std::f64::consts::TAU * 6.0 * t).sin() * hold
                    + 0.05 * (i as f64 * 0.37).sin() * hold
            })
            .collect()
    }

    fn params(i: usize, n: f64) -> BoucWenParams<f64> {
        let f = i as f64;
        BoucWenParams {
            w: 0.05 * f,
            alpha: 1.0 + 0.1 * f,
            beta: 0.3 + 0.05 * f,
            gamma: 0.4 - 0.07 * f,
            n,
            h0: 0.1 - 0.03 * f,
            // instance 0 starts where the input does: at rest
            z0: if i == 0 { 0.0 } else { 0.02 * f - 0.1 },
            stiffness: if i % 3 == 1 {
                StiffnessMap::new(vec![0.0, 0.5, 2.0], vec![1.0, 1.5 + 0.1 * f, 3.0]).unwrap()
            } else {
                StiffnessMap::constant(1.0 + 0.2 * f).unwrap()
            },
        }
    }

    /// Every lane's outputs are the bits of its spring run alone, or it is
    /// flagged where that run fails.
    fn each_alone(laws: &[BoucWenParams<f64>], x: &[f64]) {
        check_each_alone(laws, x, |law| BoucWen::from_params(law.clone())?.run(x)).unwrap();
    }

    /// Thirteen `n = 1` springs (a full block and a part): softening and
    /// hardening loops, piecewise stiffness, one starting at rest, one with
    /// `β = γ` (a side with `c = 0`) and one with `β − γ` far below `β + γ`
    /// (the first piece by `expm1`).
    #[test]
    fn closed_form_lanes_are_each_spring_alone() {
        let mut laws: Vec<_> = (0..13).map(|i| params(i, 1.0)).collect();
        laws[5].gamma = laws[5].beta;
        laws[6].gamma = 0.97 * laws[6].beta;
        each_alone(&laws, &input(3000));
    }

    /// Constant stiffness and a smooth input, so that most tiles step as
    /// one run along the branches (`go_on`) and some with a reversal (the
    /// runs before and after it, the reversal by `step_lanes`), from a
    /// start at rest and from moving states; with `n = 1`, and with other
    /// exponents (most samples of most lanes within their table piece).
    #[test]
    fn tiles_without_reversals_are_each_spring_alone() {
        for n in [|_| 1.0, |i| 1.1 + 0.2 * i as f64] as [fn(usize) -> f64; 2] {
            let laws: Vec<_> = (0..11)
                .map(|i| BoucWenParams {
                    stiffness: StiffnessMap::constant(1.0 + 0.2 * i as f64).unwrap(),
                    ..params(i, n(i))
                })
                .collect();
            let x: Vec<f64> = (0..1203)
                .map(|i| 2.0 * (i as f64 * 0.013).sin() + 0.1 * (i as f64 * 0.11).sin())
                .collect();
            each_alone(&laws, &x);
        }
    }

    /// A lane whose state diverges (a hardening set, `β + γ < 0`, driven
    /// far) is flagged, and so is one whose parameters its spring refuses;
    /// the others finish with their own bits: with `n = 1`, in a block of
    /// springs with other exponents (on their tables), and in a block mixing
    /// both (the diverging spring, with `n = 1.5`, stepping alone).
    #[test]
    fn a_diverging_lane_is_flagged_and_the_others_finish() {
        let exponents = [
            |_| 1.0,
            |i| 1.5 + 0.1 * i as f64,
            |i| if i % 2 == 0 { 1.0 } else { 1.5 },
        ] as [fn(usize) -> f64; 3];
        for n in exponents {
            let mut laws: Vec<_> = (0..8).map(|i| params(i, n(i))).collect();
            laws[3].beta = -2.0;
            laws[3].gamma = -2.0;
            laws[6].alpha = f64::NAN;
            assert!(BoucWen::from_params(laws[6].clone()).is_err());
            let x: Vec<f64> = input(2000).iter().map(|v| 200.0 * v).collect();
            assert!(BoucWen::from_params(laws[3].clone())
                .unwrap()
                .run(&x)
                .is_err());
            each_alone(&laws, &x);
        }
    }

    /// Blocks of springs all with `n ≠ 1` (each on its own table): soft
    /// and hard exponents, piecewise stiffness, a start at rest, and
    /// inputs small (many table pieces per branch, each branch through
    /// the small pieces at `g = 0`) and large (into the saturating tails
    /// and far along the growing sides of hardening springs).
    #[test]
    fn tabulated_lanes_are_each_spring_alone() {
        let exponents = [1.5, 2.0, 0.6, 3.0, 1.2, 0.9, 2.5, 1.05, 4.0, 0.75, 1.7, 1.3, 5.5];
        let laws: Vec<_> = exponents
            .iter()
            .enumerate()
            .map(|(i, &n)| params(i, n))
            .collect();
        for scale in [0.3, 1.0, 6.0] {
            let x: Vec<f64> = input(3000).iter().map(|v| scale * v).collect();
            each_alone(&laws, &x);
        }
    }

    /// Lanes with `n ≠ 1` in a block run their own springs.
    #[test]
    fn other_exponents_in_a_block_are_each_spring_alone() {
        let laws: Vec<_> = (0..9)
            .map(|i| params(i, if i % 2 == 0 { 1.0 } else { 1.5 }))
            .collect();
        each_alone(&laws, &input(800));
    }
}
