//! The Bouc-Wen-like hysteresis spring with a nonlinear stiffness map.
//!
//! The spring ([`BoucWen`]) and its protocol are here; each way of
//! evaluating a sample has its module, and [`Evaluation`](evaluation)
//! chooses one when the spring is built:
//! * `closed_form`: `n = 1`;
//! * `tabulated`: the flow tabulated over `f32`/`f64`;
//! * `sensitive`: the flow tabulated with its derivatives, over dual numbers;
//! * the adaptive integration (`step_adaptive` below), where no table
//!   reaches.
//!
//! `batch` runs a branch's samples in one loop for every tabulated or
//! closed-form method; `state` holds what a step leaves; `lanes` steps
//! eight springs with different parameters together
//! ([`LaneLaw`](crate::lanes::LaneLaw)).

mod batch;
mod closed_form;
mod evaluation;
mod exp_run;
mod lanes;
mod sensitive;
mod state;
mod tabulated;

use crate::hysteretic_state::{Power, StateEquation};
use crate::{
    check, check_input, check_lengths, check_output, declare_params, process_by_trials, Beyond,
    Float, Keep, Leaf, Operator, Result, StiffnessMap, Trial,
};
use evaluation::Evaluation;
pub use lanes::{AlongTrial, BoucWenLanes};
use state::{BranchStart, State};

declare_params! {
    /// Parameters of the [`BoucWen`] spring.
    ///
    /// Sets outside the bounded class (`β + γ < 0`, hardening loops) are
    /// legitimate and accepted; if their state diverges the operator
    /// returns an error at that sample.
    pub struct BoucWenParams<T> {
        /// Elastic weight `w ∈ [0, 1]` (1: purely elastic, 0: purely hysteretic).
        w: T => UnitInterval = 0.3,
        /// `α` (finite; 1 removes the model's redundant scaling).
        alpha: T => Real = 1.0,
        /// `β` (finite, any sign).
        beta: T => Real = 0.6,
        /// `γ` (finite, any sign).
        gamma: T => Real = 0.4,
        /// Exponent `n ≥ 1`.
        n: T => AtLeast(1.0) = 1.5,
        /// Hysteretic state `h` at the initial input `z0`, before the first sample.
        #[serde(default)]
        h0: T => Real = 0.2,
        /// The input at which the spring starts (default 0): the state before the
        /// first sample is `(z0, h0)`, and the first sample moves from `z0`.
        #[serde(default)]
        z0: T => Real = -0.1,
        /// Stiffness map `S(z)`.
        stiffness: StiffnessMap<T> => nested,
    }
}

/// How [`BoucWen`] solves its state equation for `n ≠ 1` (`n = 1` is
/// always solved in closed form).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StateSolver {
    /// The flow `g = G(σ(g_a) + s)` tabulated once per parameter set as
    /// piecewise quintic Hermite polynomials, checked at build against the
    /// adaptive integration at `rtol/1000` to `rtol/4` relative per piece:
    /// each sample is one polynomial evaluation from the start of its
    /// branch, so refining the sampling of a branch changes no bit. Used for
    /// `n ≤ 64` and `rtol ≥ 6400 ε` (`f64`: 1.4e-12) with `α > 0` and
    /// `β ≥ γ`: in the bounded class (`β + γ > 0`) for states
    /// `|h| ≤ (α/(β+γ))^{1/n}`, and for hardening sets (`β + γ ≤ 0`) as far
    /// as the states go (the table is extended on demand); other parameter
    /// sets and states (a preload `h0` beyond saturation) fall back to
    /// [`StateSolver::Adaptive`]. Over dual numbers the flow of the
    /// parameters' values is tabulated with its derivatives with respect to
    /// `α, β, γ, n` (the solution of the variational equation, to about
    /// `rtol`), so a sample costs a few more polynomial evaluations, not an
    /// integration; there `n = 1` with `n` carrying a derivative is
    /// tabulated too (with the general power: `∂/∂n` needs `|h|^n ln |h|`).
    #[default]
    Tabulated,
    /// Dormand–Prince 5(4) from sample to sample, local error per sub-step
    /// below `rtol` relative.
    Adaptive,
}

