//! Derivatives of the tabulated Bouc-Wen flow with respect to its
//! parameters, tabulated alongside it: what a spring over dual numbers
//! needs to run at the table's speed instead of integrating its flow.
//!
//! On one side of zero (`u = |g| ≥ 0`, `τ = |σ|`, see `flow_table`) the
//! flow from `u(0) = 0` solves `du/dτ = f(u) = α − c u^n`. Its sensitivity
//! `J_θ(τ) = ∂u(τ)/∂θ` for `θ ∈ {α, c, n}` solves the variational equation
//!
//! `J' = f_u(u) J + f_θ(u)`, `J(0) = 0`,
//!
//! with `f_α = 1`, `f_c = −u^n`, `f_n = −c u^n ln u`, `f_u = −c n u^{n−1}`.
//! `J` is held as quintic Hermite pieces along the table's pieces: across
//! each the linear equation is solved in closed form (variation of
//! constants, its integrals by 8-point Gauss–Legendre quadrature along the
//! table's own `u(τ)`, the inner one by the spectral integration matrix of
//! the same nodes), with `J`, `J'` and `J'' = f_uu f J + f_u J' + f_θu f`
//! at the ends; a table piece is halved until the polynomials match that
//! solution at the midpoint to `rtol/4` (relative, or of a scale of the
//! parameter where `J` is near 0).
//! Beyond the last knot of a saturating side the tail is the linearisation
//! about `u* = (α/c)^{1/n}`, `λ = −f_u(u*)`: with `J* = f_θ(u*)/λ` (the
//! derivative of the saturation state) and `Δ = τ − τ_T`,
//!
//! `J(τ) = J* + (J(τ_T) − J* − K Δ) e^{−λΔ}`,
//! `K = v_T (f_uu(u*) J* + f_θu(u*))`,
//!
//! neglecting terms of order `v_T` relative to the deviation and `v²`
//! terms, as the table's own tail does (`v_T ≤ u* √rtol`).
//!
//! Along a branch from `g_a` (position `σ_a`) the state after travel `s`
//! is `g = G(σ_a + s)`; differentiating `σ(g) = σ(g_a) + s` gives
//!
//! `dg = f(g)/f(g_a) (dg_a − A(σ_a)) + f(g) ds + A(σ)`,
//!
//! where `A(σ) = Σ_θ ∂g/∂θ|_{from 0} dθ` is `±J` of the side `σ` is on
//! (see [`SensitiveFlow::at`]). That is the derivative of the exact flow;
//! the tables approximate it to about the table's tolerance (the tests
//! measure it against closed forms and difference quotients). The rate
//! `f(g)` it takes at every point is held on the same pieces where a
//! polynomial matches it to `rtol/4` of `|f| + α`, so that a point costs no
//! `pow` there (see `SideSensitivity`).

use crate::flow_table::{FlowTable, Hint, Piece, Side};
use crate::hysteretic_state::StateEquation;

/// Gauss–Legendre nodes on `[0, 1]` and their weights (8 points: exact for
/// polynomials of degree 15).
const GAUSS: [(f64, f64); 8] = [
    (0.019855071751231912, 0.05061426814518853),
    (0.10166676129318664, 0.11119051722668721),
    (0.2372337950418355, 0.15685332293894344),
    (0.4082826787521751, 0.18134189168918083),
    (0.5917173212478248, 0.18134189168918083),
    (0.7627662049581645, 0.15685332293894344),
    (0.8983332387068134, 0.11119051722668721),
    (0.9801449282487681, 0.05061426814518853),
];

/// The three parameters a side's flow depends on.
const PARAMS: usize = 3;

/// `f` and its derivatives on one side, `du/dτ = α − c u^n`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Law {
    alpha: f64,
    c: f64,
    n: f64,
}

/// `f`, its `u`-derivatives and its parameter derivatives at one `u`.
#[derive(Debug, Clone, Copy)]
struct Terms {
    f: f64,
    /// `f_u`, `f_uu`.
    fu: f64,
    fuu: f64,
    /// `[f_α, f_c, f_n]` and their `u`-derivatives.
    ft: [f64; PARAMS],
    ftu: [f64; PARAMS],
}

