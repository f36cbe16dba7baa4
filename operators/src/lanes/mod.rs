//! Many instances of one leaf, with different parameters, stepped together
//! over one input: eight instances per block, each state variable held
//! lane by lane, so that a block's step is one vector instruction per
//! operation where the CPU has AVX-512 (two with AVX2).
//!
//! A kernel does the same operations in the same order as the leaf's own
//! step, with a fused multiply-add exactly where the step has one (the PI
//! bank's sums; the compiler never fuses a product and a sum on its own),
//! so every instance's outputs are the bits it gives alone; the contract
//! test checks it for every kernel on every instruction set
//! ([`Isa::detect`], whose AVX2 includes FMA).

mod transpose;

use crate::simd::Isa;
use crate::{Error, Result};
use transpose::{Columns, Tile};

/// Instances per block: the `f64` lanes of an AVX-512 register.
pub const WIDTH: usize = 8;

/// The parameters of a leaf with a kernel that steps [`WIDTH`] instances
/// together over one input (a [`StepLaw`](crate::StepLaw), or a leaf with its own batch
/// loop such as the Bouc-Wen spring).
///
/// # Requirements
/// * [`step_lanes`](LaneLaw::step_lanes) gives lane `j` the output that
///   the leaf built from instance `j`'s parameters gives at that sample
///   from its own state ([`StepLaw::step`](crate::StepLaw::step) for a step law), bit for bit,
///   for every finite input;
/// * a block made of fewer than [`WIDTH`] instances repeats the last one in
///   the unused lanes (their outputs are not read);
/// * [`check`](LaneLaw::check) refuses the parameters the leaf refuses
///   (their lanes' outputs are not read).
pub trait LaneLaw: Sized {
    /// The parameters and states of one block of instances, lane by lane.
    type Block;

    /// Whether the leaf accepts these parameters (its `validate`):
    /// [`run_lanes`] flags an instance it refuses and clears its row, as
    /// that instance fails alone.
    ///
    /// # Errors
    /// The leaf's error for the first parameter out of its domain.
    fn check(&self) -> Result<()>;

    /// The block of `laws` (at most [`WIDTH`], at least one) in their
    /// initial states.
    fn block(laws: &[Self]) -> Self::Block;

    /// Advances every lane to the input `x`, writing lane `j`'s output to
    /// `y[j]`.
    fn step_lanes(block: &mut Self::Block, x: f64, y: &mut [f64; WIDTH]);

    /// How many of the samples `xs`, from the block's state now, every
    /// lane steps the same way, each sample independently of the others
    /// (for a hysteresis law: no lane reverses), so that
    /// [`go_on`](LaneLaw::go_on) can step them together; 0 where none (the
    /// default).
    #[inline(always)]
    fn run_length(_block: &Self::Block, _xs: &[f64]) -> usize {
        0
    }

    /// Steps the samples `xs`, a run of [`run_length`](LaneLaw::run_length),
    /// writing lane `j`'s output at `xs[k]` to `ys[k][j]`, the bits of
    /// [`step_lanes`](LaneLaw::step_lanes) sample by sample. Called only
    /// where `run_length` gave at least `xs.len()`.
    #[inline(always)]
    fn go_on(block: &mut Self::Block, xs: &[f64], ys: &mut [[f64; WIDTH]]) {
        for (y, &x) in ys.iter_mut().zip(xs) {
            Self::step_lanes(block, x, y);
        }
    }

    /// Advances every lane over the [`TILE`] inputs `xs`, writing lane
    /// `j`'s output at `xs[k]` to `ys[k][j]`: in runs by
    /// [`go_on`](LaneLaw::go_on) (the samples of a run without the checks
    /// and state updates between them, so that the processor overlaps
    /// them), and any sample where no run starts by
    /// [`step_lanes`](LaneLaw::step_lanes).
    /// The default is [`step_tile_in_runs`].
    #[inline(always)]
    fn step_tile(block: &mut Self::Block, xs: &[f64; TILE], ys: &mut [[f64; WIDTH]; TILE]) {
        step_tile_in_runs::<Self>(block, xs, ys);
    }
}

