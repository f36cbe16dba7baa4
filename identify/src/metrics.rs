//! How well a model's output matches a measured one: the error figures
//! of `hysteron validate` (RMS, largest error, NRMSE), and the zero-phase
//! Butterworth low-pass that removes measurement noise and rig vibration
//! above a cut-off before they are compared.
//!
//! For a model output `ŷ` and a measured output `y` over the `n` scored
//! samples `i`:
//!
//! * `RMS = √( Σᵢ (ŷᵢ − yᵢ)² / n )`, the root mean square of the error;
//! * `max = maxᵢ |ŷᵢ − yᵢ|`;
//! * `NRMSE = RMS(ŷ − y) / RMS(y)`, with `RMS(y) = √( Σᵢ yᵢ² / n )`: the
//!   measured signal's root mean square *about zero*, not its standard
//!   deviation (an offset in `y` makes the NRMSE smaller, not larger).
//!   `NRMSE = 1` is the error of the model `ŷ = 0`.
//!
//! Root mean squares are computed on values scaled by their largest
//! magnitude, so that squares neither overflow nor underflow.
//!
//! The low-pass ([`Lowpass`]) is a 4th-order Butterworth filter designed
//! and run by the `sci-rs` crate (`butter` as second-order sections, then
//! `sosfiltfilt`, which follow SciPy's functions of the same names): the
//! signal goes through the filter forward, then backward, so the phase
//! shifts cancel and the magnitude response is squared:
//!
//! `|H(f)|² = 1 / (1 + (f/f_c)⁸)` for one pass of the analogue prototype;
//! the digital filter (bilinear transform, cut-off pre-warped) has exactly
//! that with `f/f_c` replaced by `tan(π f/f_s) / tan(π f_c/f_s)`, which
//! equals the analogue form at `f_c` and well below it and attenuates more
//! towards Nyquist. Forward and backward the gain is `|H(f)|²`, with no
//! phase shift. The ends are handled like SciPy's `sosfiltfilt` (odd extension
//! of [`Lowpass::pad_len`] samples, initial conditions at steady state).

use sci_rs::signal::filter::design::{
    butter_dyn, DigitalFilter, FilterBandType, FilterOutputType, Sos,
};
use sci_rs::signal::filter::sosfiltfilt_dyn;

/// The order of the low-pass.
pub const LOWPASS_ORDER: usize = 4;

/// A request the metrics cannot answer.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MetricsError {
    /// Model and measured signals differ in length.
    #[error("the model output has {model} samples, the measured output {measured}")]
    LengthMismatch {
        /// Samples of the model output.
        model: usize,
        /// Samples of the measured output.
        measured: usize,
    },
    /// No samples to score.
    #[error("no samples to score")]
    Empty,
    /// A sample is NaN or infinite.
    #[error("{signal} sample {index} is not finite ({value})")]
    NonFinite {
        /// `"model"`, `"measured"` or `"input"`.
        signal: &'static str,
        /// 0-based sample index.
        index: usize,
        /// The value.
        value: f64,
    },
    /// The measured output is zero throughout: the NRMSE is undefined.
    #[error("the measured output is zero at every scored sample: the NRMSE (relative to its RMS) is undefined")]
    ZeroReference,
    /// The sample rate is not positive and finite.
    #[error("the sample rate {0} Hz must be positive and finite")]
    BadRate(f64),
    /// The cut-off is not positive and finite.
    #[error("the cut-off {0} Hz must be positive and finite")]
    BadCutoff(f64),
    /// The cut-off is not below the Nyquist frequency.
    #[error("the cut-off {cutoff} Hz must be below the Nyquist frequency {nyquist} Hz (half the sample rate)")]
    AboveNyquist {
        /// The cut-off (Hz).
        cutoff: f64,
        /// Half the sample rate (Hz).
        nyquist: f64,
    },
    /// The signal is too short for the forward-backward filter's end
    /// padding.
    #[error("a signal of {len} samples is too short for the zero-phase low-pass (it needs more than {pad} samples)")]
    TooShort {
        /// Samples given.
        len: usize,
        /// [`Lowpass::pad_len`].
        pad: usize,
    },
}

/// Root mean square about zero, `√(Σ xᵢ² / n)`, computed on `x / max|x|`
/// so that squares cannot overflow; 0 for an empty or all-zero signal.
/// Non-finite values give a non-finite result.
pub fn rms(x: &[f64]) -> f64 {
    let scale = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if x.is_empty() || scale == 0.0 {
        return 0.0;
    }
    if !scale.is_finite() || x.iter().any(|v| v.is_nan()) {
        return f64::NAN;
    }
    let sum: f64 = x.iter().map(|v| (v / scale) * (v / scale)).sum();
    scale * (sum / x.len() as f64).sqrt()
}

