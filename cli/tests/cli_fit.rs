//! End-to-end tests of `hysteron fit` and `hysteron identify-paper`: known
//! parameters recovered from noise-free synthetic records made in the
//! test, the written spec simulating back to the record, the report, the
//! exit code of a fit that did not converge, and every bad-input case (one
//! line on stderr starting with `error:`, exit code 1, nothing on stdout,
//! no file changed or created).

use assert_cmd::Command;
use hysteron::models::experiments::{chirp, sine, DRIVE};
use hysteron::models::{Spec, TransmissionParams};
use hysteron::Operator;
use std::fs;
use std::path::Path;
use tempfile::TempDir;

mod common;
use common::*;

fn read_csv_column(path: &Path, name: &str) -> Vec<f64> {
    let mut r = csv::Reader::from_path(path).expect("readable CSV");
    let i = r
        .headers()
        .unwrap()
        .iter()
        .position(|h| h == name)
        .expect("column");
    r.records()
        .map(|rec| rec.unwrap()[i].parse().unwrap())
        .collect()
}

fn csv_text(header: &str, columns: &[&[f64]]) -> String {
    let mut s = format!("{header}\n");
    for i in 0..columns[0].len() {
        let row: Vec<String> = columns.iter().map(|c| format!("{}", c[i])).collect();
        s.push_str(&row.join(","));
        s.push('\n');
    }
    s
}

// ------------------------------------------------------------------ fit

/// The true model: the paper's model as a generic spec.
fn truth() -> Spec {
    Spec::from(&TransmissionParams::default())
}

/// Parameters freed in the happy path (suffixes and a full name) and the
/// full names they resolve to.
const FREE: &str = "f_c,left.mms.k,w,beta,gamma";
const FREE_FULL: [&str; 5] = [
    "left.mms.f_c",
    "left.mms.k",
    "right.bouc_wen.w",
    "right.bouc_wen.beta",
    "right.bouc_wen.gamma",
];

/// Two thousand samples of a decaying 5-cycle sine, 1.4 deg.
fn input() -> Vec<f64> {
    (0..2000)
        .map(|i| {
            let t = i as f64 / 2000.0;
            1.4 * (-1.5 * t).exp() * (std::f64::consts::TAU * 5.0 * t).sin()
        })
        .collect()
}

struct Setup {
    tmp: TempDir,
    x: Vec<f64>,
    y: Vec<f64>,
}

in_temp_dir!(Setup);

impl Setup {
    /// `data.csv` (t,x,y: the true model's noise-free response), `in.csv`
    /// (t,x), `truth.json` and `start.json` (the free parameters off by
    /// ±20 %).
    fn new() -> Self {
        let tmp = TempDir::new().unwrap();
        let x = input();
        let spec = truth();
        let y = spec.build().unwrap().run(&x).unwrap();
        let t: Vec<f64> = (0..x.len()).map(|i| i as f64 * 1e-3).collect();
        fs::write(
            tmp.path().join("data.csv"),
            csv_text("t,x,y", &[&t, &x, &y]),
        )
        .unwrap();
        fs::write(tmp.path().join("in.csv"), csv_text("t,x", &[&t, &x])).unwrap();
        fs::write(
            tmp.path().join("truth.json"),
            spec.to_json_pretty().unwrap(),
        )
        .unwrap();
        let model = spec.build().unwrap();
        let names = model.param_names();
        let mut p = model.params();
        for (j, name) in FREE_FULL.iter().enumerate() {
            let i = names.iter().position(|n| n == name).unwrap();
            p[i] *= if j % 2 == 0 { 1.2 } else { 0.8 };
        }
        let start = spec.with_params(&p).unwrap();
        fs::write(
            tmp.path().join("start.json"),
            start.to_json_pretty().unwrap(),
        )
        .unwrap();
        Setup { tmp, x, y }
    }

    fn fit(&self, args: &[&str]) -> Command {
        let mut cmd = hysteron(self.dir());
        cmd.arg("fit").args(args);
        cmd
    }

