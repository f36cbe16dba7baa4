//! Bad parameters and bad inputs get typed errors naming the field, never a
//! panic or a NaN; valid-but-unusual settings are accepted.

use hysteron::composition::PiBankParams;
use hysteron::operators::{DeadZoneParams, SaturationParams, StopParams};
use hysteron::prelude::*;

/// Asserts an `InvalidParameter` error naming `field`.
fn names<T: std::fmt::Debug>(r: Result<T>, field: &str) {
    match r {
        Err(Error::InvalidParameter { name, .. }) => assert_eq!(name, field),
        other => panic!("expected InvalidParameter for `{field}`, got {other:?}"),
    }
}

fn bw(w: f64, n: f64, z: Vec<f64>, s: Vec<f64>) -> Result<BoucWen<f64>> {
    BoucWen::from_params(BoucWenParams {
        w,
        alpha: 1.0,
        beta: 0.5,
        gamma: 0.5,
        n,
        h0: 0.0,
        z0: 0.0,
        stiffness: StiffnessMap::new(z, s)?,
    })
}

#[test]
fn invalid_parameters_name_the_field() {
    names(Play::new(-0.1), "r");
    names(Play::new(f64::NAN), "r");
    names(
        Play::from_params(PlayParams {
            r: 1.0,
            y0: f64::INFINITY,
        }),
        "y0",
    );
    names(Stop::from_params(StopParams { r: -1.0, s0: 0.0 }), "r");
    names(ElastoPlastic::new(0.0, 1.0), "k");
    names(ElastoPlastic::new(1.0, -1.0), "f_b");
    names(
        DeadZone::from_params(DeadZoneParams { b_l: 0.1, b_r: 1.0 }),
        "b_l",
    );
    names(DeadZone::new(-1.0, -0.1), "b_r");
    names(
        Saturation::from_params(SaturationParams { lo: 1.0, hi: 1.0 }),
        "hi",
    );
    names(Saturation::new(2.0, 1.0), "hi");
    names(Saturation::new(f64::NEG_INFINITY, 1.0), "lo");
    names(Gain::new(f64::NAN), "k");
    names(Mms::new(0.0, 1.0), "f_c");
    names(Mms::new(1.0, -2.0), "k");
    names(Mms::new(f64::NAN, 1.0), "f_c");
    names(bw(1.5, 1.0, vec![0.0], vec![1.0]), "w");
    names(bw(-0.1, 1.0, vec![0.0], vec![1.0]), "w");
    names(bw(0.5, 0.9, vec![0.0], vec![1.0]), "n");
    names(bw(0.5, f64::NAN, vec![0.0], vec![1.0]), "n");
    names(
        StiffnessMap::new(vec![0.0, 1.0, 0.5], vec![1.0, 1.0, 1.0]),
        "z[2]",
    );
    names(StiffnessMap::new(vec![0.0, 1.0], vec![1.0, -1.0]), "s[1]");
    names(StiffnessMap::new(vec![-1.0, 1.0], vec![1.0, 1.0]), "z[0]");
    names(StiffnessMap::<f64>::new(vec![], vec![]), "knots");
    names(StiffnessMap::new(vec![0.0, 1.0], vec![1.0]), "knots");
    names(PiBank::new(0.0, vec![0.0, -0.5], vec![1.0, 1.0]), "r[1]");
    names(PiBank::new(0.0, vec![0.0], vec![1.0, 1.0]), "w");
    names(
        PiBank::from_params(PiBankParams {
            a0: 1.0,
            r: vec![1.0],
            w: vec![f64::NAN],
            y0: vec![],
        }),
        "w[0]",
    );
    names(Play::new(0.1).unwrap().scaled(f64::INFINITY), "w");
    let unit_series = || Gain::new(1.0).unwrap().series(Gain::new(1.0).unwrap());
    let range = TravelLimits::Range { lo: 0.1, hi: 1.0 };
    names(unit_series().with_limits(range), "limits.lo");
    let gap = TravelLimits::Gap { b: 0.0, r0: 0.0 };
    names(unit_series().with_limits(gap), "limits.b");
}

