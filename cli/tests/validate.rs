//! End-to-end tests of `hysteron validate`: the table and `--csv` for a
//! model that reproduces a record exactly and for a known offset (NRMSE by
//! hand), two records, `--skip`, `--lowpass` on a record with
//! high-frequency noise, `--plot`, and every bad-input case (one line on
//! stderr starting with `error:`, exit code 1, nothing written).
//!
//! The records are small synthetic CSV files written into a temporary
//! directory; the model is a `gain` spec (F = k·x), whose output is exact.

use std::f64::consts::TAU;
use std::fs;
use std::path::Path;
use tempfile::TempDir;

mod common;
use common::*;

/// Writes a CSV file `name` with `header` and the columns.
fn write_csv(dir: &Path, name: &str, header: &str, columns: &[&[f64]]) {
    let mut s = format!("{header}\n");
    for i in 0..columns[0].len() {
        let row: Vec<String> = columns.iter().map(|c| format!("{:?}", c[i])).collect();
        s.push_str(&row.join(","));
        s.push('\n');
    }
    fs::write(dir.join(name), s).unwrap();
}

fn gain(dir: &Path, k: f64) {
    fs::write(
        dir.join("gain.json"),
        format!("{{\"type\": \"gain\", \"k\": {k:?}}}"),
    )
    .unwrap();
}

fn num(s: &str) -> f64 {
    s.parse().unwrap_or_else(|_| panic!("not a number: {s}"))
}

/// `x` and `F = 2x` (exact) and `F = 2x + 0.5` (exact in binary) over
/// six samples: x = 0, 1, −1, 2, −2, 0.5.
const X: [f64; 6] = [0.0, 1.0, -1.0, 2.0, -2.0, 0.5];

fn setup() -> TempDir {
    let tmp = TempDir::new().unwrap();
    let d = tmp.path();
    gain(d, 2.0);
    let exact: Vec<f64> = X.iter().map(|x| 2.0 * x).collect();
    let offset: Vec<f64> = X.iter().map(|x| 2.0 * x + 0.5).collect();
    write_csv(d, "exact.csv", "x,F", &[&X, &exact]);
    write_csv(d, "offset.csv", "x,F", &[&X, &offset]);
    tmp
}

/// NRMSE of the offset record by hand: the error is −0.5 at every
/// sample, so RMS = 0.5; F = 0.5, 2.5, −1.5, 4.5, −3.5, 1.5 has
/// Σ F² = 0.25 + 6.25 + 2.25 + 20.25 + 12.25 + 2.25 = 43.5, RMS(F) =
/// √(43.5/6) = √7.25.
fn offset_nrmse() -> f64 {
    0.5 / 7.25_f64.sqrt()
}

#[test]
fn exact_and_offset_records_give_the_figures_computed_by_hand() {
    let tmp = setup();
    let d = tmp.path();
    let out = hysteron(d)
        .args(["validate", "--model", "gain.json"])
        .args(["--data", "exact.csv", "--data", "offset.csv"])
        .args(["--csv", "table.csv"])
        .assert()
        .success();
    let stdout = stdout_of(&out);
    for row in [
        "| record | samples | RMS | max \\|err\\| | NRMSE |\n",
        "| exact.csv | 6 | 0 | 0 | 0 |\n",
        // 0.5/√7.25 = 0.18569...
        "| offset.csv | 6 | 0.5000 | 0.5000 | 0.1857 |\n",
        // the mean row: unweighted means, total samples
        "| mean | 12 | 0.2500 | 0.2500 | 0.09285 |\n",
    ] {
        assert!(stdout.contains(row), "{row} in {stdout}");
    }
    assert!(!stdout.contains("low-passed NRMSE"), "{stdout}");

    let (header, rows) = read_csv(&d.join("table.csv"));
    assert_eq!(header, ["record", "samples", "rms", "max_abs_err", "nrmse"]);
    assert_eq!(rows.len(), 2, "one row per record, no mean row");
    assert_eq!(rows[0], ["exact.csv", "6", "0", "0", "0"]);
    assert_eq!(rows[1][..2], ["offset.csv", "6"]);
    assert_eq!(num(&rows[1][2]), 0.5);
    assert_eq!(num(&rows[1][3]), 0.5);
    let nrmse = num(&rows[1][4]);
    assert!(
        (nrmse - offset_nrmse()).abs() < 1e-12,
        "{nrmse} vs {}",
        offset_nrmse()
    );
    assert_no_temp_files(d);
}

