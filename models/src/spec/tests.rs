//! `with_params` over every kind of node and the repository's examples.

use super::*;
use hysteron_composition::PiBankParams;
use hysteron_operators::{
    BoucWenParams, DahlParams, DeadZoneParams, ElastoPlasticParams, Gain, GainParams, GmsParams,
    LuGreParams, MassSpringDamperParams, MaxwellSlipParams, MmsParams, ParamSet, PlayParams,
    SaturationParams, StiffnessMap, StopParams,
};

/// The example specs of the repository (`examples/specs/*.json`).
fn example_specs() -> Vec<(String, Spec)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/specs");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    paths.sort();
    assert!(paths.len() >= 4, "{paths:?}");
    paths
        .into_iter()
        .map(|p| {
            let spec = Spec::from_json_file(&p).unwrap();
            (p.display().to_string(), spec)
        })
        .collect()
}

/// One tree with every variant and every kind of travel limits.
fn every_variant() -> Spec {
    let b = Box::new;
    let spring = BoucWenParams {
        w: 0.6,
        alpha: 1.0,
        beta: 2.5,
        gamma: 1.5,
        n: 1.5,
        h0: 0.1,
        z0: -0.05,
        stiffness: StiffnessMap::new(vec![0.0, 0.4, 1.0], vec![10.0, 12.0, 18.0]).unwrap(),
    };
    let transmission = TransmissionParams {
        slider0: 0.05,
        ..TransmissionParams::default()
    };
    Spec::Cascade {
        first: b(Spec::Parallel {
            left: b(Spec::Scaled {
                w: 0.5,
                inner: b(Spec::leaf::<hysteron_operators::Play<f64>>(PlayParams {
                    r: 0.2,
                    y0: 0.1,
                })),
            }),
            right: b(Spec::Cascade {
                first: b(Spec::leaf::<hysteron_operators::Stop<f64>>(StopParams {
                    r: 0.3,
                    s0: -0.1,
                })),
                second: b(Spec::leaf::<hysteron_operators::ElastoPlastic<f64>>(
                    ElastoPlasticParams {
                        k: 20.0,
                        f_b: 1.0,
                        f0: 0.2,
                    },
                )),
            }),
        }),
        second: b(Spec::Parallel {
            left: b(Spec::Feedback {
                forward: b(Spec::leaf::<hysteron_operators::DeadZone<f64>>(
                    DeadZoneParams {
                        b_l: -0.1,
                        b_r: 0.2,
                    },
                )),
                back: b(Spec::leaf::<hysteron_operators::Saturation<f64>>(
                    SaturationParams { lo: -1.0, hi: 2.0 },
                )),
                solver: Some(SolverOptions::default()),
            }),
            right: b(Spec::Parallel {
                left: b(Spec::Series {
                    left: b(Spec::leaf::<hysteron_operators::Mms<f64>>(MmsParams {
                        f_c: 1.5,
                        k: 30.0,
                        y0: 0.2,
                    })),
                    right: b(Spec::leaf::<hysteron_operators::BoucWen<f64>>(
                        spring.clone(),
                    )),
                    limits: TravelLimits::Range { lo: -0.2, hi: 0.3 },
                    solver: None,
                }),
                right: b(Spec::Parallel {
                    left: b(Spec::Series {
                        left: b(Spec::leaf::<hysteron_operators::Gain<f64>>(
                            hysteron_operators::GainParams { k: 3.0 },
                        )),
                        right: b(Spec::leaf::<hysteron_composition::PiBank<f64>>(
                            PiBankParams {
                                a0: 0.5,
                                r: vec![0.0, 0.1, 0.4],
                                w: vec![1.0, -0.5, 2.0],
                                y0: Vec::new(),
                            },
                        )),
                        limits: TravelLimits::None,
                        solver: None,
                    }),
                    right: b(Spec::Parallel {
                        left: b(Spec::Inverse {
                            inner: b(Spec::leaf::<hysteron_operators::Gain<f64>>(
                                hysteron_operators::GainParams { k: 2.0 },
                            )),
                            solver: None,
                        }),
                        right: b(Spec::Parallel {
                            left: b(Spec::Transmission(transmission)),
                            right: b(Spec::leaf::<hysteron_composition::PiBank<f64>>(
                                PiBankParams {
                                    a0: 0.0,
                                    r: vec![0.2],
                                    w: vec![1.0],
                                    y0: vec![0.1],
                                },
                            )),
                        }),
                    }),
                }),
            }),
        }),
    }
}

