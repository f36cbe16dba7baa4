//! Modified Maxwell-slip (MMS) pre-sliding friction.

use crate::lanes::{lanes_of, select, LaneLaw, WIDTH};
use crate::{
    check_lengths, declare_params, reversal, CastScalar, Error, Float, Result, StepLaw, Stepped,
    Trial,
};

declare_params! {
    /// Parameters of the [`Mms`] friction operator.
    pub struct MmsParams<T>: Copy {
        /// Coulomb friction level `F_c > 0`.
        f_c: T => Positive = 1.5,
        /// Exponential rate (initial stiffness over `F_c`) `K > 0`, in 1/input unit.
        k: T => Positive = 30.0,
        /// Friction force at input `x = 0` before the first sample (default 0).
        /// With `|y0| ≤ F_c` the output stays in `[−F_c, F_c]`.
        #[serde(default)]
        y0: T => Real = -0.4,
    }
    law: "mms", "y = y_r + (sgn(ẋ) F_c − y_r)(1 − exp(−K |x − x_r|)), (x_r, y_r) the last reversal";
}

/// The committed state: last input and output, the last reversal point and
/// the current direction of motion (`0` before any motion).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MmsState<T> {
    x: T,
    y: T,
    x_r: T,
    y_r: T,
    dir: i8,
    /// `e^{−K |x − x_r|}` at `x` (kept so that a trial at the committed
    /// input, which the mechanical series makes at every sample where the
    /// slider rests at a stop, needs no exponential).
    decay: T,
}

/// Modified Maxwell-slip pre-sliding friction (Ruderman & Bertram 2011):
/// on each branch since the last reversal at `(x_r, y_r)`,
///
/// `y = y_r + Ω (1 − exp(−K |x − x_r|))`,  `Ω = sgn(ẋ) F_c − y_r`,
///
/// i.e. `ẏ = Ω K |ẋ| exp(−K |x − x_r|)`. Local memory only: a reversal keeps
/// just `(x_r, y_r)`. Each branch is monotone and approaches `±F_c`
/// (Coulomb saturation): after travel `d`, `|y − sgn(ẋ) F_c| ≤ 2 F_c e^{−K d}`
/// when `|y_r| ≤ F_c`. The branch is evaluated in closed form, so the
/// operator is exactly rate-independent. Tangent:
/// `dy/dx = (F_c − sgn(ẋ) y_r) K exp(−K |x − x_r|) ≥ 0`; at a standstill it
/// is the tangent of continuing in the last direction (upward before any
/// motion).
///
/// ```
/// use hysteron_operators::{Mms, Operator};
/// let mut f = Mms::new(2.0_f64, 50.0).unwrap();
/// let y = f.run(&[0.01, 0.2, 1.0]).unwrap();
/// assert!(y[0] > 0.0 && y[0] < y[1] && y[1] < y[2] && y[2] <= 2.0);
/// ```
pub type Mms<T> = Stepped<MmsParams<T>, T>;

impl<T: Float> Mms<T> {
    /// MMS friction with Coulomb level `f_c` and rate `k`, starting unloaded.
    pub fn new(f_c: T, k: T) -> Result<Self> {
        Self::from_params(MmsParams {
            f_c,
            k,
            y0: T::zero(),
        })
    }

    /// The committed friction force.
    pub fn output(&self) -> T {
        self.state().y
    }
}

impl<T: Float> MmsParams<T> {
    fn start(p: &MmsParams<T>) -> MmsState<T> {
        MmsState {
            x: T::zero(),
            y: p.y0,
            x_r: T::zero(),
            y_r: p.y0,
            dir: 0,
            decay: T::one(),
        }
    }

