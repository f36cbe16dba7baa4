//! Model specs (`hysteron::models::Spec`): JSON round trips of random
//! model trees (lossless, bit for bit, and the built models agree bit for
//! bit), errors that name the path, the paper's model from the algebra
//! alone, and the example specs under `examples/specs/`.
//!
//! `cargo test --test spec -- --ignored write_example_specs` rewrites the
//! example files from the generators below.

use hysteron::composition::{Oversample, PiBankParams, SolverOptions, TravelLimits};
use hysteron::models::spec::MAX_DEPTH;
use hysteron::models::{Spec, SpecError, TransmissionParams};
use hysteron::operators::{
    BoucWenParams, DahlParams, DeadZoneParams, ElastoPlasticParams, GmsParams, LuGreParams,
    MassSpringDamper, MassSpringDamperParams, MaxwellSlipParams, MmsParams, PlayParams,
    PreisachMeasure, PreisachParams, PreisachStart, SaturationParams, StiffnessMap, StopParams,
    ViscousDamper,
};
use hysteron::{Error, Operator};
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;
use std::path::PathBuf;

mod common;

// ---------------------------------------------------------------------------
// Random specs
// ---------------------------------------------------------------------------

/// A float in `[lo, hi)` with a full random mantissa, sometimes `-0.0` or
/// `0.0` when the range holds them (to check signed zeros survive).
fn num(lo: f64, hi: f64) -> BoxedStrategy<f64> {
    if lo <= 0.0 && hi > 0.0 {
        prop_oneof![8 => lo..hi, 1 => Just(-0.0), 1 => Just(0.0)].boxed()
    } else {
        (lo..hi).boxed()
    }
}

fn stiffness() -> impl Strategy<Value = StiffnessMap<f64>> {
    prop::collection::vec((0.01..0.5f64, 0.0..20.0f64), 1..5).prop_map(|knots| {
        let mut z = 0.0;
        let (zs, ss): (Vec<f64>, Vec<f64>) = knots
            .iter()
            .enumerate()
            .map(|(i, &(dz, s))| {
                if i > 0 {
                    z += dz;
                }
                (z, s)
            })
            .unzip();
        StiffnessMap::new(zs, ss).unwrap_or_else(|e| panic!("generated knots: {e}"))
    })
}

fn mms() -> impl Strategy<Value = MmsParams<f64>> {
    (0.1..3.0f64, 1.0..60.0f64, num(-0.1, 0.1)).prop_map(|(f_c, k, y0)| MmsParams { f_c, k, y0 })
}

fn bouc_wen() -> impl Strategy<Value = BoucWenParams<f64>> {
    (
        (0.0..=1.0f64, 0.5..1.5f64, 0.0..3.0f64, -0.5..2.0f64),
        (
            prop_oneof![3 => Just(1.0), 1 => 1.0..2.5f64],
            num(-0.3, 0.3),
        ),
        (num(-0.2, 0.2), stiffness()),
    )
        .prop_map(
            |((w, alpha, beta, gamma), (n, h0), (z0, stiffness))| BoucWenParams {
                w,
                alpha,
                beta,
                gamma,
                n,
                h0,
                z0,
                stiffness,
            },
        )
}

fn pi_bank() -> impl Strategy<Value = PiBankParams<f64>> {
    (
        num(-1.0, 1.0),
        prop::collection::vec((0.0..1.0f64, -1.0..2.0f64), 0..6),
    )
        .prop_flat_map(|(a0, plays)| {
            let m = plays.len();
            let y0 = prop_oneof![
                Just(Vec::new()),
                prop::collection::vec(num(-0.2, 0.2), m..=m)
            ];
            (Just(a0), Just(plays), y0)
        })
        .prop_map(|(a0, plays, y0)| PiBankParams {
            a0,
            r: plays.iter().map(|p| p.0).collect(),
            w: plays.iter().map(|p| p.1).collect(),
            y0,
        })
}

/// A forward PI bank the analytic inverse accepts: `a0 > 0`, positive
/// weights, and initial play outputs some history reaches (the plays'
/// states after the input `0 → c → 0`), or none.
fn pi_inverse() -> impl Strategy<Value = PiBankParams<f64>> {
    (
        0.1..1.0f64,
        prop::collection::vec((0.0..1.0f64, 0.0..2.0f64), 0..6),
        prop_oneof![Just(None), (-0.5..0.5f64).prop_map(Some)],
    )
        .prop_map(|(a0, plays, c)| {
            let r: Vec<f64> = plays.iter().map(|p| p.0).collect();
            let y0 = match c {
                None => Vec::new(),
                Some(c) => r
                    .iter()
                    .map(|&r| {
                        let y: f64 = 0.0_f64.clamp(c - r, c + r);
                        y.clamp(-r, r)
                    })
                    .collect(),
            };
            PiBankParams {
                a0,
                r,
                w: plays.iter().map(|p| p.1).collect(),
                y0,
            }
        })
}

fn maxwell_slip() -> impl Strategy<Value = MaxwellSlipParams<f64>> {
    prop::collection::vec((0.5..50.0f64, 0.01..2.0f64), 1..6)
        .prop_flat_map(|elements| {
            let n = elements.len();
            let f0 = prop_oneof![
                Just(Vec::new()),
                prop::collection::vec(num(-1.0, 1.0), n..=n)
            ];
            (Just(elements), f0)
        })
        .prop_map(|(elements, f0)| MaxwellSlipParams {
            k: elements.iter().map(|e| e.0).collect(),
            f_b: elements.iter().map(|e| e.1).collect(),
            f0,
        })
}

fn dahl() -> impl Strategy<Value = DahlParams<f64>> {
    (
        1.0..100.0f64,
        0.1..3.0f64,
        prop_oneof![Just(0.0), Just(1.0), 0.0..3.0f64],
        num(-1.0, 1.0),
    )
        .prop_map(|(sigma, f_c, alpha, f0)| DahlParams {
            sigma,
            f_c,
            alpha,
            f0,
        })
}

fn lugre() -> impl Strategy<Value = LuGreParams<f64>> {
    (
        (10.0..1e4f64, num(0.0, 10.0), num(0.0, 2.0)),
        (0.1..2.0f64, 0.1..3.0f64, 0.001..1.0f64, 0.5..3.0f64),
        (num(-1e-3, 1e-3), 0.001..0.1f64),
    )
        .prop_map(|(bristles, stribeck, (z0, dt))| common::lugre_of(bristles, stribeck, z0, dt))
}

fn gms() -> impl Strategy<Value = GmsParams<f64>> {
    (
        prop::collection::vec((1.0..100.0f64, 0.05..1.0f64), 1..5),
        (0.1..50.0f64, 0.1..2.0f64, 0.1..3.0f64, 0.01..1.0f64),
        (1.0..3.0f64, num(0.0, 1.0), 0.001..0.1f64),
    )
        .prop_flat_map(|(elements, stribeck, rest)| {
            let n = elements.len();
            let f0 = prop_oneof![
                Just(Vec::new()),
                prop::collection::vec(num(-0.5, 0.5), n..=n)
            ];
            (Just(elements), Just(stribeck), Just(rest), f0)
        })
        .prop_map(|(elements, stribeck, rest, f0)| common::gms_of(&elements, stribeck, rest, f0))
}

