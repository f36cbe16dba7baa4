//! End-to-end tests of `hysteron compare` on synthetic records made here
//! from a known structure (MMS friction) with noise: the true structure
//! ranks first by BIC, an over-parameterized one (the same plus a spring
//! in parallel) shows no significant held-out gain, a wrong one (an
//! elastoplastic element) ranks last; a candidate that fails is reported
//! in its row while the others go on; a malformed candidates file is an
//! error naming it.

use hysteron::operators::Mms;
use hysteron::Operator;
use rand::rngs::StdRng;
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use std::fs;
use std::path::Path;
use tempfile::TempDir;

mod common;
use common::*;

/// A record of the true structure, `mms(f_c = 1.5, k = 20)`, over a sine of
/// amplitude `a` with `cycles` periods, plus noise of σ = 0.03.
fn record(dir: &Path, name: &str, a: f64, cycles: f64, rng: &mut StdRng) {
    let x: Vec<f64> = (0..1500)
        .map(|i| a * (std::f64::consts::TAU * cycles * i as f64 / 1500.0).sin())
        .collect();
    let y = Mms::new(1.5, 20.0).unwrap().run(&x).unwrap();
    let noise = Normal::new(0.0, 0.03).unwrap();
    let mut text = String::from("x,F\n");
    for (xi, yi) in x.iter().zip(&y) {
        text.push_str(&format!("{xi},{}\n", yi + noise.sample(rng)));
    }
    fs::write(dir.join(name), text).unwrap();
}

fn candidates(dir: &Path, extra: &str) {
    fs::create_dir_all(dir.join("specs")).unwrap();
    fs::write(
        dir.join("specs/mms.json"),
        r#"{"type": "mms", "f_c": 1.0, "k": 10.0}"#,
    )
    .unwrap();
    fs::write(
        dir.join("specs/mms-spring.json"),
        r#"{"type": "parallel", "left": {"type": "mms", "f_c": 1.0, "k": 10.0}, "right": {"type": "gain", "k": 0.1}}"#,
    )
    .unwrap();
    fs::write(
        dir.join("specs/elastoplastic.json"),
        r#"{"type": "elastoplastic", "k": 10.0, "f_b": 1.0}"#,
    )
    .unwrap();
    fs::write(
        dir.join("candidates.json"),
        format!(
            r#"{{"candidates": [
                {{"name": "elastoplastic", "model": "specs/elastoplastic.json", "free": ["k", "f_b"]}},
                {{"name": "mms-spring", "model": "specs/mms-spring.json", "free": ["f_c", "left.mms.k", "right.gain.k"]}},
                {{"name": "mms", "model": "specs/mms.json", "free": ["f_c", "k"]}}{extra}
            ]}}"#
        ),
    )
    .unwrap();
}

fn records(dir: &Path) -> (Vec<String>, Vec<String>) {
    let mut rng = StdRng::seed_from_u64(0x5EED_C0DE);
    let mut train = Vec::new();
    for (i, (a, c)) in [(1.0, 2.0), (0.3, 3.0)].iter().enumerate() {
        let name = format!("train{i}.csv");
        record(dir, &name, *a, *c, &mut rng);
        train.push(name);
    }
    let mut validate = Vec::new();
    for (i, (a, c)) in [
        (0.5, 2.0),
        (0.8, 1.0),
        (0.2, 4.0),
        (1.2, 2.0),
        (0.6, 3.0),
        (0.4, 1.0),
    ]
    .iter()
    .enumerate()
    {
        let name = format!("val{i}.csv");
        record(dir, &name, *a, *c, &mut rng);
        validate.push(name);
    }
    (train, validate)
}

/// `compare` of the candidates in `candidates.json` (fitted into
/// `fitted/`) on the `train` and `validate` records.
fn compare_cmd(dir: &Path, train: &[String], validate: &[String]) -> assert_cmd::Command {
    let mut cmd = hysteron(dir);
    cmd.args([
        "compare",
        "--candidates",
        "candidates.json",
        "--work-dir",
        "fitted",
    ]);
    for t in train {
        cmd.args(["--train", t]);
    }
    for v in validate {
        cmd.args(["--validate", v]);
    }
    cmd
}

