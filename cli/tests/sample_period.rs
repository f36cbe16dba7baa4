//! The sample period is never silent: a spec's `dt` that disagrees with
//! the data's time column is refused, `--time-column` and `--dt` choose,
//! a spec may leave `dt` to the data, and every report of a rate-dependent
//! model states the period it ran at.

use hysteron::models::Spec;
use hysteron::Operator;
use std::f64::consts::TAU;
use std::fs;
use std::path::Path;
use tempfile::TempDir;

mod common;
use common::*;

/// LuGre friction (the example's values) with `f_c` and `dt` as given;
/// `dt: None` leaves the period out.
fn lugre(f_c: f64, dt: Option<f64>) -> String {
    let dt = dt.map_or(String::new(), |dt| format!(r#", "dt": {dt}"#));
    format!(
        r#"{{"type": "lugre", "sigma0": 1000, "sigma1": 5, "sigma2": 0.2, "f_c": {f_c},
            "f_s": 1.5, "v_s": 0.5, "delta": 2, "z0": 0{dt}}}"#
    )
}

/// `lu.csv`: columns `t, x, y`, 4000 samples at 1 ms of the true model
/// (`f_c = 1`, `dt = 1e-3`).
fn data(dir: &Path) {
    let n = 4000;
    let t: Vec<f64> = (0..n).map(|i| i as f64 * 1e-3).collect();
    let x: Vec<f64> = t
        .iter()
        .map(|t| 0.05 * (TAU * t).sin() + 0.02 * (3.3 * TAU * t).sin())
        .collect();
    let y = Spec::from_json(&lugre(1.0, Some(1e-3)))
        .unwrap()
        .build()
        .unwrap()
        .run(&x)
        .unwrap();
    let mut text = String::from("t,x,y\n");
    for i in 0..n {
        text.push_str(&format!("{},{},{}\n", t[i], x[i], y[i]));
    }
    fs::write(dir.join("lu.csv"), text).unwrap();
}

fn fitted_f_c(path: &Path) -> f64 {
    let spec = Spec::from_json_file(path).unwrap();
    spec.to_value()["f_c"].as_f64().unwrap()
}

/// Runs `hysteron` with the words of `line` in `dir`, which must succeed;
/// its stdout.
fn ok(dir: &Path, line: &str) -> String {
    let out = hysteron(dir)
        .args(line.split_whitespace())
        .assert()
        .success();
    stdout_of(&out)
}

fn fit(dir: &Path, model: &str, extra: &[&str]) -> assert_cmd::Command {
    let mut cmd = hysteron(dir);
    cmd.args([
        "fit",
        "--model",
        model,
        "--data",
        "lu.csv",
        "--free",
        "f_c",
        "--output",
        "fitted.json",
        "--no-progress",
    ])
    .args(extra);
    cmd
}

/// The case a new user met: a start spec saying 0.5 s, data at 1 ms with
/// a `t` column. It used to fit at 0.5 s without a word (f_c = 10.57);
/// now it is refused, naming both periods and both ways to choose.
#[test]
fn a_fit_whose_spec_period_disagrees_with_the_data_is_refused() {
    let tmp = TempDir::new().unwrap();
    data(tmp.path());
    fs::write(tmp.path().join("start.json"), lugre(2.0, Some(0.5))).unwrap();
    let stderr = fails_leaving_dir_unchanged(
        tmp.path(),
        &mut fit(tmp.path(), "start.json", &[]),
        &[
            "data `lu.csv`: its time column `t` steps 0.001 s",
            "the model's spec gives the sample period 0.5 s",
            "--time-column t",
            "--dt SECONDS",
        ],
    );
    assert!(stderr.starts_with("error: "), "{stderr}");

    // --time-column t chooses the data's period: the truth, to 1e-6
    succeeds_saying(
        &mut fit(tmp.path(), "start.json", &["--time-column", "t"]),
        &["sample period: 0.001 s (--time-column t)"],
    );
    let f_c = fitted_f_c(&tmp.path().join("fitted.json"));
    assert!((f_c - 1.0).abs() < 1e-6, "f_c = {f_c}");
    // so does --dt
    succeeds_saying(
        &mut fit(tmp.path(), "start.json", &["--dt", "0.001"]),
        &["sample period: 0.001 s (--dt)"],
    );
    assert!((fitted_f_c(&tmp.path().join("fitted.json")) - 1.0).abs() < 1e-6);
}

