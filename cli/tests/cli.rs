//! End-to-end tests of the `hysteron` command-line program: `paper` and
//! `simulate`, including every bad-input case of `simulate` (one-line
//! error on stderr naming file/row/column, non-zero exit, no panic, input
//! untouched, no output file).

use assert_cmd::Command;
use hysteron::models::experiments;
use hysteron::models::{Spec, TransmissionParams};
use hysteron::Operator;
use std::fs;
use std::path::{Path, PathBuf};
use tempfile::TempDir;

mod common;
use common::*;

// ---------------------------------------------------------------- paper

#[test]
fn paper_writes_csvs_figures_and_summary() {
    let tmp = TempDir::new().unwrap();
    let out = tmp.path().join("figs");
    let assert = hysteron(tmp.path())
        .args(["paper", "--out"])
        .arg(&out)
        .assert()
        .success();
    let stdout = stdout_of(&assert);

    let exps = experiments::paper_experiments(&TransmissionParams::default()).unwrap();
    assert_eq!(exps.len(), 4);
    let mut total = 0;
    for e in &exps {
        let path = out.join(format!("{}.csv", e.name));
        let (headers, rows) = read_csv(&path);
        assert_eq!(headers, ["t", "x", "F", "z", "slider", "friction", "h"]);
        assert_eq!(rows.len(), e.signal.len(), "{}", e.name);
        total += rows.len();
        // The CSV holds exactly what the library simulates.
        let rec = experiments::simulate(&e.params, &e.signal).unwrap();
        assert_eq!(column(&headers, &rows, "x"), rec.x, "{}", e.name);
        assert_eq!(column(&headers, &rows, "F"), rec.force, "{}", e.name);
        let h: Vec<f64> = rec.state.iter().map(|s| s.h).collect();
        assert_eq!(column(&headers, &rows, "h"), h, "{}", e.name);
        assert!(
            stdout.contains(&e.name),
            "summary lacks {}: {stdout}",
            e.name
        );
    }
    for fig in ["loops.svg", "chirp.svg", "stiffness.svg"] {
        assert_svg(&out.join(fig));
    }
    // Each part of the `sines` run on its own: its rows of `sines.csv`.
    let sines = exps.iter().find(|e| e.name == "sines").unwrap();
    let (_, all) = read_csv(&out.join("sines.csv"));
    for (part, file) in
        sines
            .parts
            .iter()
            .zip(["sines-0.05Hz.csv", "sines-0.5Hz.csv", "sines-5Hz.csv"])
    {
        let (headers, rows) = read_csv(&out.join(file));
        assert_eq!(headers, ["t", "x", "F", "z", "slider", "friction", "h"]);
        assert_eq!(rows, all[part.range.clone()], "{file}");
    }
    assert_eq!(fs::read_dir(&out).unwrap().count(), 10);
    assert_no_temp_files(&out);

    // The loops figure has the three frequencies and both initial states.
    let loops = fs::read_to_string(out.join("loops.svg")).unwrap();
    for label in [
        "0.05 Hz",
        "0.5 Hz",
        "5 Hz",
        "initial state I\n",
        "initial state II\n",
    ] {
        assert!(loops.contains(label), "loops.svg lacks {label}");
    }
    // Summary: per-experiment lines, the total, the throughput.
    assert!(stdout.contains("peak |F|") && stdout.contains("loop width"));
    assert!(
        stdout.contains(&format!("total: {total} samples")),
        "{stdout}"
    );
    assert!(stdout.contains("samples/s") && stdout.contains("wall time"));
}