/// [`compare_cmd`] run, writing `table.csv` and `table.svg`.
fn compare(dir: &Path, train: &[String], validate: &[String]) -> assert_cmd::assert::Assert {
    compare_cmd(dir, train, validate)
        .args(["--csv", "table.csv", "--plot", "table.svg"])
        .assert()
}

/// What a successful `compare` reports: its standard output and the
/// header and rows of `table.csv`.
struct Table {
    report: String,
    headers: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    /// Checks that the run succeeded; reads `table.csv` in `dir`.
    fn of(dir: &Path, run: assert_cmd::assert::Assert) -> Table {
        let report = stdout_of(&run.success());
        let (headers, rows) = read_csv(&dir.join("table.csv"));
        Table {
            report,
            headers,
            rows,
        }
    }

    /// The index of the column `name`.
    fn col(&self, name: &str) -> usize {
        self.headers.iter().position(|h| h == name).unwrap()
    }

    /// The first row whose column `name` holds `value`.
    fn row_with(&self, name: &str, value: &str) -> &[String] {
        let c = self.col(name);
        self.rows.iter().find(|r| r[c] == value).unwrap()
    }

    /// The column `name` of the candidate `cand`'s row.
    fn get(&self, cand: &str, name: &str) -> &str {
        &self.row_with("candidate", cand)[self.col(name)]
    }
}

/// A temporary directory holding the records and the candidates (with
/// `extra` ones): the directory and the training and validation records.
fn setup(extra: &str) -> (TempDir, Vec<String>, Vec<String>) {
    let tmp = TempDir::new().unwrap();
    let (train, validate) = records(tmp.path());
    candidates(tmp.path(), extra);
    (tmp, train, validate)
}

#[test]
fn the_true_structure_wins_by_bic_and_the_richer_one_gains_nothing_real() {
    let (tmp, train, validate) = setup("");
    let t = Table::of(tmp.path(), compare(tmp.path(), &train, &validate));
    let table = &t.report;
    assert_eq!(t.rows.len(), 3, "{table}");
    let bic = |cand: &str| t.get(cand, "bic").parse::<f64>().unwrap();
    // BIC: the true structure first, the over-parameterized one pays for
    // its parameter, the wrong one last
    assert!(bic("mms") < bic("mms-spring"), "{table}");
    assert!(bic("mms-spring") < bic("elastoplastic"), "{table}");
    // k and n as fitted
    assert_eq!(t.get("mms", "k"), "2");
    assert_eq!(t.get("mms-spring", "k"), "3");
    assert_eq!(t.get("mms", "n"), "3000");
    // the wrong structure ranks last on held-out data, significantly
    // behind the rank before it (6 of 6 records: p = 2/64)
    assert_eq!(t.get("elastoplastic", "rank"), "3", "{table}");
    // whichever of the two MMS candidates ranks first, its gain over the
    // other on held-out records is not significant at 5 %
    let first = t.row_with("rank", "1");
    assert!(first[t.col("candidate")].starts_with("mms"), "{table}");
    let p: f64 = first[t.col("p_vs_next")].parse().unwrap();
    assert!(p > 0.05, "p = {p}: {table}");
    let second = t.row_with("rank", "2");
    let p_last: f64 = second[t.col("p_vs_next")].parse().unwrap();
    assert!((p_last - 2.0 / 64.0).abs() < 1e-12, "{table}");
    // the fitted specs are written, and the true one recovers f_c
    let fitted = fs::read_to_string(tmp.path().join("fitted/mms.json")).unwrap();
    let spec: serde_json::Value = serde_json::from_str(&fitted).unwrap();
    let f_c = spec["f_c"].as_f64().unwrap();
    assert!((f_c - 1.5).abs() < 0.02, "{f_c}");
    assert!(table.contains("| rank | candidate | k |"), "{table}");
    assert_svg(&tmp.path().join("table.svg"));
    assert_no_temp_files(tmp.path());
}