    /// Runs `hysteron <args>` expecting failure: exit code 1, one line on
    /// stderr containing every `expect`ed fragment, nothing on stdout, no
    /// file changed or created.
    fn fails_cmd(&self, args: &[&str], expect: &[&str]) -> String {
        fails_leaving_dir_unchanged(self.dir(), hysteron(self.dir()).args(args), expect)
    }

    /// `fit` with the standard arguments, `overrides` replacing or adding
    /// options.
    fn fit_with(&self, overrides: &[(&str, &str)]) -> Command {
        let args = fit_args(overrides);
        let mut cmd = hysteron(self.dir());
        cmd.args(&args);
        cmd
    }

    /// Runs [`fit_with`](Self::fit_with) expecting the exit code `code`
    /// and nothing on stderr; returns the standard output.
    fn fits_quietly(&self, overrides: &[(&str, &str)], code: i32) -> String {
        let (stdout, stderr) = exits_with(&mut self.fit_with(overrides), code);
        assert!(stderr.is_empty(), "stderr: {stderr:?}");
        stdout
    }

    /// Runs `simulate` of `model` on `in.csv` into `sim.csv`, expecting
    /// success.
    fn simulates(&self, model: &str) {
        hysteron(self.dir())
            .args(["simulate", "--model", model])
            .args(["--input", "in.csv", "--output", "sim.csv"])
            .assert()
            .success();
    }

    /// [`fit_with`](Self::fit_with) expected to fail as
    /// [`fails_cmd`](Self::fails_cmd).
    fn fails(&self, overrides: &[(&str, &str)], expect: &[&str]) -> String {
        let args = fit_args(overrides);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        self.fails_cmd(&args, expect)
    }
}

/// `fit` with the standard options (`start.json` fitted to `data.csv`,
/// [`FREE`] free, into `fitted.json`), `overrides` replacing or adding
/// options.
fn fit_args(overrides: &[(&str, &str)]) -> Vec<String> {
    let mut opts: Vec<(String, String)> = [
        ("--model", "start.json"),
        ("--data", "data.csv"),
        ("--free", FREE),
        ("--output", "fitted.json"),
    ]
    .iter()
    .map(|(a, b)| (a.to_string(), b.to_string()))
    .collect();
    for (k, v) in overrides {
        match opts.iter_mut().find(|(a, _)| a == k) {
            Some(o) => o.1 = v.to_string(),
            None => opts.push((k.to_string(), v.to_string())),
        }
    }
    let mut args = vec!["fit".to_string()];
    for (k, v) in opts {
        args.push(k);
        args.push(v);
    }
    args
}

#[test]
fn fit_recovers_known_parameters_and_the_spec_simulates_back() {
    let s = Setup::new();
    // Not a terminal: no progress display, nothing on stderr at all.
    let stdout = s.fits_quietly(&[("--plot", "fit.svg")], 0);
    println!("{stdout}");
    for want in [
        "fit of `start.json` (series, 24 parameters, 5 free) to `data.csv`: 2000 samples, x -> y",
        "parameter",
        "start",
        "std error",
        "95% CI",
        "cost ",
        "RMS ",
        "NRMSE ",
        "cond(JᵀJ) ",
        "iterations ",
        "evaluations ",
        "jacobian     exact (forward-mode derivatives)",
        "wall time ",
        "status       converged",
        "wrote fitted.json, fit.svg",
    ] {
        assert!(stdout.contains(want), "`{want}` not in:\n{stdout}");
    }
    for name in FREE_FULL {
        assert!(
            stdout.lines().any(|l| l.starts_with(name)),
            "{name}:\n{stdout}"
        );
    }
    assert!(!stdout.contains("NOT CONVERGED"));

    // The parameters: free ones recovered, the others untouched (bit for
    // bit).
    let want_model = truth().build().unwrap();
    let want = want_model.params();
    let names = want_model.param_names();
    let start = Spec::from_json_file(s.path("start.json"))
        .unwrap()
        .build()
        .unwrap()
        .params();
    let fitted_spec = Spec::from_json_file(s.path("fitted.json")).unwrap();
    assert_eq!(fitted_spec.kind(), "series");
    let got = fitted_spec.build().unwrap().params();
    for (i, name) in names.iter().enumerate() {
        if FREE_FULL.contains(&name.as_str()) {
            let rel = (got[i] - want[i]).abs() / want[i].abs();
            assert!(rel < 1e-6, "{name}: {} vs {} ({rel:e})", got[i], want[i]);
        } else {
            assert_eq!(got[i].to_bits(), start[i].to_bits(), "{name}");
        }
    }

    // `simulate` accepts the written spec and reproduces the record.
    s.simulates("fitted.json");
    let sim = read_csv_column(&s.path("sim.csv"), "y");
    assert_eq!(sim.len(), s.y.len());
    let scale = s.y.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    let worst = sim
        .iter()
        .zip(&s.y)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(worst <= 1e-6 * scale, "max |error| {worst:e} of {scale}");
    assert_eq!(read_csv_column(&s.path("sim.csv"), "x"), s.x);

    assert_svg(&s.path("fit.svg"));
    let svg = fs::read_to_string(s.path("fit.svg")).unwrap();
    for label in ["measured", "fitted", "residual"] {
        assert!(svg.contains(label), "{label}");
    }
    assert_no_temp_files(s.dir());
}

