//! `e^x` and `e^x − 1` (for `x ≤ 0`) in `f64`, written so that a loop
//! over them vectorises: no branch, no table, no call.
//!
//! The MMS branch `1 − e^{−K |x − x_r|}` and the Bouc-Wen branch
//! `g∞ − (f/c) e^{−c s}` need one per sample; a call to the C library's
//! `exp` or `expm1` cannot be vectorised and costs more than the rest of
//! the sample. These functions give the same bits wherever they run (one
//! sample in a `step`, or four or eight per instruction in a batch loop or
//! across the lanes of an ensemble), since every version does the same
//! operations in the same order, with no fused multiply-add. A lane
//! kernel of one's own ([`LaneLaw`](crate::lanes::LaneLaw)) calls them for
//! the bits of the leaf it steps.

use crate::simd::Isa;
use crate::Float;
use core::any::TypeId;

/// `ln 2` in two parts: the high part has 21 trailing zero bits, so
/// `k · LN2_HI` is exact for `|k| < 2^21`, and `LN2_HI + LN2_LO` is `ln 2`
/// to about `2^-86`.
const LN2_HI: f64 = f64::from_bits(0x3FE6_2E42_FEE0_0000);
/// See [`LN2_HI`].
const LN2_LO: f64 = f64::from_bits(0x3DEA_39EF_3579_3C76);
/// `1.5 · 2^52`: adding it to `|v| < 2^51` rounds `v` to the nearest integer
/// (ties to even), which then sits in the low bits of the sum's pattern.
const SHIFTER: f64 = 6_755_399_441_055_744.0;
/// Below it `e^x < 2^-57`, so `e^x − 1` rounds to `−1`; clamping there
/// keeps `2^k` a normal number.
const FLOOR: f64 = -40.0;

/// `C[j] = 1/(j + 2)!`, the Taylor coefficients of `(e^r − 1 − r)/r²`.
const C: [f64; 12] = [
    1.0 / 2.0,
    1.0 / 6.0,
    1.0 / 24.0,
    1.0 / 120.0,
    1.0 / 720.0,
    1.0 / 5_040.0,
    1.0 / 40_320.0,
    1.0 / 362_880.0,
    1.0 / 3_628_800.0,
    1.0 / 39_916_800.0,
    1.0 / 479_001_600.0,
    1.0 / 6_227_020_800.0,
];

/// `e^x − 1` for `x ≤ 0`, within about one ulp (see the tests), `−1` below
/// `−40` and for `x = −∞`, NaN for NaN.
///
/// With `k = round(x / ln 2)` and `r = x − k ln 2` (`|r| ≤ ln 2 / 2`, the
/// product `k ln 2` in two parts),
///
/// `e^x − 1 = (2^k − 1) + 2^k s`,  `s = e^r − 1 = r + r² Σ_{j<12} r^j/(j+2)!`,
///
/// the sum by Estrin's scheme (short dependency chains for a scalar call),
/// its truncation below `2^-60` relative. `2^k − 1` is exact for
/// `−53 ≤ k ≤ 0` and rounds to `−1` below, where the result is `−1` too;
/// near `x = 0` (`k = 0`) the result is `s` itself, so it keeps its
/// relative accuracy there, as `expm1` does.
///
/// # Reference
/// P. T. P. Tang, "Table-driven implementation of the expm1 function in
/// IEEE floating-point arithmetic", *ACM TOMS* 18(2), 1992 (the reduction
/// and the `(2^k − 1) + 2^k s` recombination, here without the table).
///
/// ```
/// use hysteron_operators::exp_kernel::exp_m1_nonpositive;
/// assert!((exp_m1_nonpositive(-1e-3) - (-1e-3_f64).exp_m1()).abs() < 1e-19);
/// ```
#[inline(always)]
pub fn exp_m1_nonpositive(x: f64) -> f64 {
    // (a NaN fails the comparison and runs through as NaN)
    let x = if x < FLOOR { FLOOR } else { x };
    let (k, s) = reduce(x);
    // 2^k from the integer k ≥ −58: (k + 1023) << 52.
    let scale = power_of_two(k);
    (scale - 1.0) + scale * s
}

