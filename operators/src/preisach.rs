//! The classical scalar Preisach model, from a discrete relay grid or from
//! an Everett function (tabulated or in closed form).

use crate::{
    check, check_input, check_output, CastScalar, Domain, Error, FieldInfo, FieldKind, Float,
    Operator, ParamSet, Result, Trial,
};
use serde::{Deserialize, Serialize};

/// The Preisach measure `μ(α, β) ≥ 0` on the half-plane `α ≥ β` of relay
/// thresholds, in one of four representations.
///
/// The Everett function of the measure is its mass on the triangle below
/// `α` and above `β`:
///
/// `E(α, β) = ∬_{T(α,β)} μ(α', β') dα' dβ'`,
/// `T(α, β) = {(α', β') : β ≤ β' ≤ α' ≤ α}`, for `α ≥ β` (so `E(α, α) = 0`,
/// `E ≥ 0`, non-decreasing in `α`, non-increasing in `β`).
///
/// Row-indexed lower-triangular arrays are written as ragged rows: row `i`
/// has `i + 1` entries (`mu[i][j]` for `j ≤ i`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum PreisachMeasure<T> {
    /// **Discretized relay plane**: relay `(i, j)`, `j ≤ i`, has up
    /// threshold `α = t[i]`, down threshold `β = t[j]` and weight
    /// `mu[i][j] ≥ 0` (a point mass). `t` is strictly increasing (at least
    /// one level); a diagonal relay `(i, i)` switches without hysteresis.
    /// `E(α, β) = Σ_{β ≤ t[j] ≤ t[i] ≤ α} mu[i][j]`: the output is a
    /// staircase in the input (tangent 0), with `Σ μ` the saturated output.
    Grid {
        /// Threshold levels, strictly increasing.
        t: Vec<T>,
        /// Relay weights, ragged lower-triangular: `mu[i][j]`, `j ≤ i`.
        mu: Vec<Vec<T>>,
    },
    /// **Tabulated Everett function** (what measured first-order reversal
    /// curves give), interpolated piecewise-bilinearly: nodes `x[0] < … <
    /// x[m]` (`m ≥ 1`) on both axes and `e[k][j] = E(x[k+1], x[j])` for
    /// `j ≤ k < m` (`E(x[i], x[i]) = 0` is implied). On a cell
    /// `[x[i], x[i+1]] × [x[j], x[j+1]]` with `i > j`, `E` is the bilinear
    /// interpolant of its four corners (density `μ = −∂²E/∂α∂β`, constant
    /// on the cell); on a diagonal cell (`i = j`) it is
    /// `e[i][i] (α − β)/(x[i+1] − x[i])`, continuous with its neighbours
    /// and zero on `α = β`: the cell's mass sits on the diagonal (relays
    /// without hysteresis, a reversible part). Every cell's mass must be
    /// `≥ 0`: `E(x[i+1], x[j]) + E(x[i], x[j+1]) − E(x[i], x[j]) −
    /// E(x[i+1], x[j+1]) ≥ −8 ε Σ|corners|` (zero up to the rounding of
    /// its four values) and `e[k][k] ≥ 0`. The input range is
    /// `[x[0], x[m]]`.
    Table {
        /// Nodes, strictly increasing (at least two).
        x: Vec<T>,
        /// `e[k][j] = E(x[k+1], x[j])`, ragged lower-triangular, `j ≤ k`.
        e: Vec<Vec<T>>,
    },
    /// **Uniform density** `μ ≥ 0` on the triangle `x_min ≤ β ≤ α ≤
    /// x_max`: `E(α, β) = μ (α − β)² / 2`.
    Uniform {
        /// Density `μ ≥ 0`.
        mu: T,
        /// Lower input limit (negative saturation below it).
        x_min: T,
        /// Upper input limit (positive saturation above it), `> x_min`.
        x_max: T,
    },
    /// **Closed-form two-peak family**:
    /// `E(α, β) = (a/4) (F(α) − F(β)) (G(α) − G(β))` with
    /// `F(x) = tanh((x − h_c)/w)`, `G(x) = tanh((x + h_c)/w)`, whose
    /// density on `α ≥ β`,
    /// `μ(α, β) = (a/4) (F'(α) G'(β) + G'(α) F'(β)) > 0`,
    /// peaks at the coercive relays `(α, β) = (h_c, −h_c)` with width `w`.
    /// Strictly positive: every branch strictly increases on
    /// `[x_min, x_max]`. Over a wide range the output saturates near `±a`.
    Tanh {
        /// Amplitude `a ≥ 0` (the saturated output for `x_max − x_min ≫ w`).
        amplitude: T,
        /// Coercive threshold `h_c` (finite; `> 0` for a loop of width `≈ 2 h_c`).
        hc: T,
        /// Width `w > 0` of the distribution of thresholds.
        w: T,
        /// Lower input limit.
        x_min: T,
        /// Upper input limit, `> x_min`.
        x_max: T,
    },
}

/// Where the [`Preisach`] model is at input `x = 0` before the first sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PreisachStart {
    /// Negative saturation (every relay down), then the input rose to 0:
    /// memory `[x_min, 0]` (`y = −E₀ + 2 E(0, x_min)`). The default.
    #[default]
    FromBelow,
    /// Positive saturation (every relay up), then the input fell to 0:
    /// memory `[x_min, x_max, 0]` (`y = E₀ − 2 E(x_max, 0)`).
    FromAbove,
}

