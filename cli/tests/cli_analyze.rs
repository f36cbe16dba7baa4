//! End-to-end tests of `hysteron analyze`: the printed describing
//! function and loop work of a play against their closed forms, the CSV
//! output, and bad inputs (one-line error, exit code 1, no panic, nothing
//! written).

use hysteron::composition::PiBank;
use hysteron::models::describing::play_describing_function;
use hysteron::models::energy::pi_bank_loop_work;
use hysteron::models::Spec;
use std::f64::consts::PI;
use std::fs;
use std::path::Path;
use tempfile::TempDir;

mod common;
use common::*;

const PLAY: &str = r#"{"type": "play", "r": 0.3}"#;

/// The table rows of the report: `A, |N|, phase_deg, dissipated_per_loop,
/// work`.
fn rows(stdout: &str) -> Vec<[f64; 5]> {
    stdout
        .lines()
        .filter_map(|line| {
            let v: Vec<f64> = line
                .split_whitespace()
                .map(|t| t.parse::<f64>())
                .collect::<Result<_, _>>()
                .ok()?;
            (v.len() == 5).then(|| [v[0], v[1], v[2], v[3], v[4]])
        })
        .collect()
}

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.join(name);
    fs::write(&p, text).unwrap();
    p
}

#[test]
fn play_matches_the_closed_forms() {
    let tmp = TempDir::new().unwrap();
    let spec = write(tmp.path(), "play.json", PLAY);
    let out = tmp.path().join("table.csv");
    let n = 4096;
    let assert = hysteron(tmp.path())
        .args([
            "analyze",
            "--model",
            "play.json",
            "--amplitudes",
            "1,0.5,2.75,0.2",
        ])
        .args([
            "--samples-per-period",
            &n.to_string(),
            "--settle-periods",
            "3",
            // every digit, for the closed forms' bounds
            "--precision",
            "17",
        ])
        .arg("--output")
        .arg(&out)
        .assert()
        .success();
    let stdout = stdout_of(&assert);
    let table = rows(&stdout);
    assert_eq!(table.len(), 4, "{stdout}");
    let r = 0.3;
    let h = 2.0 * PI / n as f64;
    // quadrature bound of the describing function (see tests/describing.rs:
    // two kinks, slope 1): √2 h² (2/(8π) + 2/3)
    let df_bound = 2f64.sqrt() * h * h * (2.0 / (8.0 * PI) + 2.0 / 3.0);
    for (row, a) in table.iter().zip([1.0, 0.5, 2.75, 0.2]) {
        assert_eq!(row[0], a);
        let (re, im) = play_describing_function(r, a);
        let gain = re.hypot(im);
        assert!(
            (row[1] - gain).abs() <= df_bound,
            "A={a}: |N| {} vs {gain}",
            row[1]
        );
        if gain > 0.0 {
            let phase = im.atan2(re).to_degrees();
            // |Δ arg| ≤ |ΔN| / |N| (radians)
            let tol = (df_bound / gain).to_degrees();
            assert!(
                (row[2] - phase).abs() <= tol,
                "A={a}: phase {} vs {phase}",
                row[2]
            );
            assert!(row[2] < 0.0, "a play lags");
        } else {
            assert_eq!((row[1], row[2]), (0.0, 0.0));
        }
        // ∮ y dx = −4 r (A − r) for A > r, within the trapezoid rule's
        // kink bound 2 Δx²/8, Δx ≤ 2A sin(π/N), plus rounding
        let work = if a > r { -4.0 * r * (a - r) } else { 0.0 };
        let dx = 2.0 * a * (PI / n as f64).sin();
        let bound = 2.0 * dx * dx / 8.0 + 1e-12 * a;
        assert!(
            (row[4] - work).abs() <= bound,
            "A={a}: work {} vs {work}",
            row[4]
        );
        // the dissipated energy is the loop's area: positive
        assert_eq!(row[3], row[4].abs());
    }
    assert!(stdout.contains("wrote"), "{stdout}");

    // The CSV holds the same numbers at full precision.
    let mut reader = csv::Reader::from_path(&out).unwrap();
    assert_eq!(
        reader.headers().unwrap().iter().collect::<Vec<_>>(),
        [
            "amplitude",
            "gain",
            "phase_deg",
            "re",
            "im",
            "work",
            "dissipated"
        ]
    );
    let recs: Vec<Vec<f64>> = reader
        .records()
        .map(|r| r.unwrap().iter().map(|c| c.parse().unwrap()).collect())
        .collect();
    assert_eq!(recs.len(), 4);
    for (rec, row) in recs.iter().zip(&table) {
        // printed with 17 significant digits
        for (i, j) in [(0, 0), (1, 1), (2, 2), (5, 4), (6, 3)] {
            assert!(
                (rec[i] - row[j]).abs() <= 1e-15 * rec[i].abs().max(1e-300),
                "{rec:?} {row:?}"
            );
        }
        assert!((rec[3].hypot(rec[4]) - rec[1]).abs() <= 1e-15);
    }
    assert_no_temp_files(tmp.path());
    assert_eq!(fs::read_to_string(&spec).unwrap(), PLAY);
}

