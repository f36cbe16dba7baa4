//! The lanes of springs whose exponent is not 1: each on its own tabulated
//! flow ([`FlowTable`](crate::flow_table::FlowTable)), the quintic piece
//! each lane's state is on held lane by lane.

use super::BoucWenLanes;
use crate::bouc_wen::evaluation::Evaluation;
use crate::bouc_wen::state::BranchStart;
use crate::lanes::{select, WIDTH};
use crate::{BoucWen, Operator};

/// The springs of the lanes whose exponent is not 1, and, where every lane
/// of the block is such a spring on its table, each lane's state and the
/// table piece it is on, lane by lane.
pub(super) struct FlowLanes {
    /// Each such lane and its spring (`None`: refused, the lane gives NaN),
    /// in lane order.
    pub(super) springs: Vec<(usize, Option<BoucWen<f64>>)>,
    /// Whether every lane's exponent is not 1: the block steps them
    /// together ([`BoucWenLanes::step_flow`]), each lane off its table
    /// (integrated, or refused) by its spring; else each spring steps
    /// alone.
    pub(super) lockstep: bool,
    /// The lane's input and state, newer than its spring's (which
    /// [`spring_mut`](Self::spring_mut) brings up to date).
    z: [f64; WIDTH],
    h: [f64; WIDTH],
    /// The direction of motion `±1`, the branch start `z_a` and its
    /// position `σ_a` on the flow.
    sign: [f64; WIDTH],
    z_a: [f64; WIDTH],
    sa: [f64; WIDTH],
    /// Whether the lane moves along a branch of its table (else each of its
    /// samples is its spring's).
    on_flow: [bool; WIDTH],
    /// The piece the lane's last state was on: its side (below zero), its
    /// start and inverse width in `τ = |σ|`, the end of its `τ` (its own
    /// where `closed`: the side's last piece), and its coefficients. A
    /// start of `+∞`: no piece.
    lower: [bool; WIDTH],
    start: [f64; WIDTH],
    inv_width: [f64; WIDTH],
    end: [f64; WIDTH],
    closed: [bool; WIDTH],
    b: [[f64; WIDTH]; 6],
}

impl FlowLanes {
    /// The lanes of `springs` (lane index and spring, in lane order), from
    /// the springs' states.
    pub(super) fn new(springs: Vec<(usize, Option<BoucWen<f64>>)>) -> Self {
        let lockstep =
            springs.len() == WIDTH && springs.iter().enumerate().all(|(j, (k, _))| *k == j);
        let mut lanes = FlowLanes {
            springs,
            lockstep,
            z: [0.0; WIDTH],
            h: [0.0; WIDTH],
            sign: [1.0; WIDTH],
            z_a: [0.0; WIDTH],
            sa: [0.0; WIDTH],
            on_flow: [false; WIDTH],
            lower: [false; WIDTH],
            start: [f64::INFINITY; WIDTH],
            inv_width: [0.0; WIDTH],
            end: [0.0; WIDTH],
            closed: [false; WIDTH],
            b: [[0.0; WIDTH]; 6],
        };
        if lockstep {
            for j in 0..WIDTH {
                lanes.refresh(j);
            }
        }
        lanes
    }

    /// Lane `j`'s spring (`None` where the lane's exponent is 1), its
    /// state brought up to the lane's.
    pub(super) fn spring_mut(&mut self, j: usize) -> Option<&mut Option<BoucWen<f64>>> {
        let (z, h) = (self.z.get(j).copied(), self.h.get(j).copied());
        let lockstep = self.lockstep;
        let (_, spring) = self.springs.iter_mut().find(|(k, _)| *k == j)?;
        if let (true, Some(s), Some(z), Some(h)) = (lockstep, spring.as_mut(), z, h) {
            (s.s.z, s.s.h) = (z, h);
        }
        Some(spring)
    }

