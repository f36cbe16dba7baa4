//! Signal processing for periodic records.
//!
//! * [`fft_upsample`]: band-limited (trigonometric) interpolation of one
//!   period of a periodic record onto a `q` times finer grid;
//! * [`decimate_fir_periodic`]: the FIR decimation used by the Bouc-Wen
//!   benchmark's reference (a 30th-order Hamming-window low-pass, delay
//!   compensated, then every `r`-th sample) applied to one steady-state
//!   period, so a simulation on the fine grid can be decimated exactly as
//!   the published data were.

use hysteron_operators::{Error, Result};
use rustfft::num_complex::Complex;
use rustfft::FftPlanner;

fn invalid(name: &str, value: f64, reason: &'static str) -> Error {
    Error::InvalidParameter {
        name: name.into(),
        value,
        reason,
    }
}

fn check_record(x: &[f64]) -> Result<()> {
    if x.is_empty() {
        return Err(invalid("x", 0.0, "must hold at least one sample"));
    }
    match x.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        Some((i, &value)) => Err(Error::NonFiniteInput { value }.at_sample(i)),
        None => Ok(()),
    }
}

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
/// Errors: an empty record or `q = 0` is an [`Error::InvalidParameter`], a
/// non-finite sample an [`Error::NonFiniteInput`] at its index.
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

/// The taps of MATLAB's `fir1(order, wn)` low-pass: the ideal low-pass of
/// cutoff `wn` (a fraction of the Nyquist frequency) windowed by a Hamming
/// window of `order + 1` points and scaled to unit gain at DC.
pub fn fir1_lowpass(order: usize, wn: f64) -> Result<Vec<f64>> {
    if !(wn > 0.0 && wn < 1.0) {
        return Err(invalid("wn", wn, "must lie in (0, 1)"));
    }
    if order == 0 {
        return Err(invalid("order", 0.0, "must be ≥ 1"));
    }
    let len = order + 1;
    let centre = order as f64 / 2.0;
    let pi = std::f64::consts::PI;
    let taps: Vec<f64> = (0..len)
        .map(|i| {
            let m = i as f64 - centre;
            let ideal = if m == 0.0 {
                wn
            } else {
                (pi * wn * m).sin() / (pi * m)
            };
            let window = 0.54 - 0.46 * (2.0 * pi * i as f64 / order as f64).cos();
            ideal * window
        })
        .collect();
    let sum: f64 = taps.iter().sum();
    Ok(taps.into_iter().map(|b| b / sum).collect())
}

/// Decimates one period `x` of a periodic record by `r`, the way MATLAB's
/// `decimate(x, p, 'fir')` does it for every prime factor `p` of `r` in
/// increasing order (`r = 20`: 2, 2, 5), in the interior of a long periodic
/// record: each stage filters with `fir1(30, 1/p)` (even order, so its delay
/// of 15 samples is compensated exactly), here circularly, and keeps
/// samples `0, p, 2p, …`. `x.len()` must be a multiple of `r`.
///
/// This is the decimation of the Bouc-Wen benchmark's reference
/// simulation (Noël & Schoukens 2016), which integrates at 15 kHz and
/// decimates by 20 to 750 Hz.
pub fn decimate_fir_periodic(x: &[f64], r: usize) -> Result<Vec<f64>> {
    check_record(x)?;
    if r == 0 {
        return Err(invalid("r", 0.0, "must be ≥ 1"));
    }
    if !x.len().is_multiple_of(r) {
        return Err(invalid(
            "x",
            x.len() as f64,
            "length must be a multiple of the decimation factor",
        ));
    }
    let mut y = x.to_vec();
    for p in prime_factors(r) {
        let taps = fir1_lowpass(30, 1.0 / p as f64)?;
        let n = y.len();
        let delay = (taps.len() - 1) / 2;
        // y[(at + delay − k) mod n], without going below 0 when the period
        // is shorter than the filter (always `< n = y.len()`).
        let circ = |i: usize, k: usize| (i % n + n - k % n) % n;
        y = (0..n / p)
            .map(|j| {
                let at = j * p;
                taps.iter()
                    .enumerate()
                    .map(|(k, b)| b * y.get(circ(at + delay, k)).copied().unwrap_or(0.0))
                    .sum()
            })
            .collect();
    }
    Ok(y)
}