impl Law {
    fn f(&self, u: f64) -> f64 {
        self.alpha - self.c * u.powf(self.n)
    }

    /// `f`, `f_u = −c n u^{n−1}`, `f_uu = −c n (n−1) u^{n−2}`,
    /// `f_θ = [1, −u^n, −c u^n ln u]` and
    /// `f_θu = [0, −n u^{n−1}, −c u^{n−1} (n ln u + 1)]`, from one `ln`
    /// and one `exp` (`u^{n−1} = e^{(n−1) ln u}`: the `ln` is wanted
    /// anyway, and `exp` costs less than `pow`; the relative error is
    /// about `|n − 1| |ln u| ε` more than `pow`'s).
    ///
    /// At `u = 0`: `f_u` is `−c` for `n = 1` and 0 above, `f_uu` is taken
    /// as 0 (where `f_uu J → 0`), `f_cu` is `−1` for `n = 1` (0 above), and
    /// `f_nu`, `−∞` there for `n = 1`, is taken as 0 (only the jet at the
    /// first knot uses these; the refinement of the pieces makes up).
    fn terms(&self, u: f64) -> Terms {
        let (alpha, c, n) = (self.alpha, self.c, self.n);
        if u <= 0.0 {
            let linear = n == 1.0;
            return Terms {
                f: alpha,
                fu: if linear { -c } else { 0.0 },
                fuu: 0.0,
                ft: [1.0, 0.0, 0.0],
                ftu: [0.0, if linear { -1.0 } else { 0.0 }, 0.0],
            };
        }
        let ln = u.ln();
        let un1 = ((n - 1.0) * ln).exp();
        let un = un1 * u;
        Terms {
            f: alpha - c * un,
            fu: -c * n * un1,
            fuu: -c * n * (n - 1.0) * un1 / u,
            ft: [1.0, -un, -c * un * ln],
            ftu: [0.0, -n * un1, -c * un1 * (n * ln + 1.0)],
        }
    }

    /// `[f, df/dτ, d²f/dτ²]` along the flow at `u` (`du/dτ = f`): `f_u f`
    /// and `f_uu f² + f_u (f_u f)`.
    fn rate_jet(&self, u: f64) -> [f64; 3] {
        let Terms { f, fu, fuu, .. } = self.terms(u);
        let d1 = fu * f;
        [f, d1, fuu * f * f + fu * d1]
    }

    /// `[J, J', J'']` of each parameter at `u` with `J = j`:
    /// `J' = f_u J + f_θ`, `J'' = f_uu f J + f_u J' + f_θu f`.
    // `std::array::from_fn` indices are `< PARAMS`, the arrays' length.
    #[allow(clippy::indexing_slicing)]
    fn jets(&self, u: f64, j: [f64; PARAMS]) -> [[f64; 3]; PARAMS] {
        let Terms {
            f,
            fu,
            fuu,
            ft,
            ftu,
        } = self.terms(u);
        std::array::from_fn(|k| {
            let d1 = fu * j[k] + ft[k];
            [j[k], d1, fuu * f * j[k] + fu * d1 + ftu[k] * f]
        })
    }

    /// `J(t0 + w)` from `j = J(t0)`, both within a piece of the table: the
    /// variational equation is linear, `J(t0 + w) = e^{A(w)} J(t0) +
    /// ∫_0^w e^{A(w) − A(t)} f_θ dt` with `A(t) = ∫_0^t f_u dt'`, along
    /// the piece's `u`:
    /// the outer integral by Gauss–Legendre quadrature, `A` at its nodes by
    /// integrating the degree-7 polynomial through `f_u` at the same nodes
    /// ([`integration_matrix`]). It never divides by `f`, which loses its
    /// relative accuracy near saturation (`f(u) ≈ λ (u* − u)`).
    fn across(&self, piece: &Piece<f64>, t0: f64, w: f64, j: [f64; PARAMS]) -> [f64; PARAMS] {
        let mut a = [0.0; 8];
        let mut ft = [[0.0; PARAMS]; 8];
        for ((&(x, _), a), ft) in GAUSS.iter().zip(&mut a).zip(&mut ft) {
            let u = piece.eval(t0 + x * w);
            let t = self.terms(u);
            (*a, *ft) = (t.fu, t.ft);
        }
        let a_w = w * GAUSS
            .iter()
            .zip(&a)
            .map(|(&(_, wt), a)| wt * a)
            .sum::<f64>();
        let mut out = j.map(|jk| a_w.exp() * jk);
        for ((row, &(_, wt)), ft) in integration_matrix().iter().zip(&GAUSS).zip(&ft) {
            let a_t = w * row.iter().zip(&a).map(|(s, a)| s * a).sum::<f64>();
            let weight = w * wt * (a_w - a_t).exp();
            for (o, f) in out.iter_mut().zip(ft) {
                *o += weight * f;
            }
        }
        out
    }
}

