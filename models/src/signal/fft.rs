//! Band-limited interpolation of one period of a periodic record.

use super::{check_record, invalid};
use hysteron_operators::Result;
use rustfft::num_complex::Complex;
use rustfft::FftPlanner;

/// Band-limited interpolation of one period `x` (length `N`) of a periodic
/// record onto the grid `q` times finer: `y[q·j + i] = x̃((j + i/q))`, where
/// `x̃` is the trigonometric interpolant of `x` (the unique real
/// trigonometric polynomial of degree `< N/2` through the samples, plus for
/// even `N` half the Nyquist component as `cos`). The result has `N·q`
/// samples, keeps the original ones at multiples of `q` (to rounding), and
/// is exact for any periodic signal whose spectrum lies below the Nyquist
/// frequency of `x`, such as a multisine.
///
/// It zero-pads the spectrum: bins `0 … ⌈N/2⌉ − 1` and their mirror
/// images keep their place, and for even `N` the Nyquist bin `X[N/2]` is
/// split evenly between `+N/2` and `−N/2`, so the interpolant stays real.
///
/// Errors: an empty record or `q = 0` is an [`Error::InvalidParameter`](hysteron_operators::Error::InvalidParameter), a
/// non-finite sample an [`Error::NonFiniteInput`](hysteron_operators::Error::NonFiniteInput) at its index.
///
/// ```
/// use hysteron_models::signal::fft_upsample;
/// let x: Vec<f64> = (0..8).map(|n| (2.0 * std::f64::consts::PI * n as f64 / 8.0).sin()).collect();
/// let y = fft_upsample(&x, 4).unwrap();
/// assert_eq!(y.len(), 32);
/// let t = 2.0 * std::f64::consts::PI * 5.0 / 32.0;
/// assert!((y[5] - t.sin()).abs() < 1e-14);
/// ```
// `half = ⌈n/2⌉ ≤ n ≤ fine` and `n ≥ 1` (`check_record`), `q ≥ 2`: the
// indices `n − j`, `n/2` are `< n = spectrum.len()` and `fine − j`,
// `fine − n/2` are in `(0, fine)`.
#[allow(clippy::indexing_slicing)]
pub fn fft_upsample(x: &[f64], q: usize) -> Result<Vec<f64>> {
    check_record(x)?;
    if q == 0 {
        return Err(invalid("q", 0.0, "must be ≥ 1"));
    }
    if q == 1 {
        return Ok(x.to_vec());
    }
    let n = x.len();
    let fine = n
        .checked_mul(q)
        .ok_or_else(|| invalid("q", q as f64, "x.len() · q overflows"))?;
    let mut planner = FftPlanner::<f64>::new();
    let mut spectrum: Vec<Complex<f64>> = x.iter().map(|&v| Complex::new(v, 0.0)).collect();
    planner.plan_fft_forward(n).process(&mut spectrum);

    let mut padded = vec![Complex::new(0.0, 0.0); fine];
    // Bins strictly below the Nyquist frequency, positive and negative.
    let half = n.div_ceil(2); // 0 … half − 1 are the non-negative ones
    padded[..half].copy_from_slice(&spectrum[..half]);
    for j in 1..half {
        padded[fine - j] = spectrum[n - j];
    }
    if n.is_multiple_of(2) {
        let nyquist = spectrum[n / 2] * 0.5;
        padded[n / 2] = nyquist;
        padded[fine - n / 2] = nyquist;
    }
    planner.plan_fft_inverse(fine).process(&mut padded);
    // rustfft does not normalise: the inverse of the coarse spectrum needs 1/N.
    let scale = 1.0 / n as f64;
    Ok(padded.iter().map(|c| c.re * scale).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::signal::test_signals::{max_diff, multisine};
    use hysteron_operators::Error;
    use std::f64::consts::PI;

    #[test]
    fn reproduces_a_sum_of_sines_at_the_fine_points() {
        for (n, q) in [(64, 20), (63, 7), (50, 3), (8192, 20), (9, 2)] {
            let top = (n - 1) / 2;
            let harmonics = [
                (0, 0.7, PI / 2.0), // a constant
                (1, 1.0, 0.3),
                (3, 0.5, -1.1),
                (top / 2, 0.25, 2.0),
                (top, 0.125, 0.7), // the highest below Nyquist
            ];
            let x = multisine(&harmonics, n);
            let y = fft_upsample(&x, q).unwrap();
            assert_eq!(y.len(), n * q);
            let exact = multisine(&harmonics, n * q);
            let e = max_diff(&y, &exact);
            assert!(e < 1e-12, "n = {n}, q = {q}: error {e:e}");
            let kept: Vec<f64> = y.iter().step_by(q).copied().collect();
            let e = max_diff(&kept, &x);
            assert!(
                e < 1e-12,
                "n = {n}, q = {q}: original samples moved by {e:e}"
            );
        }
    }

    #[test]
    fn even_lengths_split_the_nyquist_bin() {
        // x_j = cos(π j) is the Nyquist component: interpolated as cos(π t),
        // real, through the samples.
        let n = 16;
        let q = 5;
        let x: Vec<f64> = (0..n).map(|j| 0.5 + (PI * j as f64).cos()).collect();
        let y = fft_upsample(&x, q).unwrap();
        let exact: Vec<f64> = (0..n * q)
            .map(|j| 0.5 + (PI * j as f64 / q as f64).cos())
            .collect();
        assert!(max_diff(&y, &exact) < 1e-12);
    }

    #[test]
    fn q_one_and_errors() {
        let x = [1.0, -2.0, 3.0];
        assert_eq!(fft_upsample(&x, 1).unwrap(), x.to_vec());
        assert!(fft_upsample(&x, 0).is_err());
        assert!(fft_upsample(&[], 3).is_err());
        assert!(matches!(
            fft_upsample(&[1.0, f64::NAN], 3),
            Err(Error::AtSample { index: 1, .. })
        ));
        let y = fft_upsample(&[2.5], 4).unwrap();
        assert_eq!(y, vec![2.5; 4]);
    }

    /// `x.len() · q` overflowing is an error, not a panic (or a wrapped,
    /// too short buffer).
    #[test]
    fn upsample_overflow() {
        assert!(fft_upsample(&[1.0, 2.0, 3.0], usize::MAX / 2).is_err());
    }
}