/// Prime factors of `r ≥ 1` in increasing order, with multiplicity
/// (MATLAB's `factor`).
fn prime_factors(mut r: usize) -> Vec<usize> {
    let mut out = Vec::new();
    let mut p = 2;
    while p * p <= r {
        while r.is_multiple_of(p) {
            out.push(p);
            r /= p;
        }
        p += 1;
    }
    if r > 1 {
        out.push(r);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// A sum of sines `(harmonic, amplitude, phase)` over one period of
    /// `len` samples. The phase `h·j/len` is reduced exactly (integers)
    /// before the sine, so the reference itself is accurate to rounding.
    fn multisine(harmonics: &[(usize, f64, f64)], len: usize) -> Vec<f64> {
        (0..len)
            .map(|j| {
                harmonics
                    .iter()
                    .map(|&(h, a, phi)| {
                        let t = ((h * j) % len) as f64 / len as f64;
                        a * (2.0 * PI * t + phi).sin()
                    })
                    .sum()
            })
            .collect()
    }

    fn max_diff(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    }

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

    #[test]
    fn fir1_is_a_windowed_half_band_lowpass() {
        // fir1(30, 1/2) in MATLAB: symmetric, unit DC gain, centre 0.5 / sum.
        let b = fir1_lowpass(30, 0.5).unwrap();
        assert_eq!(b.len(), 31);
        assert!((b.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        for i in 0..31 {
            assert!((b[i] - b[30 - i]).abs() < 1e-16);
        }
        // half-band: every other tap (even offsets from the centre) is zero
        assert!(b[15 + 2].abs() < 1e-16 && b[15 - 4].abs() < 1e-16);
        // gain at the cutoff (half the Nyquist frequency) is the centre tap,
        // about one half (−6 dB) for a window design
        assert!((b[15] - 0.5).abs() < 1e-2, "{}", b[15]);
        assert!(fir1_lowpass(30, 1.0).is_err() && fir1_lowpass(0, 0.5).is_err());
    }

    /// Zero-phase gain of symmetric taps at `f` cycles per sample.
    fn gain(taps: &[f64], f: f64) -> f64 {
        let c = (taps.len() - 1) as f64 / 2.0;
        taps.iter()
            .enumerate()
            .map(|(k, b)| b * (2.0 * PI * f * (k as f64 - c)).cos())
            .sum()
    }

    #[test]
    fn decimation_is_the_zero_phase_fir_chain_on_the_coarse_grid() {
        assert_eq!(prime_factors(20), vec![2, 2, 5]);
        assert_eq!(prime_factors(1), Vec::<usize>::new());
        assert_eq!(prime_factors(97), vec![97]);
        assert_eq!(prime_factors(12), vec![2, 2, 3]);
        // A sine of harmonic h over n fine samples comes out on the grid of
        // every 20th sample, scaled by the product of the stages' gains
        // (each at its own rate) and not shifted.
        let n = 4000;
        for h in [1, 37, 80, 150] {
            let x = multisine(&[(h, 1.0, 0.4)], n);
            let y = decimate_fir_periodic(&x, 20).unwrap();
            assert_eq!(y.len(), n / 20);
            let mut g = 1.0;
            let mut len = n as f64;
            for p in [2, 2, 5] {
                g *= gain(&fir1_lowpass(30, 1.0 / p as f64).unwrap(), h as f64 / len);
                len /= p as f64;
            }
            let expected: Vec<f64> = multisine(&[(h, 1.0, 0.4)], n / 20)
                .iter()
                .map(|v| g * v)
                .collect();
            let e = max_diff(&y, &expected);
            assert!(e < 1e-13, "h = {h}: {e:e}");
        }
        let x = multisine(&[(1, 1.0, 0.0)], 2000);
        assert!(decimate_fir_periodic(&x[..1999], 20).is_err());
        assert_eq!(decimate_fir_periodic(&x, 1).unwrap(), x);
    }
    /// A period shorter than the filter's delay (15 samples) wraps the
    /// circular index several times: `at + n + delay − k` underflowed (a
    /// panic in debug builds, a wrong sample in release ones).
    #[test]
    fn decimate_short_period() {
        let x = [1.0, -0.5, 0.25, 2.0];
        let y = decimate_fir_periodic(&x, 2).unwrap();
        let taps = fir1_lowpass(30, 0.5).unwrap();
        // y[j] = Σ_k b_k x[(2j + 15 − k) mod 4]
        for (j, &v) in y.iter().enumerate() {
            let want: f64 = taps
                .iter()
                .enumerate()
                .map(|(k, b)| b * x[(2 * j + 15 + 4 * 8 - k) % 4])
                .sum();
            assert!((v - want).abs() < 1e-15, "{v} {want}");
        }
        assert_eq!(decimate_fir_periodic(&[3.0], 1).unwrap(), vec![3.0]);
    }

    /// `x.len() · q` overflowing is an error, not a panic (or a wrapped,
    /// too short buffer).
    #[test]
    fn upsample_overflow() {
        assert!(fft_upsample(&[1.0, 2.0, 3.0], usize::MAX / 2).is_err());
    }
}
