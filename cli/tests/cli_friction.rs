//! End-to-end tests of `hysteron simulate --model SPEC` with the friction
//! models (`maxwell_slip`, `dahl`, `lugre`, `gms`): the CSV holds bit for bit what
//! the library computes, a bad parameter is a one-line error naming the
//! field, and the rate-dependent `lugre` and `gms` take their sample period from
//! `--dt` or `--time-column`.

use hysteron::models::Spec;
use hysteron::Operator;
use std::fs;
use std::path::{Path, PathBuf};
use tempfile::TempDir;

mod common;
use common::*;

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples/specs")
        .join(name)
}

/// A displacement record sampled every 1/256 s (exact in binary and in the
/// CSV) with a time column `t`: two cycles of a 1 Hz sine of amplitude 1.2
/// with a slower ripple (so there are minor loops).
fn record(dir: &Path) -> Vec<f64> {
    let dt = 1.0 / 256.0;
    let x: Vec<f64> = (0..512)
        .map(|i| {
            let t = i as f64 * dt;
            1.2 * (std::f64::consts::TAU * t).sin() + 0.1 * (std::f64::consts::TAU * 7.0 * t).sin()
        })
        .collect();
    let mut text = String::from("t,x\n");
    for (i, v) in x.iter().enumerate() {
        text.push_str(&format!("{},{v}\n", i as f64 * dt));
    }
    fs::write(dir.join("x.csv"), text).unwrap();
    x
}

/// Runs `simulate` on `x.csv` with `args` added and returns the `y` column
/// (checking the input columns were kept and a plot was written).
fn simulate(dir: &Path, model: &Path, args: &[&str], x: &[f64]) -> Vec<f64> {
    let (x_written, y) = succeeds_writing_txy(
        hysteron(dir)
            .arg("simulate")
            .arg("--model")
            .arg(model)
            .args([
                "--input", "x.csv", "--output", "y.csv", "--plot", "loop.svg",
            ])
            .args(args),
        &dir.join("y.csv"),
    );
    assert_eq!(x_written, x);
    assert_svg(&dir.join("loop.svg"));
    assert_no_temp_files(dir);
    y
}

/// Runs `simulate` expecting a one-line error holding every `expect`ed
/// fragment and no output file (see [`fails_leaving_dir_unchanged`]).
fn fails(dir: &Path, model: &str, args: &[&str], expect: &[&str]) {
    let mut cmd = hysteron(dir);
    cmd.args([
        "simulate", "--model", model, "--input", "x.csv", "--output", "bad.csv",
    ])
    .args(args);
    fails_leaving_dir_unchanged(dir, &mut cmd, expect);
}

#[test]
fn simulate_maxwell_slip_example() {
    let tmp = TempDir::new().unwrap();
    let x = record(tmp.path());
    let spec_path = example("maxwell-slip.json");
    let y = simulate(tmp.path(), &spec_path, &[], &x);
    let spec = Spec::from_json_file(&spec_path).unwrap();
    assert_eq!(y, spec.build().unwrap().run(&x).unwrap());
    // saturated at the peaks: |F| reaches Σ F_i (= 2.73) and never exceeds it
    let Some(p) = spec.leaf_params::<hysteron::operators::MaxwellSlip<f64>>() else {
        panic!("{spec:?}")
    };
    let total: f64 = p.f_b.iter().sum();
    let peak = y.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    assert!(peak <= total && peak > 0.99 * total, "{peak} vs {total}");
    // a bad element names its index
    fs::write(
        tmp.path().join("bad.json"),
        r#"{"type": "maxwell_slip", "k": [10, 5], "f_b": [1, 0]}"#,
    )
    .unwrap();
    fails(
        tmp.path(),
        "bad.json",
        &[],
        &[
            "model `bad.json`",
            "maxwell_slip.f_b[1]: must be > 0 (got 0)",
        ],
    );
}

