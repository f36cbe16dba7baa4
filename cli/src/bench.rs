//! `hysteron bench`: the table of performance kernels, timed on
//! its defined input, one line per kernel in a format that reads side by
//! side with other implementations:
//!
//! `| hysteron | <kernel> | <runs> | <samples/s median> | <ns/sample median> | <min..max> |`
//!
//! The kernels (also used by the criterion benches in `benches/`):
//!
//! * input `x_i = 2.5 sin(2π i/2000) + 0.3 sin(2π i/97.3)`, `f64`, read from
//!   one buffer and written to another (`reset` + `process` per run);
//! * `play`: threshold 0.5;
//! * `pi_bank 4`, `pi_bank 64`: `0.1 x + Σ_j w_j play_{r_j}(x)`,
//!   `r_j = 3j/m`, `w_j = exp(−r_j)/m`, `j = 0..m−1` ([`PI_PLAYS`]);
//! * `bouc_wen n=1`, `bouc_wen n=1.5`: `ż = ẋ − β|ẋ||z|^{n−1}z − γẋ|z|^n`,
//!   `H = a k x + (1 − a) k z`, `β = 0.7`, `γ = 0.3`, `a = 0.1`, `k = 1`
//!   (the library's [`BoucWen`] with `w = a`, `α = 1`, constant `S = k`);
//!   `n = 1.5` runs at [`BW15_RTOL`] (tabulated flow), and the command prints its measured
//!   error against a tight-tolerance run;
//! * `mms`: `F_c = 1`, `K = 5`;
//! * `paper model`: the paper's composed model (MMS bedstop with backlash
//!   in series with the Bouc-Wen spring, [`TransmissionParams::default`]),
//!   static, and the same model boxed from its JSON spec;
//! * `paper model batch`: the input cut into [`BATCH`] records, run through
//!   the boxed paper model with rayon (each record from the initial state,
//!   into preallocated outputs), on 1 and on 2 threads;
//! * `bwbn`, `jiles_atherton`: the two leaves integrated by adaptive
//!   Dormand–Prince, at their example parameters ([`bwbn`],
//!   [`jiles_atherton`]); the command prints each output's sum, the
//!   checksum that `bench/families.c`, their C reference, prints too;
//! * `ensemble play`, `ensemble pi_bank 4`, `ensemble pi_bank 64`,
//!   `ensemble mms`, `ensemble bouc_wen n=1`, `ensemble bouc_wen n=1.5`: an
//!   [`Ensemble`] of [`ENSEMBLE`] instances of the play, PI bank, MMS and
//!   Bouc-Wen kernels (the threshold, `a0`, `F_c` or `β` spread over
//!   `0.5..1.5` times the kernel's) over the first `1/ENSEMBLE` of
//!   the input, on one thread, into one output buffer: timed per
//!   instance-sample, and compared in a note with the single-instance
//!   kernel of the same run; the command prints the sum of the outputs
//!   (and of the `bouc_wen n=1` kernel's), the checksums that
//!   `bench/families.c` prints for its Bouc-Wen rows;
//! * `exp kernel`, `exp_m1 kernel`: the library's vectorised exponentials
//!   ([`crate::operators::exp_kernel`]) over `−|x_i|` for the
//!   first [`EXP_BLOCK`] samples, in place, repeated over a block in the L1
//!   cache to the sample count: the one the Bouc-Wen spring (`exp`) and the MMS element
//!   (`exp_m1`) take per sample: both the single-instance kernels and the
//!   ensembles evaluate one per (instance-)sample, eight per instruction,
//!   so the note on each ensemble gives the bound `one at a time / exp` on
//!   its ratio;
//! * `lanes bouc_wen n=1.5`: the lanes of [`ENSEMBLE`] springs of the
//!   `bouc_wen n=1.5` kernel (`β` spread as in its ensemble) run directly
//!   ([`run_lanes`]: each lane on its tabulated flow) over the first
//!   `1/ENSEMBLE` of the input, building the tables included, timed per
//!   instance-sample against the single kernel (an [`Ensemble`] of springs
//!   with `n ≠ 1` runs one instance at a time: these lanes were no
//!   faster);
//! * `bouc_wen system`, `ensemble bouc_wen system`: the Bouc-Wen benchmark
//!   system ([`BW_SYSTEM_SPEC`]: a mass-spring-damper with the spring fed
//!   back, 20 sub-steps per sample) driven by the force `u_i = 20 x_i`
//!   over the first `1/ENSEMBLE` of the input, one instance (built
//!   statically, and boxed from its spec), and an [`Ensemble`] of
//!   [`ENSEMBLE`] instances with the spring's `β` spread over `0.5..1.5`
//!   times its own; timed per (instance-)sample, each sample 20 sub-steps.