/// Parameters of the [`Preisach`] model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PreisachParams<T> {
    /// The Preisach measure.
    pub measure: PreisachMeasure<T>,
    /// The state at input 0 before the first sample (not a parameter of the
    /// flat vector).
    #[serde(default)]
    pub start: PreisachStart,
}

/// The same measure over the scalar `U` (see [`CastScalar`]).
impl<T: Float, U: Float> CastScalar<U> for PreisachParams<T> {
    type Out = PreisachParams<U>;
    fn cast_scalar(&self) -> PreisachParams<U> {
        let rows = |m: &Vec<Vec<T>>| m.iter().map(|r| r.cast_scalar()).collect();
        let c = |v: &T| -> U { v.cast_scalar() };
        let measure = match &self.measure {
            PreisachMeasure::Grid { t, mu } => PreisachMeasure::Grid {
                t: t.cast_scalar(),
                mu: rows(mu),
            },
            PreisachMeasure::Table { x, e } => PreisachMeasure::Table {
                x: x.cast_scalar(),
                e: rows(e),
            },
            PreisachMeasure::Uniform { mu, x_min, x_max } => PreisachMeasure::Uniform {
                mu: c(mu),
                x_min: c(x_min),
                x_max: c(x_max),
            },
            PreisachMeasure::Tanh {
                amplitude,
                hc,
                w,
                x_min,
                x_max,
            } => PreisachMeasure::Tanh {
                amplitude: c(amplitude),
                hc: c(hc),
                w: c(w),
                x_min: c(x_min),
                x_max: c(x_max),
            },
        };
        PreisachParams {
            measure,
            start: self.start,
        }
    }
}

/// Checks a strictly increasing, finite, non-empty axis of at least `min` entries.
fn check_axis<T: Float>(name: &str, v: &[T], min: usize, reason: &'static str) -> Result<()> {
    if v.len() < min {
        return Err(check::invalid(name, T::lit(v.len() as f64), reason));
    }
    let mut prev: Option<T> = None;
    for (k, &x) in v.iter().enumerate() {
        check::finite(&format!("{name}[{k}]"), x)?;
        if prev.is_some_and(|p| x <= p) {
            return Err(check::invalid(
                &format!("{name}[{k}]"),
                x,
                "must be strictly increasing",
            ));
        }
        prev = Some(x);
    }
    Ok(())
}

/// Checks that `rows` is ragged lower-triangular with `n` rows, every entry
/// finite and `≥ 0`.
fn check_triangle<T: Float>(name: &str, rows: &[Vec<T>], n: usize) -> Result<()> {
    if rows.len() != n {
        return Err(check::invalid(
            name,
            T::lit(rows.len() as f64),
            "must have one row per level (as many rows as the axis has levels, or nodes − 1)",
        ));
    }
    for (i, row) in rows.iter().enumerate() {
        if row.len() != i + 1 {
            return Err(check::invalid(
                &format!("{name}[{i}]"),
                T::lit(row.len() as f64),
                "row i must have i + 1 entries (lower-triangular)",
            ));
        }
        for (j, &v) in row.iter().enumerate() {
            check::non_negative(&format!("{name}[{i}][{j}]"), v)?;
        }
    }
    Ok(())
}

impl<T: Float> PreisachMeasure<T> {
    /// Checks the measure (see the variants): finite values, strictly
    /// increasing axes, lower-triangular shapes, `μ ≥ 0`, `x_min < x_max`.
    pub fn validate(&self) -> Result<()> {
        match self {
            PreisachMeasure::Grid { t, mu } => {
                check_axis("t", t, 1, "need at least one threshold level")?;
                check_triangle("mu", mu, t.len())
            }
            PreisachMeasure::Table { x, e } => {
                check_axis("x", x, 2, "need at least two nodes")?;
                let m = x.len() - 1;
                check_triangle("e", e, m)?;
                // E at node pairs (p ≥ q); E(p, p) = 0. Called below with
                // 1 ≤ p ≤ m, q < p: row p − 1 of `e` has p entries by
                // `check_triangle` (m rows, row k has k + 1 entries).
                #[allow(clippy::indexing_slicing)]
                let at = |p: usize, q: usize| if p == q { T::zero() } else { e[p - 1][q] };
                // Row i of `e` is E(x[i+1], ·): the cells (i, j), j < i.
                for (i, row) in e.iter().enumerate().skip(1) {
                    for (j, &a) in row.iter().enumerate().take(i) {
                        let (b, c, d) = (at(i, j + 1), at(i, j), at(i + 1, j + 1));
                        let mass = a + b - c - d;
                        // A mass below the rounding of its corners is zero
                        // to the table's precision (tables summed from
                        // cell masses round like that).
                        let noise = T::lit(8.0) * T::epsilon() * (a + b + c + d);
                        if mass < -noise {
                            return Err(check::invalid(
                                &format!("e[{i}][{j}]"),
                                a,
                                "the Everett table has negative mass on the cell [x[i], x[i+1]] × [x[j], x[j+1]]: need E(x[i+1], x[j]) + E(x[i], x[j+1]) ≥ E(x[i], x[j]) + E(x[i+1], x[j+1])",
                            ));
                        }
                    }
                }
                Ok(())
            }
            PreisachMeasure::Uniform { mu, x_min, x_max } => {
                check::non_negative("mu", *mu)?;
                check::ordered("x_min", *x_min, "x_max", *x_max)
            }
            PreisachMeasure::Tanh {
                amplitude,
                hc,
                w,
                x_min,
                x_max,
            } => {
                check::non_negative("amplitude", *amplitude)?;
                check::finite("hc", *hc)?;
                check::positive("w", *w)?;
                check::ordered("x_min", *x_min, "x_max", *x_max)
            }
        }
    }

