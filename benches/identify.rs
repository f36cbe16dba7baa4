//! Cost of identification: one model evaluation over a record, and whole
//! Levenberg-Marquardt fits.
//!
//! * `paper_model_eval`: one run (`reset` + `process`) of the paper's
//!   model, `TransmissionParams::default().build()`, over `N = 20 000`
//!   samples of a decaying sine (throughput: samples);
//! * `paper_model_dual_pass`: its derivatives with respect to the three
//!   parameters stage 2 of the paper's identification fits (`limits.b`,
//!   `f_c`, `K`), one pass over dual numbers;
//! * `bouc_wen_fit_5`: a fit of 5 parameters of a Bouc-Wen spring with a
//!   constant stiffness (`stiffness.s[0]`, `w`, `beta`, `gamma`, `n`) to
//!   `N` samples of its response to a decaying sine with 1 % Gaussian noise
//!   (fixed seed), starting from values perturbed by ±20 %; one iteration
//!   is one whole fit (throughput: samples of the record);
//! * `bouc_wen_eval`: one run of that spring (at the true parameters) over
//!   the record, the unit the fit's cost is made of;
//! * `bouc_wen_dual_pass`: the derivatives of that run with respect to the
//!   5 fitted parameters (one pass over dual numbers, what a fit's
//!   Jacobian costs);
//! * `paper_two_stages`: [`identify_paper`] on records of the paper's model
//!   sampled at 250 Hz (a 0.5 Hz major loop, 2 cycles, 2001 samples; the
//!   5 → 0.1 Hz down-chirp over 20 s, 5001 samples), with the truth's
//!   spring `n = 1.5`, `h0 = 0.1` and a start 20 % off in backlash, `F_c`
//!   and `K` (throughput: samples of both records);
//! * `benchmark_system_eval` and `benchmark_system_dual_pass`: the
//!   Bouc-Wen benchmark system (`feedback` of `mass_spring_damper` and
//!   `bouc_wen`) at the start the benchmark identification takes from
//!   `train_multisine` (`start_from_data`, `n = 1.5`), run over the
//!   record's first period (8192 samples at 750 Hz) upsampled 20× to
//!   15 kHz: one simulation, and the derivatives with respect to the seven
//!   parameters the identification fits (the two units its cost is made
//!   of; throughput: samples at 15 kHz).
//!
//! * `jiles_atherton_fit_5`: a fit of all five parameters of the
//!   Jiles-Atherton model (`ms`, `a`, `k`, `c`, `alpha`) to its response,
//!   with 1 % Gaussian noise (fixed seed), to two major cycles and a minor
//!   loop (1 540 samples), from a start 20–30 % off (as
//!   identify/tests/jiles_atherton_fit.rs; throughput: samples);
//!
//! * `speculation`: the paper's two stages and a bounded benchmark-system
//!   fit, each with its dual passes started beside its simulations on a
//!   second core and without (see the function).
//!
//! Small sample sizes and short measurement times keep the whole run
//! within a few minutes. Run with `cargo bench --bench identify`.

use criterion::measurement::WallTime;
use criterion::{criterion_group, criterion_main, BenchmarkGroup, Criterion, Throughput};
use hysteron::identify::benchmark::{start_from_data, FREE as BENCHMARK_FREE};
use hysteron::identify::paper::{identify_paper, PaperIdentification, PaperOptions};
use hysteron::identify::{fit, free_by_names, FitOptions};
use hysteron::models::benchmark::boucwen_system;
use hysteron::models::experiments::{chirp, sine, DRIVE};
use hysteron::models::sensitivity::derivatives_at;
use hysteron::models::signal::fft_upsample;
use hysteron::models::TransmissionParams;
use hysteron::prelude::*;
use rand::rngs::StdRng;
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use std::f64::consts::TAU;
use std::hint::black_box;
use std::time::Duration;

// The Jiles-Atherton case of the identification crate's fit test, so the
// benchmark times the very fit that test checks.
#[path = "../identify/tests/common/jiles_atherton.rs"]
mod jiles_atherton_case;

/// Samples of every record.
const N: usize = 20_000;