fn transmission() -> impl Strategy<Value = TransmissionParams> {
    (0.05..0.6f64, -0.5..0.5f64, mms(), bouc_wen()).prop_map(|(backlash, s, friction, spring)| {
        TransmissionParams {
            backlash,
            slider0: s * backlash,
            friction,
            spring,
        }
    })
}

/// A strictly increasing axis of `n` points from `start`.
fn axis(start: f64, steps: &[f64]) -> Vec<f64> {
    let mut v = start;
    steps
        .iter()
        .map(|&d| {
            let here = v;
            v += d;
            here
        })
        .collect()
}

/// A Preisach model in each representation. A table is built from random
/// non-negative cell masses (`m[i][j]` on cell `(i, j)`, the diagonal ones
/// on the diagonal), so its Everett values are valid by construction:
/// `E(x[p], x[q]) = Σ_{q ≤ j ≤ i < p} m[i][j]`.
fn preisach() -> impl Strategy<Value = PreisachParams<f64>> {
    let start = prop_oneof![
        Just(PreisachStart::FromBelow),
        Just(PreisachStart::FromAbove)
    ];
    let tri = |n: usize| {
        (0..n)
            .map(|i| prop::collection::vec(num(0.0, 1.0), i + 1..=i + 1))
            .collect::<Vec<_>>()
    };
    let grid = (num(-1.5, 0.5), prop::collection::vec(0.05..0.8f64, 1..6))
        .prop_flat_map(move |(t0, steps)| (Just(axis(t0, &steps)), tri(steps.len())))
        .prop_map(|(t, mu)| PreisachMeasure::Grid { t, mu });
    let table = (num(-1.5, 0.0), prop::collection::vec(0.05..0.8f64, 2..6))
        .prop_flat_map(move |(x0, steps)| (Just(axis(x0, &steps)), tri(steps.len() - 1)))
        .prop_map(|(x, m)| {
            let cells = m.len();
            let e = (0..cells)
                .map(|k| {
                    (0..=k)
                        .map(|q| {
                            // E(x[k+1], x[q]) = Σ_{q ≤ j ≤ i ≤ k} m[i][j]
                            (q..=k).map(|i| m[i][q..=i].iter().sum::<f64>()).sum()
                        })
                        .collect()
                })
                .collect();
            PreisachMeasure::Table { x, e }
        });
    let uniform = (num(0.0, 2.0), -2.0..0.0f64, 0.1..2.0f64).prop_map(|(mu, x_min, d)| {
        PreisachMeasure::Uniform {
            mu,
            x_min,
            x_max: x_min + d,
        }
    });
    let tanh = (
        num(0.0, 3.0),
        num(-0.5, 0.8),
        0.05..1.0f64,
        -2.0..0.0f64,
        0.1..3.0f64,
    )
        .prop_map(|(amplitude, hc, w, x_min, d)| PreisachMeasure::Tanh {
            amplitude,
            hc,
            w,
            x_min,
            x_max: x_min + d,
        });
    (prop_oneof![grid, table, uniform, tanh], start)
        .prop_map(|(measure, start)| PreisachParams { measure, start })
}

/// Every elementary operator, with valid random parameters.
fn leaf() -> BoxedStrategy<Spec> {
    prop_oneof![
        (0.0..1.0f64, num(-0.5, 0.5))
            .prop_map(|(r, y0)| Spec::leaf::<hysteron::operators::Play<f64>>(PlayParams { r, y0 })),
        (0.0..1.0f64, num(-0.5, 0.5))
            .prop_map(|(r, s0)| Spec::leaf::<hysteron::operators::Stop<f64>>(StopParams { r, s0 })),
        (0.5..50.0f64, 0.0..2.0f64, num(-0.5, 0.5)).prop_map(|(k, f_b, f0)| Spec::leaf::<
            hysteron::operators::ElastoPlastic<f64>,
        >(
            ElastoPlasticParams { k, f_b, f0 }
        )),
        (num(-1.0, 0.0), num(0.0, 1.0)).prop_map(|(b_l, b_r)| Spec::leaf::<
            hysteron::operators::DeadZone<f64>,
        >(DeadZoneParams {
            b_l,
            b_r
        })),
        (-2.0..-0.1f64, 0.1..2.0f64).prop_map(|(lo, hi)| Spec::leaf::<
            hysteron::operators::Saturation<f64>,
        >(SaturationParams { lo, hi })),
        num(-3.0, 3.0).prop_map(|k| Spec::leaf::<hysteron::operators::Gain<f64>>(
            hysteron::operators::GainParams { k }
        )),
        mms().prop_map(Spec::leaf::<hysteron::operators::Mms<f64>>),
        bouc_wen().prop_map(Spec::leaf::<hysteron::operators::BoucWen<f64>>),
        pi_bank().prop_map(Spec::leaf::<hysteron::composition::PiBank<f64>>),
        pi_inverse().prop_map(Spec::leaf::<hysteron::composition::PiInverse<f64>>),
        preisach().prop_map(Spec::leaf::<hysteron::operators::Preisach<f64>>),
        transmission().prop_map(Spec::Transmission),
        (0.1..2.0f64, num(0.0, 5.0), num(0.0, 100.0), 0.001..0.1f64).prop_map(|(m, c, k, dt)| {
            Spec::leaf::<hysteron::operators::MassSpringDamper<f64>>(MassSpringDamperParams {
                m,
                c,
                k,
                dt,
            })
        }),
        (num(0.0, 3.0), 0.001..0.1f64).prop_map(|(c, dt)| Spec::leaf::<
            hysteron::operators::ViscousDamper<f64>,
        >(
            hysteron::operators::ViscousDamperParams { c, dt }
        )),
        maxwell_slip().prop_map(Spec::leaf::<hysteron::operators::MaxwellSlip<f64>>),
        dahl().prop_map(Spec::leaf::<hysteron::operators::Dahl<f64>>),
        lugre().prop_map(Spec::leaf::<hysteron::operators::LuGre<f64>>),
        gms().prop_map(Spec::leaf::<hysteron::operators::Gms<f64>>),
    ]
    .boxed()
}

fn solver() -> impl Strategy<Value = Option<SolverOptions<f64>>> {
    prop_oneof![
        2 => Just(None),
        1 => (1e-15..1e-9f64, 0.0..1e-12f64, 20..200usize, 8..64usize).prop_map(
            |(rel_tol, abs_tol, max_iter, max_expansions)| Some(SolverOptions {
                rel_tol,
                abs_tol,
                max_iter,
                max_expansions,
            })
        ),
    ]
}

fn limits() -> impl Strategy<Value = TravelLimits<f64>> {
    prop_oneof![
        Just(TravelLimits::None),
        (-1.0..0.0f64, 0.01..1.0f64).prop_map(|(lo, hi)| TravelLimits::Range { lo, hi }),
        (0.01..1.0f64, -0.5..=0.5f64).prop_map(|(b, s)| TravelLimits::Gap { b, r0: s * b }),
    ]
}

