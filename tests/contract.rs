//! The trial/commit contract, checked over every operator and combinator
//! (static, boxed and nested): `process` equals a trial + commit loop bit for
//! bit, and so does `process_while` up to the first refused sample; replay after `reset` is identical; repeated, discarded and failed
//! trials leave no trace; clones are independent; boxed equals static; the
//! flat parameter vector round-trips.

use hysteron::models::spec::registry::{leaf_kind, LEAVES};
use hysteron::models::Spec;
use hysteron::operators::{
    process_while, process_while_beyond, Beyond, Differentiable, Domain, Dual,
};
use hysteron::prelude::*;

mod common;
use common::{bits, trial_commit_loop};

/// A signal with reversals of varying amplitude, repeated samples and a
/// zero crossing, in the range of the paper's experiments.
fn signal<T: Float>() -> Vec<T> {
    let mut xs: Vec<T> = (0..600)
        .map(|i| {
            let t = i as f64;
            T::lit(
                1.4 * (0.045 * t).sin() * (1.0 + 0.3 * (0.011 * t).sin()) + 0.05 * (0.31 * t).sin(),
            )
        })
        .collect();
    // standstills
    xs[100] = xs[99];
    xs[101] = xs[99];
    xs
}

/// The signal and the outputs of a fresh operator on it, to check others
/// against, bit for bit.
struct Reference<'a, T> {
    label: &'a str,
    xs: &'a [T],
    ys: &'a [T],
}

impl<T: Float> Reference<'_, T> {
    /// `op` run on the signal from sample `from` on gives the reference's
    /// outputs there; `what` names the check.
    fn resumed_by(&self, op: &mut impl Operator<T>, from: usize, what: &str) {
        let label = self.label;
        let ys = op
            .run(&self.xs[from..])
            .unwrap_or_else(|e| panic!("{label}: {what}: {e}"));
        assert_eq!(bits(&ys), bits(&self.ys[from..]), "{label}: {what}");
    }
}