/// A decaying sine: 10 cycles, amplitude `a` decaying to `a e^{-3}`.
fn decaying_sine(a: f64) -> Vec<f64> {
    (0..N)
        .map(|i| {
            let t = i as f64 / N as f64;
            a * (-3.0 * t).exp() * (TAU * 10.0 * t).sin()
        })
        .collect()
}

/// The `identify` group: 10 samples of `measure` seconds after a warm-up
/// of `warm_up` seconds, throughput in `samples` per run.
fn group(
    c: &mut Criterion,
    warm_up: f64,
    measure: u64,
    samples: usize,
) -> BenchmarkGroup<'_, WallTime> {
    let mut g = c.benchmark_group("identify");
    g.sample_size(10)
        .warm_up_time(Duration::from_secs_f64(warm_up))
        .measurement_time(Duration::from_secs(measure))
        .throughput(Throughput::Elements(samples as u64));
    g
}

/// Times `op` over the record `x` from its initial state.
fn bench_eval(
    g: &mut BenchmarkGroup<'_, WallTime>,
    name: &str,
    op: &mut impl Operator<f64>,
    x: &[f64],
) {
    let mut y = vec![0.0; x.len()];
    g.bench_function(name, |b| {
        b.iter(|| {
            op.reset();
            op.process(black_box(x), &mut y).expect("process");
            black_box(&mut y);
        })
    });
}

/// Times the derivatives of `op` along `x` with respect to its parameters
/// `free`, at its own values: one pass over dual numbers through its twin.
fn bench_dual_pass(
    g: &mut BenchmarkGroup<'_, WallTime>,
    name: &str,
    op: &dyn Operator<f64>,
    x: &[f64],
    free: &[usize],
) {
    let dual = op.to_dual().expect("every operator here has a dual twin");
    let base = op.params();
    g.bench_function(name, |b| {
        b.iter(|| {
            let (_, columns) = derivatives_at(dual.as_ref(), black_box(&base), black_box(x), free)
                .expect("dual pass");
            black_box(columns)
        })
    });
}

fn paper_model_eval(c: &mut Criterion) {
    let mut model = TransmissionParams::default()
        .build()
        .expect("default paper model");
    let x = decaying_sine(1.5);
    let mut y = vec![0.0; N];
    model.process(&x, &mut y).expect("paper model runs");
    let mut g = group(c, 0.5, 3, N);
    bench_eval(&mut g, "paper_model_eval", &mut model, &x);
    let free = free_by_names(&model, &["limits.b", "f_c", "left.mms.k"]).expect("stage 2's names");
    bench_dual_pass(&mut g, "paper_model_dual_pass", &model, &x, &free);
    g.finish();
}

/// True spring: `S = 10`, `w = 0.6`, `α = 1`, `β = 2.5`, `γ = 1.5`,
/// `n = 1.5`.
const TRUE: [f64; 5] = [10.0, 0.6, 2.5, 1.5, 1.5];
/// The fitted parameters, in the order of `TRUE`.
const FREE: [&str; 5] = ["stiffness.s[0]", "w", "beta", "gamma", "n"];

fn bouc_wen_fit(c: &mut Criterion) {
    let [k, w, beta, gamma, n] = TRUE;
    let truth = BoucWen::constant(k, w, 1.0, beta, gamma, n)
        .expect("true spring")
        .boxed();
    let x = decaying_sine(1.2);
    let clean = truth.clone().run(&x).expect("true response");
    let rms = (clean.iter().map(|v| v * v).sum::<f64>() / N as f64).sqrt();
    let noise = Normal::new(0.0, 0.01 * rms).expect("noise");
    let mut rng = StdRng::seed_from_u64(20_150_601);
    let y: Vec<f64> = clean.iter().map(|v| v + noise.sample(&mut rng)).collect();

    let free = free_by_names(truth.as_ref(), &FREE).expect("free names");
    let mut start = truth.clone();
    let mut p = start.params();
    for (j, &i) in free.iter().enumerate() {
        // ±20 %, alternating
        p[i] *= if j % 2 == 0 { 1.2 } else { 0.8 };
    }
    start.set_params(&p).expect("perturbed start");
    let opts = FitOptions::default();

    // One untimed fit: check it recovers the truth and show its report.
    let f = fit(start.as_ref(), &x, &y, &free, &opts).expect("fit runs");
    let r = &f.report;
    eprintln!("bouc_wen_fit_5 (true values {TRUE:?}):\n{r}");
    for (fp, t) in r.params.iter().zip(TRUE) {
        assert!(
            (fp.value - t).abs() <= 0.05 * t.abs(),
            "{} not recovered",
            fp.name
        );
    }

    let mut g = group(c, 0.5, 10, N);
    g.bench_function("bouc_wen_fit_5", |b| {
        b.iter(|| {
            let f = fit(start.as_ref(), black_box(&x), black_box(&y), &free, &opts).expect("fit");
            black_box(f.report.cost)
        })
    });
    g.measurement_time(Duration::from_secs(3));
    bench_eval(&mut g, "bouc_wen_eval", &mut truth.clone(), &x);
    bench_dual_pass(&mut g, "bouc_wen_dual_pass", truth.as_ref(), &x, &free);
    g.finish();
}