/// Two gains in parallel: only their sum is determined, and the report
/// says so, naming both; the fit itself succeeds.
#[test]
fn fit_warns_about_parameters_the_data_do_not_determine() {
    let tmp = TempDir::new().unwrap();
    let x: Vec<f64> = (0..500).map(|i| (0.05 * i as f64).sin()).collect();
    let y: Vec<f64> = x.iter().map(|v| 1.5 * v).collect();
    fs::write(tmp.path().join("data.csv"), csv_text("x,y", &[&x, &y])).unwrap();
    fs::write(
        tmp.path().join("start.json"),
        r#"{"type": "parallel", "left": {"type": "gain", "k": 2}, "right": {"type": "gain", "k": 0.5}}"#,
    )
    .unwrap();
    let args =
        "fit --model start.json --data data.csv --free left.gain.k,right.gain.k --output f.json";
    let out = hysteron(tmp.path())
        .args(args.split(' '))
        .assert()
        .success();
    let stdout = stdout_of(&out);
    // correlated or singular, the warning names both
    let warned = stdout.lines().any(|l| {
        l.starts_with("warning: ") && l.contains("`left.gain.k`") && l.contains("`right.gain.k`")
    });
    assert!(warned, "{stdout}");
}

/// A play's threshold from a start beyond the input's amplitude: one start
/// cannot move (the output never changes there), `--starts 8` finds the
/// truth and says how many starts reached it; a bad `--starts` or
/// `--spread` is an argument error.
#[test]
fn fit_starts_searches_from_a_latin_hypercube() {
    let tmp = TempDir::new().unwrap();
    let x: Vec<f64> = (0..800).map(|i| (0.03 * i as f64).sin()).collect();
    let mut truth = hysteron::operators::Play::new(0.3).unwrap();
    let y = truth.run(&x).unwrap();
    fs::write(tmp.path().join("data.csv"), csv_text("x,y", &[&x, &y])).unwrap();
    fs::write(tmp.path().join("start.json"), r#"{"type": "play", "r": 2}"#).unwrap();
    let fit = |extra: &str| {
        let args =
            format!("fit --model start.json --data data.csv --free r --output f.json {extra}");
        hysteron(tmp.path())
            .args(args.split_whitespace())
            .output()
            .unwrap()
    };
    let one = fit("");
    let text = String::from_utf8(one.stdout).unwrap();
    assert!(!text.contains("starts "), "{text}");
    let fitted = Spec::from_json_file(tmp.path().join("f.json")).unwrap();
    assert_eq!(fitted.build().unwrap().params()[0], 2.0, "{text}");

    let many = fit("--starts 8 --seed 1");
    assert!(many.status.success());
    let text = String::from_utf8(many.stdout).unwrap();
    let line = text
        .lines()
        .find(|l| l.starts_with("starts       8 ("))
        .unwrap_or_else(|| panic!("{text}"));
    assert!(line.contains("reached the best cost within 1 %"), "{line}");
    let fitted = Spec::from_json_file(tmp.path().join("f.json")).unwrap();
    let r = fitted.build().unwrap().params()[0];
    assert!((r - 0.3).abs() < 1e-9, "{r}: {text}");

    for (bad, expected) in [
        ("--starts 0", "'--starts <N>': must be at least 1 (got 0)"),
        ("--spread 0", "'--spread <S>': must be positive and finite"),
    ] {
        let out = fit(bad);
        assert_eq!(out.status.code(), Some(1), "{bad}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(expected), "{bad}: {err}");
    }
}

/// `--jacobian fd` keeps the central differences; both Jacobians reach the
/// same parameters, the exact one in fewer simulations.
#[test]
fn fit_jacobian_exact_and_by_finite_differences_agree() {
    let tmp = TempDir::new().unwrap();
    let x: Vec<f64> = (0..1500)
        .map(|i| 1.2 * (-2.0 * i as f64 / 1500.0).exp() * (0.02 * i as f64).sin())
        .collect();
    let truth = r#"{"type": "bouc_wen", "w": 0.6, "alpha": 1.0, "beta": 2.5, "gamma": 1.5, "n": 1.0,
        "h0": 0.0, "z0": 0.0, "stiffness": {"z": [0.0], "s": [10.0]}}"#;
    let y = Spec::from_json(truth)
        .unwrap()
        .build()
        .unwrap()
        .run(&x)
        .unwrap();
    fs::write(tmp.path().join("data.csv"), csv_text("x,y", &[&x, &y])).unwrap();
    fs::write(
        tmp.path().join("start.json"),
        truth.replace("2.5", "3.0").replace("0.6", "0.5"),
    )
    .unwrap();
    let fit = |jacobian: &str| {
        let args = format!(
            "fit --model start.json --data data.csv --free w,beta --output {jacobian}.json --jacobian {jacobian}"
        );
        let out = hysteron(tmp.path())
            .args(args.split_whitespace())
            .output()
            .unwrap();
        assert!(out.status.success(), "{out:?}");
        let text = String::from_utf8(out.stdout).unwrap();
        let evaluations: usize = text
            .lines()
            .find_map(|l| l.strip_prefix("evaluations "))
            .and_then(|v| v.trim().parse().ok())
            .unwrap_or_else(|| panic!("{text}"));
        let p = Spec::from_json_file(tmp.path().join(format!("{jacobian}.json")))
            .unwrap()
            .build()
            .unwrap()
            .params();
        (text, evaluations, p)
    };
    let (exact_text, exact_runs, exact) = fit("exact");
    let (fd_text, fd_runs, fd) = fit("fd");
    assert!(exact_text.contains("jacobian     exact"), "{exact_text}");
    assert!(
        fd_text.contains("jacobian     central finite differences"),
        "{fd_text}"
    );
    // w and beta at indices 0 and 2; both back at the truth
    for p in [&exact, &fd] {
        assert!(
            (p[0] - 0.6).abs() < 1e-8 && (p[2] - 2.5).abs() < 1e-7,
            "{p:?}"
        );
    }
    assert!(exact_runs < fd_runs, "{exact_runs} vs {fd_runs}");
    usage_error(
        hysteron(tmp.path()).args(
            "fit --model start.json --data data.csv --free w --output b.json --jacobian numeric"
                .split_whitespace(),
        ),
        "invalid value 'numeric' for '--jacobian",
    );
}

#[test]
fn fit_on_other_columns_and_overwrites_its_old_output_atomically() {
    let s = Setup::new();
    // Columns `u` (input) and `F` (output), in another order.
    let t: Vec<f64> = (0..s.x.len()).map(|i| i as f64).collect();
    s.write("other.csv", &csv_text("F,t,u", &[&s.y, &t, &s.x]));
    s.write("fitted.json", "old\n");
    // Only f_c and k off.
    let mut start = TransmissionParams::default();
    start.friction.f_c *= 1.2;
    start.friction.k *= 0.8;
    s.write("start2.json", &Spec::from(&start).to_json_pretty().unwrap());
    succeeds_saying(
        &mut s.fit(&[
            "--model",
            "start2.json",
            "--data",
            "other.csv",
            "--input-column",
            "u",
            "--output-column",
            "F",
            "--free",
            " f_c , k ",
            "--output",
            "fitted.json",
            "--no-progress",
        ]),
        &["2000 samples, u -> F", "2 free"],
    );
    let fitted = Spec::from_json_file(s.path("fitted.json")).unwrap();
    let Spec::Series { left, .. } = fitted else {
        panic!("{fitted:?}")
    };
    let Some(m) = left.leaf_params::<hysteron::operators::Mms<f64>>() else {
        panic!("{left:?}")
    };
    assert!((m.f_c - 1.5).abs() < 1.5e-6, "{m:?}");
    assert!((m.k - 30.0).abs() < 30e-6, "{m:?}");
    assert_no_temp_files(s.dir());
}

#[test]
fn fit_that_runs_out_of_budget_exits_3_and_says_so() {
    let s = Setup::new();
    let stdout = s.fits_quietly(&[("--patience", "1")], 3);
    assert!(stdout.contains("status       NOT CONVERGED"), "{stdout}");
    assert!(stdout.contains("the fit did not converge"), "{stdout}");
    assert!(stdout.contains("exit code 3"), "{stdout}");
    // The last iterate is written and is a valid spec.
    Spec::from_json_file(s.path("fitted.json"))
        .unwrap()
        .build()
        .unwrap();
}

/// A `fit` that must fail: the files written first (name and text), the
/// options replacing or added to the standard ones, and what the error
/// says.
type Refusal<'a> = (
    Vec<(&'a str, &'a str)>,
    Vec<(&'a str, &'a str)>,
    Vec<&'a str>,
);

