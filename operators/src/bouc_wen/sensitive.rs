//! Over dual numbers: each sample on the flow of the parameters' values,
//! tabulated with its derivatives with respect to `α, β, γ, n`.

use super::batch::goes_on;
use super::evaluation::Evaluation;
use super::state::{BranchStart, SensitiveStep};
use super::BoucWen;
use crate::flow_sensitivity::{FlowPoint, SensitiveFlow, SensitivityHint};
use crate::Float;

impl<T: Float> BoucWen<T> {
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
    pub(super) fn step_sensitive(&mut self, z: T, dir: i64, sign: T) -> Option<SensitiveStep<T>> {
        let Evaluation::Sensitive(flow, hint) = &mut self.evaluation else {
            return None;
        };
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
}

/// `A(σ) = Σ_θ ∂G(σ)/∂θ dθ` over `θ = (α, β, γ, n)` with derivative parts
/// `d` (0 unless `seeded`).
#[inline(always)]
pub(super) fn flow_part<T: Float>(dp: [f64; 4], d: &[T; 4], seeded: bool) -> T {
    if !seeded {
        return T::zero();
    }
    dp.iter()
        .zip(d)
        .fold(T::zero(), |acc, (&j, &dt)| acc + dt.mul_const(j))
}

/// The state on a tabulated branch over dual numbers at the flow point
/// `p`, `g = G + f(G) (carry + sgn(ż) dz) + A(σ)` (see
/// [`BoucWen::step_sensitive`]); one function for `step` and the batch loop,
/// so that both give the same bits.
#[inline(always)]
pub(super) fn sensitive_state<T: Float>(
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

/// Samples whose flow points the batch loop of a tabulated branch over
/// dual numbers looks up at once ([`SensitiveFlow::lookup_run`]).
const AHEAD: usize = 32;

/// The flow points of the batch loop along a tabulated branch over dual
/// numbers, looked up [`AHEAD`] samples at a time while the input keeps its
/// direction (as `run_branch` goes on), so that their rates' `|g|^n`
/// overlap; the same points as one lookup per sample.
pub(super) struct Lookahead<T> {
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
    pub(super) fn new(position: f64, sign: T, z_a: T, first: usize) -> Self {
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
    pub(super) fn next(
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
        self.points
            .get(k - self.from)
            .filter(|_| k < self.from + self.found)
    }
}
