//! 4K aliasing, the hypothesis of the performance issue for the MMS
//! kernel's bimodality: the kernel (`F_c = 1`, `K = 5`, the input of
//! `hysteron bench`, 2^16 samples) reading its input from one buffer and
//! writing its output to another placed at a chosen byte offset from the
//! input modulo 4 KiB (0: the low 12 address bits of `x_i` and `y_i`
//! coincide, as for two page-aligned allocations). If stores to `y_i`
//! falsely alias loads of later `x_j`, offset 0 (and small ones) would be
//! slower than the others. Run with `cargo bench --bench aliasing`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use hysteron::prelude::*;
use std::f64::consts::TAU;
use std::hint::black_box;
use std::time::Duration;

const N: usize = 1 << 16;

fn mms_output_offsets(c: &mut Criterion) {
    let x: Vec<f64> = (0..N)
        .map(|i| {
            let i = i as f64;
            2.5 * (TAU * i / 2000.0).sin() + 0.3 * (TAU * i / 97.3).sin()
        })
        .collect();
    // One arena for both buffers: the input starts 4 KiB-aligned; N·8
    // bytes is a multiple of 4 KiB, so the output starts `offset` bytes
    // past an aligned address.
    let mut arena = vec![0.0f64; 2 * N + 1024];
    let misalign = arena.as_ptr() as usize % 4096;
    let start = (4096 - misalign) % 4096 / 8;
    let mut op = Mms::new(1.0, 5.0).expect("kernel");
    let mut g = c.benchmark_group("aliasing");
    g.sample_size(20)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1))
        .throughput(Throughput::Elements(N as u64));
    for offset in [0usize, 8, 64, 512, 2048, 4088] {
        let (a, b) = arena.split_at_mut(start + N + offset / 8);
        let xs = &mut a[start..start + N];
        xs.copy_from_slice(&x);
        let ys = &mut b[..N];
        g.bench_with_input(
            BenchmarkId::new("mms_output_offset", offset),
            &offset,
            |bch, _| {
                bch.iter(|| {
                    op.reset();
                    op.process(black_box(&*xs), &mut *ys).expect("process");
                    black_box(&mut *ys);
                })
            },
        );
    }
    g.finish();
}

criterion_group!(benches, mms_output_offsets);
criterion_main!(benches);