/// A model that is missing, malformed, invalid or fails at the start, data
/// that are missing, lack a column or hold a cell that is not a number or
/// not finite, an empty file or a ragged row, the same column twice, or
/// `--free` names that are ambiguous, empty or given twice: the one-line
/// error names the file (and the field, row and column, or the names).
#[test]
fn fit_errors_name_the_bad_model_data_or_names() {
    let s = Setup::new();
    let non_finite: Vec<(String, String)> =
        [("NaN", "x"), ("inf", "y"), ("-inf", "x"), ("nan", "y")]
            .iter()
            .map(|(bad, col)| {
                let row = if *col == "x" {
                    format!("1,{bad},0.1")
                } else {
                    format!("1,0.1,{bad}")
                };
                (
                    format!("t,x,y\n0,0,0\n{row}\n2,1,1\n"),
                    format!("column `{col}`"),
                )
            })
            .collect();
    let mut cases: Vec<Refusal> = vec![
        (
            vec![],
            vec![("--model", "nope.json")],
            vec!["model `nope.json`", "No such file"],
        ),
        (
            vec![("bad.json", "{\"type\": \"play\",\n \"r\": }\n")],
            vec![("--model", "bad.json")],
            vec!["model `bad.json`", "line 2"],
        ),
        (
            vec![(
                "bad.json",
                r#"{"type": "scaled", "w": 2, "inner": {"type": "play", "r": -1}}"#,
            )],
            vec![("--model", "bad.json")],
            vec!["model `bad.json`", "scaled.inner.play.r", "-1"],
        ),
        // The inverse of a saturation has no solution beyond its limits.
        (
            vec![
                (
                    "inv.json",
                    r#"{"type": "inverse", "inner": {"type": "saturation", "lo": -1, "hi": 1}}"#,
                ),
                ("d.csv", "t,x,y\n0,0,0\n1,0.5,0.5\n2,1.5,1\n3,0,0\n"),
            ],
            vec![
                ("--model", "inv.json"),
                ("--data", "d.csv"),
                ("--free", "hi"),
            ],
            vec![
                "model `inv.json` fails at the starting parameters",
                "sample 2",
                "data `d.csv`",
                "row 3 (line 4)",
                "column `x`",
                "1.5",
            ],
        ),
        (
            vec![],
            vec![("--data", "nope.csv")],
            vec!["data `nope.csv`", "No such file"],
        ),
        (
            vec![],
            vec![("--input-column", "theta")],
            vec!["data `data.csv`", "no column `theta`", "`t`, `x`, `y`"],
        ),
        (
            vec![],
            vec![("--output-column", "F")],
            vec!["data `data.csv`", "no column `F`", "`t`, `x`, `y`"],
        ),
        (
            vec![],
            vec![("--output-column", "x")],
            vec!["--input-column and --output-column", "`x`"],
        ),
        (
            vec![("d.csv", "t,x,y\n0,0,0\n1,0.5,abc\n")],
            vec![("--data", "d.csv")],
            vec![
                "data `d.csv`",
                "row 2 (line 3)",
                "column `y`",
                "`abc` is not a number",
            ],
        ),
        (
            vec![("d.csv", "t,x,y\n0,,1\n")],
            vec![("--data", "d.csv")],
            vec!["row 1 (line 2)", "column `x`", "not a number"],
        ),
        (
            vec![("hdr.csv", "t,x,y\n")],
            vec![("--data", "hdr.csv")],
            vec!["data `hdr.csv`", "no data rows"],
        ),
        (
            vec![("empty.csv", "")],
            vec![("--data", "empty.csv")],
            vec!["data `empty.csv`", "empty file"],
        ),
        (
            vec![("rag.csv", "t,x,y\n0,0,0\n1,1\n")],
            vec![("--data", "rag.csv")],
            vec!["data `rag.csv`", "row 2 (line 3)", "field"],
        ),
        (
            vec![(
                "two.json",
                r#"{"type": "parallel", "left": {"type": "gain", "k": 1},
            "right": {"type": "mms", "f_c": 1, "k": 5}}"#,
            )],
            vec![("--model", "two.json"), ("--free", "k")],
            vec!["--free", "`k` is ambiguous", "left.gain.k", "right.mms.k"],
        ),
        (
            vec![],
            vec![("--free", "")],
            vec!["--free names no parameter", "the model has: limits.b"],
        ),
        (
            vec![],
            vec![("--free", " , ")],
            vec!["--free names no parameter"],
        ),
        (
            vec![],
            vec![("--free", "f_c,left.mms.f_c")],
            vec!["parameter `left.mms.f_c`", "named twice"],
        ),
    ];
    for (text, column) in &non_finite {
        cases.push((
            vec![("d.csv", text.as_str())],
            vec![("--data", "d.csv")],
            vec!["data `d.csv`", "row 2 (line 3)", column, "not finite"],
        ));
    }
    for (writes, overrides, expect) in cases {
        for (name, text) in writes {
            s.write(name, text);
        }
        s.fails(&overrides, &expect);
    }
}

