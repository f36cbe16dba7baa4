//! The Bouc-Wen-like hysteresis spring with a nonlinear stiffness map.

use crate::flow_sensitivity::{FlowPoint, SensitiveFlow, SensitivityHint};
use crate::flow_table::{FlowTable, Hint};
use crate::hysteretic_state::{Branch, Power, StateEquation};
use crate::{
    check, check_input, check_lengths, check_output, declare_params, process_by_trials,
    process_while_by_trials, Beyond, Float, Keep, Leaf, Operator, Result, StiffnessMap, Trial,
};

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

#[derive(Debug, Clone, Copy, PartialEq)]
struct State<T> {
    z: T,
    h: T,
    /// The direction of motion, −1, 0 (before any) or 1. A full word: a
    /// byte and its padding were copied by `commit` in pieces that the
    /// next trial's 8-byte load could not be forwarded from (a stall of
    /// about 10 ns per trial and commit, measured on Zen 4: 31.9 → 20.7–24.5
    /// ns for the paper's spring in a trial-and-commit loop).
    dir: i64,
    /// The input where the current branch started.
    z_a: T,
    branch: BranchStart<T>,
}

/// A step on the derivatives' table ([`BoucWen::step_sensitive`]): the
/// parts of the new state it computes, and the rate `f(g)` there.
#[derive(Debug, Clone, Copy)]
struct SensitiveStep<T> {
    h: T,
    z_a: T,
    position: f64,
    carry: T,
    rate: f64,
}