/// Bouc-Wen-like hysteresis spring (Ruderman & Bertram 2015, eqs. 1–2):
///
/// `H = w S(z) z + (1 − w) S(z) h`,
/// `ḣ = α ż − β |ż| |h|^{n−1} h − γ ż |h|^n`,
///
/// integrated in the input domain, `dh/dz = α − |h|^n (β sgn(ż h) + γ)`, so
/// the operator is rate-independent. Every sample is evaluated from the
/// start of its branch (the last reversal), so refining the sampling of a
/// path does not change a bit:
///
/// * `n = 1`: in closed form, exact to rounding;
/// * other `n` ([`StateSolver::Tabulated`], the default): on the flow of the
///   state equation tabulated once per parameter set, `h = G(σ(h_a) + s)`
///   with `σ` the travel from `h = 0` and `s` the travel since the branch
///   start, accurate to about `rtol` relative (default `1e-10` for `f64`,
///   see [`BoucWen::with_tolerance`]); parameter sets outside the bounded
///   class below, and states beyond saturation, are integrated step by step
///   like [`StateSolver::Adaptive`] (Dormand–Prince 5(4), local error per
///   sub-step below `rtol` relative).
///
/// The state update between two samples assumes the input moves
/// monotonically between them.
///
/// With `α > 0`, `β + γ > 0`, `β − γ ≥ 0`:
/// `|h| ≤ max(|h0|, (α/(β+γ))^{1/n})`.
///
/// ```
/// use hysteron_operators::{BoucWen, Operator};
/// // constant stiffness 2, w = 0.3, α = 1, β = 0.6, γ = 0.4, n = 1
/// let mut bw = BoucWen::constant(2.0_f64, 0.3, 1.0, 0.6, 0.4, 1.0).unwrap();
/// let y = bw.run(&[0.5, 20.0, -20.0]).unwrap();
/// // far along a branch the state saturates at ±α/(β+γ) = ±1:
/// // H ≈ ±(0.3·2·20 + 0.7·2·1) = ±13.4
/// assert!((y[1] - 13.4).abs() < 1e-6);
/// assert!((y[2] + 13.4).abs() < 1e-6);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct BoucWen<T> {
    p: BoucWenParams<T>,
    /// The stiffness map's segment slopes, cached.
    slopes: Vec<T>,
    eq: StateEquation<T>,
    solver: StateSolver,
    /// How each sample is evaluated (chosen at build).
    evaluation: Evaluation<T>,
    /// The derivative parts of `(α, β, γ, n)` (value 0).
    d_params: [T; 4],
    /// Whether any of them is not 0.
    seeded: bool,
    s: State<T>,
    pending: Option<State<T>>,
}

impl<T: Float> BoucWen<T> {
    /// A spring from validated parameters.
    pub fn from_params(p: BoucWenParams<T>) -> Result<Self> {
        p.validate()?;
        Ok(Self::build(
            p,
            Self::default_tolerance(),
            StateSolver::Tabulated,
        ))
    }

    /// The spring for validated `p`, tolerance `rtol` and `solver`.
    fn build(p: BoucWenParams<T>, rtol: T, solver: StateSolver) -> Self {
        Self::build_reusing(p, rtol, solver, None)
    }