fn all_specs() -> Vec<(String, Spec)> {
    let mut specs = example_specs();
    specs.push(("every variant".into(), every_variant()));
    specs.push((
        "transmission".into(),
        Spec::Transmission(TransmissionParams::default()),
    ));
    specs.push((
        "paper as series".into(),
        Spec::from(&TransmissionParams::default()),
    ));
    specs.push((
        "rate-dependent".into(),
        Spec::Parallel {
            left: Box::new(Spec::Oversample {
                inner: Box::new(Spec::leaf::<hysteron_operators::MassSpringDamper<f64>>(
                    MassSpringDamperParams {
                        m: 0.5,
                        c: 3.0,
                        k: 200.0,
                        dt: 0.0025,
                    },
                )),
                q: 4,
            }),
            right: Box::new(Spec::leaf::<hysteron_operators::ViscousDamper<f64>>(
                hysteron_operators::ViscousDamperParams { c: 2.0, dt: 0.01 },
            )),
        },
    ));
    specs.push((
        "friction models".into(),
        Spec::Parallel {
            left: Box::new(Spec::leaf::<hysteron_operators::MaxwellSlip<f64>>(
                MaxwellSlipParams {
                    k: vec![20.0, 8.0, 3.0],
                    f_b: vec![0.2, 0.5, 0.8],
                    f0: vec![],
                },
            )),
            right: Box::new(Spec::Parallel {
                left: Box::new(Spec::leaf::<hysteron_operators::Dahl<f64>>(DahlParams {
                    sigma: 30.0,
                    f_c: 1.2,
                    alpha: 1.5,
                    f0: 0.3,
                })),
                right: Box::new(Spec::leaf::<hysteron_operators::LuGre<f64>>(LuGreParams {
                    sigma0: 1e3,
                    sigma1: 5.0,
                    sigma2: 0.4,
                    f_c: 1.0,
                    f_s: 1.3,
                    v_s: 0.05,
                    delta: 2.0,
                    z0: 1e-4,
                    dt: 0.01,
                })),
            }),
        },
    ));
    specs.push((
        "gms".into(),
        // Its declared example (two elements, dt = 1e-3).
        Spec::leaf::<hysteron_operators::Gms<f64>>(GmsParams::example()),
    ));
    specs
}

fn bits(p: &[f64]) -> Vec<u64> {
    p.iter().map(|v| v.to_bits()).collect()
}

#[test]
fn with_params_of_own_params_is_the_same_spec() {
    for (name, spec) in all_specs() {
        let p = spec.build().unwrap().params();
        let back = spec.with_params(&p).unwrap();
        assert_eq!(back, spec, "{name}");
        // bit for bit, signed zeros included
        assert_eq!(
            back.to_json_pretty().unwrap(),
            spec.to_json_pretty().unwrap(),
            "{name}"
        );
        assert_eq!(bits(&back.build().unwrap().params()), bits(&p), "{name}");
    }
}

/// Each parameter changed on its own ends up in the place `params()`
/// reads it from: the new spec builds to exactly `p`.
#[test]
fn every_parameter_is_written_to_its_own_field() {
    for (name, spec) in all_specs() {
        let model = spec.build().unwrap();
        let p = model.params();
        let names = model.param_names();
        let domains = model.param_domains();
        let mut checked = 0;
        for i in 0..p.len() {
            let candidates = [p[i] * 0.9375, p[i] * 1.0625, p[i] + 0.0625, p[i] - 0.0625];
            let Some(v) = candidates
                .into_iter()
                .find(|&v| v != p[i] && domains[i].contains(v))
            else {
                continue;
            };
            let mut q = p.clone();
            q[i] = v;
            let accepted = model.clone().set_params(&q).is_ok();
            match spec.with_params(&q) {
                Ok(new) => {
                    assert!(accepted, "{name}: {} = {v} accepted", names[i]);
                    assert_eq!(
                        bits(&new.build().unwrap().params()),
                        bits(&q),
                        "{name}: {}",
                        names[i]
                    );
                    assert_ne!(new, spec, "{name}: {}", names[i]);
                    checked += 1;
                }
                // a tied parameter cannot move alone, and says why
                Err(e) => assert!(
                    !accepted
                        || (spec.tied_params().contains(&names[i]) && e.to_string().contains("z0")),
                    "{name}: {} = {v}: {e}",
                    names[i]
                ),
            }
        }
        assert!(
            checked * 4 >= p.len() * 3,
            "{name}: {checked} of {}",
            p.len()
        );
    }
}