#[test]
fn paper_defaults_to_out_and_overwrites() {
    let tmp = TempDir::new().unwrap();
    for _ in 0..2 {
        hysteron(tmp.path()).arg("paper").assert().success();
    }
    let out = tmp.path().join("out");
    for f in [
        "sines.csv",
        "sine-5hz-I.csv",
        "sine-5hz-II.csv",
        "chirp.csv",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    assert_svg(&out.join("loops.svg"));
    assert_no_temp_files(&out);
}

#[test]
fn paper_reports_an_unusable_out_dir_in_one_line() {
    let tmp = TempDir::new().unwrap();
    let file = tmp.path().join("taken");
    fs::write(&file, "not a directory").unwrap();
    let assert = hysteron(tmp.path())
        .args(["paper", "--out", "taken"])
        .assert()
        .failure();
    let stderr = one_line_error(&assert.get_output().stderr);
    assert!(stderr.contains("taken"), "{stderr}");
    assert_eq!(fs::read_to_string(&file).unwrap(), "not a directory");
}

// ------------------------------------------------------------- simulate

/// A temp dir with a model spec and an input CSV.
struct Setup {
    tmp: TempDir,
}

const INPUT: &str = "t,x,label\n0,0,start\n0.1,0.4,\"a, b\"\n0.2,1.2,c\n0.3,-0.3,d\n0.4,0.9,e\n";

in_temp_dir!(Setup);

impl Setup {
    fn new() -> Self {
        let tmp = TempDir::new().unwrap();
        fs::write(tmp.path().join("in.csv"), INPUT).unwrap();
        // The paper's model as a generic spec, written by the library.
        let spec = Spec::from(&TransmissionParams::default());
        fs::write(
            tmp.path().join("model.json"),
            spec.to_json_pretty().unwrap(),
        )
        .unwrap();
        Setup { tmp }
    }

    fn simulate(&self, args: &[&str]) -> Command {
        let mut cmd = hysteron(self.dir());
        cmd.arg("simulate").args(args);
        cmd
    }

    /// Runs `simulate` expecting failure: exit code 1, one line on stderr
    /// starting with `error:` and containing every `expect`ed fragment,
    /// nothing on stdout, all files in the directory unchanged and no new
    /// file (in particular no output and no temporary file).
    fn fails(&self, args: &[&str], expect: &[&str]) -> String {
        fails_leaving_dir_unchanged(self.dir(), &mut self.simulate(args), expect)
    }
}

/// `--model MODEL --input INPUT --output OUTPUT`, then `extra`.
fn files<'a>(model: &'a str, input: &'a str, output: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec!["--model", model, "--input", input, "--output", output];
    args.extend(extra);
    args
}

fn run_in_process(spec_path: &Path, xs: &[f64]) -> Vec<f64> {
    let mut model = Spec::from_json_file(spec_path).unwrap().build().unwrap();
    model.run(xs).unwrap()
}

#[test]
fn simulate_matches_the_spec_run_in_process() {
    let s = Setup::new();
    succeeds_saying(
        &mut s.simulate(&files(
            "model.json",
            "in.csv",
            "out.csv",
            &["--plot", "loop.svg"],
        )),
        &["simulated 5 samples"],
    );
    let (headers, rows) = read_csv(&s.path("out.csv"));
    assert_eq!(headers, ["t", "x", "label", "y"]);
    // All input columns kept verbatim (the quoted comma too).
    let (in_headers, in_rows) = read_csv(&s.path("in.csv"));
    assert_eq!(&headers[..3], &in_headers[..]);
    for (r, i) in rows.iter().zip(&in_rows) {
        assert_eq!(&r[..3], &i[..]);
    }
    assert_eq!(rows[1][2], "a, b");
    // y is bit for bit what the library computes.
    let x = column(&headers, &rows, "x");
    let y = column(&headers, &rows, "y");
    assert_eq!(y, run_in_process(&s.path("model.json"), &x));
    assert!(y.iter().any(|v| *v != 0.0));
    assert_svg(&s.path("loop.svg"));
    assert_eq!(fs::read_to_string(s.path("in.csv")).unwrap(), INPUT);
    assert_no_temp_files(s.dir());
}

