//! End-to-end tests of `hysteron fit` on several records: one parameter
//! set fitted to all, per-record initial states (`--own`), a warm-up
//! (`--skip`), gzip-compressed records, the hard budget
//! (`--max-evaluations`, `--max-seconds`), and the bad-input cases (one
//! line on stderr starting with `error:`, exit code 1, nothing written).

use hysteron::models::Spec;
use hysteron::operators::{ElastoPlastic, ElastoPlasticParams};
use hysteron::Operator;
use std::fs;
use std::io::Write;
use std::path::Path;
use tempfile::TempDir;

mod common;
use common::*;

const DT: f64 = 0.01;

/// `n` samples of `c + a sin(2π f t)` at 100 Hz, and their times.
fn sweep(n: usize, a: f64, f: f64, c: f64) -> (Vec<f64>, Vec<f64>) {
    let t: Vec<f64> = (0..n).map(|i| i as f64 * DT).collect();
    let x = t
        .iter()
        .map(|t| c + a * (2.0 * std::f64::consts::PI * f * t).sin())
        .collect();
    (t, x)
}

/// The true element (k = 4, F_b = 1.5) preloaded with `f0`, over `x`.
fn truth(x: &[f64], f0: f64) -> Vec<f64> {
    let p = ElastoPlasticParams {
        k: 4.0,
        f_b: 1.5,
        f0,
    };
    ElastoPlastic::from_params(p).unwrap().run(x).unwrap()
}

fn csv(t: &[f64], x: &[f64], f: &[f64]) -> String {
    let mut s = "t,x,F\n".to_string();
    for ((t, x), f) in t.iter().zip(x).zip(f) {
        s.push_str(&format!("{t},{x},{f}\n"));
    }
    s
}

/// A directory with the starting spec and three records of the true
/// element, each preloaded differently; the second gzip-compressed.
fn setup() -> TempDir {
    let dir = tempfile::tempdir().unwrap();
    let start = r#"{"type": "elastoplastic", "k": 2.0, "f_b": 0.8}"#;
    fs::write(dir.path().join("start.json"), start).unwrap();
    let records = [
        ("a.csv", sweep(300, 1.0, 0.7, 0.1), 0.3),
        ("b.csv.gz", sweep(200, 0.4, 1.5, -0.2), -0.4),
        ("c.csv", sweep(250, 2.0, 0.4, 0.0), 0.0),
    ];
    for (name, (t, x), f0) in records {
        let text = csv(&t, &x, &truth(&x, f0));
        let path = dir.path().join(name);
        if name.ends_with(".gz") {
            let file = fs::File::create(path).unwrap();
            let mut gz = flate2::write::GzEncoder::new(file, flate2::Compression::best());
            gz.write_all(text.as_bytes()).unwrap();
            gz.finish().unwrap();
        } else {
            fs::write(path, text).unwrap();
        }
    }
    dir
}

const RECORDS: [&str; 6] = ["--data", "a.csv", "--data", "b.csv.gz", "--data", "c.csv"];

fn fit(dir: &Path, args: &[&str]) -> assert_cmd::Command {
    let mut cmd = hysteron(dir);
    cmd.args(["fit", "--model", "start.json", "--output-column", "F"])
        .args(args)
        .arg("--no-progress");
    cmd
}

/// The value column of a report line `name ...  start  value ...`.
fn value(stdout: &str, label: &str) -> f64 {
    let line = stdout
        .lines()
        .find(|l| l.starts_with(label))
        .unwrap_or_else(|| panic!("no line {label:?} in {stdout}"));
    let rest = line[label.len()..].split_whitespace().collect::<Vec<_>>();
    rest[1].parse().unwrap()
}

#[test]
fn one_parameter_set_to_three_records_with_their_own_preloads() {
    let dir = setup();
    let (stdout, _) = exits_with(
        fit(dir.path(), &RECORDS).args([
            "--free",
            "k,f_b",
            "--own",
            "f0",
            "--output",
            "fitted.json",
        ]),
        0,
    );
    assert!(
        stdout.contains("to 3 records: 750 samples, x -> F"),
        "{stdout}"
    );
    assert!(
        stdout.contains("record 1: `b.csv.gz` (200 samples)"),
        "{stdout}"
    );
    let close = |label: &str, want: f64| {
        let got = value(&stdout, label);
        assert!(
            (got - want).abs() < 1e-6,
            "{label}: {got} vs {want}\n{stdout}"
        );
    };
    close("k ", 4.0);
    close("f_b ", 1.5);
    close("f0[record 0]", 0.3);
    close("f0[record 1]", -0.4);
    close("f0[record 2]", 0.0);
    // a per-record table follows
    assert!(stdout.contains("record  samples  RMS"), "{stdout}");
    // the fitted spec holds the shared values and the starting f0
    let spec = Spec::from_json_file(dir.path().join("fitted.json")).unwrap();
    let p = spec.build().unwrap().params();
    assert!(
        (p[0] - 4.0).abs() < 1e-6 && (p[1] - 1.5).abs() < 1e-6,
        "{p:?}"
    );
    assert_eq!(p[2], 0.0);
}