#[test]
fn fit_error_unknown_free_name_lists_the_parameters() {
    let s = Setup::new();
    let e = s.fails(
        &[("--free", "f_c,mu")],
        &[
            "--free",
            "model `start.json`",
            "unknown parameter `mu`",
            "the model has: limits.b, limits.r0, left.mms.f_c, left.mms.k",
            "right.bouc_wen.stiffness.s[5]",
        ],
    );
    assert!(!e.contains("`f_c`"), "{e}");
}

#[test]
fn fit_error_tied_parameter_of_a_transmission_spec() {
    let s = Setup::new();
    s.write(
        "tr.json",
        &Spec::Transmission(TransmissionParams::default())
            .to_json_pretty()
            .unwrap(),
    );
    // a generic series with a gap ties its spring the same way
    s.write(
        "series.json",
        &Spec::from(&TransmissionParams::default())
            .to_json_pretty()
            .unwrap(),
    );
    for (model, name) in [
        ("tr.json", "r0"),
        ("tr.json", "right.bouc_wen.z0"),
        ("series.json", "r0"),
        ("series.json", "z0"),
    ] {
        s.fails(
            &[("--model", model), ("--free", name)],
            &[
                "--free",
                &format!("model `{model}`"),
                "cannot be fitted on its own",
                "z0 is -r0 of the gap",
                "-slider0 in a `transmission` spec",
            ],
        );
    }
    // The rest of a transmission spec fits as usual.
    s.fit_with(&[("--model", "tr.json"), ("--free", "f_c")])
        .assert()
        .success();
    assert_eq!(
        Spec::from_json_file(s.path("fitted.json")).unwrap().kind(),
        "transmission"
    );
}

