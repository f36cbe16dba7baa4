//! `MechanicalSeries::process` runs stretches where the left element rests
//! at a travel limit through the right element's `process_while`, in chunks
//! of 256 samples. These tests drive the paper's model over the performance
//! kernel's input, whose stops last longer than one chunk, and series with
//! other children (rate-dependent, boxed, a Bouc-Wen spring with n ≠ 1), and
//! check `process` against the trial + commit loop bit for bit, including
//! the state it leaves behind.

use hysteron::models::{paper_state, PaperModel, Spec, SpecError, TransmissionParams};
use hysteron::prelude::*;

mod common;
use common::{bits, trial_commit_loop};

/// The input of `hysteron bench`: `2.5 sin(2π i/2000) + 0.3 sin(2π i/97.3)`.
fn kernel_input(n: usize) -> Vec<f64> {
    let tau = std::f64::consts::TAU;
    (0..n)
        .map(|i| 2.5 * (tau * i as f64 / 2000.0).sin() + 0.3 * (tau * i as f64 / 97.3).sin())
        .collect()
}

/// The paper's model, static.
fn paper_model() -> Result<PaperModel> {
    TransmissionParams::default().build()
}

/// The same model from its JSON spec (a boxed `series` tree).
fn paper_model_from_json() -> std::result::Result<Box<dyn Operator<f64>>, SpecError> {
    let json = Spec::from(&TransmissionParams::default()).to_json_pretty()?;
    Spec::from_json(&json)?.build()
}

/// `process` (in one call, and split at awkward places) equals the
/// trial + commit loop, and leaves the same state (trials after either
/// agree in output and tangent).
fn same_as_trial_commit<O: Operator<f64> + Clone>(label: &str, op: O, xs: &[f64]) {
    let mut a = op.clone();
    let got = a.run(xs).unwrap_or_else(|e| panic!("{label}: {e}"));
    let mut b = op.clone();
    let want = trial_commit_loop(&mut b, xs);
    assert_eq!(bits(&got), bits(&want), "{label}: process vs trial/commit");
    let last = xs[xs.len() - 1];
    for probe in [last, last + 0.05, last - 0.05, last + 1.0] {
        let (ta, tb) = (a.trial(probe).unwrap(), b.trial(probe).unwrap());
        assert_eq!(
            (ta.output.to_bits(), ta.tangent.to_bits()),
            (tb.output.to_bits(), tb.tangent.to_bits()),
            "{label}: state after process (probe {probe})"
        );
    }
    // Split into calls that end inside stretches at a stop.
    let mut c = op.clone();
    let mut split = Vec::with_capacity(xs.len());
    for part in xs.chunks(777) {
        split.extend(c.run(part).unwrap());
    }
    assert_eq!(bits(&split), bits(&want), "{label}: process in parts");
}

/// The longest stretch of consecutive samples at which the paper model's
/// slider rests at a stop (±b/2), and the stretch it ends in.
fn rest_at_stop(xs: &[f64]) -> (usize, usize) {
    let mut m = paper_model().unwrap();
    let half = 0.5 * hysteron::models::TransmissionParams::default().backlash;
    let (mut run, mut longest) = (0, 0);
    for &x in xs {
        m.trial(x).unwrap();
        m.commit();
        let r = paper_state(&m, x).slider;
        run = if r.abs() == half { run + 1 } else { 0 };
        longest = longest.max(run);
    }
    (longest, run)
}

#[test]
fn paper_model_process_is_the_trial_commit_loop() {
    let xs = kernel_input(20_000);
    // The stops last several chunks of 256 samples, so chunk continuation
    // and the return to the solver at the end of a stop are both covered.
    let (longest, _) = rest_at_stop(&xs);
    println!("longest rest at a stop: {longest} samples");
    assert!(longest > 3 * 256, "{longest}");
    same_as_trial_commit("paper model", paper_model().unwrap(), &xs);
    same_as_trial_commit("paper model boxed", paper_model_from_json().unwrap(), &xs);
}