use crate::args;
use crate::composition::{Feedback, OperatorExt, Oversample, PiBank};
use crate::identify::batch::process_records;
use crate::identify::ensemble::Ensemble;
use crate::models::{Spec, TransmissionParams};
use crate::operators::exp_kernel;
use crate::operators::lanes::run_lanes;
use crate::operators::{
    BoucWen, BoucWenParams, Bwbn, BwbnParams, Error, JilesAtherton, JilesAthertonParams,
    MassSpringDamper, Mms, Operator, ParamSet, Play, Result, StateSolver,
};
use nalgebra::DMatrix;
use std::f64::consts::TAU;
use std::fmt;
use std::time::Instant;

/// Relative local error tolerance of the `bouc_wen n=1.5` kernel.
pub const BW15_RTOL: f64 = 1e-10;

/// Signals in the batch kernels.
pub const BATCH: usize = 64;

/// Values per block of the `exp kernel` and `exp_m1 kernel` (16 KiB:
/// in the L1 data cache).
pub const EXP_BLOCK: usize = 2048;

/// Instances in the ensemble kernels.
pub const ENSEMBLE: usize = 64;

/// The plays of the PI bank kernels: a small bank (whose ensemble steps in
/// lanes) and a large one (whose ensemble runs one instance at a time).
pub const PI_PLAYS: [usize; 2] = [4, 64];

/// The `bouc_wen n=1` kernel's spring as a spec (for its ensemble).
pub const BW_SPEC_1: &str = r#"{"type": "bouc_wen", "w": 0.1, "alpha": 1.0, "beta": 0.7,
    "gamma": 0.3, "n": 1.0, "h0": 0.0, "z0": 0.0, "stiffness": 1.0}"#;

/// The `bouc_wen n=1.5` kernel's spring as a spec (default tolerance, the
/// kernel's [`BW15_RTOL`]).
pub const BW_SPEC_15: &str = r#"{"type": "bouc_wen", "w": 0.1, "alpha": 1.0, "beta": 0.7,
    "gamma": 0.3, "n": 1.5, "h0": 0.0, "z0": 0.0, "stiffness": 1.0}"#;

/// The Bouc-Wen benchmark system as a spec (`examples/specs/boucwen-benchmark.json`).
pub const BW_SYSTEM_SPEC: &str = include_str!("../../examples/specs/boucwen-benchmark.json");

/// The kernel input `x_i = 2.5 sin(2π i/2000) + 0.3 sin(2π i/97.3)`.
pub fn kernel_input(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| {
            let i = i as f64;
            2.5 * (TAU * i / 2000.0).sin() + 0.3 * (TAU * i / 97.3).sin()
        })
        .collect()
}

/// The play kernel: threshold 0.5.
pub fn play() -> Result<Play<f64>> {
    Play::new(0.5)
}

/// The PI kernel with `m` plays: `0.1 x + Σ_j w_j play_{r_j}(x)`,
/// `r_j = 3j/m`, `w_j = exp(−r_j)/m`.
pub fn pi_bank(m: usize) -> Result<PiBank<f64>> {
    let r: Vec<f64> = (0..m).map(|j| 3.0 * j as f64 / m as f64).collect();
    let w: Vec<f64> = r.iter().map(|&r| (-r).exp() / m as f64).collect();
    PiBank::new(0.1, r, w)
}

/// The Bouc-Wen kernel with exponent `n`: `a = 0.1`, `k = 1`, `A = 1`,
/// `β = 0.7`, `γ = 0.3`.
pub fn bouc_wen(n: f64) -> Result<BoucWen<f64>> {
    BoucWen::constant(1.0, 0.1, 1.0, 0.7, 0.3, n)
}

/// The MMS kernel: `F_c = 1`, `K = 5`.
pub fn mms() -> Result<Mms<f64>> {
    Mms::new(1.0, 5.0)
}