    /// Whether the output is a staircase (the discrete relay grid).
    pub fn is_discrete(&self) -> bool {
        matches!(self, PreisachMeasure::Grid { .. })
    }

    /// The number of values in the flat parameter vector.
    pub fn n_params(&self) -> usize {
        match self {
            PreisachMeasure::Grid { t, mu } => t.len() + mu.iter().map(Vec::len).sum::<usize>(),
            PreisachMeasure::Table { x, e } => x.len() + e.iter().map(Vec::len).sum::<usize>(),
            PreisachMeasure::Uniform { .. } => 3,
            PreisachMeasure::Tanh { .. } => 5,
        }
    }

    fn params_into(&self, out: &mut Vec<T>) {
        match self {
            PreisachMeasure::Grid { t: a, mu: rows } | PreisachMeasure::Table { x: a, e: rows } => {
                out.extend_from_slice(a);
                for r in rows {
                    out.extend_from_slice(r);
                }
            }
            PreisachMeasure::Uniform { mu, x_min, x_max } => out.extend([*mu, *x_min, *x_max]),
            PreisachMeasure::Tanh {
                amplitude,
                hc,
                w,
                x_min,
                x_max,
            } => out.extend([*amplitude, *hc, *w, *x_min, *x_max]),
        }
    }

    fn param_names(&self) -> Vec<String> {
        let tri = |axis: &str, n: usize, name: &str, rows: &[Vec<T>]| -> Vec<String> {
            (0..n)
                .map(|k| format!("{axis}[{k}]"))
                .chain(
                    rows.iter()
                        .enumerate()
                        .flat_map(|(i, r)| (0..r.len()).map(move |j| format!("{name}[{i}][{j}]"))),
                )
                .collect()
        };
        match self {
            PreisachMeasure::Grid { t, mu } => tri("t", t.len(), "mu", mu),
            PreisachMeasure::Table { x, e } => tri("x", x.len(), "e", e),
            PreisachMeasure::Uniform { .. } => vec!["mu".into(), "x_min".into(), "x_max".into()],
            PreisachMeasure::Tanh { .. } => ["amplitude", "hc", "w", "x_min", "x_max"]
                .into_iter()
                .map(String::from)
                .collect(),
        }
    }

    fn param_domains(&self) -> Vec<Domain> {
        use Domain::*;
        match self {
            PreisachMeasure::Grid { t: a, mu: rows } | PreisachMeasure::Table { x: a, e: rows } => {
                let n: usize = rows.iter().map(Vec::len).sum();
                std::iter::repeat_n(Real, a.len())
                    .chain(std::iter::repeat_n(NonNegative, n))
                    .collect()
            }
            PreisachMeasure::Uniform { .. } => vec![NonNegative, Real, Real],
            PreisachMeasure::Tanh { .. } => vec![NonNegative, Real, Positive, Real, Real],
        }
    }

    /// The same representation and shape with the values `p` (in the order
    /// of [`Parameters::params`](crate::Parameters::params) of the model), unvalidated.
    // `p.len() == self.n_params()` by `check::count` (3 for `Uniform`, 5 for
    // `Tanh`), so `p[0..3]` / `p[0..5]` exist.
    #[allow(clippy::indexing_slicing)]
    pub fn from_flat(&self, p: &[T]) -> Result<Self> {
        check::count(self.n_params(), p)?;
        let refill = |a: &[T], rows: &[Vec<T>]| -> (Vec<T>, Vec<Vec<T>>) {
            let (head, mut rest) = p.split_at(a.len());
            let rows = rows
                .iter()
                .map(|r| {
                    let (row, tail) = rest.split_at(r.len());
                    rest = tail;
                    row.to_vec()
                })
                .collect();
            (head.to_vec(), rows)
        };
        Ok(match self {
            PreisachMeasure::Grid { t, mu } => {
                let (t, mu) = refill(t, mu);
                PreisachMeasure::Grid { t, mu }
            }
            PreisachMeasure::Table { x, e } => {
                let (x, e) = refill(x, e);
                PreisachMeasure::Table { x, e }
            }
            PreisachMeasure::Uniform { .. } => PreisachMeasure::Uniform {
                mu: p[0],
                x_min: p[1],
                x_max: p[2],
            },
            PreisachMeasure::Tanh { .. } => PreisachMeasure::Tanh {
                amplitude: p[0],
                hc: p[1],
                w: p[2],
                x_min: p[3],
                x_max: p[4],
            },
        })
    }
}