#[test]
fn simulate_every_example_spec() {
    let specs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/specs");
    let mut paths: Vec<PathBuf> = fs::read_dir(&specs)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    paths.sort();
    assert!(paths.iter().any(|p| p.ends_with("paper.json")), "{paths:?}");
    let s = Setup::new();
    // Two cycles of a 1.2 deg sine, 400 samples.
    let (text, x) = two_sine_cycles(400);
    s.write("sine.csv", &text);
    for spec in &paths {
        s.simulate(&[
            "--input", "sine.csv", "--output", "o.csv", "--plot", "o.svg",
        ])
        .arg("--model")
        .arg(spec)
        .assert()
        .success();
        let (headers, rows) = read_csv(&s.path("o.csv"));
        assert_eq!(headers, ["i", "x", "y"], "{}", spec.display());
        assert_eq!(column(&headers, &rows, "x"), x);
        assert_eq!(
            column(&headers, &rows, "y"),
            run_in_process(spec, &x),
            "{}",
            spec.display()
        );
        assert_svg(&s.path("o.svg"));
    }
}

#[test]
fn simulate_hand_written_spec_on_another_column() {
    let s = Setup::new();
    s.write(
        "cascade.json",
        r#"{
            "type": "cascade",
            "first": { "type": "play", "r": 0.5 },
            "second": { "type": "dead_zone", "b_l": -0.25, "b_r": 0.25 }
        }"#,
    );
    s.write("u.csv", "u;v\n0;1\n3;2\n1;3\n");
    // Not comma-separated: one column named "u;v", so `u` is missing.
    s.fails(
        &files("cascade.json", "u.csv", "o.csv", &["--column", "u"]),
        &["u.csv", "no column `u`"],
    );
    s.write("u.csv", "v,u\n1,0\n2,3\n3,1\n4,-2\n");
    s.simulate(&files("cascade.json", "u.csv", "o.csv", &["--column", "u"]))
        .assert()
        .success();
    let (headers, rows) = read_csv(&s.path("o.csv"));
    assert_eq!(headers, ["v", "u", "y"]);
    // play 0.5: 0, 2.5, 1.5, -1.5; dead-zone ±0.25: 0, 2.25, 1.25, -1.25.
    assert_eq!(column(&headers, &rows, "y"), [0.0, 2.25, 1.25, -1.25]);
    assert_eq!(
        column(&headers, &rows, "y"),
        run_in_process(&s.path("cascade.json"), &[0.0, 3.0, 1.0, -2.0])
    );
}

#[test]
fn simulate_overwrites_an_existing_output_atomically() {
    let s = Setup::new();
    s.write("out.csv", "old\n");
    let args = [
        "--model",
        "model.json",
        "--input",
        "in.csv",
        "--output",
        "out.csv",
    ];
    s.simulate(&args).assert().success();
    let (headers, rows) = read_csv(&s.path("out.csv"));
    assert_eq!(headers.last().map(String::as_str), Some("y"));
    assert_eq!(rows.len(), 5);
    assert_no_temp_files(s.dir());
}

/// A `simulate` that must fail: the files written first (name and text),
/// the arguments, and what the error says.
type Refusal<'a> = (Vec<(&'a str, &'a str)>, Vec<&'a str>, &'a [&'a str]);