/// The BWBN kernel: `α = 0.1`, `k0 = 10`, `n = 1`, `γ = β = 0.5`,
/// `a0 = 1`, `q = 0.25`, `ζ_s = 0.9`, `p = 1`, `ψ0 = 0.2`, `δ_ψ = 0.005`,
/// `λ = 0.5` (the operator's example).
pub fn bwbn() -> Result<Bwbn<f64>> {
    Bwbn::from_params(BwbnParams::example())
}

/// The Jiles-Atherton kernel: `Ms = 1`, `a = 0.3`, `k = 0.5`, `c = 0.2`,
/// `α = 0.1` (the operator's example).
pub fn jiles_atherton() -> Result<JilesAtherton<f64>> {
    JilesAtherton::from_params(JilesAthertonParams::example())
}

/// The paper's model with its default parameters, built statically.
pub fn paper_model() -> Result<crate::models::PaperModel> {
    TransmissionParams::default().build()
}

/// The same model built from its JSON spec (a boxed `series` tree).
pub fn paper_model_from_json() -> std::result::Result<Box<dyn Operator<f64>>, String> {
    let json = Spec::from(&TransmissionParams::default())
        .to_json_pretty()
        .map_err(|e| e.to_string())?;
    Spec::from_json(&json)
        .and_then(|s| s.build())
        .map_err(|e| e.to_string())
}

/// Timings of one kernel over `runs` runs.
#[derive(Debug, Clone, PartialEq)]
pub struct Timing {
    /// Kernel name.
    pub kernel: String,
    /// Samples per run.
    pub samples: usize,
    /// Nanoseconds per sample of each run, sorted.
    pub ns_per_sample: Vec<f64>,
}

impl Timing {
    fn median(&self) -> f64 {
        let v = &self.ns_per_sample;
        let m = v.len() / 2;
        if v.len() % 2 == 1 {
            v[m]
        } else {
            0.5 * (v[m - 1] + v[m])
        }
    }
}

impl fmt::Display for Timing {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let med = self.median();
        write!(
            f,
            "| hysteron | {} | {} | {:.4e} | {:.3} | {:.3}..{:.3} |",
            self.kernel,
            self.ns_per_sample.len(),
            1e9 / med,
            med,
            self.ns_per_sample[0],
            self.ns_per_sample[self.ns_per_sample.len() - 1],
        )
    }
}

/// Time the operator kernels (play, 64-play PI, Bouc-Wen n = 1 and
/// 1.5, MMS, BWBN and Jiles-Atherton, the paper's model static and
/// boxed from JSON, rayon batches on 1 and 2 threads) on the input
/// x_i = 2.5 sin(2πi/2000) + 0.3 sin(2πi/97.3); prints one table row
/// per kernel: | hysteron | kernel | runs | samples/s | ns/sample | min..max |.
/// Build with --release.
#[derive(Debug, Clone, PartialEq, clap::Args)]
pub struct BenchOptions {
    /// Samples of the kernel input per run (1 to 10^9).
    #[arg(long, value_name = "N", default_value_t = 10_000_000, value_parser = args::bench_samples, allow_negative_numbers = true)]
    pub samples: usize,
    /// Timed runs per kernel, after one untimed run (1 to 1000).
    #[arg(long, value_name = "R", default_value_t = 5, value_parser = args::bench_runs, allow_negative_numbers = true)]
    pub runs: usize,
    /// Only the kernels whose name contains this.
    #[arg(long = "kernel", value_name = "NAME")]
    pub filter: Option<String>,
}

/// What [`run`] measured.
#[derive(Debug, Clone, PartialEq)]
pub struct BenchReport {
    /// One timing per kernel run.
    pub timings: Vec<Timing>,
    /// Notes on accuracy and scaling, one line each.
    pub notes: Vec<String>,
}

impl fmt::Display for BenchReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "| implementation | kernel | runs | samples/s (median) | ns/sample (median) | ns/sample min..max |"
        )?;
        writeln!(f, "|---|---|---|---|---|---|")?;
        for t in &self.timings {
            writeln!(f, "{t}")?;
        }
        for n in &self.notes {
            writeln!(f, "{n}")?;
        }
        Ok(())
    }
}

/// Times `reset` + `process` of `op` over `x`, `runs` times after one
/// untimed run (which also checks that the kernel runs without error).
fn time_op<O: Operator<f64> + ?Sized>(
    kernel: &str,
    op: &mut O,
    x: &[f64],
    y: &mut [f64],
    runs: usize,
) -> std::result::Result<Timing, String> {
    time_with(kernel, x.len(), runs, || {
        op.reset();
        op.process(x, y)
    })
}

