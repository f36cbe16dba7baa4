//! Band-limited interpolation of a record that is not periodic.
//!
//! Upsampling by `q` inserts `q − 1` samples between neighbours and
//! low-passes at the input's Nyquist frequency. In polyphase form, the
//! fine sample `p` (`0 ≤ p < q`) after input sample `j` is
//!
//! `y[j·q + p] = Σ_i x̄[i] · h[(j − i)·q + p]`,
//!
//! with `h` the interpolation filter of [`interpolation_filter`]: a sinc of
//! cutoff `1/(2q)` cycles per fine sample under a Kaiser window
//! (`β =` [`KAISER_BETA`]) spanning [`SIDE_SAMPLES`] input samples on each
//! side, `h[m] = sinc(m/q) · I₀(β √(1 − (m/M)²)) / I₀(β)`, `M = SIDE_SAMPLES · q`.
//! `h[0] = 1` and `h[m] = 0` at the other multiples of `q`, so the input
//! samples are kept exactly.
//!
//! **Error.** For a sine of frequency `f ≤ 0.3 fs` (`fs` the input rate),
//! every fine sample is within `1e-9` of the sine's amplitude of the
//! exact value, away from the ends (the unit tests measure it; the
//! filter's passband error is `4e-10` up to `0.2 fs` and `8e-10` up to
//! `0.3 fs`). The Bouc-Wen benchmark's inputs lie below `0.2 fs`.
//!
//! **Ends.** Outside the record, `x̄` holds the first and last sample
//! (`x̄[i] = x[0]` for `i < 0`, `x[N−1]` for `i ≥ N`): the rest state
//! before a record that starts from rest. Within `SIDE_SAMPLES` samples of
//! an end, the result is the interpolant of that continued record.

use super::{check_record, invalid};
use hysteron_operators::Result;

/// Input samples the interpolation filter spans on each side.
pub const SIDE_SAMPLES: usize = 16;
/// The Kaiser window's `β` (about 190 dB side lobes; the wide transition
/// band this buys ends below the input's Nyquist frequency's images).
pub const KAISER_BETA: f64 = 20.0;

/// The modified Bessel function `I₀(x) = Σ_k ((x/2)^k / k!)²`, summed until
/// the terms no longer change the sum (`x ≤ KAISER_BETA`: under 40 terms).
fn bessel_i0(x: f64) -> f64 {
    let quarter = x * x / 4.0;
    let mut term = 1.0;
    let mut sum = 1.0;
    let mut k = 1.0;
    while term > sum * 1e-17 {
        term *= quarter / (k * k);
        sum += term;
        k += 1.0;
    }
    sum
}

/// The taps `h[m]`, `m = −M … M` (`M = SIDE_SAMPLES · q`), of the
/// interpolation filter of [`upsample_polyphase`] (see the
/// [module](self)), stored from `m = −M`.
///
/// Errors: `q = 0`, or `q` so large that the filter's length overflows,
/// is an [`Error::InvalidParameter`](hysteron_operators::Error::InvalidParameter)
/// naming `q`.
///
/// ```
/// use hysteron_models::signal::{interpolation_filter, SIDE_SAMPLES};
/// let h = interpolation_filter(4).unwrap();
/// let centre = SIDE_SAMPLES * 4;
/// assert_eq!(h.len(), 2 * centre + 1);
/// assert_eq!(h[centre], 1.0);
/// assert_eq!(h[centre + 4], 0.0); // zero at the other input samples
/// ```
pub fn interpolation_filter(q: usize) -> Result<Vec<f64>> {
    if q == 0 {
        return Err(invalid("q", 0.0, "must be ≥ 1"));
    }
    let half = SIDE_SAMPLES
        .checked_mul(q)
        .filter(|m| m.checked_mul(2).is_some_and(|l| l < usize::MAX))
        .ok_or_else(|| invalid("q", q as f64, "the filter's length overflows"))?;
    let norm = bessel_i0(KAISER_BETA);
    let pi = std::f64::consts::PI;
    Ok((0..=2 * half)
        .map(|i| {
            let m = i as isize - half as isize;
            if m == 0 {
                1.0
            } else if m.unsigned_abs().is_multiple_of(q) {
                0.0
            } else {
                let t = m as f64 / q as f64;
                let r = m as f64 / half as f64;
                (pi * t).sin() / (pi * t) * bessel_i0(KAISER_BETA * (1.0 - r * r).sqrt()) / norm
            }
        })
        .collect())
}

