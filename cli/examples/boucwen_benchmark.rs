//! The Bouc-Wen hysteretic benchmark (Noël & Schoukens 2016): simulates the
//! published system, composed from the algebra as
//! `MassSpringDamper.feedback(BoucWen)`, on benchmark records and compares
//! its output with theirs; optionally identifies the system from a training
//! record, starting from values taken from that record alone.
//!
//! Run (every path is an argument; none is built in):
//!
//! ```text
//! cargo run --release --example boucwen_benchmark -- \
//!     --periodic data/boucwen-benchmark/val_multisine.csv \
//!     [--from-rest val_sinesweep.csv] \
//!     [--train data/boucwen-benchmark/train_multisine.csv [--starts 4]]
//! ```
//!
//! Each record is a CSV file with columns `u` (force, N) and `y`
//! (displacement, m) at 750 Hz. How a record is simulated depends on what
//! it holds:
//!
//! * `--periodic FILE`: one steady-state period of a periodic input (the
//!   validation multisine). `u` is upsampled by 20 with exact trigonometric
//!   (FFT) interpolation, the system integrates at 15 kHz period after
//!   period until the response repeats to 1e-12 m, and the last period is
//!   decimated circularly after `--periodic-plan` (default `2,2,5`, MATLAB
//!   `decimate(·, 'fir')` three times, as that record was made).
//! * `--from-rest FILE`: a record from rest that is not periodic (the
//!   benchmark's sine sweep). `u` is upsampled by polyphase band-limited
//!   interpolation, the system integrates once from rest, and its output is
//!   decimated with MATLAB's end handling after `--from-rest-plan` (default
//!   `20`, one stage, as the sine-sweep record was made).
//!
//! For each record it prints the RMS error of the decimated simulation and,
//! for comparison, of every 20th sample unfiltered.
//!
//! `--train FILE` identifies `m, c, k, A, β', γ', n` from that record only
//! (from rest; `--train-upsampling fft` when it holds whole periods of a
//! periodic input, as the training multisine does, `polyphase` otherwise),
//! starting from `identify::benchmark::start_from_data`: a linear
//! least-squares estimate of `m, c` and the total stiffness, and generic
//! Bouc-Wen values. No published value enters the start. `--starts N`
//! adds `N − 1` starts spread around it (a Latin hypercube) and keeps the
//! best; the identified system is then simulated on every record given.
//! One start takes about two minutes on 2 cores: every model evaluation
//! integrates 819 200 steps.

use clap::Parser;
use hysteron::identify::benchmark::{
    identify_boucwen_multistart, linear_estimate, start_from_data, FREE,
};
use hysteron::identify::metrics::{errors, rms};
use hysteron::identify::multistart::MultiStart;
use hysteron::identify::{FitOptions, FitStatus};
use hysteron::models::benchmark::{simulate_record, BoucWenBenchmarkParams};
use hysteron::models::signal::{DecimationPlan, RecordKind, Upsampling};
use hysteron_cli::csvio::read_columns;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

#[derive(Parser)]
#[command(about = "Simulate and identify the Bouc-Wen benchmark system on records given by path")]
struct Args {
    /// A record holding one steady-state period of a periodic input (u, y).
    #[arg(long, value_name = "FILE")]
    periodic: Vec<PathBuf>,
    /// A record from rest that is not periodic, such as a sine sweep (u, y).
    #[arg(long = "from-rest", value_name = "FILE")]
    from_rest: Vec<PathBuf>,
    /// Decimation plan of the periodic records' outputs (stages, in order).
    #[arg(long, default_value = "2,2,5", value_name = "PLAN")]
    periodic_plan: DecimationPlan,
    /// Decimation plan of the records from rest.
    #[arg(long, default_value = "20", value_name = "PLAN")]
    from_rest_plan: DecimationPlan,
    /// Identify the system from this record (from rest) before validating.
    #[arg(long, value_name = "FILE")]
    train: Option<PathBuf>,
    /// How the training record's input is upsampled: `fft` for whole
    /// periods of a periodic input, `polyphase` otherwise.
    #[arg(long, default_value = "fft", value_parser = parse_upsampling)]
    train_upsampling: Upsampling,
    /// Starts of the identification (the data-driven start and N − 1 spread
    /// around it).
    #[arg(long, default_value_t = 1)]
    starts: usize,
    /// Seed of the spread starts.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Wall-time bound of each start's fit, in seconds (the best iterate so
    /// far is kept when it runs out).
    #[arg(long, value_name = "SECONDS", default_value_t = 900.0)]
    max_seconds: f64,
}

fn parse_upsampling(s: &str) -> Result<Upsampling, String> {
    match s {
        "fft" => Ok(Upsampling::Fft),
        "polyphase" => Ok(Upsampling::Polyphase),
        other => Err(format!("'{other}' is neither fft nor polyphase")),
    }
}

/// One record to compare with: its file, what it holds and its plan.
struct Record {
    path: PathBuf,
    kind: RecordKind,
    plan: DecimationPlan,
    u: Vec<f64>,
    y: Vec<f64>,
}

fn read_record(path: &Path) -> Result<(Vec<f64>, Vec<f64>), String> {
    let mut c = read_columns(path, &["u", "y"]).map_err(|e| e.to_string())?;
    let y = c.values.pop().unwrap_or_default();
    let u = c.values.pop().unwrap_or_default();
    Ok((u, y))
}

