//! The paper's two identification stages on synthetic records.
// The no-panic lints of the workspace Cargo.toml are for the library code.
#![allow(clippy::unwrap_used, clippy::indexing_slicing)]

use hysteron_identify::paper::{
    estimate_plateau, fit_bedstop, fit_joint, fit_spring, identify_paper, joint_start,
    knots_from_points, last_increasing_branch, pick_branch_points, pick_branch_points_smoothed,
    BedstopStage, JointOptions, PaperError, PaperIdentification, PaperOptions, SpringFromPoints,
    SpringShape, SpringStage,
};
use hysteron_identify::FitOptions;
use hysteron_models::experiments::{chirp, sine, DRIVE, FS};
use hysteron_models::TransmissionParams;
use hysteron_operators::Parameters;
use hysteron_operators::{BoucWen, Operator};
use rand::{rngs::StdRng, SeedableRng};
use rand_distr::{Distribution, Normal};
use std::time::Instant;

/// The truth: the illustrative defaults with `n = 1.5` (the default `n = 1`
/// sits on the bound of `n ≥ 1`, which the fit reaches only in the limit)
/// and a nonzero initial state `h0`.
fn truth() -> TransmissionParams {
    let mut p = TransmissionParams::default();
    p.spring.n = 1.5;
    p.spring.h0 = 0.1;
    p
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The spring alone, driven at 0.5 Hz, 1.5 deg, four cycles from rest.
fn spring_record(p: &TransmissionParams) -> (Vec<f64>, Vec<f64>) {
    let x = sine(0.5, 1.5, 4.0, FS).unwrap().x;
    let f = BoucWen::from_params(p.spring.clone())
        .unwrap()
        .run(&x)
        .unwrap();
    (x, f)
}

/// Points at the true knot positions, with the true spring's exact force
/// there on the record's last complete increasing branch.
fn points_at_true_knots(p: &TransmissionParams, x: &[f64]) -> Vec<(f64, f64)> {
    let b = last_increasing_branch(x).unwrap();
    let mut spring = BoucWen::from_params(p.spring.clone()).unwrap();
    spring.run(&x[..=b.start]).unwrap();
    p.spring
        .stiffness
        .knots_z()
        .iter()
        .map(|&z| (z, spring.trial(z).unwrap().output))
        .collect()
}

/// The truth, its spring record `(x, f)`, and the points picked at the true
/// knots.
struct SpringCase {
    t: TransmissionParams,
    x: Vec<f64>,
    f: Vec<f64>,
    points: Vec<(f64, f64)>,
}

fn spring_case() -> SpringCase {
    let t = truth();
    let (x, f) = spring_record(&t);
    let points = points_at_true_knots(&t, &x);
    SpringCase { t, x, f, points }
}

fn perturbed_shape(p: &TransmissionParams) -> SpringShape {
    let s = SpringShape::of(&p.spring);
    SpringShape {
        w: s.w * 1.25,
        beta: s.beta * 0.75,
        gamma: s.gamma * 1.3,
        n: s.n * 1.2,
        h0: s.h0 * 0.7,
        ..s
    }
}

const SPRING_FREE: [&str; 5] = ["w", "beta", "gamma", "n", "h0"];

/// Stage 1 on the record `(x, f)` through `points`, from the
/// [`perturbed_shape`] with every shape parameter free.
fn fit_spring_from_perturbed(
    t: &TransmissionParams,
    x: &[f64],
    f: &[f64],
    points: &[(f64, f64)],
) -> SpringStage {
    fit_spring(
        x,
        f,
        points,
        &perturbed_shape(t),
        &SPRING_FREE,
        &FitOptions::default(),
    )
    .unwrap()
}

/// The relative errors of the fitted spring shape's parameters.
fn shape_errors(got: &SpringShape, want: &SpringShape) -> [(&'static str, f64); 5] {
    [
        ("w", rel(got.w, want.w)),
        ("beta", rel(got.beta, want.beta)),
        ("gamma", rel(got.gamma, want.gamma)),
        ("n", rel(got.n, want.n)),
        ("h0", rel(got.h0, want.h0)),
    ]
}

/// Stage 2 on the record `(x, f)` from the truth with `f_c`, `k` and the
/// backlash scaled by `scale` (in that order), those three free.
fn fit_bedstop_scaled(
    t: &TransmissionParams,
    x: &[f64],
    f: &[f64],
    scale: [f64; 3],
) -> BedstopStage {
    let mut start = t.clone();
    start.friction.f_c *= scale[0];
    start.friction.k *= scale[1];
    start.backlash *= scale[2];
    fit_bedstop(
        x,
        f,
        &start,
        &["limits.b", "f_c", "k"],
        &FitOptions::default(),
    )
    .unwrap()
}

fn noisy(clean: &[f64], fraction: f64, seed: u64) -> (Vec<f64>, f64) {
    let sd = fraction * (clean.iter().map(|v| v * v).sum::<f64>() / clean.len() as f64).sqrt();
    let mut rng = StdRng::seed_from_u64(seed);
    let noise = Normal::new(0.0, sd).unwrap();
    (
        clean.iter().map(|v| v + noise.sample(&mut rng)).collect(),
        sd,
    )
}

#[test]
fn knot_rule_reproduces_the_true_stiffness_and_the_record() {
    let SpringCase { t, x, f, points } = spring_case();
    let shape = SpringShape::of(&t.spring);
    let map = knots_from_points(&x, &points, &shape).unwrap();
    let want = &t.spring.stiffness;
    assert_eq!(map.knots_z(), want.knots_z());
    let worst = map
        .knots_s()
        .iter()
        .zip(want.knots_s())
        .map(|(a, b)| rel(*a, *b))
        .fold(0.0, f64::max);
    println!("knots at the true positions: max relative error of S_i {worst:e}");
    assert!(worst < 1e-12, "{worst:e}");
    // the spring built from them replays the record
    let mut model = SpringFromPoints::new(&x, &points, &shape).unwrap();
    let y = model.run(&x).unwrap();
    let scale = f.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    let err = y
        .iter()
        .zip(&f)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    println!("replay: max |error| {err:e} of max |F| {scale}");
    assert!(err < 1e-10 * scale);
    // and passes through the points on the branch
    let b = last_increasing_branch(&x).unwrap();
    model.reset();
    model.run(&x[..=b.start]).unwrap();
    for &(px, pf) in &points {
        let h = model.trial(px).unwrap().output;
        assert!((h - pf).abs() <= 1e-12 * scale, "{px}: {h} vs {pf}");
    }
}

#[test]
fn stage1_on_the_spring_alone_recovers_the_shape() {
    let SpringCase { t, x, f, points } = spring_case();
    let started = Instant::now();
    let s = fit_spring_from_perturbed(&t, &x, &f, &points);
    let r = &s.report;
    assert!(r.status.converged(), "{:?}", r.status);
    let errs = shape_errors(&SpringShape::of(&s.spring), &SpringShape::of(&t.spring));
    let knots = s
        .spring
        .stiffness
        .knots_s()
        .iter()
        .zip(t.spring.stiffness.knots_s())
        .map(|(a, b)| rel(*a, *b))
        .fold(0.0, f64::max);
    println!(
        "stage 1 (spring alone, points at the true knots): {errs:?}, knots max rel {knots:e}; \
         {} iterations, {} evaluations, rms {:e}, {:?}",
        r.iterations,
        r.evaluations,
        r.rms,
        started.elapsed()
    );
    for (name, e) in errs {
        assert!(e < 1e-6, "{name}: relative error {e:e}");
    }
    assert!(knots < 1e-6, "{knots:e}");
}

#[test]
fn stage1_with_evenly_picked_points_is_close() {
    let t = truth();
    let (x, f) = spring_record(&t);
    let points = pick_branch_points(&x, &f, 12).unwrap();
    let started = Instant::now();
    let s = fit_spring_from_perturbed(&t, &x, &f, &points);
    let r = &s.report;
    let errs = shape_errors(&SpringShape::of(&s.spring), &SpringShape::of(&t.spring));
    let map = &s.spring.stiffness;
    let s_err = (0..=150)
        .map(|i| {
            let z = 1.5 * i as f64 / 150.0;
            rel(map.eval(z).0, t.spring.stiffness.eval(z).0)
        })
        .fold(0.0, f64::max);
    println!(
        "stage 1 (spring alone, 12 points even in x): {errs:?}, S max rel {s_err:e}; \
         nrmse {:?}, {} iterations, {:?}",
        r.nrmse,
        r.iterations,
        started.elapsed()
    );
    assert!(r.status.converged(), "{:?}", r.status);
}

#[test]
fn stage2_on_the_chirp_recovers_the_bedstop() {
    let t = truth();
    let x = chirp(5.0, 0.1, 20.0, FS, |f| DRIVE.amplitude(f)).unwrap().x;
    let started = Instant::now();
    let f = t.build().unwrap().run(&x).unwrap();
    println!("chirp simulation: {:?}", started.elapsed());
    let started = Instant::now();
    let s = fit_bedstop_scaled(&t, &x, &f, [1.3, 0.7, 1.3]);
    let r = &s.report;
    let errs = [
        ("b", rel(s.params.backlash, t.backlash)),
        ("f_c", rel(s.params.friction.f_c, t.friction.f_c)),
        ("k", rel(s.params.friction.k, t.friction.k)),
    ];
    println!(
        "stage 2 (chirp, spring at truth): {errs:?}; {} iterations, {} evaluations, rms {:e}, {:?}",
        r.iterations,
        r.evaluations,
        r.rms,
        started.elapsed()
    );
    assert!(r.status.converged(), "{:?}", r.status);
    for (name, e) in errs {
        assert!(e < 1e-6, "{name}: relative error {e:e}");
    }
}

#[test]
fn stage2_noisy_truth_within_three_standard_errors() {
    let t = truth();
    let x = chirp(5.0, 0.1, 20.0, FS, |f| DRIVE.amplitude(f)).unwrap().x;
    let clean = t.build().unwrap().run(&x).unwrap();
    let (f, sd) = noisy(&clean, 0.01, 11);
    let started = Instant::now();
    let s = fit_bedstop_scaled(&t, &x, &f, [0.7, 1.3, 0.7]);
    let r = &s.report;
    assert!(r.status.converged(), "{:?}", r.status);
    let want = t.build().unwrap().params();
    for p in &r.params {
        let se = p.std_error.expect("standard error");
        let z = (p.value - want[p.index]).abs() / se;
        println!(
            "stage 2 noisy: {}: {:.6} ± {:.2e} (true {}, rel {:.2e}, z = {z:.2})",
            p.name,
            p.value,
            se,
            want[p.index],
            rel(p.value, want[p.index])
        );
        assert!(z < 3.0, "{}: {z:.1} standard errors off", p.name);
    }
    println!(
        "stage 2 noisy: rms {:e} vs noise {sd:e}, {:?}",
        r.rms,
        started.elapsed()
    );
    assert!((r.rms / sd - 1.0).abs() < 0.05);
}

/// Stage 1 with 1 % noise on the force. The knot rule passes the spring
/// exactly through the picked points, so their noise goes into the knots
/// unaveraged (12 points against 8001 samples), and the fit's standard
/// errors treat the knots as exact: raw points give errors of 8–44 % and
/// the truth 1–17 standard errors away. Smoothing the picked forces with a
/// local linear fit over ±25 samples brings the errors to ≤ 9 % (β, γ),
/// 5 % (n), 0.06 % (w), 0.8 % (h0), the truth within about 2.4 standard
/// errors (measured, seed 5). Asserted with margin.
#[test]
fn stage1_noisy_spring_alone_with_smoothed_points() {
    let t = truth();
    let (x, clean) = spring_record(&t);
    let (f, sd) = noisy(&clean, 0.01, 5);
    let started = Instant::now();
    let points = pick_branch_points_smoothed(&x, &f, 12, 25).unwrap();
    let s = fit_spring_from_perturbed(&t, &x, &f, &points);
    let r = &s.report;
    assert!(r.status.converged(), "{:?}", r.status);
    let want = SpringShape::of(&t.spring);
    let bounds = [
        (want.w, 0.005),
        (want.beta, 0.15),
        (want.gamma, 0.15),
        (want.n, 0.1),
        (want.h0, 0.05),
    ];
    for (p, (w, bound)) in r.params.iter().zip(bounds) {
        let e = rel(p.value, w);
        println!(
            "stage 1 noisy (m = 25): {}: {:.6} ± {:.2e} (true {w}, rel {e:.2e}, z = {:.2})",
            p.name,
            p.value,
            p.std_error.unwrap_or(f64::NAN),
            p.std_error.map_or(f64::NAN, |se| (p.value - w).abs() / se)
        );
        assert!(e < bound, "{}: relative error {e:e}", p.name);
    }
    println!(
        "stage 1 noisy: rms {:e} vs noise {sd:e}, {:?}",
        r.rms,
        started.elapsed()
    );
    assert!(r.rms < 1.05 * sd);
}

fn perturbed_start(t: &TransmissionParams) -> TransmissionParams {
    let mut start = t.clone();
    let s0 = perturbed_shape(t);
    start.spring.w = s0.w;
    start.spring.beta = s0.beta;
    start.spring.gamma = s0.gamma;
    start.spring.n = s0.n;
    start.spring.h0 = s0.h0;
    start.friction.f_c *= 1.3;
    start.friction.k *= 0.7;
    start.backlash *= 1.3;
    start
}

/// The full model's own records: its 0.5 Hz major loop (4 cycles at the
/// drive's amplitude, 1.455 deg) and the down-chirp.
fn full_model_records(t: &TransmissionParams) -> [Vec<f64>; 4] {
    let loop_x = sine(0.5, DRIVE.amplitude(0.5), 4.0, FS).unwrap().x;
    let loop_f = t.build().unwrap().run(&loop_x).unwrap();
    let chirp_x = chirp(5.0, 0.1, 20.0, FS, |f| DRIVE.amplitude(f)).unwrap().x;
    let chirp_f = t.build().unwrap().run(&chirp_x).unwrap();
    [loop_x, loop_f, chirp_x, chirp_f]
}

fn errors(p: &TransmissionParams, t: &TransmissionParams) -> [(&'static str, f64); 9] {
    let s_err = (0..=145)
        .map(|i| {
            let z = 0.01 * i as f64;
            rel(p.spring.stiffness.eval(z).0, t.spring.stiffness.eval(z).0)
        })
        .fold(0.0, f64::max);
    [
        ("w", rel(p.spring.w, t.spring.w)),
        ("beta", rel(p.spring.beta, t.spring.beta)),
        ("gamma", rel(p.spring.gamma, t.spring.gamma)),
        ("n", rel(p.spring.n, t.spring.n)),
        ("h0", rel(p.spring.h0, t.spring.h0)),
        ("S on [0, 1.45]", s_err),
        ("b", rel(p.backlash, t.backlash)),
        ("f_c", rel(p.friction.f_c, t.friction.f_c)),
        ("k", rel(p.friction.k, t.friction.k)),
    ]
}

/// `identify_paper` as the paper does it (stage 3 off), on the full model's own loop and
/// chirp with the default backlash (b = 0.3 deg, a fifth of the loop's
/// amplitude). Stage 1 reads the loop as the spring's own, but the spring
/// sees `z = x − r`: the slider's travel across the gap flattens the loop
/// near zero force, and the spring absorbs it (measured: S off by up to
/// 67 %, w 21 %, β 23 %, n 178 %, h0 103 %). With that spring fixed, stage 2
/// finds a degenerate bedstop: b → 0.02 (−93 %), F_c 3×, K → ∞ (a pure
/// Coulomb step). The parameters are **not** recovered; what is achieved is
/// a model that reproduces the loop (nrmse 0.006) and the chirp (nrmse
/// 0.057, from 0.30 at stage 2's start; the starting model, which has the
/// true knots, gives 0.10). Asserted: both fits converge, these nrmse
/// levels (with margin), and stage 2 improves on its start. Stage 3
/// (`stage3_recovers_the_full_model_noise_free`) recovers the model.
#[test]
fn end_to_end_paper_procedure_on_the_full_model() {
    let t = truth();
    let [loop_x, loop_f, chirp_x, chirp_f] = full_model_records(&t);
    let start = perturbed_start(&t);
    let start_nrmse = {
        let y = start.build().unwrap().run(&chirp_x).unwrap();
        nrmse(&y, &chirp_f)
    };
    let started = Instant::now();
    let two_stages = PaperOptions {
        joint: None,
        ..PaperOptions::default()
    };
    let id = identify_paper(&loop_x, &loop_f, &chirp_x, &chirp_f, &start, &two_stages).unwrap();
    assert!(id.joint.is_none());
    assert_eq!(id.params, id.two_stage);
    let (s1, s2) = (&id.spring.report, &id.bedstop);
    println!(
        "end to end (paper's procedure, b = 0.3): {:?}",
        errors(&id.params, &t)
    );
    println!(
        "  stage 1 nrmse {:?} ({} it); stage 2 nrmse {:?} ({} it, start {start_nrmse:.3}); {:?}",
        s1.nrmse,
        s1.iterations,
        s2.nrmse,
        s2.iterations,
        started.elapsed()
    );
    assert!(s1.status.converged(), "{:?}", s1.status);
    assert!(s2.status.converged(), "{:?}", s2.status);
    assert!(s1.nrmse.unwrap() < 0.01);
    assert!(s2.nrmse.unwrap() < 0.08);
    // stage 2 improves on its own start (the stage-1 spring with the
    // starting bedstop) and on the whole starting model
    let stage2_start = TransmissionParams {
        spring: id.spring.spring.clone(),
        ..start.clone()
    };
    let y = stage2_start.build().unwrap().run(&chirp_x).unwrap();
    let stage2_start_nrmse = nrmse(&y, &chirp_f);
    println!("  chirp nrmse at stage 2's start {stage2_start_nrmse:.3}");
    assert!(s2.nrmse.unwrap() < stage2_start_nrmse);
    assert!(s2.nrmse.unwrap() < start_nrmse);
}

/// The stiffness map's knots of stage 3 placed where the truth has them
/// (0, 0.3, …, 1.5 deg): stage 1's knots sit at the 12 points picked on
/// the loop, which cannot coincide with the truth's, and a piecewise-linear
/// map on other knots cannot equal the truth's. Only the positions are
/// given; the values start from stage 1's map resampled there.
fn joint_at_true_knots(t: &TransmissionParams) -> PaperOptions {
    PaperOptions {
        joint: Some(JointOptions {
            knots: Some(t.spring.stiffness.knots_z().to_vec()),
            ..JointOptions::default()
        }),
        ..PaperOptions::default()
    }
}

/// Every parameter of the truth the model has, by name, with its fitted
/// value: the joint fit's free parameters (shape, knot values, backlash,
/// friction) compared with the truth's values at the same indices.
fn joint_errors(id: &PaperIdentification, t: &TransmissionParams) -> Vec<(String, f64, f64)> {
    let want = t.build().unwrap().params();
    let r = &id.joint.as_ref().unwrap().report;
    r.params
        .iter()
        .map(|p| {
            let se = p.std_error.unwrap_or(f64::NAN);
            (
                p.name.clone(),
                rel(p.value, want[p.index]),
                (p.value - want[p.index]).abs() / se,
            )
        })
        .collect()
}

/// The three stages on the truth's own noise-free loop and chirp, from the
/// ±20–30 % start, stage 3's knots at the truth's positions.
fn identify_own_records(t: &TransmissionParams) -> PaperIdentification {
    let [loop_x, loop_f, chirp_x, chirp_f] = full_model_records(t);
    identify_paper(
        &loop_x,
        &loop_f,
        &chirp_x,
        &chirp_f,
        &perturbed_start(t),
        &joint_at_true_knots(t),
    )
    .unwrap()
}

/// Issue 15, item 4: after the paper's two stages, stage 3 (the joint
/// refinement on the loop and the chirp together) recovers every parameter
/// of the full model from its own noise-free records at the default
/// geometry (b = 0.3 deg), from the ±20–30 % start of the other tests:
/// w, β, γ, n, h0, the six knot values (knots at the truth's positions, see
/// [`joint_at_true_knots`]), b, F_c, K, each to ≤ 1e-6 relative (measured:
/// ≤ 2.3e-14, γ). Stage 3 starts from the stage-1 spring and the backlash
/// and Coulomb force of the loop's plateau (measured: width 0.517 for
/// b = 0.3, level 1.30 for F_c = 1.5); stage 2's result is b ≈ 0.01,
/// K ≈ 2e13.
#[test]
fn stage3_recovers_the_full_model_noise_free() {
    let t = truth();
    let started = Instant::now();
    let id = identify_own_records(&t);
    let j = id.joint.as_ref().unwrap();
    let r = &j.report;
    println!(
        "stage 3 (b = 0.3, noise-free): plateau {:?}; stage 2 gave b {:.3e}, K {:.3e}",
        j.plateau, id.two_stage.backlash, id.two_stage.friction.k
    );
    println!(
        "  {} iterations, {} evaluations, nrmse {:?}, records {:?}, κ {:?}; all stages {:?}",
        r.iterations,
        r.evaluations,
        r.nrmse,
        r.records.iter().map(|f| f.nrmse).collect::<Vec<_>>(),
        r.condition_number,
        started.elapsed()
    );
    assert!(r.status.converged(), "{:?}", r.status);
    let errs = joint_errors(&id, &t);
    assert_eq!(
        errs.len(),
        14,
        "w, beta, gamma, n, h0, b, f_c, k, 6 knot values"
    );
    for (name, e, _) in &errs {
        println!("  {name}: relative error {e:.2e}");
        assert!(*e <= 1e-6, "{name}: relative error {e:e}");
    }
    // the identified model is stage 3's, and it is the truth
    assert_eq!(
        id.params.spring.stiffness.knots_z(),
        t.spring.stiffness.knots_z()
    );
    for (a, b) in [
        (id.params.backlash, t.backlash),
        (id.params.friction.f_c, t.friction.f_c),
        (id.params.friction.k, t.friction.k),
        (id.params.spring.n, t.spring.n),
    ] {
        assert!(rel(a, b) <= 1e-6, "{a} vs {b}");
    }
    // the plateau is what put stage 3 in the right basin: the start's
    // bedstop came from it, not from `start`
    let p = j.plateau.unwrap();
    assert_eq!(j.start.backlash, p.width);
    assert_eq!(j.start.friction.f_c, p.level);
    // two passes, K held at the start's in the first
    let first = j.first.as_ref().unwrap();
    assert!(first.params.iter().all(|q| !q.name.ends_with(".k")));
    assert_eq!(first.params.len(), 13);
}

/// Stage 3 on other geometries than the default, noise-free, same
/// procedure and ±20–30 % starts: every parameter to ≤ 1e-6 relative.
fn stage3_recovers(t: &TransmissionParams, label: &str) {
    let started = Instant::now();
    let id = identify_own_records(t);
    let j = id.joint.as_ref().unwrap();
    let worst = joint_errors(&id, t)
        .into_iter()
        .map(|(_, e, _)| e)
        .fold(0.0, f64::max);
    println!(
        "stage 3 ({label}): plateau {:?}; first pass {} it, second {} it; \
         max relative error {worst:.2e}; {:?}",
        j.plateau,
        j.first.as_ref().unwrap().iterations,
        j.report.iterations,
        started.elapsed()
    );
    assert!(j.report.status.converged(), "{:?}", j.report.status);
    for (name, e, _) in joint_errors(&id, t) {
        assert!(e <= 1e-6, "{label}: {name}: relative error {e:e}");
    }
}

/// A stiffer, stronger friction (F_c = 3 Nm, K = 60 /deg): the case for
/// holding `K` in stage 3's first pass. Measured: in one pass
/// (`hold_first` empty) the fit from the plateau's start ran off to
/// K ≈ 10²⁰; in two it recovers everything to ~1e-15.
#[test]
fn stage3_recovers_a_stronger_friction() {
    let mut t = truth();
    t.friction.f_c = 3.0;
    t.friction.k = 60.0;
    stage3_recovers(&t, "F_c = 3, K = 60");
}

/// A small backlash (b = 0.1 deg): the plateau overshoots it 3.5× (width
/// 0.35, mostly the spring's deflection inside the force band), and stage
/// 3 still recovers everything (measured: ~1e-14).
#[test]
fn stage3_recovers_a_small_backlash() {
    let mut t = truth();
    t.backlash = 0.1;
    stage3_recovers(&t, "b = 0.1");
}

/// Issue 15, item 4, with 1 % noise (of each record's RMS force, Gaussian,
/// fixed seeds) on both records: stage 3's estimates lie within 3 of its
/// reported standard errors of the truth, for every parameter (measured:
/// at most 2.1, the fourth knot value; `b` 1.9). The knots are at the
/// truth's positions ([`joint_at_true_knots`]); the picked forces are
/// smoothed over ±25 samples for stage 1 (stage 3 does not use them). The
/// fit's residual RMS is the noise's.
#[test]
fn stage3_noisy_truth_within_three_standard_errors() {
    let t = truth();
    let [loop_x, loop_clean, chirp_x, chirp_clean] = full_model_records(&t);
    let (loop_f, sd_loop) = noisy(&loop_clean, 0.01, 5);
    let (chirp_f, sd_chirp) = noisy(&chirp_clean, 0.01, 6);
    let start = perturbed_start(&t);
    let started = Instant::now();
    let opts = PaperOptions {
        smoothing: 25,
        ..joint_at_true_knots(&t)
    };
    let id = identify_paper(&loop_x, &loop_f, &chirp_x, &chirp_f, &start, &opts).unwrap();
    let r = &id.joint.as_ref().unwrap().report;
    println!(
        "stage 3 noisy: {} iterations, {:?}; all stages {:?}",
        r.iterations,
        r.status,
        started.elapsed()
    );
    assert!(r.status.converged(), "{:?}", r.status);
    let errs = joint_errors(&id, &t);
    assert_eq!(errs.len(), 14);
    for (name, e, z) in &errs {
        println!("  {name}: relative error {e:.2e}, {z:.2} standard errors");
        assert!(*z < 3.0, "{name}: {z:.2} standard errors off");
    }
    for (fit, sd) in r.records.iter().zip([sd_loop, sd_chirp]) {
        println!("  rms {:e} vs noise {sd:e}", fit.rms);
        assert!((fit.rms / sd - 1.0).abs() < 0.05);
    }
}

/// The triangle record 0 → 1 → −1 → 1 → 0 with `quarter` samples on each
/// leg of height 1 and `2 quarter` on each of height 2; each leg's samples
/// start on its first corner and stop a step short of its last.
fn triangle_loop(quarter: usize) -> Vec<f64> {
    let legs: [(f64, f64, usize); 4] = [
        (0.0, 1.0, quarter),
        (1.0, -1.0, 2 * quarter),
        (-1.0, 1.0, 2 * quarter),
        (1.0, 0.0, quarter),
    ];
    legs.into_iter()
        .flat_map(|(a, b, n)| (0..n).map(move |i| a + (b - a) * i as f64 / n as f64))
        .collect()
}

/// Reversals smaller than the threshold are not reversals, and the branch
/// found is the last complete rise.
#[test]
fn reversals_ignore_jitter_and_find_the_last_branch() {
    // up to 1, down to -1, up to 1 (with jitter), down to 0
    let mut x = triangle_loop(50);
    x[210] -= 0.005; // below the reversal threshold (0.02)
    let b = last_increasing_branch(&x).unwrap();
    assert_eq!((b.start, b.end), (150, 250));
    // a rise that ends with the record is not complete
    assert!(matches!(
        last_increasing_branch(&x[..240]),
        Err(PaperError::NoIncreasingBranch { .. })
    ));
    assert!(matches!(
        last_increasing_branch(&[1.0; 5]),
        Err(PaperError::NoIncreasingBranch { .. })
    ));
}

/// The plateau of a synthetic branch: a steep rise, a flat stretch of known
/// width at a known level, a steep rise.
#[test]
fn plateau_of_a_synthetic_loop() {
    // x: 0 → 1 → −1 → 1 → 0; the increasing branch's force: 10 (x + 0.7)
    // up to x = −0.7 (reaches 0), then 0.5 flat (width 0.4), then steep
    let x = triangle_loop(500);
    let rising = |v: f64| {
        if v < -0.35 {
            0.5 + 20.0 * (v + 0.35)
        } else if v < 0.05 {
            0.5
        } else {
            0.5 + 20.0 * (v - 0.05)
        }
    };
    let f: Vec<f64> = x
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            if (1500..2500).contains(&i) {
                rising(v)
            } else {
                -rising(-v)
            }
        })
        .collect();
    let p = estimate_plateau(&x, &f).unwrap();
    println!("{p:?}");
    assert_eq!((p.branch.start, p.branch.end), (1500, 2500));
    assert_eq!(p.level, 0.5);
    // the flat 0.4 plus the band's reach into the two steep parts
    let reach = 2.0 * p.band / 20.0;
    assert!((p.width - (0.4 + reach)).abs() < 0.005, "{}", p.width);
    assert!(matches!(
        estimate_plateau(&x, &vec![1.0; x.len()]),
        Err(PaperError::Data { .. })
    ));
    assert!(matches!(
        estimate_plateau(&x[..1000], &f[..1000]),
        Err(PaperError::NoIncreasingBranch { .. })
    ));
}

/// Stage 3's own errors are typed: bad knot positions, an unknown free
/// name, a bad record (named).
#[test]
fn stage3_bad_inputs_are_typed_errors() {
    let t = truth();
    let [loop_x, loop_f, chirp_x, chirp_f] = full_model_records(&t);
    let opts = FitOptions::default();
    let bad_knots = JointOptions {
        knots: Some(vec![0.5, 0.2]),
        ..JointOptions::default()
    };
    let e = joint_start(&loop_x, &loop_f, &t.spring, &t, &bad_knots).unwrap_err();
    assert!(matches!(e, PaperError::Model(_)), "{e}");
    assert!(e.to_string().contains("joint.knots"), "{e}");
    // a flat loop has no plateau
    let flat = vec![1.0; loop_x.len()];
    assert!(matches!(
        joint_start(&loop_x, &flat, &t.spring, &t, &JointOptions::default()),
        Err(PaperError::Data { .. })
    ));
    // without the plateau, the start's bedstop is kept
    let from_start = JointOptions {
        bedstop_from_plateau: false,
        ..JointOptions::default()
    };
    let (p, plateau) = joint_start(&loop_x, &flat, &t.spring, &t, &from_start).unwrap();
    assert!(plateau.is_none());
    assert_eq!((p.backlash, p.friction.f_c), (t.backlash, t.friction.f_c));
    assert!(matches!(
        fit_joint(&loop_x, &loop_f, &chirp_x, &chirp_f, &t, &["nope"], &opts),
        Err(PaperError::Fit { stage: 3, .. })
    ));
    let mut nan = chirp_f.clone();
    nan[3] = f64::NAN;
    assert!(matches!(
        fit_joint(&loop_x, &loop_f, &chirp_x, &nan, &t, &["f_c"], &opts),
        Err(PaperError::Data {
            record: "chirp",
            ..
        })
    ));
    assert!(matches!(
        fit_joint(
            &loop_x[1..],
            &loop_f,
            &chirp_x,
            &chirp_f,
            &t,
            &["f_c"],
            &opts
        ),
        Err(PaperError::Data { record: "loop", .. })
    ));
}

/// The NRMSE of `y` against the data `d`, as the fit reports it
/// (`metrics::errors`: the RMS error over `d`'s RMS about zero).
fn nrmse(y: &[f64], d: &[f64]) -> f64 {
    hysteron_identify::metrics::errors(y, d).unwrap().nrmse
}

/// Where the paper's assumption holds better (a small backlash, b = 0.05
/// deg, so the slow major loop is mostly the spring's), stage 1 alone gets
/// the spring within 1–36 % (h0 worst), but stage 2 with that spring fixed
/// still collapses (measured: b −94 %, F_c → ∞ with K → 0, a linear spring
/// in place of the friction). Freeing the spring in stage 2 as well
/// ([`PaperOptions::refine_spring_in_stage2`]: shape and knot values,
/// knot positions from stage 1) recovers everything within 5 %: measured
/// b 4.7 %, F_c 0.85 %, K 4.2 %, w 0.11 %, β 0.83 %, γ 0.32 %, n 0.44 %,
/// h0 0.44 %, S 0.9 % (the knots sit at 12 points even in x, not at the
/// true knots, so S cannot be exact). Stage 3 is off here.
#[test]
fn end_to_end_small_backlash_with_the_spring_refined_in_stage2() {
    let mut t = truth();
    t.backlash = 0.05;
    let [loop_x, loop_f, chirp_x, chirp_f] = full_model_records(&t);
    let start = perturbed_start(&t);
    let started = Instant::now();
    let opts = PaperOptions {
        joint: None,
        ..PaperOptions::default()
    }
    .refine_spring_in_stage2();
    let id = identify_paper(&loop_x, &loop_f, &chirp_x, &chirp_f, &start, &opts).unwrap();
    let errs = errors(&id.params, &t);
    println!("end to end (b = 0.05, spring refined in stage 2): {errs:?}");
    println!(
        "  stage 1 nrmse {:?} ({} it); stage 2 nrmse {:?} ({} it); {:?}",
        id.spring.report.nrmse,
        id.spring.report.iterations,
        id.bedstop.nrmse,
        id.bedstop.iterations,
        started.elapsed()
    );
    assert!(id.bedstop.status.converged(), "{:?}", id.bedstop.status);
    for (name, e) in errs {
        assert!(e < 0.1, "{name}: relative error {e:e}");
    }
    assert!(id.bedstop.nrmse.unwrap() < 0.002);
}

#[test]
fn spring_from_points_is_a_well_behaved_operator() {
    let SpringCase { t, x, points, .. } = spring_case();
    let shape = SpringShape::of(&t.spring);
    let mut m = SpringFromPoints::new(&x, &points, &shape).unwrap();
    assert_eq!(m.name(), "spring-from-points");
    assert_eq!(m.param_names(), ["w", "beta", "gamma", "n", "h0"]);
    assert_eq!(m.param_domains().len(), 5);
    let p = m.params();
    assert_eq!(p, vec![0.6, 2.5, 1.5, 1.5, 0.1]);
    for (d, v) in m.param_domains().iter().zip(&p) {
        assert!(d.contains(*v));
    }
    // invalid vectors leave it unchanged
    let y0 = m.clone().run(&x).unwrap();
    for bad in [
        vec![1.5, 2.5, 1.5, 1.5, 0.1],
        vec![0.6, 2.5, 1.5, 0.5, 0.1],
        vec![0.6, f64::NAN, 1.5, 1.5, 0.1],
        vec![0.6, 2.5, 1.5],
    ] {
        assert!(m.set_params(&bad).is_err(), "{bad:?}");
        assert_eq!(m.params(), p);
    }
    // a shape whose denominator vanishes at the z = 0 knot: α = 0 keeps
    // h at h0 = 0, so w·0 + (1 − w)·0 = 0 there
    let flat = SpringShape {
        alpha: 0.0,
        h0: 0.0,
        ..shape
    };
    assert!(matches!(
        SpringFromPoints::new(&x, &points, &flat),
        Err(PaperError::Denominator { index: 0, .. })
    ));
    let mut m2 = m.clone();
    m2.set_params(&[0.5, 2.0, 1.0, 1.2, 0.0]).unwrap();
    assert_ne!(m2.run(&x).unwrap(), y0);
    // a clone replays the original
    m.reset();
    assert_eq!(m.run(&x).unwrap(), y0);
}

#[test]
fn bad_inputs_are_typed_errors() {
    let t = truth();
    let (x, f) = spring_record(&t);
    let shape = SpringShape::of(&t.spring);
    let opts = FitOptions::default();
    let data = |r: Result<Vec<(f64, f64)>, PaperError>| matches!(r, Err(PaperError::Data { .. }));
    assert!(data(pick_branch_points(&[], &[], 12)));
    assert!(data(pick_branch_points(&x, &f[1..], 12)));
    let mut nan = f.clone();
    nan[100] = f64::NAN;
    assert!(data(pick_branch_points(&x, &nan, 12)));
    let mut inf = x.clone();
    inf[7] = f64::INFINITY;
    assert!(data(pick_branch_points(&inf, &f, 12)));
    assert!(matches!(
        pick_branch_points(&x, &f, 1),
        Err(PaperError::TooFewPoints { needed: 2, got: 1 })
    ));
    // a record without a complete increasing branch: one rise, then a fall
    let ramp: Vec<f64> = (0..100).map(|i| (i as f64 * 0.03).sin()).collect();
    assert!(matches!(
        pick_branch_points(&ramp, &ramp, 12),
        Err(PaperError::NoIncreasingBranch { .. })
    ));
    assert!(matches!(
        last_increasing_branch(&[]),
        Err(PaperError::Data { .. })
    ));

    let good = pick_branch_points(&x, &f, 12).unwrap();
    let bad_point = |pts: &[(f64, f64)]| {
        matches!(
            knots_from_points(&x, pts, &shape),
            Err(PaperError::BadPoint { .. })
        )
    };
    assert!(bad_point(&[(-0.1, 1.0), (0.5, 5.0)]));
    assert!(bad_point(&[(0.1, 1.0), (2.0, 5.0)]));
    assert!(bad_point(&[(0.1, 1.0), (0.1, 1.0)]));
    assert!(bad_point(&[(0.1, f64::NAN)]));
    assert!(matches!(
        knots_from_points(&x, &[], &shape),
        Err(PaperError::TooFewPoints { .. })
    ));
    // a negative force on the loaded part: a negative stiffness
    let mut neg = good.clone();
    neg[3].1 = -1.0;
    assert!(matches!(
        knots_from_points(&x, &neg, &shape),
        Err(PaperError::Model(_))
    ));
    let invalid = SpringShape { n: 0.5, ..shape };
    assert!(matches!(
        knots_from_points(&x, &good, &invalid),
        Err(PaperError::Model(_))
    ));
    assert!(matches!(
        fit_spring(&x, &nan, &good, &shape, &SPRING_FREE, &opts),
        Err(PaperError::Data { .. })
    ));
    assert!(matches!(
        fit_spring(&x, &f, &good, &shape, &["alpha"], &opts),
        Err(PaperError::Fit { stage: 1, .. })
    ));
    assert!(matches!(
        fit_spring(&x, &f, &good, &shape, &[], &opts),
        Err(PaperError::Fit { stage: 1, .. })
    ));
    assert!(matches!(
        fit_bedstop(&x, &f, &t, &["nope"], &opts),
        Err(PaperError::Fit { stage: 2, .. })
    ));
    let mut broken = t.clone();
    broken.backlash = -1.0;
    assert!(matches!(
        fit_bedstop(&x, &f, &broken, &["f_c"], &opts),
        Err(PaperError::Model(_))
    ));

    let p = PaperOptions::default();
    let run = |lx: &[f64], lf: &[f64], cx: &[f64], cf: &[f64]| {
        identify_paper(lx, lf, cx, cf, &t, &p).map(|_| ())
    };
    assert!(matches!(
        run(&x, &f, &[], &[]),
        Err(PaperError::Data {
            record: "chirp",
            ..
        })
    ));
    assert!(matches!(
        run(&[], &[], &x, &f),
        Err(PaperError::Data { record: "loop", .. })
    ));
    assert!(matches!(
        run(&x, &f, &x, &nan),
        Err(PaperError::Data {
            record: "chirp",
            ..
        })
    ));
    assert!(matches!(
        run(&ramp, &ramp, &x, &f),
        Err(PaperError::NoIncreasingBranch { record: "loop" })
    ));
    let few = PaperOptions {
        points: 0,
        ..PaperOptions::default()
    };
    assert!(matches!(
        identify_paper(&x, &f, &x, &f, &t, &few),
        Err(PaperError::TooFewPoints { .. })
    ));
    // errors print as one line
    let e = run(&ramp, &ramp, &x, &f).unwrap_err().to_string();
    assert!(
        e.starts_with("loop record: no complete increasing branch"),
        "{e}"
    );
}