/// Below it `e^x` rounds to `0` (it is under half the least subnormal).
const EXP_MIN: f64 = -746.0;
/// Above it `e^x` overflows to `+∞`.
const EXP_MAX: f64 = 710.0;

/// `e^x`, within about one ulp (see the tests), `0` below `−745.2`
/// (`−∞` included), `+∞` above `709.8`, NaN for NaN.
///
/// The reduction of [`exp_m1_nonpositive`], `e^x = 2^k (1 + s)`, with
/// `2^k` applied as two factors `2^{k1} 2^{k2}` (`k1 = ⌊k/2⌋`), each a
/// normal number over the whole range, so that the one rounding of the
/// last product gives subnormal results and the overflow to `+∞`.
///
/// # Reference
/// P. T. P. Tang, "Table-driven implementation of the exponential function
/// in IEEE floating-point arithmetic", *ACM TOMS* 15(2), 1989 (the
/// reduction, here without the table).
///
/// ```
/// use hysteron_operators::exp_kernel::exp;
/// assert!((exp(-2.5) - (-2.5_f64).exp()).abs() < 1e-16);
/// ```
#[inline(always)]
pub fn exp(x: f64) -> f64 {
    // (`clamp` keeps a NaN, which runs through as NaN)
    let x = x.clamp(EXP_MIN, EXP_MAX);
    let (k, s) = reduce(x);
    let k1 = k >> 1;
    ((1.0 + s) * power_of_two(k1)) * power_of_two(k - k1)
}

/// `x = k ln 2 + r` with `k = round(x / ln 2)` (`|r| ≤ ln 2 / 2`, the
/// product `k ln 2` in two parts), and `s = e^r − 1 = r + r² Σ_{j<12}
/// r^j/(j+2)!`, the sum by Estrin's scheme (short dependency chains for a
/// scalar call), its truncation below `2^-60` relative. `|x| < 2^20`.
#[inline(always)]
fn reduce(x: f64) -> (i64, f64) {
    let t = x * core::f64::consts::LOG2_E + SHIFTER;
    let k = t - SHIFTER;
    let r = (x - k * LN2_HI) - k * LN2_LO;
    // k is the integer in `t`'s low bits
    let k_int = t.to_bits().wrapping_sub(SHIFTER.to_bits()) as i64;
    let r2 = r * r;
    let r4 = r2 * r2;
    let r8 = r4 * r4;
    let [c0, c1, c2, c3, c4, c5, c6, c7, c8, c9, c10, c11] = C;
    let q = ((c0 + c1 * r) + (c2 + c3 * r) * r2) + ((c4 + c5 * r) + (c6 + c7 * r) * r2) * r4;
    let q = q + ((c8 + c9 * r) + (c10 + c11 * r) * r2) * r8;
    (k_int, r + r2 * q)
}

/// `2^k` for `−1022 ≤ k ≤ 1023`, from its bit pattern.
#[inline(always)]
fn power_of_two(k: i64) -> f64 {
    f64::from_bits((k.wrapping_add(1023) as u64) << 52)
}

/// A function of one scalar whose `f64` values are those of a kernel of
/// this module: over `f64` the kernel itself; over dual numbers `generic`
/// (the library's function, which gives the derivatives) with its value
/// replaced by the kernel's, so that the dual twin's values are the `f64`
/// model's bits (the two differ by an ulp or so: the difference is exact,
/// and so is the sum); over other scalars `generic`.
#[inline(always)]
pub(crate) fn with_kernel_value<T: Float>(
    v: T,
    kernel: fn(f64) -> f64,
    generic: impl FnOnce(T) -> T,
) -> T {
    if TypeId::of::<T>() == TypeId::of::<f64>() {
        // (`as_f64` and `lit` are the identity on `f64`)
        return T::lit(kernel(v.as_f64()));
    }
    let g = generic(v);
    if T::CARRIES_DERIVATIVES {
        return g + (T::lit(kernel(v.as_f64())) - g.without_derivatives());
    }
    g
}

