//! End-to-end tests of uncertainty bands: `fit --band` and `--covariance`,
//! `validate --covariance`, and their bad options (one line on stderr,
//! exit code 1, nothing written).

use hysteron::identify::band::{predict_band, BandMethod, Covariance};
use hysteron::models::Spec;
use hysteron::Operator;
use rand::{rngs::StdRng, SeedableRng};
use rand_distr::{Distribution, Normal};
use std::fs;
use std::path::Path;
use tempfile::TempDir;

mod common;
use common::*;

/// `y = k₁·play_r(x) + k₀·x`.
const TRUTH: &str = r#"{"type": "parallel",
  "left": {"type": "cascade", "first": {"type": "play", "r": 0.4},
           "second": {"type": "gain", "k": 1.5}},
  "right": {"type": "gain", "k": 0.8}}"#;

const START: &str = r#"{"type": "parallel",
  "left": {"type": "cascade", "first": {"type": "play", "r": 0.5},
           "second": {"type": "gain", "k": 1.8}},
  "right": {"type": "gain", "k": 1.0}}"#;

const FREE: &str = "play.r,second.gain.k,right.gain.k";

/// `data.csv` (x, F: the truth with 5 % Gaussian noise, seeded) and
/// `valid.csv` (another input, noise-free) over `n` samples, and the
/// start spec.
fn setup(n: usize) -> (TempDir, Vec<f64>) {
    let tmp = TempDir::new().unwrap();
    let truth = Spec::from_json(TRUTH).unwrap();
    let noise = Normal::new(0.0, 0.05).unwrap();
    let mut rng = StdRng::seed_from_u64(17);
    let write = |name: &str, x: &[f64], noisy: bool, rng: &mut StdRng| {
        let y = truth.build().unwrap().run(x).unwrap();
        let mut text = String::from("x,F\n");
        for (a, b) in x.iter().zip(&y) {
            let e = if noisy { noise.sample(rng) } else { 0.0 };
            text.push_str(&format!("{a},{}\n", b + e));
        }
        fs::write(tmp.path().join(name), text).unwrap();
    };
    let x: Vec<f64> = (0..n)
        .map(|i| {
            let t = i as f64 / n as f64;
            2.0 * (-t).exp() * (std::f64::consts::TAU * 3.0 * t + 0.3).sin()
        })
        .collect();
    write("data.csv", &x, true, &mut rng);
    let v: Vec<f64> = (0..n)
        .map(|i| 1.5 * (std::f64::consts::TAU * 2.0 * i as f64 / n as f64 + 0.2).sin())
        .collect();
    write("valid.csv", &v, false, &mut rng);
    fs::write(tmp.path().join("start.json"), START).unwrap();
    (tmp, x)
}

/// `fit` of the start spec to `data.csv`, writing `fitted.json`; each
/// test adds its own options.
const FIT: [&str; 12] = [
    "fit",
    "--model",
    "start.json",
    "--data",
    "data.csv",
    "--output-column",
    "F",
    "--free",
    FREE,
    "--output",
    "fitted.json",
    "--no-progress",
];

/// The records of [`setup`], and the start spec fitted to `data.csv`
/// ([`FIT`] with the `extra` options).
fn fitted(n: usize, extra: &[&str]) -> (TempDir, Vec<f64>) {
    let (tmp, x) = setup(n);
    hysteron(tmp.path())
        .args(FIT)
        .args(extra)
        .assert()
        .success();
    (tmp, x)
}