#[test]
fn with_params_errors_name_the_path() {
    let spec = Spec::from(&TransmissionParams::default());
    let p = spec.build().unwrap().params();
    let e = spec.with_params(&p[1..]).unwrap_err();
    assert!(e.to_string().contains("parameter vector has"), "{e}");
    let mut q = p.clone();
    q[0] = -0.3; // limits.b
    assert_eq!(
        spec.with_params(&q).unwrap_err().to_string(),
        "series.limits.b: must be > 0 (got -0.3)"
    );
    let names = spec.build().unwrap().param_names();
    let s1 = names
        .iter()
        .position(|n| n == "right.bouc_wen.stiffness.s[1]")
        .unwrap();
    let mut q = p.clone();
    q[s1] = -1.0;
    assert_eq!(
        spec.with_params(&q).unwrap_err().to_string(),
        "series.right.bouc_wen.stiffness.s[1]: must be ≥ 0 (got -1)"
    );
    // A transmission spec ties the spring's z0 to −slider0.
    let spec = Spec::Transmission(TransmissionParams::default());
    let mut q = spec.build().unwrap().params();
    q[1] = 0.1; // slider0, z0 left at 0
    let e = spec.with_params(&q).unwrap_err().to_string();
    assert!(
        e.starts_with("transmission.spring.z0: must equal −slider0"),
        "{e}"
    );
    let z0 = spec
        .build()
        .unwrap()
        .param_names()
        .iter()
        .position(|n| n == "right.bouc_wen.z0")
        .unwrap();
    q[z0] = -0.1;
    let new = spec.with_params(&q).unwrap();
    assert_eq!(bits(&new.build().unwrap().params()), bits(&q));
    let Spec::Transmission(t) = new else {
        panic!("{new:?}")
    };
    assert_eq!(t.slider0, 0.1);
    // and a spec that does not build is an error, not a panic
    let bad = Spec::leaf::<hysteron_operators::Play<f64>>(PlayParams { r: -1.0, y0: 0.0 });
    assert!(bad.with_params(&[1.0, 0.0]).is_err());
}

/// `n` gains cascaded into a left-deep chain: `n` nodes on the path from
/// the root to the innermost gain (as `a.then(b).then(c)…` builds it).
fn chain(n: usize) -> Spec {
    let gain = || Spec::leaf::<Gain<f64>>(GainParams { k: 1.0 });
    (1..n).fold(gain(), |first, _| Spec::Cascade {
        first: Box::new(first),
        second: Box::new(gain()),
    })
}

