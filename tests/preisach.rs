//! Property tests of the Preisach model (`hysteron::operators::Preisach`)
//! in its four representations (relay grid, tabulated Everett function,
//! uniform density, the closed-form `tanh` family): closed forms, the
//! ideal relay, wiping-out, congruency of minor loops, rate independence,
//! saturation bounds, the memory bound, tangents, the numerical inverse,
//! and parameter validation.
//!
//! The laws with a tolerance print the largest error they measured; run
//! `cargo test --test preisach -- --nocapture` to see them.
//! `LAWS_CASES_FACTOR=k` multiplies the number of random cases.

use hysteron::operators::{Preisach, PreisachMeasure, PreisachParams, PreisachStart};
use hysteron::prelude::*;
use proptest::prelude::*;

mod props;
use props::*;

const EPS: f64 = f64::EPSILON;

// ---------------------------------------------------------------------------
// Models
// ---------------------------------------------------------------------------

fn build(measure: PreisachMeasure<f64>, start: PreisachStart) -> Preisach<f64> {
    Preisach::from_params(PreisachParams { measure, start }).expect("valid model")
}

fn tanh_measure() -> PreisachMeasure<f64> {
    PreisachMeasure::Tanh {
        amplitude: 1.3,
        hc: 0.4,
        w: 0.3,
        x_min: -2.0,
        x_max: 2.0,
    }
}

/// A table sampled from the `tanh` Everett function at uneven nodes (its
/// cell masses are the exact `tanh` masses, all positive).
fn table_measure() -> PreisachMeasure<f64> {
    let x = vec![-2.0, -1.2, -0.5, 0.0, 0.6, 1.3, 2.0];
    let exact = build(tanh_measure(), PreisachStart::FromBelow);
    let e = (1..x.len())
        .map(|p| (0..p).map(|q| exact.everett(x[p], x[q])).collect())
        .collect();
    PreisachMeasure::Table { x, e }
}

fn grid_measure() -> PreisachMeasure<f64> {
    PreisachParams::grid_from_density(-2.0, 2.0, 12, |a: f64, b: f64| {
        (-((a - 0.4).powi(2) + (b + 0.4).powi(2)) / 0.3).exp()
    })
    .measure
}

fn uniform_measure() -> PreisachMeasure<f64> {
    PreisachMeasure::Uniform {
        mu: 0.7,
        x_min: -1.2,
        x_max: 1.5,
    }
}

/// Every representation, from both starts.
fn models() -> Vec<(&'static str, Preisach<f64>)> {
    let mut v = Vec::new();
    for start in [PreisachStart::FromBelow, PreisachStart::FromAbove] {
        v.push(("uniform", build(uniform_measure(), start)));
        v.push(("tanh", build(tanh_measure(), start)));
        v.push(("table", build(table_measure(), start)));
        v.push(("grid", build(grid_measure(), start)));
    }
    v
}

// ---------------------------------------------------------------------------
// Signals
// ---------------------------------------------------------------------------

/// Monotone ramps from `from` through the turning points, `n` samples each.
fn ramps(from: f64, legs: &[(f64, usize)]) -> Vec<f64> {
    let mut xs = Vec::new();
    let mut x = from;
    for &(to, n) in legs {
        for k in 1..=n {
            xs.push(lerp(x, to, k as f64 / n as f64));
        }
        x = to;
    }
    xs
}

/// Turning points (some beyond the input range of the models) with ramps
/// of 1–6 samples.
fn legs(range: f64, len: std::ops::Range<usize>) -> impl Strategy<Value = Vec<(f64, usize)>> {
    prop::collection::vec((-range..range, 1_usize..7), len)
}

// ---------------------------------------------------------------------------
// Closed forms
// ---------------------------------------------------------------------------