/// A random model tree of depth ≤ `depth`, with at most `implicit`
/// implicit combinators (feedback, series, inverse) on any path from the
/// root, so that nested solves stay cheap.
fn spec(depth: u32, implicit: u32) -> BoxedStrategy<Spec> {
    if depth == 0 {
        return leaf();
    }
    let sub = || spec(depth - 1, implicit);
    let boxed = |s: Spec| Box::new(s);
    let mut options: Vec<(u32, BoxedStrategy<Spec>)> = vec![
        (4, leaf()),
        (
            2,
            (sub(), sub())
                .prop_map(move |(a, b)| Spec::Cascade {
                    first: boxed(a),
                    second: boxed(b),
                })
                .boxed(),
        ),
        (
            2,
            (sub(), sub())
                .prop_map(move |(a, b)| Spec::Parallel {
                    left: boxed(a),
                    right: boxed(b),
                })
                .boxed(),
        ),
        (
            1,
            (num(-2.0, 2.0), sub())
                .prop_map(move |(w, a)| Spec::Scaled { w, inner: boxed(a) })
                .boxed(),
        ),
        (
            1,
            (sub(), 1..4usize)
                .prop_map(move |(a, q)| Spec::Oversample { inner: boxed(a), q })
                .boxed(),
        ),
    ];
    if implicit > 0 {
        let isub = || spec(depth - 1, implicit - 1);
        options.extend([
            (
                1,
                (isub(), isub(), solver())
                    .prop_map(move |(a, b, solver)| Spec::Feedback {
                        forward: boxed(a),
                        back: boxed(b),
                        solver,
                    })
                    .boxed(),
            ),
            (
                2,
                (isub(), isub(), limits(), solver())
                    .prop_map(move |(a, b, limits, solver)| Spec::Series {
                        left: boxed(a),
                        right: boxed(b),
                        limits,
                        solver,
                    })
                    .boxed(),
            ),
            (
                1,
                (isub(), solver())
                    .prop_map(move |(a, solver)| Spec::Inverse {
                        inner: boxed(a),
                        solver,
                    })
                    .boxed(),
            ),
        ]);
    }
    prop::strategy::Union::new_weighted(options).boxed()
}

/// A short signal with reversals, starting at 0.
fn short_signal() -> Vec<f64> {
    (0..16)
        .map(|i| {
            let t = i as f64;
            0.9 * (0.7 * t).sin() + 0.2 * (1.9 * t).sin()
        })
        .collect()
}

fn sine(n: usize, amplitude: f64) -> Vec<f64> {
    (0..n)
        .map(|i| amplitude * (std::f64::consts::TAU * i as f64 / 100.0).sin())
        .collect()
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|y| y.to_bits()).collect()
}

fn config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

fn fail(e: impl std::fmt::Display) -> TestCaseError {
    TestCaseError::fail(e.to_string())
}

proptest! {
    #![proptest_config(config(96))]

    /// Random trees survive a JSON round trip unchanged (every float bit
    /// for bit), and the models built from both run bit-identically (or
    /// fail identically, when random parameters give a loop without a
    /// solution).
    #[test]
    fn json_round_trip_is_lossless(s in spec(4, 2)) {
        let json = s.to_json_pretty().map_err(fail)?;
        let back = Spec::from_json(&json).map_err(|e| fail(format!("{e}\n{json}")))?;
        prop_assert_eq!(&back, &s);
        // PartialEq on f64 misses signed zeros: the text is a fixed point,
        // and shortest round-trip formatting is injective on floats.
        prop_assert_eq!(back.to_json_pretty().map_err(fail)?, json.clone());

        let mut a = s.build().map_err(|e| fail(format!("{e}\n{json}")))?;
        let mut b = back.build().map_err(fail)?;
        prop_assert_eq!(bits(&a.params()), bits(&b.params()));
        prop_assert_eq!(a.param_names(), b.param_names());
        let xs = short_signal();
        match (a.run(&xs), b.run(&xs)) {
            (Ok(ya), Ok(yb)) => prop_assert_eq!(bits(&ya), bits(&yb)),
            (Err(ea), Err(eb)) => prop_assert_eq!(ea, eb),
            (ra, rb) => prop_assert!(false, "original {ra:?}, round trip {rb:?}\n{json}"),
        }
    }

    /// Any finite float, subnormals and signed zeros included, is read back
    /// bit for bit.
    #[test]
    fn floats_round_trip_bit_exactly(
        k in prop::num::f64::NORMAL | prop::num::f64::SUBNORMAL | prop::num::f64::ZERO
            | prop::num::f64::NEGATIVE,
        w in prop::num::f64::ANY.prop_filter("finite", |w| w.is_finite()),
    ) {
        let s = Spec::Scaled { w, inner: Box::new(Spec::leaf::<hysteron::operators::Gain<f64>>(hysteron::operators::GainParams { k })) };
        let back = Spec::from_json(&s.to_json_pretty().map_err(fail)?).map_err(fail)?;
        match back {
            Spec::Scaled { w: w2, inner } => {
                prop_assert_eq!(w2.to_bits(), w.to_bits());
                match inner.leaf_params::<hysteron::operators::Gain<f64>>() {
                    Some(hysteron::operators::GainParams { k: k2 }) => prop_assert_eq!(k2.to_bits(), k.to_bits()),
                    other => prop_assert!(false, "inner {other:?}"),
                }
            }
            other => prop_assert!(false, "{other:?}"),
        }
    }

    /// Corrupted documents (bytes replaced, cut short) are errors or
    /// specs, never panics; whatever parses builds or fails cleanly.
    #[test]
    fn corrupted_json_never_panics(
        s in spec(3, 1),
        edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..4),
        cut in any::<prop::sample::Index>(),
        truncate in any::<bool>(),
    ) {
        let mut bytes = s.to_json_pretty().map_err(fail)?.into_bytes();
        for (at, byte) in edits {
            let i = at.index(bytes.len());
            // keep the text ASCII so that it stays a `str`
            bytes[i] = byte % 128;
        }
        if truncate {
            bytes.truncate(cut.index(bytes.len()));
        }
        let text = String::from_utf8(bytes).map_err(fail)?;
        if let Ok(spec) = Spec::from_json(&text) {
            if let Ok(mut m) = spec.build() {
                let _ = m.run(&short_signal()[..4]);
            }
        }
    }
}

// ---------------------------------------------------------------------------
// The paper's model
// ---------------------------------------------------------------------------

