//! The Krasnosel'skii-Pokrovskii operator: a weighted bank of continuous
//! relays (KP kernels) on a grid of thresholds.

use crate::{check, declare_params, Error, Float, Result, StepLaw, Stepped, Trial};

declare_params! {
    /// Parameters of the [`KrasnoselskiiPokrovskii`] operator.
    pub struct KrasnoselskiiPokrovskiiParams<T> {
        /// Threshold grid `t_0 < t_1 < … < t_{m−1}` (at least one node).
        t: Vec<T> => Real = [-1.0, -0.3, 0.4, 1.0],
        /// Kernel weights `μ_ij` (any sign), one per pair `j ≤ i` of
        /// nodes, row by row: `mu[i (i + 1)/2 + j]` weighs the kernel that
        /// switches up at `t_i` and down at `t_j` (`m (m + 1)/2` entries).
        mu: Vec<T> => Real = [0.1, 0.2, 0.1, 0.05, 0.2, 0.1, 0.05, 0.1, 0.2, 0.3],
        /// Ridge width `a > 0`: a kernel rises from −1 to +1 over
        /// `[t_i, t_i + a]` and falls over `[t_j − a, t_j]`.
        a: T => Positive = 0.25,
    }
    check = KrasnoselskiiPokrovskiiParams::grid;
    law: "krasnoselskii_pokrovskii", "y = Σ_{j≤i} μ_ij k_ij[x], k_ij = max(R_up(x − t_i), min(R_down(x − t_j), k_ij⁻)), R_up(u) = clamp(2u/a − 1, −1, 1), R_down(u) = clamp(2u/a + 1, −1, 1), from k = −1";
}

impl<T: Float> KrasnoselskiiPokrovskiiParams<T> {
    /// A strictly increasing, finite grid of at least one node, and one
    /// weight per pair `j ≤ i`.
    fn grid(&self) -> Result<()> {
        let m = self.t.len();
        if m == 0 {
            return Err(Error::InvalidParameter {
                name: "t".into(),
                value: 0.0,
                reason: "needs at least one threshold",
            });
        }
        for (i, w) in self.t.windows(2).enumerate() {
            if let [lo, hi] = w {
                if hi <= lo {
                    return Err(check::invalid(
                        &format!("t[{}]", i + 1),
                        *hi,
                        "thresholds must be strictly increasing",
                    ));
                }
            }
        }
        if self.mu.len() != m * (m + 1) / 2 {
            return Err(Error::InvalidParameter {
                name: "mu".into(),
                value: self.mu.len() as f64,
                reason: "needs one weight per pair j ≤ i of thresholds: m (m + 1)/2",
            });
        }
        Ok(())
    }

    /// The kernels in weight order, with their up and down thresholds.
    fn kernels(&self) -> impl Iterator<Item = (T, T, T)> + '_ {
        let t = &self.t;
        t.iter()
            .enumerate()
            .flat_map(move |(i, &up)| t.iter().take(i + 1).map(move |&down| (up, down)))
            .zip(&self.mu)
            .map(|((up, down), &mu)| (mu, up, down))
    }
}

/// The Krasnosel'skii-Pokrovskii operator (Krasnosel'skii & Pokrovskii
/// 1989; as a bank, Banks, Kurdila & Webb 1997): continuous relays `k_ij`,
/// each switching up along the ridge `R_up(x − t_i)` and down along
/// `R_down(x − t_j)` (`t_j ≤ t_i`),
///
/// `k_ij = max(R_up(x − t_i), min(R_down(x − t_j), k_ij⁻))`,
/// `R_up(u) = clamp(2u/a − 1, −1, 1)`,  `R_down(u) = clamp(2u/a + 1, −1, 1)`,
///
/// weighted by a discrete density, `y = Σ_{j≤i} μ_ij k_ij[x]`, from every
/// kernel at −1 (as if the input came from −∞). Unlike the Preisach relays
/// it is continuous: Lipschitz in the input with the constant
/// `(2/a) Σ |μ_ij|`, tending to the relay bank as `a → 0`. Like them it
/// is rate-independent and has the wiping-out property: an input maximum
/// beyond the earlier ones erases them (and the minima between), and so
/// does a minimum below the earlier ones. The tangent is
/// `Σ μ_ij dk_ij/dx`, `2/a` for a kernel on a ridge's slope, else 0.
///
/// ```
/// use hysteron_operators::{KrasnoselskiiPokrovskii, KrasnoselskiiPokrovskiiParams, Operator};
/// let p = KrasnoselskiiPokrovskiiParams { t: vec![0.0], mu: vec![1.0], a: 0.5 };
/// let mut kp = KrasnoselskiiPokrovskii::from_params(p).unwrap();
/// // up the ridge over [0, 0.5], held on the way back until 0, down over [−0.5, 0]
/// let y = kp.run(&[0.25, 1.0, 0.1, -0.25, -1.0]).unwrap();
/// assert_eq!(y, vec![0.0, 1.0, 1.0, 0.0, -1.0]);
/// ```
///
/// Reference: M. A. Krasnosel'skii and A. V. Pokrovskii, *Systems with
/// Hysteresis*, Springer (1989); H. T. Banks, A. J. Kurdila and G. Webb,
/// "Identification of hysteretic control influence operators representing
/// smart actuators, Part I", Math. Probl. Eng. 3 (1997) 287–328.
pub type KrasnoselskiiPokrovskii<T> = Stepped<KrasnoselskiiPokrovskiiParams<T>, T>;

impl<T: Float> StepLaw<T> for KrasnoselskiiPokrovskiiParams<T> {
    /// The kernels' values, in weight order.
    type State = Vec<T>;
    // At an unchanged input every clamp leaves its kernel where it is.
    const RESTS_WHEN_HELD: bool = true;