/// `S[i][j] = ∫_0^{x_i} L_j(s) ds` for the Lagrange basis `L_j` on the
/// Gauss–Legendre nodes `x_j`: `∫_0^{x_i} p = Σ_j S[i][j] p(x_j)` for any
/// polynomial `p` of degree ≤ 7. Each entry by the same 8-point rule on
/// `[0, x_i]` (exact: `L_j` has degree 7), `L_j` in product form.
fn integration_matrix() -> &'static [[f64; 8]; 8] {
    static MATRIX: std::sync::OnceLock<[[f64; 8]; 8]> = std::sync::OnceLock::new();
    MATRIX.get_or_init(|| {
        let nodes: [f64; 8] = GAUSS.map(|(x, _)| x);
        let basis = |j: usize, xj: f64, s: f64| {
            (nodes.iter().enumerate())
                .filter(|&(m, _)| m != j)
                .map(|(_, &xm)| (s - xm) / (xj - xm))
                .product::<f64>()
        };
        nodes.map(|xi| {
            let mut row = [0.0; 8];
            for (j, (r, &xj)) in row.iter_mut().zip(&nodes).enumerate() {
                *r = xi
                    * (GAUSS.iter())
                        .map(|&(xk, wk)| wk * basis(j, xj, xi * xk))
                        .sum::<f64>();
            }
            row
        })
    })
}

/// The linearised tail of `J` beyond the last knot of a saturating side.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Tail {
    j_star: [f64; PARAMS],
    e_t: [f64; PARAMS],
    k: [f64; PARAMS],
    lambda: f64,
}

/// `J_α, J_c, J_n` of one side: quintic Hermite pieces made along the
/// table's pieces, each of them split in halves until the polynomials
/// match the variational equation's solution at their midpoints to
/// `rtol/4` relative (or of the parameter's scale, where `J` is near 0):
/// `J` can be less smooth than `u`, as `J_n ∝ τ^{n+1} ln τ` near `τ = 0`
/// for `n` near 1, where the table's pieces are not graded. A piece that
/// cannot be made so (20 halvings, 16 384 pieces, non-finite values) ends
/// the side's use: lookups there return `None`.
///
/// The flow's rate `f(u(τ))` is held alongside, on the same pieces: a
/// quintic Hermite piece through `f`, `df/dτ = f_u f` and
/// `d²f/dτ² = f_uu f² + f_u² f` at the ends, kept where it matches `f` of
/// the table's `u` at the midpoint to `rtol/4` of `|f| + α` (else `f` is
/// computed there, by `pow`, as before; beyond the pieces too). Pieces are
/// not split for it; a few near saturation miss and compute it. On a
/// saturating side the
/// pieces end where `u* − u` falls to the tail's `v_T` (`u* √rtol`, or
/// `u* √(rtol/(4(n − 1)))` above `n = 1.25`), so on them `f ≈ λ (u* − u) ≥
/// λ v_T`, of order `α √rtol`: far above the tolerance, so the tabulated
/// rate keeps its sign and most of its digits at a branch start, where it
/// divides.
#[derive(Debug, Clone, PartialEq)]
struct SideSensitivity {
    law: Law,
    tol: f64,
    /// Floors of the error allowed per parameter (relative to these scales
    /// where `J` is smaller): `U/α`, `U/max(|c|, α U^{−n})`, `U (1 + |ln U|)`
    /// with `U` the side's extent when first made.
    scale: [f64; PARAMS],
    starts: Vec<f64>,
    pieces: Vec<[Piece<f64>; PARAMS]>,
    /// The rate on each piece, where its polynomial is accurate.
    rates: Vec<Option<Piece<f64>>>,
    /// Pieces of the table followed so far, and `τ`, `J_θ` at their end.
    followed: usize,
    end_tau: f64,
    end: [f64; PARAMS],
    tail: Option<Tail>,
    /// A piece could not be made to the tolerance (too many halvings or
    /// pieces, or non-finite values): nothing is read from this side any
    /// more (the spring integrates instead).
    broken: bool,
}