/// A model that is missing, malformed, invalid or fails at a sample, an
/// input that is missing or lacks the column, a cell that is not a number
/// or not finite, an empty file or a ragged row: the one-line error names
/// the model or the input (and the field, or the sample, row and column).
#[test]
fn simulate_errors_name_the_bad_model_or_input() {
    let s = Setup::new();
    let non_finite =
        ["NaN", "inf", "-inf", "infinity"].map(|bad| format!("t,x\n0,0\n1,{bad}\n2,1\n"));
    let mut cases: Vec<Refusal> = vec![
        (
            vec![],
            files("nope.json", "in.csv", "out.csv", &[]),
            &["model `nope.json`", "No such file"],
        ),
        (
            vec![("bad.json", "{\"type\": \"play\",\n \"r\": }\n")],
            files("bad.json", "in.csv", "out.csv", &[]),
            &["model `bad.json`", "line 2"],
        ),
        (
            vec![(
                "bad.json",
                r#"{"type": "cascade", "first": {"type": "plya", "r": 1}, "second": {"type": "gain", "k": 1}}"#,
            )],
            files("bad.json", "in.csv", "out.csv", &[]),
            &["model `bad.json`", "first.type", "plya"],
        ),
        (
            vec![(
                "bad.json",
                r#"{"type": "scaled", "w": 2, "inner": {"type": "play", "r": -1}}"#,
            )],
            files("bad.json", "in.csv", "out.csv", &[]),
            &["model `bad.json`", "scaled.inner.play.r", "-1"],
        ),
        // The inverse of a saturation has no solution beyond the limits.
        (
            vec![
                (
                    "inv.json",
                    r#"{"type": "inverse", "inner": {"type": "saturation", "lo": -1, "hi": 1}}"#,
                ),
                ("in2.csv", "t,x\n0,0\n1,0.5\n2,1.5\n3,0\n"),
            ],
            files("inv.json", "in2.csv", "out.csv", &[]),
            &[
                "model `inv.json`",
                "sample 2",
                "`in2.csv`",
                "row 3 (line 4)",
                "column `x`",
                "1.5",
            ],
        ),
        (
            vec![],
            files("model.json", "nope.csv", "out.csv", &[]),
            &["input `nope.csv`", "No such file"],
        ),
        (
            vec![],
            files("model.json", "in.csv", "out.csv", &["--column", "theta"]),
            &["input `in.csv`", "no column `theta`", "`t`, `x`, `label`"],
        ),
        (
            vec![("in2.csv", "t,x\n0,0\n1,0.5\n2,abc\n")],
            files("model.json", "in2.csv", "out.csv", &[]),
            &[
                "input `in2.csv`",
                "row 3 (line 4)",
                "column `x`",
                "`abc` is not a number",
            ],
        ),
        // An empty cell is not a number either.
        (
            vec![("in2.csv", "t,x\n0,\n")],
            files("model.json", "in2.csv", "out.csv", &[]),
            &["row 1 (line 2)", "column `x`", "not a number"],
        ),
        (
            vec![("hdr.csv", "t,x\n")],
            files("model.json", "hdr.csv", "out.csv", &[]),
            &["input `hdr.csv`", "no data rows"],
        ),
        (
            vec![("empty.csv", "")],
            files("model.json", "empty.csv", "out.csv", &[]),
            &["input `empty.csv`", "empty file"],
        ),
        (
            vec![("rag.csv", "t,x\n0,0\n1\n")],
            files("model.json", "rag.csv", "out.csv", &[]),
            &["input `rag.csv`", "row 2 (line 3)", "field"],
        ),
    ];
    for text in &non_finite {
        cases.push((
            vec![("in2.csv", text.as_str())],
            files("model.json", "in2.csv", "out.csv", &[]),
            &[
                "input `in2.csv`",
                "row 2 (line 3)",
                "column `x`",
                "not finite",
            ],
        ));
    }
    for (writes, args, expect) in cases {
        for (name, text) in writes {
            s.write(name, text);
        }
        s.fails(&args, expect);
    }
}

#[test]
fn simulate_refuses_to_overwrite_its_inputs() {
    let s = Setup::new();
    for out in spellings_of(s.dir(), "in.csv") {
        s.fails(
            &files("model.json", "in.csv", &out, &[]),
            &["output", "same file as the input", "refusing"],
        );
    }
    let abs = s.path("in.csv");
    s.fails(
        &files("model.json", "in.csv", abs.to_str().unwrap(), &[]),
        &["same file as the input"],
    );
    s.fails(
        &files("model.json", "in.csv", "model.json", &[]),
        &["same file as the model"],
    );
    // Neither exists yet: the plot would overwrite the output.
    s.fails(
        &files("model.json", "in.csv", "o.csv", &["--plot", "sub/../o.csv"]),
        &["plot", "same file as the output"],
    );
}