/// The error figures of a model output against a measured one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorFigures {
    /// Samples scored.
    pub samples: usize,
    /// `RMS(ŷ − y)`.
    pub rms: f64,
    /// `max |ŷ − y|`.
    pub max_abs: f64,
    /// `RMS(ŷ − y) / RMS(y)` (RMS about zero).
    pub nrmse: f64,
}

fn check_finite(signal: &'static str, x: &[f64]) -> Result<(), MetricsError> {
    match x.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(MetricsError::NonFinite {
            signal,
            index,
            value: x.get(index).copied().unwrap_or(f64::NAN),
        }),
        None => Ok(()),
    }
}

/// RMS, largest error and NRMSE of `model` against `measured` (see the
/// module docs for the equations).
///
/// Errors: different lengths, no samples, a non-finite sample (the first,
/// model before measured), a measured signal that is zero throughout.
///
/// ```
/// use hysteron_identify::metrics::errors;
/// // an offset of 1 on a measured signal of RMS 2: NRMSE 0.5
/// let e = errors(&[3.0, -1.0], &[2.0, -2.0]).unwrap();
/// assert_eq!((e.rms, e.max_abs, e.nrmse), (1.0, 1.0, 0.5));
/// ```
pub fn errors(model: &[f64], measured: &[f64]) -> Result<ErrorFigures, MetricsError> {
    if model.len() != measured.len() {
        return Err(MetricsError::LengthMismatch {
            model: model.len(),
            measured: measured.len(),
        });
    }
    if model.is_empty() {
        return Err(MetricsError::Empty);
    }
    check_finite("model", model)?;
    check_finite("measured", measured)?;
    let residual: Vec<f64> = model.iter().zip(measured).map(|(m, y)| m - y).collect();
    // A difference of two finite values may overflow.
    check_finite("model − measured", &residual)?;
    let reference = rms(measured);
    if reference == 0.0 {
        return Err(MetricsError::ZeroReference);
    }
    let rms_err = rms(&residual);
    Ok(ErrorFigures {
        samples: model.len(),
        rms: rms_err,
        max_abs: residual.iter().fold(0.0_f64, |m, r| m.max(r.abs())),
        nrmse: rms_err / reference,
    })
}

/// A 4th-order Butterworth low-pass run forward and backward (zero
/// phase); see the module docs.
#[derive(Debug, Clone)]
pub struct Lowpass {
    cutoff: f64,
    rate: f64,
    sos: Vec<Sos<f64>>,
}

impl Lowpass {
    /// The low-pass at `cutoff_hz` for signals sampled at `rate_hz`.
    ///
    /// Errors: a rate or cut-off that is not positive and finite, a
    /// cut-off not below the Nyquist frequency `rate_hz / 2`.
    pub fn butterworth(cutoff_hz: f64, rate_hz: f64) -> Result<Self, MetricsError> {
        if !(rate_hz.is_finite() && rate_hz > 0.0) {
            return Err(MetricsError::BadRate(rate_hz));
        }
        if !(cutoff_hz.is_finite() && cutoff_hz > 0.0) {
            return Err(MetricsError::BadCutoff(cutoff_hz));
        }
        let nyquist = rate_hz / 2.0;
        // The normalised cut-off must lie strictly inside (0, 1): sci-rs
        // panics otherwise, so it is checked here.
        let wn = cutoff_hz / nyquist;
        if !(wn > 0.0 && wn < 1.0) {
            return Err(MetricsError::AboveNyquist {
                cutoff: cutoff_hz,
                nyquist,
            });
        }
        let sos = match butter_dyn(
            LOWPASS_ORDER,
            vec![wn],
            Some(FilterBandType::Lowpass),
            Some(false),
            Some(FilterOutputType::Sos),
            None,
        ) {
            DigitalFilter::Sos(f) => f.sos,
            // sci-rs returns the format asked for; a design that does not
            // is refused like an impossible cut-off.
            _ => {
                return Err(MetricsError::AboveNyquist {
                    cutoff: cutoff_hz,
                    nyquist,
                })
            }
        };
        Ok(Lowpass {
            cutoff: cutoff_hz,
            rate: rate_hz,
            sos,
        })
    }

    /// The cut-off (Hz).
    pub fn cutoff(&self) -> f64 {
        self.cutoff
    }

    /// The sample rate (Hz).
    pub fn rate(&self) -> f64 {
        self.rate
    }