/// Halvings of a table piece at most.
const MAX_SPLITS: i32 = 20;

/// Pieces per side at most.
const MAX_PIECES: usize = 16_384;

impl SideSensitivity {
    fn new(law: Law, rtol: f64) -> Self {
        Self {
            law,
            tol: 0.25 * rtol,
            scale: [0.0; PARAMS],
            starts: Vec::new(),
            pieces: Vec::new(),
            rates: Vec::new(),
            followed: 0,
            end_tau: 0.0,
            end: [0.0; PARAMS],
            tail: None,
            broken: false,
        }
    }

    /// Makes the pieces along the table's pieces this has not followed yet
    /// (a growing side is extended on demand), and the tail once the side
    /// is complete.
    // `std::array::from_fn` indices are `< PARAMS`, the arrays' length.
    #[allow(clippy::indexing_slicing)]
    fn follow(&mut self, side: &Side<f64>) {
        let table = side.pieces();
        if self.followed < table.len() && self.scale == [0.0; PARAMS] {
            let Law { alpha, c, n } = self.law;
            let u = side.u_end().max(f64::MIN_POSITIVE);
            self.scale = [
                u / alpha,
                u / c.abs().max(alpha * u.powf(-n)),
                u * (1.0 + u.ln().abs()),
            ];
        }
        while let Some(p) = table.get(self.followed) {
            if self.broken {
                return;
            }
            let b = table.get(self.followed + 1).map_or(side.end(), |q| q.start);
            let smallest = (b - p.start) * 0.5f64.powi(MAX_SPLITS);
            let mut t0 = p.start;
            let mut w = b - t0;
            while t0 < b {
                // widths between representable points, so that the piece
                // ends where the next begins and each step advances
                let t1 = (t0 + w).min(b);
                let w_now = t1 - t0;
                let mid = t0 + 0.5 * w_now;
                let j0 = self.end;
                let j1 = self.law.across(p, t0, w_now, j0);
                let j_mid = self.law.across(p, t0, mid - t0, j0);
                let left = self.law.jets(p.eval(t0), j0);
                let right = self.law.jets(p.eval(t1), j1);
                let cand: [Piece<f64>; PARAMS] =
                    std::array::from_fn(|i| Piece::hermite(t0, w_now, left[i], right[i]));
                let fits = (0..PARAMS).all(|i| {
                    let err = (cand[i].eval(mid) - j_mid[i]).abs();
                    err <= self.tol * (j_mid[i].abs() + self.scale[i])
                });
                if !fits {
                    if 0.5 * w_now < smallest || !(mid > t0 && mid < t1) {
                        self.broken = true;
                        return;
                    }
                    w = 0.5 * w_now;
                    continue;
                }
                if self.pieces.len() >= MAX_PIECES {
                    self.broken = true;
                    return;
                }
                let rate = Piece::hermite(
                    t0,
                    w_now,
                    self.law.rate_jet(p.eval(t0)),
                    self.law.rate_jet(p.eval(t1)),
                );
                let f_mid = self.law.f(p.eval(mid));
                let rate_fits =
                    (rate.eval(mid) - f_mid).abs() <= self.tol * (f_mid.abs() + self.law.alpha);
                self.starts.push(t0);
                self.pieces.push(cand);
                self.rates.push(rate_fits.then_some(rate));
                self.end = j1;
                t0 = t1;
                w = 2.0 * w_now;
            }
            self.followed += 1;
            self.end_tau = b;
        }
        if self.tail.is_none() && self.followed == table.len() {
            if let Some(t) = side.tail() {
                let law = self.law;
                let Terms {
                    fu, fuu, ft, ftu, ..
                } = law.terms(t.u_star);
                let lambda = -fu;
                let at_end = self.end;
                let j_star = ft.map(|f| f / lambda);
                self.tail = Some(Tail {
                    j_star,
                    e_t: std::array::from_fn(|i| at_end[i] - j_star[i]),
                    k: std::array::from_fn(|i| t.v_t * (fuu * j_star[i] + ftu[i])),
                    lambda,
                });
            }
        }
    }