#[test]
fn skip_leaves_a_warm_up_out_and_needs_the_period() {
    let dir = setup();
    // a record whose first half second disagrees with the model
    let (t, x) = sweep(300, 1.0, 0.7, 0.0);
    let mut f = truth(&x, 0.0);
    for v in &mut f[..50] {
        *v += 0.5;
    }
    fs::write(dir.path().join("warm.csv"), csv(&t, &x, &f)).unwrap();
    let args = [
        "--data", "warm.csv", "--free", "k,f_b", "--output", "w.json",
    ];
    for period in [["--time-column", "t"], ["--dt", "0.01"]] {
        let (stdout, _) = exits_with(
            fit(dir.path(), &args).args(["--skip", "0.5"]).args(period),
            0,
        );
        assert!(
            (value(&stdout, "k ") - 4.0).abs() < 1e-6,
            "{period:?}: {stdout}"
        );
    }
    let before = snapshot(dir.path());
    for (extra, want) in [
        (vec!["--skip", "0.5"], "--skip needs the sample period"),
        (vec!["--skip", "-1", "--dt", "0.01"], "--skip must be"),
        (
            vec!["--skip", "3.0", "--dt", "0.01"],
            "data `warm.csv`: --skip 3 s is 300 samples, but the record has only 300",
        ),
    ] {
        let (_, stderr) = exits_with(fit(dir.path(), &args).args(&extra), 1);
        let e = one_line_error(stderr.as_bytes());
        assert!(e.contains(want), "{extra:?}: {e}");
    }
    assert_eq!(snapshot(dir.path()), before);
}

#[test]
fn bad_records_are_one_line_errors_naming_the_file() {
    let dir = setup();
    fs::write(dir.path().join("nof.csv"), "t,x,G\n0,0,0\n0.01,1,1\n").unwrap();
    fs::write(dir.path().join("nan.csv"), "t,x,F\n0,0,0\n0.01,NaN,1\n").unwrap();
    fs::write(
        dir.path().join("slow.csv"),
        "t,x,F\n0,0,0\n0.02,1,1\n0.04,0,0\n",
    )
    .unwrap();
    let before = snapshot(dir.path());
    for (args, want) in [
        (
            vec!["--data", "a.csv", "--data", "nof.csv"],
            vec!["data `nof.csv`", "no column `F`"],
        ),
        (
            vec!["--data", "a.csv", "--data", "nan.csv"],
            vec!["nan.csv", "row 2", "not finite"],
        ),
        (
            vec!["--data", "a.csv", "--data", "./a.csv"],
            vec!["--data `./a.csv` is given twice"],
        ),
        (
            vec![
                "--data",
                "a.csv",
                "--data",
                "slow.csv",
                "--time-column",
                "t",
            ],
            vec![
                "data `slow.csv`: its time column steps 0.02 s",
                "`a.csv` steps 0.01 s",
            ],
        ),
        (
            vec!["--data", "a.csv", "--own", "f0,f0"],
            vec!["named twice"],
        ),
        (
            vec!["--data", "a.csv", "--own", "nope"],
            vec!["--own: model `start.json`: unknown parameter `nope`"],
        ),
    ] {
        let mut a = args.clone();
        if !a.contains(&"--own") {
            a.extend(["--free", "k"]);
        }
        a.extend(["--output", "fitted.json"]);
        let (_, stderr) = exits_with(&mut fit(dir.path(), &a), 1);
        let e = one_line_error(stderr.as_bytes());
        for w in want {
            assert!(e.contains(w), "{args:?}: {e}");
        }
    }
    assert_eq!(snapshot(dir.path()), before);
}

/// `--max-evaluations` and `--max-seconds` really bound the work: the fit
/// ends not converged (exit 3) within the bound plus the final report's
/// 2·free + 1 runs, and says why.
#[test]
fn the_budget_options_bound_the_work() {
    let dir = setup();
    let evaluations = |stdout: &str| -> usize {
        let line = stdout
            .lines()
            .find(|l| l.starts_with("evaluations"))
            .unwrap();
        line.split_whitespace().nth(1).unwrap().parse().unwrap()
    };
    let base = ["--free", "k,f_b", "--own", "f0", "--output", "fitted.json"];
    let run =
        |extra: &[&str], code| exits_with(fit(dir.path(), &RECORDS).args(base).args(extra), code);
    let (stdout, _) = run(&[], 0);
    let unbounded = evaluations(&stdout);
    assert!(unbounded > 12, "{unbounded}");
    let k = 2 + 3;
    // the budget, what the report says, and the evaluations it allows
    for (budget, says, most) in [
        (
            ["--max-evaluations", "12"],
            "NOT CONVERGED: evaluation budget of 12",
            12,
        ),
        (["--max-seconds", "1e-6"], "NOT CONVERGED: time limit of", 1),
    ] {
        let (stdout, _) = run(&budget, 3);
        assert!(stdout.contains(says), "{budget:?}: {stdout}");
        assert!(
            evaluations(&stdout) <= most + 2 * k + 1,
            "{budget:?}: {stdout}"
        );
    }
    for bad in [["--max-evaluations", "0"], ["--max-seconds", "-2"]] {
        // clap's usage error: its first line names the option
        let (_, e) = run(&bad, 1);
        assert!(
            e.starts_with(&format!(
                "error: invalid value '{}' for '{}",
                bad[1], bad[0]
            )),
            "{e}"
        );
        assert!(!e.contains("panicked"), "{e}");
    }
}