/// Band-limited interpolation of a record `x` (length `N`) that is not
/// periodic onto the grid `q` times finer: `N·q` samples, `y[j·q] = x[j]`
/// exactly, the samples between from the Kaiser-windowed sinc of the
/// [module](self) (its error and end handling are stated there). For one
/// period of a periodic record, [`fft_upsample`](super::fft_upsample) is
/// exact.
///
/// Errors: an empty record or `q = 0` is an
/// [`Error::InvalidParameter`](hysteron_operators::Error::InvalidParameter),
/// a non-finite sample an
/// [`Error::NonFiniteInput`](hysteron_operators::Error::NonFiniteInput) at
/// its index.
///
/// ```
/// use hysteron_models::signal::upsample_polyphase;
/// let f = 0.05; // cycles per input sample
/// let x: Vec<f64> = (0..200).map(|j| (2.0 * std::f64::consts::PI * f * j as f64).sin()).collect();
/// let y = upsample_polyphase(&x, 10).unwrap();
/// assert_eq!(y.len(), 2000);
/// let t = 100.3; // an input-sample time in the interior
/// let exact = (2.0 * std::f64::consts::PI * f * t).sin();
/// assert!((y[1003] - exact).abs() < 1e-9);
/// ```
pub fn upsample_polyphase(x: &[f64], q: usize) -> Result<Vec<f64>> {
    check_record(x)?;
    let h = interpolation_filter(q)?;
    let n = x.len();
    let fine = n
        .checked_mul(q)
        .ok_or_else(|| invalid("q", q as f64, "x.len() · q overflows"))?;
    let last = n - 1; // n ≥ 1 (check_record)
    let side = SIDE_SAMPLES as isize;
    let half = (SIDE_SAMPLES * q) as isize;
    let mut y = Vec::with_capacity(fine);
    for j in 0..n as isize {
        for p in 0..q as isize {
            // taps (j − i)·q + p for d = j − i in −side ..= side
            let sum: f64 = (-side..=side)
                .filter_map(|d| {
                    let tap = h.get(usize::try_from(d * q as isize + p + half).ok()?)?;
                    let i = (j - d).clamp(0, last as isize) as usize;
                    Some(tap * x.get(i)?)
                })
                .sum();
            y.push(sum);
        }
    }
    Ok(y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use hysteron_operators::Error;
    use std::f64::consts::PI;

    #[test]
    fn bessel_i0_matches_tabulated_values() {
        // Abramowitz & Stegun, table 9.8: I₀(1) = 1.266065878, I₀(5) = 27.23987182
        assert!((bessel_i0(0.0) - 1.0).abs() < 1e-16);
        assert!((bessel_i0(1.0) - 1.266_065_877_752_008).abs() < 1e-14);
        assert!((bessel_i0(5.0) - 27.239_871_823_604_44).abs() < 1e-12);
    }

    /// Sines up to `0.3 fs`, at phases that fall between input samples,
    /// are interpolated to within `1e-9` away from the ends; the input
    /// samples stay exactly where they were.
    #[test]
    fn interpolates_sines_below_three_tenths_of_the_rate() {
        let n = 400;
        for q in [2, 7, 20] {
            for f in [0.0, 0.013, 0.07, 0.19, 0.3] {
                let sine = |t: f64| (2.0 * PI * f * t + 0.4).sin();
                let x: Vec<f64> = (0..n).map(|j| sine(j as f64)).collect();
                let y = upsample_polyphase(&x, q).unwrap();
                assert_eq!(y.len(), n * q);
                for (j, &xj) in x.iter().enumerate() {
                    assert_eq!(y[j * q], xj, "q = {q}, f = {f}: sample {j} moved");
                }
                let interior = SIDE_SAMPLES * q..(n - SIDE_SAMPLES) * q;
                let worst = interior
                    .map(|i| (y[i] - sine(i as f64 / q as f64)).abs())
                    .fold(0.0, f64::max);
                assert!(worst < 1e-9, "q = {q}, f = {f}: error {worst:e}");
            }
        }
    }

    /// A record that starts and ends at rest (a constant) stays constant
    /// up to both ends: the ends hold their values.
    #[test]
    fn holds_the_end_values() {
        let y = upsample_polyphase(&[2.5; 40], 5).unwrap();
        // the DC gain of each phase is 1 to within the filter's passband error
        let worst = y.iter().map(|v| (v - 2.5).abs()).fold(0.0, f64::max);
        assert!(worst < 2.5e-9, "{worst:e}");
        assert_eq!(upsample_polyphase(&[3.0], 4).unwrap().len(), 4);
        assert_eq!(upsample_polyphase(&[1.0, -2.0], 1).unwrap(), [1.0, -2.0]);
    }

    #[test]
    fn bad_input_is_an_error() {
        assert!(upsample_polyphase(&[], 3).is_err());
        assert!(upsample_polyphase(&[1.0], 0).is_err());
        assert!(matches!(
            upsample_polyphase(&[1.0, f64::INFINITY], 3),
            Err(Error::AtSample { index: 1, .. })
        ));
        assert!(interpolation_filter(usize::MAX / 4).is_err());
    }
}