impl<T: Float> PreisachParams<T> {
    /// A relay grid discretizing a density `μ(α, β)` on `[x_min, x_max]`
    /// with `n ≥ 1` levels by the midpoint rule: `t[k] = x_min + (k + ½) h`,
    /// `h = (x_max − x_min)/n`, `mu[i][j] = μ(t[i], t[j]) h²` for `j < i`
    /// and `μ(t[i], t[i]) h²/2` on the diagonal (half a cell). Negative or
    /// non-finite density values are rejected when the model is built.
    pub fn grid_from_density(x_min: T, x_max: T, n: usize, density: impl Fn(T, T) -> T) -> Self {
        let nn = T::lit(n.max(1) as f64);
        let h = (x_max - x_min) / nn;
        let half = T::lit(0.5);
        let t: Vec<T> = (0..n)
            .map(|k| x_min + (T::lit(k as f64) + half) * h)
            .collect();
        let mu = t
            .iter()
            .enumerate()
            .map(|(i, &ti)| {
                t.iter()
                    .take(i + 1)
                    .enumerate()
                    .map(|(j, &tj)| {
                        let m = density(ti, tj) * h * h;
                        if i == j {
                            m * half
                        } else {
                            m
                        }
                    })
                    .collect()
            })
            .collect();
        Self {
            measure: PreisachMeasure::Grid { t, mu },
            start: PreisachStart::FromBelow,
        }
    }
}

/// The measure prepared for evaluation.
///
/// Index invariant (what the `#[allow(clippy::indexing_slicing)]` below rely
/// on): `Kernel::new` runs only on a validated measure, so `t.len() = n ≥ 1`
/// and `c.len() = n(n+1)/2` (Grid), `x.len() = n ≥ 2` and
/// `e.len() = n(n+1)/2` (Table); `tri(p, q) ≤ tri(n−1, n−1) = n(n+1)/2 − 1`
/// for any `p, q ≤ n − 1`, in range.
#[derive(Debug, Clone, PartialEq)]
enum Kernel<T> {
    /// Thresholds and the cumulative masses `c[a][b] = Σ_{b ≤ j ≤ i ≤ a}
    /// μ_ij` (flat, index `a(a+1)/2 + b`). The staircase is kept in level
    /// coordinates `v(x) = #{t ≤ x} + #{t < x}` (integers in `[0, 2n]`).
    Grid { t: Vec<T>, c: Vec<T> },
    /// Nodes and `E(x[p], x[q])` for `p ≥ q` (flat, index `p(p+1)/2 + q`).
    Table { x: Vec<T>, e: Vec<T> },
    /// `E = half_mu (α − β)²`.
    Uniform { half_mu: T },
    /// `E = a4 (F(α) − F(β)) (G(α) − G(β))`.
    Tanh { a4: T, hc: T, w: T },
}

#[inline(always)]
fn tri(a: usize, b: usize) -> usize {
    a * (a + 1) / 2 + b
}

impl<T: Float> Kernel<T> {
    // Only called on a validated measure (`from_params` validates first):
    // `mu` has `n` rows, row `a` has `a + 1` entries (`b ≤ a`); `e` has
    // `n − 1` rows, row `p − 1` has `p` entries (`q < p`); `tri(a, b)` with
    // `b ≤ a < n` is `< n(n+1)/2 = c.len() = flat.len()`.
    #[allow(clippy::indexing_slicing)]
    fn new(m: &PreisachMeasure<T>) -> Self {
        match m {
            PreisachMeasure::Grid { t, mu } => {
                let n = t.len();
                let mut c = vec![T::zero(); n * (n + 1) / 2];
                for a in 0..n {
                    // c[a][b] = c[a−1][b] + Σ_{j=b..=a} μ[a][j], b from a down to 0.
                    let mut row = T::zero();
                    for b in (0..=a).rev() {
                        row = row + mu[a][b];
                        let above = if b < a { c[tri(a - 1, b)] } else { T::zero() };
                        c[tri(a, b)] = above + row;
                    }
                }
                Kernel::Grid { t: t.clone(), c }
            }
            PreisachMeasure::Table { x, e } => {
                let n = x.len();
                let mut flat = vec![T::zero(); n * (n + 1) / 2];
                for p in 1..n {
                    for q in 0..p {
                        flat[tri(p, q)] = e[p - 1][q];
                    }
                }
                Kernel::Table {
                    x: x.clone(),
                    e: flat,
                }
            }
            PreisachMeasure::Uniform { mu, .. } => Kernel::Uniform {
                half_mu: *mu * T::lit(0.5),
            },
            PreisachMeasure::Tanh {
                amplitude, hc, w, ..
            } => Kernel::Tanh {
                a4: *amplitude * T::lit(0.25),
                hc: *hc,
                w: *w,
            },
        }
    }

    /// The staircase coordinate of input `x`, and its range `[lo, hi]`.
    #[inline]
    fn coord(&self, x: T, lo: T, hi: T) -> T {
        match self {
            Kernel::Grid { t, .. } => {
                let up = t.partition_point(|&tk| tk <= x);
                let down = t.partition_point(|&tk| tk < x);
                T::lit((up + down) as f64)
            }
            _ => x.max(lo).min(hi),
        }
    }

    /// The cell `i` with `x[i] ≤ v ≤ x[i+1]`: the one to the right of a
    /// node, or to its left if `left` (and always a valid cell).
    #[inline]
    fn cell(x: &[T], v: T, left: bool) -> usize {
        let m = x.len() - 1;
        let k = if left {
            x.partition_point(|&n| n < v).saturating_sub(1)
        } else {
            x.partition_point(|&n| n <= v).saturating_sub(1)
        };
        k.min(m - 1)
    }