#[test]
fn unusual_but_valid_settings_are_accepted() {
    // Purely hysteretic and purely elastic limits.
    assert!(bw(0.0, 1.0, vec![0.0], vec![1.0]).is_ok());
    assert!(bw(1.0, 1.0, vec![0.0], vec![1.0]).is_ok());
    // Hardening Bouc-Wen set outside the bounded class (the Bouc-Wen
    // benchmark's β' = 800, γ' = −1100).
    let mut hard = BoucWen::constant(1.0, 0.0, 5e4, 800.0, -1100.0, 1.0).unwrap();
    assert!(hard
        .run(&[1e-4, -1e-4, 2e-4])
        .unwrap()
        .iter()
        .all(|y: &f64| y.is_finite()));
    // Zero thresholds and zero stiffness.
    assert!(Play::new(0.0).is_ok() && Stop::new(0.0).is_ok());
    assert!(StiffnessMap::constant(0.0).is_ok());
    assert!(DeadZone::new(0.0, 0.0).is_ok());
    // Negative gains and weights.
    assert!(Gain::new(-3.0).is_ok() && PiBank::new(-1.0, vec![0.5], vec![-2.0]).is_ok());
}

#[test]
fn non_finite_inputs_are_errors_with_the_sample_index() {
    let ops: Vec<Box<dyn Operator<f64>>> = vec![
        Play::new(0.1).unwrap().boxed(),
        Stop::new(0.1).unwrap().boxed(),
        DeadZone::symmetric(0.1).unwrap().boxed(),
        Saturation::new(-1.0, 1.0).unwrap().boxed(),
        Gain::new(2.0).unwrap().boxed(),
        Mms::new(1.0, 2.0).unwrap().boxed(),
        BoucWen::constant(1.0, 0.5, 1.0, 0.5, 0.5, 1.5)
            .unwrap()
            .boxed(),
        BoucWen::constant(1.0, 0.5, 1.0, 0.5, 0.5, 1.0)
            .unwrap()
            .boxed(),
        PiBank::new(1.0, vec![0.1], vec![1.0]).unwrap().boxed(),
        Gain::new(1.0)
            .unwrap()
            .series(Gain::new(2.0).unwrap())
            .boxed(),
    ];
    for mut op in ops {
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            op.reset();
            let err = op.run(&[0.1, 0.2, bad, 0.3]).unwrap_err();
            match err {
                Error::AtSample { index, source } => {
                    assert_eq!(index, 2, "{}", op.name());
                    assert!(
                        matches!(*source, Error::NonFiniteInput { .. }),
                        "{}: {source}",
                        op.name()
                    );
                }
                other => panic!("{}: {other}", op.name()),
            }
        }
    }
}

#[test]
fn diverging_state_is_an_error_not_a_nan() {
    // β + γ < 0 with n = 2: the state blows up in finite travel.
    let mut hard = BoucWen::constant(1.0, 0.0, 1.0, -1.0, -1.0, 2.0).unwrap();
    let xs: Vec<f64> = (0..100).map(|i| i as f64 * 0.1).collect();
    let err = hard.run(&xs).unwrap_err();
    assert!(matches!(err, Error::AtSample { .. }), "{err}");
    // An overflowing gain.
    assert!(matches!(
        Gain::new(1e300).unwrap().trial(1e300),
        Err(Error::NonFiniteOutput { .. })
    ));
}

#[test]
fn set_params_is_atomic_and_names_the_path() {
    let mut m = Play::new(0.1).unwrap().then(Mms::new(1.0, 5.0).unwrap());
    assert_eq!(
        m.param_names(),
        [
            "first.play.r",
            "first.play.y0",
            "second.mms.f_c",
            "second.mms.k",
            "second.mms.y0"
        ]
    );
    let before = m.params();
    m.run(&[0.5, 0.7]).unwrap();
    let out_before = m.trial(0.9).unwrap();
    // Valid first child, invalid second: nothing changes, not even the state.
    let err = m.set_params(&[0.2, 0.0, -1.0, 5.0, 0.0]).unwrap_err();
    assert_eq!(
        err,
        Error::InvalidParameter {
            name: "second.mms.f_c".into(),
            value: -1.0,
            reason: "must be > 0"
        }
    );
    assert_eq!(m.params(), before);
    assert_eq!(m.trial(0.9).unwrap(), out_before);
    assert!(matches!(
        m.set_params(&[0.1]),
        Err(Error::ParamCount {
            expected: 5,
            got: 1
        })
    ));
}