    /// [`build`](Self::build), taking the tables of `previous` where they
    /// are those of `p` (the same values of `α, β, γ, n`, tolerance and
    /// solver: a fit that moves only `S`, `w` or the initial state builds
    /// no table). A table extended on demand is the same table (its pieces
    /// do not depend on the order of the requests).
    fn build_reusing(
        p: BoucWenParams<T>,
        rtol: T,
        solver: StateSolver,
        previous: Option<&Self>,
    ) -> Self {
        let eq = StateEquation::new(p.alpha, p.beta, p.gamma, p.n, rtol);
        let v = |t: T| t.as_f64();
        // (the values alone: over dual numbers `n = 1` is in closed form
        // only where `n` carries no derivative)
        let closed_form = eq.power == Power::One;
        let same_flow = |q: &&Self| {
            let (a, b) = (&q.p, &p);
            q.solver == solver
                && v(q.eq.rtol).to_bits() == v(rtol).to_bits()
                && matches!(q.evaluation, Evaluation::ClosedForm) == closed_form
                && [
                    (a.alpha, b.alpha),
                    (a.beta, b.beta),
                    (a.gamma, b.gamma),
                    (a.n, b.n),
                ]
                .iter()
                .all(|&(x, y)| v(x).to_bits() == v(y).to_bits())
        };
        let evaluation = match previous.filter(same_flow) {
            Some(q) => q.evaluation.reused(),
            None => Evaluation::choose(&p, &eq, rtol, solver),
        };
        let part = |t: T| t - t.without_derivatives();
        let d_params = [part(p.alpha), part(p.beta), part(p.gamma), part(p.n)];
        let seeded = d_params.iter().any(|t| t.has_derivatives());
        Self {
            slopes: p.stiffness.slopes(),
            s: State::initial(&p),
            p,
            eq,
            solver,
            evaluation,
            d_params,
            seeded,
            pending: None,
        }
    }

    /// A spring with constant stiffness `k` and `h0 = 0`.
    pub fn constant(k: T, w: T, alpha: T, beta: T, gamma: T, n: T) -> Result<Self> {
        Self::from_params(BoucWenParams {
            w,
            alpha,
            beta,
            gamma,
            n,
            h0: T::zero(),
            z0: T::zero(),
            stiffness: StiffnessMap::constant(k)?,
        })
    }

    /// The default integration tolerance: `1e-10`, or `64 ε` where that is
    /// larger (`f32`: 7.6e-6).
    pub fn default_tolerance() -> T {
        T::lit(1e-10).max(T::epsilon() * T::lit(64.0))
    }

    /// Sets the relative tolerance of the state equation's solution for
    /// `n ≠ 1`, `rtol ∈ [64 ε, 1e-3]` (for `f64`: from 1.42e-14): of each
    /// piece of the tabulated flow ([`StateSolver::Tabulated`], checked at
    /// `rtol/4`) or of each adaptive sub-step ([`StateSolver::Adaptive`]).
    /// Rebuilds the table and resets the spring.
    pub fn with_tolerance(self, rtol: T) -> Result<Self> {
        Self::check_tolerance(rtol)?;
        Ok(Self::build(self.p, rtol, self.solver))
    }

    /// `rtol ∈ [64 ε, 1e-3]` (see [`with_tolerance`](Self::with_tolerance)).
    fn check_tolerance(rtol: T) -> Result<()> {
        check::positive("rtol", rtol)?;
        if rtol < T::epsilon() * T::lit(64.0) || rtol > T::lit(1e-3) {
            return Err(check::invalid("rtol", rtol, "must lie in [64 ε, 1e-3]"));
        }
        Ok(())
    }

    /// The same spring over the scalar `U` ([`Leaf::cast_leaf`]): the
    /// parameters as constants, the same solver and tolerance (an error if
    /// the tolerance is outside `[64 ε, 1e-3]` of `U`), its initial state.
    pub fn cast_leaf<U: Float>(&self) -> Result<BoucWen<U>> {
        let p: BoucWenParams<U> = crate::CastScalar::cast_scalar(&self.p);
        p.validate()?;
        let rtol = U::lit(self.eq.rtol.as_f64());
        BoucWen::<U>::check_tolerance(rtol)?;
        Ok(BoucWen::build(p, rtol, self.solver))
    }

    /// Chooses how the state equation is solved for `n ≠ 1` (default
    /// [`StateSolver::Tabulated`]; `n = 1` is always in closed form). Resets
    /// the spring.
    pub fn with_solver(self, solver: StateSolver) -> Self {
        Self::build(self.p, self.eq.rtol, solver)
    }