    /// `[J_α, J_c, J_n]` at `τ ≥ 0` (`None` beyond the pieces of a side
    /// without a tail), and the rate `f` there where its piece holds it
    /// (see the type); `hint` is the piece to look at first.
    // `std::array::from_fn` indices are `< PARAMS`, the arrays' length;
    // `k` is checked against `pieces`.
    // Inlined into the dual batch loop: returned through memory, the three
    // values stalled the loads that read them back.
    #[allow(clippy::indexing_slicing)]
    #[inline(always)]
    fn at(&self, tau: f64, hint: &mut usize) -> Option<([f64; PARAMS], Option<f64>)> {
        if self.broken {
            return None;
        }
        if tau > self.end_tau {
            return self.beyond(tau).map(|j| (j, None));
        }
        let k = self.piece(tau, hint);
        let j = self.pieces.get(k)?.map(|q| q.eval(tau));
        let rate = self.rates.get(k).copied().flatten().map(|r| r.eval(tau));
        Some((j, rate))
    }

    /// The rate of [`at`](Self::at) alone: `Some(rate)` where `at` gives a
    /// point, `None` where it gives none.
    #[inline(always)]
    fn rate_at(&self, tau: f64, hint: &mut usize) -> Option<Option<f64>> {
        if self.broken {
            return None;
        }
        if tau > self.end_tau {
            return self.tail.map(|_| None);
        }
        let k = self.piece(tau, hint);
        self.pieces.get(k)?;
        Some(self.rates.get(k).copied().flatten().map(|r| r.eval(tau)))
    }

    /// The piece of `τ ≤ end_tau` (the hint's, the next one, or found by
    /// a binary search), left in `hint`.
    #[allow(clippy::indexing_slicing)]
    #[inline(always)]
    fn piece(&self, tau: f64, hint: &mut usize) -> usize {
        let s = &self.starts;
        let holds =
            |k: usize| k < s.len() && s[k] <= tau && s.get(k + 1).is_none_or(|&next| tau < next);
        let k = if holds(*hint) {
            *hint
        } else if holds(hint.wrapping_add(1)) {
            *hint + 1
        } else {
            s.partition_point(|&start| start <= tau).max(1) - 1
        };
        *hint = k;
        k
    }
}

impl SideSensitivity {
    /// [`at`](Self::at) beyond the pieces: the tail towards saturation, if
    /// any.
    // `std::array::from_fn` indices are `< PARAMS`, the arrays' length.
    #[allow(clippy::indexing_slicing)]
    #[cold]
    fn beyond(&self, tau: f64) -> Option<[f64; PARAMS]> {
        self.tail.map(|t| {
            let d = tau - self.end_tau;
            let e = (-(t.lambda * d)).exp();
            if e == 0.0 {
                // (also at d = ∞, a state at saturation)
                return t.j_star;
            }
            std::array::from_fn(|i| t.j_star[i] + (t.e_t[i] - t.k[i] * d) * e)
        })
    }
}

/// Where the last lookups were, per side (a cache: results do not depend
/// on it).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct SensitivityHint {
    table: Hint,
    upper: usize,
    lower: usize,
}

/// Hints are a cache (see [`Hint`]).
impl PartialEq for SensitivityHint {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

/// A flow table with the derivatives of its flow with respect to
/// `α, β, γ, n` (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct SensitiveFlow {
    table: FlowTable<f64>,
    eq: StateEquation<f64>,
    upper: SideSensitivity,
    lower: SideSensitivity,
}

/// The flow at a position: the state, its rate and the derivatives of the
/// state reached from `g = 0` with respect to `α, β, γ, n`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct FlowPoint {
    /// `g = G(σ)`.
    pub g: f64,
    /// `f(g)`: its tabulated polynomial where that holds it (to `rtol/4`
    /// of `|f| + α`, see `SideSensitivity`), else computed.
    pub rate: f64,
    /// `∂G(σ)/∂(α, β, γ, n)` at fixed `σ`, for the flow from `g = 0`.
    pub d_params: [f64; 4],
}

