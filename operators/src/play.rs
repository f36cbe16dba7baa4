//! The play operator (backlash).

use crate::lanes::{lanes_of, LaneLaw, WIDTH};
use crate::{declare_params, Error, Float, Result, StepLaw, Stepped, Trial};

declare_params! {
    /// Parameters of the [`Play`] operator.
    pub struct PlayParams<T>: Copy {
        /// Threshold (half the backlash gap) `r ≥ 0`.
        r: T => NonNegative = 0.5,
        /// Output at input `x = 0` before the first sample (default 0).
        #[serde(default)]
        y0: T => Real = 0.2,
    }
    law: "play", "y_k = max(x_k − r, min(x_k + r, y_{k−1})), from y0";
}

/// Play (backlash) operator with threshold `r`:
///
/// `y_k = max(x_k − r, min(x_k + r, y_{k−1}))`,
///
/// starting from `y0` (so the first output is `y0` clipped into
/// `[x_1 − r, x_1 + r]`). Rate-independent, `|Δy| ≤ |Δx|`, and
/// `play_0 = identity`. Tangent: 1 while the input drags the output, 0 inside
/// the gap.
///
/// ```
/// use hysteron_operators::{Operator, Play};
/// let mut p = Play::new(1.0_f64).unwrap();
/// assert_eq!(p.run(&[2.0, 1.5, 0.0, -1.0]).unwrap(), vec![1.0, 1.0, 1.0, 0.0]);
/// ```
pub type Play<T> = Stepped<PlayParams<T>, T>;

/// One play step: `max(x − r, min(x + r, y_prev))`.
///
/// Written as compare-and-select (inputs are finite, so NaN handling is not
/// needed), which the compiler turns into vector min/max in batch loops.
#[inline(always)]
pub fn play_step<T: Float>(r: T, y_prev: T, x: T) -> T {
    let (lo, hi) = (x - r, x + r);
    let clipped = if y_prev < hi { y_prev } else { hi };
    if clipped > lo {
        clipped
    } else {
        lo
    }
}

/// Eight plays with one input: the thresholds and outputs lane by lane.
pub struct PlayLanes {
    r: [f64; WIDTH],
    y: [f64; WIDTH],
}

/// [`play_step`] in every lane.
impl LaneLaw for PlayParams<f64> {
    fn check(&self) -> crate::Result<()> {
        self.validate()
    }

    type Block = PlayLanes;

    fn block(laws: &[Self]) -> PlayLanes {
        PlayLanes {
            r: lanes_of(laws, |p| p.r),
            y: lanes_of(laws, |p| p.y0),
        }
    }

    #[inline(always)]
    fn step_lanes(b: &mut PlayLanes, x: f64, y: &mut [f64; WIDTH]) {
        for ((out, state), &r) in y.iter_mut().zip(b.y.iter_mut()).zip(&b.r) {
            *state = play_step(r, *state, x);
            *out = *state;
        }
    }
}

/// Samples per finiteness check in [`Play::process`](Operator::process).
const BLOCK: usize = 128;

/// Whether every value is finite: `x − x` is 0 exactly for finite `x` and
/// NaN for NaN and ±∞ (no early exit, so it vectorizes to a subtraction
/// and a comparison per lane).
#[inline(always)]
#[allow(clippy::eq_op)] // x − x is the point: 0 or NaN
fn all_finite<T: Float>(v: &[T]) -> bool {
    v.iter().fold(true, |ok, &x| ok & (x - x == T::zero()))
}

/// [`play_step`] over `xs` from `y`, outputs into `ys`; returns the last
/// (the test of the inputs is left unused, and compiled away).
#[inline(always)]
fn play_run<T: Float>(r: T, y: T, xs: &[T], ys: &mut [T]) -> T {
    play_run_testing_inputs(r, y, xs, ys).0
}

/// The exponent bits of an `f64`: all set for ±∞ and NaN only.
const EXPONENT: u64 = 0x7ff0_0000_0000_0000;

/// [`play_step`] over `xs` from `y`, outputs into `ys`: the last output,
/// and whether every input is finite, tested on the inputs' bit patterns (integer operations, beside the chain's floating-point
/// ones). From a finite state an output is finite exactly where its input
/// is (`x ± r` cannot both overflow), so this is the test of the outputs.
#[inline(always)]
fn play_run_testing_inputs<T: Float>(r: T, mut y: T, xs: &[T], ys: &mut [T]) -> (T, bool) {
    let mut finite = true;
    for (&x, out) in xs.iter().zip(ys.iter_mut()) {
        y = play_step(r, y, x);
        *out = y;
        finite &= x.as_f64().to_bits() & EXPONENT != EXPONENT;
    }
    (y, finite)
}