    /// Samples of odd extension added at each end before filtering
    /// (SciPy's default `3·(2·sections + 1)`, 15 for the 4th order); a
    /// signal must be longer than this.
    pub fn pad_len(&self) -> usize {
        let sections = self.sos.len();
        let zero_b = self.sos.iter().filter(|s| s.b[2] == 0.0).count();
        let zero_a = self.sos.iter().filter(|s| s.a[2] == 0.0).count();
        3 * (2 * sections + 1 - zero_b.min(zero_a))
    }

    /// `x` filtered forward and backward (zero phase), the same length.
    ///
    /// Errors: a signal not longer than [`pad_len`](Self::pad_len), a
    /// non-finite sample.
    pub fn filtfilt(&self, x: &[f64]) -> Result<Vec<f64>, MetricsError> {
        let pad = self.pad_len();
        if x.len() <= pad {
            return Err(MetricsError::TooShort { len: x.len(), pad });
        }
        check_finite("input", x)?;
        Ok(sosfiltfilt_dyn(x.iter(), &self.sos))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    #[test]
    fn figures_by_hand() {
        // model = measured + 0.5 everywhere: RMS 0.5, max 0.5,
        // RMS(measured) = √((1 + 4 + 9 + 16)/4) = √7.5.
        let y = [1.0, -2.0, 3.0, -4.0];
        let m: Vec<f64> = y.iter().map(|v| v + 0.5).collect();
        let e = errors(&m, &y).unwrap();
        assert_eq!(e.samples, 4);
        assert_eq!(e.rms, 0.5);
        assert_eq!(e.max_abs, 0.5);
        assert!((e.nrmse - 0.5 / 7.5_f64.sqrt()).abs() < 1e-15);
        // exact reproduction
        let e = errors(&y, &y).unwrap();
        assert_eq!((e.rms, e.max_abs, e.nrmse), (0.0, 0.0, 0.0));
        // RMS is about zero, not the standard deviation
        assert_eq!(rms(&[3.0, 3.0, 3.0]), 3.0);
        // no overflow in the squares
        assert_eq!(rms(&[1e300, -1e300]), 1e300);
    }

    #[test]
    fn bad_requests_are_errors() {
        assert_eq!(
            errors(&[1.0], &[1.0, 2.0]),
            Err(MetricsError::LengthMismatch {
                model: 1,
                measured: 2
            })
        );
        assert_eq!(errors(&[], &[]), Err(MetricsError::Empty));
        assert!(matches!(
            errors(&[1.0, f64::NAN], &[1.0, 1.0]),
            Err(MetricsError::NonFinite {
                signal: "model",
                index: 1,
                ..
            })
        ));
        assert!(matches!(
            errors(&[1.0, 1.0], &[f64::INFINITY, 1.0]),
            Err(MetricsError::NonFinite {
                signal: "measured",
                index: 0,
                ..
            })
        ));
        assert_eq!(errors(&[1.0], &[0.0]), Err(MetricsError::ZeroReference));
        assert!(matches!(
            Lowpass::butterworth(512.0, 1024.0),
            Err(MetricsError::AboveNyquist { .. })
        ));
        assert!(matches!(
            Lowpass::butterworth(0.0, 1024.0),
            Err(MetricsError::BadCutoff(_))
        ));
        assert!(matches!(
            Lowpass::butterworth(f64::NAN, 1024.0),
            Err(MetricsError::BadCutoff(_))
        ));
        assert!(matches!(
            Lowpass::butterworth(10.0, -1.0),
            Err(MetricsError::BadRate(_))
        ));
        let lp = Lowpass::butterworth(10.0, 1024.0).unwrap();
        assert_eq!(lp.pad_len(), 15);
        assert_eq!(
            lp.filtfilt(&[1.0; 15]),
            Err(MetricsError::TooShort { len: 15, pad: 15 })
        );
        assert_eq!(lp.filtfilt(&[1.0; 16]).unwrap().len(), 16);
        let mut x = vec![1.0; 20];
        x[3] = f64::NAN;
        assert!(matches!(
            lp.filtfilt(&x),
            Err(MetricsError::NonFinite { index: 3, .. })
        ));
    }

    /// The filtered sine `A sin(2π f t)` over the middle half of the
    /// record (away from the end transients): its amplitude and phase
    /// against the input's, by least squares on sin and cos.
    fn gain_and_phase(lp: &Lowpass, f: f64, seconds: f64) -> (f64, f64) {
        let rate = lp.rate();
        let n = (seconds * rate) as usize;
        let t: Vec<f64> = (0..n).map(|i| i as f64 / rate).collect();
        let x: Vec<f64> = t.iter().map(|t| (TAU * f * t).sin()).collect();
        let y = lp.filtfilt(&x).unwrap();
        let (a, b) = (n / 4, 3 * n / 4);
        // project on sin and cos over whole periods only
        let period = (rate / f).round() as usize;
        let b = a + (b - a) / period * period;
        let (mut s, mut c, mut ss, mut cc) = (0.0, 0.0, 0.0, 0.0);
        for i in a..b {
            let (si, ci) = ((TAU * f * t[i]).sin(), (TAU * f * t[i]).cos());
            s += y[i] * si;
            c += y[i] * ci;
            ss += si * si;
            cc += ci * ci;
        }
        let (s, c) = (s / ss, c / cc);
        ((s * s + c * c).sqrt(), c.atan2(s))
    }

    /// `|H_fb(f)| = |H(f)|²` of the digital 4th-order Butterworth low-pass
    /// (bilinear transform with the cut-off pre-warped): the analogue
    /// `1/(1 + (f/f_c)⁸)` with `f/f_c` replaced by
    /// `tan(π f/f_s) / tan(π f_c/f_s)`.
    fn digital_gain(f: f64, fc: f64, rate: f64) -> f64 {
        let r = (std::f64::consts::PI * f / rate).tan() / (std::f64::consts::PI * fc / rate).tan();
        1.0 / (1.0 + r.powi(8))
    }

    /// Analogue `|H(f)|² = 1/(1 + (f/f_c)⁸)`, the forward-backward gain.
    fn analogue_gain(f: f64, fc: f64) -> f64 {
        1.0 / (1.0 + (f / fc).powi(8))
    }

    #[test]
    fn sines_pass_or_are_attenuated_as_the_butterworth_magnitude_says() {
        // 1024 Hz, cut-off 16 Hz; frequencies that divide 1024, so that a
        // period is a whole number of samples.
        let (fc, rate) = (16.0, 1024.0);
        let lp = Lowpass::butterworth(fc, rate).unwrap();
        for (f, seconds) in [
            (1.0, 16.0),
            (2.0, 8.0),
            (16.0, 4.0),
            (32.0, 4.0),
            (64.0, 4.0),
        ] {
            let (g, p) = gain_and_phase(&lp, f, seconds);
            let (digital, analogue) = (digital_gain(f, fc, rate), analogue_gain(f, fc));
            let rel = (g - digital) / digital;
            let rel_analogue = (g - analogue) / analogue;
            eprintln!(
                "f = {f} Hz: gain {g:.6e}, digital {digital:.6e} (rel. error {rel:.1e}), \
                 analogue {analogue:.6e} ({rel_analogue:.1e}), phase {p:.1e} rad"
            );
            // the filter is the Butterworth design: its measured gain is
            // the closed form to 1e-9 relative (measured: ~1e-14), and it has no phase shift
            assert!(rel.abs() < 1e-9, "f = {f}: gain {g:e} vs {digital:e}");
            assert!(p.abs() < 1e-9, "f = {f}: phase {p:e} rad");
        }
        // Well below the cut-off the gain is 1 to 1e-9 (the closed form:
        // 1 − 6e-8 at 2 Hz); well above, the analogue formula holds up to
        // the bilinear warping: r_d = tan(πf/f_s)/tan(πf_c/f_s) exceeds
        // r_a = f/f_c, so the gain lies between analogue·(r_a/r_d)⁸ and
        // analogue (at 64 Hz: (r_d/r_a)⁸ = 1.10, 9 % below).
        let (g, _) = gain_and_phase(&lp, 2.0, 8.0);
        assert!((g - analogue_gain(2.0, fc)).abs() < 1e-9, "{g}");
        let (g, _) = gain_and_phase(&lp, 64.0, 4.0);
        let analogue = analogue_gain(64.0, fc);
        let pi = std::f64::consts::PI;
        let warp = ((pi * 64.0 / rate).tan() / (pi * fc / rate).tan() / (64.0 / fc)).powi(8);
        assert!(
            g < analogue && g > analogue / warp,
            "{g:e} vs {analogue:e}, warp {warp}"
        );
    }

    #[test]
    fn a_constant_passes_unchanged_end_to_end() {
        let lp = Lowpass::butterworth(5.0, 100.0).unwrap();
        let y = lp.filtfilt(&[2.5; 200]).unwrap();
        assert!(y.iter().all(|v| (v - 2.5).abs() < 1e-12), "{y:?}");
    }
}