/// `Spec::from(&TransmissionParams)` (a generic `series` of `mms` and
/// `bouc_wen` in a gap) builds the same model as the named parameters, bit
/// for bit, and so does the `transmission` convenience variant.
#[test]
fn paper_model_from_the_algebra_equals_transmission_params() {
    let mut shifted = TransmissionParams {
        slider0: 0.1,
        ..TransmissionParams::default()
    };
    shifted.spring.h0 = 0.05;
    for p in [TransmissionParams::default(), shifted] {
        let generic = Spec::from(&p);
        match &generic {
            // (a solver other than the default falls to the panic below)
            Spec::Series {
                left,
                right,
                limits,
                solver: None,
            } => {
                assert_eq!(
                    **left,
                    Spec::leaf::<hysteron::operators::Mms<f64>>(p.friction)
                );
                assert!(right
                    .leaf_params::<hysteron::operators::BoucWen<f64>>()
                    .is_some());
                assert_eq!(
                    *limits,
                    TravelLimits::Gap {
                        b: p.backlash,
                        r0: p.slider0
                    }
                );
            }
            other => panic!("not a series with the default solver: {other:?}"),
        }
        let xs = sine(400, 1.4);
        let mut paper = p.build().unwrap();
        let reference = paper.run(&xs).unwrap();
        let mut from_algebra = generic.build().unwrap();
        assert_eq!(bits(&from_algebra.run(&xs).unwrap()), bits(&reference));
        let mut named = Spec::Transmission(p.clone()).build().unwrap();
        assert_eq!(bits(&named.run(&xs).unwrap()), bits(&reference));
        // and through JSON
        let back = Spec::from_json(&generic.to_json_pretty().unwrap()).unwrap();
        assert_eq!(
            bits(&back.build().unwrap().run(&xs).unwrap()),
            bits(&reference)
        );
    }
}

// ---------------------------------------------------------------------------
// Errors
// ---------------------------------------------------------------------------

/// Asserts a JSON error at `path` whose message contains `message`.
#[track_caller]
fn json_error(text: &str, path: &str, message: &str) {
    match Spec::from_json(text) {
        Err(e @ SpecError::Json { .. }) => {
            assert_eq!(e.path(), path, "{e}");
            assert!(e.to_string().contains(message), "{e}");
            assert!(e.to_string().starts_with(&format!("{path}: ")), "{e}");
        }
        other => panic!("expected a JSON error at {path}, got {other:?}"),
    }
}

const SPRING: &str = r#""w": 0.5, "alpha": 1, "beta": 2, "gamma": 1, "n": 1"#;

#[test]
fn malformed_json_names_the_path() {
    // unknown type, deep
    json_error(
        r#"{"type": "cascade", "first": {"type": "plya", "r": 1}, "second": {"type": "gain", "k": 1}}"#,
        "first.type",
        "unknown variant `plya`, expected one of `play`,",
    );
    // missing field
    json_error(
        r#"{"type": "series", "left": {"type": "mms", "f_c": 1}, "right": {"type": "gain", "k": 1}}"#,
        "left",
        "missing field `k`",
    );
    // missing type
    json_error(
        r#"{"type": "parallel", "left": {"k": 1}, "right": {"type": "gain", "k": 1}}"#,
        "left",
        "missing field `type`",
    );
    // wrong type, deep in a tree and in an array
    json_error(
        &format!(
            r#"{{"type": "inverse", "inner": {{"type": "series",
                "left": {{"type": "gain", "k": 1}},
                "right": {{"type": "bouc_wen", {SPRING},
                          "stiffness": {{"z": [0, 1], "s": [1, "2"]}}}}}}}}"#
        ),
        "inner.right.stiffness.s[1]",
        r#"invalid type: string "2", expected f64"#,
    );
    json_error(
        r#"{"type": "scaled", "w": 1, "inner": "play"}"#,
        "inner",
        r#"invalid type: string "play", expected a spec"#,
    );
    json_error(
        r#"{"type": "scaled", "w": true, "inner": {"type": "gain", "k": 1}}"#,
        "w",
        "invalid type: boolean `true`, expected f64",
    );
    // unknown fields, in a combinator and in a parameter struct
    json_error(
        r#"{"type": "cascade", "first": {"type": "gain", "k": 1}, "second": {"type": "gain", "k": 1}, "third": 1}"#,
        "third",
        "unknown field `third`, expected `first` or `second`",
    );
    json_error(
        r#"{"type": "scaled", "w": 1, "inner": {"type": "play", "r": 1, "y_0": 2}}"#,
        "inner.y_0",
        "unknown field `y_0`, expected `r` or `y0`",
    );
    json_error(
        &format!(
            r#"{{"type": "bouc_wen", {SPRING}, "stiffness": {{"z": [0], "s": [1], "q": 0}}}}"#
        ),
        "stiffness.q",
        "unknown field `q`",
    );
    // travel limits and solver options
    json_error(
        r#"{"type": "series", "left": {"type": "gain", "k": 1}, "right": {"type": "gain", "k": 1},
            "limits": {"type": "slot", "b": 1}}"#,
        "limits.type",
        "unknown variant `slot`, expected one of `none`, `range`, `gap`",
    );
    json_error(
        r#"{"type": "series", "left": {"type": "gain", "k": 1}, "right": {"type": "gain", "k": 1},
            "limits": {"type": "gap"}}"#,
        "limits",
        "missing field `b`",
    );
    json_error(
        r#"{"type": "feedback", "forward": {"type": "gain", "k": 1}, "back": {"type": "gain", "k": 1},
            "solver": {"max_iter": -3}}"#,
        "solver.max_iter",
        "invalid value: integer `-3`, expected usize",
    );
    // `type` not first: the path is still found
    json_error(
        r#"{"first": {"r": "x", "type": "play"}, "type": "cascade", "second": {"type": "gain", "k": 1}}"#,
        "first.r",
        r#"invalid type: string "x", expected f64"#,
    );
    // syntax errors, trailing characters, empty input, out-of-range numbers
    json_error(
        r#"{"type": "gain", "k": 1,}"#,
        "?",
        "trailing comma at line 1 column 25",
    );
    // the root has no readable `type` yet: it is called `spec`, never `.`
    json_error(
        r#"{"type": "gain", "k": 1} x"#,
        "spec",
        "trailing characters",
    );
    json_error("", "spec", "EOF while parsing");
    json_error("[1, 2]", "spec", "invalid type: sequence, expected a spec");
    json_error(r#"{"type": "play"}"#, "play", "missing field `r`");
    json_error(
        r#"{"type": "gain", "k": 1e400}"#,
        "k",
        "number out of range",
    );
}

