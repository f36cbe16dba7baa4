//! End-to-end test of `hysteron simulate` with the Preisach example spec
//! (`examples/specs/preisach.json`) and with an invalid Preisach spec.

use hysteron::models::Spec;
use hysteron::Operator;
use std::fs;
use std::path::{Path, PathBuf};
use tempfile::TempDir;

mod common;
use common::*;

fn example() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/specs/preisach.json")
}

/// Columns `t, x` of a CSV with a major loop and a minor loop inside it.
fn input() -> (String, Vec<f64>) {
    let mut xs: Vec<f64> = (0..=40).map(|i| -2.0 + 0.1 * i as f64).collect(); // up to 2
    xs.extend((1..=40).map(|i| 2.0 - 0.1 * i as f64)); // down to −2
    xs.extend((1..=20).map(|i| -2.0 + 0.1 * i as f64)); // up to 0
    xs.extend((1..=5).map(|i| -0.1 * i as f64)); // minor reversal down to −0.5
    let mut text = String::from("t,x\n");
    for (i, x) in xs.iter().enumerate() {
        text.push_str(&format!("{},{x}\n", i as f64 * 0.01));
    }
    (text, xs)
}

fn column(path: &Path, name: &str) -> Vec<f64> {
    let mut r = csv::Reader::from_path(path).unwrap();
    let i = r.headers().unwrap().iter().position(|h| h == name).unwrap();
    r.records()
        .map(|rec| rec.unwrap()[i].parse().unwrap())
        .collect()
}

#[test]
fn simulate_runs_the_preisach_example() {
    let tmp = TempDir::new().unwrap();
    let (text, xs) = input();
    fs::write(tmp.path().join("in.csv"), &text).unwrap();
    let assert = hysteron(tmp.path())
        .args(["simulate", "--model"])
        .arg(example())
        .args([
            "--input", "in.csv", "--output", "out.csv", "--plot", "loop.svg",
        ])
        .assert()
        .success();
    let stdout = stdout_of(&assert);
    assert!(
        stdout.contains(&format!("simulated {} samples", xs.len())),
        "{stdout}"
    );
    let out = tmp.path().join("out.csv");
    assert_eq!(column(&out, "x"), xs);
    let y = column(&out, "y");
    // Bit for bit what the library computes.
    let mut model = Spec::from_json_file(example()).unwrap().build().unwrap();
    assert_eq!(y, model.run(&xs).unwrap());
    // A hysteresis loop: at x = 0 the ascending branch (sample 20) lies
    // below the descending one (sample 60), both inside ±E₀ < ±1.
    assert_eq!(xs[20], 0.0);
    assert!((xs[60]).abs() < 1e-12);
    assert!(y[20] < y[60] - 0.5, "{} {}", y[20], y[60]);
    assert!(y.iter().all(|v| v.abs() < 1.0));
    assert_svg(&tmp.path().join("loop.svg"));
    assert_eq!(fs::read_to_string(tmp.path().join("in.csv")).unwrap(), text);
    assert_no_temp_files(tmp.path());
}

#[test]
fn simulate_names_a_bad_preisach_weight() {
    let tmp = TempDir::new().unwrap();
    fs::write(tmp.path().join("in.csv"), "x\n0.5\n").unwrap();
    fs::write(
        tmp.path().join("bad.json"),
        r#"{"type": "preisach", "measure": {"grid": {"t": [-1, 1], "mu": [[0], [-2, 0]]}}}"#,
    )
    .unwrap();
    let assert = hysteron(tmp.path())
        .args([
            "simulate", "--model", "bad.json", "--input", "in.csv", "--output", "out.csv",
        ])
        .assert()
        .failure()
        .code(1);
    let err = one_line_error(&assert.get_output().stderr);
    assert!(err.contains("preisach.mu[1][0]"), "{err}");
    assert!(err.contains("must be ≥ 0"), "{err}");
    assert!(!tmp.path().join("out.csv").exists());
}