    /// One step from state `s` to input `x`: the new state and the tangent.
    #[inline(always)]
    fn advance(p: &MmsParams<T>, s: &MmsState<T>, x: T) -> (MmsState<T>, T) {
        let dir = reversal::travel(s.x, x, s.dir);
        let (x_r, y_r) = reversal::point(dir, s.dir, (s.x, s.y), (s.x_r, s.y_r));
        let sign = if dir < 0 { -T::one() } else { T::one() };
        let target = sign * p.f_c;
        // Standing still keeps the branch (dir = s.dir), so the committed
        // decay is the one at x.
        // (Over dual numbers the branch is evaluated there too, so that the
        // output follows the input's derivatives: the one-sided derivative
        // in the current direction, upward before any motion.)
        let (y, decay) = if x == s.x && !T::CARRIES_DERIVATIVES {
            (s.y, s.decay)
        } else {
            // 1 − e^{−a} via expm1 keeps full accuracy near a reversal.
            let rise = rise(p.k, x, x_r);
            (on_branch(rise, target, y_r), T::one() - rise)
        };
        // (F_c − sgn·y_r) K e^{−a}, with the decay applied first so that a
        // huge |Ω| times a vanishing decay gives 0, not ∞·0.
        let tangent = sign * (decay * target - decay * y_r) * p.k;
        (
            MmsState {
                x,
                y,
                x_r,
                y_r,
                dir,
                decay,
            },
            tangent,
        )
    }
}

/// Eight MMS elements with one input: the parameters, outputs and
/// reversal outputs lane by lane; the input, its direction and its last
/// reversal are the same in every lane.
pub struct MmsLanes {
    f_c: [f64; WIDTH],
    k: [f64; WIDTH],
    y: [f64; WIDTH],
    y_r: [f64; WIDTH],
    x: f64,
    x_r: f64,
    dir: i8,
}

/// The output of [`StepLaw::step`] in every lane: the same reversal test,
/// exponential (the branch-free `exp_m1` kernel, vectorised) and clamp.
impl LaneLaw for MmsParams<f64> {
    type Block = MmsLanes;

    fn check(&self) -> crate::Result<()> {
        self.validate()
    }

    fn block(laws: &[Self]) -> MmsLanes {
        let y0 = lanes_of(laws, |p| p.y0);
        MmsLanes {
            f_c: lanes_of(laws, |p| p.f_c),
            k: lanes_of(laws, |p| p.k),
            y: y0,
            y_r: y0,
            x: 0.0,
            x_r: 0.0,
            dir: 0,
        }
    }

    #[inline(always)]
    fn step_lanes(b: &mut MmsLanes, x: f64, y: &mut [f64; WIDTH]) {
        let dir = reversal::travel(b.x, x, b.dir);
        if x != b.x {
            if dir != b.dir {
                (b.x_r, b.y_r) = (b.x, b.y);
            }
            let sign = if dir < 0 { -1.0 } else { 1.0 };
            let d = (x - b.x_r).abs();
            for (((state, &y_r), &k), &f_c) in b.y.iter_mut().zip(&b.y_r).zip(&b.k).zip(&b.f_c) {
                let rise = -crate::exp_kernel::exp_m1_nonpositive(-k * d);
                *state = on_branch(rise, sign * f_c, y_r);
            }
            (b.x, b.dir) = (x, dir);
        }
        *y = b.y;
    }

    /// How many of the samples keep the direction of travel now (0 before
    /// any motion): along them every sample's outputs follow from its
    /// distance to the same reversal, independently of the others.
    #[inline(always)]
    fn run_length(b: &MmsLanes, xs: &[f64]) -> usize {
        if b.dir == 0 {
            return 0;
        }
        let mut prev = b.x;
        xs.iter()
            .take_while(|&&x| {
                let same = reversal::travel(prev, x, b.dir) == b.dir;
                prev = x;
                same
            })
            .count()
    }

    /// The operations of [`step_lanes`](LaneLaw::step_lanes) per lane; a
    /// held input gives the same distance, so the same outputs, as the
    /// step that skips it.
    #[inline(always)]
    fn go_on(b: &mut MmsLanes, xs: &[f64], ys: &mut [[f64; WIDTH]]) {
        let sign = if b.dir < 0 { -1.0 } else { 1.0 };
        for (&x, y) in xs.iter().zip(ys.iter_mut()) {
            let d = (x - b.x_r).abs();
            let lanes = b.y_r.iter().zip(&b.k).zip(&b.f_c);
            for (y, ((&y_r, &k), &f_c)) in y.iter_mut().zip(lanes) {
                let rise = -crate::exp_kernel::exp_m1_nonpositive(-k * d);
                *y = on_branch_lane(rise, sign * f_c, y_r);
            }
        }
        if let (Some(&x), Some(y)) = (xs.last(), ys.last()) {
            (b.x, b.y) = (x, *y);
        }
    }
}