    /// Whether the flow of the state equation is tabulated (see
    /// [`StateSolver::Tabulated`] for when it is).
    pub fn is_tabulated(&self) -> bool {
        self.evaluation.is_tabulated()
    }

    /// The parameters.
    pub fn parameters(&self) -> &BoucWenParams<T> {
        &self.p
    }

    /// The committed hysteretic state `h`.
    pub fn state(&self) -> T {
        self.s.h
    }

    /// The direction of motion to `z` from the committed state (kept where
    /// `z` equals it) and its sign `±1` (`+1` before any motion).
    #[inline(always)]
    fn direction(&self, z: T) -> (i64, T) {
        let dz = z - self.s.z;
        let dir = if dz > T::zero() {
            1
        } else if dz < T::zero() {
            -1
        } else {
            self.s.dir
        };
        (dir, if dir < 0 { -T::one() } else { T::one() })
    }

    /// The state after input `z` (finite), from the committed state.
    #[inline]
    fn step(&mut self, z: T) -> Result<State<T>> {
        let (dir, sign) = self.direction(z);
        if let Evaluation::Sensitive(..) = self.evaluation {
            if dir == 0 {
                return Ok(self.at_rest(z));
            }
            if let Some(t) = self.step_sensitive(z, dir, sign) {
                return Ok(t.state(z, dir));
            }
        }
        self.step_integrated(z, dir, sign)
    }

    /// [`step`](Self::step) into the pending state, returning its `h`, its
    /// direction and the rate `f(g)` where the derivatives' table gave it
    /// (over dual numbers on the tabulated flow: the rate the derivatives
    /// were carried with, see [`step_sensitive`](Self::step_sensitive)).
    /// The state is written where it stays: over dual numbers it is
    /// hundreds of bytes, and each copy of it cost a trial a tenth of its
    /// time.
    #[inline]
    fn step_pending(&mut self, z: T) -> Result<(T, i64, Option<f64>)> {
        let (dir, sign) = self.direction(z);
        if let Evaluation::Sensitive(..) = self.evaluation {
            if dir == 0 {
                let next = self.at_rest(z);
                let (h, dir) = (next.h, next.dir);
                self.pending = Some(next);
                return Ok((h, dir, None));
            }
            if let Some(t) = self.step_sensitive(z, dir, sign) {
                let (h, rate) = (t.h, t.rate);
                self.pending = Some(t.state(z, dir));
                return Ok((h, dir, Some(rate)));
            }
        }
        let next = self.step_integrated(z, dir, sign)?;
        let (h, dir) = (next.h, next.dir);
        self.pending = Some(next);
        Ok((h, dir, None))
    }

    /// [`step`](Self::step) on the `f64` table, in closed form, or by the
    /// integration (where the table does not reach, and over dual numbers
    /// where the derivatives' table does not).
    #[inline(always)]
    fn step_integrated(&mut self, z: T, dir: i64, sign: T) -> Result<State<T>> {
        match &mut self.evaluation {
            Evaluation::ClosedForm => self.step_closed_form(z, dir, sign),
            Evaluation::Table(table, hint) => {
                match tabulated::step(table, hint, &self.s, z, dir, sign) {
                    Some(next) => Ok(next),
                    None => self.step_adaptive(z, dir, sign),
                }
            }
            Evaluation::Sensitive(..) | Evaluation::Adaptive => self.step_adaptive(z, dir, sign),
        }
    }

    /// [`step`](Self::step) by Dormand–Prince 5(4) from the committed
    /// state ([`StateSolver::Adaptive`]).
    #[inline(always)]
    fn step_adaptive(&mut self, z: T, dir: i64, sign: T) -> Result<State<T>> {
        let c = &self.s;
        let h = sign * self.eq.advance(sign * c.h, (z - c.z).abs())?;
        Ok(State {
            z,
            h,
            dir,
            z_a: c.z_a,
            branch: BranchStart::Unknown,
        })
    }