/// Nesting up to `MAX_DEPTH` operators on one path reads, builds, runs and
/// round-trips; one more is refused by `build` naming `nesting`, and text
/// nested far deeper is refused before it is parsed, not a stack overflow.
#[test]
fn deep_nesting_is_an_error_not_a_crash() {
    // `wrappers` combinators around one play: `wrappers + 1` operators.
    let nested = |wrappers: usize| {
        let mut text = r#"{"type": "play", "r": 0.01}"#.to_string();
        for i in 0..wrappers {
            text = if i % 2 == 0 {
                format!(r#"{{"type": "scaled", "w": 1.0, "inner": {text}}}"#)
            } else {
                format!(
                    r#"{{"type": "cascade", "first": {text}, "second": {{"type": "gain", "k": 1}}}}"#
                )
            };
        }
        text
    };
    let spec = Spec::from_json(&nested(MAX_DEPTH - 1)).unwrap();
    let y = spec.build().unwrap().run(&[0.5, 1.0]).unwrap();
    assert_eq!(y, vec![0.49, 0.99]);
    assert_eq!(
        spec.to_json_pretty().map(|t| Spec::from_json(&t)),
        Ok(Ok(spec))
    );
    let e = Spec::from_json(&nested(MAX_DEPTH))
        .unwrap()
        .build()
        .unwrap_err()
        .to_string();
    assert!(e.contains("nesting: at most 120 operators"), "{e}");
    for wrappers in [130, 5_000] {
        let e = Spec::from_json(&nested(wrappers)).unwrap_err();
        assert!(
            e.to_string().contains("nested deeper than 124 levels"),
            "{e}"
        );
    }
}

/// Fields may come in any order; optional ones may be left out.
#[test]
fn field_order_and_defaults() {
    let a = Spec::from_json(
        r#"{"right": {"k": 2, "type": "gain"}, "limits": {"b": 0.5, "type": "gap"},
            "left": {"type": "play", "r": 0.1}, "type": "series", "solver": {"max_iter": 50}}"#,
    )
    .unwrap();
    let b = Spec::Series {
        left: Box::new(Spec::leaf::<hysteron::operators::Play<f64>>(PlayParams {
            r: 0.1,
            y0: 0.0,
        })),
        right: Box::new(Spec::leaf::<hysteron::operators::Gain<f64>>(
            hysteron::operators::GainParams { k: 2.0 },
        )),
        limits: TravelLimits::Gap { b: 0.5, r0: 0.0 },
        solver: Some(SolverOptions {
            max_iter: 50,
            ..SolverOptions::default()
        }),
    };
    assert_eq!(a, b);
    let none = Spec::from_json(
        r#"{"type": "series", "left": {"type": "gain", "k": 1}, "right": {"type": "gain", "k": 1},
            "limits": {"type": "none"}}"#,
    )
    .unwrap();
    assert!(matches!(
        none,
        Spec::Series {
            limits: TravelLimits::None,
            solver: None,
            ..
        }
    ));
    // serde_json's own entry points accept specs too
    let c: Spec = serde_json::from_str(&b.to_json_pretty().unwrap()).unwrap();
    assert_eq!(c, b);
}

/// Asserts a build error with exactly this message.
#[track_caller]
fn invalid(spec: &Spec, expected: &str) {
    match spec.build() {
        Err(e @ SpecError::Invalid { .. }) => {
            assert_eq!(e.to_string(), expected);
            assert!(matches!(
                e,
                SpecError::Invalid {
                    source: Error::InvalidParameter { .. },
                    ..
                }
            ));
        }
        Err(e) => panic!("expected an invalid parameter, got {e:?}"),
        Ok(m) => panic!("expected an error, built {m:?}"),
    }
}

#[test]
fn invalid_values_name_the_spec_path() {
    // a negative stiffness knot in the spring of a series
    let mut spring = TransmissionParams::default().spring;
    let (z, mut s) = (
        spring.stiffness.knots_z().to_vec(),
        spring.stiffness.knots_s().to_vec(),
    );
    s[3] = -1.0;
    spring.stiffness = serde_json::from_value(serde_json::json!({ "z": z, "s": s })).unwrap();
    let series = Spec::Series {
        left: Box::new(Spec::leaf::<hysteron::operators::Mms<f64>>(
            TransmissionParams::default().friction,
        )),
        right: Box::new(Spec::leaf::<hysteron::operators::BoucWen<f64>>(
            spring.clone(),
        )),
        limits: TravelLimits::Gap { b: 0.3, r0: 0.0 },
        solver: None,
    };
    invalid(
        &series,
        "series.right.bouc_wen.stiffness.s[3]: must be ≥ 0 (got -1)",
    );
    // the same from JSON
    let text = series.to_json_pretty().unwrap();
    invalid(
        &Spec::from_json(&text).unwrap(),
        "series.right.bouc_wen.stiffness.s[3]: must be ≥ 0 (got -1)",
    );

    // deep in a tree
    let deep = Spec::Cascade {
        first: Box::new(Spec::Feedback {
            forward: Box::new(Spec::leaf::<hysteron::operators::Gain<f64>>(
                hysteron::operators::GainParams { k: 1.0 },
            )),
            back: Box::new(Spec::Scaled {
                w: 0.5,
                inner: Box::new(Spec::leaf::<hysteron::operators::Play<f64>>(PlayParams {
                    r: -0.5,
                    y0: 0.0,
                })),
            }),
            solver: None,
        }),
        second: Box::new(Spec::leaf::<hysteron::operators::Gain<f64>>(
            hysteron::operators::GainParams { k: 1.0 },
        )),
    };
    invalid(
        &deep,
        "cascade.first.feedback.back.scaled.inner.play.r: must be ≥ 0 (got -0.5)",
    );

    // the combinators' own parameters
    let gain = || {
        Box::new(Spec::leaf::<hysteron::operators::Gain<f64>>(
            hysteron::operators::GainParams { k: 1.0 },
        ))
    };
    invalid(
        &Spec::Series {
            left: gain(),
            right: gain(),
            limits: TravelLimits::Gap { b: 0.2, r0: 0.3 },
            solver: None,
        },
        "series.limits.r0: must lie in the gap [−b/2, b/2] (got 0.3)",
    );
    invalid(
        &Spec::Inverse {
            inner: gain(),
            solver: Some(SolverOptions {
                max_iter: 0,
                ..SolverOptions::default()
            }),
        },
        "inverse.solver.max_iter: must lie in [1, 100000] (got 0)",
    );
    invalid(
        &Spec::Feedback {
            forward: gain(),
            back: gain(),
            solver: Some(SolverOptions {
                rel_tol: -1e-9,
                ..SolverOptions::default()
            }),
        },
        "feedback.solver.rel_tol: must be ≥ 0 (got -0.000000001)",
    );
    invalid(
        &Spec::Scaled {
            w: f64::NAN,
            inner: gain(),
        },
        "scaled.w: must be finite (got NaN)",
    );
    invalid(
        &Spec::Parallel {
            left: gain(),
            right: Box::new(Spec::leaf::<hysteron::composition::PiBank<f64>>(
                PiBankParams {
                    a0: 1.0,
                    r: vec![0.1, 0.2],
                    w: vec![1.0],
                    y0: vec![],
                },
            )),
        },
        "parallel.right.pi_bank.w: r, w (and y0 if given) must have the same length (got 1)",
    );

    // the named model speaks in its own field names
    let p = TransmissionParams {
        backlash: -0.1,
        ..TransmissionParams::default()
    };
    invalid(
        &Spec::Transmission(p),
        "transmission.backlash: must be > 0 (got -0.1)",
    );
    let p = TransmissionParams {
        slider0: 1.0,
        ..TransmissionParams::default()
    };
    invalid(
        &Spec::Transmission(p),
        "transmission.slider0: must lie in the gap [−b/2, b/2] (got 1)",
    );
    let mut p = TransmissionParams::default();
    p.friction.f_c = 0.0;
    invalid(
        &Spec::Transmission(p),
        "transmission.friction.f_c: must be > 0 (got 0)",
    );
    invalid(
        &Spec::Transmission(TransmissionParams {
            spring,
            ..TransmissionParams::default()
        }),
        "transmission.spring.stiffness.s[3]: must be ≥ 0 (got -1)",
    );
}

