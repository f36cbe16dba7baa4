//! End-to-end tests of `hysteron sensitivity`: the closed form of a
//! play-then-gain cascade, the paper's model against central differences
//! of `hysteron simulate` runs, more parameters than one pass of dual
//! numbers holds, and the bad-input cases (one line on stderr starting with
//! `error:`, exit code 1, nothing on stdout, no file changed or created).

use assert_cmd::Command;
use hysteron::models::sensitivity::sensitivity;
use hysteron::models::Spec;
use std::fs;
use std::path::{Path, PathBuf};
use tempfile::TempDir;

mod common;
use common::*;

/// y = k·play_r(x) with r = 0.5, k = 2: on the rising branch y = k (x − r).
const CASCADE: &str = r#"{"type": "cascade",
  "first": {"type": "play", "r": 0.5}, "second": {"type": "gain", "k": 2.0}}"#;

struct Setup {
    tmp: TempDir,
}

in_temp_dir!(Setup);

impl Setup {
    /// A temp dir with `cascade.json` and `in.csv` (t, x = 1, 2, label).
    fn new() -> Self {
        let s = Setup {
            tmp: TempDir::new().unwrap(),
        };
        s.write("cascade.json", CASCADE);
        s.write("in.csv", "t,x,label\n0,1,\"a, b\"\n0.1,2,c\n");
        s
    }

    /// Runs `sensitivity` with [`files`]`(args)` and `extra`, expecting
    /// success; returns the output file's header and records.
    fn sensitivity(&self, args: [&str; 4], extra: &[&str]) -> (Vec<String>, Vec<Vec<String>>) {
        succeeds_writing_csv(
            self.cmd("sensitivity", &files(args)).args(extra),
            &self.path(args[3]),
        )
    }

    fn cmd(&self, sub: &str, args: &[&str]) -> Command {
        let mut cmd = hysteron(self.dir());
        cmd.arg(sub).args(args);
        cmd
    }

    /// Runs `sensitivity` expecting failure that leaves the directory as
    /// it was; returns the error line.
    fn fails(&self, args: &[&str], expect: &[&str]) -> String {
        fails_leaving_dir_unchanged(self.dir(), &mut self.cmd("sensitivity", args), expect)
    }
}

/// `--model MODEL --input INPUT --output OUTPUT --params PARAMS`, from
/// `[MODEL, INPUT, PARAMS, OUTPUT]` (the first six without `--params`).
fn files([model, input, params, output]: [&str; 4]) -> [&str; 8] {
    [
        "--model", model, "--input", input, "--output", output, "--params", params,
    ]
}

/// `examples/specs/paper.json`.
fn paper_spec() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/specs/paper.json")
}

/// Two cycles of a 1.2 sine, 200 samples, as `i,x`.
fn sine_csv() -> (String, Vec<f64>) {
    two_sine_cycles(200)
}

#[test]
fn cascade_matches_the_closed_form() {
    let s = Setup::new();
    let args = [
        "cascade.json",
        "in.csv",
        "first.play.r,second.gain.k",
        "out.csv",
    ];
    succeeds_saying(
        &mut s.cmd("sensitivity", &files(args)),
        &["2 parameter(s) (first.play.r, second.gain.k) over 2 samples"],
    );
    let (headers, rows) = read_csv(&s.path("out.csv"));
    assert_eq!(
        headers,
        [
            "t",
            "x",
            "label",
            "y",
            "dy/dfirst.play.r",
            "dy/dsecond.gain.k"
        ]
    );
    // The input's fields verbatim (the quoted comma too).
    assert_eq!(rows[0][..3], ["0", "1", "a, b"]);
    assert_eq!(column(&headers, &rows, "y"), [1.0, 3.0]);
    // ∂y/∂r = −k, ∂y/∂k = x − r
    assert_eq!(column(&headers, &rows, "dy/dfirst.play.r"), [-2.0, -2.0]);
    assert_eq!(column(&headers, &rows, "dy/dsecond.gain.k"), [0.5, 1.5]);
    assert_no_temp_files(s.dir());
}