/// Uniform density `μ` on `[x_min, x_max]`: `E(α, β) = μ (α − β)²/2`,
/// ascending major branch `y = −E₀ + μ (x − x_min)²`, descending
/// `y = E₀ − μ (x_max − x)²`, and a first-order reversal curve from a
/// maximum `M`: `y = −E₀ + μ (M − x_min)² − μ (M − x)²`. Measured error in
/// units of `E₀` (each output is two or three roundings of quantities of
/// size `≤ E₀`: bound `8 ε E₀`).
#[test]
fn uniform_density_gives_the_quadratic_branches() {
    let (mu, lo, hi) = (0.7, -1.2, 1.5);
    let mut p = build(uniform_measure(), PreisachStart::FromBelow);
    let e0 = mu * (hi - lo) * (hi - lo) / 2.0;
    assert_eq!(p.saturation(), e0);
    for (a, b) in [(1.0, -1.0), (0.3, 0.2), (1.5, -1.2), (0.0, -0.7)] {
        assert_eq!(p.everett(a, b), mu / 2.0 * (a - b) * (a - b), "E({a}, {b})");
    }
    let mut worst: f64 = 0.0;
    let mut cmp = |y: f64, expected: f64| {
        let err = (y - expected).abs() / e0;
        assert!(err <= 8.0 * EPS, "{y} vs {expected}");
        worst = worst.max(err);
    };
    // Negative saturation first, then the ascending major branch.
    p.run(&[-3.0]).unwrap();
    assert_eq!(p.output(), -e0);
    for k in 0..=60 {
        let x = lo + (hi - lo) * k as f64 / 60.0;
        let y = p.run(&[x]).unwrap()[0];
        cmp(y, -e0 + mu * (x - lo) * (x - lo));
    }
    p.run(&[3.0]).unwrap();
    assert_eq!(p.output(), e0, "positive saturation is exactly E₀");
    for k in 0..=60 {
        let x = hi - (hi - lo) * k as f64 / 60.0;
        let y = p.run(&[x]).unwrap()[0];
        cmp(y, e0 - mu * (hi - x) * (hi - x));
    }
    // First-order reversal curves from maxima M.
    for m in [-0.8, 0.1, 0.9] {
        p.run(&[-5.0, m]).unwrap();
        for k in 0..=30 {
            let x = m - (m - lo) * k as f64 / 30.0;
            let y = p.run(&[x]).unwrap()[0];
            cmp(y, -e0 + mu * (m - lo) * (m - lo) - mu * (m - x) * (m - x));
        }
    }
    // The default start: negative saturation, then up to 0.
    let fresh = build(uniform_measure(), PreisachStart::FromBelow);
    cmp(fresh.output(), -e0 + mu * lo * lo);
    let above = build(uniform_measure(), PreisachStart::FromAbove);
    cmp(above.output(), e0 - mu * hi * hi);
    eprintln!("uniform density vs closed form: max {worst:.3e} E₀");
}

/// A grid with one relay (`α`, `β`, weight `w`, the other weights 0) is
/// the ideal relay `w γ_{αβ}`: `+w` once `x ≥ α`, `−w` once `x ≤ β`,
/// unchanged in between; exactly, from both starts.
#[test]
fn single_relay_grid_is_an_ideal_relay() {
    let strategy = (
        -1.0..1.0f64,
        0.0..1.0f64,
        0.1..3.0f64,
        any::<bool>(),
        legs(2.0, 1..25),
    );
    measure(
        "single relay vs ideal relay (exact)",
        512,
        strategy,
        |(beta, width, w, above, legs)| {
            let alpha = beta + width;
            // With α = β the grid has one level: a relay without hysteresis.
            let (t, mu) = if width == 0.0 {
                (vec![alpha], vec![vec![w]])
            } else {
                (vec![beta, alpha], vec![vec![0.0], vec![w, 0.0]])
            };
            let start = if above {
                PreisachStart::FromAbove
            } else {
                PreisachStart::FromBelow
            };
            let mut p = ok(Preisach::from_params(PreisachParams {
                measure: PreisachMeasure::Grid { t, mu },
                start,
            }))?;
            // Initial state: saturated, then moved to 0.
            let mut state = if above { 1.0 } else { -1.0 };
            if 0.0 >= alpha && !above {
                state = 1.0;
            }
            if 0.0 <= beta && above {
                state = -1.0;
            }
            let xs = ramps(0.0, &legs);
            let ys = ok(p.run(&xs))?;
            let mut prev = 0.0;
            for (&x, &y) in xs.iter().zip(&ys) {
                if x >= alpha && x <= beta {
                    // α = β = x: the relay follows the direction of arrival.
                    if x > prev {
                        state = 1.0;
                    } else if x < prev {
                        state = -1.0;
                    }
                } else if x >= alpha {
                    state = 1.0;
                } else if x <= beta {
                    state = -1.0;
                }
                prop_assert_eq!(y, w * state, "x = {}", x);
                prev = x;
            }
            Ok(0.0)
        },
    );
}