/// The bits of each value (exact for `f32` too: widening is exact).
/// The whole contract for one operator, for any scalar.
fn check<T: Float, O: Operator<T> + Clone + 'static>(label: &str, op: O) {
    let xs = signal::<T>();
    let lit = T::lit;
    let fresh = op.clone();

    // process == trial + commit loop, bit for bit
    let mut a = fresh.clone();
    let reference = a.run(&xs).unwrap_or_else(|e| panic!("{label}: {e}"));
    let expected = Reference {
        label,
        xs: &xs,
        ys: &reference,
    };
    let mut b = fresh.clone();
    assert_eq!(
        bits(&trial_commit_loop(&mut b, &xs)),
        bits(&reference),
        "{label}: process vs trial/commit"
    );
    // ... and leaves the same state: trials after either agree, output and
    // tangent (a batch loop that skips state a trial needs shows here)
    let last = xs[xs.len() - 1];
    for probe in [last, last + lit(0.3), last - lit(0.3)] {
        let (ta, tb) = (a.trial(probe), b.trial(probe));
        let (ta, tb) = (ta.unwrap(), tb.unwrap());
        assert_eq!(
            (ta.output.as_f64().to_bits(), ta.tangent.as_f64().to_bits()),
            (tb.output.as_f64().to_bits(), tb.tangent.as_f64().to_bits()),
            "{label}: state after process vs after trial/commit (probe {probe})"
        );
    }

    // An operator that gives its second derivative gives the derivative of
    // its tangent (central differences on the pending trial's branch, over
    // f64, at a few points of the signal), to rounding: the differences'
    // error is about ε times the largest tangent on the way over `h`.
    if T::epsilon().as_f64() < 1e-10 {
        for at in [150, xs.len() / 3, xs.len() - 2] {
            let mut op = fresh.clone();
            let mut t_max = 0.0_f64;
            for &x in &xs[..at] {
                t_max = t_max.max(op.trial(x).unwrap().tangent.as_f64().abs());
                op.commit();
            }
            let (from, x) = (xs[at - 1], xs[at]);
            let c = {
                op.trial(x).unwrap();
                op.trial_curvature()
            };
            let Some(c) = c else { continue };
            let h = (x - from).abs() * lit(1e-3);
            let up = op.trial(x + h).unwrap().tangent;
            let down = op.trial(x - h).unwrap().tangent;
            let fd = ((up - down) / (h + h)).as_f64();
            let rounding = 64.0 * f64::EPSILON * t_max / h.as_f64();
            assert!(
                (c.as_f64() - fd).abs() <= 1e-4 * fd.abs() + rounding,
                "{label}: curvature {} against {fd} at sample {at}",
                c.as_f64()
            );
        }
    }

    // An operator that rests when held gives the committed output again at
    // the committed input, and repeating trial + commit there leaves the
    // state (probed by trials elsewhere) as one trial + commit left it: at
    // a few points of the signal, at a reversal and mid-branch.
    if fresh.rests_when_held() {
        for at in [1, 2, 150, xs.len() / 3, xs.len() - 1] {
            let mut once = fresh.clone();
            once.run(&xs[..at]).unwrap();
            let x = xs[at - 1];
            let first = once.trial(x).unwrap();
            once.commit();
            let mut held = once.clone();
            for _ in 0..3 {
                let t = held.trial(x).unwrap();
                assert_eq!(
                    t.output.as_f64().to_bits(),
                    first.output.as_f64().to_bits(),
                    "{label}: rests when held, but the output moved at sample {at}"
                );
                held.commit();
            }
            for probe in [x, x + lit(0.3), x - lit(0.3)] {
                let (a, b) = (once.trial(probe).unwrap(), held.trial(probe).unwrap());
                assert_eq!(
                    (a.output.as_f64().to_bits(), a.tangent.as_f64().to_bits()),
                    (b.output.as_f64().to_bits(), b.tangent.as_f64().to_bits()),
                    "{label}: rests when held, but holding changed the state (sample {at}, probe {probe})"
                );
            }
        }
    }

    // process_while == trial, keep, commit, stopping uncommitted at the
    // first sample `keep` refuses; `keep` sees each output once, in order
    for cut in [0, 1, 2, 100, 101, 102, xs.len() / 2, xs.len() - 1, xs.len()] {
        let mut p = fresh.clone();
        let mut ys = vec![T::nan(); xs.len()];
        let mut seen = Vec::new();
        let n = process_while(&mut p, &xs, &mut ys, &mut |i, y| {
            seen.push((i, y.as_f64().to_bits()));
            i < cut
        });
        assert_eq!(n, cut, "{label}: process_while stopped at {n}, not {cut}");
        assert_eq!(
            bits(&ys[..n]),
            bits(&reference[..n]),
            "{label}: process_while outputs (cut {cut})"
        );
        let offered: Vec<(usize, u64)> = (0..(cut + 1).min(xs.len()))
            .map(|i| (i, reference[i].as_f64().to_bits()))
            .collect();
        assert_eq!(seen, offered, "{label}: process_while offers (cut {cut})");
        // the refused sample left no trace
        expected.resumed_by(
            &mut p,
            n,
            &format!("process_while refused sample left a trace (cut {cut})"),
        );
    }
    // process_while_beyond == process_while with `Beyond::admits` as keep:
    // bounds at a few outputs of the reference, from above and below
    for at in [0, 1, 100, xs.len() / 2, xs.len() - 1] {
        for beyond in [Beyond::Above(reference[at]), Beyond::Below(reference[at])] {
            let cut = reference
                .iter()
                .position(|&y| !beyond.admits(y))
                .unwrap_or(xs.len());
            let mut p = fresh.clone();
            let mut ys = vec![T::nan(); xs.len()];
            let n = process_while_beyond(&mut p, &xs, &mut ys, beyond);
            assert_eq!(
                n, cut,
                "{label}: process_while_beyond({beyond:?}) stopped at {n}, not {cut}"
            );
            assert_eq!(
                bits(&ys[..n]),
                bits(&reference[..n]),
                "{label}: process_while_beyond outputs ({beyond:?})"
            );
            expected.resumed_by(
                &mut p,
                n,
                &format!("process_while_beyond refused sample left a trace ({beyond:?})"),
            );
        }
    }
    // ... and a failing sample ends it there, uncommitted, without an error
    let mut p = fresh.clone();
    let mut bad = xs.clone();
    bad[150] = T::nan();
    let mut ys = vec![T::zero(); xs.len()];
    assert_eq!(
        process_while(&mut p, &bad, &mut ys, &mut |_, _| true),
        150,
        "{label}: process_while past a NaN"
    );
    assert_eq!(bits(&ys[..150]), bits(&reference[..150]), "{label}");
    expected.resumed_by(&mut p, 150, "process_while failed sample left a trace");

    // replay after reset is identical (twice, and after a partial run)
    a.reset();
    expected.resumed_by(&mut a, 0, "replay after reset");
    a.reset();
    a.run(&xs[..123]).unwrap();
    a.reset();
    expected.resumed_by(&mut a, 0, "reset after partial run");

    // repeated and discarded trials leave no trace
    let mut c = fresh.clone();
    let mut out = Vec::with_capacity(xs.len());
    for (i, &x) in xs.iter().enumerate() {
        for probe in [x + lit(0.37), x - lit(1.1), lit(3.0) * x, -x] {
            c.trial(probe)
                .unwrap_or_else(|e| panic!("{label}: probe {probe}: {e}"));
        }
        let t1 = c.trial(x).unwrap();
        let t2 = c.trial(x).unwrap();
        assert_eq!(
            t1.output.as_f64().to_bits(),
            t2.output.as_f64().to_bits(),
            "{label}: repeated trial at sample {i}"
        );
        assert_eq!(
            t1.tangent.as_f64().to_bits(),
            t2.tangent.as_f64().to_bits(),
            "{label}: repeated tangent at sample {i}"
        );
        c.commit();
        out.push(t1.output);
        // a second commit without a new trial does nothing
        c.commit();
    }
    assert_eq!(
        bits(&out),
        bits(&reference),
        "{label}: discarded trials left a trace"
    );

    // a failed trial (non-finite input) leaves no trace, even after a commit
    let mut d = fresh.clone();
    let half = xs.len() / 2;
    d.run(&xs[..half]).unwrap();
    d.trial(xs[half] + lit(0.5)).unwrap();
    assert!(d.trial(T::nan()).is_err(), "{label}: NaN input accepted");
    d.commit();
    assert!(
        d.trial(T::infinity()).is_err(),
        "{label}: infinite input accepted"
    );
    expected.resumed_by(&mut d, half, "failed trial left a trace");

    // commit on a fresh operator without a trial does nothing
    let mut e = fresh.clone();
    e.commit();
    expected.resumed_by(&mut e, 0, "commit without trial");

    // clones are independent
    let mut f = fresh.clone();
    f.run(&xs[..half]).unwrap();
    let mut g = f.clone();
    g.run(&[lit(5.0), lit(-5.0), lit(2.0)]).unwrap(); // drive the clone elsewhere
    g.reset();
    expected.resumed_by(&mut f, half, "clone shares state");
    expected.resumed_by(&mut g, 0, "reset clone differs");

    // boxed equals static, and a boxed clone of a boxed operator too
    let mut boxed: Box<dyn Operator<T>> = Box::new(fresh.clone());
    expected.resumed_by(&mut boxed, 0, "boxed vs static");
    let mut boxed_clone = boxed.clone();
    boxed_clone.reset();
    expected.resumed_by(&mut boxed_clone, 0, "boxed clone");
    let mut boxed_trials = fresh.clone().boxed();
    assert_eq!(
        bits(&trial_commit_loop(&mut boxed_trials, &xs)),
        bits(&reference),
        "{label}: boxed trials"
    );

    // the parameter vector round-trips and set_params resets
    let mut h = fresh.clone();
    let p = h.params();
    assert_eq!(p.len(), h.n_params(), "{label}: n_params");
    assert_eq!(h.param_names().len(), p.len(), "{label}: param_names");
    let domains = h.param_domains();
    assert_eq!(domains.len(), p.len(), "{label}: param_domains");
    for ((v, d), name) in p.iter().zip(&domains).zip(h.param_names()) {
        assert!(
            d.contains(v.as_f64()),
            "{label}: {name} = {v} outside its domain {d:?}"
        );
    }
    // The domains are tight: a value just outside each bounded one is
    // rejected by set_params (`e` is "just" in this scalar's precision).
    let e = (4.0 * T::epsilon().as_f64()).max(1e-9);
    for (i, d) in domains.iter().enumerate() {
        let outside = match *d {
            Domain::Real => continue,
            Domain::NonNegative => vec![-e],
            Domain::Positive => vec![0.0, -e],
            Domain::NonPositive => vec![e],
            Domain::AtLeast(a) => vec![a - e * a.abs().max(1.0)],
            Domain::UnitInterval => vec![-e, 1.0 + e],
        };
        for v in outside {
            let mut q = p.clone();
            q[i] = T::lit(v);
            assert!(
                h.clone().set_params(&q).is_err(),
                "{label}: {} = {v} accepted outside {d:?}",
                h.param_names()[i]
            );
        }
    }
    h.run(&xs[..half]).unwrap();
    h.set_params(&p).unwrap();
    expected.resumed_by(&mut h, 0, "set_params(params())");
    assert!(
        h.set_params(&p[..p.len().saturating_sub(1)]).is_err() || p.is_empty(),
        "{label}: short vector accepted"
    );

    // the dual twin (`to_dual`, what exact Jacobians run): over `f64`,
    // every operator has one, with the same parameters under the same
    // names, and its values along the signal are the `f64` ones
    if T::epsilon().as_f64() == f64::EPSILON && !T::CARRIES_DERIVATIVES {
        let mut twin = fresh
            .to_dual()
            .unwrap_or_else(|| panic!("{label}: no dual twin"));
        assert_eq!(twin.name(), fresh.name(), "{label}: twin's name");
        assert_eq!(
            twin.param_names(),
            fresh.param_names(),
            "{label}: twin's names"
        );
        assert_eq!(
            twin.params().iter().map(|v| v.re).collect::<Vec<_>>(),
            bits(&fresh.params())
                .into_iter()
                .map(f64::from_bits)
                .collect::<Vec<_>>(),
            "{label}: twin's parameters"
        );
        let dual_xs: Vec<Dual> = xs.iter().map(|x| Dual::constant(x.as_f64())).collect();
        let values: Vec<f64> = twin
            .run(&dual_xs)
            .unwrap_or_else(|e| panic!("{label}: twin: {e}"))
            .iter()
            .map(|y| y.re)
            .collect();
        // (within rounding: dual arithmetic may order a value's operations
        // differently, as `powf` by `exp(n ln x)`)
        let scale = reference
            .iter()
            .fold(1.0f64, |m, y| m.max(y.as_f64().abs()));
        let worst = values
            .iter()
            .zip(&reference)
            .map(|(a, b)| (a - b.as_f64()).abs())
            .fold(0.0f64, f64::max);
        assert!(
            worst <= 1e-12 * scale,
            "{label}: twin's values differ by {worst:e} (scale {scale:e})"
        );
    }

    // mismatched buffers are an error
    let mut ys = vec![T::zero(); 3];
    assert!(matches!(
        fresh.clone().process(&xs[..4], &mut ys),
        Err(Error::LengthMismatch { .. })
    ));
}