/// [`LaneLaw::step_tile`] in runs: each run of
/// [`run_length`](LaneLaw::run_length) by [`go_on`](LaneLaw::go_on), and
/// any sample where no run starts by [`step_lanes`](LaneLaw::step_lanes).
#[inline(always)]
pub fn step_tile_in_runs<L: LaneLaw>(
    block: &mut L::Block,
    xs: &[f64; TILE],
    ys: &mut [[f64; WIDTH]; TILE],
) {
    let (mut xs, mut ys) = (&xs[..], &mut ys[..]);
    while !xs.is_empty() {
        // (where no run starts, one sample by `step_lanes`)
        let run = L::run_length(block, xs);
        let (Some((run_xs, xs_rest)), Some((run_ys, ys_rest))) = (
            xs.split_at_checked(run.max(1)),
            ys.split_at_mut_checked(run.max(1)),
        ) else {
            break;
        };
        if run > 0 {
            L::go_on(block, run_xs, run_ys);
        } else if let (Some(&x), Some(y)) = (run_xs.first(), run_ys.first_mut()) {
            L::step_lanes(block, x, y);
        }
        (xs, ys) = (xs_rest, ys_rest);
    }
}

/// `a` where `take_a`, else `b`, bit for bit, as a mask blend: in a loop
/// over the lanes the compiler keeps it in vector registers, where a plain
/// `if` between two loaded or computed values becomes a branch or a load
/// per lane.
///
/// ```
/// use hysteron_operators::lanes::select;
/// assert_eq!(select(true, 1.0, f64::NAN), 1.0);
/// assert!(select(false, 1.0, f64::NAN).is_nan());
/// ```
#[inline(always)]
pub fn select(take_a: bool, a: f64, b: f64) -> f64 {
    let mask = u64::from(take_a).wrapping_neg();
    f64::from_bits((a.to_bits() & mask) | (b.to_bits() & !mask))
}

/// The lanes of a block, from `laws` (one to [`WIDTH`] of them) with the
/// last repeated: `lane(laws, j)` is instance `min(j, len − 1)`.
///
/// ```
/// use hysteron_operators::lanes::lanes_of;
/// assert_eq!(lanes_of(&[1.0, 2.0, 3.0], |v| *v), [1.0, 2.0, 3.0, 3.0, 3.0, 3.0, 3.0, 3.0]);
/// ```
pub fn lanes_of<L>(laws: &[L], field: impl Fn(&L) -> f64) -> [f64; WIDTH] {
    let mut lanes = [0.0; WIDTH];
    let mut last = 0.0;
    for (j, lane) in lanes.iter_mut().enumerate() {
        if let Some(law) = laws.get(j) {
            last = field(law);
        }
        *lane = last;
    }
    lanes
}