fn time_with(
    kernel: &str,
    samples: usize,
    runs: usize,
    mut f: impl FnMut() -> Result<()>,
) -> std::result::Result<Timing, String> {
    f().map_err(|e| format!("kernel {kernel}: {e}"))?;
    let mut ns = Vec::with_capacity(runs);
    for _ in 0..runs {
        let start = Instant::now();
        let r = f();
        let elapsed = start.elapsed();
        std::hint::black_box(&r);
        r.map_err(|e| format!("kernel {kernel}: {e}"))?;
        ns.push(elapsed.as_secs_f64() * 1e9 / samples as f64);
    }
    ns.sort_by(f64::total_cmp);
    Ok(Timing {
        kernel: kernel.to_string(),
        samples,
        ns_per_sample: ns,
    })
}

/// Times an ensemble of [`ENSEMBLE`] instances of `spec` (its parameter
/// `spread` over `0.5..1.5` times its value, the others as given)
/// over the first `x.len() / ENSEMBLE` samples of `x`, on one thread, into
/// one output buffer: the same instance-samples as one kernel run, timed
/// per instance-sample; with the checksum, and the median time of a run
/// over the first sample alone (setting the instances up: for a Bouc-Wen
/// spring with `n ≠ 1`, building its table) per instance-sample of the
/// whole run.
fn time_ensemble(
    kernel: &str,
    spec: &str,
    spread: &str,
    x: &[f64],
    runs: usize,
) -> std::result::Result<(Timing, f64, f64), String> {
    let spec = Spec::from_json(spec).map_err(|e| e.to_string())?;
    let model = spec.build().map_err(|e| e.to_string())?;
    let own = model.params();
    let column = model
        .param_names()
        .iter()
        .position(|n| n == spread)
        .ok_or_else(|| format!("kernel {kernel}: no parameter {spread}"))?;
    let params = DMatrix::from_fn(ENSEMBLE, own.len(), |i, j| {
        let spread = if j == column {
            0.5 + i as f64 / ENSEMBLE as f64
        } else {
            1.0
        };
        own.get(j).copied().unwrap_or(0.0) * spread
    });
    let ensemble = Ensemble::new(&spec, &params).map_err(|e| e.to_string())?;
    let x = &x[..(x.len() / ENSEMBLE).max(1).min(x.len())];
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map_err(|e| e.to_string())?;
    // (checked once untimed: every instance runs; then into the same
    // buffer, as the single kernels write theirs)
    let mut out = vec![0.0; ENSEMBLE * x.len()];
    let check = pool
        .install(|| ensemble.run_into(x, &mut out))
        .map_err(|e| format!("kernel {kernel}: {e}"))?;
    if let Some(f) = check.first() {
        return Err(format!("kernel {kernel}: {f}"));
    }
    let checksum = out.iter().sum();
    let t = time_with(kernel, ENSEMBLE * x.len(), runs, || {
        let run = pool.install(|| ensemble.run_into(x, &mut out));
        std::hint::black_box(run.map(|f| f.len()).ok());
        Ok(())
    })?;
    let (first, first_out) = (&x[..1], &mut out[..ENSEMBLE]);
    let setup = time_with(kernel, ENSEMBLE * x.len(), runs, || {
        let run = pool.install(|| ensemble.run_into(first, first_out));
        std::hint::black_box(run.map(|f| f.len()).ok());
        Ok(())
    })?;
    Ok((t, checksum, setup.median()))
}

/// Times the Bouc-Wen lanes of springs with `n ≠ 1` ([`run_lanes`] of
/// [`ENSEMBLE`] springs of the `bouc_wen n=1.5` kernel, `β` spread over
/// `0.5..1.5` times its own) over the first `x.len() / ENSEMBLE` samples of
/// `x`, per instance-sample, building the springs' tables included.
fn time_flow_lanes(kernel: &str, x: &[f64], runs: usize) -> std::result::Result<Timing, String> {
    let own = bouc_wen(1.5)
        .map_err(|e| e.to_string())?
        .parameters()
        .clone();
    let laws: Vec<_> = (0..ENSEMBLE)
        .map(|i| BoucWenParams {
            beta: own.beta * (0.5 + i as f64 / ENSEMBLE as f64),
            ..own.clone()
        })
        .collect();
    let x = &x[..(x.len() / ENSEMBLE).max(1).min(x.len())];
    let mut out = vec![0.0; ENSEMBLE * x.len()];
    // (checked once untimed: every instance runs)
    let failed = run_lanes(&laws, x, &mut out).map_err(|e| format!("kernel {kernel}: {e}"))?;
    if let Some(i) = failed.first() {
        return Err(format!("kernel {kernel}: instance {i} fails"));
    }
    time_with(kernel, ENSEMBLE * x.len(), runs, || {
        std::hint::black_box(run_lanes(&laws, x, &mut out)?.len());
        Ok(())
    })
}