/// [`on_branch`] over `f64` with its selects as mask blends, which stay in
/// vector registers across lanes; the same bits.
#[inline(always)]
fn on_branch_lane(rise: f64, target: f64, y_r: f64) -> f64 {
    let v = y_r + (target - y_r) * rise;
    let rising = y_r < target;
    let (lo, hi) = (select(rising, y_r, target), select(rising, target, y_r));
    let v = select(v < hi, v, hi);
    select(v > lo, v, lo)
}

/// Samples per block of the batch loop of [`Mms::process`].
const RUN_BLOCK: usize = 64;

/// `1 − e^{−K |x − x_r|}`, within about one ulp for every distance from
/// the reversal: see [`exp_m1_of_negative`].
#[inline(always)]
fn rise<T: Float>(k: T, x: T, x_r: T) -> T {
    -exp_m1_of_negative(-k * (x - x_r).abs())
}

/// `e^{−a} − 1` for `−a ≤ 0`, keeping full relative accuracy near the
/// reversal (`a → 0`), where `e^{−a} − 1` would cancel.
///
/// Over `f64` it is the branch-free kernel of [`crate::exp_kernel`] (within
/// about one ulp), which the batch loop runs four or eight samples per
/// instruction, so that `step` and the batch loop give the same bits.
/// Over other scalars the library's `expm1` near the reversal (`a ≤ ln 2`)
/// and `exp` beyond, where `e^{−a} < 1/2` and the subtraction adds at most
/// one rounding; over dual numbers these give the derivatives, and the
/// value is the `f64` kernel's.
#[inline(always)]
fn exp_m1_of_negative<T: Float>(minus_a: T) -> T {
    crate::exp_kernel::with_kernel_value(minus_a, crate::exp_kernel::exp_m1_nonpositive, |m| {
        if m < -T::LN_2() {
            m.exp() - T::one()
        } else {
            m.exp_m1()
        }
    })
}

/// [`exp_m1_of_negative`] of every value of `v`, in place (over `f64`
/// vectorised: [`crate::exp_kernel::exp_m1_nonpositive_in_place`]).
fn exp_m1_of_negative_in_place<T: Float>(v: &mut [T]) {
    match crate::simd::as_f64_mut(v) {
        Some(v) => crate::exp_kernel::exp_m1_nonpositive_in_place(v),
        None => {
            for a in v {
                *a = exp_m1_of_negative(*a);
            }
        }
    }
}

/// The branch value `y_r + Ω · rise`, `Ω = target − y_r`.
///
/// The branch runs from `y_r` towards `target = ±F_c`; clamping to that
/// interval keeps a rounded value from overshooting `±F_c` by an ulp (which
/// would flip the sign of `Ω` on the next branch).
#[inline(always)]
fn on_branch<T: Float>(rise: T, target: T, y_r: T) -> T {
    let v = y_r + (target - y_r) * rise;
    // Compare-and-select (all values finite): cheaper than `max`/`min`,
    // which also handle NaN.
    let (lo, hi) = if y_r < target {
        (y_r, target)
    } else {
        (target, y_r)
    };
    let v = if v < hi { v } else { hi };
    if v > lo {
        v
    } else {
        lo
    }
}

impl<T: Float> StepLaw<T> for MmsParams<T> {
    // At an unchanged input the branch and the direction stay, and the
    // output is the committed one (over dual numbers: the branch value at
    // that input, the same each time once committed).
    const RESTS_WHEN_HELD: bool = true;
    type State = MmsState<T>;

    fn initial(&self) -> MmsState<T> {
        Self::start(self)
    }

    #[inline(always)]
    fn step(&self, s: &MmsState<T>, x: T) -> Result<(MmsState<T>, Trial<T>)> {
        let (s, tangent) = Self::advance(self, s, x);
        let output = s.y;
        Ok((s, Trial { output, tangent }))
    }