#[test]
fn unreadable_file_is_an_io_error() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.json");
    match Spec::from_json_file(&missing) {
        Err(e @ SpecError::Io { .. }) => {
            assert_eq!(e.path(), missing.display().to_string());
        }
        other => panic!("expected an I/O error, got {other:?}"),
    }
    let bad = dir.path().join("bad.json");
    std::fs::write(&bad, r#"{"type": "gain"}"#).unwrap();
    assert!(matches!(
        Spec::from_json_file(&bad),
        Err(SpecError::Json { .. })
    ));
}

// ---------------------------------------------------------------------------
// Example specs
// ---------------------------------------------------------------------------

fn examples_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/specs")
}

/// The example files and the specs they hold.
fn examples() -> Vec<(&'static str, Spec)> {
    let gain = |k| {
        Box::new(Spec::leaf::<hysteron::operators::Gain<f64>>(
            hysteron::operators::GainParams { k },
        ))
    };
    let eight_plays = PiBankParams {
        a0: 0.2,
        r: vec![0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7],
        w: vec![1.0, 0.6, 0.4, 0.3, 0.2, 0.15, 0.1, 0.05],
        y0: vec![],
    };
    vec![
        // The paper's model (illustrative default parameters) from the
        // algebra: MMS slider in a backlash gap, in series with the spring.
        ("paper.json", Spec::from(&TransmissionParams::default())),
        // A Prandtl-Ishlinskii operator with eight plays.
        (
            "prandtl-ishlinskii.json",
            Spec::leaf::<hysteron::composition::PiBank<f64>>(eight_plays.clone()),
        ),
        // The analytic inverse of that operator (a compensator): the same
        // fields, type `pi_inverse`.
        (
            "pi-inverse.json",
            Spec::leaf::<hysteron::composition::PiInverse<f64>>(eight_plays),
        ),
        // A Preisach model with the closed-form two-peak Everett function.
        (
            "preisach.json",
            Spec::leaf::<hysteron::operators::Preisach<f64>>(PreisachParams {
                measure: PreisachMeasure::Tanh {
                    amplitude: 1.0,
                    hc: 0.4,
                    w: 0.25,
                    x_min: -1.5,
                    x_max: 1.5,
                },
                start: PreisachStart::FromBelow,
            }),
        ),
        // Backlash (play) followed by a dead-zone.
        (
            "play-deadzone.json",
            Spec::Cascade {
                first: Box::new(Spec::leaf::<hysteron::operators::Play<f64>>(PlayParams {
                    r: 0.2,
                    y0: 0.0,
                })),
                second: Box::new(Spec::leaf::<hysteron::operators::DeadZone<f64>>(
                    DeadZoneParams {
                        b_l: -0.1,
                        b_r: 0.1,
                    },
                )),
            },
        ),
        // A spring in parallel with MMS friction, closed by a compliant
        // return path: y = (spring + friction)[x − c·y].
        (
            "friction-spring-feedback.json",
            Spec::Feedback {
                forward: Box::new(Spec::Parallel {
                    left: gain(8.0),
                    right: Box::new(Spec::leaf::<hysteron::operators::Mms<f64>>(MmsParams {
                        f_c: 1.0,
                        k: 40.0,
                        y0: 0.0,
                    })),
                }),
                back: gain(0.05),
                solver: Some(SolverOptions {
                    rel_tol: 1e-14,
                    abs_tol: 1e-300,
                    max_iter: 100,
                    max_expansions: 64,
                }),
            },
        ),
        // Maxwell-slip friction: six elastoplastic elements whose
        // break-away displacements F_i/k_i spread from 0.02 to 0.6.
        (
            "maxwell-slip.json",
            Spec::leaf::<hysteron::operators::MaxwellSlip<f64>>(MaxwellSlipParams {
                k: vec![25.0, 10.0, 6.0, 4.0, 2.5, 1.5],
                f_b: vec![0.5, 0.4, 0.36, 0.32, 0.25, 0.9],
                f0: vec![],
            }),
        ),
        // Dahl friction with Dahl's exponent 1.
        (
            "dahl.json",
            Spec::leaf::<hysteron::operators::Dahl<f64>>(DahlParams {
                sigma: 20.0,
                f_c: 1.0,
                alpha: 1.0,
                f0: 0.0,
            }),
        ),
        // LuGre friction sampled at 100 Hz (rate-dependent: `simulate --dt`
        // or `--time-column` overrides the dt).
        (
            "lugre.json",
            Spec::leaf::<hysteron::operators::LuGre<f64>>(common::lugre_at_100_hz()),
        ),
        // Generalized Maxwell-slip friction sampled at 100 Hz: four
        // elements, Stribeck velocity 0.5, attraction rate 20 per second.
        (
            "gms.json",
            Spec::leaf::<hysteron::operators::Gms<f64>>(GmsParams {
                k: vec![25.0, 10.0, 4.0, 1.5],
                alpha: vec![0.4, 0.3, 0.2, 0.1],
                f0: vec![],
                c: 20.0,
                f_c: 1.0,
                f_s: 1.5,
                v_s: 0.5,
                delta: 2.0,
                sigma2: 0.2,
                dt: 0.01,
            }),
        ),
    ]
}

/// Rewrites `examples/specs/` from [`examples`].
#[test]
#[ignore = "writes the example files"]
fn write_example_specs() {
    let dir = examples_dir();
    std::fs::create_dir_all(&dir).unwrap();
    for (name, spec) in examples() {
        std::fs::write(dir.join(name), spec.to_json_pretty().unwrap() + "\n").unwrap();
    }
}

/// Every file in `examples/specs/` parses, builds and runs on a sine; the
/// documented ones hold exactly what their generators give.
#[test]
fn example_specs_parse_build_and_run() {
    let xs = sine(300, 1.2);
    let mut seen = Vec::new();
    for entry in std::fs::read_dir(examples_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("json") {
            continue;
        }
        let spec = Spec::from_json_file(&path).unwrap_or_else(|e| panic!("{e}"));
        let mut model = spec
            .build()
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let ys = model
            .run(&xs)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(ys.iter().all(|y| y.is_finite()), "{}", path.display());
        assert!(
            ys.iter().any(|&y| y != 0.0),
            "{}: no output",
            path.display()
        );
        seen.push((
            path.file_name().unwrap().to_string_lossy().to_string(),
            spec,
        ));
    }
    for (name, expected) in examples() {
        let found = seen.iter().find(|(n, _)| n == name);
        assert_eq!(
            found.map(|(_, s)| s),
            Some(&expected),
            "{name} differs from its generator (rerun write_example_specs?)"
        );
    }
}

#[test]
fn loose_solver_tolerances_and_deep_implicit_nesting_are_rejected() {
    let loose = r#"{"type":"series","left":{"type":"gain","k":1.0},"right":{"type":"gain","k":1.0},
        "solver":{"rel_tol":0.5}}"#;
    let e = Spec::from_json(loose).unwrap().build().unwrap_err();
    assert!(e.to_string().contains("rel_tol"), "{e}");
    let mut spec = r#"{"type":"gain","k":2.0}"#.to_string();
    for _ in 0..5 {
        spec = format!(r#"{{"type":"inverse","inner":{spec}}}"#);
    }
    let s = Spec::from_json(&spec).unwrap();
    assert_eq!(s.implicit_depth(), 5);
    let e = s.build().unwrap_err();
    assert!(e.to_string().contains("nesting"), "{e}");
}