    /// Takes lane `j`'s state from its spring, and the piece its table has
    /// there, where the lanes step together.
    pub(super) fn refresh(&mut self, j: usize) {
        if !self.lockstep {
            return;
        }
        let (Some((_, Some(spring))), Some(on_flow)) =
            (self.springs.get(j), self.on_flow.get_mut(j))
        else {
            return;
        };
        let s = &spring.s;
        let flow = match s.branch {
            BranchStart::Flow(sa) if s.dir != 0 => Some(sa),
            _ => None,
        };
        *on_flow = flow.is_some() && matches!(spring.evaluation, Evaluation::Table(..));
        for (v, value) in [
            (&mut self.z, s.z),
            (&mut self.h, s.h),
            (&mut self.sign, if s.dir < 0 { -1.0 } else { 1.0 }),
            (&mut self.z_a, s.z_a),
            (&mut self.sa, flow.unwrap_or(0.0)),
        ] {
            if let Some(v) = v.get_mut(j) {
                *v = value;
            }
        }
        if let Some(sa) = flow {
            let sign = if s.dir < 0 { -1.0 } else { 1.0 };
            let sigma = sa + sign * (s.z - s.z_a);
            self.take_piece(j, sigma);
        }
    }

    /// Makes the piece of lane `j`'s table that holds `σ` the lane's:
    /// `Some(None)` where there is one, `Some(Some(G(σ)))` where the table
    /// holds `σ` on no piece (the saturating tail), `None` where it does
    /// not hold `σ` (or the lane has no table).
    // `j < WIDTH`, the length of every lane array.
    #[allow(clippy::indexing_slicing)]
    fn take_piece(&mut self, j: usize, sigma: f64) -> Option<Option<f64>> {
        let Some((_, Some(spring))) = self.springs.get_mut(j) else {
            return None;
        };
        let Evaluation::Table(table, hint) = &mut spring.evaluation else {
            return None;
        };
        match table.piece_at(sigma, hint) {
            Some((piece, end, closed)) => {
                self.lower[j] = sigma < 0.0;
                self.start[j] = piece.start;
                self.inv_width[j] = piece.inv_width();
                self.end[j] = end;
                self.closed[j] = closed;
                for (b, &v) in self.b.iter_mut().zip(&piece.b) {
                    b[j] = v;
                }
                Some(None)
            }
            None => {
                self.start[j] = f64::INFINITY;
                table.state_at(sigma, hint).map(Some)
            }
        }
    }

    /// `h = sgn(ż) G(σ)` in every lane from its piece (`G(σ) = ±` the
    /// piece at `τ = |σ|`, `−` below zero: [`FlowTable::state_at`]'s
    /// operations; a lane outside its piece computes a value that is not
    /// used).
    ///
    /// [`FlowTable::state_at`]: crate::flow_table::FlowTable::state_at
    // `j < WIDTH`, the length of every lane array.
    #[allow(clippy::indexing_slicing)]
    #[inline(always)]
    fn along_pieces(&self, tau: &[f64; WIDTH], neg: &[bool; WIDTH]) -> [f64; WIDTH] {
        let mut h = [0.0; WIDTH];
        for j in 0..WIDTH {
            let b = |k: usize| self.b[k][j];
            let t = (tau[j] - self.start[j]) * self.inv_width[j];
            let u = b(0) + t * (b(1) + t * (b(2) + t * (b(3) + t * (b(4) + t * b(5)))));
            h[j] = self.sign[j] * select(neg[j], -u, u);
        }
        h
    }

    /// Lane `j`'s spring's own step to `x` from the lane's state `(z, h)`:
    /// the lane takes its spring's new state, or a NaN state where the
    /// step fails (the spring alone fails there).
    // `j < WIDTH`, the length of every lane array.
    #[allow(clippy::indexing_slicing)]
    fn spring_step(&mut self, j: usize, x: f64, z: f64, h: f64) {
        let stepped = match self.springs.get_mut(j) {
            Some((_, Some(spring))) => {
                (spring.s.z, spring.s.h) = (z, h);
                spring.process(&[x], &mut [0.0]).is_ok()
            }
            _ => false,
        };
        if stepped {
            self.refresh(j);
        } else {
            self.h[j] = f64::NAN;
        }
    }