/// Runs every instance of `laws` from its initial state over `xs`, writing
/// instance `i`'s outputs to `out[i · xs.len() ..][.. xs.len()]` (one row
/// per instance); returns the instances whose parameters the leaf refuses
/// ([`LaneLaw::check`], their rows NaN) and those whose outputs are not
/// all finite (those the leaf's own run refuses at a sample), in order.
///
/// # Errors
/// * [`Error::NonFiniteInput`] ([`Error::AtSample`]) at the first sample of `xs` that is not
///   finite (every instance would refuse it);
/// * [`Error::LengthMismatch`] when `out` does not hold `laws.len() ·
///   xs.len()` values.
///
/// ```
/// use hysteron_operators::{lanes::run_lanes, Operator, Play, PlayParams};
/// let laws: Vec<PlayParams<f64>> =
///     [0.1, 0.5, 1.0].iter().map(|&r| PlayParams { r, y0: 0.0 }).collect();
/// let x = [1.0, 2.0, 0.0];
/// let mut out = vec![0.0; 9];
/// run_lanes(&laws, &x, &mut out)?;
/// let alone = Play::new(0.5)?.run(&x)?;
/// assert_eq!(&out[3..6], &alone[..]);
/// # Ok::<(), hysteron_operators::Error>(())
/// ```
pub fn run_lanes<L: LaneLaw>(laws: &[L], xs: &[f64], out: &mut [f64]) -> Result<Vec<usize>> {
    if out.len() != laws.len() * xs.len() {
        return Err(Error::LengthMismatch {
            input: laws.len() * xs.len(),
            output: out.len(),
        });
    }
    if let Some(i) = xs.iter().position(|x| !x.is_finite()) {
        let value = xs.get(i).copied().unwrap_or(f64::NAN);
        return Err(Error::NonFiniteInput { value }.at_sample(i));
    }
    let mut failed = Vec::new();
    if xs.is_empty() {
        return Ok(failed);
    }
    for (b, (block, rows)) in laws
        .chunks(WIDTH)
        .zip(out.chunks_mut(WIDTH * xs.len()))
        .enumerate()
    {
        let finite = run_block(block, xs, rows);
        let lanes = finite.iter().take(block.len()).enumerate();
        failed.extend(lanes.filter(|(_, ok)| !**ok).map(|(j, _)| b * WIDTH + j));
        for (j, (law, row)) in block.iter().zip(rows.chunks_mut(xs.len())).enumerate() {
            if law.check().is_err() {
                row.fill(f64::NAN);
                failed.push(b * WIDTH + j);
            }
        }
    }
    failed.sort_unstable();
    failed.dedup();
    Ok(failed)
}

/// The contract of a lane kernel, for its tests: runs `laws` in lanes
/// over `x` ([`run_lanes`]) and checks every instance's row against
/// `alone(law)`, the instance's own run from its initial state: bit for
/// bit where that run succeeds, and the instance flagged where it fails.
///
/// # Errors
/// The first instance that breaks the contract, described (its index, and
/// the sample and both values, or how its flag disagrees), or the error
/// of [`run_lanes`].
///
/// ```
/// use hysteron_operators::{lanes::check_each_alone, Leaf, Operator, Play, PlayParams};
/// let laws: Vec<PlayParams<f64>> =
///     [0.1, 0.5, 1.0].iter().map(|&r| PlayParams { r, y0: 0.0 }).collect();
/// let x = [1.0, 2.0, 0.0, -1.5];
/// check_each_alone(&laws, &x, |law| Play::from_params(*law)?.run(&x))?;
/// # Ok::<(), String>(())
/// ```
pub fn check_each_alone<L: LaneLaw>(
    laws: &[L],
    x: &[f64],
    alone: impl Fn(&L) -> Result<Vec<f64>>,
) -> core::result::Result<(), String> {
    let mut out = vec![0.0; laws.len() * x.len()];
    let failed = run_lanes(laws, x, &mut out).map_err(|e| e.to_string())?;
    for (i, (law, row)) in laws.iter().zip(out.chunks(x.len().max(1))).enumerate() {
        match (alone(law), failed.contains(&i)) {
            (Ok(y), false) => {
                let differs = y
                    .iter()
                    .zip(row)
                    .enumerate()
                    .find(|(_, (a, b))| a.to_bits() != b.to_bits());
                if let Some((k, (a, b))) = differs {
                    return Err(format!("instance {i}, sample {k}: {a} alone, {b} in lanes"));
                }
            }
            (Ok(_), true) => return Err(format!("instance {i} runs alone but is flagged")),
            (Err(e), false) => {
                return Err(format!("instance {i} fails alone ({e}) but is not flagged"))
            }
            (Err(_), true) => {}
        }
    }
    Ok(())
}