#[test]
fn the_nrmse_is_relative_to_the_rms_about_zero_not_the_std() {
    // F = 2x + 10: the std of F is that of 2x, its RMS about zero is
    // √(Σ(2x + 10)²/n); the error −10 over RMS about zero.
    let tmp = setup();
    let d = tmp.path();
    let f: Vec<f64> = X.iter().map(|x| 2.0 * x + 10.0).collect();
    write_csv(d, "big.csv", "x,F", &[&X, &f]);
    hysteron(d)
        .args(["validate", "--model", "gain.json", "--data", "big.csv"])
        .args(["--csv", "t.csv"])
        .assert()
        .success();
    let (_, rows) = read_csv(&d.join("t.csv"));
    let rms_f = (f.iter().map(|v| v * v).sum::<f64>() / 6.0).sqrt();
    let expected = 10.0 / rms_f;
    let got = num(&rows[0][4]);
    assert!((got - expected).abs() < 1e-12, "{got} vs {expected}");
}

#[test]
fn skip_leaves_the_warm_up_unscored() {
    // 10 samples at dt = 0.1 s; the first 3 (t = 0, 0.1, 0.2 < 0.3) are
    // wrong by 100, the rest exact.
    let tmp = setup();
    let d = tmp.path();
    let x: Vec<f64> = (0..10).map(|i| f64::from(i) - 4.5).collect();
    let f: Vec<f64> = x
        .iter()
        .enumerate()
        .map(|(i, x)| if i < 3 { 100.0 } else { 2.0 * x })
        .collect();
    write_csv(d, "warm.csv", "x,F", &[&x, &f]);
    let run = |skip: &str| {
        hysteron(d)
            .args(["validate", "--model", "gain.json", "--data", "warm.csv"])
            .args(["--dt", "0.1", "--skip", skip, "--csv", "t.csv"])
            .assert()
            .success();
        read_csv(&d.join("t.csv")).1.remove(0)
    };
    let row = run("0.3");
    assert_eq!(row[1..], ["7", "0", "0", "0"]);
    // one sample less skipped: the third (x = −2.5, F = 100) is scored
    let row = run("0.2");
    assert_eq!(row[1], "8");
    assert_eq!(num(&row[3]), 105.0);
    let row = run("0");
    assert_eq!(row[1], "10");

    // a record not longer than its skip
    let out = hysteron(d)
        .args(["validate", "--model", "gain.json", "--data", "exact.csv"])
        .args(["--data", "warm.csv", "--dt", "0.1", "--skip", "0.6"])
        .assert()
        .failure()
        .code(1);
    let e = one_line_error(&out.get_output().stderr);
    assert!(e.contains("`exact.csv`") && e.contains("--skip 0.6"), "{e}");
}

/// `--lowpass` on a record whose measurement is the model's output plus
/// high-frequency tones (the noise).
#[test]
fn lowpass_removes_high_frequency_noise_from_the_score() {
    let tmp = setup();
    let d = tmp.path();
    // 4 s at 1024 Hz: x a 1 Hz sine of amplitude 1; the measurement 2x
    // plus tones of amplitude 0.1 at 150, 230 and 370 Hz.
    let rate = 1024.0;
    let n = 4096;
    let t: Vec<f64> = (0..n).map(|i| f64::from(i) / rate).collect();
    let x: Vec<f64> = t.iter().map(|t| (TAU * t).sin()).collect();
    let noise = |t: f64| {
        0.1 * ((TAU * 150.0 * t).sin()
            + (TAU * 230.0 * t + 1.0).sin()
            + (TAU * 370.0 * t + 2.0).sin())
    };
    let f: Vec<f64> = x.iter().zip(&t).map(|(x, t)| 2.0 * x + noise(*t)).collect();
    write_csv(d, "noisy.csv", "t,x,F", &[&t, &x, &f]);
    succeeds_saying(
        hysteron(d)
            .args(["validate", "--model", "gain.json", "--data", "noisy.csv"])
            .args(["--time-column", "t", "--lowpass", "15", "--csv", "t.csv"]),
        &[" low-passed NRMSE |\n"],
    );
    let (header, rows) = read_csv(&d.join("t.csv"));
    assert_eq!(header.last().unwrap(), "lowpassed_nrmse");
    let (full, low) = (num(&rows[0][4]), num(&rows[0][5]));
    // Full band: the error is the noise, RMS 0.1·√(3/2) = 0.1225, over
    // RMS(F) ≈ √(2 + 0.015) = 1.4195: 0.0863.
    let noise_rms = 0.1 * 1.5_f64.sqrt();
    let expected_full = noise_rms / (2.0 + noise_rms * noise_rms).sqrt();
    assert!(
        (full - expected_full).abs() < 1e-3,
        "{full} vs {expected_full}"
    );
    // Low-passed at 15 Hz: both signals go through the same linear filter,
    // so the error is the filtered noise. In steady state a tone at
    // f ≥ 150 Hz keeps |H_fb| = 1/(1 + (tan(πf/f_s)/tan(πf_c/f_s))⁸) ≤ 1e-8
    // of its amplitude. What is left are the start-up transients where
    // the forward pass and the backward pass begin (the constant part of
    // the start is absorbed by the steady-state initial conditions): a tone
    // A sin(ωt) switched on excites each pole p_k of
    // H(s) = ω_c⁴/Π(s − p_k) with amplitude |r_k|·A·ω/|p_k² + ω²| ≈
    // |r_k|·A/ω, and Σ|r_k| = 3.414·ω_c for the 4th-order Butterworth, so
    // the transient is at most 3.414·(f_c/f)·A per tone: 3 tones,
    // 3·3.414·0.1·0.1 = 0.1024. It decays at least as e^(−t/τ), with
    // τ = 1/(ω_c sin(π/8)) = 0.0277 s (the slowest pole), so its energy is
    // at most 0.1024²·τ/2 per end; the other pass (|H| ≤ 1) cannot add
    // energy. Two ends over 4 s: RMS ≤ √(0.1024²·0.0277/4) = 8.5e-3,
    // NRMSE ≤ 8.5e-3/1.4195 = 6.0e-3 (measured: 5.1e-3), at most 1/14 of
    // the full-band NRMSE.
    assert!(low < 6.0e-3, "low-passed NRMSE {low:e}");
    assert!(low < full / 14.0, "{low:e} vs {full:e}");
}