impl<T: Float> SensitiveStep<T> {
    /// The state at input `z`, moving in direction `dir`.
    #[inline(always)]
    fn state(self, z: T, dir: i64) -> State<T> {
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

/// The branch the state moves on, from its start at `z_a` (in the
/// direction frame `g = sgn(ż) h`).
#[derive(Debug, Clone, Copy, PartialEq)]
enum BranchStart<T> {
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
    fn fold_probe(&mut self, along: &T) {
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

    fn initial(p: &BoucWenParams<T>) -> Self {
        State {
            z: p.z0,
            h: p.h0,
            dir: 0,
            z_a: p.z0,
            branch: BranchStart::Unknown,
        }
    }
}

/// Where [`BoucWen::run_branch`] stopped: the next sample, the last state,
/// and the error of the sample it stopped at, if any, or whether `keep`
/// refused that sample.
struct Run<T> {
    end: usize,
    z: T,
    h: T,
    error: Option<crate::Error>,
    refused: bool,
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
    /// `n = 1`: every sample in closed form from its branch start.
    closed_form: bool,
    eq: StateEquation<T>,
    solver: StateSolver,
    /// Over `f32`/`f64`, `n ≠ 1` with [`StateSolver::Tabulated`], where
    /// tabulated.
    table: Option<FlowTable<T>>,
    /// Where the last table lookups were (speed only; results do not
    /// depend on it).
    hint: Hint,
    /// Over dual numbers, with [`StateSolver::Tabulated`] unless `n = 1` is
    /// in closed form (`n` carrying no derivative): the flow of the
    /// parameters' values tabulated with its derivatives.
    sensitive: Option<Box<SensitiveFlow>>,
    sensitive_hint: SensitivityHint,
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
        let closed_form = eq.power == Power::One;
        let v = |t: T| t.as_f64();
        let same_flow = |q: &&Self| {
            let (a, b) = (&q.p, &p);
            q.solver == solver
                && v(q.eq.rtol).to_bits() == v(rtol).to_bits()
                && q.closed_form == closed_form
                && [(a.alpha, b.alpha), (a.beta, b.beta), (a.gamma, b.gamma), (a.n, b.n)]
                    .iter()
                    .all(|&(x, y)| v(x).to_bits() == v(y).to_bits())
        };
        let (table, sensitive) = match previous.filter(same_flow) {
            Some(q) => (q.table.clone(), q.sensitive.clone()),
            None => {
                let table = match solver {
                    StateSolver::Tabulated if !closed_form && !T::CARRIES_DERIVATIVES => {
                        FlowTable::new(&eq)
                    }
                    _ => None,
                };
                // Over a dual scalar the flow of the values is tabulated with
                // its derivatives (those of the flow, not of the table's
                // interpolant).
                let sensitive = match solver {
                    StateSolver::Tabulated if !closed_form && T::CARRIES_DERIVATIVES => {
                        // The same powers as the f64 spring (the same values),
                        // but at n = 1 the general one: ∂/∂n needs |g|^n ln |g|.
                        let power = match Power::new(v(p.n)) {
                            Power::One => Power::Real(1.0),
                            other => other,
                        };
                        let eq = StateEquation::with_power(
                            v(p.alpha),
                            v(p.beta),
                            v(p.gamma),
                            power,
                            v(rtol),
                        );
                        SensitiveFlow::new(eq).map(Box::new)
                    }
                    _ => None,
                };
                (table, sensitive)
            }
        };
        let part = |t: T| t - t.without_derivatives();
        let d_params = [part(p.alpha), part(p.beta), part(p.gamma), part(p.n)];
        let seeded = d_params.iter().any(|t| t.has_derivatives());
        Self {
            slopes: p.stiffness.slopes(),
            closed_form,
            s: State::initial(&p),
            p,
            eq,
            solver,
            table,
            hint: Hint::default(),
            sensitive,
            sensitive_hint: SensitivityHint::default(),
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
            return Err(crate::Error::InvalidParameter {
                name: "rtol".into(),
                value: rtol.as_f64(),
                reason: "must lie in [64 ε, 1e-3]",
            });
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
        self.table.is_some() || self.sensitive.is_some()
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
        if self.sensitive.is_some() {
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
        if self.sensitive.is_some() {
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

    /// [`step`](Self::step) on the `f64` table, by the integration or in
    /// closed form.
    #[inline(always)]
    fn step_integrated(&mut self, z: T, dir: i64, sign: T) -> Result<State<T>> {
        let c = &self.s;
        if let Some(table) = &mut self.table {
            // Tabulated flow: the state at position σ_a + travel, from the
            // start of the branch (a new one starts on a reversal, or where
            // the last state was outside the table).
            let (z_a, sigma_a) = match c.branch {
                BranchStart::Flow(sa) if dir == c.dir => (c.z_a, Some(sa)),
                _ if dir == 0 => return Ok(*c),
                _ => (c.z, table.position_growing(sign * c.h, &mut self.hint)),
            };
            if let Some(sa) = sigma_a {
                if let Some(g) = table.state_at_growing(sa + sign * (z - z_a), &mut self.hint) {
                    return Ok(State {
                        z,
                        h: sign * g,
                        dir,
                        z_a,
                        branch: BranchStart::Flow(sa),
                    });
                }
            }
        }
        if !self.closed_form {
            let h = sign * self.eq.advance(sign * c.h, (z - c.z).abs())?;
            return Ok(State {
                z,
                h,
                dir,
                z_a: c.z_a,
                branch: BranchStart::Unknown,
            });
        }
        // n = 1: closed form along the branch that started at the last
        // reversal (a new one starts when the direction changes).
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

    /// [`step`](Self::step) over dual numbers on the tabulated flow with
    /// its derivatives (`None` where the state or the position is outside
    /// the table, the branch starts at saturation (`f(g_a) = 0`, position
    /// `∞`) or a side of the derivatives' table could not be made: the
    /// caller integrates). The value is the table's
    /// `g = G(σ_a + s)`, as for `f64`; the derivatives, from
    /// `σ(g) = σ(g_a) + s`,
    ///
    /// `dg = f(g) ((dg_a − A(σ_a))/f(g_a) + ds) + A(σ)`,
    ///
    /// with `s = sgn(ż)(z − z_a)` and `A(σ) = Σ ∂G(σ)/∂θ dθ` over
    /// `θ = (α, β, γ, n)` (the flow from 0, tabulated). The branch start's
    /// part is computed once per branch (the `carry`).
    fn step_sensitive(&mut self, z: T, dir: i64, sign: T) -> Option<SensitiveStep<T>> {
        let flow = self.sensitive.as_deref_mut()?;
        let hint = &mut self.sensitive_hint;
        let (d, seeded) = (&self.d_params, self.seeded);
        let part = |t: T| t - t.without_derivatives();
        let c = &self.s;
        let (z_a, position, carry) = match c.branch {
            BranchStart::Sensitive { position, carry } if dir == c.dir => (c.z_a, position, carry),
            _ => {
                let g_a = sign * c.h;
                let position = flow.position(g_a.as_f64())?;
                let start = flow.at(position, hint)?;
                if !(position.is_finite() && start.rate != 0.0) {
                    return None;
                }
                let carry = (part(g_a) - flow_part(start.d_params, d, seeded))
                    * T::lit(1.0 / start.rate)
                    - sign * part(c.z);
                (c.z, position, carry)
            }
        };
        let travel = (sign * (z - z_a)).as_f64();
        let p = flow.at(position + travel, hint)?;
        Some(SensitiveStep {
            h: sign * sensitive_state(&p, carry, sign, z, d, seeded),
            z_a,
            position,
            carry,
            rate: p.rate,
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
    fn run_while(&mut self, zs: &[T], ys: &mut [T], mut keep: impl FnMut(usize, T) -> bool) -> usize {
        self.pending = None;
        if !self.closed_form && self.table.is_none() && self.sensitive.is_none() {
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
    fn run_batch(
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
            let run = match (self.s.branch, &self.table) {
                (BranchStart::Linear(branch), _) => {
                    self.run_branch(
                    zs,
                    ys,
                    i,
                    |s, _| Some(branch.at(s)),
                    &mut keep,
                    &mut segment,
                )
                }
                (BranchStart::Flow(sa), Some(table)) => {
                    let mut hint = self.hint;
                    let run = self.run_branch(
                        zs,
                        ys,
                        i,
                        |s, _| table.state_at(sa + s, &mut hint),
                        &mut keep,
                        &mut segment,
                    );
                    self.hint = hint;
                    run
                }
                (BranchStart::Sensitive { position, carry }, _) => {
                    // (`step`'s formula along the branch, on the table as
                    // it is: a lookup beyond it ends the run, and `step`
                    // extends a growing side)
                    let Some(flow) = self.sensitive.as_deref() else {
                        continue;
                    };
                    let (d, seeded) = (self.d_params, self.seeded);
                    let sign = if self.s.dir < 0 { -T::one() } else { T::one() };
                    let mut hint = self.sensitive_hint;
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
                    self.sensitive_hint = hint;
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

    /// [`trial`](Operator::trial) for `n = 1`: the same values as
    /// [`step`](Self::step) followed by the output and tangent of `trial`,
    /// computed in place from the committed state (the branch is read where
    /// it is, not copied through intermediate states), with `dh/dz` of the
    /// linear rate `α − c |h|` written out.
    #[inline(always)]
    fn trial_closed_form(&mut self, z: T) -> Result<Trial<T>> {
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
    fn trial_value_closed_form(&self, z: f64) -> Option<Result<Trial<f64>>> {
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
    fn direction_value(&self, z: f64) -> (i64, f64) {
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
    fn value_trial(&self, z: f64, h: f64, slope: T) -> Result<Trial<f64>> {
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

    /// `dh/dz` at state `h` moving in direction `dir`.
    #[inline(always)]
    fn slope(&self, h: T, sign: T) -> T {
        self.eq.rate(sign * h)
    }
}

/// `A(σ) = Σ_θ ∂G(σ)/∂θ dθ` over `θ = (α, β, γ, n)` with derivative parts
/// `d` (0 unless `seeded`).
#[inline(always)]
fn flow_part<T: Float>(dp: [f64; 4], d: &[T; 4], seeded: bool) -> T {
    if !seeded {
        return T::zero();
    }
    dp.iter()
        .zip(d)
        .fold(T::zero(), |acc, (&j, &dt)| acc + dt.mul_const(j))
}

/// Whether a run along a branch of direction `sign` goes on from input
/// `before` to `z`: `z` finite and not moving back (standing still goes on).
/// `run_branch` and [`Lookahead`] share it, so that the points looked up
/// ahead are those of the samples the run takes.
#[inline(always)]
fn goes_on<T: Float>(sign: T, before: T, z: T) -> bool {
    sign * (z - before) >= T::zero() && z.is_finite()
}

/// Samples whose flow points the batch loop of a tabulated branch over
/// dual numbers looks up at once ([`SensitiveFlow::lookup_run`]).
const AHEAD: usize = 32;

/// The flow points of the batch loop along a tabulated branch over dual
/// numbers, looked up [`AHEAD`] samples at a time while the input keeps its
/// direction (as `run_branch` goes on), so that their rates' `|g|^n`
/// overlap; the same points as one lookup per sample.
struct Lookahead<T> {
    /// The branch: its start's flow position, direction and input.
    position: f64,
    sign: T,
    z_a: T,
    /// The sample the next call is for.
    asked: usize,
    /// `points[..found]` are those of samples `from..from + found`.
    from: usize,
    found: usize,
    points: [FlowPoint; AHEAD],
    sigmas: [f64; AHEAD],
}

impl<T: Float> Lookahead<T> {
    fn new(position: f64, sign: T, z_a: T, first: usize) -> Self {
        Self {
            position,
            sign,
            z_a,
            asked: first,
            from: first,
            found: 0,
            points: [FlowPoint::default(); AHEAD],
            sigmas: [0.0; AHEAD],
        }
    }

    /// The point of the next sample of `zs`, whose travel is `s = sgn(ż)
    /// (z − z_a)` (samples asked one after the other, from `first` on);
    /// `None` beyond the table.
    #[inline(always)]
    fn next(
        &mut self,
        flow: &SensitiveFlow,
        hint: &mut SensitivityHint,
        zs: &[T],
        s: T,
    ) -> Option<&FlowPoint> {
        let k = self.asked;
        self.asked += 1;
        if k == self.from + self.found {
            (self.from, self.found) = (k, 0);
            let mut m = 0;
            for (q, sigma) in self.sigmas.iter_mut().enumerate() {
                let Some(&z) = zs.get(k + q) else { break };
                let s = if q == 0 {
                    s
                } else {
                    let before = zs.get(k + q - 1).copied().unwrap_or(z);
                    if !goes_on(self.sign, before, z) {
                        break;
                    }
                    self.sign * (z - self.z_a)
                };
                *sigma = self.position + s.as_f64();
                m += 1;
            }
            let sigmas = self.sigmas.get(..m).unwrap_or_default();
            self.found = flow.lookup_run(sigmas, hint, &mut self.points);
        }
        self.points.get(k - self.from).filter(|_| k < self.from + self.found)
    }
}

/// The state on a tabulated branch over dual numbers at the flow point
/// `p`, `g = G + f(G) (carry + sgn(ż) dz) + A(σ)` (see
/// [`BoucWen::step_sensitive`]); one function for `step` and the batch loop,
/// so that both give the same bits.
#[inline(always)]
fn sensitive_state<T: Float>(
    p: &FlowPoint,
    carry: T,
    sign: T,
    z: T,
    d: &[T; 4],
    seeded: bool,
) -> T {
    let dz = z - z.without_derivatives();
    T::lit(p.g) + (carry + sign * dz).mul_const(p.rate) + flow_part(p.d_params, d, seeded)
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
        if self.closed_form {
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
        if !self.closed_form && self.table.is_none() && self.sensitive.is_none() {
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
        let p = self.pending.as_ref().filter(|_| self.closed_form)?;
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
        if self.closed_form {
            return self.trial_value_closed_form(z);
        }
        let (dir, sign) = self.direction_value(z);
        if dir == 0 {
            return None;
        }
        let flow = self.sensitive.as_deref_mut()?;
        let hint = &mut self.sensitive_hint;
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
        Ok(Self::build_reusing(p, self.eq.rtol, self.solver, Some(self)))
    }
}