// ---------------------------------------------------------------------------
// Wiping-out, congruency, rate independence, bounds
// ---------------------------------------------------------------------------

/// Wiping-out: after a common prefix ending at `x_p`, two histories that
/// wander differently inside `[x_p, M]` (or `[M, x_p]`) and then reach `M`
/// give bit-identical outputs from `M` on: the extrema inside are erased.
#[test]
fn wiping_out_erases_the_inner_history() {
    let strategy = (
        legs(2.5, 0..8),
        prop::collection::vec(0.0..1.0f64, 0..12),
        prop::collection::vec(0.0..1.0f64, 0..12),
        0.0..2.0f64,
        any::<bool>(),
        legs(2.5, 1..8),
    );
    let models = models();
    measure(
        "wiping-out (bitwise)",
        512,
        strategy,
        |(prefix, d1, d2, reach, down, tail)| {
            let pre = ramps(0.0, &prefix);
            let xp = pre.last().copied().unwrap_or(0.0);
            let m = if down { xp - reach } else { xp + reach };
            let inner = |d: &[f64]| d.iter().map(|&t| lerp(xp, m, t)).collect::<Vec<_>>();
            let after: Vec<f64> = std::iter::once(m).chain(ramps(m, &tail)).collect();
            let h1: Vec<f64> = pre.iter().copied().chain(inner(&d1)).collect();
            let h2: Vec<f64> = pre.iter().copied().chain(inner(&d2)).collect();
            for (name, model) in &models {
                let (mut a, mut b) = (model.clone(), model.clone());
                ok(a.run(&h1))?;
                ok(b.run(&h2))?;
                let ya = ok(a.run(&after))?;
                let yb = ok(b.run(&after))?;
                prop_assert_eq!(bits(&ya), bits(&yb), "{}", name);
            }
            Ok(0.0)
        },
    );
}

/// Congruency of minor loops: two different histories, each ending with
/// an excursion above `u2` and a fall to `u1`, then the same loop
/// `u1 → u2 → u1`: the outputs differ by a constant along the loop. The
/// measured deviation from the constant, in units of `E₀`, is rounding
/// (each output `2P − E₀` carries `≤ 2` roundings of sums of size `≤ E₀`,
/// so a difference of differences `≤ 8 ε E₀`).
#[test]
fn minor_loops_are_congruent() {
    let strategy = (
        legs(2.5, 0..10),
        legs(2.5, 0..10),
        -1.8..1.6f64,
        0.05..1.5f64,
        0.0..1.0f64,
        0.0..1.0f64,
        2_usize..25,
    );
    let models = models();
    measure(
        "minor-loop congruency (units of E₀)",
        512,
        strategy,
        |(h1, h2, u1, width, top1, top2, n)| {
            let u2 = (u1 + width).min(1.9);
            let loop_x: Vec<f64> = (0..=n)
                .map(|k| lerp(u1, u2, k as f64 / n as f64))
                .chain((1..=n).map(|k| lerp(u2, u1, k as f64 / n as f64)))
                .collect();
            let run = |model: &Preisach<f64>, legs: &[(f64, usize)], top: f64| {
                let mut p = model.clone();
                let mut xs = ramps(0.0, legs);
                let last = xs.last().copied().unwrap_or(0.0);
                xs.extend(ramps(last, &[(u2 + top, 3), (u1, 4)]));
                p.run(&xs)?;
                p.run(&loop_x)
            };
            let mut worst: f64 = 0.0;
            for (name, model) in &models {
                let ya = ok(run(model, &h1, top1))?;
                let yb = ok(run(model, &h2, top2))?;
                let shift = ya[0] - yb[0];
                let e0 = model.saturation();
                for (k, (a, b)) in ya.iter().zip(&yb).enumerate() {
                    let dev = ((a - b) - shift).abs() / e0;
                    prop_assert!(
                        dev <= 8.0 * EPS,
                        "{}: sample {} deviates {:e} E₀",
                        name,
                        k,
                        dev
                    );
                    worst = worst.max(dev);
                }
            }
            Ok(worst)
        },
    );
}