    /// On the branch, `y'' = −sgn(ẋ) K y'`: the tangent decays with the
    /// branch's exponential.
    fn curvature(&self, s: &MmsState<T>) -> Option<T> {
        let sign = if s.dir < 0 { -T::one() } else { T::one() };
        let target = sign * self.f_c;
        let tangent = sign * (s.decay * target - s.decay * s.y_r) * self.k;
        Some(-sign * self.k * tangent)
    }

    /// [`step`](StepLaw::step) over `f64` on the values of the parameters
    /// and the state (over dual numbers the values are the `f64` kernel's,
    /// see `exp_m1_of_negative`).
    fn fold_probe(&self, s: &mut MmsState<T>, along: &T) -> bool {
        for v in [&mut s.x, &mut s.y, &mut s.x_r, &mut s.y_r, &mut s.decay] {
            v.fold_probe(along);
        }
        true
    }

    fn step_value(&self, s: &MmsState<T>, x: f64) -> Option<Result<Trial<f64>>> {
        let v = |t: T| t.as_f64();
        let law: MmsParams<f64> = self.cast_scalar();
        let s = MmsState {
            x: v(s.x),
            y: v(s.y),
            x_r: v(s.x_r),
            y_r: v(s.y_r),
            dir: s.dir,
            decay: v(s.decay),
        };
        Some(law.step(&s, x).map(|(_, t)| t))
    }

