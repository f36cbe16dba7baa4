//! The Jiles-Atherton identification case shared by the fit test and the
//! identification benchmark: a true parameter set, the field of a major
//! and a minor loop, the true response with seeded noise, and a start
//! away from the truth.

use hysteron_models::experiments::through_corners;
use hysteron_operators::{JilesAtherton, JilesAthertonParams, Operator};
use rand::{rngs::StdRng, SeedableRng};
use rand_distr::{Distribution, Normal};

/// The true parameters.
pub fn truth() -> JilesAthertonParams<f64> {
    JilesAthertonParams {
        ms: 1.2,
        a: 0.4,
        k: 0.3,
        c: 0.3,
        alpha: 0.15,
    }
}

/// Two major cycles of amplitude 3, then a minor loop between −0.5 and
/// 1.2 (straight segments, 0.01 apart).
pub fn field() -> Vec<f64> {
    through_corners(&[0.0, 3.0, -3.0, 3.0, -3.0, 1.2, -0.5, 1.2], 0.01).unwrap()
}

/// The truth's response to [`field`], with Gaussian noise of `noise`
/// times its peak (seed 11): the record `(h, m)`.
pub fn record(noise: f64) -> (Vec<f64>, Vec<f64>) {
    let h = field();
    let clean = JilesAtherton::from_params(truth())
        .unwrap()
        .run(&h)
        .unwrap();
    let peak = clean.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    let normal = Normal::new(0.0, noise * peak).unwrap();
    let mut rng = StdRng::seed_from_u64(11);
    let m = clean.iter().map(|v| v + normal.sample(&mut rng)).collect();
    (h, m)
}

/// The start of the fits: the truth scaled by 1.3, 0.7, 1.25, 0.8 and 1.2.
pub fn perturbed_start() -> JilesAtherton<f64> {
    let t = truth();
    JilesAtherton::from_params(JilesAthertonParams {
        ms: t.ms * 1.3,
        a: t.a * 0.7,
        k: t.k * 1.25,
        c: t.c * 0.8,
        alpha: t.alpha * 1.2,
    })
    .unwrap()
}