#[test]
fn simulate_error_output_directory_missing() {
    let s = Setup::new();
    s.fails(
        &files("model.json", "in.csv", "nodir/out.csv", &[]),
        &["output `nodir/out.csv`", "does not exist"],
    );
}

#[test]
fn simulate_error_keeps_an_existing_output() {
    let s = Setup::new();
    s.write("out.csv", "previous\n");
    s.write("in2.csv", "t,x\n0,0\n1,NaN\n");
    s.fails(
        &files("model.json", "in2.csv", "out.csv", &[]),
        &["not finite"],
    );
    assert_eq!(fs::read_to_string(s.path("out.csv")).unwrap(), "previous\n");
}

// ------------------------------------------------- rate-dependent models

/// A mass-spring-damper spec whose own `dt` (1) is not the data's.
const MSD_SPEC: &str = r#"{"type": "mass_spring_damper", "m": 0.5, "c": 3, "k": 200, "dt": 1}"#;

/// A force record sampled every 1/128 s (exact in binary and in the CSV),
/// with a time column `t`.
fn msd_record() -> (String, Vec<f64>) {
    let dt = 1.0 / 128.0;
    let x: Vec<f64> = (0..200)
        .map(|i| 10.0 * (std::f64::consts::TAU * i as f64 * dt).sin())
        .collect();
    let mut text = String::from("t,x\n");
    for (i, v) in x.iter().enumerate() {
        text.push_str(&format!("{},{v}\n", i as f64 * dt));
    }
    (text, x)
}

#[test]
fn simulate_mass_spring_damper_with_time_column_matches_in_process() {
    let s = Setup::new();
    s.write("msd.json", MSD_SPEC);
    let (text, x) = msd_record();
    s.write("f.csv", &text);
    let expected = {
        let spec = Spec::from_json(MSD_SPEC).unwrap().with_dt(1.0 / 128.0);
        spec.build().unwrap().run(&x).unwrap()
    };
    for dt_args in [&["--time-column", "t"][..], &["--dt", "0.0078125"][..]] {
        let (_, y) = succeeds_writing_txy(
            s.simulate(&files("msd.json", "f.csv", "o.csv", &[]))
                .args(dt_args),
            &s.path("o.csv"),
        );
        assert_eq!(y, expected, "{dt_args:?}");
    }
    // Without either, the spec's own dt (1 s) disagrees with the data's
    // time column `t`: refused, naming both periods and both ways out,
    // and nothing is written.
    fs::remove_file(s.path("o.csv")).unwrap();
    s.fails(
        &files("msd.json", "f.csv", "o.csv", &[]),
        &[
            "data `f.csv`: its time column `t` steps 0.0078125 s",
            "the model's spec gives the sample period 1 s",
            "--time-column t",
            "--dt SECONDS",
        ],
    );
    assert!(!s.path("o.csv").exists());
    // A column not named as time is not read as one: the spec's dt (1 s)
    // is used, and the report says so.
    s.write("f.csv", &text.replacen("t,x", "stamp,x", 1));
    let out = s
        .simulate(&files("msd.json", "f.csv", "o.csv", &[]))
        .assert()
        .success();
    let stdout = String::from_utf8_lossy(&out.get_output().stdout).into_owned();
    assert!(
        stdout.contains("at a sample period of 1 s (the spec's dt)"),
        "{stdout}"
    );
    let (headers, rows) = read_csv(&s.path("o.csv"));
    let y = column(&headers, &rows, "y");
    assert_eq!(y, run_in_process(&s.path("msd.json"), &x));
    assert_ne!(y, expected);
    assert_no_temp_files(s.dir());
}