/// Every leaf of the spec registry, built from its declared example, in
/// `f64` (boxed, as a spec builds it) and in `f32`; its name is its spec
/// `type`, and its example spec reads back from its own JSON.
#[test]
fn every_registered_leaf_in_f64_and_f32() {
    let mut kinds: Vec<&str> = LEAVES.iter().map(|l| l.kind()).collect();
    kinds.sort_unstable();
    kinds.dedup();
    assert_eq!(kinds.len(), LEAVES.len(), "a kind is registered twice");
    assert!(LEAVES.len() >= 17, "{kinds:?}");
    for leaf in LEAVES {
        let kind = leaf.kind();
        let spec = leaf.example_spec();
        assert_eq!(spec.kind(), kind);
        let text = spec.to_json_pretty().unwrap();
        assert_eq!(
            Spec::from_json(&text).unwrap(),
            spec,
            "{kind}: JSON round trip"
        );
        let op = spec.build().unwrap_or_else(|e| panic!("{kind}: {e}"));
        assert_eq!(op.name(), kind, "one name in the spec and the operator");
        assert!(op.n_params() > 0, "{kind}: no parameters");
        assert!(
            leaf.equation().chars().count() > 5,
            "{kind}: declare the equation it implements (Leaf::EQUATION)"
        );
        let rests = op.rests_when_held();
        check(&format!("{kind} (f64)"), op);
        let op32 = leaf
            .example_f32()
            .unwrap_or_else(|e| panic!("{kind} f32: {e}"));
        assert_eq!(op32.name(), kind);
        // the built spec says what its operator says (a series holding it
        // at a stop relies on it)
        assert_eq!(
            rests,
            op32.rests_when_held(),
            "{kind}: rests_when_held through the spec"
        );
        check(&format!("{kind} (f32)"), op32);
    }
}