/// [`exp_m1_nonpositive`] of every value of `v`, in place: four or eight
/// per instruction where the CPU has AVX2 or AVX-512 ([`Isa::detect`]), two
/// otherwise; the same bits either way.
///
/// ```
/// use hysteron_operators::exp_kernel::{exp_m1_nonpositive, exp_m1_nonpositive_in_place};
/// let mut v = [-2.0, -1e-9, 0.0];
/// exp_m1_nonpositive_in_place(&mut v);
/// assert_eq!(v[1], exp_m1_nonpositive(-1e-9));
/// ```
pub fn exp_m1_nonpositive_in_place(v: &mut [f64]) {
    map_in_place(v, exp_m1_nonpositive)
}

/// [`exp`] of every value of `v`, in place, as
/// [`exp_m1_nonpositive_in_place`] runs its kernel.
///
/// ```
/// use hysteron_operators::exp_kernel::{exp, exp_in_place};
/// let mut v = [-2.0, 0.5];
/// exp_in_place(&mut v);
/// assert_eq!(v, [exp(-2.0), exp(0.5)]);
/// ```
pub fn exp_in_place(v: &mut [f64]) {
    map_in_place(v, exp)
}

/// `kernel` (a kernel of this module) on every value of `v`, in place, on
/// the widest vector unit the CPU has.
#[inline(always)]
fn map_in_place<F: Fn(f64) -> f64>(v: &mut [f64], kernel: F) {
    #[cfg(target_arch = "x86_64")]
    match Isa::detect() {
        // SAFETY: the instruction set was detected on this CPU.
        Some(Isa::Avx512) => return unsafe { in_place_avx512(v, kernel) },
        // SAFETY: as above.
        Some(Isa::Avx2) => return unsafe { in_place_avx2(v, kernel) },
        None => {}
    }
    in_place(v, kernel)
}