/// `clamp(y, lo, hi)` for `lo ≤ hi`, as [`play_step`] computes it (`min`
/// with `hi` first), and in the other order (`max` with `lo` first), which
/// selects the same operand for finite values with `lo < hi` strictly.
#[inline(always)]
fn clamp_hi_first<T: Float>(y: T, lo: T, hi: T) -> T {
    let c = if y < hi { y } else { hi };
    if c > lo {
        c
    } else {
        lo
    }
}

#[inline(always)]
fn clamp_lo_first<T: Float>(y: T, lo: T, hi: T) -> T {
    let c = if y > lo { y } else { lo };
    if c < hi {
        c
    } else {
        hi
    }
}

/// [`play_run`] two samples at a time, for `r > 0`: clamping to
/// `[a₁, b₁]` and then to `[a₂, b₂]` (`a = x − r`, `b = x + r`) is one
/// clamp to `[A, B]`, the ends of the first interval clamped to the second,
/// and min/max select one of their operands, so the composition is exact.
/// The dependency chain through `y` is one clamp per two samples instead of
/// two (the play kernel of `hysteron bench`: 1.33 → 0.91–0.95 ns/sample).
/// The first sample's output and the interval are computed with the other
/// clamp order (the same values for `a < b`), which keeps the compiler from
/// packing them with the chain into one vector clamp plus shuffles.
// Hot loop, kept free of checks: `chunks_exact(2)` yields chunks of exactly
// two samples, so `[0]` and `[1]` exist.
#[allow(clippy::indexing_slicing)]
#[inline(always)]
fn play_pairs<T: Float>(r: T, mut y: T, xs: &[T], ys: &mut [T]) -> T {
    let mut xp = xs.chunks_exact(2);
    let mut yp = ys.chunks_exact_mut(2);
    for (x2, y2) in (&mut xp).zip(&mut yp) {
        let (a1, b1, a2, b2) = (x2[0] - r, x2[0] + r, x2[1] - r, x2[1] + r);
        let lo = clamp_lo_first(a1, a2, b2);
        let hi = clamp_lo_first(b1, a2, b2);
        y2[0] = clamp_lo_first(y, a1, b1);
        y = clamp_hi_first(y, lo, hi);
        y2[1] = y;
    }
    play_run(r, y, xp.remainder(), yp.into_remainder())
}

/// The tangent of one play step (1 while dragged, 0 inside the gap).
#[inline(always)]
pub fn play_tangent<T: Float>(r: T, y_prev: T, x: T) -> T {
    if x - r >= y_prev || x + r <= y_prev {
        T::one()
    } else {
        T::zero()
    }
}

impl<T: Float> Play<T> {
    /// A play with threshold `r`, starting at output 0.
    pub fn new(r: T) -> Result<Self> {
        Self::from_params(PlayParams { r, y0: T::zero() })
    }

    /// The committed output.
    pub fn output(&self) -> T {
        *self.state()
    }
}

impl<T: Float> StepLaw<T> for PlayParams<T> {
    // At an unchanged input the clamp that moves the state leaves it.
    const RESTS_WHEN_HELD: bool = true;
    type State = T;

    fn initial(&self) -> T {
        self.y0
    }

    #[inline(always)]
    fn step(&self, y: &T, x: T) -> Result<(T, Trial<T>)> {
        let r = self.r;
        let next = play_step(r, *y, x);
        Ok((
            next,
            Trial {
                output: next,
                tangent: play_tangent(r, *y, x),
            },
        ))
    }

    /// Two samples per step of the dependency chain for `r > 0` (see
    /// `play_pairs`), finiteness checked once per block of outputs; the
    /// plain chain, inputs tested as it goes, on CPUs with few
    /// floating-point pipes ([`few_float_pipes`](crate::simd::few_float_pipes)).
    /// The same outputs either way.
    fn run(&self, state: &mut T, xs: &[T], ys: &mut [T]) -> Result<()> {
        run_blocks(self.r, state, xs, ys, crate::simd::few_float_pipes())
    }
}