#[test]
fn fit_refuses_to_overwrite_its_inputs() {
    let s = Setup::new();
    for out in spellings_of(s.dir(), "data.csv") {
        s.fails(
            &[("--output", &out)],
            &["output", "same file as the data", "refusing"],
        );
    }
    let abs = s.path("start.json");
    s.fails(
        &[("--output", abs.to_str().unwrap())],
        &["same file as the model"],
    );
    s.fails(
        &[("--output", "o.json"), ("--plot", "sub/../o.json")],
        &["plot", "same file as the output"],
    );
    s.fails(
        &[("--plot", "data.csv")],
        &["plot", "same file as the data"],
    );
}

#[test]
fn fit_error_output_directory_missing_and_keeps_old_output() {
    let s = Setup::new();
    s.fails(
        &[("--output", "nodir/fitted.json")],
        &["output `nodir/fitted.json`", "does not exist"],
    );
    s.write("fitted.json", "previous\n");
    s.write("d.csv", "t,x,y\n0,0,0\n1,NaN,0\n");
    s.fails(&[("--data", "d.csv")], &["not finite"]);
    assert_eq!(
        fs::read_to_string(s.path("fitted.json")).unwrap(),
        "previous\n"
    );
}

#[test]
fn fit_usage_errors_are_clap_errors() {
    let s = Setup::new();
    // Argument errors are bad input like any other: exit code 1 (not
    // clap's 2), clap's message naming the option. --free is required.
    usage_error(
        hysteron(s.dir()).args([
            "fit",
            "--model",
            "start.json",
            "--data",
            "data.csv",
            "--output",
            "o.json",
        ]),
        "--free",
    );
    // --patience must be ≥ 1, said so (not `0 is not in 1..18446744073709551615`),
    // negative values and non-integers included; --dt must be positive
    for (args, expected) in [
        (
            ["--patience", "0"],
            "'--patience <N>': must be at least 1 (got 0)",
        ),
        (
            ["--patience", "-3"],
            "'--patience <N>': must be at least 1 (got -3)",
        ),
        (
            ["--patience", "2.5"],
            "'--patience <N>': `2.5` is not a whole number",
        ),
        (
            ["--dt", "-1"],
            "'--dt <SECONDS>': must be positive and finite (got -1)",
        ),
        (
            ["--dt", "1e999"],
            "'--dt <SECONDS>': must be positive and finite (got 1e999)",
        ),
    ] {
        let err = usage_error(
            s.fit_with(&[("--output", "o.json"), ("--free", "k")])
                .args(args),
            expected,
        );
        assert!(!err.contains("18446744073709551615"), "{err}");
    }
    assert!(!s.path("o.json").exists());
}