#[test]
fn suffixes_another_column_and_output_column_name() {
    let s = Setup::new();
    s.write("xy.csv", "u,y\n1,9\n2,9\n");
    let (headers, rows) = s.sensitivity(
        ["cascade.json", "xy.csv", "k, r", "out.csv"],
        &["--column", "u", "--output-column", "F"],
    );
    assert_eq!(
        headers,
        ["u", "y", "F", "dF/dsecond.gain.k", "dF/dfirst.play.r"]
    );
    assert_eq!(column(&headers, &rows, "F"), [1.0, 3.0]);
    assert_eq!(column(&headers, &rows, "dF/dsecond.gain.k"), [0.5, 1.5]);
    assert_eq!(column(&headers, &rows, "dF/dfirst.play.r"), [-2.0, -2.0]);
}

/// Runs `simulate` with the paper's spec, `left.mms.f_c` moved by `delta`.
fn simulate_with_f_c(s: &Setup, delta: f64) -> Vec<f64> {
    let mut spec: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(paper_spec()).unwrap()).unwrap();
    let f_c = spec["left"]["f_c"].as_f64().unwrap();
    spec["left"]["f_c"] = serde_json::json!(f_c + delta);
    s.write("moved.json", &serde_json::to_string(&spec).unwrap());
    let (headers, rows) = succeeds_writing_csv(
        &mut s.cmd(
            "simulate",
            &[
                "--model",
                "moved.json",
                "--input",
                "sine.csv",
                "--output",
                "moved.csv",
            ],
        ),
        &s.path("moved.csv"),
    );
    column(&headers, &rows, "y")
}

#[test]
fn paper_model_matches_central_differences_of_simulate() {
    let s = Setup::new();
    let (text, x) = sine_csv();
    s.write("sine.csv", &text);
    let paper = paper_spec();
    let paper = paper.to_str().unwrap();
    let (headers, rows) = s.sensitivity([paper, "sine.csv", "f_c", "sens.csv"], &[]);
    assert_eq!(headers, ["i", "x", "y", "dy/dleft.mms.f_c"]);
    assert_eq!(column(&headers, &rows, "x"), x);
    let y = column(&headers, &rows, "y");
    let ad = column(&headers, &rows, "dy/dleft.mms.f_c");

    // The output is simulate's (up to the rounding of an implicit solve).
    let y0 = simulate_with_f_c(&s, 0.0);
    let y_max = y0.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (k, (a, b)) in y.iter().zip(&y0).enumerate() {
        assert!((a - b).abs() <= 1e-12 * y_max, "sample {k}: y {a} vs {b}");
    }

    let h = 1e-5;
    let plus = simulate_with_f_c(&s, h);
    let minus = simulate_with_f_c(&s, -h);
    let scale = ad.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(scale > 0.1, "∂y/∂f_c vanishes: {scale}");
    // Smooth samples: the one-sided differences agree (no switch of
    // stick/slip or contact between f_c − h and f_c + h).
    let mut compared = 0;
    for k in 0..x.len() {
        let forward = (plus[k] - y0[k]) / h;
        let backward = (y0[k] - minus[k]) / h;
        if (forward - backward).abs() > 1e-3 * scale {
            continue;
        }
        let central = (plus[k] - minus[k]) / (2.0 * h);
        assert!(
            (ad[k] - central).abs() <= 1e-6 * scale,
            "sample {k}: dual {} vs central difference {central} (scale {scale})",
            ad[k]
        );
        compared += 1;
    }
    assert!(compared >= 180, "only {compared} smooth samples of 200");
}

#[test]
fn more_parameters_than_one_pass_of_dual_numbers() {
    let s = Setup::new();
    let (text, x) = sine_csv();
    s.write("sine.csv", &text);
    // Ten parameters: two passes of 8 (the second holding 2).
    let names = [
        "left.mms.f_c",
        "left.mms.k",
        "right.bouc_wen.w",
        "right.bouc_wen.alpha",
        "right.bouc_wen.beta",
        "right.bouc_wen.gamma",
        "right.bouc_wen.n",
        "right.bouc_wen.stiffness.s[0]",
        "right.bouc_wen.stiffness.s[2]",
        "right.bouc_wen.stiffness.z[1]",
    ];
    let (paper, params) = (paper_spec(), names.join(","));
    let (headers, rows) = s.sensitivity(
        [paper.to_str().unwrap(), "sine.csv", &params, "sens.csv"],
        &[],
    );
    let expected: Vec<String> = ["i", "x", "y"]
        .iter()
        .map(|h| h.to_string())
        .chain(names.iter().map(|n| format!("dy/d{n}")))
        .collect();
    assert_eq!(headers, expected);
    // Each column is that of the parameter on its own (in a pass of one),
    // so the passes are seeded and assembled in the right order (up to
    // the implicit solves' stopping point, which moves with the pass's
    // other seeds, in y too, at the 1e-12 level).
    let spec = Spec::from_json_file(paper_spec()).unwrap();
    for name in names {
        let alone = sensitivity(&spec, &x, &[name]).unwrap();
        let got = column(&headers, &rows, &format!("dy/d{name}"));
        let want = &alone.columns[0];
        let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(scale > 0.0, "{name}: zero column");
        for (k, (a, b)) in got.iter().zip(want).enumerate() {
            assert!(
                (a - b).abs() <= 1e-9 * scale,
                "{name}, sample {k}: {a} vs {b}"
            );
        }
        let y = column(&headers, &rows, "y");
        let y_max = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (k, (a, b)) in y.iter().zip(&alone.output).enumerate() {
            assert!(
                (a - b).abs() <= 1e-9 * y_max,
                "{name}, sample {k}: y {a} vs {b}"
            );
        }
    }
}