/// `RMS(a − b)`; NaN when the two cannot be compared (different lengths,
/// a non-finite sample), which prints as such.
fn rms_error(a: &[f64], b: &[f64]) -> f64 {
    errors(a, b).map_or(f64::NAN, |e| e.rms)
}

/// Simulates `p` on every record and prints the errors; returns the
/// largest decimated RMS error.
fn validate(p: &BoucWenBenchmarkParams, records: &[Record], label: &str) -> Result<f64, String> {
    let mut worst: f64 = 0.0;
    for r in records {
        let start = Instant::now();
        let response = simulate_record(p, &r.u, r.kind, &r.plan)
            .map_err(|e| format!("{}: simulation: {e}", r.path.display()))?;
        if !response.converged {
            return Err(format!(
                "{}: no steady state after {} periods",
                r.path.display(),
                response.periods
            ));
        }
        let e = rms_error(&response.decimated, &r.y);
        worst = worst.max(e);
        println!(
            "{label} {}: rms error {e:.3e} m (decimated {}, output rms {:.3e} m); every 20th sample {:.3e} m; {} period(s), {:.2} s",
            r.path.display(),
            r.plan,
            rms(&r.y),
            rms_error(&response.picked, &r.y),
            response.periods,
            start.elapsed().as_secs_f64()
        );
    }
    Ok(worst)
}

fn identify(args: &Args, train: &Path, records: &[Record]) -> Result<(), String> {
    let (u, y) = read_record(train)?;
    // the records' rates: 750 Hz, integrated 20 times finer
    let (fs, upsample) = (750.0, 20);
    let lin = linear_estimate(&u, &y, fs).map_err(|e| e.to_string())?;
    let start = start_from_data(&u, &y, fs, upsample).map_err(|e| e.to_string())?;
    println!(
        "training record {}: {} samples; linear estimate m = {:.4}, c = {:.3}, k + A = {:.5e}",
        train.display(),
        u.len(),
        lin.m,
        lin.c,
        lin.k_total
    );
    let opts = FitOptions {
        max_seconds: Some(args.max_seconds),
        ..FitOptions::default()
    };
    let ms = MultiStart {
        starts: args.starts,
        seed: args.seed,
        ..MultiStart::default()
    };
    let clock = Instant::now();
    let id = identify_boucwen_multistart(&u, &y, &start, args.train_upsampling, &opts, &ms)
        .map_err(|e| format!("identification: {e}"))?;
    let report = &id.report;
    println!(
        "identified in {:.0} s: {} iterations, {} evaluations, {}; train rms {:.3e} m",
        clock.elapsed().as_secs_f64(),
        report.iterations,
        report.evaluations,
        match &report.status {
            FitStatus::Converged(why) => format!("converged: {why}"),
            other => format!("{other:?}"),
        },
        report.rms
    );
    if let Some(s) = &report.starts {
        let costs: Vec<String> = s
            .costs
            .iter()
            .map(|c| c.map_or("failed".into(), |c| format!("{c:.4e}")))
            .collect();
        println!(
            "starts: {} of {} reached the best cost (within 1 %), best is start {}; costs [{}]",
            s.reached,
            s.costs.len(),
            s.best,
            costs.join(", ")
        );
    }
    let starts = [
        start.m,
        start.c,
        start.k,
        start.a,
        start.beta,
        start.gamma,
        start.n,
    ];
    println!("  parameter      start (data)      identified    std error");
    for (fp, s0) in report.params.iter().zip(starts) {
        println!(
            "  {:<8} {:>16.6} {:>16.6} {:>12.3e}",
            fp.name.rsplit('.').next().unwrap_or(&fp.name),
            s0,
            fp.value,
            fp.std_error.unwrap_or(f64::NAN),
        );
    }
    debug_assert_eq!(report.params.len(), FREE.len());
    validate(&id.params, records, "identified")?;
    Ok(())
}

fn run(args: &Args) -> Result<(), String> {
    let mut records = Vec::new();
    let given = args
        .periodic
        .iter()
        .map(|p| (p, RecordKind::Periodic, &args.periodic_plan))
        .chain(
            args.from_rest
                .iter()
                .map(|p| (p, RecordKind::FromRest, &args.from_rest_plan)),
        );
    for (path, kind, plan) in given {
        let (u, y) = read_record(path)?;
        records.push(Record {
            path: path.clone(),
            kind,
            plan: plan.clone(),
            u,
            y,
        });
    }
    if records.is_empty() && args.train.is_none() {
        return Err(
            "no record given: pass --periodic FILE, --from-rest FILE or --train FILE (see --help)"
                .into(),
        );
    }
    let p = BoucWenBenchmarkParams::published();
    println!(
        "published system: MassSpringDamper(m = {}, c = {}, k = {}).feedback(BoucWen(A = {}, β' = {}, γ' = {}, n = {})), integrated at {} Hz",
        p.m, p.c, p.k, p.a, p.beta, p.gamma, p.n, p.fs * p.upsample as f64
    );
    validate(&p, &records, "published")?;
    if let Some(train) = &args.train {
        identify(args, train, &records)?;
    }
    Ok(())
}

fn main() -> ExitCode {
    match run(&Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("boucwen_benchmark: {e}");
            ExitCode::FAILURE
        }
    }
}
