//! The analytic inverse of the Prandtl-Ishlinskii operator (Krejčí &
//! Kuhnen 2001): closed-form parameters, both compositions equal to the
//! identity from the first sample on (also with non-zero initial play
//! states), agreement with the generic numerical `Inverse`, typed errors,
//! and the `pi_inverse` spec.
//!
//! The property tests print the largest error they measured; run
//! `cargo test --test pi_inverse -- --nocapture` to see them
//! (`LAWS_CASES_FACTOR=k` multiplies the number of cases).

use hysteron::composition::PiBankParams;
use hysteron::models::Spec;
use hysteron::prelude::*;
use proptest::prelude::*;
use std::cell::Cell;

mod props;
use props::*;

const EPS: f64 = f64::EPSILON;

/// A piecewise-monotone signal from 0: ramps to random turning points in
/// `[−amp, amp]`, some exactly back to 0, some held.
fn signal(amp: f64) -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec((-1.0_f64..1.0, 1_usize..6, 0_u8..8), 1..12).prop_map(move |legs| {
        let mut xs = Vec::new();
        let mut x = 0.0;
        for (t, n, kind) in legs {
            let target = match kind {
                0 => 0.0,
                1 => x,
                _ => t * amp,
            };
            for k in 1..=n {
                xs.push(x + (target - x) * k as f64 / n as f64);
            }
            x = target;
        }
        xs
    })
}

/// A forward bank the analytic inverse accepts: `a0 > 0`, weights of
/// either sign (cumulative sums kept positive by the filter), some zero
/// and some repeated thresholds, and initial play states left by a random
/// history `0 → c1 → c2 → 0` (so they are reachable; sometimes none).
fn bank() -> impl Strategy<Value = PiBankParams<f64>> {
    let threshold = prop_oneof![1 => Just(0.0), 1 => Just(0.5), 6 => 0.0_f64..1.5];
    (
        0.2_f64..2.0,
        prop::collection::vec((threshold, -0.4_f64..2.0), 0..8),
        prop_oneof![
            1 => Just(None),
            3 => (-2.0_f64..2.0, -2.0_f64..2.0).prop_map(Some)
        ],
    )
        .prop_map(|(a0, plays, history)| {
            let r: Vec<f64> = plays.iter().map(|p| p.0).collect();
            let w: Vec<f64> = plays.iter().map(|p| p.1).collect();
            let y0 = match history {
                None => Vec::new(),
                Some((c1, c2)) => {
                    let mut b = PiBank::new(a0, r.clone(), w.clone()).expect("valid bank");
                    b.run(&[c1, c2, 0.0]).expect("finite");
                    b.play_outputs().to_vec()
                }
            };
            PiBankParams { a0, r, w, y0 }
        })
        .prop_filter("cumulative weights must be positive", |p| {
            PiInverse::from_params(p.clone()).is_ok()
        })
}

/// A [`bank`] and a [`signal`] scaled by an amplitude from `amplitude`.
fn bank_and_input(
    amplitude: impl Strategy<Value = f64>,
) -> impl Strategy<Value = (PiBankParams<f64>, Vec<f64>)> {
    (bank(), signal(1.0), amplitude)
        .prop_map(|(p, xs, amp)| (p, xs.iter().map(|x| x * amp).collect()))
}

/// The slopes `W_i = a0 + Σ_{r_j ≤ r_i} w_j` of the forward operator's
/// branches, one per distinct threshold (plays with equal thresholds act as
/// one, as the inverse merges them).
fn cumulative_weights(fwd: &PiBankParams<f64>) -> Vec<f64> {
    // The linear part (a0 and the zero-threshold plays) is the first slope.
    let mut w_cum = fwd.a0
        + fwd
            .r
            .iter()
            .zip(&fwd.w)
            .filter(|(&r, _)| r == 0.0)
            .map(|(_, &w)| w)
            .sum::<f64>();
    let mut out = vec![w_cum];
    let mut order: Vec<usize> = (0..fwd.r.len()).filter(|&j| fwd.r[j] > 0.0).collect();
    order.sort_by(|&a, &b| fwd.r[a].total_cmp(&fwd.r[b]));
    for (k, &j) in order.iter().enumerate() {
        w_cum += fwd.w[j];
        if order.get(k + 1).is_none_or(|&n| fwd.r[n] != fwd.r[j]) {
            out.push(w_cum);
        }
    }
    out
}