#[test]
fn error_unknown_parameter_names_it_and_lists_the_available() {
    let s = Setup::new();
    s.fails(
        &files(["cascade.json", "in.csv", "second.gain.k,no_such", "out.csv"]),
        &[
            "--params",
            "cascade.json",
            "`no_such`",
            "first.play.r, first.play.y0, second.gain.k",
        ],
    );
}

#[test]
fn error_bad_parameter_lists() {
    let s = Setup::new();
    let with = |params| files(["cascade.json", "in.csv", params, "out.csv"]);
    // Given twice, once by suffix.
    s.fails(
        &with("k,second.gain.k"),
        &["`second.gain.k` is given twice"],
    );
    // Nothing but separators.
    s.fails(&with(" , "), &["no parameter given", "first.play.r"]);
    // Ambiguous suffix.
    s.write(
        "two.json",
        r#"{"type": "parallel", "left": {"type": "play", "r": 0.5},
            "right": {"type": "play", "r": 0.2}}"#,
    );
    s.fails(
        &files(["two.json", "in.csv", "r", "out.csv"]),
        &["`r` is ambiguous", "left.play.r", "right.play.r"],
    );
    // --params is required.
    usage_error(&mut s.cmd("sensitivity", &with("k")[..6]), "--params");
}

#[test]
fn error_bad_input() {
    let s = Setup::new();
    let run = |input: &str, expect: &[&str]| {
        s.fails(&files(["cascade.json", input, "k", "out.csv"]), expect)
    };
    s.write("nan.csv", "t,x\n0,1\n0.1,NaN\n0.2,3\n");
    run(
        "nan.csv",
        &[
            "nan.csv",
            "row 2 (line 3)",
            "column `x`",
            "`NaN` is not finite",
        ],
    );
    s.write("header.csv", "t,x\n");
    run("header.csv", &["header.csv", "no data rows"]);
    s.write("empty.csv", "");
    run("empty.csv", &["empty.csv", "empty file"]);
    s.write("text.csv", "t,x\n0,one\n");
    run(
        "text.csv",
        &["row 1 (line 2)", "column `x`", "`one` is not a number"],
    );
    s.write("other.csv", "t,u\n0,1\n");
    run("other.csv", &["no column `x`", "`u`"]);
    // An output column the input already has.
    s.write("taken.csv", "x,dy/dsecond.gain.k\n1,0\n");
    run("taken.csv", &["already has a column `dy/dsecond.gain.k`"]);
    run("missing.csv", &["missing.csv"]);
}

#[test]
fn error_bad_model_and_same_file() {
    let s = Setup::new();
    s.write("bad.json", r#"{"type": "play", "r": -1}"#);
    s.fails(
        &files(["bad.json", "in.csv", "r", "out.csv"]),
        &["model `bad.json`", "r"],
    );
    s.fails(
        &files(["cascade.json", "in.csv", "k", "in.csv"]),
        &["same file"],
    );
}

#[test]
fn help_describes_the_command() {
    let s = Setup::new();
    let assert = s.cmd("sensitivity", &["--help"]).assert().success();
    let help = stdout_of(&assert);
    for fragment in [
        "--params",
        "--column",
        "--time-column",
        "dy/d<path>",
        "automatic",
    ] {
        assert!(help.contains(fragment), "`{fragment}` not in: {help}");
    }
    let assert = s.cmd("--help", &[]).assert().success();
    assert!(stdout_of(&assert).contains("sensitivity"));
}
