//! `a^n` for `a ≥ 0` and `n ≥ 1` in `f64` as `e^{n ln a}`, inline: no
//! call, no table, no branch but selects.
//!
//! The derivatives of a tabulated Bouc-Wen branch need the rate `f(g) = α −
//! c |g|^n` at every sample of a dual pass; the C library's `pow` (correctly
//! rounded in most cases, and a call) was a fifth of a fit's time. The rate
//! only scales derivative parts there (see `BoucWen::step_sensitive`), so
//! an error of a few ulps is immaterial; values of the model never go
//! through this function.

use crate::exp_m1::{exp_parts, LN2_HI, LN2_LO};

/// `L[j] = 2/(2j + 1)`: `ln m = s Σ_j L[j] s^{2j}` with `s = (m − 1)/(m +
/// 1)` (the series of `2 artanh s`).
const L: [f64; 12] = [
    2.0,
    2.0 / 3.0,
    2.0 / 5.0,
    2.0 / 7.0,
    2.0 / 9.0,
    2.0 / 11.0,
    2.0 / 13.0,
    2.0 / 15.0,
    2.0 / 17.0,
    2.0 / 19.0,
    2.0 / 21.0,
    2.0 / 23.0,
];

/// `2^54`, which brings a subnormal into the normal range.
const TWO_54: f64 = 18_014_398_509_481_984.0;

/// `ln a` for `a ≥ 0` finite (`a = 0` gives about `−746.4`, the logarithm of
/// the smallest subnormal's half, not `−∞`; see [`pow_positive`]).
///
/// With `a = 2^k m`, `m ∈ [√½, √2)`, and `s = (m − 1)/(m + 1)` (`|s| ≤
/// 0.172`), `ln a = k ln 2 + 2 artanh s = k ln 2 + s Σ_{j<12} 2 s^{2j}/(2j +
/// 1)`, the sum by Estrin's scheme, its truncation below `2^-60` relative;
/// `k ln 2` in two parts, as in [`exp_parts`].
///
/// # Reference
/// J.-M. Muller, *Elementary Functions: Algorithms and Implementation*,
/// 3rd ed., Birkhäuser 2016, §11.3 (range reduction of the logarithm).
#[inline(always)]
fn ln_nonnegative(a: f64) -> f64 {
    let subnormal = a < f64::MIN_POSITIVE;
    let a = if subnormal { a * TWO_54 } else { a };
    let bits = a.to_bits();
    // the biased exponent has 11 bits: the cast is exact
    #[allow(clippy::cast_possible_wrap)]
    let e = ((bits >> 52) & 0x7ff) as i64 - 1023 - if subnormal { 54 } else { 0 };
    let m = f64::from_bits((bits & ((1 << 52) - 1)) | (1023 << 52));
    let big = m > core::f64::consts::SQRT_2;
    let m = if big { 0.5 * m } else { m };
    // |e| < 1100: exact in f64
    #[allow(clippy::cast_precision_loss)]
    let k = (e + i64::from(big)) as f64;
    let f = m - 1.0;
    let s = f / (2.0 + f);
    let z = s * s;
    let z2 = z * z;
    let z4 = z2 * z2;
    let z8 = z4 * z4;
    let [l0, l1, l2, l3, l4, l5, l6, l7, l8, l9, l10, l11] = L;
    let p = ((l0 + l1 * z) + (l2 + l3 * z) * z2) + ((l4 + l5 * z) + (l6 + l7 * z) * z2) * z4;
    let p = p + ((l8 + l9 * z) + (l10 + l11 * z) * z2) * z8;
    let ln = k * LN2_HI + (s * p + k * LN2_LO);
    // NaN and ∞ through
    if a < f64::INFINITY {
        ln
    } else {
        a
    }
}

/// `a^n` for `a ≥ 0` finite and `n ≥ 1`: `e^{x}`, `x = n ln a`, `0` where
/// `x < −708` (so `0^n = 0`; the true value is below `2^-1021` there) and
/// `∞` where `x > 709`.
///
/// The relative error is at most about `(3 + 2|x|) ε` (`ε = 2^-52`): a few
/// ulps of `ln a`, scaled by `n`, become the relative error of `e^x`
/// (checked against `powf` in the tests).
#[inline(always)]
pub(crate) fn pow_positive(a: f64, n: f64) -> f64 {
    let x = n * ln_nonnegative(a);
    let (scale, s) = exp_parts(x.clamp(-708.0, 709.0));
    let y = scale + scale * s;
    if x < -708.0 {
        0.0
    } else if x > 709.0 {
        f64::INFINITY
    } else {
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Relative error against `powf` within `(3 + 2|n ln a|) ε` (0 where
    /// `n ln a < −708`) on a geometric grid of `a` from `1e-300` to `1e30` (and the subnormal
    /// range) and exponents from 1 to 9, including the integer and
    /// half-integer ones and the reduction's edges `m = √2` and `m = 1`.
    #[test]
    fn within_its_bound_of_powf() {
        let mut worst: (f64, f64, f64) = (0.0, 0.0, 0.0);
        let mut check = |a: f64, n: f64| {
            let (want, x) = (a.powf(n), n * a.ln());
            if x < -708.0 {
                // flushed: the true value is below e^-708
                assert_eq!(pow_positive(a, n), 0.0, "{a}^{n}");
                assert!(want < 3.31e-308);
                return;
            }
            if x > 709.0 {
                return;
            }
            let err =
                (pow_positive(a, n) / want - 1.0).abs() / f64::EPSILON / (3.0 + 2.0 * x.abs());
            if err > worst.0 {
                worst = (err, a, n);
            }
        };
        for n in [1.0, 1.2, 1.5, 2.0, 2.5029, std::f64::consts::PI, 7.0, 9.0] {
            let mut a = 1e-300_f64;
            while a < 1e30 {
                check(a, n);
                a *= 1.000_9;
            }
            let mut a = 5e-324_f64;
            while a < 1e-300 {
                check(a, n);
                a *= 3.7;
            }
            for e in -60..60 {
                let edge = core::f64::consts::SQRT_2 * 2f64.powi(e);
                let mut x = edge;
                for _ in 0..16 {
                    check(x, n);
                    check(2f64.powi(e), n);
                    x = f64::from_bits(x.to_bits() + 1);
                }
            }
        }
        assert!(worst.0 <= 1.0, "{:?}", worst);
    }

    /// `1^n = 1` and `0^n = 0` exactly, and the ends.
    #[test]
    fn exact_values_and_ends() {
        assert_eq!(pow_positive(1.0, 1.7), 1.0);
        assert_eq!(pow_positive(0.0, 1.0), 0.0);
        assert_eq!(pow_positive(0.0, 3.5), 0.0);
        assert_eq!(pow_positive(1e-200, 4.0), 0.0);
        assert_eq!(pow_positive(1e200, 4.0), f64::INFINITY);
        assert!(pow_positive(f64::NAN, 2.0).is_nan());
    }
}