/// The error scale of one sample of `inverse(forward(x))`: the forward
/// output carries a rounding error of about `(m + 1) ε S_y`
/// (`S_y = |a0 x| + Σ |w_j p_j|`, the sum of the magnitudes it adds), the
/// inverse amplifies an input error by at most its Lipschitz constant
/// `1 / min_i W_i`, and adds its own `(m + 1) ε S_x` (`S_x` likewise for
/// the inverse bank, whose parameters are computed by `m`-term sums of the
/// same kind). Errors are reported in units of
/// `ε (m + 1) (S_y / W_min + S_x)`.
fn unit(fwd: &PiBankParams<f64>, inv: &PiBankParams<f64>, x: f64, y: f64) -> f64 {
    let m = fwd.r.len() as f64;
    let w_min = cumulative_weights(fwd)
        .into_iter()
        .fold(f64::INFINITY, f64::min);
    // |p_j| ≤ |x| + r_j + |y0_j| bounds every play output along the way.
    let s_y = fwd.a0.abs() * x.abs()
        + fwd
            .r
            .iter()
            .zip(&fwd.w)
            .enumerate()
            .map(|(j, (r, w))| w.abs() * (x.abs() + r + fwd.y0.get(j).map_or(0.0, |v| v.abs())))
            .sum::<f64>();
    let s_x = inv.a0.abs() * y.abs()
        + inv
            .r
            .iter()
            .zip(&inv.w)
            .zip(&inv.y0)
            .map(|((r, w), y0)| w.abs() * (y.abs() + r + y0.abs()))
            .sum::<f64>();
    EPS * (m + 1.0) * (s_y / w_min + s_x)
}

/// Tolerance in the units of [`unit`]: "a few ulps" times the condition.
const ULPS: f64 = 4.0;

/// The parameters of the bank that inverts `fwd` (its analytic inverse).
fn analytic_inverse_params(fwd: &PiBank<f64>) -> PiBankParams<f64> {
    fwd.analytic_inverse()
        .unwrap()
        .inverse_bank()
        .parameters()
        .clone()
}

#[test]
fn inverse_parameters_match_the_closed_form() {
    // a0 = 1, r = (1, 2), w = (1, 2): W = (1, 2, 4);
    // r' = (1·1, 1·1 + 2·1) = (1, 3); w' = (−1/(2·1), −2/(4·2)).
    let fwd = PiBank::new(1.0, vec![2.0, 1.0], vec![2.0, 1.0]).unwrap();
    let p = analytic_inverse_params(&fwd);
    assert_eq!(p.a0, 1.0);
    assert_eq!(p.r, vec![1.0, 3.0]);
    assert_eq!(p.w, vec![-0.5, -0.25]);
    assert_eq!(p.y0, vec![0.0, 0.0]);
    // Cumulative inverse weights are 1/W: 1, 1/2, 1/4.
    assert_eq!(p.a0 + p.w[0], 0.5);
    assert_eq!(p.a0 + p.w[0] + p.w[1], 0.25);

    // a0 merges with a zero threshold play, equal thresholds merge.
    let fwd = PiBank::new(-0.5, vec![0.0, 1.0, 1.0], vec![1.0, 0.5, 1.5]).unwrap();
    let p = analytic_inverse_params(&fwd);
    // w_0 = 0.5, one play r = 1 with w = 2: W = (0.5, 2.5).
    assert_eq!(
        (p.a0, p.r.clone(), p.w.clone()),
        (2.0, vec![0.5], vec![-1.6])
    );

    // Initial states: a0 = 1, r = (1, 2), w = (1, 2), y0 = (0.5, 1.5)
    // (left by the history 0 → 3.5 → −0.5 → 0: |0.5| ≤ 1, |1.5 − 0.5| ≤ 1).
    // ψ = (−0.5, −1.5), σ_1 = W_0 (ψ_1 − 0) = −0.5,
    // σ_2 = σ_1 + W_1 (ψ_2 − ψ_1) = −0.5 − 2 = −2.5,
    // Y0 = 1·0.5 + 2·1.5 = 3.5, y0' = Y0 − σ = (4, 6).
    let fwd = PiBank::from_params(PiBankParams {
        a0: 1.0,
        r: vec![1.0, 2.0],
        w: vec![1.0, 2.0],
        y0: vec![0.5, 1.5],
    })
    .unwrap();
    let p = analytic_inverse_params(&fwd);
    assert_eq!(p.y0, vec![4.0, 6.0]);
    // The first sample is inverted exactly.
    let mut f = fwd.clone();
    let mut i = fwd.analytic_inverse().unwrap();
    for x in [0.25_f64, 3.0, -4.0, 0.0] {
        let y = f.trial(x).unwrap().output;
        f.commit();
        let back = i.trial(y).unwrap().output;
        i.commit();
        assert!((back - x).abs() <= 1e-14, "{back} vs {x}");
    }
}