/// Rate independence: inserting linearly interpolated samples between
/// consecutive samples leaves the outputs at the original samples
/// bit-identical (every representation).
#[test]
fn inserted_samples_change_nothing() {
    let strategy = (legs(2.5, 1..15), 1_usize..5);
    let models = models();
    measure(
        "rate independence (bitwise)",
        512,
        strategy,
        |(legs, extra)| {
            let xs = ramps(0.0, &legs);
            let mut fine = Vec::new();
            let mut idx = Vec::new();
            let mut prev = 0.0;
            for &x in &xs {
                for k in 1..=extra {
                    fine.push(lerp(prev, x, k as f64 / (extra + 1) as f64));
                }
                idx.push(fine.len());
                fine.push(x);
                prev = x;
            }
            for (name, model) in &models {
                let coarse = ok(model.clone().run(&xs))?;
                let dense = ok(model.clone().run(&fine))?;
                let picked: Vec<f64> = idx.iter().map(|&i| dense[i]).collect();
                prop_assert_eq!(bits(&coarse), bits(&picked), "{}", name);
            }
            Ok(0.0)
        },
    );
}

/// `|y| ≤ E₀` (to rounding: the measured excess is in units of `E₀`,
/// bound `4 ε`), `y = E₀` exactly once the input passes `x_max` and `−E₀`
/// exactly once it passes `x_min`; the memory depth of the grid stays
/// within `2n + 2` for `n` levels.
#[test]
fn output_is_bounded_by_saturation() {
    let models = models();
    measure(
        "|y| − E₀ (units of E₀)",
        512,
        legs(3.0, 1..30),
        |legs| {
            let xs = ramps(0.0, &legs);
            let mut worst: f64 = 0.0;
            for (name, model) in &models {
                let mut p = model.clone();
                let e0 = p.saturation();
                for &x in &xs {
                    let y = ok(p.trial(x))?.output;
                    p.commit();
                    let excess = (y.abs() - e0) / e0;
                    prop_assert!(excess <= 4.0 * EPS, "{}: y = {} at x = {}", name, y, x);
                    worst = worst.max(excess);
                    if x >= 2.0 {
                        prop_assert_eq!(y, e0, "{}: not saturated at {}", name, x);
                    }
                    if x <= -2.0 {
                        prop_assert_eq!(y, -e0, "{}: not saturated at {}", name, x);
                    }
                    if *name == "grid" {
                        prop_assert!(p.memory_depth() <= 2 * 12 + 2);
                    }
                }
            }
            Ok(worst.max(0.0))
        },
    );
}

/// A periodic input reaches a fixed memory depth (nothing grows once the
/// first period is through), and a decaying oscillation stores one entry
/// per nested reversal.
#[test]
fn memory_depth_is_bounded_for_periodic_input() {
    for (name, model) in models() {
        let mut p = model.clone();
        let period: Vec<f64> = (0..97)
            .map(|i| {
                let t = i as f64 / 97.0 * std::f64::consts::TAU;
                1.5 * t.sin() + 0.4 * (3.0 * t).sin()
            })
            .collect();
        p.run(&period).unwrap();
        let depth = p.memory_depth();
        for _ in 0..20 {
            p.run(&period).unwrap();
            assert_eq!(p.memory_depth(), depth, "{name}");
        }
        // decaying: 1, −0.9, 0.8, … (inside the range, nested)
        let mut q = model.clone();
        let xs: Vec<f64> = (0..10)
            .map(|k| (1.0 - 0.09 * k as f64) * if k % 2 == 0 { 1.0 } else { -1.0 })
            .collect();
        q.run(&[-3.0]).unwrap();
        q.run(&xs).unwrap();
        if name != "grid" {
            // x_min, then the ten nested extrema
            assert_eq!(q.memory_depth(), 11, "{name}");
        }
    }
}