/// Measured time stamps are written rounded (`1.000976562` for 1025/1024
/// s at 9 decimals); such a column is uniform to within its rounding and is
/// accepted (a 1e-9 relative check on each step once refused it), the
/// period being the mean step: the output matches `--dt 1/1024` to the
/// rounding of the last stamp.
#[test]
fn simulate_accepts_rounded_time_stamps() {
    let s = Setup::new();
    s.write("msd.json", MSD_SPEC);
    let n = 3000;
    let mut text = String::from("t,x\n");
    let mut x = Vec::new();
    for i in 0..n {
        let t = i as f64 / 1024.0;
        let v = 10.0 * (std::f64::consts::TAU * 3.0 * t).sin();
        x.push(v);
        text.push_str(&format!("{t:.9},{v}\n"));
    }
    assert!(text.contains("1.000976562,"), "a rounded stamp");
    s.write("f.csv", &text);
    s.simulate(&files(
        "msd.json",
        "f.csv",
        "o.csv",
        &["--time-column", "t"],
    ))
    .assert()
    .success();
    let (headers, rows) = read_csv(&s.path("o.csv"));
    let y = column(&headers, &rows, "y");
    let exact = Spec::from_json(MSD_SPEC)
        .unwrap()
        .with_dt(1.0 / 1024.0)
        .build()
        .unwrap()
        .run(&x)
        .unwrap();
    let scale = exact.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let err = y
        .iter()
        .zip(&exact)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    // the mean step differs from 1/1024 by at most 5e-10 s / 2.9 s
    assert!(err <= 1e-8 * scale, "max error {err:e} of {scale:e}");
}

/// The Bouc-Wen benchmark as an `oversample` spec (20 sub-steps of the
/// oscillator per data sample) run by `simulate --time-column` over three
/// periods of `val_multisine`: the last period matches the published output
/// to ≤ 1e-5 m RMS. When the time column's period reached the inner
/// oscillator as the data period instead of T/20, the error was 7.7e-4 m.
#[test]
fn simulate_time_column_gives_an_oversampled_spec_its_sub_step() {
    let s = Setup::new();
    s.write(
        "bw.json",
        r#"{"type": "oversample", "q": 20, "inner": {"type": "feedback",
            "forward": {"type": "mass_spring_damper", "m": 2, "c": 10, "k": 50000, "dt": 1},
            "back": {"type": "bouc_wen", "w": 0, "alpha": 50000, "beta": 800, "gamma": -1100,
                     "n": 1, "stiffness": {"z": [0], "s": [1]}}}}"#,
    );
    let data = fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/boucwen-benchmark/val_multisine.csv"),
    )
    .unwrap();
    let rows: Vec<(f64, f64)> = data
        .lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|c| c.parse().unwrap()).collect();
            (v[1], v[2])
        })
        .collect();
    let n = rows.len();
    let mut text = String::from("t,u\n");
    for i in 0..3 * n {
        text.push_str(&format!("{},{}\n", i as f64 / 750.0, rows[i % n].0));
    }
    s.write("u.csv", &text);
    s.simulate(&files("bw.json", "u.csv", "o.csv", &[]))
        .args(["--column", "u", "--time-column", "t"])
        .assert()
        .success();
    let (headers, out) = read_csv(&s.path("o.csv"));
    let y = column(&headers, &out, "y");
    let sq: f64 = y[2 * n..]
        .iter()
        .zip(&rows)
        .map(|(a, (_, b))| (a - b) * (a - b))
        .sum();
    let rms = (sq / n as f64).sqrt();
    assert!(rms <= 1e-5, "rms error {rms:e} m");
}