/// By default the table has at most 6 significant digits (`0.2`, not
/// `2.000000000000000e-1`); `--precision` asks for more, and a value
/// outside 1 to 17 is refused naming the option.
#[test]
fn the_table_is_short_by_default() {
    let tmp = TempDir::new().unwrap();
    write(tmp.path(), "play.json", PLAY);
    let run = |extra: &[&str]| {
        let assert = hysteron(tmp.path())
            .args(["analyze", "--model", "play.json", "--amplitudes", "0.2,1"])
            .args(extra)
            .assert()
            .success();
        stdout_of(&assert)
    };
    let short = run(&[]);
    let cells: Vec<String> = short
        .lines()
        .filter(|l| l.trim_start().starts_with(|c: char| c.is_ascii_digit()))
        .flat_map(|l| l.split_whitespace().map(str::to_string).collect::<Vec<_>>())
        .collect();
    assert_eq!(cells.len(), 10, "{short}");
    assert_eq!(cells[0], "0.2", "{short}");
    for c in &cells {
        let digits = c
            .split(['e', 'E'])
            .next()
            .unwrap()
            .chars()
            .filter(char::is_ascii_digit)
            .collect::<String>();
        let significant = digits.trim_start_matches('0').len();
        assert!(significant <= 6, "`{c}` has {significant} digits: {short}");
    }
    let long = run(&["--precision", "12"]);
    assert_ne!(long, short);
    for bad in ["0", "18"] {
        let assert = hysteron(tmp.path())
            .args(["analyze", "--model", "play.json", "--amplitudes", "1"])
            .args(["--precision", bad])
            .assert()
            .failure()
            .code(1);
        let stderr = String::from_utf8_lossy(&assert.get_output().stderr).into_owned();
        assert!(stderr.contains("--precision"), "{stderr}");
    }
}