// ---------------------------------------------------------------------------
// Tangent and inverse
// ---------------------------------------------------------------------------

/// The tangent of the continuous forms is the slope of the branch:
/// compared with the Richardson difference `(4 D(h) − D(2h))/(2h)`,
/// `D(h) = y(x ± h) − y(x)` probed by trials from the committed state, whose
/// truncation error is `O(h²)`: `h = 1e-5` on branches with `|y'''| ≲ 10²`
/// (`tanh`: `a/w³ ≈ 48`) gives `≲ 1e-8`, plus rounding `≈ 4 ε E₀/h ≈ 1e-10`;
/// bound `1e-6` relative to `max(1, |y'|)`. The table is bilinear: exact
/// slopes within a cell.
#[test]
fn tangent_matches_the_branch_slope() {
    let strategy = (legs(1.9, 1..10), -1.9..1.9f64, any::<bool>());
    let models: Vec<_> = models().into_iter().filter(|(n, _)| *n != "grid").collect();
    measure(
        "tangent vs Richardson difference (relative)",
        512,
        strategy,
        |(legs, x0, up)| {
            let mut worst: f64 = 0.0;
            let h = 1e-5;
            let mut xs = ramps(0.0, &legs);
            xs.push(x0);
            // Skip kinks within reach of the probes: a stored extremum.
            if xs[..xs.len() - 1].iter().any(|v| (v - x0).abs() <= 3.0 * h) {
                return Ok(0.0);
            }
            for (name, model) in &models {
                let mut p = model.clone();
                // ... a range end, or a table node
                let (lo, hi, nodes) = match &p.parameters().measure {
                    PreisachMeasure::Table { x, .. } => (x[0], x[x.len() - 1], x.clone()),
                    PreisachMeasure::Uniform { x_min, x_max, .. }
                    | PreisachMeasure::Tanh { x_min, x_max, .. } => (*x_min, *x_max, vec![]),
                    PreisachMeasure::Grid { .. } => unreachable!(),
                };
                if x0 <= lo + 3.0 * h
                    || x0 >= hi - 3.0 * h
                    || nodes.iter().any(|n| (n - x0).abs() <= 3.0 * h)
                {
                    continue;
                }
                ok(p.run(&xs))?;
                let s = if up { 1.0 } else { -1.0 };
                let t = ok(p.trial(x0 + s * 1e-12))?.tangent;
                let y0 = p.output();
                let d1 = ok(p.trial(x0 + s * h))?.output - y0;
                let d2 = ok(p.trial(x0 + 2.0 * s * h))?.output - y0;
                let slope = s * (4.0 * d1 - d2) / (2.0 * h);
                let err = (t - slope).abs() / t.abs().max(1.0);
                prop_assert!(err <= 1e-6, "{}: tangent {} vs {}", name, t, slope);
                worst = worst.max(err);
            }
            Ok(worst)
        },
    );
}