/// `--output-column` names the output; a name the input already has is an
/// error naming it (the input may have a `y` column of its own).
#[test]
fn simulate_output_column_is_named_and_may_not_clash() {
    let s = Setup::new();
    s.write("g.json", r#"{"type": "gain", "k": 2}"#);
    s.write("f.csv", "x,y\n1,10\n2,20\n");
    let args = ["--model", "g.json", "--input", "f.csv", "--output", "o.csv"];
    s.fails(
        &args,
        &[
            "input `f.csv`",
            "already has a column `y`",
            "--output-column",
        ],
    );
    s.fails(
        &[&args[..], &["--output-column", "x"]].concat(),
        &["already has a column `x`"],
    );
    s.simulate(&[&args[..], &["--output-column", "force"]].concat())
        .assert()
        .success();
    let (headers, rows) = read_csv(&s.path("o.csv"));
    assert_eq!(headers, ["x", "y", "force"]);
    assert_eq!(column(&headers, &rows, "force"), [2.0, 4.0]);
    assert_eq!(column(&headers, &rows, "y"), [10.0, 20.0]);
}

#[test]
fn simulate_error_non_uniform_time_column_names_the_row() {
    let s = Setup::new();
    s.write("msd.json", MSD_SPEC);
    s.write("f.csv", "t,x\n0,0\n0.5,1\n1,2\n1.6,3\n2.1,4\n");
    let args = [
        "--model",
        "msd.json",
        "--input",
        "f.csv",
        "--output",
        "o.csv",
        "--time-column",
        "t",
    ];
    s.fails(
        &args,
        &[
            "input `f.csv`",
            "row 4 (line 5)",
            "column `t`",
            "uniformly spaced",
        ],
    );
    // time running backwards, a missing time column, a single row
    s.write("f.csv", "t,x\n1,0\n0.5,1\n");
    s.fails(
        &args,
        &["row 2 (line 3)", "column `t`", "does not increase"],
    );
    s.write("f.csv", "u,x\n0,0\n1,1\n");
    s.fails(&args, &["f.csv", "no column `t`"]);
    s.write("f.csv", "t,x\n0,0\n");
    s.fails(&args, &["row 1 (line 2)", "at least 2 rows"]);
    // --dt overrides; it must be positive and finite (refused as an
    // argument, exit code 1, negative values included)
    s.write("f.csv", "t,x\n0,0\n1,1\n");
    for dt in ["0", "-1", "-0.5", "-inf", "inf", "NaN"] {
        let before = snapshot(s.dir());
        let err = usage_error(
            &mut s.simulate(&files("msd.json", "f.csv", "o.csv", &["--dt", dt])),
            "'--dt <SECONDS>'",
        );
        assert!(
            err.contains("must be positive and finite"),
            "--dt {dt}: {err}"
        );
        assert!(!err.contains("unexpected argument"), "{err}");
        assert_eq!(snapshot(s.dir()), before);
    }
    // the two options exclude each other (an argument error, exit code 1)
    s.simulate(&files("msd.json", "f.csv", "o.csv", &[]))
        .args(["--dt", "0.1", "--time-column", "t"])
        .assert()
        .failure()
        .code(1);
    assert!(!s.path("o.csv").exists());
}

#[test]
fn fit_mass_spring_damper_with_time_column() {
    let s = Setup::new();
    let (text, x) = msd_record();
    // The measured output: the same oscillator with c = 5 at the data rate.
    let truth = Spec::from_json(MSD_SPEC)
        .unwrap()
        .with_dt(1.0 / 128.0)
        .with_params(&[0.5, 5.0, 200.0])
        .unwrap();
    let y = truth.build().unwrap().run(&x).unwrap();
    let mut data = String::from("t,x,y\n");
    for (line, v) in text.lines().skip(1).zip(&y) {
        data.push_str(&format!("{line},{v}\n"));
    }
    s.write("data.csv", &data);
    s.write("msd.json", MSD_SPEC);
    hysteron(s.dir())
        .args([
            "fit",
            "--model",
            "msd.json",
            "--data",
            "data.csv",
            "--free",
            "c",
            "--output",
            "fitted.json",
            "--time-column",
            "t",
            "--no-progress",
        ])
        .assert()
        .success();
    let fitted = Spec::from_json_file(s.path("fitted.json")).unwrap();
    let Some(p) = fitted.leaf_params::<hysteron::operators::MassSpringDamper<f64>>() else {
        panic!("{fitted:?}")
    };
    assert_eq!(p.dt, 1.0 / 128.0);
    assert!((p.c - 5.0).abs() < 1e-6, "{p:?}");
    assert_eq!((p.m, p.k), (0.5, 200.0));
}
