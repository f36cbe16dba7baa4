//! What a new user ran into, end to end: blank lines and duplicate column
//! names in a CSV file, huge and tiny numbers written as hundreds of
//! digits, exit codes of argument errors, `simulate` on a long record
//! (streamed; output bit for bit as before) and its figure (bounded, the
//! extremes kept).

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use std::fs;
use std::path::Path;
use tempfile::TempDir;

mod common;
use common::*;

const GAIN: &str = r#"{"type": "gain", "k": 2.0}"#;

fn specs() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/specs")
}

fn fixtures() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures")
}

/// Runs `simulate --model m.json --input in.csv --output out.csv` plus
/// `extra` in `dir`: exit code, stdout, stderr.
fn simulate(dir: &Path, extra: &[&str]) -> (i32, String, String) {
    let out = hysteron(dir)
        .args([
            "simulate", "--model", "m.json", "--input", "in.csv", "--output", "out.csv",
        ])
        .args(extra)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A directory holding `m.json`, a gain of 2.
fn gain_dir() -> TempDir {
    let tmp = TempDir::new().unwrap();
    fs::write(tmp.path().join("m.json"), GAIN).unwrap();
    tmp
}

/// Writes `csv` as `in.csv` in `dir` and simulates it.
fn simulate_csv(dir: &Path, csv: &str) -> (i32, String, String) {
    fs::write(dir.join("in.csv"), csv).unwrap();
    simulate(dir, &[])
}

/// Writes `csv` as `in.csv` in `dir` and simulates it, expecting exit code
/// 1, nothing on stdout, a one-line error holding every `expected`
/// fragment, and no file changed or written; `case` names the case in every
/// message.
fn refused(dir: &Path, case: &str, csv: &str, expected: &[&str]) {
    fs::write(dir.join("in.csv"), csv).unwrap();
    let before = snapshot(dir);
    let (code, stdout, stderr) = simulate(dir, &[]);
    assert_eq!(code, 1, "{case}: {stderr}");
    assert!(stdout.is_empty(), "{case}: {stdout}");
    let err = one_line_error(stderr.as_bytes());
    for e in expected {
        assert!(err.contains(e), "{case}: `{e}` not in: {err}");
    }
    assert_eq!(snapshot(dir), before, "{case}: wrote something");
}

// ---------------------------------------------------------- CSV structure

/// A blank line between rows, or a column name given twice: a one-line
/// error naming it (and, for blank lines, where they are accepted), nothing
/// on stdout and nothing written.
#[test]
fn a_blank_line_between_rows_or_a_duplicate_column_name_is_an_error_naming_it() {
    let tmp = gain_dir();
    const BLANK_LINES: &str = "blank lines are only accepted at the end of the file";
    let cases: [(&str, &[&str]); 5] = [
        (
            "t,x\n0,1\n1,2\n\n2,3\n",
            &[
                "`in.csv`, line 4: blank line before row 3 (line 5)",
                BLANK_LINES,
            ],
        ),
        (
            "t,x\r\n0,1\r\n\r\n1,2\r\n",
            &[
                "`in.csv`, line 3: blank line before row 2 (line 4)",
                BLANK_LINES,
            ],
        ),
        (
            "t,x\n\n0,1\n",
            &[
                "`in.csv`, line 2: blank line before row 1 (line 3)",
                BLANK_LINES,
            ],
        ),
        (
            "x,x\n1,2\n",
            &["`in.csv`: column `x` appears twice in the header (columns 1 and 2)"],
        ),
        (
            "t,x, t \n0,1,2\n",
            &["`in.csv`: column `t` appears twice in the header (columns 1 and 3)"],
        ),
    ];
    for (csv, expected) in cases {
        refused(tmp.path(), &format!("{csv:?}"), csv, expected);
        assert!(!tmp.path().join("out.csv").exists(), "{csv:?}");
    }
    // a final line end and blank lines after the last row are accepted
    for csv in ["t,x\n0,1\n1,2", "t,x\n0,1\n1,2\n", "t,x\n0,1\n1,2\n\n\n"] {
        let (code, _, stderr) = simulate_csv(tmp.path(), csv);
        assert_eq!(code, 0, "{csv:?}: {stderr}");
        assert_eq!(
            fs::read_to_string(tmp.path().join("out.csv")).unwrap(),
            "t,x,y\n0,1,2\n1,2,4\n"
        );
    }
    // fit reads its record through the same reader
    fs::write(tmp.path().join("in.csv"), "x,y,y\n1,2,3\n").unwrap();
    let out = hysteron(tmp.path())
        .args([
            "fit", "--model", "m.json", "--data", "in.csv", "--free", "k", "--output", "f.json",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = one_line_error(&out.stderr);
    assert!(err.contains("column `y` appears twice"), "{err}");
}

// --------------------------------------------------------- number format

#[test]
fn huge_and_tiny_values_are_written_short_and_read_back_exactly() {
    let tmp = TempDir::new().unwrap();
    fs::write(tmp.path().join("m.json"), r#"{"type": "gain", "k": 1.0}"#).unwrap();
    let mut values = vec![
        1e300,
        -1e300,
        5e-324,
        -0.0,
        0.0,
        1.0 / 3.0,
        0.1,
        1e-5,
        123456.789,
        f64::MAX,
        -f64::MIN_POSITIVE,
    ];
    // random bit patterns over the whole finite range
    let mut rng = StdRng::seed_from_u64(0x2545_F491_4F6C_DD1D);
    let random_bits = std::iter::repeat_with(|| f64::from_bits(rng.random()));
    values.extend(random_bits.filter(|v| v.is_finite()).take(3000));
    let mut csv = String::from("x\n");
    for v in &values {
        csv.push_str(&format!("{v:e}\n"));
    }
    fs::write(tmp.path().join("in.csv"), csv).unwrap();
    let (code, _, stderr) = simulate(tmp.path(), &[]);
    assert_eq!(code, 0, "{stderr}");
    let text = fs::read_to_string(tmp.path().join("out.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("x,y"));
    let ys: Vec<&str> = lines.map(|l| l.rsplit(',').next().unwrap()).collect();
    assert_eq!(ys.len(), values.len());
    assert_eq!(
        &ys[..8],
        [
            "1e300",
            "-1e300",
            "5e-324",
            "-0",
            "0",
            "0.3333333333333333",
            "0.1",
            "1e-5"
        ]
    );
    for (y, v) in ys.iter().zip(&values) {
        assert!(y.len() <= 24, "{y}");
        assert_eq!(y.parse::<f64>().unwrap().to_bits(), v.to_bits(), "{y}");
    }
}

// ------------------------------------------------------------ exit codes

/// `identify-paper` with all its files named (none of them read when an
/// argument is refused).
const IDENTIFY_PAPER: [&str; 7] = [
    "identify-paper",
    "--loop",
    "l.csv",
    "--chirp",
    "c.csv",
    "--output",
    "o.json",
];

#[test]
fn argument_errors_exit_with_1_help_and_version_with_0() {
    let tmp = TempDir::new().unwrap();
    for args in [
        &["--help"][..],
        &["--version"],
        &["simulate", "--help"],
        &["help", "fit"],
    ] {
        let out = hysteron(tmp.path()).args(args).output().unwrap();
        assert_eq!(out.status.code(), Some(0), "{args:?}");
        assert!(!out.stdout.is_empty(), "{args:?}");
    }
    for args in [
        &[][..],
        &["no-such-command"],
        &["simulate"],
        &[
            "simulate", "--model", "m.json", "--input", "i.csv", "--output", "o.csv", "--bogus",
        ],
        &[
            "simulate", "--model", "m.json", "--input", "i.csv", "--output", "o.csv", "--dt", "-1",
        ],
        &[
            "fit",
            "--model",
            "m.json",
            "--data",
            "d.csv",
            "--free",
            "k",
            "--output",
            "o.json",
            "--patience",
            "0",
        ],
        &[&IDENTIFY_PAPER[..], &["--points", "1"]].concat()[..],
        &[
            "analyze",
            "--model",
            "m.json",
            "--amplitudes",
            "1",
            "--samples-per-period",
            "abc",
        ],
    ] {
        let out = hysteron(tmp.path()).args(args).output().unwrap();
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.starts_with("error: ") || err.contains("Usage:"),
            "{args:?}: {err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
    usage_error(
        hysteron(tmp.path())
            .args(IDENTIFY_PAPER)
            .args(["--points", "-4"]),
        "'--points <N>': must be at least 2 (got -4)",
    );
}

// ------------------------------------------------------- streamed simulate

/// The output of `simulate` on a small file is what it was before the
/// record was streamed (the fixtures were written by the program before
/// that change), bit for bit, except values below 1e-4 in magnitude, now
/// written in scientific notation (same bits). The paper model's fixture
/// was rewritten twice since, when MMS took `exp` instead of `expm1` past
/// `K |x − x_r| = ln 2`, and when it took its own vectorisable `e^x − 1`
/// (outputs moved by at most 2.8e-15 of max |y| each time: 187 of 600
/// lines the second time), and a third time when the series' solver took
/// Newton steps from a predicted split and stopped at the first point whose
/// Newton step is within its tolerance, one evaluation before it used to
/// (240 lines, by at most 2.7e-15 of max |y|), and a fourth when the
/// series' predicted split became the cubic through the last two roots
/// with their slopes (128 lines, by at most 2.0e-16 of max |y|), and a
/// fifth when a Halley step from the predicted split took the elements'
/// second derivatives, and from just inside a limit where the contact
/// lets go (188 lines, by at most 5.3e-16 of max |y|), and a sixth when the
/// Bouc-Wen spring took its own vectorisable `e^x` (104 lines, by at most
/// 1.5e-16 of max |y|).
#[test]
fn simulate_output_is_unchanged_by_streaming() {
    let tmp = TempDir::new().unwrap();
    fs::copy(fixtures().join("small_in.csv"), tmp.path().join("in.csv")).unwrap();
    for (spec, extra) in [
        ("paper", &[][..]),
        ("prandtl-ishlinskii", &[]),
        ("lugre", &["--time-column", "t"]),
    ] {
        fs::copy(
            specs().join(format!("{spec}.json")),
            tmp.path().join("m.json"),
        )
        .unwrap();
        let (code, _, stderr) = simulate(tmp.path(), &[&["--column", "x"], extra].concat());
        assert_eq!(code, 0, "{stderr}");
        let now = fs::read_to_string(tmp.path().join("out.csv")).unwrap();
        let before = fs::read_to_string(fixtures().join(format!("small_out_{spec}.csv"))).unwrap();
        assert_eq!(now.lines().count(), before.lines().count());
        let mut rewritten = 0;
        for (a, b) in now.lines().zip(before.lines()) {
            if a == b {
                continue;
            }
            let (ya, yb) = (a.rsplit(',').next().unwrap(), b.rsplit(',').next().unwrap());
            assert_eq!(a[..a.len() - ya.len()], b[..b.len() - yb.len()], "{spec}");
            let (va, vb): (f64, f64) = (ya.parse().unwrap(), yb.parse().unwrap());
            assert_eq!(va.to_bits(), vb.to_bits(), "{spec}: {a} vs {b}");
            assert!(vb.abs() < 1e-4 && ya.contains('e'), "{spec}: {a} vs {b}");
            rewritten += 1;
        }
        assert!(rewritten <= 1, "{spec}: {rewritten}");
    }
}

/// A record longer than a chunk: an operator error and a bad cell past the
/// first chunk are named by their row and line, and nothing is written.
#[test]
fn streamed_errors_name_rows_past_the_first_chunk() {
    let tmp = gain_dir();
    let n = 3 * hysteron_cli::simulate::CHUNK + 17;
    let mut csv = String::from("x\n");
    for i in 0..n {
        csv.push_str(&format!("{}\n", i as f64 * 1e-3));
    }
    fs::write(tmp.path().join("in.csv"), &csv).unwrap();
    let (code, stdout, stderr) = simulate(tmp.path(), &[]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains(&format!("simulated {n} samples")),
        "{stdout}"
    );
    let out = fs::read_to_string(tmp.path().join("out.csv")).unwrap();
    assert_eq!(out.lines().count(), n + 1);
    fs::remove_file(tmp.path().join("out.csv")).unwrap();

    let bad_row = 2 * hysteron_cli::simulate::CHUNK + 5;
    let lines: Vec<String> = csv
        .lines()
        .enumerate()
        .map(|(i, l)| {
            if i == bad_row {
                "oops".to_string()
            } else {
                l.to_string()
            }
        })
        .collect();
    let place = format!(
        "row {bad_row} (line {}), column `x`: `oops` is not a number",
        bad_row + 1
    );
    refused(tmp.path(), "a bad cell", &lines.join("\n"), &[&place]);

    // an inverse that cannot be solved past the first chunk
    fs::write(
        tmp.path().join("m.json"),
        r#"{"type": "inverse", "inner": {"type": "saturation", "lo": -1, "hi": 1}}"#,
    )
    .unwrap();
    let mut csv = String::from("x\n");
    for i in 0..n {
        csv.push_str(if i == bad_row - 1 { "5\n" } else { "0.5\n" });
    }
    let place = format!(
        "at sample {}: input `in.csv`, row {bad_row} (line {}), column `x` = 5",
        bad_row - 1,
        bad_row + 1
    );
    refused(tmp.path(), "an operator error", &csv, &[&place]);
}

// ----------------------------------------------------------------- figure

/// The `(x, y)` points of every polyline of the data's colour (the first
/// of the palette, `#0072B2`) in an SVG file, in pixels.
fn polylines(svg: &str) -> Vec<Vec<(f64, f64)>> {
    svg.match_indices("<polyline")
        .filter(|(i, _)| {
            svg[*i..]
                .split('>')
                .next()
                .unwrap()
                .contains("stroke=\"#0072B2\"")
        })
        .map(|(i, _)| {
            let rest = &svg[i..];
            let start = rest.find("points=\"").unwrap() + 8;
            let end = start + rest[start..].find('"').unwrap();
            rest[start..end]
                .split_whitespace()
                .map(|p| {
                    let (x, y) = p.split_once(',').unwrap();
                    (x.parse().unwrap(), y.parse().unwrap())
                })
                .collect()
        })
        .collect()
}

/// 400 000 samples of a slowly drifting loop (200 periods): the figure
/// draws a bounded number of points, and its extent (the extreme pixels
/// of the drawn line) is that of all the data.
#[test]
fn the_loop_figure_of_a_long_record_is_bounded_and_keeps_the_extremes() {
    let tmp = TempDir::new().unwrap();
    fs::write(tmp.path().join("m.json"), r#"{"type": "play", "r": 0.2}"#).unwrap();
    let n = 400_000;
    let mut csv = String::from("x\n");
    for i in 0..n {
        let th = i as f64 * 2.0 * std::f64::consts::PI / 2000.0;
        // amplitude creeping from 1 to 1.3, one sample sticking out
        let a = 1.0 + 0.3 * i as f64 / n as f64;
        let x = if i == 123_457 { 1.9 } else { a * th.sin() };
        csv.push_str(&format!("{x}\n"));
    }
    fs::write(tmp.path().join("in.csv"), &csv).unwrap();
    let (code, _, stderr) = simulate(tmp.path(), &["--plot", "loop.svg"]);
    assert_eq!(code, 0, "{stderr}");
    let svg = fs::read_to_string(tmp.path().join("loop.svg")).unwrap();
    assert_svg(&tmp.path().join("loop.svg"));
    let lines = polylines(&svg);
    assert!(!lines.is_empty());
    let total: usize = lines.iter().map(Vec::len).sum();
    assert!(
        total <= hysteron_cli::plot::MAX_LINE_POINTS + 1000,
        "{total} points drawn"
    );
    // (before: one polyline of 97 072 points, 780 kB)
    assert!(svg.len() < 300_000, "{} bytes", svg.len());
    // The extremes of the data (x = 1.9 at one sample, and x, y of the
    // outermost loop) are the extremes of the drawn line: compare with a
    // figure of just those points' bounding box drawn by the same code.
    let y: Vec<f64> = {
        let out = fs::read_to_string(tmp.path().join("out.csv")).unwrap();
        out.lines()
            .skip(1)
            .map(|l| l.rsplit(',').next().unwrap().parse().unwrap())
            .collect()
    };
    let x: Vec<f64> = csv.lines().skip(1).map(|l| l.parse().unwrap()).collect();
    let data = hysteron_cli::plot::loop_panel("t", "x", "y", &x, &y);
    let (x0, x1, y0, y1) = data.data_bounds().unwrap();
    assert_eq!(x1, 1.9);
    let mut corners = hysteron_cli::plot::loop_panel("t", "x", "y", &[x0, x1], &[y0, y1]);
    corners.x_range = Some(hysteron_cli::plot::padded(x0, x1));
    corners.y_range = Some(hysteron_cli::plot::padded(y0, y1));
    let reference = hysteron_cli::plot::render(&[corners], 1, 1, (760, 560)).unwrap();
    let extent = |lines: &[Vec<(f64, f64)>]| {
        lines
            .iter()
            .flatten()
            .fold((f64::MAX, f64::MIN, f64::MAX, f64::MIN), |b, p| {
                (b.0.min(p.0), b.1.max(p.0), b.2.min(p.1), b.3.max(p.1))
            })
    };
    let want = extent(&polylines(&reference));
    let got = extent(&lines);
    assert_eq!(got, want, "drawn extent vs the data's");
}