// ------------------------------------------------------- identify-paper

/// Short records of the paper's model (250 Hz): the 0.5 Hz major loop, two
/// cycles, and a 5 → 0.1 Hz down-chirp over 20 s, written as `t,x,F`.
fn paper_records(dir: &Path) {
    let fs_hz = 250.0;
    let p = TransmissionParams::default();
    let sig = sine(0.5, DRIVE.amplitude(0.5), 2.0, fs_hz).unwrap();
    let f = p.build().unwrap().run(&sig.x).unwrap();
    fs::write(
        dir.join("loop.csv"),
        csv_text("t,x,F", &[&sig.t, &sig.x, &f]),
    )
    .unwrap();
    let sig = chirp(5.0, 0.1, 20.0, fs_hz, |f| DRIVE.amplitude(f)).unwrap();
    let f = p.build().unwrap().run(&sig.x).unwrap();
    fs::write(
        dir.join("chirp.csv"),
        csv_text("t,x,F", &[&sig.t, &sig.x, &f]),
    )
    .unwrap();
}

#[test]
fn identify_paper_writes_a_transmission_spec_and_the_stage_reports() {
    let s = Setup::new();
    paper_records(s.dir());
    let assert = hysteron(s.dir())
        .args([
            "identify-paper",
            "--loop",
            "loop.csv",
            "--chirp",
            "chirp.csv",
            "--output",
            "ident.json",
            "--plot",
            "figs",
        ])
        .assert();
    let out = assert.get_output();
    let stdout = String::from_utf8(out.stdout.clone()).unwrap();
    println!("{stdout}");
    let code = out.status.code();
    assert!(code == Some(0) || code == Some(3), "{code:?}: {out:?}");
    assert!(out.stderr.is_empty(), "stderr: {:?}", out.stderr);
    for want in [
        "stage 1: the spring",
        "stage 2: the bedstop",
        "stage 3: all parameters on the loop and the chirp together",
        "from the loop's plateau",
        "limits.b",
        "left.mms.f_c",
        "knots S",
        "RMS error of the identified model",
        "wrote ident.json, figs/loop.svg, figs/chirp.svg",
    ] {
        assert!(stdout.contains(want), "`{want}` not in:\n{stdout}");
    }
    assert_eq!(stdout.matches("95% CI").count(), 3, "{stdout}");
    assert_eq!(code == Some(3), stdout.contains("NOT CONVERGED"));
    let spec = Spec::from_json_file(s.path("ident.json")).unwrap();
    assert_eq!(spec.kind(), "transmission");
    assert_svg(&s.path("figs/loop.svg"));
    assert_svg(&s.path("figs/chirp.svg"));
    // and `simulate` runs it
    s.simulates("ident.json");
    assert_no_temp_files(s.dir());
}