    fn initial(&self) -> Vec<T> {
        vec![-T::one(); self.mu.len()]
    }

    fn step(&self, s: &Vec<T>, x: T) -> Result<(Vec<T>, Trial<T>)> {
        let (one, two) = (T::one(), T::lit(2.0));
        let slope = two / self.a;
        let mut next = Vec::with_capacity(s.len());
        let (mut output, mut tangent) = (T::zero(), T::zero());
        for ((mu, up, down), &k) in self.kernels().zip(s) {
            let rise = slope * (x - up) - one;
            let fall = slope * (x - down) + one;
            let (r_up, r_down) = (rise.max(-one).min(one), fall.max(-one).min(one));
            // on a ridge's slope, the kernel follows it
            let (v, d) = if r_up >= k && rise > -one && rise < one {
                (r_up, slope)
            } else if r_down <= k && fall > -one && fall < one {
                (r_down, slope)
            } else {
                (r_up.max(r_down.min(k)), T::zero())
            };
            output = output + mu * v;
            tangent = tangent + mu * d;
            next.push(v);
        }
        Ok((next, Trial { output, tangent }))
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::indexing_slicing)]
    use super::*;
    use crate::test_support::{refinement_difference, rejected_field};
    use crate::Operator;

    fn params() -> KrasnoselskiiPokrovskiiParams<f64> {
        KrasnoselskiiPokrovskiiParams::example()
    }

    use crate::ParamSet;

    fn ramps(corners: &[f64], step: f64) -> Vec<f64> {
        let mut x = Vec::new();
        for w in corners.windows(2) {
            let n = ((w[1] - w[0]).abs() / step).ceil().max(1.0) as usize;
            x.extend((1..=n).map(|i| w[0] + (w[1] - w[0]) * i as f64 / n as f64));
        }
        x
    }

    /// A new maximum beyond the earlier ones erases them and the minima in
    /// between: the output from then on is the one without them, bit for
    /// bit; likewise a new minimum.
    #[test]
    fn wiping_out() {
        let run = |corners: &[f64]| {
            let x = ramps(corners, 0.01);
            let y = KrasnoselskiiPokrovskii::from_params(params())
                .unwrap()
                .run(&x)
                .unwrap();
            (x, y)
        };
        let tail = [1.2, -0.1, 0.7, -1.3, 0.2];
        let with = [&[0.0, 0.9, -0.2, 0.6, -0.1][..], &tail].concat();
        let without = [&[0.0][..], &tail].concat();
        let (xa, ya) = run(&with);
        let (xb, yb) = run(&without);
        // the samples from the new maximum 1.2 on
        let from_a = xa.iter().position(|&v| v == 1.2).unwrap();
        let from_b = xb.iter().position(|&v| v == 1.2).unwrap();
        assert_eq!(ya[from_a..], yb[from_b..]);
    }

    /// Lipschitz: from any state, `|Δy| ≤ (2/a) Σ|μ| |Δx|`.
    #[test]
    fn continuous_in_the_input() {
        let p = params();
        let lip = 2.0 / p.a * p.mu.iter().map(|m| m.abs()).sum::<f64>();
        let mut op = KrasnoselskiiPokrovskii::from_params(p).unwrap();
        for &x in &ramps(&[0.0, 1.5, -0.4, 0.8, -1.5, 0.3], 0.013) {
            let y = op.trial(x).unwrap().output;
            for dx in [1e-3, -1e-3, 0.05, -0.05, 0.4] {
                let z = op.trial(x + dx).unwrap().output;
                assert!(
                    (z - y).abs() <= lip * dx.abs() * (1.0 + 1e-12),
                    "x = {x}, dx = {dx}"
                );
            }
            op.trial(x).unwrap();
            op.commit();
        }
    }

    /// A kernel with `a → 0` is a relay; with its thresholds one ridge
    /// width apart its loop is the relay's widened by `a`.
    #[test]
    fn one_kernel_is_a_continuous_relay() {
        let p = KrasnoselskiiPokrovskiiParams {
            t: vec![-0.5, 0.5],
            mu: vec![0.0, 1.0, 0.0],
            a: 1e-9,
        };
        let y = KrasnoselskiiPokrovskii::from_params(p)
            .unwrap()
            .run(&[0.4, 0.6, -0.4, -0.6])
            .unwrap();
        assert_eq!(y, vec![-1.0, 1.0, 1.0, -1.0]);
    }

    /// Rate-independent: refining the sampling does not move the output
    /// at the shared samples beyond rounding.
    #[test]
    fn refining_the_sampling_changes_the_output_by_rounding_only() {
        let op = KrasnoselskiiPokrovskii::from_params(params()).unwrap();
        let coarse = ramps(&[0.0, 1.3, -0.7, 0.9, -1.4, 0.5], 0.05);
        let (i, d) = refinement_difference(&op, &coarse, 7);
        assert!(d < 1e-14, "sample {i}: {d:e}");
    }

    #[test]
    fn malformed_grids_are_typed_errors() {
        let grid = |t: Vec<f64>, mu: Vec<f64>| KrasnoselskiiPokrovskiiParams { t, mu, a: 1.0 };
        for (p, field) in [
            (grid(vec![0.0, 0.0], vec![1.0; 3]), "t[1]"),
            (grid(vec![0.0, 1.0], vec![1.0; 2]), "mu"),
            (grid(vec![], vec![]), "t"),
            (KrasnoselskiiPokrovskiiParams { a: 0.0, ..params() }, "a"),
            (grid(vec![f64::NAN], vec![1.0]), "t[0]"),
        ] {
            assert_eq!(
                rejected_field(KrasnoselskiiPokrovskii::from_params(p)),
                field
            );
        }
    }
}