#[test]
fn inverse_then_forward_and_forward_then_inverse_are_the_identity() {
    let worst = Cell::new((0.0_f64, 0.0_f64, 0.0_f64));
    let max = measure(
        "pi_inverse: both compositions [units of ε (m+1) (S_y/W_min + S_x)]",
        512,
        bank_and_input(prop_oneof![Just(3.0), 0.01_f64..100.0]),
        |(p, xs)| {
            let fwd = ok(PiBank::from_params(p.clone()))?;
            let inv = ok(fwd.analytic_inverse())?;
            let ip = inv.inverse_bank().parameters().clone();
            // inverse ∘ forward
            let ys = ok(fwd.clone().run(&xs))?;
            let back = ok(inv.clone().run(&ys))?;
            // forward ∘ inverse (the inverse as a compensator before the plant)
            let us = ok(inv.clone().run(&xs))?;
            let again = ok(fwd.clone().run(&us))?;
            let mut e = 0.0_f64;
            let (mut a1, mut a2) = (0.0_f64, 0.0_f64);
            for i in 0..xs.len() {
                let e1 = (back[i] - xs[i]).abs();
                let e2 = (again[i] - xs[i]).abs();
                let u1 = unit(&p, &ip, xs[i], ys[i]);
                let u2 = unit(&p, &ip, us[i], xs[i]);
                prop_assert!(
                    e1 <= ULPS * u1,
                    "inverse(forward) sample {}: {:e} vs {:e} ({:.2} units)",
                    i,
                    back[i],
                    xs[i],
                    e1 / u1
                );
                prop_assert!(
                    e2 <= ULPS * u2,
                    "forward(inverse) sample {}: {:e} vs {:e} ({:.2} units)",
                    i,
                    again[i],
                    xs[i],
                    e2 / u2
                );
                a1 = a1.max(e1);
                a2 = a2.max(e2);
                e = e.max(e1 / u1).max(e2 / u2);
            }
            let w = worst.get();
            // relative to the largest value in the record (inputs or outputs)
            let scale = xs
                .iter()
                .chain(&ys)
                .chain(&us)
                .fold(f64::MIN_POSITIVE, |m, x| m.max(x.abs()));
            worst.set((w.0.max(a1 / scale), w.1.max(a2 / scale), w.2));
            Ok(e)
        },
    );
    let w = worst.get();
    eprintln!(
        "pi_inverse: relative to max(|x|, |y|, |u|): inverse(forward) {:.3e}, forward(inverse) {:.3e}",
        w.0, w.1
    );
    assert!(max <= ULPS);
}

/// The generic numerical inverse solves `P[u] = x` each sample from the
/// forward's committed state: the same operator, to its solver tolerance
/// (`rel_tol = 16 ε` of the bracket scale, the default), reported relative
/// to `max |u|`.
#[test]
fn agrees_with_the_numerical_inverse() {
    measure(
        "pi_inverse vs numerical Inverse [relative to max|u|]",
        256,
        bank_and_input(prop_oneof![Just(2.0), 0.1_f64..10.0]),
        |(p, xs)| {
            let fwd = ok(PiBank::from_params(p.clone()))?;
            let analytic = ok(ok(fwd.analytic_inverse())?.run(&xs))?;
            let numeric = ok(fwd.clone().inverse().run(&xs))?;
            let scale = analytic.iter().fold(1e-300_f64, |m, u| m.max(u.abs()));
            let ip = ok(PiInverse::from_params(p.clone()))?
                .inverse_bank()
                .parameters()
                .clone();
            let slopes = cumulative_weights(&p);
            let kappa = slopes.iter().fold(0.0_f64, |m, w| m.max(w.abs()))
                / slopes.iter().fold(f64::INFINITY, |m, &w| m.min(w));
            let mut e = 0.0_f64;
            for i in 0..xs.len() {
                let d = (analytic[i] - numeric[i]).abs();
                // The solver stops within 16 ε · max(|u|, |u_prev|) of a
                // root. That error is carried into the plays' memory, and a
                // later sample can see it amplified by the ratio of the
                // steepest to the flattest branch slope (seen: 8× after a
                // repeated input). The two inverses also round differently
                // (ULPS × condition, see `unit`).
                let tol = 64.0 * EPS * scale * kappa + ULPS * unit(&p, &ip, analytic[i], xs[i]);
                prop_assert!(
                    d <= tol,
                    "sample {}: analytic {:e}, numeric {:e}",
                    i,
                    analytic[i],
                    numeric[i]
                );
                e = e.max(d / scale);
            }
            Ok(e)
        },
    );
}