/// A spec without `dt` takes the period of the data's time column, in
/// every command, and says so; the fitted spec carries the period.
#[test]
fn a_spec_without_dt_takes_the_data_period() {
    let tmp = TempDir::new().unwrap();
    data(tmp.path());
    fs::write(tmp.path().join("start.json"), lugre(2.0, None)).unwrap();
    succeeds_saying(
        &mut fit(tmp.path(), "start.json", &[]),
        &["sample period: 0.001 s (the data's time column `t`)"],
    );
    let fitted = tmp.path().join("fitted.json");
    assert!((fitted_f_c(&fitted) - 1.0).abs() < 1e-6);
    assert_eq!(
        Spec::from_json_file(&fitted).unwrap().stated_periods(),
        [1e-3]
    );

    // simulate and sensitivity, the same
    let said = "at a sample period of 0.001 s (the data's time column `t`)";
    let run = "--model start.json --input lu.csv --column x --output-column model";
    assert!(ok(tmp.path(), &format!("simulate {run} --output sim.csv")).contains(said));
    let line = format!("sensitivity {run} --params f_c --output dydp.csv");
    assert!(ok(tmp.path(), &line).contains(said));

    // validate: the fitted spec's own dt, which the column agrees with
    let report = ok(
        tmp.path(),
        "validate --model fitted.json --data lu.csv --input-column x --output-column y",
    );
    assert!(
        report
            .contains("sample period: 0.001 s (the spec's dt; the data's time column `t` agrees)"),
        "{report}"
    );

    // without any period at all: the build says which node lacks it
    let text = fs::read_to_string(tmp.path().join("lu.csv")).unwrap();
    fs::write(
        tmp.path().join("no-t.csv"),
        text.replacen("t,x,y", "s,x,y", 1),
    )
    .unwrap();
    fails_leaving_dir_unchanged(
        tmp.path(),
        hysteron(tmp.path()).args([
            "simulate",
            "--model",
            "start.json",
            "--input",
            "no-t.csv",
            "--column",
            "x",
            "--output-column",
            "model",
            "--output",
            "none.csv",
        ]),
        &[
            "model `start.json`: lugre.dt: the sample period is not given",
            "--time-column",
        ],
    );
}

/// A rate-independent model ignores the period: no time column is read
/// and no report speaks of one.
#[test]
fn a_rate_independent_model_says_nothing_of_the_period() {
    let tmp = TempDir::new().unwrap();
    data(tmp.path());
    fs::write(
        tmp.path().join("gain.json"),
        r#"{"type": "gain", "k": 0.5}"#,
    )
    .unwrap();
    let simulated = ok(
        tmp.path(),
        "simulate --model gain.json --input lu.csv --column x --output-column model --output sim.csv",
    );
    assert!(!simulated.contains("period"), "{simulated}");
    let fitted = ok(
        tmp.path(),
        "fit --model gain.json --data lu.csv --free k --output g.json --no-progress --dt 0.5",
    );
    assert!(!fitted.contains("sample period"), "{fitted}");
}

/// `--dt`'s help lists exactly the registry's rate-dependent operators.
#[test]
fn dt_help_lists_the_rate_dependent_kinds() {
    let kinds: Vec<&str> = hysteron::models::spec::registry::LEAVES
        .iter()
        .filter(|l| l.is_rate_dependent())
        .map(|l| l.kind())
        .collect();
    assert!(
        kinds.contains(&"lugre") && kinds.contains(&"gms"),
        "{kinds:?}"
    );
    for command in ["simulate", "fit", "validate", "sensitivity", "analyze"] {
        let help = ok(Path::new("."), &format!("{command} --help"));
        assert!(
            help.contains(&format!("({};", kinds.join(", "))),
            "{command}: {help}"
        );
    }
}