/// [`StepLaw::run`] of the play from `state`, by the plain chain (`chain`)
/// or in pairs. From a finite state a play step maps a finite input to a
/// finite output and a non-finite one (NaN, ±∞) to a non-finite output
/// (in the paired form too), so the hot loop needs no per-sample check:
/// each block's outputs (or inputs) are tested once, and the first
/// non-finite output names the sample.
fn run_blocks<T: Float>(r: T, state: &mut T, xs: &[T], ys: &mut [T], chain: bool) -> Result<()> {
    let mut y = *state;
    for (b, (xb, yb)) in xs.chunks(BLOCK).zip(ys.chunks_mut(BLOCK)).enumerate() {
        let start = y;
        let finite;
        (y, finite) = if chain {
            play_run_testing_inputs(r, y, xb, yb)
        } else if r > T::zero() {
            (play_pairs(r, y, xb, yb), all_finite(yb))
        } else {
            (play_run(r, y, xb, yb), all_finite(yb))
        };
        if !finite {
            let j = yb.iter().position(|v| !v.is_finite()).unwrap_or(0);
            *state = j
                .checked_sub(1)
                .and_then(|k| yb.get(k))
                .copied()
                .unwrap_or(start);
            return Err(Error::NonFiniteInput {
                value: xb.get(j).map_or(f64::NAN, |v| v.as_f64()),
            }
            .at_sample(b * BLOCK + j));
        }
    }
    *state = y;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Operator;

    /// Every sequence of 5 inputs from values that tie with the play's
    /// bounds (`±0`, `±r`, `±2r`, …) from initial states that tie too:
    /// `process`, and the run in pairs (for `r > 0`) and by the plain
    /// chain that it dispatches to, give the bits of the trial + commit
    /// loop, signed zeros included, and leave the same state.
    #[test]
    fn process_matches_steps_bitwise_on_ties() {
        for r in [0.5, 0.0, -0.0, 1e-300] {
            let alphabet = [0.0, -0.0, r, -r, 2.0 * r, -2.0 * r, 0.5 * r, 3.0];
            for y0 in [0.0, -0.0, r, -r, 0.25, -3.0] {
                let play = Play::from_params(PlayParams { r, y0 }).unwrap();
                for code in 0..alphabet.len().pow(5) {
                    let xs: Vec<f64> = (0..5)
                        .map(|k| alphabet[code / alphabet.len().pow(k) % alphabet.len()])
                        .collect();
                    let mut slow = play.clone();
                    let want: Vec<f64> = xs
                        .iter()
                        .map(|&x| {
                            let y = slow.trial(x).unwrap().output;
                            slow.commit();
                            y
                        })
                        .collect();
                    let mut fast = play.clone();
                    let mut ys = [0.0; 5];
                    fast.process(&xs, &mut ys).unwrap();
                    let mut runs = vec![(ys, fast.output())];
                    for chain in [false, true] {
                        let (mut ys, mut state) = ([0.0; 5], y0);
                        run_blocks(r, &mut state, &xs, &mut ys, chain).unwrap();
                        runs.push((ys, state));
                    }
                    for (ys, state) in runs {
                        let bits = |v: &[f64]| v.iter().map(|y| y.to_bits()).collect::<Vec<_>>();
                        assert_eq!(bits(&ys), bits(&want), "r {r:e}, y0 {y0:e}, xs {xs:?}");
                        assert_eq!(state.to_bits(), slow.output().to_bits());
                    }
                }
            }
        }
    }

    #[test]
    fn process_names_the_first_non_finite_sample_and_keeps_the_state_before_it() {
        for n in [1, 2, 3, 127, 128, 129, 255, 256, 257, 600] {
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                let mut xs: Vec<f64> = (0..700).map(|i| (i as f64 * 0.37).sin() * 3.0).collect();
                xs[n] = bad;
                xs[n + 5] = f64::NAN;
                let mut reference = Play::new(0.5).unwrap();
                let want = reference.run(&xs[..n]).unwrap();
                let mut ys = vec![0.0; xs.len()];
                let mut play = Play::new(0.5).unwrap();
                let err = play.process(&xs, &mut ys).unwrap_err();
                let mut states = vec![(err, play.output())];
                for chain in [false, true] {
                    let mut state = 0.0;
                    let err = run_blocks(0.5, &mut state, &xs, &mut ys, chain).unwrap_err();
                    states.push((err, state));
                }
                for (err, state) in states {
                    assert!(
                        matches!(err, Error::AtSample { index, .. } if index == n),
                        "{err:?}"
                    );
                    assert_eq!(state.to_bits(), want[n - 1].to_bits());
                }
            }
        }
    }
}