fn spring(n: f64) -> BoucWen<f64> {
    BoucWen::from_params(BoucWenParams {
        w: 0.4,
        alpha: 1.0,
        beta: 3.0,
        gamma: 1.0,
        n,
        h0: 0.05,
        z0: 0.0,
        stiffness: StiffnessMap::new(vec![0.0, 0.4, 1.0], vec![6.0, 9.0, 16.0]).unwrap(),
    })
    .unwrap()
}

/// `left` in series with `right` across a centred gap of width `b`.
fn across_gap<A, B>(left: A, b: f64, right: B) -> MechanicalSeries<f64, A, B>
where
    A: Operator<f64> + Clone + 'static,
    B: Operator<f64> + Clone,
{
    left.series(right)
        .with_limits(TravelLimits::Gap { b, r0: 0.0 })
        .unwrap()
}

/// 37 plays: four full chunks of the vector kernels' 8 lanes and a scalar
/// tail of 5, so process (vector) against trial + commit (portable) checks
/// both, bit for bit (`scripts/test.sh` runs this file once more with
/// `HYSTERON_ISA=avx2` and `portable`).
fn pi() -> PiBank<f64> {
    pi_of(37)
}

/// `n` plays with thresholds from 0 to about 1.1 (8 to 64 plays in
/// multiples of 8: the AVX-512 kernel keeps them in registers; other
/// lengths go through its blocks with the plays in memory).
fn pi_of(n: usize) -> PiBank<f64> {
    let r: Vec<f64> = (0..n).map(|j| 1.1 * j as f64 / n as f64).collect();
    let w: Vec<f64> = r.iter().map(|r| (-r).exp() / 4.0).collect();
    PiBank::new(0.2, r, w).unwrap()
}