/// One block over `xs` into its rows, on the widest instruction set found;
/// whether each lane's outputs are all finite.
fn run_block<L: LaneLaw>(laws: &[L], xs: &[f64], rows: &mut [f64]) -> [bool; WIDTH] {
    #[cfg(target_arch = "x86_64")]
    match Isa::detect() {
        // SAFETY: the instruction set was detected on this CPU.
        Some(Isa::Avx512) => return unsafe { run_block_avx512(laws, xs, rows) },
        // SAFETY: as above.
        Some(Isa::Avx2) => return unsafe { run_block_avx2(laws, xs, rows) },
        None => {}
    }
    run_block_portable(laws, xs, rows, transpose::portable)
}

/// Samples per tile: a block's outputs for [`TILE`] samples are kept lane
/// by lane, transposed, and written row by row, [`TILE`] contiguous values
/// per instance.
pub const TILE: usize = 8;

/// Whether every value is finite (`v − v` is 0 exactly for finite `v`,
/// NaN otherwise; no early exit, so it vectorises).
#[inline(always)]
#[allow(clippy::eq_op)]
fn all_finite(v: &[f64]) -> bool {
    v.iter().fold(true, |ok, &v| ok & (v - v == 0.0))
}

/// [`run_block`] on whatever instruction set it is compiled for: full
/// tiles with constant trip counts (so that the tile stays in registers
/// and its transpose is a few shuffles), then the remainder.
// `rows` holds `laws.len()` rows of `xs.len()` values (from `run_lanes`);
// each tile's range `start..start + n` lies within a row.
#[allow(clippy::indexing_slicing)]
#[inline(always)]
fn run_block_portable<L: LaneLaw>(
    laws: &[L],
    xs: &[f64],
    rows: &mut [f64],
    transpose: impl Fn(&Tile) -> Columns,
) -> [bool; WIDTH] {
    let t = xs.len();
    let mut block = L::block(laws);
    let mut finite = [true; WIDTH];
    let mut store = |start: usize, n: usize, tile: &Tile| {
        let cols = transpose(tile);
        for ((row, col), ok) in rows.chunks_exact_mut(t).zip(&cols).zip(&mut finite) {
            let col = &col[..n];
            *ok &= all_finite(col);
            row[start..start + n].copy_from_slice(col);
        }
    };
    let mut tiles = xs.chunks_exact(TILE);
    for (c, chunk) in (&mut tiles).enumerate() {
        let mut tile = [[0.0; WIDTH]; TILE];
        if let Ok(chunk) = <&[f64; TILE]>::try_from(chunk) {
            L::step_tile(&mut block, chunk, &mut tile);
        }
        store(c * TILE, TILE, &tile);
    }
    let rest = tiles.remainder();
    if !rest.is_empty() {
        let mut tile = [[0.0; WIDTH]; TILE];
        for (y, &x) in tile.iter_mut().zip(rest) {
            L::step_lanes(&mut block, x, y);
        }
        store(t - rest.len(), rest.len(), &tile);
    }
    finite
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn run_block_avx2<L: LaneLaw>(laws: &[L], xs: &[f64], rows: &mut [f64]) -> [bool; WIDTH] {
    run_block_portable(laws, xs, rows, |t| transpose::avx2(t))
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn run_block_avx512<L: LaneLaw>(laws: &[L], xs: &[f64], rows: &mut [f64]) -> [bool; WIDTH] {
    run_block_portable(laws, xs, rows, |t| transpose::avx512(t))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Leaf, MmsParams, Operator, PlayParams, Stepped};

    /// A walk with reversals, holds (repeated samples) and large and tiny
    /// steps, the same on every run.
    fn walk(n: usize) -> Vec<f64> {
        let mut x = 0.0;
        let mut seed = 12_345_u64;
        (0..n)
            .map(|i| {
                seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
                let u = (seed >> 11) as f64 / (1u64 << 53) as f64;
                if i % 17 != 3 {
                    x += (u - 0.5) * if i % 5 == 0 { 2.0 } else { 1e-3 };
                }
                x
            })
            .collect()
    }

    /// Every instance of `laws` run in lanes gives the bits of its own run.
    /// A slow sine with holds and a small ripple: most tiles of it keep
    /// their direction, some reverse.
    fn smooth(n: usize) -> Vec<f64> {
        (0..n)
            .map(|i| {
                let t = (i - i % 7 / 5) as f64;
                2.0 * (t * 0.011).sin() + 0.05 * (t * 0.07).sin()
            })
            .collect()
    }

    fn lanes_are_each_alone<L>(laws: &[L])
    where
        L: LaneLaw + crate::StepLaw<f64> + Clone,
        Stepped<L, f64>: Leaf<f64, Params = L> + Operator<f64>,
    {
        lanes_are_each_alone_over(laws, &walk(1000));
        lanes_are_each_alone_over(laws, &smooth(1203));
    }

    fn lanes_are_each_alone_over<L>(laws: &[L], x: &[f64])
    where
        L: LaneLaw + crate::StepLaw<f64> + Clone,
        Stepped<L, f64>: Leaf<f64, Params = L> + Operator<f64>,
    {
        check_each_alone(laws, x, |law| {
            Stepped::<L, f64>::from_params(law.clone())?.run(x)
        })
        .unwrap();
    }

    /// Thirteen plays (a full block and a part), thresholds 0 to 0.6.
    #[test]
    fn play_lanes_are_each_play_alone() {
        let laws: Vec<_> = (0..13)
            .map(|i| PlayParams {
                r: 0.05 * i as f64,
                y0: 0.01 * i as f64 - 0.05,
            })
            .collect();
        lanes_are_each_alone(&laws);
    }

    /// Thirteen MMS elements with different levels, rates and preloads.
    #[test]
    fn mms_lanes_are_each_mms_alone() {
        let laws: Vec<_> = (0..13)
            .map(|i| MmsParams {
                f_c: 0.5 + 0.1 * i as f64,
                k: 2.0 + 7.0 * i as f64,
                y0: 0.3 - 0.04 * i as f64,
            })
            .collect();
        lanes_are_each_alone(&laws);
    }

    /// An instance whose parameters the leaf refuses (a negative
    /// threshold, a negative MMS stiffness) is flagged with a NaN row, as
    /// it fails alone; the others keep their bits.
    #[test]
    fn refused_parameters_are_flagged() {
        let mut plays: Vec<_> = (0..10)
            .map(|i| PlayParams {
                r: 0.1 * i as f64,
                y0: 0.0,
            })
            .collect();
        plays[9].r = -0.2;
        lanes_are_each_alone(&plays);
        let mut out = vec![0.0; 10 * 5];
        let failed = run_lanes(&plays, &[0.0, 1.0, -1.0, 2.0, 0.5], &mut out).unwrap();
        assert_eq!(failed, vec![9]);
        assert!(out[45..].iter().all(|v| v.is_nan()));
        let mms = [
            MmsParams {
                f_c: 1.0,
                k: 5.0,
                y0: 0.0,
            },
            MmsParams {
                f_c: 1.0,
                k: -5.0,
                y0: 0.0,
            },
        ];
        lanes_are_each_alone(&mms);
    }

    /// A non-finite input names its sample; a wrong buffer its lengths.
    #[test]
    fn bad_input_and_buffer_are_typed_errors() {
        let laws = [PlayParams { r: 0.1, y0: 0.0 }];
        let mut out = vec![0.0; 3];
        match run_lanes(&laws, &[0.0, f64::NAN, 1.0], &mut out) {
            Err(Error::AtSample { index: 1, source }) => {
                assert!(matches!(*source, Error::NonFiniteInput { .. }))
            }
            other => panic!("{other:?}"),
        }
        assert!(matches!(
            run_lanes(&laws, &[0.0, 1.0], &mut out),
            Err(Error::LengthMismatch {
                input: 2,
                output: 3
            })
        ));
        assert!(run_lanes(&laws, &[], &mut []).is_ok());
    }
}
