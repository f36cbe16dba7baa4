//! End-to-end tests of `hysteron sobol`: the table written is the
//! library's estimate for the same spec and input, bit for bit, and bad
//! input is one `error:` line naming the factor, with nothing written.

use hysteron::identify::sobol::{sobol, Factor, SobolOptions, Statistic};
use hysteron::models::Spec;
use tempfile::TempDir;

mod common;
use common::*;

const SPEC: &str = r#"{"type": "parallel",
  "left": {"type": "stop", "r": 0.5},
  "right": {"type": "gain", "k": 2.0}}"#;

/// A temp dir with `in.csv` (two sine cycles, column `x`) and
/// `model.json` (a stop beside a gain).
fn setup() -> (TempDir, Vec<f64>) {
    let s = TempDir::new().unwrap();
    let (text, x) = two_sine_cycles(200);
    s.write("in.csv", &text);
    s.write("model.json", SPEC);
    (s, x)
}

fn sobol_cmd(s: &TempDir, extra: &[&str]) -> assert_cmd::Command {
    let mut cmd = hysteron(s.dir());
    cmd.args(["sobol", "--model", "model.json", "--input", "in.csv"])
        .args(extra);
    cmd
}

#[test]
fn the_table_written_is_the_librarys_estimate() {
    let (s, x) = setup();
    for (statistic, name) in [(Statistic::Energy, "energy"), (Statistic::Peak, "peak")] {
        let report = succeeds_saying(
            &mut sobol_cmd(
                &s,
                &[
                    "--factor",
                    "r=0.3:0.7",
                    "--factor",
                    "right.gain.k=1.5:2.5",
                    "--statistic",
                    name,
                    "--samples",
                    "128",
                    "--seed",
                    "7",
                    "--output",
                    "out.csv",
                ],
            ),
            &[
                "Sobol indices",
                "128 base samples, 512 runs",
                "wrote out.csv",
            ],
        );
        let (headers, rows) = read_csv(&s.path().join("out.csv"));
        assert_eq!(headers, ["factor", "low", "high", "first", "total"]);
        let want = sobol(
            &Spec::from_json(SPEC).unwrap(),
            &x,
            &[Factor::new("r", 0.3, 0.7), Factor::new("k", 1.5, 2.5)],
            &statistic,
            &SobolOptions {
                samples: 128,
                seed: 7,
            },
        )
        .unwrap();
        assert_eq!(want.names, ["left.stop.r", "right.gain.k"]);
        for (i, row) in rows.iter().enumerate() {
            assert_eq!(row[0], want.names[i]);
            assert_eq!(row[3].parse::<f64>().unwrap(), want.first[i], "{name}");
            assert_eq!(row[4].parse::<f64>().unwrap(), want.total[i], "{name}");
            // the printed table shows the same row
            let shown = format!("| {:>8.4} | {:>8.4} |", want.first[i], want.total[i]);
            assert!(report.contains(&shown), "{shown} not in {report}");
        }
        assert_eq!(rows.len(), 2);
        // the gain's work over whole cycles closes to nothing: only the
        // stop's threshold moves the loop energy
        if name == "energy" {
            assert!(want.total[0] > 0.9 && want.total[1] < 0.05, "{want:?}");
        }
    }
}

#[test]
fn bad_factors_and_samples_are_one_line_errors_that_write_nothing() {
    let (s, _) = setup();
    let out = ["--output", "out.csv"];
    for (args, expect) in [
        (
            vec!["--factor", "f_c=1:2"],
            vec!["factor `f_c`", "left.stop.r"],
        ),
        (vec!["--factor", "r=0.7:0.3"], vec!["factor `r`: bounds"]),
        (
            vec!["--factor", "r=0.3:0.7", "--factor", "left.stop.r=0.1:0.2"],
            vec!["factor `left.stop.r`", "already the factor `r`"],
        ),
        (
            vec!["--factor", "r=0.3:0.7", "--samples", "100"],
            vec!["samples: 100", "power of two"],
        ),
        // a threshold below 0 is out of the stop's domain: the run names it
        (
            vec!["--factor", "r=-0.5:0.5"],
            vec!["run ", "left.stop.r = -"],
        ),
    ] {
        let mut cmd = sobol_cmd(&s, &args);
        cmd.args(out);
        fails_leaving_dir_unchanged(s.dir(), &mut cmd, &expect);
    }
    for (bad, expect) in [
        ("r", "NAME=LOW:HIGH"),
        ("r=1", "NAME=LOW:HIGH"),
        ("r=a:1", "`a` is not a number"),
    ] {
        usage_error(&mut sobol_cmd(&s, &["--factor", bad]), expect);
    }
    usage_error(
        &mut sobol_cmd(&s, &["--factor", "r=0:1", "--samples", "8"]),
        "at least 16",
    );
    usage_error(&mut sobol_cmd(&s, &[]), "--factor");
    let mut cmd = sobol_cmd(&s, &["--factor", "r=0.3:0.7", "--output", "in.csv"]);
    fails_leaving_dir_unchanged(s.dir(), &mut cmd, &["output"]);
}