/// `A⁻¹` then `A` is the identity to the solver tolerance, for `A` the
/// `tanh` form (positive density) or the table plus a linear term `k x`
/// (no flat region beyond the range). The forward residual is bounded by
/// `sup A' · τ` with `τ = 16 ε max(|u|, scale)` the solver tolerance:
/// `sup A' ≤ 2a/w + k ≈ 9` here, `|u| ≲ 40`, so `≲ 1.3e-12`; asserted
/// `≤ 1e-11`.
#[test]
fn inverse_then_forward_is_the_identity() {
    let strategy = legs(2.5, 1..20);
    let parts = [
        ("tanh + 0.1 x", tanh_measure()),
        ("table + 0.1 x", table_measure()),
    ];
    measure("|A(A⁻¹(x)) − x|", 256, strategy, |legs| {
        let xs = ramps(0.0, &legs);
        let mut worst: f64 = 0.0;
        for (name, m) in &parts {
            for start in [PreisachStart::FromBelow, PreisachStart::FromAbove] {
                let a = build(m.clone(), start).plus(ok(Gain::new(0.1))?);
                let mut inv = a.clone().inverse();
                let us = ok(inv.run(&xs))?;
                let back = ok(a.clone().run(&us))?;
                for (x, y) in xs.iter().zip(&back) {
                    let err = (x - y).abs();
                    prop_assert!(err <= 1e-11, "{}: {} -> {}", name, x, y);
                    worst = worst.max(err);
                }
            }
        }
        Ok(worst)
    });
    // Without the linear term the range is [−E₀, E₀]: a target inside is
    // reached, one beyond is a NoBracket error.
    let p = build(tanh_measure(), PreisachStart::FromBelow);
    let e0 = p.saturation();
    let mut inv = p.clone().inverse();
    let u = inv.run(&[0.5 * e0, -0.9 * e0]).unwrap();
    let back = p.clone().run(&u).unwrap();
    assert!((back[0] - 0.5 * e0).abs() <= 1e-12 && (back[1] + 0.9 * e0).abs() <= 1e-12);
    let err = p.clone().inverse().trial(1.01 * e0).unwrap_err();
    assert!(matches!(err, Error::NoBracket { .. }), "{err}");
}

/// The relay grid is a staircase: it has no inverse. `.inverse()` of it
/// returns `Error::Jump` for a target between two steps (naming the jump),
/// and for a target equal to a step level a point of that step (exact).
#[test]
fn inverse_of_the_relay_grid_reports_the_jump() {
    let p = build(grid_measure(), PreisachStart::FromBelow);
    let y0 = p.output();
    // Levels reached going up from the start: sample the staircase.
    let xs: Vec<f64> = (0..=400).map(|i| i as f64 * 0.005).collect();
    let ys = p.clone().run(&xs).unwrap();
    let (k, _) = ys
        .windows(2)
        .enumerate()
        .find(|(_, w)| w[1] > w[0] + 1e-6)
        .expect("a step");
    let (below, above) = (ys[k], ys[k + 1]);
    let mid = 0.5 * (below + above);
    match p.clone().inverse().trial(mid) {
        Err(Error::Jump {
            below: b,
            above: a,
            at,
            ..
        }) => {
            assert!(b <= mid && mid <= a, "{b} {mid} {a}");
            assert!(at >= xs[k] && at <= xs[k + 1], "jump at {at}");
        }
        other => panic!("expected a Jump error, got {other:?}"),
    }
    // A target on a level: some input of that plateau, exactly.
    let mut inv = p.clone().inverse();
    let u = inv.trial(above).unwrap().output;
    assert_eq!(p.clone().run(&[u]).unwrap()[0], above);
    assert!(y0 <= below);
}

// ---------------------------------------------------------------------------
// Validation
// ---------------------------------------------------------------------------

fn rejects(measure: PreisachMeasure<f64>, name: &str) {
    match Preisach::from_params(PreisachParams {
        measure: measure.clone(),
        start: PreisachStart::FromBelow,
    }) {
        Err(Error::InvalidParameter { name: n, .. }) => assert_eq!(n, name, "{measure:?}"),
        other => panic!("{measure:?}: expected an error naming {name}, got {other:?}"),
    }
}

