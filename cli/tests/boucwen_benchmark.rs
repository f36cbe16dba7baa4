//! The Bouc-Wen hysteretic benchmark (Noël & Schoukens 2016): the published
//! system, composed as `MassSpringDamper.feedback(BoucWen)` and integrated
//! at 15 kHz on the band-limited (FFT) upsampled validation multisine,
//! reproduces the published steady-state output.
//!
//! Measured (release and test profile alike): RMS error 5.6e-8 m when the
//! 15 kHz response is decimated as the reference's was (MATLAB
//! `decimate(·, 'fir')` by 2, 2, 5), 2.1e-7 m picking every 20th sample,
//! against an output RMS of 6.67e-4 m. The remaining error is the
//! integration of the Bouc-Wen state: exact along each step's displacement
//! increment here, the trapezoidal rule in time in the reference (with that
//! rule instead, the same pipeline matches the data to 1e-15 m).

use hysteron::models::benchmark::{
    boucwen_system, boucwen_system_at_data_rate, periodic_steady_state, BoucWenBenchmarkParams,
};
use hysteron::models::signal::{decimate_fir_periodic, fft_upsample};
use hysteron_cli::csvio::read_columns;
use std::path::Path;

/// The threshold on the simulation RMS error (m).
const THRESHOLD: f64 = 1e-6;

fn validation_data() -> (Vec<f64>, Vec<f64>) {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/boucwen-benchmark/val_multisine.csv");
    let mut c = read_columns(&path, &["t", "u", "y"]).expect("val_multisine.csv");
    assert_eq!(c.values[0].len(), 8192);
    // 750 Hz
    assert!((c.values[0][1] - 1.0 / 750.0).abs() < 1e-15);
    let y = c.values.pop().unwrap();
    let u = c.values.pop().unwrap();
    (u, y)
}

fn rms(v: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x * x, n + 1));
    (sum / n as f64).sqrt()
}

fn rms_error(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    rms(a.iter().zip(b).map(|(a, b)| a - b))
}

#[test]
fn simulation_error_on_val_multisine() {
    let (u, y_ref) = validation_data();
    let y_rms = rms(y_ref.iter().copied());
    assert!((y_rms - 6.67e-4).abs() < 0.005e-4, "output rms {y_rms:e}");

    let p = BoucWenBenchmarkParams::published();
    let u_fine = fft_upsample(&u, p.upsample).unwrap();
    // The upsampled input keeps the data's samples.
    for (a, b) in u_fine.iter().step_by(p.upsample).zip(&u) {
        assert!((a - b).abs() < 1e-12);
    }
    let mut system = boucwen_system(&p).unwrap();
    let response = periodic_steady_state(&mut system, &u_fine, 1e-12, 6).unwrap();
    assert!(
        response.converged && response.periods <= 4,
        "steady state: {} periods, change {:e}",
        response.periods,
        response.change
    );

    let decimated = decimate_fir_periodic(&response.output, p.upsample).unwrap();
    let e = rms_error(&decimated, &y_ref);
    println!("simulation rms {e:.3e} m (decimated as the reference)");
    assert!(e <= THRESHOLD, "simulation rms {e:e} m");

    let picked: Vec<f64> = response
        .output
        .iter()
        .step_by(p.upsample)
        .copied()
        .collect();
    let e = rms_error(&picked, &y_ref);
    println!("simulation rms {e:.3e} m (every 20th sample)");
    assert!(e <= THRESHOLD, "simulation rms, every 20th sample: {e:e} m");
}

/// At the data rate through `Oversample`, the input is interpolated
/// linearly between samples: not band-limited, so the response is less
/// accurate (measured 7.3e-6 m), though still far below the published
/// black-box models' errors (1.87e-5 m and more).
#[test]
fn oversampled_at_the_data_rate() {
    let (u, y_ref) = validation_data();
    let p = BoucWenBenchmarkParams::published();
    let mut system = boucwen_system_at_data_rate(&p).unwrap();
    let response = periodic_steady_state(&mut system, &u, 1e-12, 6).unwrap();
    assert!(response.converged);
    let e = rms_error(&response.output, &y_ref);
    println!("oversampled simulation rms {e:.3e} m");
    assert!(e > 2e-6 && e < 1.5e-5, "{e:e}");
}
