//! The sample period comes from the structure above a node:
//! `SamplePeriod::set_sample_period` reaches every rate-dependent node, an
//! `oversample` of `q` sub-steps passes `dt / q`, and the period may change
//! from sample to sample.

use hysteron::models::Spec;
use hysteron::operators::{Error, Operator};
use std::path::Path;

/// The Bouc-Wen benchmark (Noël & Schoukens) as a spec: the published
/// oscillator with the hysteretic spring in its feedback path, run at 20
/// sub-steps per data sample. The oscillator's own `dt` is deliberately
/// wrong (1 s): the period must come from the tree.
const BENCHMARK: &str = r#"{
  "type": "oversample", "q": 20,
  "inner": {
    "type": "feedback",
    "forward": {"type": "mass_spring_damper", "m": 2, "c": 10, "k": 50000, "dt": 1},
    "back": {"type": "bouc_wen", "w": 0, "alpha": 50000, "beta": 800, "gamma": -1100,
             "n": 1, "stiffness": {"z": [0], "s": [1]}}
  }
}"#;

fn val_multisine() -> (Vec<f64>, Vec<f64>) {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("data/boucwen-benchmark/val_multisine.csv");
    let text = std::fs::read_to_string(path).unwrap();
    let mut u = Vec::new();
    let mut y = Vec::new();
    for line in text.lines().skip(1) {
        let v: Vec<f64> = line.split(',').map(|c| c.parse().unwrap()).collect();
        u.push(v[1]);
        y.push(v[2]);
    }
    (u, y)
}

fn rms(v: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = v.fold((0.0, 0), |(s, n), x| (s + x * x, n + 1));
    (s / n as f64).sqrt()
}

/// Three periods of `val_multisine` at 750 Hz through the oversampled
/// benchmark: the last period matches the published output to ≤ 1e-5 m
/// RMS (the output's own RMS is 6.7e-4 m). When the inner oscillator was
/// given the data period instead of `T / q`, the error was 7.7e-4 m.
#[test]
fn the_benchmark_oversampled_takes_its_period_from_the_tree() {
    let (u, y) = val_multisine();
    let n = u.len();
    let x: Vec<f64> = u.iter().cycle().take(3 * n).copied().collect();
    let spec = Spec::from_json(BENCHMARK).unwrap();
    assert!(spec.is_rate_dependent());

    let mut model = spec.build().unwrap();
    model.set_sample_period(1.0 / 750.0).unwrap();
    let out = model.run(&x).unwrap();
    let err = rms(out[2 * n..].iter().zip(&y).map(|(a, b)| a - b));
    assert!(err <= 1e-5, "rms error {err:e}");

    // the spec-level period gives the same bits
    let same = spec.with_dt(1.0 / 750.0).build().unwrap().run(&x).unwrap();
    assert_eq!(
        same.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
        out.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
    );

    // the data period given to the oscillator itself is the old error
    let wrong = Spec::from_json(&BENCHMARK.replace(r#""dt": 1"#, r#""dt": 0.0013333333333333333"#))
        .unwrap()
        .build()
        .unwrap()
        .run(&x)
        .unwrap();
    let err_wrong = rms(wrong[2 * n..].iter().zip(&y).map(|(a, b)| a - b));
    assert!(err_wrong > 1e-4, "rms error {err_wrong:e}");
}

/// A viscous damper `F = c (x_k − x_{k−1}) / dt_k` with a period set
/// before every sample, alone, inside an `oversample` (each sub-step sees
/// `dt / q` and a `1/q` of the increment: the same force), and under every
/// combinator that forwards the period.
#[test]
fn the_period_may_change_between_samples_and_reaches_every_node() {
    let xs = [0.1, 0.3, 0.2, 0.25, -0.05];
    let dts = [0.01, 0.02, 0.005, 0.04, 0.01];
    let c = 2.0;
    let mut prev = 0.0;
    let expected: Vec<f64> = xs
        .iter()
        .zip(&dts)
        .map(|(&x, &dt)| {
            let f = c * (x - prev) / dt;
            prev = x;
            f
        })
        .collect();
    let damper = r#"{"type": "viscous_damper", "c": 2, "dt": 1}"#;
    let wrap = |outer: &str| Spec::from_json(&outer.replace("D", damper)).unwrap();
    let trees = [
        (wrap("D"), 1.0),
        (wrap(r#"{"type": "oversample", "q": 4, "inner": D}"#), 1.0),
        (wrap(r#"{"type": "scaled", "w": 3, "inner": D}"#), 3.0),
        (
            wrap(r#"{"type": "cascade", "first": {"type": "gain", "k": 1}, "second": D}"#),
            1.0,
        ),
        (
            wrap(r#"{"type": "parallel", "left": D, "right": {"type": "gain", "k": 0}}"#),
            1.0,
        ),
    ];
    for (spec, scale) in &trees {
        let mut model = spec.build().unwrap();
        for (i, (&x, &dt)) in xs.iter().zip(&dts).enumerate() {
            model.set_sample_period(dt).unwrap();
            let y = model.trial(x).unwrap().output;
            model.commit();
            let want = scale * expected[i];
            assert!(
                (y - want).abs() <= 1e-12 * want.abs().max(1.0),
                "{}: sample {i}: {y} vs {want}",
                spec.describe()
            );
        }
    }
    // implicit combinators forward it too: a damper in a feedback loop with
    // a unit gain, y = F(x − y) solved each sample, changes with the period
    let fb = wrap(r#"{"type": "feedback", "forward": D, "back": {"type": "gain", "k": 1}}"#);
    let run_at = |dt: f64| {
        let mut m = fb.build().unwrap();
        m.set_sample_period(dt).unwrap();
        m.run(&[0.1]).unwrap()[0]
    };
    // y = (c/dt)(x − y) ⇒ y = x (c/dt) / (1 + c/dt)
    for dt in [0.01, 0.5] {
        let k = c / dt;
        assert!((run_at(dt) - 0.1 * k / (1.0 + k)).abs() < 1e-12);
    }
}

/// Every model checks the period, rate-dependent or not.
#[test]
fn a_bad_period_is_an_error_naming_dt() {
    for text in [
        r#"{"type": "play", "r": 0.1}"#,
        r#"{"type": "viscous_damper", "c": 2, "dt": 1}"#,
        r#"{"type": "oversample", "q": 3, "inner": {"type": "lugre", "sigma0": 1e4,
            "sigma1": 50, "sigma2": 0.4, "f_c": 1, "f_s": 1.5, "v_s": 0.01, "dt": 0.001}}"#,
    ] {
        let mut model = Spec::from_json(text).unwrap().build().unwrap();
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            match model.set_sample_period(bad) {
                Err(Error::InvalidParameter { name, .. }) => assert_eq!(name, "dt"),
                other => panic!("{text}: dt = {bad}: {other:?}"),
            }
        }
    }
}