#[test]
fn a_failing_candidate_is_reported_in_its_row_and_the_others_go_on() {
    let (tmp, train, validate) =
        setup(r#", {"name": "typo", "model": "specs/mms.json", "free": ["f_k"]}"#);
    let t = Table::of(tmp.path(), compare(tmp.path(), &train[..1], &validate[..2]));
    let typo = t.row_with("candidate", "typo");
    assert_eq!(typo[t.col("rank")], "");
    assert!(typo[t.col("error")].contains("f_k"), "{:?}", typo);
    assert!(t.report.contains("failed"), "{}", t.report);
    let rank = t.col("rank");
    let ranked = t.rows.iter().filter(|r| !r[rank].is_empty()).count();
    assert_eq!(ranked, 3);
}

#[test]
fn a_malformed_candidates_file_is_an_error_naming_it() {
    let tmp = TempDir::new().unwrap();
    let (train, validate) = records(tmp.path());
    for (text, expect) in [
        ("{", "candidates.json"),
        (r#"{"candidates": []}"#, "at least two candidates"),
        (
            r#"{"candidates": [{"name": "a", "model": "m.json", "free": ["k"]}, {"name": "a", "model": "m.json", "free": ["k"]}]}"#,
            "`a` is used twice",
        ),
        (
            r#"{"candidates": [{"name": "a b", "model": "m.json", "free": ["k"]}, {"name": "c", "model": "m.json", "free": ["k"]}]}"#,
            "candidates[0].name",
        ),
        (
            r#"{"candidates": [{"name": "a", "model": "m.json", "free": []}, {"name": "c", "model": "m.json", "free": ["k"]}]}"#,
            "candidates[0].free",
        ),
        (
            r#"{"candidates": [{"name": "a", "model": "m.json", "free": ["k"], "fre": 1}]}"#,
            "unknown field",
        ),
    ] {
        fs::write(tmp.path().join("candidates.json"), text).unwrap();
        let out = compare(tmp.path(), &train, &validate).code(1);
        let err = String::from_utf8_lossy(&out.get_output().stderr).into_owned();
        assert!(err.contains(expect), "{text}: {err}");
        assert!(!tmp.path().join("table.csv").exists());
        assert!(!tmp.path().join("table.svg").exists());
    }
}

#[test]
fn cross_validation_scores_every_record_from_the_fit_without_it() {
    let (tmp, train, validate) = setup("");
    let all: Vec<String> = train.iter().chain(&validate).cloned().collect();
    let t = Table::of(
        tmp.path(),
        compare_cmd(tmp.path(), &all, &[])
            .args(["--cross-validate", "4", "--csv", "table.csv"])
            .assert(),
    );
    let table = &t.report;
    // every one of the 8 records held out once: the wrong structure loses
    // on all of them (p = 2/2^8 against the rank before it)
    assert_eq!(t.get("elastoplastic", "rank"), "3", "{table}");
    let second = t.row_with("rank", "2");
    let p: f64 = second[t.col("p_vs_next")].parse().unwrap();
    assert!((p - 2.0 / 256.0).abs() < 1e-12, "{table}");
    // training figures from the fit on all 8 records
    assert_eq!(t.get("mms", "n"), "12000");
    for fold in 1..=4 {
        assert!(tmp
            .path()
            .join(format!("fitted/mms.fold{fold}.json"))
            .exists());
    }
    assert!(!tmp.path().join("fitted/mms.fold5.json").exists());
}

#[test]
fn cross_validation_needs_folds_that_fit_the_records() {
    let (tmp, train, validate) = setup("");
    for (k, with_validate, expect) in [
        ("1", false, "at least 2"),
        ("3", false, "at most the 2 --train records"),
        ("2", true, "give no --validate"),
    ] {
        let validate = if with_validate { &validate[..1] } else { &[] };
        let out = compare_cmd(tmp.path(), &train, validate)
            .args(["--cross-validate", k])
            .assert()
            .code(1);
        let err = String::from_utf8_lossy(&out.get_output().stderr).into_owned();
        assert!(err.contains(expect), "K = {k}: {err}");
    }
}