#[test]
fn non_invertible_banks_and_unreachable_states_are_typed_errors() {
    let name = |r: hysteron::Result<PiInverse<f64>>| match r {
        Err(Error::InvalidParameter { name, value, .. }) => (name, value),
        other => panic!("expected InvalidParameter, got {other:?}"),
    };
    // the analytic inverse of `PiBank::new(a0, r, w)`
    let bank_error =
        |a0: f64, r: Vec<f64>, w: Vec<f64>| name(PiBank::new(a0, r, w).unwrap().analytic_inverse());
    // a0 ≤ 0 and no zero threshold play
    assert_eq!(bank_error(0.0, vec![1.0], vec![1.0]), ("a0".into(), 0.0));
    // a0 + w of the zero threshold play ≤ 0
    assert_eq!(
        bank_error(0.5, vec![0.0, 1.0], vec![-1.0, 1.0]),
        ("a0".into(), -0.5)
    );
    // cumulative sum 1 + 1 − 3 = −1 at the third threshold (w[0], sorted last)
    assert_eq!(
        bank_error(1.0, vec![2.0, 1.0], vec![-3.0, 1.0]),
        ("w[0]".into(), -1.0)
    );
    // exactly zero is not invertible either (a flat branch)
    assert_eq!(bank_error(1.0, vec![1.0], vec![-1.0]), ("w[0]".into(), 0.0));
    let with_y0 = |r: Vec<f64>, y0: Vec<f64>| {
        let w = vec![1.0; r.len()];
        PiBank::from_params(PiBankParams { a0: 1.0, r, w, y0 })
            .unwrap()
            .analytic_inverse()
    };
    // |y0| > r: no history leaves a play outside [x − r, x + r] at x = 0
    assert_eq!(name(with_y0(vec![0.5], vec![0.6])), ("y0[0]".into(), 0.6));
    // neighbouring states further apart than their thresholds
    assert_eq!(
        name(with_y0(vec![1.0, 0.5], vec![-0.9, 0.5])),
        ("y0[0]".into(), -0.9)
    );
    // equal thresholds, different states
    assert_eq!(
        name(with_y0(vec![1.0, 1.0], vec![0.1, 0.2])),
        ("y0[1]".into(), 0.2)
    );
    // a zero threshold play's y0 never shows: accepted
    assert!(with_y0(vec![0.0, 1.0], vec![5.0, 0.5]).is_ok());
    // invalid forward parameters are the bank's errors
    assert_eq!(
        name(PiInverse::from_params(PiBankParams {
            a0: 1.0,
            r: vec![-1.0],
            w: vec![1.0],
            y0: vec![]
        })),
        ("r[0]".into(), -1.0)
    );
}

#[test]
fn parameters_are_the_forward_ones_and_set_params_is_atomic() {
    let fwd = PiBank::from_params(PiBankParams {
        a0: 0.5,
        r: vec![0.3, 0.0, 1.0],
        w: vec![1.0, 0.25, -0.5],
        y0: vec![0.1, 0.0, 0.4],
    })
    .unwrap();
    let mut inv = fwd.analytic_inverse().unwrap();
    assert_eq!(inv.params(), fwd.params());
    assert_eq!(inv.param_names(), fwd.param_names());
    assert_eq!(inv.param_domains(), fwd.param_domains());
    assert_eq!(inv.name(), "pi_inverse");

    // A non-invertible vector (cumulative 0.75 + 1 − 2 < 0) leaves it unchanged.
    let before = inv.clone();
    let mut bad = fwd.params();
    bad[6] = -2.0;
    assert!(matches!(
        inv.set_params(&bad),
        Err(Error::InvalidParameter { ref name, .. }) if name == "w[2]"
    ));
    assert_eq!(inv, before);

    // Setting the forward parameters rebuilds the inverse of that bank.
    let mut p = fwd.params();
    p[0] = 2.0;
    inv.set_params(&p).unwrap();
    let mut f2 = fwd.clone();
    f2.set_params(&p).unwrap();
    assert_eq!(inv, f2.analytic_inverse().unwrap());
    // An omitted y0 reads as zeros.
    let plain = PiBank::new(1.0, vec![0.5], vec![1.0]).unwrap();
    assert_eq!(
        plain.analytic_inverse().unwrap().params(),
        vec![1.0, 0.5, 1.0, 0.0]
    );
}