/// A Prandtl-Ishlinskii loop (the example spec) runs counterclockwise and
/// dissipates: `dissipated_per_loop` is positive and equals the closed form
/// `Σ_{r_j < A} 4 w_j r_j (A − r_j)` (the library's `pi_bank_loop_work`,
/// checked against it in `tests/energy.rs`), the signed work `∮ y dx` is its
/// negative, and the help says which is which. A stop's clockwise loop
/// dissipates too: positive, with positive work.
#[test]
fn a_prandtl_ishlinskii_loop_dissipates_a_positive_energy() {
    let tmp = TempDir::new().unwrap();
    let spec =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/specs/prandtl-ishlinskii.json");
    let bank = Spec::from_json_file(&spec)
        .unwrap()
        .leaf_params::<PiBank<f64>>()
        .unwrap();
    let n = 4096;
    let assert = hysteron(tmp.path())
        .arg("analyze")
        .arg("--model")
        .arg(&spec)
        .args([
            "--amplitudes",
            "0.35,1",
            "--samples-per-period",
            &n.to_string(),
        ])
        .assert()
        .success();
    let stdout = stdout_of(&assert);
    let table = rows(&stdout);
    assert_eq!(table.len(), 2, "{stdout}");
    for row in &table {
        let a = row[0];
        let closed = -pi_bank_loop_work(&bank, a);
        // the trapezoid rule's kink bound: 2 |w_j| Δx²/8 per play
        let dx = 2.0 * a * (PI / n as f64).sin();
        let bound = bank
            .w
            .iter()
            .map(|w| 2.0 * w.abs() * dx * dx / 8.0)
            .sum::<f64>()
            + 1e-12;
        assert!(row[3] > 0.0, "dissipated {} ≤ 0: {stdout}", row[3]);
        assert!(
            (row[3] - closed).abs() <= bound,
            "A={a}: {} vs {closed}",
            row[3]
        );
        assert!(row[4] < 0.0 && row[4] == -row[3], "work {}", row[4]);
    }
    assert!(
        stdout.contains("dissipated_per_loop = loop area |∮ y dx| (> 0 for any hysteresis loop)")
            && stdout.contains("work = ∮ y dx (< 0 counterclockwise"),
        "{stdout}"
    );
    let help = hysteron(tmp.path())
        .args(["analyze", "--help"])
        .assert()
        .success();
    let help = stdout_of(&help);
    let help = help.split_whitespace().collect::<Vec<_>>().join(" ");
    for words in [
        "the energy dissipated per loop (the loop's area |∮ y dx|",
        "∮ y dx (< 0 for a counterclockwise loop, > 0 for a clockwise one)",
    ] {
        assert!(help.contains(words), "{words} in {help}");
    }
    assert!(!help.contains("> 0 dissipative"), "{help}");

    write(tmp.path(), "stop.json", r#"{"type": "stop", "r": 0.25}"#);
    let assert = hysteron(tmp.path())
        .args(["analyze", "--model", "stop.json", "--amplitudes", "1"])
        .assert()
        .success();
    let stdout = stdout_of(&assert);
    let row = rows(&stdout)[0];
    assert!((row[3] - 4.0 * 0.25 * 0.75).abs() < 1e-5, "{stdout}");
    assert!(row[4] > 0.0 && row[4] == row[3], "{stdout}");
}

/// Bad inputs: exit code 1 and one line on stderr naming the problem;
/// nothing written.
#[test]
fn bad_inputs_are_one_line_errors() {
    let tmp = TempDir::new().unwrap();
    write(tmp.path(), "play.json", PLAY);
    write(tmp.path(), "broken.json", r#"{"type": "play", "r": "#);
    write(tmp.path(), "invalid.json", r#"{"type": "play", "r": -1}"#);
    write(
        tmp.path(),
        "unknown.json",
        r#"{"type": "sprocket", "m": 1}"#,
    );
    write(
        tmp.path(),
        "ringing.json",
        r#"{"type": "mass_spring_damper", "m": 1, "c": 0.05, "k": 40, "dt": 0.01}"#,
    );
    write(
        tmp.path(),
        "noinverse.json",
        r#"{"type": "inverse", "inner": {"type": "saturation", "lo": -1, "hi": 1}}"#,
    );
    // the arguments of `analyze` (split at spaces) and what the error says
    let cases = [
        (
            "--model play.json --amplitudes -1",
            "invalid amplitude = -1",
        ),
        (
            "--model play.json --amplitudes 1,-0.5",
            "invalid amplitude = -0.5",
        ),
        (
            "--model play.json --amplitudes -1,2",
            "invalid amplitude = -1",
        ),
        ("--model play.json --amplitudes=0", "invalid amplitude = 0"),
        (
            "--model play.json --amplitudes nan",
            "invalid amplitude = NaN",
        ),
        (
            "--model play.json --amplitudes inf",
            "invalid amplitude = inf",
        ),
        ("--model missing.json --amplitudes 1", "missing.json"),
        ("--model broken.json --amplitudes 1", "broken.json"),
        ("--model invalid.json --amplitudes 1", "must be ≥ 0"),
        ("--model unknown.json --amplitudes 1", "sprocket"),
        (
            "--model play.json --amplitudes 1 --samples-per-period 10",
            "samples_per_period",
        ),
        (
            "--model play.json --amplitudes 1 --steady-tol -1",
            "steady_tol",
        ),
        (
            "--model ringing.json --amplitudes 1 --samples-per-period 64 --settle-periods 3",
            "not periodic",
        ),
        (
            "--model noinverse.json --amplitudes 2",
            "failed in period 0",
        ),
        (
            "--model play.json --amplitudes 1 --output play.json",
            "same file as the model",
        ),
        (
            "--model play.json --amplitudes 1 --output nodir/out.csv",
            "does not exist",
        ),
    ];
    let before = snapshot(tmp.path());
    for (args, expected) in cases {
        let args: Vec<&str> = args.split_whitespace().collect();
        let assert = hysteron(tmp.path())
            .arg("analyze")
            .args(&args)
            .assert()
            .code(1);
        let err = one_line_error(&assert.get_output().stderr);
        assert!(err.contains(expected), "{args:?}: {err}");
        assert!(assert.get_output().stdout.is_empty(), "{args:?}");
        assert_eq!(snapshot(tmp.path()), before, "{args:?} wrote something");
    }
    // Options refused as arguments (clap's message naming the option and
    // what it needs; negative numbers are values, not unknown options):
    // exit code 1 too.
    let cases: Vec<([&str; 2], &str)> = vec![
        (
            ["--dt", "-0.5"],
            "'--dt <SECONDS>': must be positive and finite (got -0.5)",
        ),
        (
            ["--dt", "0"],
            "'--dt <SECONDS>': must be positive and finite (got 0)",
        ),
        (
            ["--settle-periods", "1"],
            "'--settle-periods <P>': must be at least 2 (got 1)",
        ),
        (
            ["--settle-periods", "-2"],
            "'--settle-periods <P>': must be at least 2 (got -2)",
        ),
        (
            ["--samples-per-period", "-8"],
            "'--samples-per-period <N>': must be at least 8 (got -8)",
        ),
    ];
    for (args, expected) in cases {
        let err = usage_error(
            hysteron(tmp.path())
                .args(["analyze", "--model", "play.json", "--amplitudes", "1"])
                .args(args),
            expected,
        );
        assert!(!err.contains("unexpected argument"), "{err}");
        assert_eq!(snapshot(tmp.path()), before, "{args:?} wrote something");
    }
}