#[inline(always)]
fn in_place<F: Fn(f64) -> f64>(v: &mut [f64], kernel: F) {
    for a in v {
        *a = kernel(*a);
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn in_place_avx2<F: Fn(f64) -> f64>(v: &mut [f64], kernel: F) {
    in_place(v, kernel)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn in_place_avx512<F: Fn(f64) -> f64>(v: &mut [f64], kernel: F) {
    in_place(v, kernel)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The largest distance in ulps between `kernel` and `reference` over
    /// `points`, and where it is.
    fn worst_ulps(
        kernel: fn(f64) -> f64,
        reference: fn(f64) -> f64,
        points: impl Iterator<Item = f64>,
    ) -> (u64, f64) {
        points
            .map(|x| (kernel(x).to_bits().abs_diff(reference(x).to_bits()), x))
            .fold((0, 0.0), |worst, d| if d.0 > worst.0 { d } else { worst })
    }

    /// The ends of the reduction intervals `(k + 1/2) ln 2` for `k` in
    /// `ks`, each with 64 neighbours on either side.
    fn interval_ends(ks: core::ops::Range<i32>) -> impl Iterator<Item = f64> {
        ks.flat_map(|k| {
            let edge = (f64::from(k) + 0.5) * core::f64::consts::LN_2;
            let up = core::iter::successors(Some(edge), |x| Some(x.next_up()));
            let down = core::iter::successors(Some(edge), |x| Some(x.next_down()));
            up.take(64).chain(down.take(64))
        })
    }

    /// `start, start·ratio, …` below `end`.
    fn geometric(start: f64, ratio: f64, end: f64) -> impl Iterator<Item = f64> {
        core::iter::successors(Some(start), move |a| Some(a * ratio)).take_while(move |a| *a < end)
    }

    /// Against the C library's `expm1` (itself within one ulp) on a
    /// geometric grid from `−1e-300` to `−50` and at the ends of every
    /// reduction interval `(k ± 1/2) ln 2`, with neighbours.
    #[test]
    fn within_two_ulps_of_expm1() {
        let points = geometric(1e-300, 1.000_37, 50.0)
            .map(|a| -a)
            .chain(interval_ends(-60..0));
        let worst = worst_ulps(exp_m1_nonpositive, f64::exp_m1, points);
        assert!(worst.0 <= 2, "{} ulps at x = {:e}", worst.0, worst.1);
    }

    /// Ends and special values: `0` and `−0` exactly, `−1` far out and at
    /// `−∞`, NaN through.
    #[test]
    fn special_values() {
        assert_eq!(exp_m1_nonpositive(0.0).to_bits(), 0.0_f64.to_bits());
        assert_eq!(exp_m1_nonpositive(-0.0), 0.0);
        assert_eq!(exp_m1_nonpositive(-1e-320), -1e-320);
        assert_eq!(exp_m1_nonpositive(-38.0), -1.0);
        assert_eq!(exp_m1_nonpositive(-1e300), -1.0);
        assert_eq!(exp_m1_nonpositive(f64::NEG_INFINITY), -1.0);
        assert!(exp_m1_nonpositive(f64::NAN).is_nan());
    }

    /// `exp` against the C library's (itself within one ulp) on a grid
    /// over its whole range, from results far in the subnormals to the
    /// largest finite ones, and at the ends of every reduction interval
    /// near `0`, with neighbours.
    #[test]
    fn exp_within_one_ulp_of_the_c_library() {
        let grid = (0..)
            .map(|i| -745.0 + f64::from(i) * 0.000_731_3)
            .take_while(|x| *x < 709.7);
        let small = geometric(1e-300, 1.001, 1.0).flat_map(|a| [a, -a]);
        let points = grid.chain(small).chain(interval_ends(-60..60));
        let worst = worst_ulps(exp, f64::exp, points);
        assert!(worst.0 <= 1, "{} ulps at x = {:e}", worst.0, worst.1);
    }

    /// `exp`'s ends and special values: `1` at `0`, `0` far below and at
    /// `−∞`, `+∞` past the overflow and at `+∞`, NaN through.
    #[test]
    fn exp_special_values() {
        assert_eq!(exp(0.0), 1.0);
        assert_eq!(exp(-0.0), 1.0);
        assert_eq!(exp(-746.0), 0.0);
        assert_eq!(exp(-1e300), 0.0);
        assert_eq!(exp(f64::NEG_INFINITY), 0.0);
        assert!(exp(-745.0) > 0.0);
        assert!(exp(709.7).is_finite());
        assert_eq!(exp(709.8), f64::INFINITY);
        assert_eq!(exp(1e300), f64::INFINITY);
        assert_eq!(exp(f64::INFINITY), f64::INFINITY);
        assert!(exp(f64::NAN).is_nan());
    }

    /// The slice version gives the scalar's bits on whichever instruction
    /// set it dispatches to (`scripts/test.sh` runs the tests once more
    /// with `HYSTERON_ISA=avx2` and `portable`), also for lengths that
    /// leave a remainder.
    #[test]
    fn in_place_is_the_scalar_bit_for_bit() {
        for n in [0, 1, 3, 7, 8, 9, 31, 1000] {
            let xs: Vec<f64> = (0..n)
                .map(|i| -((i * 7919) % 1000) as f64 * 0.037 * (1.0 + i as f64 * 1e-3))
                .collect();
            let mut v = xs.clone();
            exp_m1_nonpositive_in_place(&mut v);
            for (x, y) in xs.iter().zip(&v) {
                assert_eq!(y.to_bits(), exp_m1_nonpositive(*x).to_bits(), "x = {x}");
            }
            // `exp` over both signs, past its overflow and underflow too
            let xs: Vec<f64> = xs
                .iter()
                .enumerate()
                .map(|(i, x)| if i % 2 == 0 { -30.0 * x } else { *x })
                .collect();
            let mut v = xs.clone();
            exp_in_place(&mut v);
            for (x, y) in xs.iter().zip(&v) {
                assert_eq!(y.to_bits(), exp(*x).to_bits(), "x = {x}");
            }
        }
    }
}
