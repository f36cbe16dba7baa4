//! End-to-end tests of `hysteron sweep`: every set's column is what
//! `simulate` writes for a spec holding that set (on the lane kernel and
//! one instance at a time), a set out of its domain is reported and the
//! others run, and bad input is one `error:` line with nothing written.

use hysteron::models::Spec;
use std::fs;
use tempfile::TempDir;

mod common;
use common::*;

/// A temp dir with `in.csv` (two sine cycles, column `x`).
fn setup() -> TempDir {
    let s = TempDir::new().unwrap();
    s.write("in.csv", &two_sine_cycles(300).0);
    s
}

/// `sweep` of `model.json` (written from `spec`) over the sets of
/// `sets.csv` (written from `sets`): the report and the output CSV.
fn sweep(s: &TempDir, spec: &str, sets: &str) -> (String, Vec<String>, Vec<Vec<String>>) {
    s.write("model.json", spec);
    s.write("sets.csv", sets);
    let report = sweep_into(s, "out.csv");
    let (headers, rows) = read_csv(&s.path().join("out.csv"));
    (report, headers, rows)
}

/// `sweep` of the `model.json` and `sets.csv` in `s` into `output`: the
/// report.
fn sweep_into(s: &TempDir, output: &str) -> String {
    succeeds_saying(
        hysteron(s.dir()).args([
            "sweep",
            "--model",
            "model.json",
            "--params",
            "sets.csv",
            "--input",
            "in.csv",
            "--output",
            output,
        ]),
        &["parameter sets", &format!("wrote {output}")],
    )
}

/// The output column `simulate` writes for `spec`, as text.
fn simulated(s: &TempDir, spec: &Spec) -> Vec<String> {
    s.write("one.json", &spec.to_json_pretty().unwrap());
    let (headers, rows) = succeeds_writing_csv(
        hysteron(s.dir()).args([
            "simulate", "--model", "one.json", "--input", "in.csv", "--output", "one.csv",
        ]),
        &s.path().join("one.csv"),
    );
    let j = headers.iter().position(|h| h == "y").unwrap();
    rows.iter().map(|r| r[j].clone()).collect()
}

/// Each set's column, as written, against `simulate` of the spec with the
/// set's values (by `names`, full paths).
fn check_columns(s: &TempDir, spec: &Spec, names: &[&str], sets: &[Vec<f64>]) {
    let (_, headers, rows) = sweep(
        s,
        &spec.to_json_pretty().unwrap(),
        &std::iter::once(names.join(","))
            .chain(sets.iter().map(|v| {
                v.iter()
                    .map(|x| format!("{x:?}"))
                    .collect::<Vec<_>>()
                    .join(",")
            }))
            .collect::<Vec<_>>()
            .join("\n"),
    );
    let model = spec.build().unwrap();
    let all = model.param_names();
    for (i, set) in sets.iter().enumerate() {
        let mut p = model.params();
        for (name, v) in names.iter().zip(set) {
            p[all.iter().position(|n| n == name).unwrap()] = *v;
        }
        let want = simulated(s, &spec.with_params(&p).unwrap());
        let j = headers
            .iter()
            .position(|h| *h == format!("set_{}", i + 1))
            .unwrap();
        let got: Vec<String> = rows.iter().map(|r| r[j].clone()).collect();
        assert_eq!(got, want, "set {}", i + 1);
    }
}

