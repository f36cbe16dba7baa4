//! The generalized Prandtl-Ishlinskii model, `cascade(envelope, pi_bank)`
//! (examples/specs/generalized-pi.json), and its analytic inverse,
//! `cascade(pi_inverse, envelope_inverse)`
//! (examples/specs/generalized-pi-inverse.json): inverse compensation
//! leaves a residual of rounding on random desired outputs, and the
//! inverse undoes the model on random inputs.
// The no-panic lints of the workspace Cargo.toml are for the library code.
#![allow(clippy::unwrap_used, clippy::indexing_slicing)]

use hysteron::models::Spec;
use hysteron::prelude::*;
use rand::{rngs::StdRng, Rng, SeedableRng};

fn model(name: &str) -> Box<dyn Operator<f64>> {
    let path = format!("{}/examples/specs/{name}.json", env!("CARGO_MANIFEST_DIR"));
    Spec::from_json_file(path).unwrap().build().unwrap()
}

/// A random walk in `[lo, hi]`: steps of up to `step`, reflected at the
/// bounds, with a jump to a uniform point every 50 samples on average.
fn walk(seed: u64, lo: f64, hi: f64, step: f64, n: usize) -> Vec<f64> {
    let mut rng = StdRng::seed_from_u64(seed);
    let mut v = 0.0;
    (0..n)
        .map(|_| {
            if rng.random::<f64>() < 0.02 {
                v = rng.random_range(lo..hi);
            } else {
                v += rng.random_range(-step..step);
                if v > hi {
                    v = 2.0 * hi - v;
                } else if v < lo {
                    v = 2.0 * lo - v;
                }
            }
            v
        })
        .collect()
}

/// The outputs of the major loop at the envelope's saturation: the
/// range a compensator can ask for (the envelope saturates at
/// `1/(b (1 + s))` and `−1/(b (1 − s))`, here 0.96 and −1.79).
fn output_range() -> (f64, f64) {
    let mut m = model("generalized-pi");
    let y = m.run(&[-100.0, 100.0]).unwrap();
    (y[0], y[1])
}

#[test]
fn inverse_compensation_leaves_a_residual_of_rounding() {
    let (lo, hi) = output_range();
    let range = hi - lo;
    let mut worst: f64 = 0.0;
    for seed in 0..20 {
        // desired outputs inside 90 % of the reachable range
        let desired = walk(seed, 0.9 * lo, 0.9 * hi, 0.05 * range, 5_000);
        let command = model("generalized-pi-inverse").run(&desired).unwrap();
        let reached = model("generalized-pi").run(&command).unwrap();
        for (i, (d, y)) in desired.iter().zip(&reached).enumerate() {
            let e = (d - y).abs();
            assert!(e < 1e-9 * range, "seed {seed}, sample {i}: {y} for {d}");
            worst = worst.max(e);
        }
    }
    println!("largest residual {:e} of the range", worst / range);
}

#[test]
fn the_inverse_undoes_the_model() {
    for seed in 0..20 {
        let x = walk(seed, -4.0, 4.0, 0.3, 5_000);
        let y = model("generalized-pi").run(&x).unwrap();
        let back = model("generalized-pi-inverse").run(&y).unwrap();
        for (i, ((a, b), yi)) in x.iter().zip(&back).zip(&y).enumerate() {
            // a rounding error in y moves x by it over the envelope's slope
            // φ'(x) = (1 − T²)/(1 + s T)², T = tanh(b x) (b = 0.8, s = 0.3)
            let t = (0.8 * a).tanh();
            let slope = (1.0 - t * t) / (1.0 + 0.3 * t).powi(2);
            let bound = 64.0 * f64::EPSILON * yi.abs().max(1.0) / slope;
            assert!(
                (a - b).abs() < bound,
                "seed {seed}, sample {i}: {b} for {a}"
            );
        }
    }
}

/// The loops are asymmetric: the envelope saturates sooner above.
#[test]
fn the_saturated_loop_is_asymmetric() {
    let (lo, hi) = output_range();
    assert!(hi > 0.0 && lo < 0.0 && hi < -lo, "{lo} {hi}");
}