impl SensitiveFlow {
    /// The table and its sensitivities for `eq`, or `None` where the flow is
    /// not tabulated (see `FlowTable::new`).
    pub(crate) fn new(eq: StateEquation<f64>) -> Option<Self> {
        let table = FlowTable::new(&eq)?;
        let n = eq.power.exponent();
        let (alpha, beta, gamma, rtol) = (eq.alpha, eq.beta, eq.gamma, eq.rtol);
        let mut flow = SensitiveFlow {
            table,
            eq,
            upper: SideSensitivity::new(
                Law {
                    alpha,
                    c: beta + gamma,
                    n,
                },
                rtol,
            ),
            lower: SideSensitivity::new(
                Law {
                    alpha,
                    c: gamma - beta,
                    n,
                },
                rtol,
            ),
        };
        flow.upper.follow(flow.table.upper());
        flow.lower.follow(flow.table.lower());
        Some(flow)
    }

    /// The position `σ(g)` (extending a growing side to hold `g`), or
    /// `None` outside the table.
    pub(crate) fn position(&mut self, g: f64) -> Option<f64> {
        let sigma = self.table.position_growing(g, &mut Hint::default())?;
        self.follow();
        Some(sigma)
    }

    fn follow(&mut self) {
        self.upper.follow(self.table.upper());
        self.lower.follow(self.table.lower());
    }

    /// [`at`](Self::at) of each of `sigmas` in turn into `out`, without
    /// extending the table, up to the first that is beyond it (where `at`
    /// would give a point without extending, so does this); how many were
    /// found. The rates that are not tabulated (see `SideSensitivity`) come
    /// last, in a loop of their own: their `|g|^n` (the longest computation
    /// of a point, a call of the C library's `pow`) then overlap from one
    /// point to the next, and the same bits come out as from `at`.
    // `out[..found]`, `found ≤ out.len()`.
    #[allow(clippy::indexing_slicing)]
    #[inline]
    pub(crate) fn lookup_run(
        &self,
        sigmas: &[f64],
        hint: &mut SensitivityHint,
        out: &mut [FlowPoint],
    ) -> usize {
        let mut found = 0;
        for (&sigma, p) in sigmas.iter().zip(out.iter_mut()) {
            let Some(g) = self.table.state_at(sigma, &mut hint.table) else {
                break;
            };
            let Some(point) = self.point_without_rate(sigma, g, hint) else {
                break;
            };
            *p = point;
            found += 1;
        }
        for p in &mut out[..found] {
            *p = self.with_rate(*p);
        }
        found
    }

    /// The flow at position `σ` (extending a growing side to reach it), or
    /// `None` outside the table. Above zero (`σ ≥ 0`, `u = g`, `τ = σ`) the
    /// derivatives are `(J_α, J_c, J_c, J_n)` with `c = β + γ`; below it
    /// (`u = −g`, `τ = −σ`, `c = γ − β`) `(−J_α, J_c, −J_c, −J_n)`.
    pub(crate) fn at(&mut self, sigma: f64, hint: &mut SensitivityHint) -> Option<FlowPoint> {
        let g = self.table.state_at_growing(sigma, &mut hint.table)?;
        self.follow();
        self.point(sigma, g, hint)
    }

    /// The state `g` and rate `f(g)` of [`at`](Self::at), without the
    /// derivatives: `None` where `at` gives `None`, and the same bits
    /// where it gives a point.
    pub(crate) fn value_at(
        &mut self,
        sigma: f64,
        hint: &mut SensitivityHint,
    ) -> Option<(f64, f64)> {
        let g = self.table.state_at_growing(sigma, &mut hint.table)?;
        self.follow();
        let rate = if sigma >= 0.0 {
            self.upper.rate_at(sigma, &mut hint.upper)?
        } else {
            self.lower.rate_at(-sigma, &mut hint.lower)?
        };
        let rate = rate.unwrap_or(f64::NAN);
        Some((g, if rate.is_nan() { self.eq.rate(g) } else { rate }))
    }

    /// The flow point at `σ` with state `g = G(σ)` (see [`at`](Self::at)).
    #[inline(always)]
    fn point(&self, sigma: f64, g: f64, hint: &mut SensitivityHint) -> Option<FlowPoint> {
        self.point_without_rate(sigma, g, hint)
            .map(|p| self.with_rate(p))
    }