/// The `bouc_wen system` kernels (see the module's documentation), where
/// `wanted`.
fn system_kernels(
    x: &[f64],
    runs: usize,
    wanted: &dyn Fn(&str) -> bool,
    timings: &mut Vec<Timing>,
    notes: &mut Vec<String>,
) -> std::result::Result<(), String> {
    let lib = |e: Error| e.to_string();
    let u: Vec<f64> = x.iter().map(|v| 20.0 * v).collect();
    let part = &u[..(u.len() / ENSEMBLE).max(1).min(u.len())];
    let mut y = vec![0.0; part.len()];
    let spec = Spec::from_json(BW_SYSTEM_SPEC).map_err(|e| e.to_string())?;
    let mut alone = None;
    if wanted("bouc_wen system") {
        let mut stat = bouc_wen_system().map_err(lib)?;
        let t = time_op("bouc_wen system", &mut stat, part, &mut y, runs)?;
        let static_y = y.clone();
        let mut boxed = spec.build().map_err(|e| e.to_string())?;
        let t_boxed = time_op(
            "bouc_wen system, boxed from JSON",
            boxed.as_mut(),
            part,
            &mut y,
            runs,
        )?;
        if y != static_y {
            return Err("bouc_wen system: boxed and static outputs differ".into());
        }
        notes.push(format!(
            "bouc_wen system: checksum (sum of outputs) {:.10e}",
            y.iter().sum::<f64>()
        ));
        alone = Some(t.median().min(t_boxed.median()));
        timings.push(t);
        timings.push(t_boxed);
    }
    let kernel = "ensemble bouc_wen system";
    if wanted(kernel) {
        let (t, checksum, _) = time_ensemble(
            kernel,
            BW_SYSTEM_SPEC,
            "inner.feedback.back.bouc_wen.beta",
            &u,
            runs,
        )?;
        notes.push(format!(
            "{kernel}: checksum (sum of outputs) {checksum:.10e}"
        ));
        if let Some(one) = alone {
            notes.push(format!(
                "{kernel}: {:.2}x the instances per second of one bouc_wen system at a time (the faster of static and boxed; 1 thread)",
                one / t.median()
            ));
        }
        timings.push(t);
    }
    Ok(())
}

/// The Bouc-Wen benchmark system, statically typed.
pub type BoucWenSystem = Oversample<f64, Feedback<f64, MassSpringDamper<f64>, BoucWen<f64>>>;

/// The Bouc-Wen benchmark system of [`BW_SYSTEM_SPEC`], built statically:
/// `oversample(20, feedback(mass_spring_damper, bouc_wen))`.
pub fn bouc_wen_system() -> Result<BoucWenSystem> {
    let forward = MassSpringDamper::new(2.0, 10.0, 5e4, 1.0 / 15000.0)?;
    let back = BoucWen::constant(1.0, 0.0, 5e4, 800.0, -1100.0, 1.0)?;
    Oversample::new(forward.feedback(back), 20)
}