    /// Monotone runs with the branch constants hoisted, in blocks of three
    /// loops (see the comments); bit for bit the loop of `step`.
    // Hot loop, kept free of checks: `i < xs.len() = ys.len()` (checked once
    // on entry: `run` is public) and `i ≤ end ≤ end_max ≤ xs.len()`.
    #[allow(clippy::indexing_slicing)]
    fn run(&self, state: &mut MmsState<T>, xs: &[T], ys: &mut [T]) -> Result<()> {
        check_lengths(xs, ys)?;
        let non_finite = |x: T, i: usize| {
            Error::NonFiniteOutput {
                operator: "mms",
                input: x.as_f64(),
            }
            .at_sample(i)
        };
        let mut s = *state;
        let mut i = 0;
        while i < xs.len() {
            // The first sample of a monotone run goes through `step` (which
            // starts a new branch on a reversal) ...
            let x = xs[i];
            if !x.is_finite() {
                *state = s;
                return Err(Error::NonFiniteInput { value: x.as_f64() }.at_sample(i));
            }
            let next = Self::advance(self, &s, x).0;
            if !next.y.is_finite() {
                *state = s;
                return Err(non_finite(x, i));
            }
            s = next;
            ys[i] = s.y;
            i += 1;
            if s.dir == 0 {
                continue;
            }
            // ... the rest of the run stays on that branch: the same
            // formula as `step`, with the branch constants hoisted, and no
            // dependency from one sample to the next. It runs in blocks of
            // three loops: the exponent of every sample, `e^{−a} − 1` (over
            // `f64` four or eight samples per instruction, dispatched once
            // per block to the CPU's vector instructions), and the outputs;
            // the same operations on the same values as one loop.
            let up = s.dir > 0;
            let target = if up { self.f_c } else { -self.f_c };
            let (k, x_r, y_r) = (self.k, s.x_r, s.y_r);
            while i < xs.len() {
                // The block's part of the run: same direction (or standing
                // still); a non-finite sample ends the run here and is
                // reported above.
                let end_max = (i + RUN_BLOCK).min(xs.len());
                let (mut end, mut prev) = (i, s.x);
                while end < end_max {
                    let x = xs[end];
                    let same_run = if up { x >= prev } else { x <= prev };
                    if !(same_run && x.is_finite()) {
                        break;
                    }
                    prev = x;
                    end += 1;
                }
                let (xb, yb) = (&xs[i..end], &mut ys[i..end]);
                // −K |x − x_r|, then e^{−K |x − x_r|} − 1 = −rise.
                for (a, &x) in yb.iter_mut().zip(xb) {
                    *a = -k * (x - x_r).abs();
                }
                exp_m1_of_negative_in_place(yb);
                // Within the run a sample standing still gives the same
                // value as the committed one (the same formula at the same
                // `x`), so the loop needs no test of `x` against the
                // previous sample, nor any other branch: it vectorises.
                let (Some(&x_last), Some(&minus_rise_last)) = (xb.last(), yb.last()) else {
                    break;
                };
                for y_out in yb.iter_mut() {
                    *y_out = on_branch(-*y_out, target, y_r);
                }
                // The outputs lie between `y_r` and `±F_c`, both finite, so
                // this holds; checked anyway, after the loop.
                if let Some(j) = yb.iter().position(|y| !y.is_finite()) {
                    *state = s;
                    return Err(non_finite(xb.get(j).copied().unwrap_or(x_last), i + j));
                }
                s.x = x_last;
                s.y = yb.last().copied().unwrap_or(s.y);
                s.decay = T::one() + minus_rise_last;
                i = end;
                if end < end_max {
                    break;
                }
            }
        }
        *state = s;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ParamSet;

    /// `StepLaw::run` is public: an output slice shorter than the input was
    /// indexed past its end (a panic); now it is a length error.
    #[test]
    fn run_with_unequal_lengths_is_an_error() {
        let law = MmsParams::<f64>::example();
        let mut s = law.initial();
        let mut ys = [0.0; 1];
        assert!(matches!(
            law.run(&mut s, &[0.1, 0.2, 0.3], &mut ys),
            Err(Error::LengthMismatch { .. })
        ));
    }

    /// The dual twin's values are the `f64` operator's bits (its
    /// derivatives come from the library's `expm1`/`exp`), in `step` and in
    /// the batch loop.
    #[test]
    fn dual_values_are_the_f64_values() {
        use crate::{Dual, Operator};
        let xs: Vec<f64> = (0..600)
            .map(|i| 2.0 * (i as f64 * 0.05).sin() + 0.3 * (i as f64 * 0.71).sin())
            .collect();
        let mut f = Mms::new(1.5_f64, 7.0).unwrap();
        let want = f.run(&xs).unwrap();
        let mut d = Mms::new(Dual::variable(1.5, 0), Dual::variable(7.0, 1)).unwrap();
        let dx: Vec<Dual> = xs.iter().map(|&x| Dual::constant(x)).collect();
        let batch = d.run(&dx).unwrap();
        d.reset();
        for (k, (&x, y)) in dx.iter().zip(&want).enumerate() {
            let t = d.trial(x).unwrap();
            d.commit();
            assert_eq!(t.output.re.to_bits(), y.to_bits(), "step at {k}");
            assert_eq!(batch[k].re.to_bits(), y.to_bits(), "batch at {k}");
        }
    }

    /// Over `f64` the branch is the vectorisable kernel, bit for bit;
    /// over `f32` (the library's `exp` past `ln 2`, `expm1` before) it stays
    /// within two ulps of `expm1`, across the switch too (`exp` alone would
    /// be off by up to `ε/a` relative near the reversal).
    #[test]
    fn exp_m1_of_negative_is_the_kernel_over_f64_and_expm1_over_f32() {
        let mut grid: Vec<f64> = (-300..=2).map(|e| 10f64.powi(e)).collect();
        grid.extend((1..=4000).map(|i| f64::from(i) * 0.01));
        let ln2 = std::f32::consts::LN_2;
        let (mut above, mut below) = (ln2, ln2);
        for _ in 0..64 {
            grid.extend([f64::from(above), f64::from(below)]);
            above = above.next_up();
            below = below.next_down();
        }
        for a in grid {
            let kernel = crate::exp_kernel::exp_m1_nonpositive(-a);
            assert_eq!(exp_m1_of_negative(-a).to_bits(), kernel.to_bits());
            let a = a as f32;
            let (got, want) = (exp_m1_of_negative(-a), (-a).exp_m1());
            let ulp = want.abs() * f32::EPSILON;
            assert!(
                (got - want).abs() <= 2.0 * ulp,
                "a = {a:e}: {got:e} against {want:e}"
            );
        }
    }
}
