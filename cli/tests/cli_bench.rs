//! End-to-end tests of `hysteron bench`: the table rows have the format the
//! performance issue defines, one per kernel, with consistent numbers; bad
//! options give a one-line error and a non-zero exit code.

use tempfile::TempDir;

mod common;
use common::*;

/// The fields of a row `| hysteron | kernel | runs | samples/s | ns | min..max |`.
fn row(line: &str) -> Option<(String, usize, f64, f64, f64, f64)> {
    let cells: Vec<&str> = line
        .trim()
        .strip_prefix('|')?
        .strip_suffix('|')?
        .split('|')
        .map(str::trim)
        .collect();
    if cells.len() != 6 || cells[0] != "hysteron" {
        return None;
    }
    let (min, max) = cells[5].split_once("..")?;
    Some((
        cells[1].to_string(),
        cells[2].parse().ok()?,
        cells[3].parse().ok()?,
        cells[4].parse().ok()?,
        min.parse().ok()?,
        max.parse().ok()?,
    ))
}

/// `hysteron bench ARGS` run in a fresh directory.
fn bench(args: &[&str]) -> std::process::Output {
    let dir = TempDir::new().unwrap();
    hysteron(dir.path())
        .arg("bench")
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn prints_one_row_per_kernel_in_the_table_format() {
    let out = bench(&["--samples", "3000", "--runs", "3"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8(out.stdout).unwrap();
    let rows: Vec<_> = stdout.lines().filter_map(row).collect();
    let kernels: Vec<&str> = rows.iter().map(|r| r.0.as_str()).collect();
    assert_eq!(
        kernels,
        [
            "play",
            "pi_bank 4",
            "pi_bank 64",
            "bouc_wen n=1",
            "bouc_wen n=1.5",
            "mms",
            "bwbn",
            "jiles_atherton",
            "paper model",
            "paper model, boxed from JSON",
            "paper model batch x64, 1 thread(s)",
            "paper model batch x64, 2 thread(s)",
            "exp kernel",
            "exp_m1 kernel",
            "bouc_wen system",
            "bouc_wen system, boxed from JSON",
            "ensemble bouc_wen system",
            "ensemble play",
            "ensemble pi_bank 4",
            "ensemble pi_bank 64",
            "ensemble mms",
            "ensemble bouc_wen n=1",
            "ensemble bouc_wen n=1.5",
            "lanes bouc_wen n=1.5",
        ],
        "{stdout}"
    );
    for (kernel, runs, per_s, ns, min, max) in &rows {
        assert_eq!(*runs, 3, "{kernel}");
        assert!(
            *min > 0.0 && min <= ns && ns <= max,
            "{kernel}: {min} {ns} {max}"
        );
        // samples/s is the reciprocal of the median ns/sample (printed to
        // 5 and 3 significant digits).
        let rel = (per_s * ns * 1e-9 - 1.0).abs();
        assert!(rel < 5e-3, "{kernel}: {per_s} samples/s vs {ns} ns");
    }
    // The accuracy note of the n = 1.5 kernel: a measured relative error.
    let note = stdout
        .lines()
        .find(|l| l.starts_with("bouc_wen n=1.5"))
        .unwrap_or_else(|| panic!("no accuracy note: {stdout}"));
    let rel: f64 = note
        .rsplit("(relative ")
        .next()
        .and_then(|t| t.split(')').next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("unparsable note {note}"));
    assert!(rel < 1e-6, "{note}");
}

#[test]
fn kernel_filter_selects_rows() {
    let out = bench(&["--samples", "1000", "--runs", "1", "--kernel", "mms"]);
    assert!(out.status.success());
    let stdout = String::from_utf8(out.stdout).unwrap();
    let kernels: Vec<String> = stdout.lines().filter_map(row).map(|r| r.0).collect();
    assert_eq!(kernels, ["mms", "exp_m1 kernel", "ensemble mms"]);
    // with its single-instance kernel in the run, the ensemble's ratio to
    // it, and the bound the exponential both take puts on that ratio
    assert!(
        stdout.contains("ensemble mms: ")
            && stdout.contains("x the instances per second of one mms")
            && stdout.contains("x by the exp_m1 kernel"),
        "{stdout}"
    );
}

#[test]
fn bad_options_are_errors_not_panics() {
    let out = bench(&["--samples", "100", "--kernel", "no-such-kernel"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(one_line_error(&out.stderr).contains("no kernel matches"));
    // argument errors exit with 1 like all bad input, saying the range
    for (args, expected) in [
        (
            ["--samples", "0"],
            "'--samples <N>': must be at least 1 (got 0)",
        ),
        (["--runs", "0"], "'--runs <R>': must be at least 1 (got 0)"),
        (
            ["--runs", "1001"],
            "'--runs <R>': must be at most 1000 (got 1001)",
        ),
        (
            ["--samples", "-5"],
            "'--samples <N>': must be at least 1 (got -5)",
        ),
    ] {
        let out = bench(&args);
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!err.contains("panicked"));
        assert!(err.contains(expected), "{args:?}: {err}");
    }
}
