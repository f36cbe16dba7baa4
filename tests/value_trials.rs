//! `Hints::trial_value`, the value path an implicit combinator searches
//! its root on over dual numbers, against `trial`: the same values bit for
//! bit, for every leaf of the registry; and a feedback loop over dual
//! numbers that searches on values against the same loop searching over
//! dual numbers.

use hysteron::composition::{Feedback, TravelLimits};
use hysteron::models::benchmark::BoucWenBenchmarkParams;
use hysteron::models::spec::registry::LEAVES;
use hysteron::models::TransmissionParams;
use hysteron::operators::{BoucWen, Differentiable, Dual, Keep, Mms, DUAL_WIDTH};
use hysteron::prelude::*;
use hysteron_operators::Derivatives;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

mod common;

/// The benchmark's parameters with `n = 1.5`: the spring on its table.
fn benchmark_on_its_table() -> BoucWenBenchmarkParams {
    BoucWenBenchmarkParams {
        n: 1.5,
        ..BoucWenBenchmarkParams::published()
    }
}

/// A walk with reversals of every size and stretches held still, scaled
/// to `a`.
fn walk(n: usize, a: f64) -> Vec<f64> {
    let mut x = 0.0;
    (0..n)
        .map(|i| {
            let t = i as f64;
            if i % 37 < 3 {
                return x; // held
            }
            x = a * ((0.031 * t).sin() + 0.4 * (0.17 * t).cos() * (0.007 * t).sin());
            x
        })
        .collect()
}

/// `op` with every parameter seeded (parameter `i` in slot `i mod N`).
fn seeded(op: Box<dyn Operator<Dual>>) -> Box<dyn Operator<Dual>> {
    seeded_in(op, DUAL_WIDTH)
}

/// `op` with parameter `i` seeded in slot `i mod slots`.
fn seeded_in(mut op: Box<dyn Operator<Dual>>, slots: usize) -> Box<dyn Operator<Dual>> {
    let p: Vec<Dual> = (op.params().iter().enumerate())
        .map(|(i, v)| Dual::variable(v.re, i % slots))
        .collect();
    op.set_params(&p).expect("its own values");
    op
}

/// Drives `op` along `xs` (inputs seeded in the last slot, as a dual pass
/// through a combinator hands them on). Before each sample, where
/// `trial_value` gives a value it must be `trial`'s, bit for bit, and a
/// commit right after it must change nothing. Returns how many samples had
/// a value path.
fn check(label: &str, mut op: Box<dyn Operator<Dual>>, xs: &[f64]) -> usize {
    let mut with_path = 0;
    for (i, &x) in xs.iter().enumerate() {
        let mut twin = op.clone();
        let value = op.trial_value(x);
        op.commit();
        let input = Dual::variable(x, DUAL_WIDTH - 1);
        let (t, expected) = (op.trial(input), twin.trial(input));
        match (&t, &expected) {
            (Ok(t), Ok(e)) => {
                assert_eq!(t.output.re.to_bits(), e.output.re.to_bits(), "{label} {i}");
                // (bits: a NaN derivative equals itself here)
                assert_eq!(
                    t.output.eps.map(f64::to_bits),
                    e.output.eps.map(f64::to_bits),
                    "{label} {i}: a commit after trial_value moved the state"
                );
            }
            (Err(_), Err(_)) => {}
            _ => panic!("{label} {i}: {t:?} against {expected:?}"),
        }
        match (value, &t) {
            (Some(Ok(v)), Ok(t)) => {
                with_path += 1;
                assert_eq!(
                    (v.output.to_bits(), v.tangent.to_bits()),
                    (t.output.re.to_bits(), t.tangent.re.to_bits()),
                    "{label} {i}: {v:?} against {t:?}"
                );
            }
            (Some(Ok(v)), Err(e)) => panic!("{label} {i}: {v:?} where trial fails: {e}"),
            _ => {}
        }
        if t.is_ok() {
            op.commit();
        }
    }
    with_path
}

#[test]
fn every_leaf_gives_the_values_of_its_trials() {
    let xs = walk(600, 1.3);
    for leaf in LEAVES {
        let spec = leaf.example_spec();
        let op = seeded(spec.build_dual().expect("example builds over dual numbers"));
        check(leaf.kind(), op, &xs);
    }
}

