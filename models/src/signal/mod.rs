//! Signal processing for records sampled at a data rate and simulated at a
//! finer integration rate, as the Bouc-Wen benchmark's reference does:
//!
//! * [`fft_upsample`]: band-limited (trigonometric) interpolation of one
//!   period of a periodic record onto a `q` times finer grid, exact for a
//!   multisine;
//! * [`upsample_polyphase`]: band-limited interpolation of a record that is
//!   not periodic (a sine sweep, a record from rest), by a Kaiser-windowed
//!   sinc in polyphase form;
//! * [`Upsampling`]: the choice between the two, and [`RecordKind`]: what a
//!   record holds (one steady-state period, or a record from rest);
//! * [`decimate_fir`] and [`decimate_fir_periodic`]: MATLAB's
//!   `decimate(x, r, 'fir')`, applied stage by stage after a
//!   [`DecimationPlan`] (`2·2·5` or a single `20`), to a record with two
//!   ends or to one period of a periodic one, so a simulation on the fine
//!   grid can be decimated exactly as published data were.

pub mod decimate;
pub mod fft;
pub mod polyphase;

pub use decimate::{
    decimate_fir, decimate_fir_periodic, fir1_lowpass, DecimationPlan, PlanError, DECIMATE_ORDER,
};
pub use fft::fft_upsample;
pub use polyphase::{interpolation_filter, upsample_polyphase, KAISER_BETA, SIDE_SAMPLES};

use hysteron_operators::{Error, Result};
use serde::{Deserialize, Serialize};

/// How a record's input is interpolated onto the integration grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Upsampling {
    /// [`fft_upsample`]: exact for a record of whole periods of a periodic
    /// input (a multisine), wrong at the ends of any other.
    Fft,
    /// [`upsample_polyphase`]: for a record that is not periodic; the
    /// record is taken to hold its end values beyond its ends.
    Polyphase,
}

impl Upsampling {
    /// Upsamples `x` by `q`.
    pub fn upsample(self, x: &[f64], q: usize) -> Result<Vec<f64>> {
        match self {
            Upsampling::Fft => fft_upsample(x, q),
            Upsampling::Polyphase => upsample_polyphase(x, q),
        }
    }
}

/// What a record holds, which decides how it is upsampled, simulated and
/// decimated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RecordKind {
    /// One period of a periodic input in steady state (a multisine):
    /// upsampled by [`fft_upsample`], simulated period after period until
    /// the response repeats, decimated circularly.
    Periodic,
    /// A record that starts from rest and is not periodic (a sine sweep, a
    /// transient): upsampled by [`upsample_polyphase`], simulated once from
    /// the rest state, decimated with MATLAB's end handling.
    FromRest,
}

impl RecordKind {
    /// How this kind of record is upsampled.
    pub fn upsampling(self) -> Upsampling {
        match self {
            RecordKind::Periodic => Upsampling::Fft,
            RecordKind::FromRest => Upsampling::Polyphase,
        }
    }

    /// Decimates `x` after `plan` the way this kind of record needs.
    pub fn decimate(self, x: &[f64], plan: &DecimationPlan) -> Result<Vec<f64>> {
        match self {
            RecordKind::Periodic => decimate_fir_periodic(x, plan),
            RecordKind::FromRest => decimate_fir(x, plan),
        }
    }
}

fn invalid(name: &str, value: f64, reason: &'static str) -> Error {
    Error::InvalidParameter {
        name: name.into(),
        value,
        reason,
    }
}

/// A record must hold at least one sample, each finite.
fn check_record(x: &[f64]) -> Result<()> {
    if x.is_empty() {
        return Err(invalid("x", 0.0, "must hold at least one sample"));
    }
    match x.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        Some((i, &value)) => Err(Error::NonFiniteInput { value }.at_sample(i)),
        None => Ok(()),
    }
}

#[cfg(test)]
mod test_signals {
    use std::f64::consts::PI;

    /// A sum of sines `(harmonic, amplitude, phase)` over one period of
    /// `len` samples. The phase `h·j/len` is reduced exactly (integers)
    /// before the sine, so the reference itself is accurate to rounding.
    pub fn multisine(harmonics: &[(usize, f64, f64)], len: usize) -> Vec<f64> {
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

    pub fn max_diff(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    }
}