    /// `E(α, β)` for coordinates `α ≥ β`.
    // Grid: `a ≤ 2n` (a level count, see `coord`), so `up − 1 ≤ n − 1` and
    // `down ≤ up − 1` is checked; Table: `cell` returns `i, j ≤ n − 2`. See
    // the index invariant on `Kernel`.
    #[allow(clippy::indexing_slicing)]
    #[inline]
    fn everett(&self, a: T, b: T) -> T {
        match self {
            Kernel::Grid { c, .. } => {
                let up = a.to_usize().unwrap_or(0).div_ceil(2); // relays with i < up are reached
                let down = b.to_usize().unwrap_or(0) / 2; // relays with j ≥ down
                if up == 0 || up - 1 < down {
                    T::zero()
                } else {
                    c[tri(up - 1, down)]
                }
            }
            Kernel::Table { x, e } => {
                let i = Self::cell(x, a, false);
                let j = Self::cell(x, b, false);
                Self::table_value(x, e, i, j, a, b)
            }
            Kernel::Uniform { half_mu } => {
                let d = a - b;
                *half_mu * d * d
            }
            Kernel::Tanh { a4, hc, w } => {
                let f = |v: T| ((v - *hc) / *w).tanh();
                let g = |v: T| ((v + *hc) / *w).tanh();
                *a4 * (f(a) - f(b)) * (g(a) - g(b))
            }
        }
    }

    // `i, j ≤ n − 2` (from `cell`), so `x[i + 1]`, `x[j + 1]` exist and
    // every `tri(p, q)` here has `p, q ≤ n − 1` (see `Kernel`).
    #[allow(clippy::indexing_slicing)]
    #[inline]
    fn table_value(x: &[T], e: &[T], i: usize, j: usize, a: T, b: T) -> T {
        let (hi, hj) = (x[i + 1] - x[i], x[j + 1] - x[j]);
        let s = (a - x[i]) / hi;
        let r = (b - x[j]) / hj;
        if i == j {
            e[tri(i + 1, i)] * (s - r)
        } else {
            let e00 = e[tri(i, j)];
            let e10 = e[tri(i + 1, j)];
            // E(x[i], x[j+1]); 0 (the diagonal) when j + 1 = i.
            let e01 = e[tri(i, j + 1)];
            let e11 = e[tri(i + 1, j + 1)];
            let one = T::one();
            (one - s) * (one - r) * e00 + s * (one - r) * e10 + (one - s) * r * e01 + s * r * e11
        }
    }

    /// `∂E/∂α (α, β)` (right derivative in `α`).
    // `i, j ≤ n − 2` (from `cell`): see `table_value`.
    #[allow(clippy::indexing_slicing)]
    fn d_alpha(&self, a: T, b: T) -> T {
        match self {
            Kernel::Grid { .. } => T::zero(),
            Kernel::Table { x, e } => {
                let i = Self::cell(x, a, false);
                let j = Self::cell(x, b, false);
                let hi = x[i + 1] - x[i];
                if i == j {
                    return e[tri(i + 1, i)] / hi;
                }
                let r = (b - x[j]) / (x[j + 1] - x[j]);
                let e01 = e[tri(i, j + 1)];
                let one = T::one();
                ((one - r) * (e[tri(i + 1, j)] - e[tri(i, j)]) + r * (e[tri(i + 1, j + 1)] - e01))
                    / hi
            }
            Kernel::Uniform { half_mu } => (*half_mu + *half_mu) * (a - b),
            Kernel::Tanh { a4, hc, w } => {
                let (fa, fb) = (((a - *hc) / *w).tanh(), ((b - *hc) / *w).tanh());
                let (ga, gb) = (((a + *hc) / *w).tanh(), ((b + *hc) / *w).tanh());
                let one = T::one();
                *a4 * ((one - fa * fa) * (ga - gb) + (fa - fb) * (one - ga * ga)) / *w
            }
        }
    }

    /// `−∂E/∂β (α, β) ≥ 0` (left derivative in `β`: the slope of a
    /// descending branch).
    // `i, j ≤ n − 2` (from `cell`): see `table_value`.
    #[allow(clippy::indexing_slicing)]
    fn neg_d_beta(&self, a: T, b: T) -> T {
        match self {
            Kernel::Grid { .. } => T::zero(),
            Kernel::Table { x, e } => {
                let i = Self::cell(x, a, true);
                let j = Self::cell(x, b, true);
                let hj = x[j + 1] - x[j];
                if i <= j {
                    return e[tri(j + 1, j)] / hj;
                }
                let s = (a - x[i]) / (x[i + 1] - x[i]);
                let e01 = e[tri(i, j + 1)];
                let one = T::one();
                ((one - s) * (e[tri(i, j)] - e01) + s * (e[tri(i + 1, j)] - e[tri(i + 1, j + 1)]))
                    / hj
            }
            Kernel::Uniform { half_mu } => (*half_mu + *half_mu) * (a - b),
            Kernel::Tanh { a4, hc, w } => {
                let (fa, fb) = (((a - *hc) / *w).tanh(), ((b - *hc) / *w).tanh());
                let (ga, gb) = (((a + *hc) / *w).tanh(), ((b + *hc) / *w).tanh());
                let one = T::one();
                *a4 * ((one - fb * fb) * (ga - gb) + (fa - fb) * (one - gb * gb)) / *w
            }
        }
    }
}