fn jiles_atherton_fit(c: &mut Criterion) {
    let truth = jiles_atherton_case::truth();
    let (h, m) = jiles_atherton_case::record(0.01);
    let model = jiles_atherton_case::perturbed_start();
    let free: Vec<usize> = (0..model.n_params()).collect();
    let opts = FitOptions::default();
    let f = fit(&model, &h, &m, &free, &opts).expect("fit runs");
    eprintln!(
        "jiles_atherton_fit_5 (true values {truth:?}):\n{}",
        f.report
    );

    let mut g = group(c, 0.5, 5, h.len());
    g.bench_function("jiles_atherton_fit_5", |b| {
        b.iter(|| {
            let f = fit(&model, black_box(&h), black_box(&m), &free, &opts).expect("fit");
            black_box(f.report.cost)
        })
    });
    g.finish();
}

/// The records of `paper_two_stages` and the start it identifies from.
struct PaperRecords {
    loop_x: Vec<f64>,
    loop_f: Vec<f64>,
    chirp_x: Vec<f64>,
    chirp_f: Vec<f64>,
    start: TransmissionParams,
}

impl PaperRecords {
    /// The paper's identification on the two records from `start`.
    fn identify(&self, opts: &PaperOptions) -> PaperIdentification {
        let (lx, lf, cx, cf) = (&self.loop_x, &self.loop_f, &self.chirp_x, &self.chirp_f);
        identify_paper(lx, lf, cx, cf, &self.start, opts).expect("identification runs")
    }
}

/// The paper's model with the truth's spring `n = 1.5`, `h0 = 0.1`,
/// sampled at 250 Hz over a 0.5 Hz major loop (2 cycles) and the 5 → 0.1 Hz
/// down-chirp over 20 s; the start 20 % off in backlash, `F_c` and `K`.
fn paper_records() -> PaperRecords {
    let fs = 250.0;
    let mut truth = TransmissionParams::default();
    truth.spring.n = 1.5;
    truth.spring.h0 = 0.1;
    let model = truth.build().expect("true model");
    let loop_x = sine(0.5, DRIVE.amplitude(0.5), 2.0, fs).expect("loop").x;
    let loop_f = model.clone().run(&loop_x).expect("loop record");
    let chirp_x = chirp(5.0, 0.1, 20.0, fs, |f| DRIVE.amplitude(f))
        .expect("chirp")
        .x;
    let chirp_f = model.clone().run(&chirp_x).expect("chirp record");
    let mut start = TransmissionParams::default();
    start.backlash *= 1.2;
    start.friction.f_c *= 1.2;
    start.friction.k *= 0.8;
    PaperRecords {
        loop_x,
        loop_f,
        chirp_x,
        chirp_f,
        start,
    }
}