#[test]
fn identify_paper_bad_inputs() {
    let s = Setup::new();
    paper_records(s.dir());
    let base = |over: &[(&str, &str)]| -> Vec<String> {
        let mut opts = vec![
            ("--loop", "loop.csv"),
            ("--chirp", "chirp.csv"),
            ("--output", "ident.json"),
        ];
        for (k, v) in over {
            match opts.iter_mut().find(|(a, _)| a == k) {
                Some(o) => o.1 = v,
                None => opts.push((k, v)),
            }
        }
        let mut args = vec!["identify-paper".to_string()];
        for (k, v) in opts {
            args.push(k.into());
            args.push(v.into());
        }
        args
    };
    let fails = |over: &[(&str, &str)], expect: &[&str]| {
        let args = base(over);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        s.fails_cmd(&args, expect);
    };
    fails(
        &[("--loop", "nope.csv")],
        &["record `nope.csv`", "No such file"],
    );
    fails(
        &[("--chirp", "data.csv")],
        &["record `data.csv`", "no column `F`"],
    );
    s.write("nan.csv", "t,x,F\n0,0,0\n1,0.5,NaN\n");
    fails(
        &[("--chirp", "nan.csv")],
        &["`nan.csv`", "row 2 (line 3)", "column `F`", "not finite"],
    );
    s.write("hdr.csv", "t,x,F\n");
    fails(&[("--loop", "hdr.csv")], &["`hdr.csv`", "no data rows"]);
    // A record without a complete increasing branch.
    s.write("flat.csv", "t,x,F\n0,0,0\n1,0.1,1\n2,0.2,2\n");
    fails(
        &[("--loop", "flat.csv")],
        &["loop `flat.csv`", "no complete increasing branch"],
    );
    for out in ["loop.csv", "./chirp.csv"] {
        fails(&[("--output", out)], &["same file as the", "refusing"]);
    }
    fails(
        &[
            ("--output", "o.json"),
            ("--plot", "."),
            ("--loop", "loop.svg"),
        ],
        &["plot", "same file as the loop record"],
    );
    fails(
        &[("--start", "truth.json")],
        &[
            "start `truth.json`",
            "must be a `transmission` spec",
            "series",
        ],
    );
    fails(
        &[("--start", "nope.json")],
        &["start `nope.json`", "No such file"],
    );
    fails(
        &[("--output-column", "x")],
        &["--input-column and --output-column"],
    );
}