#[test]
fn invalid_measures_are_typed_errors() {
    let grid = |t: Vec<f64>, mu: Vec<Vec<f64>>| PreisachMeasure::Grid { t, mu };
    rejects(grid(vec![], vec![]), "t");
    rejects(
        grid(vec![0.0, 0.0], vec![vec![1.0], vec![1.0, 1.0]]),
        "t[1]",
    );
    rejects(
        grid(vec![1.0, 0.0], vec![vec![1.0], vec![1.0, 1.0]]),
        "t[1]",
    );
    rejects(grid(vec![f64::NAN], vec![vec![1.0]]), "t[0]");
    rejects(grid(vec![0.0, 1.0], vec![vec![1.0]]), "mu");
    rejects(grid(vec![0.0, 1.0], vec![vec![1.0], vec![1.0]]), "mu[1]");
    rejects(
        grid(vec![0.0, 1.0], vec![vec![1.0], vec![-1.0, 1.0]]),
        "mu[1][0]",
    );
    rejects(
        grid(vec![0.0, 1.0], vec![vec![1.0], vec![1.0, f64::INFINITY]]),
        "mu[1][1]",
    );
    let table = |x: Vec<f64>, e: Vec<Vec<f64>>| PreisachMeasure::Table { x, e };
    rejects(table(vec![0.0], vec![]), "x");
    rejects(
        table(vec![0.0, 1.0, 0.5], vec![vec![1.0], vec![1.0, 1.0]]),
        "x[2]",
    );
    // E(x2, x0) = 1 < E(x1, x0) + E(x2, x1) = 2 − 0: negative mass on cell (1, 0).
    rejects(
        table(vec![0.0, 1.0, 2.0], vec![vec![1.0], vec![1.0, 1.0]]),
        "e[1][0]",
    );
    rejects(table(vec![0.0, 1.0], vec![vec![-0.5]]), "e[0][0]");
    rejects(
        PreisachMeasure::Uniform {
            mu: -1.0,
            x_min: 0.0,
            x_max: 1.0,
        },
        "mu",
    );
    rejects(
        PreisachMeasure::Uniform {
            mu: 1.0,
            x_min: 1.0,
            x_max: 1.0,
        },
        "x_max",
    );
    rejects(
        PreisachMeasure::Tanh {
            amplitude: 1.0,
            hc: 0.0,
            w: 0.0,
            x_min: -1.0,
            x_max: 1.0,
        },
        "w",
    );
    rejects(
        PreisachMeasure::Tanh {
            amplitude: 1.0,
            hc: f64::NAN,
            w: 1.0,
            x_min: -1.0,
            x_max: 1.0,
        },
        "hc",
    );
    // set_params is atomic: a bad vector changes nothing.
    let mut p = build(table_measure(), PreisachStart::FromBelow);
    let before = p.params();
    let mut bad = before.clone();
    bad[7] = -1.0; // e[0][0]
    assert!(p.set_params(&bad).is_err());
    assert_eq!(p.params(), before);
    assert_eq!(p.param_names()[7], "e[0][0]");
}

// ---------------------------------------------------------------------------
// Specs
// ---------------------------------------------------------------------------

/// A Preisach spec in JSON builds the same model as the library, its
/// parameters round-trip through `with_params`, and errors name the path
/// in the document (JSON errors) or through the tree (parameter errors).
#[test]
fn preisach_specs_build_and_name_their_errors() {
    use hysteron::models::Spec;
    let json = r#"{"type": "preisach", "start": "from_above",
        "measure": {"table": {"x": [-1, 0, 1], "e": [[0.5], [2, 0.5]]}}}"#;
    let spec = Spec::from_json(json).unwrap();
    let mut built = spec.build().unwrap();
    let mut direct = build(
        PreisachMeasure::Table {
            x: vec![-1.0, 0.0, 1.0],
            e: vec![vec![0.5], vec![2.0, 0.5]],
        },
        PreisachStart::FromAbove,
    );
    let xs = [0.3, -0.4, 0.9, -2.0, 0.1];
    assert_eq!(
        bits(&built.run(&xs).unwrap()),
        bits(&direct.run(&xs).unwrap())
    );
    assert_eq!(
        built.param_names(),
        ["x[0]", "x[1]", "x[2]", "e[0][0]", "e[1][0]", "e[1][1]"]
    );
    let mut p = built.params();
    assert_eq!(spec.with_params(&p).unwrap(), spec);
    p[4] = 3.0;
    assert_eq!(spec.with_params(&p).unwrap().build().unwrap().params(), p);
    // A misspelt field inside the measure: named by its JSON path.
    let err = Spec::from_json(
        r#"{"type": "preisach", "measure": {"uniform": {"mu": 1, "x_min": -1, "xmax": 1}}}"#,
    )
    .unwrap_err();
    assert_eq!(err.path(), "measure.uniform.xmax", "{err}");
    assert!(err.to_string().contains("xmax"), "{err}");
    // An unknown representation.
    let err = Spec::from_json(r#"{"type": "preisach", "measure": {"spline": {}}}"#).unwrap_err();
    assert_eq!(err.path(), "measure", "{err}");
    // A table with negative mass: named through the tree.
    let err = Spec::from_json(
        r#"{"type": "preisach", "measure": {"table": {"x": [0, 1, 2], "e": [[1], [1, 1]]}}}"#,
    )
    .unwrap()
    .build()
    .unwrap_err();
    assert_eq!(err.path(), "preisach.e[1][0]", "{err}");
    // Inside a combinator.
    let err = Spec::from_json(
        r#"{"type": "inverse", "inner": {"type": "preisach",
            "measure": {"tanh": {"amplitude": 1, "hc": 0.2, "w": -1, "x_min": -1, "x_max": 1}}}}"#,
    )
    .unwrap()
    .build()
    .unwrap_err();
    assert_eq!(
        err.to_string(),
        "inverse.inner.preisach.w: must be > 0 (got -1)"
    );
}