/// One entry of the memory staircase: a coordinate and the running sum
/// `P` of the Everett terms up to it.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Entry<T> {
    v: T,
    p: T,
}

/// A trial: keep the first `keep` committed entries, then append `top`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Pending<T> {
    keep: usize,
    top: Entry<T>,
}

/// The classical scalar **Preisach model** with relays `γ_{αβ} = ±1`:
///
/// `y(t) = ∬_{α ≥ β} μ(α, β) γ_{αβ}[x](t) dα dβ`,
///
/// where the relay `γ_{αβ}` switches to `+1` when `x ≥ α` and to `−1` when
/// `x ≤ β` and otherwise keeps its value, and `μ ≥ 0` is given by a
/// [`PreisachMeasure`] on the triangle `x_min ≤ β ≤ α ≤ x_max` (a relay
/// grid, a tabulated Everett function, or a closed form). The input is
/// clipped to `[x_min, x_max]` (beyond, every relay is saturated).
///
/// # Everett form
/// The memory is the **staircase** of dominant extrema
/// `p_0 = x_min, p_1, …, p_n = x(t)`, alternately maxima and minima with
/// `p_1 > p_3 > …` and `p_0 < p_2 < …` (the current input last). With the
/// Everett function `E` of the measure and `E₀ = E(x_max, x_min)`,
///
/// `y = −E₀ + 2 Σ_{k=1}^{n} s_k E(max(p_{k−1}, p_k), min(p_{k−1}, p_k))`,
/// `s_k = sgn(p_k − p_{k−1})`,
///
/// i.e. `2 ∬_{S⁺} μ − E₀` with `S⁺` the relays that are up. A new input
/// that passes a stored extremum of its own kind **wipes out** it and the
/// extremum after it (the pair's loop is closed), so the staircase always
/// alternates and contracts. The output is bounded by `±E₀`. Minor loops
/// between the same two extrema are **congruent**, and the model is
/// rate-independent.
///
/// Tangent on the current branch: `dy/dx = 2 ∂E/∂α(x, p_{n−1})` while the
/// input rises, `−2 ∂E/∂β(p_{n−1}, x)` while it falls (at a standstill:
/// continuing the last motion); 0 outside `[x_min, x_max]` and for the
/// relay grid, whose output is a staircase of jumps. With a strictly
/// positive density (the `tanh` family, a table with positive cell masses)
/// each branch strictly increases on `[x_min, x_max]`, so
/// `Inverse` (`.inverse()`) inverts it there; the grid's
/// staircase has no inverse, and `.inverse()` of it fails with
/// [`Error::Jump`] where a target falls between two steps.
///
/// # Memory
/// The staircase is a stack reused from sample to sample (a trial stores
/// only where it truncates the stack and the new top, no allocation).
/// For the grid it is kept in level coordinates (how many thresholds lie
/// below the input), so its depth is at most `2n + 2` for `n` levels and
/// is allocated once. For the continuous forms it holds every nested,
/// not yet wiped-out reversal (the model remembers all of them): a
/// periodic input reaches a fixed depth, after which nothing is allocated;
/// a decaying oscillation with `N` reversals inside each other needs `N`
/// entries (16 bytes each for `f64`).
///
/// # Initial state
/// At input 0 before the first sample, from [`PreisachStart`]: negative
/// saturation then a rise to 0 (default), or positive saturation then a
/// fall to 0.
///
/// ```
/// use hysteron_operators::{Operator, Preisach, PreisachMeasure, PreisachParams, PreisachStart};
/// // Uniform density μ = 1 on [−1, 1]: E(α, β) = (α − β)²/2, E₀ = 2.
/// let mut p = Preisach::from_params(PreisachParams {
///     measure: PreisachMeasure::Uniform { mu: 1.0_f64, x_min: -1.0, x_max: 1.0 },
///     start: PreisachStart::FromBelow,
/// }).unwrap();
/// // ascending from negative saturation: y = −2 + (x + 1)²
/// assert_eq!(p.run(&[0.5, 1.0]).unwrap(), vec![0.25, 2.0]);
/// // descending from positive saturation: y = 2 − (1 − x)²
/// assert_eq!(p.run(&[0.0]).unwrap(), vec![1.0]);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Preisach<T> {
    p: PreisachParams<T>,
    kernel: Kernel<T>,
    /// Input range `[lo, hi]` and its coordinates.
    lo: T,
    hi: T,
    e0: T,
    stack: Vec<Entry<T>>,
    pending: Option<Pending<T>>,
}