fn paper_two_stages(c: &mut Criterion) {
    let records = paper_records();
    // the paper's two stages only (stage 3 off), as the README's figure
    let opts = PaperOptions {
        joint: None,
        ..PaperOptions::default()
    };

    let run = || records.identify(&opts);
    let r = run();
    eprintln!(
        "paper_two_stages: stage 1 {} iterations, {} evaluations, {:.3} s, NRMSE {:.3e}, {:?}; \
         stage 2 {} iterations, {} evaluations, {:.3} s, NRMSE {:.3e}, {:?}",
        r.spring.report.iterations,
        r.spring.report.evaluations,
        r.spring.report.wall_time.as_secs_f64(),
        r.spring.report.nrmse.unwrap_or(f64::NAN),
        r.spring.report.status,
        r.bedstop.iterations,
        r.bedstop.evaluations,
        r.bedstop.wall_time.as_secs_f64(),
        r.bedstop.nrmse.unwrap_or(f64::NAN),
        r.bedstop.status,
    );

    let mut g = group(c, 0.1, 20, records.loop_x.len() + records.chirp_x.len());
    g.bench_function("paper_two_stages", |b| {
        b.iter(|| black_box(run().params.backlash))
    });
    g.finish();
}

/// Columns `u` and `y` of `data/boucwen-benchmark/train_multisine.csv`.
fn train_multisine() -> (Vec<f64>, Vec<f64>) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/data/boucwen-benchmark/train_multisine.csv"
    );
    let text = std::fs::read_to_string(path).expect("train_multisine.csv");
    let (mut u, mut y) = (Vec::new(), Vec::new());
    // header `t,u,y`, then numbers
    for line in text.lines().skip(1) {
        let cols: Vec<f64> = line
            .split(',')
            .map(|v| v.trim().parse().expect("a number"))
            .collect();
        u.push(cols[1]);
        y.push(cols[2]);
    }
    (u, y)
}

fn benchmark_system(c: &mut Criterion) {
    let (u, y) = train_multisine();
    let start = start_from_data(&u, &y, 750.0, 20).expect("data start");
    // the multisine's period is 8192 samples
    let fine = fft_upsample(&u[..8192], start.upsample).expect("upsampled period");
    let model = boucwen_system(&start).expect("benchmark system").boxed();
    let free = free_by_names(model.as_ref(), &BENCHMARK_FREE).expect("the seven names");
    let mut g = group(c, 0.5, 5, fine.len());
    bench_eval(&mut g, "benchmark_system_eval", &mut model.clone(), &fine);
    bench_dual_pass(
        &mut g,
        "benchmark_system_dual_pass",
        model.as_ref(),
        &fine,
        &free,
    );
    g.finish();
}

/// The same fits with and without their dual passes handed to a second
/// core at each trial point (`FitOptions::parallel`; one record, one pass
/// per Jacobian: nothing else of these fits runs in parallel), side by
/// side: the paper's two stages (stage 2's simulation takes about 1 ms)
/// and 40 evaluations of the benchmark system's fit on the record's first
/// 1024 samples, upsampled 20× (20 480 samples a simulation).
fn speculation(c: &mut Criterion) {
    let records = paper_records();

    let (u, y) = train_multisine();
    let from = start_from_data(&u, &y, 750.0, 20).expect("data start");
    let n = 1024;
    let fine = fft_upsample(&u[..n], from.upsample).expect("upsampled");
    let system = boucwen_system(&from).expect("benchmark system").boxed();
    let free = free_by_names(system.as_ref(), &BENCHMARK_FREE).expect("the seven names");

    let mut g = group(c, 0.1, 10, records.loop_x.len() + records.chirp_x.len());
    for (name, parallel) in [("speculating", true), ("alone", false)] {
        let opts = PaperOptions {
            joint: None,
            fit: FitOptions {
                parallel,
                ..FitOptions::default()
            },
            ..PaperOptions::default()
        };
        g.bench_function(format!("paper_two_stages/{name}"), |b| {
            b.iter(|| {
                let r = records.identify(&opts);
                black_box(r.params.backlash)
            })
        });
        let opts = FitOptions {
            parallel,
            stride: from.upsample,
            max_evaluations: Some(40),
            ..FitOptions::default()
        };
        g.bench_function(format!("benchmark_fit_40/{name}"), |b| {
            b.iter(|| {
                let f = fit(system.as_ref(), &fine, &y[..n], &free, &opts).expect("fit runs");
                black_box(f.report.cost)
            })
        });
    }
    g.finish();
}

criterion_group!(
    benches,
    paper_model_eval,
    bouc_wen_fit,
    jiles_atherton_fit,
    paper_two_stages,
    benchmark_system,
    speculation
);
criterion_main!(benches);