#[test]
fn leaves() {
    check("play", Play::new(0.3).unwrap());
    check("play r=0", Play::new(0.0).unwrap());
    check(
        "play y0",
        Play::from_params(PlayParams { r: 0.2, y0: 0.7 }).unwrap(),
    );
    check("stop", Stop::new(0.3).unwrap());
    check("elastoplastic", ElastoPlastic::new(12.0, 2.0).unwrap());
    check("deadzone", DeadZone::new(-0.2, 0.5).unwrap());
    check("saturation", Saturation::new(-0.7, 0.4).unwrap());
    check("gain", Gain::new(-2.5).unwrap());
    check("mms", Mms::new(2.0, 15.0).unwrap());
    check(
        "mms y0",
        Mms::from_params(MmsParams {
            f_c: 1.0,
            k: 4.0,
            y0: -0.6,
        })
        .unwrap(),
    );
    for n in [1.0, 1.5, 2.0, 2.7] {
        check(&format!("bouc_wen n={n}"), spring(n));
    }
    for n in [1.5, 2.7] {
        check(
            &format!("bouc_wen n={n} adaptive"),
            spring(n).with_solver(StateSolver::Adaptive),
        );
    }
    check("pi bank", pi());
    // 64 and 8 plays; then banks the AVX-512 kernel does not keep in
    // registers: scalar plays only, and more chunks than registers with a
    // tail
    for n in [64, 8, 5, 100] {
        check(&format!("pi bank of {n}"), pi_of(n));
    }
    check(
        "mass-spring-damper",
        MassSpringDamper::new(2.0, 10.0, 5e4, 1.0 / 750.0).unwrap(),
    );
    check("viscous damper", ViscousDamper::new(3.0, 0.01).unwrap());
    for (label, measure) in preisach_measures() {
        for (start_label, start) in [
            ("", PreisachStart::FromBelow),
            (" from above", PreisachStart::FromAbove),
        ] {
            check(
                &format!("{label}{start_label}"),
                Preisach::from_params(PreisachParams {
                    measure: measure.clone(),
                    start,
                })
                .unwrap(),
            );
        }
    }
    check("maxwell-slip", maxwell_slip());
    check(
        "maxwell-slip one element",
        MaxwellSlip::new(vec![12.0], vec![2.0]).unwrap(),
    );
    for alpha in [0.0, 0.5, 1.0, 2.5] {
        check(
            &format!("dahl α={alpha}"),
            Dahl::new(40.0, 1.5, alpha).unwrap(),
        );
        check(
            &format!("dahl α={alpha} f0 beyond F_c"),
            Dahl::from_params(DahlParams {
                sigma: 40.0,
                f_c: 1.5,
                alpha,
                f0: -2.5,
            })
            .unwrap(),
        );
    }
    check("gms", gms(vec![0.1, -0.3, 0.0]));
    check("gms f0 beyond the limits", gms(vec![0.8, -1.0, 0.5]));
    check("lugre", lugre(100.0, 0.3));
    check("lugre pre-sliding", lugre(2.0, 0.0));
}

/// Five elements, two of them preloaded (one beyond its break-away force).
fn maxwell_slip() -> MaxwellSlip<f64> {
    MaxwellSlip::from_params(MaxwellSlipParams {
        k: vec![30.0, 12.0, 8.0, 5.0, 2.5],
        f_b: vec![0.3, 0.5, 0.9, 1.2, 2.0],
        f0: vec![0.1, 0.0, -0.9, 1.5, 0.0],
    })
    .unwrap()
}

/// GMS at dt = 0.01 on the contract signal: three elements with
/// break-away displacements 0.02–0.3, Stribeck velocity 0.5.
fn gms(f0: Vec<f64>) -> Gms<f64> {
    Gms::from_params(GmsParams {
        k: vec![20.0, 8.0, 1.5],
        alpha: vec![0.3, 0.4, 0.3],
        f0,
        c: 15.0,
        f_c: 1.0,
        f_s: 1.4,
        v_s: 0.5,
        delta: 2.0,
        sigma2: 0.2,
        dt: 0.01,
    })
    .unwrap()
}

/// LuGre at dt = 0.01 on the contract signal (velocities up to ≈ 7,
/// Stribeck velocity 0.5): stiffness `sigma0`, a preloaded bristle.
fn lugre(sigma0: f64, z0: f64) -> LuGre<f64> {
    LuGre::from_params(LuGreParams {
        sigma0,
        sigma1: 0.8,
        sigma2: 0.3,
        f_c: 1.0,
        f_s: 1.4,
        v_s: 0.5,
        delta: 2.0,
        z0,
        dt: 0.01,
    })
    .unwrap()
}

