//! The analytic inverse of a Prandtl-Ishlinskii operator (Krejčí & Kuhnen
//! 2001), itself a play-type Prandtl-Ishlinskii operator.

use crate::{PiBank, PiBankParams};
use hysteron_operators::{Error, Float, Operator, Result};

/// The analytic inverse `x = P⁻¹[y]` of a play-type Prandtl-Ishlinskii
/// operator `y = P[x] = a0 · x + Σ_j w_j play_{r_j}[x]` ([`PiBank`]),
/// after Krejčí & Kuhnen (2001). It is again a play-type PI operator,
/// computed once from the forward parameters:
///
/// * **Thresholds and weights.** Treat `a0` as the weight of a play with
///   threshold 0 (adding the weights of any `r_j = 0` plays), merge plays
///   of equal threshold, and sort: `0 = r_0 < r_1 < … < r_n` with weights
///   `w_0, …, w_n` and cumulative weights `W_i = Σ_{j≤i} w_j`. The inverse
///   has thresholds and weights
///
///   `r'_i = Σ_{j≤i} w_j (r_i − r_j)`  (so `r'_0 = 0`),
///   `w'_0 = 1 / w_0`,  `w'_i = −w_i / (W_i W_{i−1})`  (`i ≥ 1`),
///
///   so that its cumulative weights are `W'_i = 1 / W_i`. This needs
///   `W_i > 0` for every `i` (otherwise the forward operator is not
///   strictly increasing on some branch and has no inverse): an
///   [`Error::InvalidParameter`] names the weight (`a0`, or the first
///   `w[j]`) at which the cumulative sum is not positive, with that sum as
///   the value.
///
/// * **Initial states.** The forward plays start at `y0_j` at `x = 0`; write
///   them as stop values `ψ_i = 0 − y0_i` (`ψ_0 = 0`: a zero threshold play
///   always equals its input, so its `y0` never shows). On a monotone input
///   increase by `Δ` from any state, play `i` starts moving when `Δ`
///   exceeds `d_i = r_i − ψ_i` (on a decrease, `r_i + ψ_i`); the forward
///   output is then piecewise linear in `Δ` with slopes `W_i`, breaking at
///   `D_i = Σ_{k<i} W_k (d_{k+1} − d_k)`. The inverse breaks at its own
///   `r'_i − σ_i` with slopes `1 / W_i`, so it inverts the branch exactly
///   when its stop values are
///
///   `σ_i = Σ_{k<i} W_k (ψ_{k+1} − ψ_k)`  (`σ_0 = 0`),
///
///   and this relation is preserved by every step (both sets of plays move
///   to `±r_i`, `±r'_i` or shift by `Δ`, `Δy` together). The forward output
///   at `x = 0` is `Y0 = Σ_{i≥1} w_i y0_i`, the inverse's input there; a
///   play's step depends only on its state, not on the previous input, so
///   the inverse's initial play outputs are
///
///   `y0'_i = Y0 − σ_i`,
///
///   and `P⁻¹[P[x]] = x`, `P[P⁻¹[y]] = y` hold from the first sample on,
///   up to rounding (the inverse's output at its nominal input 0 is never
///   seen: the first sample moves it from `Y0`). The derivation needs
///   `d_i` and `r_i + ψ_i` non-decreasing in `i`, i.e. initial states that
///   some input history can reach:
///   `|y0_i − y0_{i−1}| ≤ r_i − r_{i−1}` in threshold order (with the zero
///   threshold play at 0), within 16 ε relative for rounding; plays of
///   equal threshold must start equal. Otherwise an
///   [`Error::InvalidParameter`] names the `y0[j]`.
///
/// The inverse is an [`Operator`] whose parameters are the **forward**
/// parameters `[a0, r_0..r_m, w_0..w_m, y0_0..y0_m]` with the forward's
/// names and domains: fitting the inverse (a compensator to measured
/// input/output pairs swapped) fits the forward model, and `set_params`
/// recomputes the inverse (atomically: an invertibility error leaves it
/// unchanged). Its trial/commit/process are those of the play-type bank
/// ([`inverse_bank`](PiInverse::inverse_bank)), exactly rate-independent,
/// with the tangent `1 / P'` (the inverse's active weights).
///
/// ```
/// use hysteron_composition::PiBank;
/// use hysteron_operators::Operator;
/// let mut fwd = PiBank::new(0.5_f64, vec![0.0, 1.0], vec![1.0, 2.0]).unwrap();
/// let mut inv = fwd.analytic_inverse().unwrap();
/// // merged zero threshold: w_0 = 1.5, W_1 = 3.5; r'_1 = 1.5, w'_1 = −2/(3.5·1.5)
/// let p = inv.inverse_bank().parameters();
/// assert_eq!((p.a0, p.r[0], p.w[0]), (1.0 / 1.5, 1.5, -2.0 / (3.5 * 1.5)));
/// let x = [2.0, -1.0, 0.5];
/// let y = fwd.run(&x).unwrap();
/// let back = inv.run(&y).unwrap();
/// for (a, b) in x.iter().zip(&back) {
///     assert!((a - b).abs() < 1e-14);
/// }
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PiInverse<T> {
    forward: PiBankParams<T>,
    inverse: PiBank<T>,
}

/// One play of the normalized forward operator (threshold order, merged).
struct Merged<T> {
    r: T,
    w: T,
    psi: T,
    /// Index of the first original play in this group.
    first: usize,
}

fn invalid<T: Float>(name: String, value: T, reason: &'static str) -> Error {
    Error::InvalidParameter {
        name,
        value: value.as_f64(),
        reason,
    }
}