#[test]
fn works_in_f32() {
    let fwd = PiBank::new(0.5_f32, vec![0.0, 0.2, 0.6], vec![1.0, 0.5, -0.2]).unwrap();
    let mut inv = fwd.analytic_inverse().unwrap();
    let xs: Vec<f32> = (0..200).map(|i| (i as f32 * 0.07).sin() * 1.3).collect();
    let ys = fwd.clone().run(&xs).unwrap();
    let back = inv.run(&ys).unwrap();
    let e = xs
        .iter()
        .zip(&back)
        .fold(0.0_f32, |m, (a, b)| m.max((a - b).abs()));
    // condition: S_y/W_min ≈ (0.5 + 1 + 0.5 + 0.2)·2/1.5, (m+1) = 4,
    // 4 ulps of f32 (1.2e-7) → ~1e-5
    assert!(e < 1e-5, "{e}");
}

#[test]
fn pi_inverse_spec_builds_the_analytic_inverse() {
    let json = r#"{"type": "pi_inverse", "a0": 0.2, "r": [0.0, 0.3, 0.7],
        "w": [1.0, 0.5, 0.25], "y0": [0.0, 0.1, 0.2]}"#;
    let spec = Spec::from_json(json).unwrap();
    assert_eq!(spec.kind(), "pi_inverse");
    assert_eq!(
        Spec::from_json(&spec.to_json_pretty().unwrap()).unwrap(),
        spec
    );
    let mut model = spec.build().unwrap();
    let fwd = PiBank::from_params(PiBankParams {
        a0: 0.2,
        r: vec![0.0, 0.3, 0.7],
        w: vec![1.0, 0.5, 0.25],
        y0: vec![0.0, 0.1, 0.2],
    })
    .unwrap();
    let mut direct = fwd.analytic_inverse().unwrap();
    let xs: Vec<f64> = (0..100).map(|i| 2.0 * (i as f64 * 0.1).sin()).collect();
    let a = model.run(&xs).unwrap();
    let b = direct.run(&xs).unwrap();
    assert_eq!(
        a.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
        b.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
    );
    // spec.with_params round-trips and keeps the variant
    assert_eq!(spec.with_params(&model.params()).unwrap(), spec);
    // a cascade of the spec'd inverse and the bank is the identity
    let cascade = format!(
        r#"{{"type": "cascade", "first": {json}, "second": {}}}"#,
        json.replace("pi_inverse", "pi_bank")
    );
    let mut id = Spec::from_json(&cascade).unwrap().build().unwrap();
    let out = id.run(&xs).unwrap();
    for (x, y) in xs.iter().zip(&out) {
        assert!((x - y).abs() < 1e-14, "{x} {y}");
    }
    // errors name the path
    let bad = r#"{"type": "scaled", "w": 2, "inner": {"type": "pi_inverse", "a0": 1,
        "r": [1.0], "w": [-1.5]}}"#;
    let e = Spec::from_json(bad).unwrap().build().unwrap_err();
    assert!(
        e.to_string().starts_with("scaled.inner.pi_inverse.w[0]"),
        "{e}"
    );
}

/// The inverse's parameters are the forward ones, so fitting the inverse
/// as a compensator (input: the measured output `y`, target: the input
/// `x` that produced it) identifies the forward model.
#[test]
fn fitting_the_inverse_identifies_the_forward_model() {
    use hysteron::identify::{fit, FitOptions};
    let truth = PiBank::new(0.5, vec![0.2, 0.5, 0.9], vec![0.8, 0.4, 0.2]).unwrap();
    let x: Vec<f64> = (0..600)
        .map(|i| {
            let t = i as f64 / 100.0;
            (0.3 + 0.25 * t) * (std::f64::consts::TAU * t).sin()
        })
        .collect();
    let y = truth.clone().run(&x).unwrap();
    // start: a0 and weights off by 20–40 %, thresholds known
    let start = PiBank::new(0.4, vec![0.2, 0.5, 0.9], vec![1.1, 0.3, 0.28])
        .unwrap()
        .analytic_inverse()
        .unwrap();
    let free = [0, 4, 5, 6]; // a0, w[0], w[1], w[2]
    let fitted = fit(&start, &y, &x, &free, &FitOptions::default()).unwrap();
    let p = fitted.model.params();
    let t = truth.params();
    eprintln!("fitted forward parameters through the inverse: {p:?}");
    for i in free {
        assert!(
            (p[i] - t[i]).abs() < 1e-8,
            "parameter {i}: {} vs {}",
            p[i],
            t[i]
        );
    }
}