// ---------------------------------------------------------------------------
// Rate-dependent operators
// ---------------------------------------------------------------------------

fn msd_params(dt: f64) -> MassSpringDamperParams<f64> {
    MassSpringDamperParams {
        m: 0.5,
        c: 3.0,
        k: 200.0,
        dt,
    }
}

/// The three rate-dependent variants read from JSON, written back
/// unchanged, and built into exactly the library's operators.
#[test]
fn rate_dependent_specs_round_trip_build_and_run() {
    let xs = sine(300, 1.2);
    let check = |text: &str, expected: &Spec, mut direct: Box<dyn Operator<f64>>| {
        let spec = Spec::from_json(text).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(&spec, expected);
        let json = spec.to_json_pretty().unwrap();
        assert_eq!(Spec::from_json(&json).unwrap(), spec);
        let mut model = spec.build().unwrap();
        assert_eq!(model.param_names(), direct.param_names(), "{text}");
        assert_eq!(bits(&model.params()), bits(&direct.params()));
        let ys = model.run(&xs).unwrap();
        assert!(ys.iter().any(|&y| y != 0.0), "{text}");
        assert_eq!(bits(&ys), bits(&direct.run(&xs).unwrap()), "{text}");
        // with_params of its own parameters is the same spec
        assert_eq!(spec.with_params(&model.params()).unwrap(), spec);
        spec
    };
    let msd = check(
        r#"{"type": "mass_spring_damper", "m": 0.5, "c": 3, "k": 200, "dt": 0.01}"#,
        &Spec::leaf::<hysteron::operators::MassSpringDamper<f64>>(msd_params(0.01)),
        Box::new(MassSpringDamper::from_params(msd_params(0.01)).unwrap()),
    );
    assert_eq!(msd.kind(), "mass_spring_damper");
    assert_eq!(msd.build().unwrap().param_names().len(), 3);
    let damper = check(
        r#"{"type": "viscous_damper", "c": 2.5, "dt": 0.02}"#,
        &Spec::leaf::<hysteron::operators::ViscousDamper<f64>>(
            hysteron::operators::ViscousDamperParams { c: 2.5, dt: 0.02 },
        ),
        Box::new(ViscousDamper::new(2.5, 0.02).unwrap()),
    );
    assert_eq!(damper.kind(), "viscous_damper");
    assert_eq!(damper.describe(), "viscous_damper[dt=0.02]");
    let over = check(
        r#"{"type": "oversample", "q": 4,
            "inner": {"type": "mass_spring_damper", "m": 0.5, "c": 3, "k": 200, "dt": 0.0025}}"#,
        &Spec::Oversample {
            inner: Box::new(Spec::leaf::<hysteron::operators::MassSpringDamper<f64>>(
                msd_params(0.0025),
            )),
            q: 4,
        },
        Box::new(
            Oversample::new(
                MassSpringDamper::from_params(msd_params(0.0025)).unwrap(),
                4,
            )
            .unwrap(),
        ),
    );
    assert_eq!(over.kind(), "oversample");
    assert_eq!(
        over.describe(),
        "oversample[q=4](mass_spring_damper[dt=0.0025])"
    );
    assert_eq!(over.implicit_depth(), 0);
    assert_eq!(over.children().len(), 1);
    // oversample is not implicit itself, but counts what it holds
    let inv = Spec::from_json(
        r#"{"type": "oversample", "q": 2, "inner": {"type": "inverse", "inner": {"type": "gain", "k": 2}}}"#,
    )
    .unwrap();
    assert_eq!(inv.implicit_depth(), 1);
    // q = 1 runs the inner operator itself, bit for bit
    let one = check(
        r#"{"type": "oversample", "q": 1, "inner": {"type": "viscous_damper", "c": 2.5, "dt": 0.02}}"#,
        &Spec::Oversample {
            inner: Box::new(Spec::leaf::<hysteron::operators::ViscousDamper<f64>>(
                hysteron::operators::ViscousDamperParams { c: 2.5, dt: 0.02 },
            )),
            q: 1,
        },
        Box::new(Oversample::new(ViscousDamper::new(2.5, 0.02).unwrap(), 1).unwrap()),
    );
    assert_eq!(
        bits(&one.build().unwrap().run(&xs).unwrap()),
        bits(&damper.build().unwrap().run(&xs).unwrap())
    );
}

#[test]
fn rate_dependent_errors_name_the_path() {
    invalid(
        &Spec::leaf::<hysteron::operators::MassSpringDamper<f64>>(msd_params(0.0)),
        "mass_spring_damper.dt: must be > 0 (got 0)",
    );
    invalid(
        &Spec::leaf::<hysteron::operators::MassSpringDamper<f64>>(MassSpringDamperParams {
            m: -1.0,
            ..msd_params(0.01)
        }),
        "mass_spring_damper.m: must be > 0 (got -1)",
    );
    invalid(
        &Spec::leaf::<hysteron::operators::ViscousDamper<f64>>(
            hysteron::operators::ViscousDamperParams { c: -1.0, dt: 0.01 },
        ),
        "viscous_damper.c: must be ≥ 0 (got -1)",
    );
    invalid(
        &Spec::Scaled {
            w: 2.0,
            inner: Box::new(Spec::Oversample {
                inner: Box::new(Spec::leaf::<hysteron::operators::ViscousDamper<f64>>(
                    hysteron::operators::ViscousDamperParams { c: 1.0, dt: -0.1 },
                )),
                q: 2,
            }),
        },
        "scaled.inner.oversample.inner.viscous_damper.dt: must be > 0 (got -0.1)",
    );
    for (q, expected) in [
        (0, "oversample.q: must lie in [1, 100000] (got 0)"),
        (
            1_000_000,
            "oversample.q: must lie in [1, 100000] (got 1000000)",
        ),
    ] {
        invalid(
            &Spec::Oversample {
                inner: Box::new(Spec::leaf::<hysteron::operators::Gain<f64>>(
                    hysteron::operators::GainParams { k: 1.0 },
                )),
                q,
            },
            expected,
        );
    }
    // a rate-dependent leaf may leave dt out (it reads), but does not build
    // until the period is given; fields are strict, q is a count
    for (text, path) in [
        (
            r#"{"type": "mass_spring_damper", "m": 1, "c": 0, "k": 1}"#,
            "mass_spring_damper.dt",
        ),
        (
            r#"{"type": "scaled", "w": 2, "inner": {"type": "viscous_damper", "c": 1}}"#,
            "scaled.inner.viscous_damper.dt",
        ),
    ] {
        let spec = Spec::from_json(text).unwrap();
        let err = spec.build().unwrap_err();
        assert!(matches!(err, SpecError::MissingPeriod { .. }), "{err:?}");
        assert_eq!(err.path(), path);
        assert!(
            err.to_string()
                .starts_with(&format!("{path}: the sample period is not given")),
            "{err}"
        );
        assert!(spec.with_dt(0.1).build().is_ok());
    }
    json_error(
        r#"{"type": "viscous_damper", "c": 1, "dt": 0.1, "k": 2}"#,
        "k",
        "unknown field `k`",
    );
    json_error(
        r#"{"type": "cascade", "first": {"type": "gain", "k": 1},
            "second": {"type": "mass_spring_damper", "m": 1, "c": 0, "k": 1, "dt": 0.1, "mass": 1}}"#,
        "second.mass",
        "unknown field `mass`",
    );
    json_error(
        r#"{"type": "oversample", "q": -1, "inner": {"type": "gain", "k": 1}}"#,
        "q",
        "invalid value",
    );
    json_error(
        r#"{"type": "oversample", "q": 2.5, "inner": {"type": "gain", "k": 1}}"#,
        "q",
        "invalid type",
    );
    json_error(
        r#"{"type": "oversample", "q": 2, "inner": {"type": "viscous_damper", "dt": 0.1}}"#,
        "inner",
        "missing field `c`",
    );
}