/// The representations agree where they should, to rounding:
/// * a grid discretizing a uniform density `μ` by the midpoint rule
///   (`n` cells of width `h`, relays at the cell centres, half a cell on
///   the diagonal) holds `μ h² (k(k−1)/2 + k/2) = μ (k h)²/2` on a triangle
///   of `k` cells: its Everett function equals `μ (α − β)²/2` whenever `α`,
///   `β` are cell boundaries, so for inputs on cell boundaries the grid's
///   output equals the uniform form's;
/// * the table sampled from the `tanh` Everett function equals it at the
///   nodes, so for inputs on the nodes the outputs agree.
///
/// Measured in units of `E₀` (sums of `≤ n²` weights: bound `n² ε` for the
/// grid, `8 ε` for the table).
#[test]
fn representations_agree_at_their_nodes() {
    let n = 10;
    let (lo, hi, mu) = (-1.0, 1.5, 0.8);
    let h = (hi - lo) / n as f64;
    let uniform = build(
        PreisachMeasure::Uniform {
            mu,
            x_min: lo,
            x_max: hi,
        },
        PreisachStart::FromBelow,
    );
    let grid = build(
        PreisachParams::grid_from_density(lo, hi, n, |_: f64, _: f64| mu).measure,
        PreisachStart::FromBelow,
    );
    let table = build(table_measure(), PreisachStart::FromBelow);
    let tanh = build(tanh_measure(), PreisachStart::FromBelow);
    let nodes = match &table.parameters().measure {
        PreisachMeasure::Table { x, .. } => x.clone(),
        _ => unreachable!(),
    };
    let strategy = (
        prop::collection::vec(0..=n, 1..30),
        prop::collection::vec(0..nodes.len(), 1..30),
    );
    measure(
        "grid vs uniform, table vs tanh at nodes (units of E₀)",
        512,
        strategy,
        |(ks, js)| {
            let mut worst: f64 = 0.0;
            let pairs = [
                (
                    &grid,
                    &uniform,
                    ks.iter().map(|&k| lo + h * k as f64).collect::<Vec<_>>(),
                    (n * n) as f64 * EPS,
                ),
                (
                    &table,
                    &tanh,
                    js.iter().map(|&j| nodes[j]).collect(),
                    8.0 * EPS,
                ),
            ];
            for (a, b, xs, bound) in pairs {
                // The start at input 0 is not a node in general: saturate first.
                let xs: Vec<f64> = std::iter::once(-5.0).chain(xs).collect();
                let ya = ok(a.clone().run(&xs))?;
                let yb = ok(b.clone().run(&xs))?;
                let e0 = b.saturation();
                for (x, (p, q)) in xs.iter().zip(ya.iter().zip(&yb)) {
                    let err = (p - q).abs() / e0;
                    prop_assert!(err <= bound, "x = {}: {} vs {}", x, p, q);
                    worst = worst.max(err);
                }
            }
            Ok(worst)
        },
    );
}
