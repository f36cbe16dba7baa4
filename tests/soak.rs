//! Ten million random samples through every registered leaf at its
//! example parameters: no hang, no non-finite output, no error. Ignored by
//! default (minutes in a release build); run with
//! `cargo test --release --test soak -- --ignored --nocapture`, which
//! prints each leaf's time.
// The no-panic lints of the workspace Cargo.toml are for the library code.
#![allow(clippy::unwrap_used)]

use hysteron::models::spec::registry::LEAVES;
use rand::{rngs::StdRng, Rng, SeedableRng};
use std::time::Instant;

const SAMPLES: usize = 10_000_000;
const BLOCK: usize = 100_000;

/// A random walk in `[−3, 3]` (steps of up to 0.1, reflected at the
/// bounds), with a jump to a uniform point every 1000 samples on average
/// and a repeated sample every 100.
fn block(rng: &mut StdRng, x: &mut f64, out: &mut [f64]) {
    for v in out.iter_mut() {
        let r: f64 = rng.random();
        if r < 1e-3 {
            *x = rng.random_range(-3.0..3.0);
        } else if r > 0.01 {
            *x += rng.random_range(-0.1..0.1);
            if x.abs() > 3.0 {
                *x = x.signum() * 6.0 - *x;
            }
        }
        *v = *x;
    }
}

#[test]
#[ignore = "minutes in a release build: run on demand"]
fn ten_million_random_samples_through_every_leaf() {
    for leaf in LEAVES {
        let mut op = leaf.build(&leaf.example()).unwrap();
        let mut rng = StdRng::seed_from_u64(2026);
        let (mut x, mut xs, mut ys) = (0.0, vec![0.0; BLOCK], vec![0.0; BLOCK]);
        let start = Instant::now();
        for b in 0..SAMPLES / BLOCK {
            block(&mut rng, &mut x, &mut xs);
            op.process(&xs, &mut ys)
                .unwrap_or_else(|e| panic!("{}: block {b}: {e}", leaf.kind()));
            assert!(
                ys.iter().all(|y| y.is_finite()),
                "{}: block {b}",
                leaf.kind()
            );
        }
        println!(
            "{:<22} {SAMPLES} samples in {:.2} s",
            leaf.kind(),
            start.elapsed().as_secs_f64()
        );
    }
}