/// `with_dt` sets the sample period of every rate-dependent node as the
/// tree gives it (`dt / q` inside an `oversample`, which once got `dt`) and
/// keeps everything else; `with_params` keeps the dt (it is not a
/// parameter).
#[test]
fn with_dt_sets_the_period_the_tree_gives_every_rate_dependent_node() {
    // the tree, with the oscillator's and the damper's sample periods
    let tree = |msd_dt, damper_dt| Spec::Cascade {
        first: Box::new(Spec::Oversample {
            inner: Box::new(Spec::leaf::<hysteron::operators::MassSpringDamper<f64>>(
                msd_params(msd_dt),
            )),
            q: 3,
        }),
        second: Box::new(Spec::Parallel {
            left: Box::new(Spec::leaf::<hysteron::operators::ViscousDamper<f64>>(
                hysteron::operators::ViscousDamperParams {
                    c: 2.0,
                    dt: damper_dt,
                },
            )),
            right: Box::new(Spec::leaf::<hysteron::operators::Play<f64>>(PlayParams {
                r: 0.1,
                y0: 0.0,
            })),
        }),
    };
    let spec = tree(0.01, 0.02);
    let expected = tree(0.5 / 3.0, 0.5);
    assert_eq!(spec.with_dt(0.5), expected);
    assert!(spec.is_rate_dependent());
    // rate-independent trees are unchanged
    let paper = Spec::from(&TransmissionParams::default());
    assert_eq!(paper.with_dt(0.5), paper);
    assert!(!paper.is_rate_dependent());
    // parameters: m, c, k of the oscillator, c of the damper, r, y0 of the play
    let model = spec.build().unwrap();
    let p = model.params();
    assert_eq!(p, [0.5, 3.0, 200.0, 2.0, 0.1, 0.0]);
    let q = [1.0, 4.0, 100.0, 0.5, 0.2, 0.0];
    let new = spec.with_params(&q).unwrap();
    assert_eq!(bits(&new.build().unwrap().params()), bits(&q));
    assert_eq!(new.with_dt(0.5), expected.with_params(&q).unwrap());
    let Spec::Cascade { first, second } = &new else {
        panic!("{new:?}")
    };
    assert_eq!(
        **first,
        Spec::Oversample {
            inner: Box::new(Spec::leaf::<hysteron::operators::MassSpringDamper<f64>>(
                MassSpringDamperParams {
                    m: 1.0,
                    c: 4.0,
                    k: 100.0,
                    dt: 0.01,
                }
            )),
            q: 3,
        }
    );
    assert!(matches!(**second, Spec::Parallel { ref left, .. }
        if **left == Spec::leaf::<hysteron::operators::ViscousDamper<f64>>(hysteron::operators::ViscousDamperParams { c: 0.5, dt: 0.02 })));
    // a new value out of range names the path
    let e = spec
        .with_params(&[1.0, -4.0, 100.0, 0.5, 0.2, 0.0])
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "cascade.first.oversample.inner.mass_spring_damper.c: must be ≥ 0 (got -4)"
    );
    // a bad dt is reported by build
    let e = spec.with_dt(0.0).build().unwrap_err();
    assert_eq!(
        e.to_string(),
        "cascade.first.oversample.inner.mass_spring_damper.dt: must be > 0 (got 0)"
    );
}

/// A generic `series` with a gap whose `r0 ≠ 0` drives its spring from
/// `−r0` at `x = 0`: the spring starts at rest there (`z0 = −r0`, the tie
/// the series declares), so the first sample does not jump (a spring left
/// at `z0 = 0` once jumped by 0.23 Nm), whatever `z0` the spec wrote; the
/// tie is listed and `with_params` keeps it.
#[test]
fn a_series_gap_ties_its_spring_to_rest() {
    let paper = TransmissionParams {
        slider0: 0.1,
        ..TransmissionParams::default()
    };
    let written = |z0: &str| {
        let text = format!(
            r#"{{"type": "series",
                "left": {{"type": "mms", "f_c": 1.5, "k": 30}},
                "right": {{"type": "bouc_wen", "w": 0.6, "alpha": 1, "beta": 2.5, "gamma": 1.5,
                          "n": 1{z0}, "stiffness": {{"z": [0], "s": [10]}}}},
                "limits": {{"type": "gap", "b": 0.3, "r0": 0.1}}}}"#
        );
        Spec::from_json(&text).unwrap()
    };
    let omitted = written("");
    let explicit = written(r#", "z0": -0.1"#);
    let mut stiff = paper.clone();
    stiff.spring.stiffness = StiffnessMap::constant(10.0).unwrap();
    let xs = [0.0, 1e-9, 2e-9, 0.05, 0.4, -0.4, 0.0];
    let run = |s: &Spec| s.build().unwrap().run(&xs).unwrap();
    let reference = run(&Spec::Transmission(stiff));
    assert_eq!(bits(&run(&omitted)), bits(&reference));
    assert_eq!(bits(&run(&explicit)), bits(&reference));
    // no jump: a nanometre of input moves the force by about stiffness ×
    // nanometre
    let y = run(&omitted);
    assert!((y[1] - y[0]).abs() < 1e-7, "{y:?}");
    // the tie is declared, and kept by with_params
    assert_eq!(omitted.tied_params(), ["limits.r0", "right.bouc_wen.z0"]);
    let model = omitted.build().unwrap();
    let names = model.param_names();
    let mut p = model.params();
    let r0 = names.iter().position(|n| n == "limits.r0").unwrap();
    let z0 = names.iter().position(|n| n == "right.bouc_wen.z0").unwrap();
    assert_eq!((p[r0], p[z0]), (0.1, -0.1));
    assert_eq!(omitted.with_params(&p).unwrap(), omitted);
    p[r0] = 0.05;
    let e = omitted.with_params(&p).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("series.right.bouc_wen.z0: must equal −r0"),
        "{e}"
    );
    p[z0] = -0.05;
    let moved = omitted.with_params(&p).unwrap();
    assert_eq!(moved.build().unwrap().params(), p);
    // without a gap, or with another right element, nothing is tied
    let range = Spec::from_json(
        r#"{"type": "series", "left": {"type": "gain", "k": 1},
            "right": {"type": "gain", "k": 2}, "limits": {"type": "gap", "b": 0.3, "r0": 0.1}}"#,
    )
    .unwrap();
    assert!(range.tied_params().is_empty());
}
