//! Prandtl-Ishlinskii banks with different parameters, [`WIDTH`] instances
//! stepped together over one input.

// The lane loops index every lane array by the lane `j`, the form that
// compiles to one vector operation per line.
#![allow(clippy::needless_range_loop)]

use crate::pi_bank::{PiBankParams, LANES};
use hysteron_operators::lanes::{select, LaneLaw, WIDTH};
use hysteron_operators::{play_step, Result};

/// Eight PI banks with one input: for each play of the banks its
/// threshold, weight and output lane by lane, and the linear weight `a0`.
pub struct PiLanes {
    a0: [f64; WIDTH],
    r: Vec<[f64; WIDTH]>,
    w: Vec<[f64; WIDTH]>,
    y: Vec<[f64; WIDTH]>,
    /// The lanes whose bank has another number of plays than the first
    /// lane's: they give NaN (a failed lane).
    odd: [bool; WIDTH],
}

/// `y = a0 x + Σ_k w_k play_{r_k}[x]` ([`PiBank`](crate::PiBank)) in every
/// lane, with the bank's own arithmetic: each play's [`play_step`], and
/// the sum in eight interleaved partial sums over the whole groups of
/// eight plays, each term added by a fused multiply-add, the plays after
/// the last whole group in a running sum, and the partial sums added in
/// the bank's order. So each lane's outputs are its bank's bits, on every
/// instruction set. A bank alone steps each whole group of eight plays
/// eight per instruction and the rest one play at a time; the lanes step
/// every play eight instances per instruction, so they gain where a bank
/// has a rest (the ensembles of `hysteron-identify` take them for banks of
/// fewer than 64 plays not a multiple of eight).
///
/// # Requirements
/// Every bank of a block has the same number of plays (the structure, not
/// a parameter); a lane whose bank has another number than the first
/// lane's gives NaN (a failed lane); one whose parameters are out of their
/// domains is flagged by [`check`](LaneLaw::check).
///
/// ```
/// use hysteron_composition::{PiBank, PiBankParams};
/// use hysteron_operators::{lanes::run_lanes, Leaf, Operator};
/// let bank = |a0: f64| PiBankParams { a0, r: vec![0.0, 0.5], w: vec![1.0, 2.0], y0: vec![] };
/// let laws = vec![bank(0.1), bank(0.5), bank(0.9)];
/// let x = [1.0, 2.0, 0.0, -1.5];
/// let mut y = vec![0.0; 3 * x.len()];
/// run_lanes(&laws, &x, &mut y)?;
/// assert_eq!(&y[4..8], &PiBank::from_params(bank(0.5))?.run(&x)?[..]);
/// # Ok::<(), hysteron_operators::Error>(())
/// ```
impl LaneLaw for PiBankParams<f64> {
    type Block = PiLanes;

    fn check(&self) -> Result<()> {
        self.validate()
    }

    fn block(laws: &[Self]) -> PiLanes {
        let lane = |j: usize| laws.get(j).or(laws.last());
        let m = lane(0).map_or(0, |p| p.r.len());
        let odd = core::array::from_fn(|j| lane(j).is_none_or(|p| p.r.len() != m));
        // (a lane of another length, or a `y0` not of the bank's length,
        // takes zeros: a refused or odd lane's outputs are not read)
        let field = |f: fn(&Self) -> &Vec<f64>, k: usize| -> [f64; WIDTH] {
            core::array::from_fn(|j| lane(j).and_then(|p| f(p).get(k)).copied().unwrap_or(0.0))
        };
        PiLanes {
            a0: core::array::from_fn(|j| lane(j).map_or(0.0, |p| p.a0)),
            r: (0..m).map(|k| field(|p| &p.r, k)).collect(),
            w: (0..m).map(|k| field(|p| &p.w, k)).collect(),
            y: (0..m).map(|k| field(|p| &p.y0, k)).collect(),
            odd,
        }
    }

    // `j < WIDTH` and `l < LANES` index the lane arrays and partial sums.
    #[allow(clippy::indexing_slicing)]
    #[inline(always)]
    fn step_lanes(b: &mut PiLanes, x: f64, out: &mut [f64; WIDTH]) {
        // (the three have the banks' length, built so; `whole` is within it)
        let whole = b.y.len().min(b.r.len()).min(b.w.len()) / LANES * LANES;
        let (y, y_rest) = b.y.split_at_mut(whole);
        let (r, r_rest) = b.r.split_at(whole);
        let (w, w_rest) = b.w.split_at(whole);
        let mut acc = [[0.0; WIDTH]; LANES];
        let groups = y
            .chunks_exact_mut(LANES)
            .zip(r.chunks_exact(LANES))
            .zip(w.chunks_exact(LANES));
        for ((y, r), w) in groups {
            for (((y, r), w), acc) in y.iter_mut().zip(r).zip(w).zip(&mut acc) {
                play_and_add(y, r, w, acc, x);
            }
        }
        let mut tail = [0.0; WIDTH];
        for ((y, r), w) in y_rest.iter_mut().zip(r_rest).zip(w_rest) {
            play_and_add(y, r, w, &mut tail, x);
        }
        for j in 0..WIDTH {
            let a = |l: usize| acc[l][j];
            let sum = ((a(0) + a(1)) + (a(2) + a(3))) + ((a(4) + a(5)) + (a(6) + a(7))) + tail[j];
            out[j] = select(b.odd[j], f64::NAN, b.a0[j] * x + sum);
        }
    }
}