impl<T: Float> Preisach<T> {
    /// A Preisach model from validated parameters.
    // A validated table has at least two nodes, so `x[0]` and `x[len − 1]`
    // exist.
    #[allow(clippy::indexing_slicing)]
    pub fn from_params(p: PreisachParams<T>) -> Result<Self> {
        p.validate()?;
        let kernel = Kernel::new(&p.measure);
        let (lo, hi) = match &p.measure {
            PreisachMeasure::Grid { t, .. } => (T::zero(), T::lit((2 * t.len()) as f64)),
            PreisachMeasure::Table { x, .. } => (x[0], x[x.len() - 1]),
            PreisachMeasure::Uniform { x_min, x_max, .. }
            | PreisachMeasure::Tanh { x_min, x_max, .. } => (*x_min, *x_max),
        };
        let cap = match &p.measure {
            PreisachMeasure::Grid { t, .. } => 2 * t.len() + 3,
            _ => 32,
        };
        let e0 = kernel.everett(hi, lo);
        let mut s = Self {
            p,
            kernel,
            lo,
            hi,
            e0,
            stack: Vec::with_capacity(cap),
            pending: None,
        };
        s.reset();
        if !s.e0.is_finite() {
            return Err(check::invalid(
                "measure",
                s.e0,
                "the total mass E(x_max, x_min) overflows",
            ));
        }
        Ok(s)
    }

    /// The parameters.
    pub fn parameters(&self) -> &PreisachParams<T> {
        &self.p
    }

    /// The saturated output `E₀ = E(x_max, x_min)`: `|y| ≤ E₀`.
    pub fn saturation(&self) -> T {
        self.e0
    }

    /// The Everett function `E(α, β)` of the measure for inputs `α ≥ β`
    /// (clipped to the input range; 0 if `α < β`).
    pub fn everett(&self, alpha: T, beta: T) -> T {
        let a = self.kernel.coord(alpha, self.lo, self.hi);
        let b = self.kernel.coord(beta, self.lo, self.hi);
        if a < b {
            T::zero()
        } else {
            self.kernel.everett(a, b)
        }
    }

    /// The number of entries of the committed staircase (the initial
    /// minimum, the stored extrema and the current input).
    pub fn memory_depth(&self) -> usize {
        self.stack.len()
    }

    /// The committed output.
    // The stack is never empty: `reset` (run by `from_params`) pushes an
    // entry, and `commit` pushes one after every truncation.
    #[allow(clippy::indexing_slicing)]
    pub fn output(&self) -> T {
        self.out(self.stack[self.stack.len() - 1].p)
    }

    #[inline(always)]
    fn out(&self, p: T) -> T {
        (p + p) - self.e0
    }

    /// The term `s E(max, min)` of a segment from `a` to `b`.
    #[inline(always)]
    fn term(&self, a: T, b: T) -> T {
        if b > a {
            self.kernel.everett(b, a)
        } else {
            -self.kernel.everett(a, b)
        }
    }

    /// Where the staircase goes for coordinate `v` from the committed one.
    // The stack is never empty (see `output`), so `n = len − 1` is an index;
    // `n − 1` is used only when `n ≥ 1`; `keep ≤ n + 1 = len`, and
    // `keep − 2`, `keep − 1` only when `keep ≥ 2`, `keep ≥ 1`.
    #[allow(clippy::indexing_slicing)]
    #[inline]
    fn advance(&self, v: T) -> Pending<T> {
        let s = &self.stack;
        let n = s.len() - 1;
        let top = s[n];
        if v == top.v {
            return Pending { keep: n, top };
        }
        let up = v > top.v;
        let continuing = n >= 1 && (top.v > s[n - 1].v) == up;
        let mut keep = if continuing { n } else { n + 1 };
        // Wipe-out: passing (or reaching) the extremum two back closes its loop.
        while keep >= 2
            && (if up {
                v >= s[keep - 2].v
            } else {
                v <= s[keep - 2].v
            })
        {
            keep -= 2;
        }
        let p = if keep == 0 {
            T::zero()
        } else {
            let prev = s[keep - 1];
            prev.p + self.term(prev.v, v)
        };
        Pending {
            keep,
            top: Entry { v, p },
        }
    }

    /// The tangent of the branch through `pend` (raw input `x`).
    // The stack is never empty and `pend` came from `advance` on it, so
    // `1 ≤ pend.keep ≤ len` in the last branch; in the standstill branch
    // `keep = n ≥ 1` (the first branch took `keep = 0`).
    #[allow(clippy::indexing_slicing)]
    fn tangent(&self, x: T, pend: &Pending<T>) -> T {
        if matches!(self.kernel, Kernel::Grid { .. }) {
            return T::zero();
        }
        let s = &self.stack;
        let n = s.len() - 1;
        let v = pend.top.v;
        // Direction and the origin of the current branch.
        let (up, origin) = if pend.keep == 0 {
            // at x_min (reached, or never left): the next branch rises
            (true, self.lo)
        } else if pend.keep == n && v == s[n].v {
            // standstill: continue the last motion (here n ≥ 1)
            (s[n].v > s[n - 1].v, s[n - 1].v)
        } else {
            let o = s[pend.keep - 1].v;
            (v > o, o)
        };
        let flat = x > self.hi || x < self.lo || (up && x == self.hi) || (!up && x == self.lo);
        if flat {
            return T::zero();
        }
        let two = T::lit(2.0);
        if up {
            two * self.kernel.d_alpha(v, origin)
        } else {
            two * self.kernel.neg_d_beta(origin, v)
        }
    }
}