#[test]
fn plot_writes_one_figure_per_record() {
    let tmp = setup();
    let d = tmp.path();
    // a stem with dots keeps them all
    fs::copy(d.join("offset.csv"), d.join("sine_0.5Hz.csv")).unwrap();
    // a compressed record A.csv.gz is drawn as A.svg
    let mut gz = flate2::write::GzEncoder::new(
        fs::File::create(d.join("rec_1.5in.csv.gz")).unwrap(),
        flate2::Compression::fast(),
    );
    std::io::Write::write_all(&mut gz, &fs::read(d.join("offset.csv")).unwrap()).unwrap();
    gz.finish().unwrap();
    succeeds_saying(
        hysteron(d)
            .args(["validate", "--model", "gain.json"])
            .args(["--data", "exact.csv", "--data", "sine_0.5Hz.csv"])
            .args(["--data", "rec_1.5in.csv.gz"])
            .args(["--plot", "figs"]),
        &["wrote figs/exact.svg, figs/sine_0.5Hz.svg, figs/rec_1.5in.svg"],
    );
    let mut names: Vec<String> = fs::read_dir(d.join("figs"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["exact.svg", "rec_1.5in.svg", "sine_0.5Hz.svg"]);
    for n in &names {
        let p = d.join("figs").join(n);
        assert_svg(&p);
        let svg = fs::read_to_string(&p).unwrap();
        let has = |label: &str| svg.lines().any(|l| l.trim() == label);
        assert!(has("measured") && has("model"), "{n}");
    }
    assert_no_temp_files(&d.join("figs"));

    // with --lowpass the measured trace is the low-passed one
    let t: Vec<f64> = (0..64).map(|i| f64::from(i) / 64.0).collect();
    let x: Vec<f64> = t.iter().map(|t| (TAU * t).sin()).collect();
    let f: Vec<f64> = x.iter().map(|x| 2.0 * x + 0.01).collect();
    write_csv(d, "lp.csv", "t,x,F", &[&t, &x, &f]);
    hysteron(d)
        .args(["validate", "--model", "gain.json", "--data", "lp.csv"])
        .args(["--time-column", "t", "--lowpass", "4", "--plot", "figs"])
        .assert()
        .success();
    let svg = fs::read_to_string(d.join("figs/lp.svg")).unwrap();
    assert!(
        svg.lines()
            .any(|l| l.trim() == "measured, low-passed at 4 Hz"),
        "{svg}"
    );
}

/// Runs `validate` with `args` in the setup directory expecting a one-line
/// error holding every `expect`ed fragment, and checks that nothing was
/// written; the messages name the arguments.
fn refused(tmp: &TempDir, args: &[&str], expect: &[&str]) {
    let mut cmd = hysteron(tmp.path());
    cmd.arg("validate").args(args);
    let e = fails_leaving_dir_unchanged(tmp.path(), &mut cmd, &[]);
    for x in expect {
        assert!(e.contains(x), "{args:?}: `{x}` not in: {e}");
    }
}

/// Runs [`refused`] on each case: `base` followed by the case's arguments.
fn all_refused(tmp: &TempDir, base: &[&str], cases: &[(&[&str], &[&str])]) {
    for (args, expect) in cases {
        refused(tmp, &[base, args].concat(), expect);
    }
}

#[test]
fn bad_records_are_one_line_errors_naming_file_row_and_column() {
    let tmp = setup();
    let d = tmp.path();
    // records whose headers differ in the needed columns
    write_csv(d, "other.csv", "x,Force", &[&X, &X]);
    // NaN in a record, row named
    fs::write(d.join("nan.csv"), "x,F\n1,2\n2,4\n3,NaN\n").unwrap();
    // empty records: header only, and an empty file
    fs::write(d.join("header.csv"), "x,F\n").unwrap();
    fs::write(d.join("empty.csv"), "").unwrap();
    all_refused(
        &tmp,
        &["--model", "gain.json"],
        &[
            // missing column in one record
            (
                &["--data", "exact.csv", "--output-column", "G"],
                &["`exact.csv`: no column `G`"],
            ),
            (
                &["--data", "exact.csv", "--data", "other.csv"],
                &[
                    "`other.csv`: no column `F`",
                    "first record `exact.csv` has it",
                    "headers differ",
                ],
            ),
            (
                &["--data", "exact.csv", "--data", "nan.csv"],
                &["`nan.csv`, row 3 (line 4), column `F`: `NaN` is not finite"],
            ),
            (&["--data", "header.csv"], &["`header.csv`: no data rows"]),
            (&["--data", "empty.csv"], &["`empty.csv`: empty file"]),
            // the same column for input and output
            (
                &["--data", "exact.csv", "--output-column", "x"],
                &["both name the column `x`"],
            ),
        ],
    );
}

#[test]
fn a_non_finite_model_output_is_an_error_naming_the_sample() {
    let tmp = setup();
    let d = tmp.path();
    gain(d, 1e300);
    // 1e300 · 1e10 overflows at sample 1 (row 2, line 3)
    write_csv(d, "big.csv", "x,F", &[&[1.0, 1e10, 1.0], &[1.0, 1.0, 1.0]]);
    refused(
        &tmp,
        &["--model", "gain.json", "--data", "big.csv"],
        &[
            "model `gain.json`",
            "sample 1",
            "`big.csv`, row 2 (line 3), column `x`",
        ],
    );
}

#[test]
fn outputs_may_not_be_inputs() {
    let tmp = setup();
    // a figure DIR/<stem>.svg that is an input
    fs::write(tmp.path().join("exact.svg"), "x,F\n1,2\n").unwrap();
    // two records with one stem
    fs::create_dir(tmp.path().join("sub")).unwrap();
    fs::copy(
        tmp.path().join("exact.csv"),
        tmp.path().join("sub/exact.csv"),
    )
    .unwrap();
    all_refused(
        &tmp,
        &[
            "--model",
            "gain.json",
            "--data",
            "exact.csv",
            "--data",
            "offset.csv",
        ],
        &[
            (
                &["--csv", "offset.csv"],
                &["is the same file as the data `offset.csv`"],
            ),
            (
                &["--csv", "./gain.json"],
                &["is the same file as the model `gain.json`"],
            ),
            (&["--data", "exact.svg", "--plot", "."], &["exact.svg"]),
            (
                &["--data", "sub/exact.csv", "--plot", "figs"],
                &["same file stem"],
            ),
        ],
    );
}

#[test]
fn lowpass_and_skip_need_a_rate_and_a_cut_off_below_nyquist() {
    let tmp = setup();
    let m = ["--model", "gain.json", "--data", "exact.csv"];
    all_refused(
        &tmp,
        &m,
        &[
            (&["--lowpass", "10"], &["--lowpass needs the sample period"]),
            (&["--skip", "1"], &["--skip needs the sample period"]),
            // dt = 0.01 s: Nyquist 50 Hz
            (
                &["--dt", "0.01", "--lowpass", "50"],
                &[
                    "--lowpass 50 Hz must be below the Nyquist frequency 50 Hz",
                    "`exact.csv`",
                ],
            ),
            // six samples are too few for the filter's end padding
            (
                &["--dt", "0.01", "--lowpass", "10"],
                &["`exact.csv`", "too short"],
            ),
        ],
    );
    // a negative cut-off is clap's error naming the option
    let out = hysteron(tmp.path())
        .arg("validate")
        .args(m)
        .args(["--dt", "0.01", "--lowpass", "-1"])
        .assert()
        .failure()
        .code(1);
    let e = String::from_utf8(out.get_output().stderr.clone()).unwrap();
    assert!(
        e.starts_with("error: invalid value '-1' for '--lowpass <HZ>'"),
        "{e}"
    );
}
