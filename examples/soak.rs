//! Soak: 10⁸ samples of a periodic input through the paper's model and
//! through a Bouc-Wen spring with `n = 1.5` (tabulated flow), in chunks of
//! 10⁵ samples with one reused buffer.
//!
//! The input `x_i = 2.5 sin(2π (i mod P) / P)` repeats bit for bit every
//! `P = 2000` samples, so each model settles on a periodic loop. Checked
//! and printed per model:
//! * the last loop against the tenth: `max |y_last − y_10| / max |y_10|`
//!   (≤ 1e-9 asked);
//! * that no output is NaN or infinite (an error is reported with its
//!   sample);
//! * the resident memory after the first chunk and at the end (`VmRSS`
//!   from `/proc/self/status`, Linux), which must not grow.
//!
//! ```sh
//! cargo run --release --example soak            # 10⁸ samples per model
//! cargo run --release --example soak -- 1000000 # fewer
//! ```
//! Exits with status 1 if a check fails.

use hysteron::models::TransmissionParams;
use hysteron::prelude::*;
use std::time::Instant;

/// Samples per loop of the input.
const PERIOD: usize = 2000;
/// Samples per call of `process`.
const CHUNK: usize = 100_000;
/// The loop compared with the last one.
const REFERENCE_LOOP: usize = 10;

/// The resident set size in kB (`None` where `/proc` is not there).
fn rss_kb() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// A model to soak, by name, or the error building it.
type Candidate = (&'static str, Result<Box<dyn Operator<f64>>>);

/// What one soak run measured.
struct Soak {
    seconds: f64,
    /// `max |y_last − y_10| / max |y_10|`.
    drift: f64,
    rss_first: Option<u64>,
    rss_last: Option<u64>,
}

/// Runs `samples` samples (a whole number of loops) through `op`.
fn soak(op: &mut dyn Operator<f64>, samples: usize) -> Result<Soak> {
    let one_loop: Vec<f64> = (0..PERIOD)
        .map(|i| 2.5 * (std::f64::consts::TAU * i as f64 / PERIOD as f64).sin())
        .collect();
    let xs: Vec<f64> = one_loop.iter().cycle().take(CHUNK).copied().collect();
    let mut ys = vec![0.0; CHUNK];
    let mut reference = Vec::with_capacity(PERIOD);
    let mut last = vec![0.0; PERIOD];
    let (mut rss_first, mut done) = (None, 0);
    let start = Instant::now();
    while done < samples {
        let n = CHUNK.min(samples - done);
        op.process(&xs[..n], &mut ys[..n]).map_err(|e| match e {
            // The index within the chunk, made an index within the run.
            Error::AtSample { index, source } => Error::AtSample {
                index: done + index,
                source,
            },
            other => other.at_sample(done),
        })?;
        if let Some(i) = ys[..n].iter().position(|y| !y.is_finite()) {
            return Err(Error::NonFiniteOutput {
                operator: "soak",
                input: xs[i],
            }
            .at_sample(done + i));
        }
        for (k, &y) in ys[..n].iter().enumerate() {
            let i = done + k;
            if i / PERIOD == REFERENCE_LOOP - 1 {
                reference.push(y);
            }
            last[i % PERIOD] = y;
        }
        done += n;
        if rss_first.is_none() {
            rss_first = rss_kb();
        }
    }
    let seconds = start.elapsed().as_secs_f64();
    let scale = reference.iter().fold(0.0_f64, |m, y| m.max(y.abs()));
    let drift = reference
        .iter()
        .zip(&last)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0_f64, f64::max)
        / scale;
    Ok(Soak {
        seconds,
        drift,
        rss_first,
        rss_last: rss_kb(),
    })
}

fn main() {
    let samples: usize = match std::env::args().nth(1).map(|a| a.parse::<usize>()) {
        None => 100_000_000,
        Some(Ok(n)) if n >= (REFERENCE_LOOP + 1) * PERIOD => n - n % PERIOD,
        Some(_) => {
            eprintln!(
                "soak: the sample count must be an integer ≥ {}",
                (REFERENCE_LOOP + 1) * PERIOD
            );
            std::process::exit(1);
        }
    };
    let models: Vec<Candidate> = vec![
        (
            "paper model",
            TransmissionParams::default().build().map(|m| m.boxed()),
        ),
        (
            "bouc_wen n=1.5",
            BoucWen::constant(1.0, 0.1, 1.0, 0.7, 0.3, 1.5).map(|m| m.boxed()),
        ),
    ];
    let mut failed = false;
    for (name, op) in models {
        let result = op.and_then(|mut op| soak(&mut *op, samples));
        match result {
            Ok(s) => {
                let kb = |v: Option<u64>| v.map_or("?".to_string(), |v| format!("{v} kB"));
                let grew = matches!((s.rss_first, s.rss_last), (Some(a), Some(b)) if b > a + 1024);
                let ok = s.drift <= 1e-9 && !grew;
                failed |= !ok;
                println!(
                    "{name}: {samples} samples in {:.2} s ({:.1} ns/sample); last loop vs loop {REFERENCE_LOOP}: {:.2e} relative; no NaN; RSS {} after the first chunk, {} at the end{}",
                    s.seconds,
                    s.seconds * 1e9 / samples as f64,
                    s.drift,
                    kb(s.rss_first),
                    kb(s.rss_last),
                    if ok { "" } else { "  FAILED" }
                );
            }
            Err(e) => {
                failed = true;
                println!("{name}: FAILED: {e}");
            }
        }
    }
    if failed {
        std::process::exit(1);
    }
}