    /// The lanes not `inside` their piece at `x`, after the vector form: a
    /// lane that goes on along its branch takes the piece of its table that
    /// holds `σ` (marked in the mask returned, for the vector form to
    /// evaluate), or its table's state there (the saturating tail); any
    /// other lane (a reversal, at rest, off its table) takes its spring's
    /// step from its state before `x`, `(z, h)`.
    // `j < WIDTH`, the length of every lane array.
    #[allow(clippy::indexing_slicing)]
    #[cold]
    #[inline(never)]
    fn fix(
        &mut self,
        x: f64,
        sigma: &[f64; WIDTH],
        goes: &[bool; WIDTH],
        inside: &[bool; WIDTH],
        (z, h): (&[f64; WIDTH], &[f64; WIDTH]),
    ) -> [bool; WIDTH] {
        let mut taken = [false; WIDTH];
        for j in (0..WIDTH).filter(|&j| !inside[j]) {
            let piece = if goes[j] {
                self.take_piece(j, sigma[j])
            } else {
                None
            };
            match piece {
                Some(None) => taken[j] = true,
                Some(Some(g)) => self.h[j] = self.sign[j] * g,
                // (a lane whose spring failed has failed for good: its
                // state stays NaN, its spring is not tried again)
                None if h[j].is_nan() => self.h[j] = f64::NAN,
                None => self.spring_step(j, x, z[j], h[j]),
            }
        }
        taken
    }
}

impl BoucWenLanes {
    /// A step of every lane to `x` where each is a spring on its table
    /// ([`FlowLanes::lockstep`]): `H = w S z + (1 − w) S h`, `h = sgn(ż)
    /// G(σ_a + sgn(ż) (z − z_a))`, where `G` is the quintic piece of the
    /// lane's table that holds `σ` (`−` of the lower side's at `−σ`), as
    /// the spring's own step takes it. Where every lane goes on along its
    /// branch within its piece (the common case), it is the vector form
    /// alone; a lane leaving its piece takes the next one from its table,
    /// and a reversal takes its spring's step.
    // `j < WIDTH`, the length of every lane array.
    #[allow(clippy::indexing_slicing)]
    #[inline(always)]
    pub(super) fn step_flow(&mut self, x: f64, y: &mut [f64; WIDTH]) {
        let f = &mut self.flow;
        let mut sigma = [0.0; WIDTH];
        let mut neg = [false; WIDTH];
        let mut tau = [0.0; WIDTH];
        let mut goes = [false; WIDTH];
        let mut inside = [false; WIDTH];
        let mut all = true;
        // (`Side::locate`'s test of the piece held, lane by lane)
        for j in 0..WIDTH {
            goes[j] = f.on_flow[j] & (f.sign[j] * (x - f.z[j]) >= 0.0);
            sigma[j] = f.sa[j] + f.sign[j] * (x - f.z_a[j]);
            neg[j] = sigma[j] < 0.0;
            tau[j] = select(neg[j], -sigma[j], sigma[j]);
            let below_end = (tau[j] < f.end[j]) | (f.closed[j] & (tau[j] <= f.end[j]));
            inside[j] = goes[j] & (neg[j] == f.lower[j]) & (f.start[j] <= tau[j]) & below_end;
            all &= inside[j];
        }
        let h = f.along_pieces(&tau, &neg);
        let before = (f.z, f.h);
        f.z = [x; WIDTH];
        f.h = h;
        if !all {
            let taken = f.fix(x, &sigma, &goes, &inside, (&before.0, &before.1));
            // (the lanes that took a piece, again in the vector form)
            if taken.contains(&true) {
                let again = f.along_pieces(&tau, &neg);
                for j in 0..WIDTH {
                    f.h[j] = select(taken[j], again[j], f.h[j]);
                }
            }
        }
        let (z, h) = (self.flow.z, self.flow.h);
        self.forces(&z, &h, y);
    }
}