impl<T: Float> Operator<T> for Preisach<T> {
    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        self.pending = None;
        let x = check_input(x)?;
        let v = self.kernel.coord(x, self.lo, self.hi);
        let pend = self.advance(v);
        let t = check_output(
            "preisach",
            x,
            Trial {
                output: self.out(pend.top.p),
                tangent: self.tangent(x, &pend),
            },
        )?;
        self.pending = Some(pend);
        Ok(t)
    }

    fn commit(&mut self) {
        if let Some(pend) = self.pending.take() {
            self.stack.truncate(pend.keep);
            self.stack.push(pend.top);
        }
    }

    fn reset(&mut self) {
        self.pending = None;
        self.stack.clear();
        let (lo, hi) = (self.lo, self.hi);
        let zero = self.kernel.coord(T::zero(), lo, hi);
        self.stack.push(Entry {
            v: lo,
            p: T::zero(),
        });
        if self.p.start == PreisachStart::FromAbove {
            self.stack.push(Entry {
                v: hi,
                p: self.kernel.everett(hi, lo),
            });
        }
        let pend = self.advance(zero);
        self.stack.truncate(pend.keep);
        self.stack.push(pend.top);
    }

    fn name(&self) -> &'static str {
        <Self as crate::Leaf<T>>::KIND
    }
}

crate::leaf_traits!(Preisach);

/// No fast paths beyond the batch loop of `process`.
impl<T: Float> crate::Hints<T> for Preisach<T> {}

/// Rate-independent: the period is only checked.
impl<T: Float> crate::SamplePeriod<T> for Preisach<T> {}

/// The flat parameters are the measure's (see [`PreisachMeasure`]); the
/// start is a setting.
impl<T: Float> ParamSet<T> for PreisachParams<T> {
    const FIELDS: &'static [FieldInfo] = &[
        FieldInfo {
            name: "measure",
            kind: FieldKind::Nested,
            doc: &["The Preisach measure."],
        },
        FieldInfo {
            name: "start",
            kind: FieldKind::Fixed,
            doc: &["The state at input 0 before the first sample."],
        },
    ];

    fn count(&self) -> usize {
        self.measure.n_params()
    }

    fn names_into(&self, prefix: &str, out: &mut Vec<String>) {
        out.extend(
            self.measure
                .param_names()
                .into_iter()
                .map(|n| format!("{prefix}{n}")),
        );
    }

    fn domains_into(&self, out: &mut Vec<Domain>) {
        out.extend(self.measure.param_domains());
    }

    fn write(&self, out: &mut Vec<T>) {
        self.measure.params_into(out);
    }

    fn read(&self, p: &mut &[T]) -> Result<Self> {
        let n = self.count();
        if p.len() < n {
            return Err(Error::ParamCount {
                expected: n,
                got: p.len(),
            });
        }
        let (head, tail) = p.split_at(n);
        *p = tail;
        Ok(Self {
            measure: self.measure.from_flat(head)?,
            start: self.start,
        })
    }

    fn validate(&self) -> Result<()> {
        self.measure.validate()
    }

    /// A `tanh` measure starting from above.
    fn example() -> Self {
        PreisachParams {
            measure: PreisachMeasure::Tanh {
                amplitude: T::lit(1.5),
                hc: T::lit(0.3),
                w: T::lit(0.4),
                x_min: T::lit(-2.0),
                x_max: T::lit(2.0),
            },
            start: PreisachStart::FromAbove,
        }
    }
}

crate::impl_leaf!(
    Preisach,
    PreisachParams,
    "preisach",
    p,
    equation: "y = ∬_{α≥β} μ(α, β) γ_{αβ}[x] dα dβ (relays γ_{αβ} switching up at α, down at β)"
);

#[cfg(test)]
mod tests {
    use super::*;

    /// The model is generic: in `f32` the uniform density's ascending
    /// branch `y = −E₀ + μ (x − x_min)²` holds to a few ulps of `E₀`, and
    /// the grid's staircase levels are exact sums of its weights.
    #[test]
    fn works_in_f32() {
        let mut p = Preisach::from_params(PreisachParams {
            measure: PreisachMeasure::Uniform {
                mu: 0.5_f32,
                x_min: -1.0,
                x_max: 1.0,
            },
            start: PreisachStart::FromBelow,
        })
        .unwrap();
        let e0 = p.saturation();
        assert_eq!(e0, 1.0);
        p.run(&[-2.0]).unwrap();
        for k in 0..=20 {
            let x = -1.0 + 0.1 * k as f32;
            let y = p.run(&[x]).unwrap()[0];
            let expected = -e0 + 0.5 * (x + 1.0) * (x + 1.0);
            assert!(
                (y - expected).abs() <= 4.0 * f32::EPSILON * e0,
                "{x}: {y} vs {expected}"
            );
        }
        let mut g = Preisach::from_params(PreisachParams {
            measure: PreisachMeasure::Grid {
                t: vec![-0.5_f32, 0.5],
                mu: vec![vec![0.25], vec![0.5, 0.125]],
            },
            start: PreisachStart::FromBelow,
        })
        .unwrap();
        // E₀ = 0.875, all down at −1; the diagonal relay at −0.5 goes up
        // there (+0.5), the relays with α = 0.5 at 0.5 (+1.25); back at 0
        // the diagonal relay at 0.5 is down again (x ≤ β = 0.5: −0.25), at
        // −0.5 every relay is down (β ≥ −0.5 for all).
        assert_eq!(
            g.run(&[-1.0, -0.5, 0.0, 0.5, 0.0, -0.5]).unwrap(),
            vec![-0.875, -0.375, -0.375, 0.875, 0.625, -0.875]
        );
    }
}