/// One Preisach model per representation, ranges inside and outside the
/// contract signal's (≈ ±1.9, probes to ±5.7).
fn preisach_measures() -> Vec<(&'static str, PreisachMeasure<f64>)> {
    let x = vec![-1.5, -0.7, 0.0, 0.4, 1.2];
    let e = (1..x.len())
        .map(|p| {
            (0..p)
                .map(|q| {
                    let d: f64 = x[p] - x[q];
                    0.3 * d * d + 0.1 * d // uniform density 0.6 plus diagonal mass
                })
                .collect()
        })
        .collect();
    vec![
        (
            "preisach grid",
            PreisachParams::grid_from_density(-1.6, 1.8, 9, |a: f64, b: f64| 1.0 + a * b * 0.1)
                .measure,
        ),
        ("preisach table", PreisachMeasure::Table { x, e }),
        (
            "preisach uniform",
            PreisachMeasure::Uniform {
                mu: 0.8,
                x_min: -1.0,
                x_max: 2.5,
            },
        ),
        (
            "preisach tanh",
            PreisachMeasure::Tanh {
                amplitude: 1.5,
                hc: 0.3,
                w: 0.4,
                x_min: -2.0,
                x_max: 2.0,
            },
        ),
    ]
}

#[test]
fn combinators() {
    check(
        "cascade",
        Play::new(0.2)
            .unwrap()
            .then(DeadZone::symmetric(0.3).unwrap()),
    );
    check("parallel", Stop::new(0.2).unwrap().plus(spring(1.0)));
    check("scaled", Mms::new(1.0, 9.0).unwrap().scaled(-3.0).unwrap());
    check("feedback", spring(1.5).feedback(Gain::new(0.8).unwrap()));
    check(
        "feedback hysteretic loop",
        Gain::new(5.0).unwrap().feedback(Play::new(0.1).unwrap()),
    );
    check(
        "series",
        ElastoPlastic::new(20.0, 1.5)
            .unwrap()
            .series(Gain::new(8.0).unwrap()),
    );
    check(
        "series with gap",
        across_gap(Mms::new(2.0, 40.0).unwrap(), 0.3, spring(1.0)),
    );
    check(
        "series with range",
        Gain::new(3.0)
            .unwrap()
            .series(spring(2.0))
            .with_limits(TravelLimits::Range { lo: -0.05, hi: 0.2 })
            .unwrap(),
    );
    check(
        "feedback rate-dependent",
        MassSpringDamper::new(2.0, 10.0, 5e4, 1.0 / 15000.0)
            .unwrap()
            .feedback(BoucWen::constant(1.0, 0.0, 5e4, 800.0, -1100.0, 1.0).unwrap()),
    );
    check(
        "oversample bouc_wen",
        Oversample::new(spring(1.5), 5).unwrap(),
    );
    check(
        "oversample mass-spring-damper",
        Oversample::new(
            MassSpringDamper::new(2.0, 10.0, 5e4, 1.0 / 15000.0).unwrap(),
            20,
        )
        .unwrap(),
    );
    check(
        "oversample rate-dependent loop",
        Oversample::new(
            MassSpringDamper::new(2.0, 10.0, 5e4, 1.0 / 15000.0)
                .unwrap()
                .feedback(BoucWen::constant(1.0, 0.0, 5e4, 800.0, -1100.0, 1.0).unwrap()),
            20,
        )
        .unwrap(),
    );
    check("inverse", pi().inverse());
    check("inverse bouc_wen", spring(1.0).inverse());
    // (whose curvature, from the spring's, the check compares with
    // differences of its tangent)
    let mut inverse = spring(1.0).inverse();
    inverse.trial(0.3).unwrap();
    assert!(
        inverse.trial_curvature().is_some(),
        "inverse bouc_wen: curvature"
    );
    check(
        "inverse preisach + gain",
        Preisach::from_params(PreisachParams {
            measure: preisach_measures()[3].1.clone(),
            start: PreisachStart::FromBelow,
        })
        .unwrap()
        .plus(Gain::new(0.2).unwrap())
        .inverse(),
    );
    check(
        "maxwell-slip in parallel with lugre",
        maxwell_slip().plus(lugre(100.0, 0.0)),
    );
    check(
        "dahl in series with a spring",
        Dahl::new(40.0, 1.5, 1.0)
            .unwrap()
            .series(Gain::new(20.0).unwrap()),
    );
}