/// Leaves with a value path, where it must be taken: the oscillator
/// always, the Bouc-Wen spring on its table (`n ≠ 1`) and in closed form
/// (`n = 1`) away from a start at rest.
#[test]
fn the_oscillator_and_the_tabulated_spring_have_value_paths() {
    let p = benchmark_on_its_table();
    // displacements of the benchmark's size (its output RMS is 6.7e-4 m)
    let xs = walk(2000, 6e-4);
    let msd = seeded(p.oscillator().unwrap().to_dual().unwrap());
    assert_eq!(check("mass_spring_damper", msd, &xs), xs.len());
    // (none at the samples held at the start, at rest: there `trial` takes
    // the rest state, not the table or the closed form)
    let at_rest = xs.iter().take_while(|&&x| x == 0.0).count();
    assert!(at_rest > 0);
    // on the table (n = 1.5), and in closed form (n = 1, not seeded: with
    // `n` seeded the general power is tabulated)
    for (label, n) in [("bouc_wen n = 1.5", 1.5), ("bouc_wen n = 1", 1.0)] {
        let spring = BoucWenBenchmarkParams { n, ..p }.spring().unwrap();
        let mut bw = spring.to_dual().unwrap();
        let mut q = bw.params();
        for (i, v) in q.iter_mut().enumerate() {
            if bw.param_names()[i] != "n" {
                *v = Dual::variable(v.re, i % DUAL_WIDTH);
            }
        }
        bw.set_params(&q).unwrap();
        let found = check(label, bw, &xs);
        assert_eq!(
            found,
            xs.len() - at_rest,
            "{label}: {found} of {}",
            xs.len()
        );
    }
}

/// An operator as it is, counting its trials over dual numbers, with its
/// value path or without it (and then without its fold of the probe slot).
#[derive(Debug, Clone)]
struct Counted {
    op: Box<dyn Operator<Dual>>,
    value_path: bool,
    trials: Arc<AtomicUsize>,
}
impl Operator<Dual> for Counted {
    fn name(&self) -> &'static str {
        self.op.name()
    }
    common::counted_trials!(Dual, op);
}

impl hysteron_operators::Hints<Dual> for Counted {
    fn trial_value(&mut self, x: f64) -> Option<Result<Trial<f64>>> {
        if self.value_path {
            self.op.trial_value(x)
        } else {
            None
        }
    }
    fn fold_probe(&mut self, along: &Dual) -> bool {
        self.value_path && self.op.fold_probe(along)
    }
    fn batch_while(
        &mut self,
        xs: &[Dual],
        ys: &mut [Dual],
        keep: &mut Keep<'_, Dual>,
    ) -> Option<usize> {
        self.op.batch_while(xs, ys, keep)
    }
}

impl hysteron_operators::SamplePeriod<Dual> for Counted {}

impl hysteron_operators::Parameters<Dual> for Counted {
    common::parameters_of!(Dual, op);
}

impl hysteron_operators::Derivatives<Dual> for Counted {}

/// Runs `xs` through the model `build` makes of its two children (each
/// seeded in `slots` slots, counted, with or without its value path);
/// returns the outputs and the trials over dual numbers per sample.
fn counted_run<M: Operator<Dual>>(
    xs: &[Dual],
    children: (Box<dyn Operator<Dual>>, Box<dyn Operator<Dual>>),
    build: impl Fn(Counted, Counted) -> M,
    value_path: bool,
    slots: usize,
) -> (Vec<Dual>, f64) {
    let trials = Arc::new(AtomicUsize::new(0));
    let child = |op: Box<dyn Operator<Dual>>| Counted {
        op: seeded_in(op, slots),
        value_path,
        trials: trials.clone(),
    };
    let mut model = build(child(children.0), child(children.1));
    let ys = model.run(xs).expect("the model runs");
    (ys, trials.load(Ordering::Relaxed) as f64 / xs.len() as f64)
}