/// Runs the kernel table.
pub fn run(opts: &BenchOptions) -> std::result::Result<BenchReport, String> {
    if opts.samples == 0 || opts.runs == 0 {
        return Err("--samples and --runs must be at least 1".into());
    }
    let x = kernel_input(opts.samples);
    let mut y = vec![0.0; x.len()];
    let wanted = |k: &str| opts.filter.as_deref().is_none_or(|f| k.contains(f));
    let lib = |e: Error| e.to_string();
    let mut timings = Vec::new();
    let mut notes = Vec::new();
    let runs = opts.runs;

    if wanted("play") {
        timings.push(time_op(
            "play",
            &mut play().map_err(lib)?,
            &x,
            &mut y,
            runs,
        )?);
    }
    for m in PI_PLAYS {
        let kernel = format!("pi_bank {m}");
        if wanted(&kernel) {
            timings.push(time_op(
                &kernel,
                &mut pi_bank(m).map_err(lib)?,
                &x,
                &mut y,
                runs,
            )?);
        }
    }
    if wanted("bouc_wen n=1") {
        let mut bw = bouc_wen(1.0).map_err(lib)?;
        timings.push(time_op("bouc_wen n=1", &mut bw, &x, &mut y, runs)?);
        notes.push(format!(
            "bouc_wen n=1: checksum (sum of outputs) {:.10e}",
            y.iter().sum::<f64>()
        ));
    }
    if wanted("bouc_wen n=1.5") {
        let mut bw = bouc_wen(1.5)
            .map_err(lib)?
            .with_tolerance(BW15_RTOL)
            .map_err(lib)?;
        timings.push(time_op("bouc_wen n=1.5", &mut bw, &x, &mut y, runs)?);
        // The reference is the other solver: step-by-step adaptive
        // integration at a tolerance a thousand times tighter.
        let mut reference = bouc_wen(1.5)
            .map_err(lib)?
            .with_tolerance(1e-13)
            .map_err(lib)?
            .with_solver(StateSolver::Adaptive);
        let want = reference.run(&x).map_err(lib)?;
        let scale = want.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let err = y
            .iter()
            .zip(&want)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        notes.push(format!(
            "bouc_wen n=1.5 ({}, rtol {BW15_RTOL:e}): max |error| {:.2e} of max |H| {scale:.3} (relative {:.2e}) against adaptive DP5 at rtol 1e-13",
            if bw.is_tabulated() { "tabulated flow" } else { "adaptive DP5" },
            err,
            err / scale
        ));
    }
    if wanted("mms") {
        timings.push(time_op("mms", &mut mms().map_err(lib)?, &x, &mut y, runs)?);
    }
    for (kernel, mut op) in [
        (
            "bwbn",
            Box::new(bwbn().map_err(lib)?) as Box<dyn Operator<f64>>,
        ),
        ("jiles_atherton", Box::new(jiles_atherton().map_err(lib)?)),
    ] {
        if wanted(kernel) {
            timings.push(time_op(kernel, op.as_mut(), &x, &mut y, runs)?);
            notes.push(format!(
                "{kernel}: checksum (sum of outputs) {:.10e}",
                y.iter().sum::<f64>()
            ));
        }
    }
    if wanted("paper model") {
        let mut stat = paper_model().map_err(lib)?;
        let t_static = time_op("paper model", &mut stat, &x, &mut y, runs)?;
        let static_y = y.clone();
        let mut boxed = paper_model_from_json()?;
        let t_boxed = time_op("paper model, boxed from JSON", &mut boxed, &x, &mut y, runs)?;
        if y != static_y {
            return Err("paper model: boxed and static outputs differ".into());
        }
        notes.push(format!(
            "paper model: boxed from JSON / static = {:.2}",
            t_boxed.median() / t_static.median()
        ));
        timings.push(t_static);
        timings.push(t_boxed);
    }
    if wanted("batch") {
        // The same samples as one kernel run, as BATCH records of
        // samples/BATCH each (every record from the model's initial state),
        // into preallocated outputs.
        let model = paper_model_from_json()?;
        let len = x.len().div_ceil(BATCH).max(1);
        let inputs: Vec<&[f64]> = x.chunks(len).collect();
        let mut medians = Vec::new();
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .map_err(|e| e.to_string())?;
            let kernel = format!("paper model batch x{}, {threads} thread(s)", inputs.len());
            let t = time_with(&kernel, x.len(), runs, || {
                let mut outputs: Vec<&mut [f64]> = y.chunks_mut(len).collect();
                pool.install(|| process_records(model.as_ref(), &inputs, &mut outputs))
                    .into_iter()
                    .collect::<Result<Vec<()>>>()
                    .map(|_| ())
            })?;
            medians.push(t.median());
            timings.push(t);
        }
        notes.push(format!(
            "paper model batch: 2 threads are {:.2}x 1 thread",
            medians[0] / medians[1]
        ));
    }
    let mut exp_costs = Vec::new();
    // (each also where the ensemble whose bound it gives runs)
    for (kernel, f, ensemble) in [
        (
            "exp kernel",
            exp_kernel::exp_in_place as fn(&mut [f64]),
            "ensemble bouc_wen n=1",
        ),
        (
            "exp_m1 kernel",
            exp_kernel::exp_m1_nonpositive_in_place,
            "ensemble mms",
        ),
    ] {
        if wanted(kernel) || wanted(ensemble) {
            // (over blocks that stay in the L1 cache: the cost of the
            // arithmetic, which the kernels pay, not of streaming memory)
            let minus: Vec<f64> = x.iter().take(EXP_BLOCK).map(|v| -v.abs()).collect();
            let mut block = minus.clone();
            let blocks = (x.len() / EXP_BLOCK).max(1);
            let t = time_with(kernel, blocks * minus.len(), runs, || {
                for _ in 0..blocks {
                    block.copy_from_slice(&minus);
                    f(&mut block);
                    std::hint::black_box(&mut block);
                }
                Ok(())
            })?;
            exp_costs.push((kernel, t.median()));
            timings.push(t);
        }
    }
    if wanted("bouc_wen system") || wanted("ensemble bouc_wen system") {
        system_kernels(&x, runs, &wanted, &mut timings, &mut notes)?;
    }
    // (kernel, the single kernel it is compared with, spec, the parameter
    // spread)
    let fixed = |k: &str, alone: &str, spec: &str, spread| {
        (k.to_string(), alone.to_string(), spec.to_string(), spread)
    };
    let mut ensembles = vec![fixed(
        "ensemble play",
        "play",
        r#"{"type": "play", "r": 0.5}"#,
        "r",
    )];
    for m in PI_PLAYS {
        let p = pi_bank(m).map_err(lib)?.parameters().clone();
        let spec = Spec::leaf::<PiBank<f64>>(p)
            .to_json_pretty()
            .map_err(|e| e.to_string())?;
        ensembles.push((
            format!("ensemble pi_bank {m}"),
            format!("pi_bank {m}"),
            spec,
            "a0",
        ));
    }
    ensembles.extend([
        fixed(
            "ensemble mms",
            "mms",
            r#"{"type": "mms", "f_c": 1.0, "k": 5.0}"#,
            "f_c",
        ),
        fixed("ensemble bouc_wen n=1", "bouc_wen n=1", BW_SPEC_1, "beta"),
        fixed(
            "ensemble bouc_wen n=1.5",
            "bouc_wen n=1.5",
            BW_SPEC_15,
            "beta",
        ),
    ]);
    for (kernel, alone, spec, spread) in &ensembles {
        let (kernel, alone) = (kernel.as_str(), alone.as_str());
        if wanted(kernel) {
            let (t, checksum, setup) = time_ensemble(kernel, spec, spread, &x, runs)?;
            notes.push(format!(
                "{kernel}: checksum (sum of outputs) {checksum:.10e}"
            ));
            notes.push(format!(
                "{kernel}: of its {:.3} ns, {setup:.3} set the instances up (a run over one sample)",
                t.median()
            ));
            if let Some(one) = timings.iter().find(|t| t.kernel == alone) {
                notes.push(format!(
                    "{kernel}: {:.2}x the instances per second of one {alone} at a time (1 thread)",
                    one.median() / t.median()
                ));
                // (the exponential each (instance-)sample takes, which
                // both evaluate eight per instruction)
                let exp = match alone {
                    "mms" => Some("exp_m1 kernel"),
                    "bouc_wen n=1" => Some("exp kernel"),
                    _ => None,
                };
                let cost = exp.and_then(|exp| exp_costs.iter().find(|(k, _)| *k == exp));
                if let Some((exp, e)) = cost {
                    notes.push(format!(
                        "{kernel}: at most {:.2}x by the {exp} ({e:.3} ns per value, the same in both)",
                        one.median() / e
                    ));
                }
            }
            timings.push(t);
        }
    }
    let kernel = "lanes bouc_wen n=1.5";
    if wanted(kernel) {
        let t = time_flow_lanes(kernel, &x, runs)?;
        if let Some(one) = timings.iter().find(|t| t.kernel == "bouc_wen n=1.5") {
            notes.push(format!(
                "{kernel}: {:.2}x the instances per second of one bouc_wen n=1.5 at a time (1 thread; ensembles do not take these lanes)",
                one.median() / t.median()
            ));
        }
        timings.push(t);
    }
    if timings.is_empty() {
        return Err(format!(
            "no kernel matches {:?}",
            opts.filter.as_deref().unwrap_or("")
        ));
    }
    Ok(BenchReport { timings, notes })
}