#[test]
fn nested_and_boxed() {
    // A boxed child inside static combinators, and combinators of boxes.
    let friction: Box<dyn Operator<f64>> = Mms::new(1.5, 25.0).unwrap().boxed();
    check(
        "boxed child in series",
        across_gap(friction.clone(), 0.25, spring(1.5)),
    );
    check(
        "cascade of boxes",
        Play::new(0.1)
            .unwrap()
            .boxed()
            .then(spring(1.0).boxed())
            .boxed(),
    );
    check(
        "deep nesting",
        Play::new(0.05)
            .unwrap()
            .then(friction.series(Gain::new(30.0).unwrap()))
            .plus(pi().scaled(0.5).unwrap())
            .feedback(Gain::new(0.3).unwrap())
            .then(Saturation::new(-3.0, 3.0).unwrap()),
    );
    check("inverse in cascade", pi().inverse().then(pi()));
    check("pi inverse", pi().analytic_inverse().unwrap());
    check(
        "pi inverse y0",
        PiInverse::from_params(hysteron::composition::PiBankParams {
            a0: 0.5,
            r: vec![0.0, 0.3, 0.3, 0.8],
            w: vec![0.2, 1.0, -0.3, 0.6],
            y0: vec![0.0, 0.2, 0.2, -0.1],
        })
        .unwrap(),
    );
    check(
        "pi inverse in cascade",
        pi().analytic_inverse().unwrap().then(pi()),
    );
}

/// A bank whose output overflows, or whose input is not finite, at one
/// sample stops there on every kernel path (AVX-512 with plays in
/// registers, in blocks of eight samples or one by one; AVX2 in pairs of
/// samples; the portable loop; `scripts/test.sh` runs this file under
/// each): the error names the sample, the outputs before it are those of
/// trial + commit, and the bank is left as after the last good sample, so
/// it goes on from there as a bank that never saw the bad sample. The bad
/// sample is placed in the first block of eight, inside a later one, at a
/// block's end and in the samples after the last full block.
#[test]
fn a_bad_sample_stops_the_batch_at_its_sample() {
    let bank = |n| {
        let r: Vec<f64> = (0..n).map(|j| 0.1 * j as f64).collect();
        PiBank::new(1e10, r, vec![1e9; n]).unwrap()
    };
    // 1e299 · (1e10 + n · 1e9) overflows; 1e290 does not
    let good: Vec<f64> = (0..27)
        .map(|i| match i % 5 {
            2 => 1e290,
            _ => (0.37 * i as f64).sin(),
        })
        .collect();
    for n in [8, 37, 64] {
        for at in [4, 13, 15, 25] {
            for bad in [1e299, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                let case = format!("{n} plays, {bad:e} at sample {at}");
                let mut xs = good.clone();
                xs[at] = bad;
                let mut p = bank(n);
                let mut ys = vec![0.0; xs.len()];
                let err = p.process(&xs, &mut ys).unwrap_err();
                assert!(
                    matches!(err, hysteron::operators::Error::AtSample { index, .. } if index == at),
                    "{case}: {err}"
                );
                let mut reference = bank(n);
                let expected = trial_commit_loop(&mut reference, &xs[..at]);
                assert_eq!(bits(&ys[..at]), bits(&expected), "{case}");
                // after the error the bank goes on from sample at − 1
                let after = p.run(&xs[at + 1..]).unwrap();
                assert_eq!(
                    bits(&after),
                    bits(&reference.run(&xs[at + 1..]).unwrap()),
                    "{case}"
                );
            }
        }
    }
}

/// Which hints an operator gives along the contract's signal: whether it
/// rests when held, and whether it gave a value-only trial, a curvature
/// and a fold of the probe slot at any sample.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Given {
    rests: bool,
    value: bool,
    curvature: bool,
    fold: bool,
}

impl Given {
    fn and(self, o: Given) -> Given {
        Given {
            rests: self.rests && o.rests,
            value: self.value && o.value,
            curvature: self.curvature && o.curvature,
            fold: self.fold && o.fold,
        }
    }
}

/// Drives `op` (and its dual twin) over the signal and records the hints it
/// gives; a value-only trial that is given must be the values of the
/// trial, bit for bit.
fn given(label: &str, op: Box<dyn Operator<f64>>) -> Given {
    let xs = signal::<f64>();
    let mut f = op.clone();
    let mut d = op
        .to_dual()
        .unwrap_or_else(|| panic!("{label}: no dual twin"));
    let mut g = Given {
        rests: op.rests_when_held(),
        value: false,
        curvature: false,
        fold: false,
    };
    let along = Dual::variable(0.0, 0);
    for &x in &xs[..200] {
        f.trial(x).unwrap_or_else(|e| panic!("{label}: {e}"));
        g.curvature |= f.trial_curvature().is_some();
        f.commit();
        if let Some(v) = d.trial_value(x) {
            let v = v.unwrap_or_else(|e| panic!("{label}: value trial: {e}"));
            let t = d.trial(Dual::constant(x)).unwrap();
            assert_eq!(
                (v.output.to_bits(), v.tangent.to_bits()),
                (t.output.re.to_bits(), t.tangent.re.to_bits()),
                "{label}: value-only trial at {x} differs from the trial's values"
            );
            g.value = true;
        }
        d.trial(Dual::constant(x).probe()).unwrap();
        g.fold |= d.fold_probe(&along);
        d.trial(Dual::constant(x)).unwrap();
        d.commit();
    }
    g
}