/// The outputs with the value paths and without: the same values bit for
/// bit (the search on values takes the steps of the search over dual
/// numbers), the same derivatives to 1e-9 of each column (the implicit
/// function theorem at the same root), in the first `seeded` slots not all
/// zero.
fn assert_same_outputs(label: &str, by_value: &[Dual], by_duals: &[Dual], seeded: usize) {
    let scale: Vec<f64> = (0..DUAL_WIDTH)
        .map(|k| by_duals.iter().fold(0.0f64, |m, y| m.max(y.eps[k].abs())))
        .collect();
    assert!(
        scale.iter().take(seeded).all(|&s| s > 0.0),
        "{label}: {scale:?}"
    );
    for (i, (a, b)) in by_value.iter().zip(by_duals).enumerate() {
        assert_eq!(a.re.to_bits(), b.re.to_bits(), "{label}: sample {i}");
        for (k, ((p, q), s)) in a.eps.iter().zip(&b.eps).zip(&scale).enumerate() {
            assert!(
                (p - q).abs() <= 1e-9 * s,
                "{label}: sample {i}, slot {k}: {p} against {q}"
            );
        }
    }
}

/// The benchmark's loop (`n = 1.5`) over dual numbers, every parameter
/// seeded, with and without its children's value paths: two trials of
/// each child over dual numbers per sample with them (four without: two
/// Newton steps and two at the root), and the same outputs.
#[test]
fn a_loop_searched_on_values_has_the_roots_and_derivatives_of_one_searched_on_duals() {
    let p = benchmark_on_its_table();
    // a force of 60 N, 25 Hz at 15 kHz, rising from rest
    let xs: Vec<Dual> = (0..6000)
        .map(|i| {
            let t = i as f64 * p.dt();
            let f = 60.0 * (1.0 - (-40.0 * t).exp()) * (25.0 * std::f64::consts::TAU * t).sin();
            Dual::constant(f)
        })
        .collect();
    let children = || {
        (
            p.oscillator().unwrap().to_dual().unwrap(),
            p.spring().unwrap().to_dual().unwrap(),
        )
    };
    // every slot seeded: the probe slot is taken, two evaluations at the
    // root; one slot free: one evaluation, probed and folded
    for (slots, most) in [(DUAL_WIDTH, 4.01), (DUAL_WIDTH - 1, 2.01)] {
        let run = |value_path| counted_run(&xs, children(), Feedback::new, value_path, slots);
        let ((by_value, per_sample), (by_duals, per_sample_duals)) = (run(true), run(false));
        eprintln!("feedback, {slots} slots: trials per sample {per_sample} on values, {per_sample_duals} on duals");
        assert!(per_sample < most, "{per_sample}");
        assert!(per_sample_duals > 5.0, "{per_sample_duals}");
        assert_same_outputs("feedback", &by_value, &by_duals, 6);
    }
}

/// A sample period carrying a derivative in the probe slot (it is not a
/// parameter, so the loop cannot see it): the oscillator refuses to fold,
/// the loop evaluates at its root twice, and the derivatives with respect
/// to the period are those of the search over dual numbers.
#[test]
fn a_probe_slot_taken_by_a_sample_period_is_not_folded() {
    let p = benchmark_on_its_table();
    let xs: Vec<Dual> = (0..3000)
        .map(|i| Dual::constant(60.0 * (25.0 * std::f64::consts::TAU * i as f64 * p.dt()).sin()))
        .collect();
    let run = |value_path| {
        let trials = Arc::new(AtomicUsize::new(0));
        let child = |op| Counted {
            op: seeded_in(op, DUAL_WIDTH - 1),
            value_path,
            trials: trials.clone(),
        };
        let mut msd = child(p.oscillator().unwrap().to_dual().unwrap());
        msd.op
            .set_sample_period(Dual::variable(p.dt(), DUAL_WIDTH - 1))
            .unwrap();
        let spring = child(p.spring().unwrap().to_dual().unwrap());
        let ys = Feedback::new(msd, spring).run(&xs).unwrap();
        (ys, trials.load(Ordering::Relaxed) as f64 / xs.len() as f64)
    };
    let ((by_value, per_sample), (by_duals, _)) = (run(true), run(false));
    assert!(per_sample > 3.0, "{per_sample}");
    assert_same_outputs("feedback, dt seeded", &by_value, &by_duals, DUAL_WIDTH);
}