#[test]
fn a_loop_without_solution_is_an_error_not_a_huge_number() {
    // y = x + y has no solution; in floating point y − (x + y) rounds to 0
    // once |y| ≥ 2^53, which must not be taken for a root.
    let mut m = Gain::new(1.0_f64)
        .unwrap()
        .feedback(Gain::new(-1.0).unwrap());
    assert!(matches!(m.trial(1.0), Err(Error::NoBracket { .. })));
    let mut m = Gain::new(2.0_f64)
        .unwrap()
        .feedback(Gain::new(-0.5).unwrap());
    assert!(m.trial(1.0).is_err());
}

#[test]
fn extreme_but_valid_parameters_give_errors_or_numbers_never_nan() {
    // F_b / k underflows: rejected, naming f_b.
    names(ElastoPlastic::new(1e300_f64, 1e-30), "f_b");
    names(ElastoPlastic::new(1e-300_f64, 1e10), "f_b");
    // Ω = ±F_c − y_r overflows: outputs stay finite (the branch is
    // clamped to [y_r, ±F_c]) and tangents are numbers, not NaN.
    let mut m = Mms::new(1.7e308_f64, 1.0).unwrap();
    let y = m.run(&[10.0, -800.0]).unwrap();
    assert!(y.iter().all(|v| v.is_finite()) && y[1] == -1.7e308, "{y:?}");
    let mut m = Mms::new(1.7e308_f64, 1.0).unwrap();
    m.trial(10.0).unwrap();
    m.commit();
    let t = m.trial(-800.0).unwrap();
    assert!(!t.tangent.is_nan() && t.output == -1.7e308, "{t:?}");
    // A probe that overflows inside a solve is not blamed on the input.
    let mut s = Gain::new(1.0_f64).unwrap().series(Gain::new(1.0).unwrap());
    match s.run(&[1.7e308, -1.7e308]) {
        Ok(y) => assert!(y.iter().all(|v| v.is_finite())),
        Err(Error::AtSample { source, .. }) => {
            assert!(!matches!(*source, Error::NonFiniteInput { .. }), "{source}")
        }
        Err(e) => panic!("{e}"),
    }
}

#[test]
fn bouc_wen_works_in_f32() {
    let mut bw = BoucWen::<f32>::constant(2.0, 0.3, 1.0, 0.6, 0.4, 1.5).unwrap();
    let x: Vec<f32> = (0..400).map(|i| 1.5 * (i as f32 * 0.05).sin()).collect();
    let y = bw.run(&x).unwrap();
    let mut bw64 = BoucWen::<f64>::constant(2.0, 0.3, 1.0, 0.6, 0.4, 1.5).unwrap();
    let y64 = bw64
        .run(&x.iter().map(|&v| v as f64).collect::<Vec<_>>())
        .unwrap();
    for (a, b) in y.iter().zip(&y64) {
        assert!(
            (*a as f64 - b).abs() < 1e-4 * b.abs().max(1.0),
            "{a} vs {b}"
        );
    }
}

#[test]
fn signal_generators_reject_absurd_lengths() {
    use hysteron::models::experiments::{chirp, sine};
    assert!(sine(1e-300, 1.0, 1.0, 1000.0).is_err());
    assert!(sine(1e-9, 1.0, 1.0, 1000.0).is_err());
    assert!(chirp(5.0, 0.1, 1e300, 1000.0, |_| 1.0).is_err());
    let s = sine(1.0, 1.0, 1.0, 100.0).unwrap();
    assert!(s.clone().then(1e300, 100.0, &s).is_err());
    assert!(s.clone().then(-1.0, 100.0, &s).is_err());
    let mut p = hysteron::models::TransmissionParams::default();
    p.friction.f_c = -1.0;
    assert!(hysteron::models::experiments::paper_experiments(&p).is_err());
}
