//! Throughput of the elementary operators and of a composed model.
//!
//! Every benchmark runs `reset()` + `process()` over the same precomputed
//! input of `N` samples, `x_i = 2.5 sin(2π i/2000) + 0.3 sin(2π i/97.3)`,
//! into a preallocated output buffer, so the time per iteration divided by
//! `N` is the cost per sample (reported by criterion as elements/s).
//!
//! Run with `cargo bench --bench operators`.

use criterion::measurement::WallTime;
use criterion::{criterion_group, criterion_main, BenchmarkGroup, Criterion, Throughput};
use hysteron::prelude::*;
use std::f64::consts::TAU;
use std::hint::black_box;
use std::time::Duration;

/// Samples per iteration.
const N: usize = 100_000;

/// Gap of the composed model's friction element (total travel).
const GAP: f64 = 0.3;

fn input() -> Vec<f64> {
    (0..N)
        .map(|i| {
            let i = i as f64;
            2.5 * (TAU * i / 2000.0).sin() + 0.3 * (TAU * i / 97.3).sin()
        })
        .collect()
}

/// Benchmarks `op.reset(); op.process(x, y)` under `id` in group `g`.
fn bench_op<O: Operator<f64>>(
    g: &mut BenchmarkGroup<'_, WallTime>,
    id: &str,
    mut op: O,
    x: &[f64],
    y: &mut [f64],
) {
    // One untimed run: fail loudly on an error instead of timing it.
    op.reset();
    op.process(x, y)
        .unwrap_or_else(|e| panic!("{id}: process failed: {e}"));
    g.bench_function(id, |b| {
        b.iter(|| {
            op.reset();
            let r = op.process(black_box(x), &mut *y);
            black_box(r).expect("process");
            black_box(&mut *y);
        })
    });
}

/// A PI bank of `m` plays: `r_j = 3j/m`, `w_j = exp(−r_j)/m`, `a0 = 0.1`.
fn pi_bank(m: usize) -> PiBank<f64> {
    let r: Vec<f64> = (0..m).map(|j| 3.0 * j as f64 / m as f64).collect();
    let w: Vec<f64> = r.iter().map(|&r| (-r).exp() / m as f64).collect();
    PiBank::new(0.1, r, w).expect("valid PI bank")
}

/// MMS friction (`F_c = 2`, `K = 40`) in series with a Bouc-Wen spring of
/// stiffness 8..14 (3 knots), the friction travel limited to a gap of
/// [`GAP`]. For the benchmark input (|x| ≤ 2.8, spring force up to ~25)
/// the friction element both slides inside the gap and sits at the stops.
fn composed() -> MechanicalSeries<f64, Mms<f64>, BoucWen<f64>> {
    let stiffness =
        StiffnessMap::new(vec![0.0, 0.5, 1.5], vec![8.0, 10.0, 14.0]).expect("valid knots");
    let spring = BoucWen::from_params(BoucWenParams {
        w: 0.5,
        alpha: 1.0,
        beta: 0.6,
        gamma: 0.4,
        n: 1.0,
        h0: 0.0,
        z0: 0.0,
        stiffness,
    })
    .expect("valid Bouc-Wen");
    Mms::new(2.0, 40.0)
        .expect("valid MMS")
        .series(spring)
        .with_limits(TravelLimits::Gap { b: GAP, r0: 0.0 })
        .expect("valid gap")
}

/// Checks (untimed) that the composed model really visits both regimes for
/// the benchmark input: friction travel strictly inside the gap, and at a stop.
fn check_composed_regimes(x: &[f64]) {
    let mut m = composed();
    let (mut inside, mut at_stop) = (0usize, 0usize);
    for &xi in x {
        m.trial(xi).expect("composed trial");
        m.commit();
        if m.left_displacement().abs() >= 0.5 * GAP {
            at_stop += 1;
        } else {
            inside += 1;
        }
    }
    eprintln!(
        "composed model: {inside} samples inside the gap, {at_stop} at a stop (of {})",
        x.len()
    );
    assert!(inside > 0 && at_stop > 0, "composed model misses a regime");
}

fn benches(c: &mut Criterion) {
    let x = input();
    let mut y = vec![0.0; N];
    let elements = Throughput::Elements(N as u64);

    {
        let mut g = c.benchmark_group("play");
        g.throughput(elements.clone());
        bench_op(&mut g, "r=0.5", Play::new(0.5).expect("play"), &x, &mut y);
        g.finish();
    }
    {
        let mut g = c.benchmark_group("mms");
        g.throughput(elements.clone());
        bench_op(
            &mut g,
            "fc=1,k=5",
            Mms::new(1.0, 5.0).expect("mms"),
            &x,
            &mut y,
        );
        g.finish();
    }
    {
        let mut g = c.benchmark_group("pi64");
        g.throughput(elements.clone());
        bench_op(&mut g, "m=64", pi_bank(64), &x, &mut y);
        g.finish();
    }
    {
        let mut g = c.benchmark_group("pi_size");
        g.throughput(elements.clone());
        for m in [16, 64, 256, 1024] {
            bench_op(&mut g, &format!("m={m}"), pi_bank(m), &x, &mut y);
        }
        g.finish();
    }
    {
        let mut g = c.benchmark_group("bouc_wen");
        g.throughput(elements.clone());
        for n in [1.0, 1.5] {
            let op = BoucWen::constant(1.0, 0.1, 1.0, 0.7, 0.3, n).expect("bouc-wen");
            bench_op(&mut g, &format!("n={n}"), op, &x, &mut y);
        }
        g.finish();
    }
    {
        check_composed_regimes(&x);
        let mut g = c.benchmark_group("composed_mms_series_bw_gap");
        g.throughput(elements);
        bench_op(&mut g, "static", composed(), &x, &mut y);
        bench_op(&mut g, "boxed", composed().boxed(), &x, &mut y);
        g.finish();
    }
}

criterion_group! {
    name = operators;
    config = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    targets = benches
}
criterion_main!(operators);