#[test]
fn simulate_dahl_hand_written_spec() {
    let tmp = TempDir::new().unwrap();
    let x = record(tmp.path());
    let text = r#"{"type": "dahl", "sigma": 20, "f_c": 1, "alpha": 2, "f0": 0.5}"#;
    fs::write(tmp.path().join("dahl.json"), text).unwrap();
    let y = simulate(tmp.path(), &tmp.path().join("dahl.json"), &[], &x);
    let spec = Spec::from_json(text).unwrap();
    assert_eq!(y, spec.build().unwrap().run(&x).unwrap());
    assert!(y.iter().all(|v| v.abs() <= 1.0));
    // rate-independent: --dt is accepted and changes nothing
    assert!(!spec.is_rate_dependent());
    assert_eq!(
        simulate(
            tmp.path(),
            &tmp.path().join("dahl.json"),
            &["--dt", "0.5"],
            &x
        ),
        y
    );
    fs::write(
        tmp.path().join("bad.json"),
        r#"{"type": "dahl", "sigma": 20, "f_c": 1, "alpha": -1}"#,
    )
    .unwrap();
    fails(
        tmp.path(),
        "bad.json",
        &[],
        &["model `bad.json`", "dahl.alpha: must be ≥ 0 (got -1)"],
    );
}

/// The rate-dependent examples (LuGre, GMS) take their sample period from
/// `--time-column` or `--dt` (the same output). Without either, the spec's
/// own `dt` (0.01 s) disagrees with the data's time column `t` (1/256 s):
/// refused; a spec without `dt` takes the column's period; and with no
/// column named as time, the spec's own `dt` is used (another output).
#[test]
fn simulate_rate_dependent_examples_take_dt_from_the_data() {
    let tmp = TempDir::new().unwrap();
    let x = record(tmp.path());
    let text = fs::read_to_string(tmp.path().join("x.csv")).unwrap();
    fs::write(tmp.path().join("no-t.csv"), text.replacen("t,x", "s,x", 1)).unwrap();
    for name in ["lugre.json", "gms.json"] {
        let spec_path = example(name);
        let spec = Spec::from_json_file(&spec_path).unwrap();
        assert!(spec.is_rate_dependent(), "{name}");
        let expected = spec.with_dt(1.0 / 256.0).build().unwrap().run(&x).unwrap();
        for dt_args in [&["--time-column", "t"][..], &["--dt", "0.00390625"][..]] {
            let y = simulate(tmp.path(), &spec_path, dt_args, &x);
            assert_eq!(y, expected, "{name} {dt_args:?}");
        }
        fails(
            tmp.path(),
            spec_path.to_str().unwrap(),
            &[],
            &[
                "its time column `t` steps 0.00390625 s",
                "gives the sample period 0.01 s",
            ],
        );
        let mut without = spec.to_value();
        without.as_object_mut().unwrap().remove("dt");
        fs::write(tmp.path().join("no-dt.json"), without.to_string()).unwrap();
        let y = simulate(tmp.path(), &tmp.path().join("no-dt.json"), &[], &x);
        assert_eq!(y, expected, "{name} without dt");
        hysteron(tmp.path())
            .arg("simulate")
            .arg("--model")
            .arg(&spec_path)
            .args(["--input", "no-t.csv", "--output", "own.csv"])
            .assert()
            .success();
        let (headers, rows) = read_csv(&tmp.path().join("own.csv"));
        let own = column(&headers, &rows, "y");
        assert_eq!(own, spec.build().unwrap().run(&x).unwrap(), "{name}");
        assert_ne!(own, expected, "{name}");
    }
}

/// A spec's own `dt` and its other parameters are checked when it is built.
#[test]
fn simulate_refuses_bad_rate_dependent_specs() {
    let tmp = TempDir::new().unwrap();
    record(tmp.path());
    let lugre = fs::read_to_string(example("lugre.json")).unwrap();
    assert!(lugre.contains(r#""dt": 0.01"#), "{lugre}");
    let gms = r#"{"type": "gms", "k": [20], "alpha": [1], "c": 0, "f_c": 1, "f_s": 1.5, "v_s": 0.5, "dt": 0.01}"#;
    for (text, expected) in [
        (
            lugre.replace(r#""dt": 0.01"#, r#""dt": 0"#),
            "lugre.dt: must be > 0 (got 0)",
        ),
        (gms.to_string(), "gms.c: must be > 0 (got 0)"),
    ] {
        fs::write(tmp.path().join("bad.json"), text).unwrap();
        fails(tmp.path(), "bad.json", &[], &["model `bad.json`", expected]);
    }
}