/// The band file holds the band the library gives for the fitted spec
/// and the covariance file, bit for bit; the fitted output is the spec's.
#[test]
fn fit_writes_the_band_and_the_covariance() {
    let (tmp, x) = fitted(300, &["--band", "band.csv", "--covariance", "cov.json"]);
    let dir = tmp.path();
    let (headers, rows) = read_csv(&dir.join("band.csv"));
    assert_eq!(headers, ["x", "output", "lower", "upper"]);
    assert_eq!(rows.len(), x.len());
    let col = |name: &str| column(&headers, &rows, name);
    let (out, lo, hi) = (col("output"), col("lower"), col("upper"));

    let model = Spec::from_json_file(dir.join("fitted.json"))
        .unwrap()
        .build()
        .unwrap();
    let cov: Covariance =
        serde_json::from_str(&fs::read_to_string(dir.join("cov.json")).unwrap()).unwrap();
    assert_eq!(cov.names.len(), 3);
    let band = predict_band(model.as_ref(), &cov, &x, 0.95, BandMethod::Linearized).unwrap();
    assert_eq!(out, band.output);
    assert_eq!(lo, band.lower);
    assert_eq!(hi, band.upper);
    assert!(lo.iter().zip(&hi).all(|(l, h)| l < h));

    // Monte Carlo, another level: its own band, around the same output
    hysteron(dir)
        .args(FIT)
        .args(["--band", "mc.csv", "--band-method", "monte_carlo"])
        .args(["--band-level", "0.9", "--band-draws", "500"])
        .args(["--band-seed", "3"])
        .assert()
        .success();
    let (h2, r2) = read_csv(&dir.join("mc.csv"));
    assert_eq!(column(&h2, &r2, "output"), out);
    let want = predict_band(
        model.as_ref(),
        &cov,
        &x,
        0.9,
        BandMethod::MonteCarlo {
            draws: 500,
            seed: 3,
        },
    )
    .unwrap();
    assert_eq!(column(&h2, &r2, "lower"), want.lower);
    assert_eq!(column(&h2, &r2, "upper"), want.upper);
}

/// Bad band options: clear one-line errors, nothing written.
#[test]
fn bad_band_options_are_refused() {
    let (tmp, _) = setup(120);
    let dir = tmp.path();
    let band = |option: &str, value: &str| {
        let mut cmd = hysteron(dir);
        cmd.args(FIT).args(["--band", "band.csv", option, value]);
        cmd
    };
    for level in ["1", "0", "-0.5", "nan", "ninety"] {
        let before = snapshot(dir);
        usage_error(&mut band("--band-level", level), "--band-level");
        assert_eq!(snapshot(dir), before);
    }
    usage_error(&mut band("--band-method", "bootstrap"), "monte_carlo");
    usage_error(&mut band("--band-draws", "0"), "--band-draws");
    // too few draws for the level: after the fit, before any file
    fails_leaving_dir_unchanged(
        dir,
        band("--band-draws", "10").args(["--band-method", "monte_carlo"]),
        &["--band: only 10 of 10 draws ran", "needs at least 40"],
    );
    // the band may not overwrite an input
    fails_leaving_dir_unchanged(
        dir,
        hysteron(dir).args(FIT).args(["--band", "data.csv"]),
        &["band", "data.csv"],
    );
}

/// `validate` of a spec on `valid.csv` (the spec, `--model SPEC`, and
/// the options follow).
const VALIDATE: [&str; 5] = ["validate", "--data", "valid.csv", "--output-column", "F"];

/// `validate --covariance` draws the band in the record's figure; it
/// needs `--plot`, and a covariance of the model's fit.
#[test]
fn validate_draws_the_band_of_the_fit() {
    let (tmp, _) = fitted(200, &["--covariance", "cov.json"]);
    let dir = tmp.path();
    let validate = |model: &str, covariance: &str| {
        let mut cmd = hysteron(dir);
        cmd.args(VALIDATE)
            .args(["--model", model, "--covariance", covariance]);
        cmd
    };
    validate("fitted.json", "cov.json")
        .args(["--plot", "figs"])
        .assert()
        .success();
    let svg = fs::read_to_string(dir.join("figs/valid.svg")).unwrap();
    assert!(
        svg.contains("95 % band (linearized)"),
        "no band in the figure"
    );
    validate("fitted.json", "cov.json")
        .args(["--plot", "mc", "--band-method", "monte_carlo"])
        .args(["--band-level", "0.8"])
        .assert()
        .success();
    let svg = fs::read_to_string(dir.join("mc/valid.svg")).unwrap();
    assert!(svg.contains("80 % band (monte_carlo)"));

    fails_leaving_dir_unchanged(
        dir,
        &mut validate("fitted.json", "cov.json"),
        &["--covariance", "--plot"],
    );
    // the covariance of another model's values
    fails_leaving_dir_unchanged(
        dir,
        validate("start.json", "cov.json").args(["--plot", "other"]),
        &["cov.json", "left.cascade.first.play.r", "fitted spec"],
    );
    fs::write(dir.join("bad.json"), "{\"names\": [1]}").unwrap();
    fails_leaving_dir_unchanged(
        dir,
        validate("fitted.json", "bad.json").args(["--plot", "b"]),
        &["--covariance `bad.json`"],
    );
    assert!(!Path::new(&dir.join("b")).exists());
}