    /// The committed state before any motion, at `z` equal to it in value:
    /// the same, but over dual numbers with derivatives of `z` that differ
    /// from the committed ones, `h` moves by the rate upward (the
    /// one-sided derivative `dh/dz = f(h)`, as a motion would start).
    fn at_rest(&self, z: T) -> State<T> {
        let c = self.s;
        let dz = z - c.z;
        if !dz.has_derivatives() {
            return c;
        }
        State {
            z,
            h: c.h + dz * self.eq.rate(c.h),
            ..c
        }
    }

    /// `H = w S(z) z + (1 − w) S(z) h` for `S = S(z)`.
    #[inline(always)]
    fn force(&self, s: T, z: T, h: T) -> T {
        let w = self.p.w;
        w * s * z + (T::one() - w) * s * h
    }

    /// `dh/dz` at state `h` moving in direction `dir`.
    #[inline(always)]
    fn slope(&self, h: T, sign: T) -> T {
        self.eq.rate(sign * h)
    }
}

impl<T: Float> Operator<T> for BoucWen<T> {
    // Always inlined where the type is known (a combinator's child), so
    // that the trial's output and tangent reach the caller in registers:
    // through memory they were written as two 8-byte stores and read back
    // as one 16-byte load, which the processor cannot forward; in the
    // paper's model that wait was on the critical path of every root
    // search step (see `trial_split` in `hysteron-composition`).
    #[inline(always)]
    fn trial(&mut self, z: T) -> Result<Trial<T>> {
        if let Evaluation::ClosedForm = self.evaluation {
            return self.trial_closed_form(z);
        }
        self.pending = None;
        let z = check_input(z)?;
        let (h, dir, rate) = self.step_pending(z)?;
        let sign = if dir < 0 { -T::one() } else { T::one() };
        let (s, ds) = self.p.stiffness.eval_with(&self.slopes, z);
        let w = self.p.w;
        let one_w = T::one() - w;
        let output = self.force(s, z, h);
        // dh/dz = f(g): over dual numbers on the tabulated flow, the rate
        // the state's derivatives were carried with (a constant: the
        // tangent's derivative parts leave out those of f)
        let slope = match rate {
            Some(f) => T::lit(f),
            None => self.slope(h, sign),
        };
        let tangent = w * (s + ds * z) + one_w * (ds * h + s * slope);
        let t = check_output(Self::KIND, z, Trial { output, tangent });
        if t.is_err() {
            self.pending = None;
        }
        t
    }

    fn process(&mut self, zs: &[T], ys: &mut [T]) -> Result<()> {
        check_lengths(zs, ys)?;
        self.pending = None;
        if let Evaluation::Adaptive = self.evaluation {
            // The adaptive integration dominates; the default loop is as fast.
            return process_by_trials(self, zs, ys);
        }
        self.run_batch(zs, ys, |_, _| true).1
    }

    #[inline]
    fn commit(&mut self) {
        if let Some(s) = self.pending.take() {
            self.s = s;
        }
    }

    fn reset(&mut self) {
        self.s = State::initial(&self.p);
        self.pending = None;
    }

    fn name(&self) -> &'static str {
        Self::KIND
    }
}

crate::leaf_traits!(BoucWen);

/// Rate-independent: the period is only checked.
impl<T: Float> crate::SamplePeriod<T> for BoucWen<T> {}