    /// `p` with its rate computed (`pow`) where the tables left it NaN.
    #[inline(always)]
    fn with_rate(&self, p: FlowPoint) -> FlowPoint {
        if p.rate.is_nan() {
            FlowPoint {
                rate: self.eq.rate(p.g),
                ..p
            }
        } else {
            p
        }
    }

    /// [`point`](Self::point) with the rate NaN where it is not tabulated.
    #[inline(always)]
    fn point_without_rate(
        &self,
        sigma: f64,
        g: f64,
        hint: &mut SensitivityHint,
    ) -> Option<FlowPoint> {
        let upper = sigma >= 0.0;
        let (j, rate) = if upper {
            self.upper.at(sigma, &mut hint.upper)?
        } else {
            self.lower.at(-sigma, &mut hint.lower)?
        };
        let d_params = if upper {
            [j[0], j[1], j[1], j[2]]
        } else {
            [-j[0], j[1], -j[1], -j[2]]
        };
        Some(FlowPoint {
            g,
            rate: rate.unwrap_or(f64::NAN),
            d_params,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flow(alpha: f64, beta: f64, gamma: f64, n: f64) -> SensitiveFlow {
        SensitiveFlow::new(StateEquation::new(alpha, beta, gamma, n, 1e-10)).unwrap()
    }

    /// n = 2 above zero: `u = a tanh(b τ)`, `a = √(α/c)`, `b = √(αc)`, so
    /// `∂u/∂α = (a/2α)(tanh + b τ sech²)` and `∂u/∂c = (a/2c)(b τ sech² −
    /// tanh)`; below zero (`c < 0`) `u = a tan(b τ)` with `a = √(α/|c|)`,
    /// `b = √(α|c|)`.
    #[test]
    fn n2_sensitivities_match_the_closed_forms() {
        let (alpha, beta, gamma) = (1.5, 0.6, 0.2);
        let mut fl = flow(alpha, beta, gamma, 2.0);
        let mut hint = SensitivityHint::default();
        let mut worst = 0.0f64;
        let (cu, cl) = (beta + gamma, beta - gamma);
        for i in 0..=4000 {
            let tau = i as f64 * 2e-3;
            let (a, b) = ((alpha / cu).sqrt(), (alpha * cu).sqrt());
            let (th, sech2) = ((b * tau).tanh(), 1.0 / (b * tau).cosh().powi(2));
            let du_da = a / (2.0 * alpha) * (th + b * tau * sech2);
            let du_dc = a / (2.0 * cu) * (b * tau * sech2 - th);
            let p = fl.at(tau, &mut hint).unwrap();
            // β and γ enter as c = β + γ above zero.
            for (got, want) in [
                (p.d_params[0], du_da),
                (p.d_params[1], du_dc),
                (p.d_params[2], du_dc),
            ] {
                worst = worst.max((got - want).abs() / a);
            }
            let (a, b) = ((alpha / cl).sqrt(), (alpha * cl).sqrt());
            if b * tau < 1.2 {
                let (tn, sec2) = ((b * tau).tan(), 1.0 / (b * tau).cos().powi(2));
                // u = a tan(b τ) with c' = |c| = β − γ: ∂u/∂α as above with
                // tan, ∂u/∂|c| = (a/2|c|)(b τ sec² − tan).
                let du_da = a / (2.0 * alpha) * (tn + b * tau * sec2);
                let du_dcl = a / (2.0 * cl) * (b * tau * sec2 - tn);
                let p = fl.at(-tau, &mut hint).unwrap();
                // g = −u: ∂g/∂α = −∂u/∂α; |c| = β − γ, so ∂g/∂β = −∂u/∂|c|
                // and ∂g/∂γ = +∂u/∂|c|.
                for (got, want) in [
                    (p.d_params[0], -du_da),
                    (p.d_params[1], -du_dcl),
                    (p.d_params[2], du_dcl),
                ] {
                    // (relative: the growing side's derivatives grow as sec²)
                    worst = worst.max((got - want).abs() / want.abs().max(a));
                }
            }
        }
        println!("n = 2: sensitivities within {worst:.2e}");
        // The table's own tolerance is 1e-10 of u*.
        assert!(worst <= 1e-9, "{worst}");
    }

    /// Every parameter, non-integer n, far into saturation: the tabulated
    /// derivatives against central differences of tables at 2e-12.
    #[test]
    fn sensitivities_match_difference_quotients_of_the_table() {
        for (n, beta, gamma) in [
            (1.5, 0.7, 0.3),
            (2.7, 0.55, 0.45),
            (1.2, 0.49, 0.42),
            (6.0, 0.4, 0.3),
        ] {
            let theta = [1.0, beta, gamma, n];
            let mut fl =
                SensitiveFlow::new(StateEquation::new(1.0, beta, gamma, n, 2e-12)).unwrap();
            let mut hint = SensitivityHint::default();
            let mut worst = 0.0f64;
            for k in 0..4 {
                let h = 1e-5 * theta[k];
                let table = |d: f64| {
                    let mut t = theta;
                    t[k] += d;
                    FlowTable::new(&StateEquation::new(t[0], t[1], t[2], t[3], 2e-12)).unwrap()
                };
                let (plus, minus) = (table(h), table(-h));
                let mut hp = crate::flow_table::Hint::default();
                let mut hm = crate::flow_table::Hint::default();
                for i in -300..=1200 {
                    let sigma = i as f64 * 0.01;
                    let (Some(a), Some(b)) = (
                        plus.state_at(sigma, &mut hp),
                        minus.state_at(sigma, &mut hm),
                    ) else {
                        continue;
                    };
                    let Some(p) = fl.at(sigma, &mut hint) else {
                        continue;
                    };
                    let fd = (a - b) / (2.0 * h);
                    worst = worst.max((p.d_params[k] - fd).abs() / fd.abs().max(1.0));
                }
            }
            println!("n = {n}: tabulated against difference quotients within {worst:.2e}");
            // Difference quotients of tables at 2e-12 with h = 1e-5 θ: about
            // 2e-12/1e-5 of rounding and table error.
            assert!(worst <= 1e-6, "n = {n}: {worst}");
        }
    }

    /// The tabulated rate is `f` of the table's state to the tolerance its
    /// pieces are kept at (`rtol/4` of `|f| + α` at their midpoints, where
    /// a quintic Hermite piece's error peaks; allowed here: `rtol/2`), on
    /// saturating and growing sides and for `n` near 1, and it is the rate
    /// of most points on the pieces (else they would not save the `pow`).
    #[test]
    fn tabulated_rates_are_the_flows_rate() {
        let rtol = 1e-10;
        for (n, beta, gamma) in [
            (1.5, 0.7, 0.3),
            (1.02, 0.6, 0.3),
            (2.0, 0.6, 0.2),
            (2.7, 0.55, 0.45),
            (6.0, 0.4, 0.3),
        ] {
            let alpha = 1.3;
            let eq = StateEquation::new(alpha, beta, gamma, n, rtol);
            let mut fl = SensitiveFlow::new(eq).unwrap();
            let mut hint = SensitivityHint::default();
            let (mut tabulated, mut points, mut worst) = (0, 0, 0.0f64);
            for i in -20_000..=60_000 {
                let sigma = i as f64 * 1e-4;
                let Some(p) = fl.at(sigma, &mut hint) else {
                    continue;
                };
                // (beyond the pieces, towards saturation, it is computed)
                let side = if sigma >= 0.0 { &fl.upper } else { &fl.lower };
                if sigma.abs() <= side.end_tau {
                    let mut table_hint = SensitivityHint::default();
                    let plain = fl.point_without_rate(sigma, p.g, &mut table_hint).unwrap();
                    points += 1;
                    if !plain.rate.is_nan() {
                        tabulated += 1;
                    }
                }
                let f = eq.rate(p.g);
                worst = worst.max((p.rate - f).abs() / (f.abs() + alpha));
            }
            let share = tabulated as f64 / points as f64;
            println!(
                "n = {n}: {share:.4} of {points} rates on pieces tabulated, all within {worst:.2e}"
            );
            assert!(worst <= 0.5 * rtol, "n = {n}: {worst}");
            assert!(share >= 0.9, "n = {n}: only {share} tabulated");
        }
    }
}