/// The chain as JSON text, written without recursion.
fn chain_json(n: usize) -> String {
    let gain = r#"{"type":"gain","k":1.0}"#;
    let open = format!(r#"{{"type":"cascade","second":{gain},"first":"#);
    format!("{}{gain}{}", open.repeat(n - 1), "}".repeat(n - 1))
}

#[test]
fn depth_counts_nodes_on_the_longest_path() {
    assert_eq!(chain(1).depth(), 1);
    assert_eq!(chain(7).depth(), 7);
    assert_eq!(
        every_variant().depth(),
        every_variant().depth_by_recursion()
    );
}

impl Spec {
    fn depth_by_recursion(&self) -> usize {
        1 + self
            .children()
            .iter()
            .map(|(_, c)| c.depth_by_recursion())
            .max()
            .unwrap_or(0)
    }
}

/// The deepest spec allowed parses, builds and runs; one level more is
/// refused by `build` with a `nesting` error.
#[test]
fn specs_nest_up_to_max_depth() {
    let spec = Spec::from_json(&chain_json(MAX_DEPTH)).unwrap();
    assert_eq!(spec.depth(), MAX_DEPTH);
    let mut op = spec.build().unwrap();
    assert_eq!(op.trial(0.5).unwrap().output, 0.5);
    let err = chain(MAX_DEPTH + 1).build().unwrap_err().to_string();
    assert!(err.starts_with("cascade.nesting: "), "{err}");
    assert!(err.contains("at most 120 operators"), "{err}");
    // The JSON of that spec still parses (the leaf's objects are allowed
    // for); it is `build` that refuses it.
    assert!(Spec::from_json(&chain_json(MAX_DEPTH + 1)).is_ok());
}

/// A spec nested 10⁵ levels deep, as JSON text and built in code: an
/// error, not a stack overflow (the test thread's stack is 2 MiB).
#[test]
fn a_spec_nested_1e5_deep_is_an_error() {
    let err = Spec::from_json(&chain_json(100_000)).unwrap_err();
    let text = err.to_string();
    assert!(matches!(err, SpecError::Json { .. }), "{text}");
    assert!(
        text.contains("nested deeper than 124 levels at line 1 column"),
        "{text}"
    );
    // Inside a string, brackets do not count.
    let quoted = format!(r#"{{"type":"gain","k":1.0,"note":"{}"}}"#, "[".repeat(1000));
    let err = Spec::from_json(&quoted).unwrap_err().to_string();
    assert!(err.contains("note"), "{err}");

    let deep = chain(100_000);
    let err = deep.build().unwrap_err().to_string();
    assert!(err.contains("nesting: "), "{err}");
    assert!(err.contains("100000"), "{err}");
    // Dropping it would recurse 10⁵ times (see `MAX_DEPTH`).
    std::mem::forget(deep);
}

#[test]
fn a_leading_byte_order_mark_is_skipped() {
    let spec = Spec::from_json("\u{feff}{\"type\": \"gain\", \"k\": 2.0}").unwrap();
    assert_eq!(spec, Spec::leaf::<Gain<f64>>(GainParams { k: 2.0 }));
    // Anywhere else it is not JSON.
    assert!(Spec::from_json("{\"type\": \"gain\", \u{feff}\"k\": 2.0}").is_err());
}

/// A rate-dependent leaf without `dt`: it reads, writes and takes new
/// parameters without one, and builds once the period is given, to the
/// model it would be with `dt` written in.
#[test]
fn a_spec_may_leave_the_period_to_the_data() {
    let without = r#"{"type": "oversample", "q": 2, "inner": {"type": "parallel",
        "left": {"type": "lugre", "sigma0": 1000, "sigma1": 5, "sigma2": 0.2,
                 "f_c": 1, "f_s": 1.5, "v_s": 0.5},
        "right": {"type": "viscous_damper", "c": 3, "dt": 0.004}}}"#;
    let spec = Spec::from_json(without).unwrap();
    assert_eq!(
        spec.missing_period().as_deref(),
        Some("oversample.inner.parallel.left.lugre")
    );
    // the stated period is the damper's, at the root
    assert_eq!(spec.stated_periods(), [0.008]);
    let err = spec.build().unwrap_err();
    assert_eq!(err.path(), "oversample.inner.parallel.left.lugre.dt");
    // written back without dt, and read back the same
    let text = spec.to_json_pretty().unwrap();
    assert!(!text.contains("\"dt\": 1"), "{text}");
    assert_eq!(Spec::from_json(&text).unwrap(), spec);
    // new parameters keep the period left out
    let stand_in = spec.or_dt(1.0).build().unwrap();
    let mut p = stand_in.params();
    p[3] = 2.0; // f_c
    let changed = spec.with_params(&p).unwrap();
    assert_eq!(changed.missing_period(), spec.missing_period());
    assert_eq!(changed.or_dt(1.0).build().unwrap().params(), p);
    // `or_dt` fills only what is missing; `with_dt` sets every period
    assert_eq!(spec.or_dt(0.01).stated_periods(), [0.01, 0.008]);
    assert_eq!(spec.with_dt(0.01).stated_periods(), [0.01]);
    // built with the period, it is the model written with it
    let written =
        Spec::from_json(&without.replace(r#""v_s": 0.5"#, r#""v_s": 0.5, "dt": 0.005"#)).unwrap();
    assert_eq!(spec.or_dt(0.01), written);
    let x: Vec<f64> = (0..200).map(|i| (i as f64 * 0.05).sin()).collect();
    assert_eq!(
        spec.or_dt(0.01).build().unwrap().run(&x).unwrap(),
        written.build().unwrap().run(&x).unwrap()
    );
    // a rate-independent spec has no period to give or miss
    let play = Spec::from_json(r#"{"type": "play", "r": 0.5}"#).unwrap();
    assert_eq!(
        (play.missing_period(), play.stated_periods()),
        (None, vec![])
    );
}

/// A constant spring may be written as a number.
#[test]
fn a_constant_stiffness_is_a_number() {
    let number = Spec::from_json(
        r#"{"type": "bouc_wen", "w": 0.4, "alpha": 1, "beta": 3, "gamma": 1, "n": 1,
            "stiffness": 5}"#,
    )
    .unwrap();
    let knots = Spec::from_json(
        r#"{"type": "bouc_wen", "w": 0.4, "alpha": 1, "beta": 3, "gamma": 1, "n": 1,
            "stiffness": {"z": [0], "s": [5]}}"#,
    )
    .unwrap();
    assert_eq!(number, knots);
    for (bad, path, message) in [
        (r#""five""#, "stiffness", "expected a constant stiffness"),
        (r#"-1"#, "bouc_wen.stiffness.s[0]", "must be ≥ 0"),
        (
            r#"{"z": [0], "s": [1], "k": 2}"#,
            "stiffness.k",
            "unknown field `k`",
        ),
    ] {
        let text = format!(
            r#"{{"type": "bouc_wen", "w": 0.4, "alpha": 1, "beta": 3, "gamma": 1, "n": 1,
                "stiffness": {bad}}}"#
        );
        let err = Spec::from_json(&text).and_then(|s| s.build().map(|_| s));
        let err = err.unwrap_err();
        assert_eq!(err.path(), path, "{err}");
        assert!(err.to_string().contains(message), "{err}");
    }
}