/// Every registered leaf inside every combinator keeps the hints the
/// combinator's equation passes on: a cascade or a parallel connection each
/// hint both its parts give, a scaled operator all of its operator's, an
/// oversampled one its rest, a feedback loop its value-only trial where
/// both its paths give theirs. A combinator that forgets to forward a hint fails
/// here, and every wrapped leaf also passes the whole contract (the
/// curvature against differences of the tangent, the rest when held).
#[test]
fn every_registered_leaf_keeps_its_hints_in_every_combinator() {
    let build = |label: &str, v: serde_json::Value| -> Box<dyn Operator<f64>> {
        Spec::from_json(&v.to_string())
            .and_then(|s| s.build())
            .unwrap_or_else(|e| panic!("{label}: {e}"))
    };
    // the partner in a cascade or a parallel connection: the Maxwell-slip
    // element gives every hint
    let mms = serde_json::to_value(leaf_kind("mms").unwrap().example_spec()).unwrap();
    let partner = given("mms", build("mms", mms.clone()));
    assert_eq!(
        partner,
        Given {
            rests: true,
            value: true,
            curvature: true,
            fold: true
        }
    );
    let none = Given {
        rests: false,
        value: false,
        curvature: false,
        fold: false,
    };
    let mut ran = Vec::new();
    for leaf in LEAVES {
        let kind = leaf.kind();
        let l = serde_json::to_value(leaf.example_spec()).unwrap();
        let alone = given(kind, build(kind, l.clone()));
        // a combinator that passes on one hint: the leaf's rests or
        // curvature, or a value-only trial where both the leaf and the
        // partner give one
        let rests = Given {
            rests: alone.rests,
            ..none
        };
        let curvature = Given {
            curvature: alone.curvature,
            ..none
        };
        let value = Given {
            value: alone.value && partner.value,
            ..none
        };
        let cases = [
            (
                "cascade",
                serde_json::json!({"type": "cascade", "first": l, "second": mms}),
                alone.and(partner),
            ),
            (
                "cascade after",
                serde_json::json!({"type": "cascade", "first": mms, "second": l}),
                alone.and(partner),
            ),
            (
                "parallel",
                serde_json::json!({"type": "parallel", "left": l, "right": mms}),
                alone.and(partner),
            ),
            (
                "scaled",
                serde_json::json!({"type": "scaled", "w": 1.0, "inner": l}),
                alone,
            ),
            (
                "oversample",
                serde_json::json!({"type": "oversample", "q": 1, "inner": l}),
                rests,
            ),
            (
                "feedback",
                serde_json::json!({"type": "feedback", "forward": l, "back": mms}),
                value,
            ),
        ];
        for (name, spec, expected) in cases {
            let label = format!("{kind} in {name}");
            let op = build(&label, spec);
            assert_eq!(given(&label, op.clone()), expected, "{label}: hints");
            check(&label, op);
        }
        // the inverse of a leaf that is increasing along the signal (the
        // others have none there): its curvature where the leaf gives one;
        // a series with the Maxwell-slip element, with and without a gap,
        // where the split exists along the signal: its value-only trial
        let implicit = [
            (
                "inverse",
                serde_json::json!({"type": "inverse", "inner": l}),
                curvature,
            ),
            (
                "series",
                serde_json::json!({"type": "series", "left": l, "right": mms}),
                value,
            ),
            (
                "series with a gap",
                serde_json::json!({"type": "series", "left": mms, "right": l,
                    "limits": {"type": "gap", "b": 0.2, "r0": 0.0}}),
                value,
            ),
        ];
        for (name, spec, expected) in implicit {
            let label = format!("{kind} in {name}");
            let op = build(&label, spec);
            if op.clone().run(&signal::<f64>()).is_ok() {
                assert_eq!(given(&label, op), expected, "{label}: hints");
                ran.push(label);
            }
        }
    }
    for case in [
        "bouc_wen in inverse",
        "dead_zone in inverse",
        "mms in series",
        "bouc_wen in series",
        "mass_spring_damper in series",
        "bouc_wen in series with a gap",
    ] {
        assert!(ran.iter().any(|r| r == case), "{case} did not run: {ran:?}");
    }
}