#[test]
fn mms_sets_on_the_lane_kernel_are_each_simulate() {
    let s = setup();
    let spec = Spec::from_json(r#"{"type": "mms", "f_c": 1.0, "k": 20.0}"#).unwrap();
    let sets: Vec<Vec<f64>> = (0..11)
        .map(|i| vec![0.5 + 0.1 * i as f64, 5.0 + 9.0 * i as f64])
        .collect();
    check_columns(&s, &spec, &["f_c", "k"], &sets);
}

#[test]
fn paper_model_sets_one_at_a_time_are_each_simulate() {
    let s = setup();
    let spec = Spec::from_json(include_str!("../../examples/specs/paper.json")).unwrap();
    let names = spec.build().unwrap().param_names();
    let f_c = names.iter().find(|n| n.ends_with("f_c")).unwrap().clone();
    let sets: Vec<Vec<f64>> = [0.5, 1.0, 1.5].iter().map(|&v| vec![v]).collect();
    check_columns(&s, &spec, &[f_c.as_str()], &sets);
}

/// A set out of its domain gets NaN and a line naming it; the others run.
#[test]
fn a_failing_set_is_reported_and_the_others_run() {
    let s = setup();
    let (report, headers, rows) = sweep(&s, r#"{"type": "play", "r": 0.5}"#, "r\n0.1\n-0.2\n0.3\n");
    assert!(
        report.contains("ran 3 parameter sets (1 failed)"),
        "{report}"
    );
    assert!(
        report.contains("set_2 (params row 2) failed: invalid parameter `r`"),
        "{report}"
    );
    assert_eq!(headers, ["x", "set_1", "set_2", "set_3"]);
    assert!(rows
        .iter()
        .all(|r| r[2] == "NaN" && r[1] != "NaN" && r[3] != "NaN"));
}

/// Unknown names, bad numbers and an output over an input are refused
/// with one error line, writing nothing.
#[test]
fn bad_parameter_files_are_errors_that_write_nothing() {
    let s = setup();
    s.write("model.json", r#"{"type": "play", "r": 0.5}"#);
    let args_of = |model: &str, sets: &str, out: &str| {
        let mut cmd = hysteron(s.dir());
        let flags = [
            "--model", model, "--params", sets, "--input", "in.csv", "--output", out,
        ];
        cmd.arg("sweep").args(flags);
        cmd
    };
    let args = |sets: &str, out: &str| args_of("model.json", sets, out);
    s.write("unknown.csv", "q\n1\n");
    fails_leaving_dir_unchanged(
        s.dir(),
        &mut args("unknown.csv", "out.csv"),
        &["params `unknown.csv`: unknown parameter `q`"],
    );
    s.write("nan.csv", "r\n0.1\nnan\n");
    fails_leaving_dir_unchanged(
        s.dir(),
        &mut args("nan.csv", "out.csv"),
        &["params `nan.csv`, row 2", "column `r`", "not finite"],
    );
    s.write(
        "scaled.json",
        r#"{"type": "scaled", "w": 2, "inner": {"type": "play", "r": 0.5}}"#,
    );
    s.write("twice.csv", "r,inner.play.r\n0.1,0.2\n");
    fails_leaving_dir_unchanged(
        s.dir(),
        &mut args_of("scaled.json", "twice.csv", "out.csv"),
        &["params `twice.csv`: parameter `inner.play.r` is named by two columns"],
    );
    s.write("empty.csv", "r\n");
    fails_leaving_dir_unchanged(s.dir(), &mut args("empty.csv", "out.csv"), &["params"]);
    fails_leaving_dir_unchanged(
        s.dir(),
        &mut args("nan.csv", "nan.csv"),
        &["refusing to overwrite"],
    );
    assert!(!s.path().join("out.csv").exists());
    assert!(fs::read_to_string(s.path().join("nan.csv"))
        .unwrap()
        .contains("nan"));
}

/// An output named `.parquet` is a Parquet table with the CSV's column
/// names and the very bits the CSV's text reads back to (NaN for the set
/// that failed).
#[test]
fn a_parquet_output_holds_the_csv_columns_bit_for_bit() {
    use parquet::file::reader::{FileReader, SerializedFileReader};
    use parquet::record::Field;
    let s = setup();
    let (_, headers, rows) = sweep(
        &s,
        r#"{"type": "mms", "f_c": 1.0, "k": 20.0}"#,
        "f_c\n0.5\n-1\n1.5\n",
    );
    let report = sweep_into(&s, "out.parquet");
    assert!(report.contains("(1 failed)"), "{report}");
    let file = fs::File::open(s.path().join("out.parquet")).unwrap();
    let reader = SerializedFileReader::new(file).unwrap();
    let names: Vec<String> = reader
        .metadata()
        .file_metadata()
        .schema_descr()
        .columns()
        .iter()
        .map(|c| c.name().to_string())
        .collect();
    assert_eq!(names, headers);
    let mut n = 0;
    for (i, row) in reader.get_row_iter(None).unwrap().enumerate() {
        let row = row.unwrap();
        for (j, (_, field)) in row.get_column_iter().enumerate() {
            let Field::Double(v) = field else {
                panic!("row {i}, column {j}: {field:?} is not a double")
            };
            let want: f64 = rows[i][j].parse().unwrap();
            assert!(
                v.to_bits() == want.to_bits() || (v.is_nan() && want.is_nan()),
                "row {i}, column {j}: {v} in Parquet, {want} in the CSV"
            );
        }
        n += 1;
    }
    assert_eq!(n, rows.len());
    assert!(rows.iter().all(|r| r[2] == "NaN"));
}