impl<T: Float> PiInverse<T> {
    /// The analytic inverse of the forward operator with parameters `p`
    /// (see the type's documentation for the conditions).
    pub fn from_params(mut p: PiBankParams<T>) -> Result<Self> {
        let inverse = PiBank::from_params(inverse_params(&p)?)?;
        if p.y0.is_empty() {
            p.y0 = vec![T::zero(); p.r.len()];
        }
        Ok(Self {
            forward: p,
            inverse,
        })
    }

    /// The parameters of the forward operator being inverted.
    pub fn forward_parameters(&self) -> &PiBankParams<T> {
        &self.forward
    }

    /// The inverse as a play-type PI bank (its `a0 = w'_0`, thresholds
    /// `r'_1..r'_n`, weights `w'_1..w'_n`, initial outputs `y0'`).
    pub fn inverse_bank(&self) -> &PiBank<T> {
        &self.inverse
    }
}

impl<T: Float> PiBank<T> {
    /// The analytic inverse of this bank ([`PiInverse`], Krejčí & Kuhnen
    /// 2001), for its parameters (not its current state: like every
    /// operator, the inverse starts from the initial state).
    ///
    /// Errors: a cumulative weight `a0 + Σ_{r_j ≤ r} w_j ≤ 0`, or initial
    /// states no input history can reach ([`Error::InvalidParameter`]).
    pub fn analytic_inverse(&self) -> Result<PiInverse<T>> {
        PiInverse::from_params(self.parameters().clone())
    }
}

/// The play-type PI parameters of the inverse of the forward `p`.
fn inverse_params<T: Float>(p: &PiBankParams<T>) -> Result<PiBankParams<T>> {
    p.validate()?;
    let zero = T::zero();
    let y0 = |j: usize| p.y0.get(j).copied().unwrap_or(zero);
    // Zero threshold plays are the identity after the first sample.
    let mut w0 = p.a0;
    let mut plays: Vec<Merged<T>> = Vec::with_capacity(p.r.len());
    for (j, (&r, &w)) in p.r.iter().zip(&p.w).enumerate() {
        if r == zero {
            w0 = w0 + w;
        } else {
            plays.push(Merged {
                r,
                w,
                psi: zero - y0(j),
                first: j,
            });
        }
    }
    // Stable sort: in a group of equal thresholds the first original play
    // names the group.
    plays.sort_by(|a, b| a.r.partial_cmp(&b.r).unwrap_or(core::cmp::Ordering::Equal));
    let mut merged: Vec<Merged<T>> = Vec::with_capacity(plays.len());
    for play in plays {
        match merged.last_mut() {
            Some(last) if last.r == play.r => {
                if last.psi != play.psi {
                    return Err(invalid(
                        format!("y0[{}]", play.first),
                        zero - play.psi,
                        "plays of equal threshold must start at equal outputs \
                         for the analytic inverse",
                    ));
                }
                last.w = last.w + play.w;
            }
            _ => merged.push(play),
        }
    }
    if w0 <= zero {
        return Err(invalid(
            "a0".into(),
            w0,
            "the weight of the zero threshold (a0 plus the weights of plays with r = 0) \
             must be > 0 for the PI operator to be invertible",
        ));
    }
    let slack = T::epsilon() * T::lit(16.0);
    let (mut r_prev, mut psi_prev, mut w_cum) = (zero, zero, w0);
    let (mut r_inv, mut sigma) = (zero, zero);
    let mut out_r = Vec::with_capacity(merged.len());
    let mut out_w = Vec::with_capacity(merged.len());
    let mut sigmas = Vec::with_capacity(merged.len());
    let mut y_start = zero;
    for m in &merged {
        let gap = m.r - r_prev;
        let scale = m.r + m.psi.abs() + psi_prev.abs();
        if (m.psi - psi_prev).abs() > gap + slack * scale {
            return Err(invalid(
                format!("y0[{}]", m.first),
                zero - m.psi,
                "initial play outputs must be reachable for the analytic inverse: \
                 |y0_i − y0_k| ≤ r_i − r_k for neighbouring thresholds r_k < r_i \
                 (a zero threshold play counts as 0)",
            ));
        }
        let w_next = w_cum + m.w;
        if w_next <= zero {
            return Err(invalid(
                format!("w[{}]", m.first),
                w_next,
                "the cumulative weight a0 + Σ_{r_j ≤ r} w_j must be > 0 at every threshold \
                 for the PI operator to be invertible",
            ));
        }
        r_inv = r_inv + w_cum * gap;
        sigma = sigma + w_cum * (m.psi - psi_prev);
        out_r.push(r_inv);
        out_w.push(zero - m.w / (w_next * w_cum));
        sigmas.push(sigma);
        y_start = y_start - m.w * m.psi;
        r_prev = m.r;
        psi_prev = m.psi;
        w_cum = w_next;
    }
    let y0_inv = sigmas.iter().map(|&s| y_start - s).collect();
    Ok(PiBankParams {
        a0: T::one() / w0,
        r: out_r,
        w: out_w,
        y0: y0_inv,
    })
}

/// Steps as the inner inverse: its input is the bank's output `y`, its
/// output the bank's input `x`.
impl<T: Float> Operator<T> for PiInverse<T> {
    crate::delegate_stepping!(T, inverse);

    fn name(&self) -> &'static str {
        <Self as hysteron_operators::Leaf<T>>::KIND
    }
}

// Its parameters are the forward bank's (`y0` written out in full).
crate::pi_bank::rate_independent_leaf!(
    PiInverse,
    PiBankParams,
    "pi_inverse",
    forward,
    equation: "x = pi_bank⁻¹[y] = â0 y + Σ_j ŵ_j play_{r̂_j}[y], the analytic inverse of the pi_bank with these parameters"
);