impl<T: Float> crate::Hints<T> for BoucWen<T> {
    /// For `n = 1` (closed form): with `S' = dS/dz` (the map is linear on
    /// its segment, `S'' = 0`), `h' = α − c |g|` and `g = sgn(ż) h`,
    ///
    /// `H'' = 2 w S' + (1 − w)(2 S' h' + S h'')`,  `h'' = −c sgn(g) sgn(ż) h'`,
    ///
    /// with `c = β + γ` for `g ≥ 0`, `γ − β` below; `None` for other `n`.
    fn trial_curvature(&self) -> Option<T> {
        let closed_form = matches!(self.evaluation, Evaluation::ClosedForm);
        let p = self.pending.as_ref().filter(|_| closed_form)?;
        let sign = if p.dir < 0 { -T::one() } else { T::one() };
        let (s, ds) = self.p.stiffness.eval_with(&self.slopes, p.z);
        let eq = &self.eq;
        let g = sign * p.h;
        let (c_g, sign_g) = if g < T::zero() {
            (eq.gamma - eq.beta, -T::one())
        } else {
            (eq.beta + eq.gamma, T::one())
        };
        let slope = eq.alpha - g.abs() * c_g;
        let bend = -c_g * sign_g * sign * slope;
        let two = T::lit(2.0);
        let w = self.p.w;
        Some(two * w * ds + (T::one() - w) * (two * ds * slope + s * bend))
    }

    /// Over dual numbers on the tabulated flow: the state from the table
    /// alone, at the position and travel `trial` takes, with the rate
    /// `trial` takes there; `None` where `trial` is not on that table (at a
    /// start at rest, for `n = 1`, for a state or a travel beyond it).
    fn trial_value(&mut self, z: f64) -> Option<Result<Trial<f64>>> {
        self.pending = None;
        if !(crate::float::values_are_f64::<T>() && z.is_finite()) {
            return None;
        }
        if let Evaluation::ClosedForm = self.evaluation {
            return self.trial_value_closed_form(z);
        }
        let (dir, sign) = self.direction_value(z);
        if dir == 0 {
            return None;
        }
        let Evaluation::Sensitive(flow, hint) = &mut self.evaluation else {
            return None;
        };
        let c = &self.s;
        let (z_a, position) = match c.branch {
            BranchStart::Sensitive { position, .. } if dir == c.dir => (c.z_a.as_f64(), position),
            _ => {
                let position = flow.position(sign * c.h.as_f64())?;
                let start = flow.at(position, hint)?;
                if !(position.is_finite() && start.rate != 0.0) {
                    return None;
                }
                (c.z.as_f64(), position)
            }
        };
        let (g, rate) = flow.value_at(position + sign * (z - z_a), hint)?;
        Some(self.value_trial(z, sign * g, T::lit(rate)))
    }

    /// The batch loop of [`process`](Operator::process) (`n = 1`, or the
    /// tabulated flow) with `keep` consulted on each output before it is
    /// committed; otherwise the default trial, `keep`, commit loop.
    fn batch_while(&mut self, zs: &[T], ys: &mut [T], keep: &mut Keep<'_, T>) -> Option<usize> {
        Some(self.run_while(zs, ys, keep))
    }

    fn batch_while_beyond(&mut self, zs: &[T], ys: &mut [T], beyond: Beyond<T>) -> Option<usize> {
        Some(self.run_while(zs, ys, |_, y| beyond.admits(y)))
    }

    /// The pending state's scalars, folded (its parameters and tables
    /// come from the parameters, which carry nothing in the probe slot
    /// where a combinator probes).
    fn fold_probe(&mut self, along: &T) -> bool {
        match self.pending.as_mut() {
            Some(s) => {
                s.fold_probe(along);
                true
            }
            None => false,
        }
    }
}

crate::impl_leaf!(
    BoucWen,
    BoucWenParams,
    "bouc_wen",
    p,
    equation: "H = w S(z) z + (1 − w) S(z) h, dh/dz = α − |h|^n (β sgn(ż h) + γ), z = x − z0",
    with_parameters: BoucWen::with_same_settings,
    cast_leaf: BoucWen::cast_leaf
);

impl<T: Float> BoucWen<T> {
    /// The spring for new parameters with this one's tolerance and solver.
    fn with_same_settings(&self, p: BoucWenParams<T>) -> Result<Self> {
        p.validate()?;
        Ok(Self::build_reusing(
            p,
            self.eq.rtol,
            self.solver,
            Some(self),
        ))
    }
}
