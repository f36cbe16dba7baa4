//! Throughput of the elementary operators and of composed models, on the
//! kernels of `hysteron bench` (defined once, in [`hysteron_cli::bench`]).
//!
//! Every benchmark runs `reset()` + `process()` over the same precomputed
//! input of `N` samples, `x_i = 2.5 sin(2π i/2000) + 0.3 sin(2π i/97.3)`,
//! into a preallocated output buffer, so the time per iteration divided by
//! `N` is the cost per sample (reported by criterion as elements/s). `N` is
//! 10⁵ here (the buffers stay in cache); `hysteron bench` times the same
//! kernels on 10⁷ samples.
//!
//! Run with `cargo bench --bench operators`.

use criterion::measurement::WallTime;
use criterion::{criterion_group, criterion_main, BenchmarkGroup, Criterion, Throughput};
use hysteron::prelude::*;
use hysteron_cli::bench::{
    bouc_wen, kernel_input, mms, paper_model, paper_model_from_json, pi_bank, play, BW15_RTOL,
};
use std::hint::black_box;
use std::time::Duration;

/// Samples per iteration.
const N: usize = 100_000;

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

/// Checks (untimed) that the paper model really visits both regimes for
/// the benchmark input: slider strictly inside the gap, and at a stop.
fn check_paper_model_regimes(x: &[f64]) {
    let mut m = paper_model().expect("paper model");
    let half_gap = 0.5 * hysteron::models::TransmissionParams::default().backlash;
    let (mut inside, mut at_stop) = (0usize, 0usize);
    for &xi in x {
        m.trial(xi).expect("paper model trial");
        m.commit();
        if m.left_displacement().abs() >= half_gap {
            at_stop += 1;
        } else {
            inside += 1;
        }
    }
    eprintln!(
        "paper model: {inside} samples inside the gap, {at_stop} at a stop (of {})",
        x.len()
    );
    assert!(inside > 0 && at_stop > 0, "paper model misses a regime");
}

fn benches(c: &mut Criterion) {
    let x = kernel_input(N);
    let mut y = vec![0.0; N];
    let elements = Throughput::Elements(N as u64);

    {
        let mut g = c.benchmark_group("play");
        g.throughput(elements.clone());
        bench_op(&mut g, "r=0.5", play().expect("play"), &x, &mut y);
        g.finish();
    }
    {
        let mut g = c.benchmark_group("mms");
        g.throughput(elements.clone());
        bench_op(&mut g, "fc=1,k=5", mms().expect("mms"), &x, &mut y);
        g.finish();
    }
    {
        let mut g = c.benchmark_group("pi_size");
        g.throughput(elements.clone());
        for m in [10, 16, 37, 64, 256, 1024] {
            let bank = pi_bank(m).expect("pi bank");
            bench_op(&mut g, &format!("m={m}"), bank, &x, &mut y);
        }
        g.finish();
    }
    {
        let mut g = c.benchmark_group("bouc_wen");
        g.throughput(elements.clone());
        bench_op(&mut g, "n=1", bouc_wen(1.0).expect("bouc_wen"), &x, &mut y);
        let bw15 = bouc_wen(1.5)
            .and_then(|b| b.with_tolerance(BW15_RTOL))
            .expect("bouc_wen");
        bench_op(&mut g, "n=1.5", bw15.clone(), &x, &mut y);
        let adaptive = bw15.with_solver(StateSolver::Adaptive);
        bench_op(&mut g, "n=1.5 adaptive", adaptive, &x, &mut y);
        g.finish();
    }
    {
        // The cost of tabulating the flow (once per parameter set, e.g. at
        // every `set_params` of a fit), default tolerance 1e-10. Each thread
        // keeps its last four tables: every iteration moves `n` by a few ulps
        // (1024 exponents in turn), so that each one builds a table.
        let mut g = c.benchmark_group("bouc_wen_table_build");
        for n in [1.5, 2.7, 8.0] {
            assert!(bouc_wen(n).expect("bouc_wen").is_tabulated());
            let mut k = 0u64;
            g.bench_function(format!("n={n}"), |b| {
                b.iter(|| {
                    k = (k + 1) % 1024;
                    let n = f64::from_bits(n.to_bits() + k);
                    black_box(bouc_wen(black_box(n)).expect("bouc_wen"))
                })
            });
        }
        g.finish();
    }
    {
        check_paper_model_regimes(&x);
        let mut g = c.benchmark_group("paper_model");
        g.throughput(elements);
        bench_op(
            &mut g,
            "static",
            paper_model().expect("paper model"),
            &x,
            &mut y,
        );
        bench_op(
            &mut g,
            "boxed",
            paper_model().expect("paper model").boxed(),
            &x,
            &mut y,
        );
        let json = paper_model_from_json().expect("paper model from JSON");
        bench_op(&mut g, "from_json", json, &x, &mut y);
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