/// One play of the banks in every lane, [`play_step`] to `x`, and its
/// weighted output added to the lane's sum `acc` by a fused multiply-add.
// `j < WIDTH`, the length of every array.
#[allow(clippy::indexing_slicing)]
#[inline(always)]
fn play_and_add(
    y: &mut [f64; WIDTH],
    r: &[f64; WIDTH],
    w: &[f64; WIDTH],
    acc: &mut [f64; WIDTH],
    x: f64,
) {
    for j in 0..WIDTH {
        y[j] = play_step(r[j], y[j], x);
        acc[j] = w[j].mul_add(y[j], acc[j]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::PiBank;
    use hysteron_operators::lanes::{check_each_alone, run_lanes};
    use hysteron_operators::Operator;

    /// A walk with reversals, holds, and large and tiny steps.
    fn walk(n: usize) -> Vec<f64> {
        let mut x = 0.0;
        let mut seed = 7_u64;
        (0..n)
            .map(|i| {
                seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
                let u = (seed >> 11) as f64 / (1u64 << 53) as f64;
                if i % 13 != 5 {
                    x += (u - 0.5) * if i % 7 == 0 { 3.0 } else { 2e-3 };
                }
                x
            })
            .collect()
    }

    /// Instance `i` of a bank of `m` plays: thresholds, weights (some
    /// negative) and initial outputs that differ between instances (no
    /// `y0` for every third).
    fn bank(i: usize, m: usize) -> PiBankParams<f64> {
        let f = i as f64;
        PiBankParams {
            a0: 0.3 - 0.07 * f,
            r: (0..m).map(|k| 0.05 * k as f64 * (1.0 + 0.1 * f)).collect(),
            w: (0..m)
                .map(|k| (1.0 + 0.2 * f) / (1.0 + k as f64) * if k % 5 == 4 { -0.5 } else { 1.0 })
                .collect(),
            y0: if i.is_multiple_of(3) {
                Vec::new()
            } else {
                (0..m).map(|k| 0.01 * (k as f64 - f)).collect()
            },
        }
    }

    fn alone(law: &PiBankParams<f64>, x: &[f64]) -> Result<Vec<f64>> {
        PiBank::from_params(law.clone())?.run(x)
    }

    /// Thirteen banks (a full block and a part), with no plays, fewer than
    /// a group of eight, whole groups, and groups and a rest: each lane
    /// gives its bank's bits.
    #[test]
    fn lanes_are_each_bank_alone() {
        let x = walk(1500);
        for m in [0, 1, 3, 8, 13, 16, 21] {
            let laws: Vec<_> = (0..13).map(|i| bank(i, m)).collect();
            if let Err(e) = check_each_alone(&laws, &x, |law| alone(law, &x)) {
                panic!("{m} plays: {e}");
            }
        }
    }

    /// A bank with a negative threshold is flagged with a NaN row, one whose
    /// output overflows is flagged as it fails alone, and the others keep
    /// their bits.
    #[test]
    fn refused_and_failing_banks_are_flagged() {
        let x = walk(400);
        let mut laws: Vec<_> = (0..10).map(|i| bank(i, 5)).collect();
        laws[2].r[1] = -0.1;
        laws[6].w[3] = 1e308;
        check_each_alone(&laws, &x, |law| alone(law, &x)).unwrap();
        let mut out = vec![0.0; laws.len() * x.len()];
        assert_eq!(run_lanes(&laws, &x, &mut out).unwrap(), vec![2, 6]);
        assert!(out[2 * x.len()..3 * x.len()].iter().all(|v| v.is_nan()));
    }

    /// A bank with another number of plays than its block's first gives
    /// NaN and is flagged (the ensemble runs it alone for its error).
    #[test]
    fn a_bank_of_another_length_is_flagged() {
        let x = walk(50);
        let laws = vec![bank(0, 4), bank(1, 4), bank(2, 5), bank(3, 4)];
        let mut out = vec![0.0; laws.len() * x.len()];
        assert_eq!(run_lanes(&laws, &x, &mut out).unwrap(), vec![2]);
        for i in [0, 1, 3] {
            let want = alone(&laws[i], &x).unwrap();
            assert_eq!(&out[i * x.len()..(i + 1) * x.len()], &want[..]);
        }
    }
}
