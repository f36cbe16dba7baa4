//! Inverse compensation of a hysteretic actuator: a play-type
//! Prandtl-Ishlinskii "actuator" `P`, its analytic inverse `P⁻¹`
//! (Krejčí & Kuhnen) cascaded before it as a feed-forward compensator,
//! tracking a reference signal. Prints the tracking error (max abs and
//! RMS) without compensation, with the exact inverse, and with inverses
//! of mis-identified models (thresholds or weights off by a few percent).
//!
//! Run: `cargo run --release --example compensation`

use hysteron::composition::PiBankParams;
use hysteron::prelude::*;
use std::f64::consts::TAU;

/// `(max |e|, RMS e)` of the tracking error `e = y − r`.
fn errors(y: &[f64], reference: &[f64]) -> (f64, f64) {
    let (mut max, mut sq) = (0.0_f64, 0.0);
    for (y, r) in y.iter().zip(reference) {
        let e = y - r;
        max = max.max(e.abs());
        sq += e * e;
    }
    (max, (sq / y.len() as f64).sqrt())
}

/// A bank's parameters with the initial play outputs that the input
/// history `0 → −1.2 → 0` leaves (reachable states, as the analytic
/// inverse requires).
fn after_history(a0: f64, r: Vec<f64>, w: Vec<f64>) -> Result<PiBankParams<f64>> {
    let mut bank = PiBank::new(a0, r.clone(), w.clone())?;
    bank.run(&[-1.2, 0.0])?;
    Ok(PiBankParams {
        a0,
        r,
        w,
        y0: bank.play_outputs().to_vec(),
    })
}

fn main() -> Result<()> {
    // The actuator: a linear part and ten plays, starting from a
    // magnetized state (the play outputs left by an earlier excursion to
    // −1.2 and back to 0).
    let r: Vec<f64> = (1..=10).map(|j| 0.12 * j as f64).collect();
    let w: Vec<f64> = r.iter().map(|r| 0.9 * (-2.0 * r).exp()).collect();
    let actuator_params = after_history(0.25, r, w)?;
    let actuator = PiBank::from_params(actuator_params.clone())?;

    // The reference: two tones with a slowly growing envelope, from 0.
    let n = 4000;
    let reference: Vec<f64> = (0..n)
        .map(|i| {
            let t = i as f64 / 1000.0;
            let envelope = 0.5 + 0.5 * t / 4.0;
            envelope * (1.4 * (TAU * t).sin() + 0.4 * (TAU * 3.3 * t).sin())
        })
        .collect();

    // Without compensation: the reference scaled by the inverse of the
    // actuator's large-signal slope a0 + Σ w_j (all plays moving).
    let slope = actuator_params.a0 + actuator_params.w.iter().sum::<f64>();
    let mut plain = Gain::new(1.0 / slope)?.then(actuator.clone());
    let (max, rms) = errors(&plain.run(&reference)?, &reference);
    println!(
        "{:<56} max |e| {max:>10.3e}   RMS {rms:>10.3e}",
        "no compensator (gain 1/(a0 + Σ w))"
    );

    // With the analytic inverse as the compensator.
    let compensator = actuator.analytic_inverse()?;
    let mut loop_ = compensator.clone().then(actuator.clone());
    let (max, rms) = errors(&loop_.run(&reference)?, &reference);
    println!(
        "{:<56} max |e| {max:>10.3e}   RMS {rms:>10.3e}",
        "exact analytic inverse"
    );
    let exact_max = max;

    // With inverses of mis-identified models (their initial state is what
    // the same history leaves in the wrong model).
    let perturbed = [
        ("weights +5 %", 1.0, 1.05, 1.0),
        ("weights −5 %", 1.0, 0.95, 1.0),
        ("thresholds +5 %", 1.05, 1.0, 1.0),
        ("thresholds −10 %", 0.9, 1.0, 1.0),
        ("a0 +10 %", 1.0, 1.0, 1.1),
        ("initial state forgotten (y0 = 0)", 1.0, 1.0, 1.0),
    ];
    for (i, (label, rs, ws, a0s)) in perturbed.iter().enumerate() {
        let mut p = after_history(
            actuator_params.a0 * a0s,
            actuator_params.r.iter().map(|r| r * rs).collect(),
            actuator_params.w.iter().map(|w| w * ws).collect(),
        )?;
        if i == perturbed.len() - 1 {
            p.y0.clear();
        }
        let wrong = PiInverse::from_params(p)?;
        let mut loop_ = wrong.then(actuator.clone());
        let (max, rms) = errors(&loop_.run(&reference)?, &reference);
        println!(
            "{:<56} max |e| {max:>10.3e}   RMS {rms:>10.3e}   ({:.1e} × exact)",
            format!("inverse of a model with {label}"),
            max / exact_max.max(f64::MIN_POSITIVE)
        );
    }
    Ok(())
}