/// Every leaf that folds its pending trial's probe slot: a trial at a
/// probed input, folded with some derivatives, leaves the state a trial at
/// an input carrying them leaves, to rounding; the oscillator, the
/// friction element and the spring (on its table and in closed form) fold
/// at every sample.
#[test]
fn a_folded_probe_is_a_trial_at_the_derivatives() {
    let folders = ["mass_spring_damper", "mms", "bouc_wen"];
    for leaf in LEAVES {
        let spec = leaf.example_spec();
        let mut op = seeded_in(spec.build_dual().unwrap(), DUAL_WIDTH - 1);
        let xs = walk(400, 1.3);
        let mut folded = 0;
        for (i, &x) in xs.iter().enumerate() {
            let mut along = Dual::constant(x);
            for (k, e) in along.eps.iter_mut().take(DUAL_WIDTH - 1).enumerate() {
                *e = 0.3 * (k as f64 + 1.0) * (0.1 * i as f64).cos();
            }
            let mut direct = op.clone();
            let Ok(t) = direct.trial(along) else {
                break;
            };
            op.trial(Dual::constant(x).probe()).unwrap();
            if op.fold_probe(&along) {
                folded += 1;
                op.commit();
            } else {
                op = direct.clone();
                op.commit();
            }
            direct.commit();
            // the next trial from both states
            let next = Dual::constant(x + 0.01);
            let (a, b) = (op.clone().trial(next), direct.trial(next));
            let (a, b) = (a.unwrap().output, b.unwrap().output);
            assert_eq!(a.re.to_bits(), b.re.to_bits(), "{} {i}", leaf.kind());
            let scale = b
                .eps
                .iter()
                .fold(t.output.re.abs().max(1.0), |m, e| m.max(e.abs()));
            for (k, (p, q)) in a.eps.iter().zip(&b.eps).enumerate() {
                assert!(
                    (p - q).abs() <= 1e-12 * scale,
                    "{} {i} slot {k}: {p} against {q}",
                    leaf.kind()
                );
            }
        }
        if folders.contains(&leaf.kind()) {
            assert_eq!(folded, xs.len(), "{}", leaf.kind());
        }
    }
}

/// The paper's model (friction and spring `n = 1.5` in series in the gap)
/// the same way: fewer trials over dual numbers with the value paths, and
/// the same outputs.
#[test]
fn a_series_searched_on_values_has_the_splits_and_derivatives_of_one_searched_on_duals() {
    let mut p = TransmissionParams::default();
    p.spring.n = 1.5;
    p.spring.h0 = 0.1;
    let n = 4000;
    let xs: Vec<Dual> = (0..n)
        .map(|i| {
            let t = i as f64 / n as f64;
            Dual::constant(1.5 * (-3.0 * t).exp() * (std::f64::consts::TAU * 6.0 * t).sin())
        })
        .collect();
    let children = || {
        (
            Mms::from_params(p.friction).unwrap().to_dual().unwrap(),
            BoucWen::from_params(p.spring_params())
                .unwrap()
                .to_dual()
                .unwrap(),
        )
    };
    let limits = TravelLimits::Gap {
        b: Dual::variable(p.backlash, DUAL_WIDTH - 1),
        r0: Dual::constant(p.slider0),
    };
    let build = |l: Counted, r: Counted| l.series(r).with_limits(limits).unwrap();
    let run = |value_path| counted_run(&xs, children(), build, value_path, DUAL_WIDTH);
    let ((by_value, per_sample), (by_duals, per_sample_duals)) = (run(true), run(false));
    eprintln!("series: trials per sample {per_sample} on values, {per_sample_duals} on duals");
    assert!(
        per_sample < per_sample_duals,
        "{per_sample} against {per_sample_duals}"
    );
    assert_same_outputs("series", &by_value, &by_duals, DUAL_WIDTH);
    // the backlash in slot 0 instead: the probe slot is free, the moving
    // samples take one evaluation at the split instead of two
    let limits = TravelLimits::Gap {
        b: Dual::variable(p.backlash, 0),
        r0: Dual::constant(p.slider0),
    };
    let build = |l: Counted, r: Counted| l.series(r).with_limits(limits).unwrap();
    let run = |value_path| counted_run(&xs, children(), build, value_path, DUAL_WIDTH - 1);
    let ((probed, probed_per_sample), (by_duals, _)) = (run(true), run(false));
    eprintln!("series, probe slot free: trials per sample {probed_per_sample}");
    assert!(
        probed_per_sample < per_sample,
        "{probed_per_sample} against {per_sample}"
    );
    assert_same_outputs("series, probed", &probed, &by_duals, DUAL_WIDTH - 1);
}
