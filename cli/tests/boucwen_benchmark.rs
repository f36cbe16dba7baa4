//! The Bouc-Wen hysteretic benchmark (Noël & Schoukens 2016): the published
//! system, composed as `MassSpringDamper.feedback(BoucWen)` and integrated
//! at 15 kHz on the band-limited (FFT) upsampled validation multisine,
//! reproduces the published steady-state output; and a record that is not
//! periodic (a sine sweep from rest, decimated in one 20× stage) is
//! reproduced by the same pipeline with polyphase upsampling and the
//! record's decimation plan.
//!
//! Measured (release and test profile alike): RMS error 5.6e-8 m when the
//! 15 kHz response is decimated as the reference's was (MATLAB
//! `decimate(·, 'fir')` by 2, 2, 5), 2.1e-7 m picking every 20th sample,
//! against an output RMS of 6.67e-4 m. The remaining error is the
//! integration of the Bouc-Wen state: exact along each step's displacement
//! increment here, the trapezoidal rule in time in the reference (with that
//! rule instead, the same pipeline matches the data to 1e-15 m).

use hysteron::models::benchmark::{
    boucwen_system, boucwen_system_at_data_rate, periodic_steady_state, simulate_record,
    BoucWenBenchmarkParams,
};
use hysteron::models::operators::Operator;
use hysteron::models::signal::{decimate_fir, fft_upsample, DecimationPlan, RecordKind};
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
    let plan: DecimationPlan = "2,2,5".parse().unwrap();
    let response = simulate_record(&p, &u, RecordKind::Periodic, &plan).unwrap();
    assert!(
        response.converged && response.periods <= 4,
        "steady state: {} periods",
        response.periods,
    );

    let e = rms_error(&response.decimated, &y_ref);
    println!("simulation rms {e:.3e} m (decimated as the reference)");
    assert!(e <= THRESHOLD, "simulation rms {e:e} m");

    let e = rms_error(&response.picked, &y_ref);
    println!("simulation rms {e:.3e} m (every 20th sample)");
    assert!(e <= THRESHOLD, "simulation rms, every 20th sample: {e:e} m");
}

/// A linear sine sweep `u = A sin(2π (f0 t + (f1 − f0) t² / 2T))`, sampled
/// at 15 kHz from `t = 0`.
fn sweep(a: f64, f0: f64, f1: f64, duration: f64, rate: f64) -> Vec<f64> {
    let n = (duration * rate).round() as usize;
    (0..n)
        .map(|i| {
            let t = i as f64 / rate;
            let phase = f0 * t + (f1 - f0) * t * t / (2.0 * duration);
            a * (std::f64::consts::TAU * phase.fract()).sin()
        })
        .collect()
}

/// A record that is not periodic, made as the benchmark's sine-sweep
/// validation record was: a 40 N linear sweep from 18 to 52 Hz over 204 s
/// through the published system at 15 kHz from rest, the input kept at
/// every 20th sample, the output decimated by MATLAB's `decimate(·, 20,
/// 'fir')` in one stage. The pipeline sees only the 750 Hz record: it
/// upsamples `u` (polyphase, band-limited), simulates from rest and
/// decimates with the record's plan. Measured (test profile): 9.6e-9 m
/// against an output RMS of 6.6e-4 m; with the wrong plan (2,2,5)
/// 2.3e-6 m, with the periodic (FFT) upsampling 5.2e-6 m.
#[test]
fn simulation_of_a_non_periodic_sweep_with_its_decimation_plan() {
    let p = BoucWenBenchmarkParams::published();
    let rate = p.fs * p.upsample as f64;
    let u_fine = sweep(40.0, 18.0, 52.0, 204.0, rate);
    let y_fine = boucwen_system(&p).unwrap().run(&u_fine).unwrap();
    let twenty = DecimationPlan::single(20).unwrap();
    let u: Vec<f64> = u_fine.iter().step_by(p.upsample).copied().collect();
    let y_ref = decimate_fir(&y_fine, &twenty).unwrap();
    assert_eq!((u.len(), y_ref.len()), (153_000, 153_000));
    let y_rms = rms(y_ref.iter().copied());

    let response = simulate_record(&p, &u, RecordKind::FromRest, &twenty).unwrap();
    let e = rms_error(&response.decimated, &y_ref);
    println!("sweep: simulation rms {e:.3e} m, output rms {y_rms:.3e} m");
    assert!(e <= THRESHOLD, "simulation rms {e:e} m");

    let wrong_plan = simulate_record(&p, &u, RecordKind::FromRest, &"2,2,5".parse().unwrap())
        .unwrap()
        .decimated;
    let e_plan = rms_error(&wrong_plan, &y_ref);
    let periodic = simulate_record(&p, &u, RecordKind::Periodic, &twenty).unwrap();
    let e_fft = rms_error(&periodic.decimated, &y_ref);
    println!("sweep: with the plan 2,2,5 {e_plan:.3e} m, upsampled as periodic {e_fft:.3e} m");
    assert!(
        e_plan > 10.0 * e && e_fft > 10.0 * e,
        "{e_plan:e} {e_fft:e}"
    );
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