/// How many samples of `xs` end with the left element of `m` at `lo` or at
/// `hi` (its travel limits).
fn samples_at_limits<L, R>(
    m: &MechanicalSeries<f64, L, R>,
    xs: &[f64],
    lo: f64,
    hi: f64,
) -> (usize, usize)
where
    L: Operator<f64> + Clone,
    R: Operator<f64> + Clone,
{
    let mut m = m.clone();
    m.reset();
    let (mut at_lo, mut at_hi) = (0, 0);
    for &x in xs {
        m.trial(x).unwrap();
        m.commit();
        at_lo += usize::from(m.left_displacement() == lo);
        at_hi += usize::from(m.left_displacement() == hi);
    }
    (at_lo, at_hi)
}

/// Checks that `left` in series with `right` within `limits` rests at
/// both limits for a good part of `xs`, then [`same_as_trial_commit`].
fn check_series<L, R>(label: &str, left: L, right: R, limits: TravelLimits<f64>, xs: &[f64])
where
    L: Operator<f64> + Clone + 'static,
    R: Operator<f64> + Clone + 'static,
{
    // The left element's travel since the start (for a gap: [−b/2 − r0, b/2 − r0]).
    let (lo, hi) = limits.bounds().expect("limits with bounds");
    let m = left.series(right).with_limits(limits).unwrap();
    let (at_lo, at_hi) = samples_at_limits(&m, xs, lo, hi);
    println!("{label}: {at_lo} samples at the lower limit, {at_hi} at the upper");
    assert!(
        at_lo > xs.len() / 10 && at_hi > xs.len() / 10,
        "{label}: {at_lo}, {at_hi}"
    );
    same_as_trial_commit(label, m, xs);
}

fn spring(n: f64) -> BoucWen<f64> {
    BoucWen::constant(10.0, 0.6, 1.0, 2.5, 1.5, n).unwrap()
}

#[test]
fn series_at_limits_with_other_children() {
    let xs = kernel_input(6_000);
    let gap = TravelLimits::Gap { b: 0.3, r0: 0.1 };
    // A rate-dependent left element: its trial at the held split changes
    // with every sample, so it is trialled and committed per sample.
    let msd = MassSpringDamper::new(1e-3, 0.5, 40.0, 1e-3).unwrap();
    check_series("mass-spring-damper in a gap", msd, spring(1.0), gap, &xs);
    // A spring without a batch loop for process_while (n ≠ 1: the default).
    let mms = Mms::new(1.5, 30.0).unwrap();
    check_series(
        "mms and bouc_wen n=1.5 in a gap",
        mms.clone(),
        spring(1.5),
        gap,
        &xs,
    );
    // Range limits.
    let ep = ElastoPlastic::new(30.0, 1.5).unwrap();
    let range = TravelLimits::Range { lo: -0.1, hi: 0.2 };
    check_series(
        "elastoplastic and bouc_wen in a range",
        ep,
        spring(1.0),
        range,
        &xs,
    );
    // Boxed children.
    check_series(
        "boxed children in a gap",
        mms.boxed(),
        spring(1.0).boxed(),
        gap,
        &xs,
    );
}

/// A non-finite input at a stop is reported at its sample, with the samples
/// before it committed, as by the trial + commit loop.
#[test]
fn error_at_a_stop_is_reported_at_its_sample() {
    let mut xs = kernel_input(3_000);
    // Sample 400 is deep in a stretch at a stop.
    let (_, trailing) = rest_at_stop(&xs[..400]);
    assert!(trailing > 100, "{trailing}");
    xs[400] = f64::NAN;
    let mut m = paper_model().unwrap();
    let mut ys = vec![0.0; xs.len()];
    let e = m.process(&xs, &mut ys).unwrap_err();
    assert!(matches!(e, Error::AtSample { index: 400, .. }), "{e:?}");
    let mut reference = paper_model().unwrap();
    let want = trial_commit_loop(&mut reference, &xs[..400]);
    assert_eq!(bits(&ys[..400]), bits(&want));
    // ... and the model goes on from sample 399's state.
    let rest = m.run(&xs[401..]).unwrap();
    let want_rest = trial_commit_loop(&mut reference, &xs[401..]);
    assert_eq!(bits(&rest), bits(&want_rest));
}
