//! Property tests of the friction models researchers compare against:
//! multi-element Maxwell-slip ([`MaxwellSlip`]), Dahl ([`Dahl`]), LuGre
//! ([`LuGre`]) and generalized Maxwell-slip ([`Gms`]), against closed forms
//! and independent references.
//!
//! Laws with a tolerance print the largest error they measured; run
//! `cargo test --test friction -- --nocapture` to see them.
//! `LAWS_CASES_FACTOR=10` multiplies the number of random cases.

use hysteron::models::Spec;
use hysteron::prelude::*;
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;
use std::cell::Cell;

mod common;
mod props;
use props::*;

const EPS: f64 = f64::EPSILON;

// ---------------------------------------------------------------------------
// Signals
// ---------------------------------------------------------------------------

/// A piecewise-monotone signal from 0: ramps of 1–8 samples to random
/// turning points in `[−amp, amp]`, some held values and some reversals of
/// a relative size 1e-12.
fn signal(amp: f64, max_legs: usize) -> impl Strategy<Value = Vec<f64>> {
    let leg = prop_oneof![
        6 => (-1.0_f64..1.0, 1_usize..9).prop_map(|(t, n)| (t, n, 0_u8)),
        1 => (1_usize..3).prop_map(|n| (0.0, n, 1)),
        1 => (-1.0_f64..1.0).prop_map(|s| (s, 1, 2)),
    ];
    prop::collection::vec(leg, 1..max_legs).prop_map(move |legs| {
        let mut xs = Vec::new();
        let mut x = 0.0_f64;
        for (t, n, kind) in legs {
            match kind {
                0 => {
                    let b = amp * t;
                    for k in 1..=n {
                        xs.push(if k == n {
                            b
                        } else {
                            lerp(x, b, k as f64 / n as f64)
                        });
                    }
                    x = b;
                }
                1 => xs.extend(std::iter::repeat_n(x, n)),
                _ => {
                    x += 1e-12 * amp * t;
                    xs.push(x);
                }
            }
        }
        xs
    })
}

// ---------------------------------------------------------------------------
// Maxwell-slip
// ---------------------------------------------------------------------------

/// 1–8 elements with stiffness in [0.5, 50], break-away force in
/// [0.01, 2], initial force in `±preload·F_i` (unloaded if `preload` is 0;
/// beyond the break-away force if it is > 1).
fn maxwell_slip(preload: f64) -> impl Strategy<Value = MaxwellSlipParams<f64>> {
    prop::collection::vec((0.5..50.0f64, 0.01..2.0f64, -1.0..=1.0f64), 1..9).prop_map(
        move |elements| MaxwellSlipParams {
            k: elements.iter().map(|e| e.0).collect(),
            f_b: elements.iter().map(|e| e.1).collect(),
            f0: if preload > 0.0 {
                elements.iter().map(|e| preload * e.1 * e.2).collect()
            } else {
                Vec::new()
            },
        },
    )
}

/// The virgin curve `φ(x) = Σ_i sgn(x) min(k_i |x|, F_i)`.
fn virgin(p: &MaxwellSlipParams<f64>, x: f64) -> f64 {
    p.k.iter()
        .zip(&p.f_b)
        .map(|(&k, &f)| (k * x.abs()).min(f) * x.signum())
        .sum()
}

/// The rounding allowance of a bank output near input `x`: each element's
/// stop carries `ulp(x)` and `ulp(F_i/k_i)` (scaled by `k_i`), its product
/// and the sum one `ε|F|` each: `Σ_i 2ε (k_i |x| + 2 F_i)` plus
/// `N ε Σ_i F_i`.
fn bank_rounding(p: &MaxwellSlipParams<f64>, x: f64) -> f64 {
    let n = p.k.len() as f64;
    let sum_f: f64 = p.f_b.iter().sum();
    let per: f64 =
        p.k.iter()
            .zip(&p.f_b)
            .map(|(&k, &f)| 2.0 * EPS * (k * x.abs() + 2.0 * f))
            .sum();
    per + n * EPS * sum_f
}

/// Measures `law` of the Maxwell-slip bank over 256 cases of its
/// parameters (initial forces in `±1.5 F_i`, some beyond the break-away
/// forces) and a signal of amplitude `amplitude`.
fn measure_maxwell_slip(
    label: &str,
    amplitude: f64,
    law: impl Fn(MaxwellSlipParams<f64>, Vec<f64>) -> Result<f64, TestCaseError>,
) {
    measure(
        label,
        256,
        (maxwell_slip(1.5), signal(amplitude, 30)),
        |(p, xs)| law(p, xs),
    );
}

/// The bank equals a left-nested `Parallel` of `ElastoPlastic` elements
/// bit for bit: outputs and tangents, sample by sample.
#[test]
fn maxwell_slip_equals_a_parallel_of_elastoplastic_elements_bit_for_bit() {
    measure_maxwell_slip(
        "maxwell-slip vs parallel elastoplastic (bits differing)",
        1.5,
        |p, xs| {
            let elements: Vec<ElastoPlastic<f64>> = (0..p.k.len())
                .map(|i| {
                    ElastoPlastic::from_params(hysteron::operators::ElastoPlasticParams {
                        k: p.k[i],
                        f_b: p.f_b[i],
                        f0: p.f0[i],
                    })
                })
                .collect::<hysteron::Result<_>>()
                .map_err(|e| TestCaseError::fail(e.to_string()))?;
            let mut parallel: Box<dyn Operator<f64>> = elements[0].clone().boxed();
            for e in &elements[1..] {
                parallel = parallel.plus(e.clone()).boxed();
            }
            let mut bank = ok(MaxwellSlip::from_params(p.clone()))?;
            let a = trials(&mut bank, &xs)?;
            let b = trials(&mut parallel, &xs)?;
            for (i, (a, b)) in a.iter().zip(&b).enumerate() {
                prop_assert_eq!(a.output.to_bits(), b.output.to_bits(), "output {}", i);
                prop_assert_eq!(a.tangent.to_bits(), b.tangent.to_bits(), "tangent {}", i);
            }
            // and the batch path too
            bank.reset();
            parallel.reset();
            prop_assert_eq!(bits(&ok(bank.run(&xs))?), bits(&ok(parallel.run(&xs))?));
            Ok(0.0)
        },
    );
}

/// Wiping-out: after a maximum `M` and a minimum `m` of the common
/// history, two different excursions inside `[m, M]` are forgotten once
/// the input reaches `M` again: the outputs from there on agree bit for
/// bit.
#[test]
fn maxwell_slip_wipes_out_inner_excursions() {
    let inner = prop::collection::vec(0.0..=1.0f64, 1..25);
    // cases whose excursions gave different outputs (the law is not vacuous)
    let differing = Cell::new(0_u32);
    measure(
        "maxwell-slip wiping-out (bits differing)",
        256,
        (
            maxwell_slip(1.5),
            signal(1.0, 12),
            (0.05..2.0f64, 0.05..2.0f64),
            (inner.clone(), inner),
            signal(1.0, 12),
        ),
        |(p, prefix, (up, down), (a, b), suffix)| {
            let last = prefix.last().copied().unwrap_or(0.0);
            let (hi, lo) = (last + up, last + up - down);
            let history = |excursion: &[f64]| -> Vec<f64> {
                let mut xs = prefix.clone();
                xs.extend([hi, lo]);
                xs.extend(excursion.iter().map(|&t| lerp(lo, hi, t)));
                xs.push(hi);
                xs.extend(suffix.iter().map(|s| hi + s));
                xs
            };
            let (xa, xb) = (history(&a), history(&b));
            let ya = ok(ok(MaxwellSlip::from_params(p.clone()))?.run(&xa))?;
            let yb = ok(ok(MaxwellSlip::from_params(p.clone()))?.run(&xb))?;
            let tail = suffix.len() + 1;
            prop_assert_eq!(bits(&ya[ya.len() - tail..]), bits(&yb[yb.len() - tail..]));
            let n = prefix.len() + 2;
            if ya[n..n + a.len().min(b.len())] != yb[n..n + a.len().min(b.len())] {
                differing.set(differing.get() + 1);
            }
            Ok(0.0)
        },
    );
    eprintln!(
        "maxwell-slip wiping-out: {} of {} cases differed inside the excursions",
        differing.get(),
        cases(256)
    );
    assert!(differing.get() * 2 > cases(256), "{}", differing.get());
}

/// Virgin curve, Masing's rules and the force bound against closed forms:
/// from the unloaded state, rise to `x_r` along `φ`; after the reversal
/// `F = F_r − 2 φ((x_r − x)/2)`; after a second reversal at `x_2 > x_r −
/// 2·travel`, `F = F_2 + 2 φ((x − x_2)/2)` until `x_r`. Error in units of
/// the rounding allowance [`bank_rounding`] (must stay ≤ 1).
#[test]
fn maxwell_slip_virgin_curve_and_masing_rules() {
    measure(
        "maxwell-slip virgin curve + Masing (error / rounding allowance)",
        512,
        (
            maxwell_slip(0.0),
            0.01..1.0f64,
            (0.0..=1.0f64, 0.0..=1.0f64),
            1_usize..40,
            any::<bool>(),
        ),
        |(p, x_r, (d1, d2), n, negative)| {
            let s = if negative { -1.0 } else { 1.0 };
            let x_r = s * x_r;
            let mut bank = ok(MaxwellSlip::from_params(p.clone()))?;
            let mut worst = 0.0_f64;
            let mut check = |x: f64, expected: f64, y: f64| -> Result<(), TestCaseError> {
                let e = (y - expected).abs() / bank_rounding(&p, x.abs().max(x_r.abs()));
                worst = worst.max(e);
                prop_assert!(e <= 1.0, "x={x}: {y} vs {expected}");
                Ok(())
            };
            // virgin curve: n samples up to x_r (breakpoints F_i/k_i inside)
            for k in 1..=n {
                let x = x_r * k as f64 / n as f64;
                let y = ok(bank.trial(x))?.output;
                bank.commit();
                check(x, virgin(&p, x), y)?;
            }
            let f_r = virgin(&p, x_r);
            // first Masing branch: back by up to 2 x_r (to −x_r, where it
            // meets the virgin curve again)
            let x_2 = x_r - s * 2.0 * d1 * x_r.abs();
            for k in 1..=n {
                let x = lerp(x_r, x_2, k as f64 / n as f64);
                let y = ok(bank.trial(x))?.output;
                bank.commit();
                check(x, f_r - 2.0 * virgin(&p, (x_r - x) / 2.0), y)?;
            }
            let f_2 = f_r - 2.0 * virgin(&p, (x_r - x_2) / 2.0);
            // second Masing branch: forward again, not beyond x_r
            let x_3 = lerp(x_2, x_r, d2);
            for k in 1..=n {
                let x = lerp(x_2, x_3, k as f64 / n as f64);
                let y = ok(bank.trial(x))?.output;
                bank.commit();
                check(x, f_2 + 2.0 * virgin(&p, (x - x_2) / 2.0), y)?;
            }
            Ok(worst)
        },
    );
}

/// `|F| ≤ Σ F_i` from the first sample on, for any initial forces (even
/// beyond the break-away forces): in units of `Σ F_i`, the excess stays
/// within the rounding allowance `(N + 4) ε`.
#[test]
fn maxwell_slip_force_is_bounded_by_the_sum_of_break_away_forces() {
    measure_maxwell_slip("maxwell-slip max |F| / Σ F_i", 3.0, |p, xs| {
        let bound: f64 = p.f_b.iter().sum();
        let ys = ok(ok(MaxwellSlip::from_params(p.clone()))?.run(&xs))?;
        let peak = ys.iter().fold(0.0_f64, |m, y| m.max(y.abs()));
        let slack = (p.k.len() as f64 + 4.0) * EPS;
        prop_assert!(peak <= bound * (1.0 + slack), "{peak} > {bound}");
        Ok(peak / bound)
    });
}

/// Rate independence, exactly: inserting linearly interpolated samples
/// leaves the outputs at the original samples unchanged, bit for bit. For
/// Maxwell-slip the initial element forces are within `±F_i` (a force
/// beyond is clipped at the first sample, and where that sample lies
/// matters); Dahl's initial force may lie beyond `F_c`.
#[test]
fn maxwell_slip_and_dahl_are_exactly_rate_independent() {
    measure(
        "maxwell-slip and dahl refined-sampling difference (bits differing)",
        256,
        (maxwell_slip(1.0), dahl(false), signal(1.5, 20), 1_usize..5),
        |(ms, dahl, xs, m)| {
            let (fine, at) = refine(&xs, &[m]);
            let ops: [Box<dyn Operator<f64>>; 2] = [
                ok(MaxwellSlip::from_params(ms))?.boxed(),
                ok(Dahl::from_params(dahl))?.boxed(),
            ];
            for op in ops {
                let coarse = ok(op.clone().run(&xs))?;
                let refined = ok(op.clone().run(&fine))?;
                let picked: Vec<f64> = at.iter().map(|&i| refined[i]).collect();
                prop_assert_eq!(bits(&picked), bits(&coarse), "{}", op.name());
            }
            Ok(0.0)
        },
    );
}

// ---------------------------------------------------------------------------
// Dahl
// ---------------------------------------------------------------------------

/// σ in [1, 100], F_c in [0.1, 3], α in [0, 4] (often exactly 0 or 1),
/// `f0` within ±F_c (if `inside`) or within ±2 F_c.
fn dahl(inside: bool) -> impl Strategy<Value = DahlParams<f64>> {
    let reach = if inside { 1.0 } else { 2.0 };
    (
        1.0..100.0f64,
        0.1..3.0f64,
        prop_oneof![Just(0.0), Just(1.0), 0.0..4.0f64],
        -reach..=reach,
    )
        .prop_map(|(sigma, f_c, alpha, f)| DahlParams {
            sigma,
            f_c,
            alpha,
            f0: f * f_c,
        })
}

/// The virgin branch (from `F = 0`, `x ≥ 0`) written out per exponent:
/// `α = 0`: `min(σx, F_c)`; `α = 0.5`: `F_c (1 − (1 − λx/2)²)` until
/// `λx = 2`; `α = 1`: `F_c (1 − e^{−λx})`; `α = 2`: `F_c λx/(1 + λx)`;
/// `α = 3`: `F_c (1 − (1 + 2λx)^{−1/2})`, with `λ = σ/F_c`.
fn dahl_virgin(alpha: f64, sigma: f64, f_c: f64, x: f64) -> f64 {
    let u = sigma / f_c * x;
    let w = if alpha == 0.0 {
        1.0 - u.min(1.0)
    } else if alpha == 0.5 {
        let h = (1.0 - u / 2.0).max(0.0);
        h * h
    } else if alpha == 1.0 {
        (-u).exp()
    } else if alpha == 2.0 {
        1.0 / (1.0 + u)
    } else {
        assert_eq!(alpha, 3.0);
        1.0 / (1.0 + 2.0 * u).sqrt()
    };
    f_c * (1.0 - w)
}

/// Virgin branches and the branch after a reversal against the closed
/// forms above (the descending branch from `(x_r, F_r)` is the point
/// reflection of a virgin branch of a shifted start: for `α = 1`,
/// `F = −F_c + (F_r + F_c) e^{−λ(x_r − x)}`). Relative error.
#[test]
fn dahl_closed_forms() {
    measure(
        "dahl virgin branch vs closed form (relative)",
        256,
        (
            prop::sample::select(vec![0.0, 0.5, 1.0, 2.0, 3.0]),
            1.0..100.0f64,
            0.1..3.0f64,
            prop::collection::vec(0.0..0.2f64, 1..30),
        ),
        |(alpha, sigma, f_c, steps)| {
            let mut f = ok(Dahl::new(sigma, f_c, alpha))?;
            let mut x = 0.0;
            let mut worst = 0.0_f64;
            for d in steps {
                x += d;
                let y = ok(f.trial(x))?.output;
                f.commit();
                let e = (y - dahl_virgin(alpha, sigma, f_c, x)).abs() / f_c;
                // a few roundings of quantities of size F_c, plus the
                // conditioning of the power forms (≤ 10 ε)
                prop_assert!(e < 32.0 * EPS, "α={alpha} x={x}: {y} ({e:e})");
                worst = worst.max(e);
            }
            Ok(worst)
        },
    );
    measure(
        "dahl α = 1 branch after a reversal vs closed form (relative)",
        256,
        (
            1.0..100.0f64,
            0.1..3.0f64,
            0.0..0.3f64,
            prop::collection::vec(0.0..0.1f64, 1..30),
        ),
        |(sigma, f_c, x_r, steps)| {
            let mut f = ok(Dahl::new(sigma, f_c, 1.0))?;
            let f_r = ok(f.trial(x_r))?.output;
            f.commit();
            let lambda = sigma / f_c;
            let mut x = x_r;
            let mut worst = 0.0_f64;
            for d in steps {
                x -= d;
                let y = ok(f.trial(x))?.output;
                f.commit();
                let expected = -f_c + (f_r + f_c) * (-lambda * (x_r - x)).exp();
                let e = (y - expected).abs() / f_c;
                prop_assert!(e < 32.0 * EPS, "x={x}: {y} vs {expected}");
                worst = worst.max(e);
            }
            Ok(worst)
        },
    );
}

/// RK4 integration of `dF/dx = σ |w|^α sgn(w)`, `w = 1 − s F/F_c`, over the
/// travel from `a` to `b` (an independent reference), in at least `n`
/// steps and at least enough that `h L ≤ 0.01`, with
/// `L = σ α |w_a|^{α−1} / F_c` the largest `|∂(dF/dx)/∂F|` on the branch
/// (`|w|` falls from `|w_a|` towards 0 along it, and `α ≥ 1`). The branch
/// contracts, so RK4's global error is about its local error over `h L`,
/// `(h L)⁴/120 ≈ 1e-10` relative.
fn dahl_rk4(p: &DahlParams<f64>, f: f64, a: f64, b: f64, n: usize) -> f64 {
    let s = if b > a { 1.0 } else { -1.0 };
    let rhs = |f: f64| {
        let w = 1.0 - s * f / p.f_c;
        p.sigma * w.abs().powf(p.alpha) * w.signum()
    };
    let w_a = (1.0 - s * f / p.f_c).abs();
    let l = p.sigma * p.alpha * w_a.powf(p.alpha - 1.0) / p.f_c;
    let n = n.max(((b - a).abs() * l / 0.01).ceil() as usize);
    rk4(rhs, f, (b - a) / n as f64, n)
}

/// Classic RK4 on `dy/dt = rhs(y)` from `y`: `n` steps of `h`.
fn rk4(rhs: impl Fn(f64) -> f64, y: f64, h: f64, n: usize) -> f64 {
    let mut y = y;
    for _ in 0..n {
        let k1 = rhs(y);
        let k2 = rhs(y + h / 2.0 * k1);
        let k3 = rhs(y + h / 2.0 * k2);
        let k4 = rhs(y + h * k3);
        y += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    y
}

/// The closed forms for any `α ≥ 1` and any starting force (also beyond
/// `F_c`) agree with RK4 of the differential form, at least 4000 steps per
/// branch and `h L ≤ 0.01` (see `dahl_rk4`; the right-hand side is smooth
/// for `α ≥ 1`), to 1e-10 F_c (measured 5e-13 over 12 800 cases). (4000
/// steps alone once failed the old bound 1e-9 F_c: at
/// `σ = 93`, `F_c = 0.1`, `α = 3.47`, `f0 = −1.65 F_c`, `h L` was 0.86.)
#[test]
fn dahl_agrees_with_rk4_of_the_differential_form() {
    measure(
        "dahl vs RK4 reference (relative to F_c)",
        64,
        (
            1.0..100.0f64,
            0.1..3.0f64,
            1.0..4.0f64,
            -2.0..2.0f64,
            prop::collection::vec(-0.1..0.1f64, 1..8),
        ),
        |(sigma, f_c, alpha, f0, turns)| {
            let p = DahlParams {
                sigma,
                f_c,
                alpha,
                f0: f0 * f_c,
            };
            let mut op = ok(Dahl::from_params(p))?;
            let (mut x, mut reference) = (0.0, p.f0);
            let mut worst = 0.0_f64;
            for t in turns {
                if t == 0.0 {
                    continue;
                }
                let y = ok(op.trial(x + t))?.output;
                op.commit();
                reference = dahl_rk4(&p, reference, x, x + t, 4000);
                x += t;
                let e = (y - reference).abs() / f_c;
                prop_assert!(e < 1e-10, "{y} vs {reference}");
                worst = worst.max(e);
            }
            Ok(worst)
        },
    );
}

/// Measures `law` of the Dahl model over `cases` cases of its parameters
/// (`|f0| ≤ F_c`) and a signal of amplitude `amplitude`.
fn measure_dahl(
    label: &str,
    cases: u32,
    amplitude: f64,
    law: impl Fn(DahlParams<f64>, Vec<f64>) -> Result<f64, TestCaseError>,
) {
    measure(
        label,
        cases,
        (dahl(true), signal(amplitude, 30)),
        |(p, xs)| law(p, xs),
    );
}

/// `|F| ≤ F_c` exactly whenever `|f0| ≤ F_c`, and every branch is monotone
/// in the direction of the input (non-decreasing while `x` rises).
#[test]
fn dahl_is_bounded_and_its_branches_monotone() {
    measure_dahl("dahl max |F| / F_c", 512, 2.0, |p, xs| {
        let ys = ok(ok(Dahl::from_params(p))?.run(&xs))?;
        let mut prev = (0.0, p.f0);
        let mut peak = 0.0_f64;
        for (&x, &y) in xs.iter().zip(&ys) {
            prop_assert!(y.abs() <= p.f_c, "|{y}| > {}", p.f_c);
            let (dx, dy) = (x - prev.0, y - prev.1);
            prop_assert!(dx * dy >= 0.0, "not monotone: dx={dx} dy={dy}");
            prev = (x, y);
            peak = peak.max(y.abs() / p.f_c);
        }
        Ok(peak)
    });
}

/// `α = 0` is the elastoplastic element of stiffness σ and break-away force
/// F_c (different formulas: agreement to rounding, `8ε(σ|x| + F_c)`).
#[test]
fn dahl_alpha_zero_is_the_elastoplastic_element() {
    measure_dahl(
        "dahl α=0 vs elastoplastic (error / 8ε(σ|x| + F_c))",
        256,
        1.0,
        |p, xs| {
            let p = DahlParams { alpha: 0.0, ..p };
            let dahl = ok(ok(Dahl::from_params(p))?.run(&xs))?;
            let ep = ok(ok(ElastoPlastic::from_params(
                hysteron::operators::ElastoPlasticParams {
                    k: p.sigma,
                    f_b: p.f_c,
                    f0: p.f0,
                },
            ))?
            .run(&xs))?;
            let mut worst = 0.0_f64;
            for ((&x, &a), &b) in xs.iter().zip(&dahl).zip(&ep) {
                let e = (a - b).abs() / (8.0 * EPS * (p.sigma * x.abs() + p.f_c));
                prop_assert!(e <= 1.0, "x={x}: {a} vs {b}");
                worst = worst.max(e);
            }
            Ok(worst)
        },
    );
}

// ---------------------------------------------------------------------------
// LuGre
// ---------------------------------------------------------------------------

fn lugre_params() -> impl Strategy<Value = LuGreParams<f64>> {
    (
        (1e2..1e5f64, 0.0..20.0f64, 0.0..2.0f64),
        (0.2..2.0f64, 0.2..3.0f64, 0.001..0.5f64, 0.5..3.0f64),
        1e-4..1e-2f64,
    )
        .prop_map(|(bristles, stribeck, dt)| common::lugre_of(bristles, stribeck, 0.0, dt))
}

/// Measures `law` of a friction model driven at a constant velocity `v`
/// (not 0) from rest for `n` samples, against its closed form: 256 cases
/// of the `params`, `v` in `(−v_max, v_max)` and `n` in `1..n_end`.
fn measure_constant_velocity<S>(
    model: &str,
    params: S,
    v_max: f64,
    n_end: usize,
    law: impl Fn(S::Value, f64, usize) -> Result<f64, TestCaseError>,
) where
    S: Strategy,
    S::Value: std::fmt::Debug,
{
    measure(
        &format!("{model} constant velocity vs closed form (relative)"),
        256,
        (params, -v_max..v_max, 1_usize..n_end),
        |(p, v, n)| {
            prop_assume!(v != 0.0);
            law(p, v, n)
        },
    );
}

/// The Stribeck curve written out: `F_c + (F_s − F_c) e^{−|v/v_s|^δ}`.
fn g(p: &LuGreParams<f64>, v: f64) -> f64 {
    p.f_c + (p.f_s - p.f_c) * (-(v.abs() / p.v_s).powf(p.delta)).exp()
}

/// At constant velocity from rest the LuGre force has the closed form
/// `g (1 − e^{−σ0 x/g}) sgn v + σ1 v e^{−σ0 x/g} + σ2 v` (`x = |v| t`),
/// which the exact integrator reproduces to rounding (relative to the
/// force scale `g + (σ1 + σ2)|v|`; each sample adds a few ε); in
/// particular the steady state is the Stribeck curve
/// `g(v) sgn(v) + σ2 v`.
#[test]
fn lugre_constant_velocity_closed_form_and_stribeck_curve() {
    measure_constant_velocity("lugre", lugre_params(), 2.0, 400, |p, v, n| {
        let mut op = ok(LuGre::from_params(p))?;
        let gv = g(&p, v);
        let scale = gv + (p.sigma1 + p.sigma2) * v.abs();
        let mut worst = 0.0_f64;
        for k in 1..=n {
            let x = v * p.dt * k as f64;
            let y = ok(op.trial(x))?.output;
            op.commit();
            let decay = (-p.sigma0 * x.abs() / gv).exp();
            let expected = gv * (1.0 - decay) * v.signum() + p.sigma1 * v * decay + p.sigma2 * v;
            let e = (y - expected).abs() / scale;
            prop_assert!(e < 1e-13 + 8.0 * EPS * k as f64, "k={k}: {y} vs {expected}");
            worst = worst.max(e);
        }
        Ok(worst)
    });
    // Far into sliding the force is the Stribeck curve itself (in closed
    // form, with g written out here): the transient has decayed by
    // e^{−σ0 x/g} < e^{−50}.
    measure(
        "lugre steady sliding vs Stribeck curve (relative)",
        256,
        (lugre_params(), -2.0..2.0f64),
        |(p, v)| {
            prop_assume!(v.abs() > 1e-6);
            let travel = 50.0 * g(&p, v) / p.sigma0;
            // 2000–4000 samples over that travel, in steps of a power of
            // two so that every increment is exact and the velocity the
            // same at every sample (at constant velocity the update is
            // exact for any dt)
            let step = (travel / 2000.0).log2().floor().exp2();
            let n = (travel / step).ceil() as usize;
            let p = LuGreParams {
                dt: step / v.abs(),
                ..p
            };
            let s = v.signum();
            let xs: Vec<f64> = (1..=n).map(|k| s * step * k as f64).collect();
            let y = *ok(ok(LuGre::from_params(p))?.run(&xs))?.last().unwrap();
            let v = s * step / p.dt; // the velocity the samples carry
            let expected = g(&p, v) * v.signum() + p.sigma2 * v;
            let e = (y - expected).abs() / expected.abs();
            prop_assert!(e < 1e-12, "{y} vs {expected}");
            Ok(e)
        },
    );
}

/// Pre-sliding: for a small monotone displacement from rest (any speed
/// profile) `z` lies in `[x − σ0 x²/(2 g_min), x]`, so
/// `|F − σ0 x| ≤ σ0² x²/(2 g_min) + (σ1 + σ2)|v|`: the model is a spring of
/// stiffness σ0 (the damping terms nearly exhaust the force bound, so the
/// bristle is checked too). Printed: the largest lag `|x| − |z|` over its
/// bound `σ0 x²/(2 g_min)` (≤ 1; about `g_min/g`, as `g ≥ g_min`).
#[test]
fn lugre_pre_sliding_is_a_spring_of_stiffness_sigma0() {
    measure(
        "lugre pre-sliding bristle lag (|x| − |z|) / (σ0 x²/(2 g_min))",
        256,
        (
            lugre_params(),
            prop::collection::vec(0.0..1.0f64, 1..50),
            any::<bool>(),
        ),
        |(p, steps, negative)| {
            let g_min = p.f_c.min(p.f_s);
            // keep the travel below 1 % of the break-away displacement
            let reach = 0.01 * g_min / p.sigma0;
            let total: f64 = steps.iter().sum();
            prop_assume!(total > 0.0);
            let s = if negative { -1.0 } else { 1.0 };
            let mut op = ok(LuGre::from_params(p))?;
            let (mut x, mut worst) = (0.0, 0.0_f64);
            for d in steps {
                let dx = s * reach * d / total;
                x += dx;
                let y = ok(op.trial(x))?.output;
                op.commit();
                let v = dx.abs() / p.dt;
                let bound = p.sigma0 * p.sigma0 * x * x / (2.0 * g_min)
                    + (p.sigma1 + p.sigma2) * v
                    + 8.0 * EPS * p.sigma0 * x.abs();
                let dev = (y - p.sigma0 * x).abs();
                prop_assert!(dev <= bound, "x={x}: F={y}, σ0 x={}", p.sigma0 * x);
                // and the bristle itself: s z in [|x| − σ0 x²/(2 g_min), |x|]
                let lag = x.abs() - s * op.bristle();
                let allowed = p.sigma0 * x * x / (2.0 * g_min);
                let slack = 8.0 * EPS * x.abs();
                prop_assert!(
                    lag >= -slack && lag <= allowed + slack,
                    "x={x}: z={}",
                    op.bristle()
                );
                if allowed > 0.0 {
                    worst = worst.max(lag / allowed);
                }
            }
            Ok(worst)
        },
    );
}

/// `|z| ≤ max(|z0|, max(F_c, F_s)/σ0)` for any input and any `dt`, exactly.
#[test]
fn lugre_bristle_is_bounded() {
    measure(
        "lugre max |z| / max(|z0|, max(F_c, F_s)/σ0)",
        256,
        (lugre_params(), -2.0..2.0f64, signal(1.0, 30)),
        |(p, z0, xs)| {
            let zmax = p.f_c.max(p.f_s) / p.sigma0;
            let p = LuGreParams { z0: z0 * zmax, ..p };
            let bound = p.z0.abs().max(zmax);
            let mut op = ok(LuGre::from_params(p))?;
            let mut worst = 0.0_f64;
            for &x in &xs {
                ok(op.trial(x))?;
                op.commit();
                let z = op.bristle();
                prop_assert!(z.abs() <= bound, "|{z}| > {bound}");
                worst = worst.max(z.abs() / bound);
            }
            Ok(worst)
        },
    );
}

/// Classic RK4 on `dz/dt = v − σ0 |v| z / g(v)` over one sample, `m`
/// sub-steps, `v` constant (an independent explicit reference).
fn lugre_rk4(p: &LuGreParams<f64>, z: f64, v: f64, m: usize) -> f64 {
    let a = p.sigma0 * v.abs() / g(p, v);
    rk4(|z: f64| v - a * z, z, p.dt / m as f64, m)
}

/// The exact per-sample update against RK4 with 1000 sub-steps per sample
/// on random piecewise-linear paths. For this linear ODE RK4's amplification
/// per sub-step differs from `e^{−ah}` by at most `(ah)⁵/120`; with
/// `θ = a dt ≤ 20` per sample (`ah ≤ 0.02`) that is ≤ 3e-11 per sub-step,
/// so the relative bristle error stays below 1e-7 even summed over all
/// sub-steps of a run; the printed maximum is far smaller. Compared: the
/// force built from the RK4 bristle with the same output formula.
#[test]
fn lugre_exact_integrator_agrees_with_fine_rk4() {
    measure(
        "lugre exact vs RK4 ×1000 (force error / force scale)",
        48,
        (lugre_params(), signal(1.0, 10)),
        |(p, xs)| {
            // keep θ = σ0 |Δx| / g ≤ 20 per sample
            let g_min = p.f_c.min(p.f_s);
            let max_step = xs
                .iter()
                .scan(0.0, |prev, &x| {
                    let d = (x - *prev).abs();
                    *prev = x;
                    Some(d)
                })
                .fold(0.0, f64::max);
            prop_assume!(max_step > 0.0);
            let scale_x = (20.0 * g_min / p.sigma0 / max_step).min(1.0);
            let xs: Vec<f64> = xs.iter().map(|x| x * scale_x).collect();
            let mut op = ok(LuGre::from_params(p))?;
            let (mut z, mut prev, mut worst) = (p.z0, 0.0, 0.0_f64);
            let f_scale = p.f_c.max(p.f_s);
            for &x in &xs {
                let y = ok(op.trial(x))?.output;
                op.commit();
                let v = (x - prev) / p.dt;
                prev = x;
                // at a standstill z holds and F = σ0 z
                let zdot = if v == 0.0 {
                    0.0
                } else {
                    z = lugre_rk4(&p, z, v, 1000);
                    v - p.sigma0 * v.abs() * z / g(&p, v)
                };
                let reference = p.sigma0 * z + p.sigma1 * zdot + p.sigma2 * v;
                let e = (y - reference).abs() / (f_scale + (p.sigma1 + p.sigma2) * v.abs());
                prop_assert!(e < 1e-7, "x={x}: {y} vs {reference}");
                worst = worst.max(e);
            }
            Ok(worst)
        },
    );
}

/// The force for `x(t) = A sin(2π f t)` sampled at `dt` over 0.4 s.
fn lugre_sine(p: &LuGreParams<f64>, dt: f64) -> Vec<f64> {
    let n = (0.4 / dt).round() as usize;
    let xs: Vec<f64> = (1..=n)
        .map(|k| 2e-3 * (std::f64::consts::TAU * 5.0 * k as f64 * dt).sin())
        .collect();
    let mut op = LuGre::from_params(LuGreParams { dt, ..*p }).unwrap();
    op.run(&xs).unwrap()
}

/// Rate-dependent, so refining `dt` on the same input path must converge
/// (not be equal). The largest error at the shared sample times against a
/// 256× finer run halves with each halving of `dt` (first order: `v` is
/// the mean velocity over a sample, `O(dt)` from the velocity at its end)
/// when `σ1` or `σ2` is non-zero; with `σ1 = σ2 = 0` only the Stribeck
/// curve sees the velocity, and the error falls about 4× (the mean
/// velocity is second-order accurate at the middle of the sample).
#[test]
fn lugre_converges_under_refinement_of_dt() {
    let base = LuGreParams {
        sigma0: 1e4,
        sigma1: 20.0,
        sigma2: 5.0,
        f_c: 1.0,
        f_s: 1.5,
        v_s: 0.01,
        delta: 2.0,
        z0: 0.0,
        dt: 1.0,
    };
    let no_damping = LuGreParams {
        sigma1: 0.0,
        sigma2: 0.0,
        ..base
    };
    for (label, p, lo, hi) in [
        ("σ1, σ2 > 0", base, 1.8, 2.2),
        ("σ1 = σ2 = 0", no_damping, 3.5, 4.5),
    ] {
        let dts = [4e-4, 2e-4, 1e-4, 5e-5];
        let fine = dts[0] / 256.0;
        let reference = lugre_sine(&p, fine);
        let errors: Vec<f64> = dts
            .iter()
            .map(|&dt| {
                let m = (dt / fine).round() as usize;
                lugre_sine(&p, dt)
                    .iter()
                    .enumerate()
                    .map(|(k, y)| (y - reference[(k + 1) * m - 1]).abs())
                    .fold(0.0, f64::max)
            })
            .collect();
        let ratios: Vec<f64> = errors.windows(2).map(|w| w[0] / w[1]).collect();
        let shown: Vec<String> = errors.iter().map(|e| format!("{e:.3e}")).collect();
        eprintln!("lugre refinement ({label}): max errors {shown:?}, ratios {ratios:.2?}");
        for r in &ratios {
            assert!(
                *r > lo && *r < hi,
                "{label}: ratios {ratios:?} ({errors:?})"
            );
        }
    }
}

/// LuGre depends on the rate (the same path at another `dt` gives another
/// force), Dahl and Maxwell-slip do not.
#[test]
fn lugre_is_rate_dependent() {
    let p = common::lugre_at_100_hz();
    let xs: Vec<f64> = (1..200).map(|k| (k as f64 * 0.05).sin()).collect();
    let a = LuGre::from_params(p).unwrap().run(&xs).unwrap();
    let b = LuGre::from_params(LuGreParams { dt: 0.1, ..p })
        .unwrap()
        .run(&xs)
        .unwrap();
    let diff = a
        .iter()
        .zip(&b)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    eprintln!("lugre at dt = 0.01 vs 0.1 on one path: max |ΔF| = {diff:.3}");
    assert!(diff > 0.1, "{diff}");
}

// ---------------------------------------------------------------------------
// GMS
// ---------------------------------------------------------------------------

/// 1–6 elements (stiffness 10–1e4, weight 0.05–1), attraction rate
/// 1–100/s, Stribeck curve with F_c in [0.2, 2], F_s in [0.2, 3], v_s in
/// [0.001, 0.5], δ in [1, 3], σ2 in [0, 2], dt in [1e-4, 1e-2]; unloaded.
fn gms_params() -> impl Strategy<Value = GmsParams<f64>> {
    (
        prop::collection::vec((10.0..1e4f64, 0.05..1.0f64), 1..7),
        (1.0..100.0f64, 0.2..2.0f64, 0.2..3.0f64, 0.001..0.5f64),
        (1.0..3.0f64, 0.0..2.0f64, 1e-4..1e-2f64),
    )
        .prop_map(|(elements, stribeck, rest)| {
            common::gms_of(&elements, stribeck, rest, Vec::new())
        })
}

/// With `F_s = F_c` (no Stribeck effect) and `σ2 = 0`, GMS is the
/// Maxwell-slip bank with break-away forces `α_i F_c`, for any attraction
/// rate and any `dt` (different formulas: GMS adds `k_i Δx` per sample,
/// so the allowance is `4ε` per sample times `Σ (α_i F_c + k_i max|x|)`).
#[test]
fn gms_without_stribeck_effect_is_maxwell_slip() {
    measure(
        "gms (F_s = F_c) vs maxwell-slip (error / allowance)",
        256,
        (
            gms_params(),
            prop::collection::vec(-1.0..=1.0f64, 6),
            signal(1.0, 30),
        ),
        |(p, preload, xs)| {
            let n = p.k.len();
            let p = GmsParams {
                f_s: p.f_c,
                sigma2: 0.0,
                f0: (0..n).map(|i| preload[i] * p.alpha[i] * p.f_c).collect(),
                ..p
            };
            // keep the travel within a few break-away displacements
            let reach = p
                .alpha
                .iter()
                .zip(&p.k)
                .map(|(a, k)| a * p.f_c / k)
                .fold(0.0, f64::max);
            let xs: Vec<f64> = xs.iter().map(|x| 3.0 * reach * x).collect();
            let ms = MaxwellSlipParams {
                k: p.k.clone(),
                f_b: p.alpha.iter().map(|a| a * p.f_c).collect(),
                f0: p.f0.clone(),
            };
            let a = ok(ok(Gms::from_params(p.clone()))?.run(&xs))?;
            let b = ok(ok(MaxwellSlip::from_params(ms.clone()))?.run(&xs))?;
            let x_max = xs.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            let scale: f64 = (0..n).map(|i| ms.f_b[i] + p.k[i] * x_max).sum();
            let allowance = 4.0 * EPS * (xs.len() as f64 + 1.0) * scale;
            let worst = a
                .iter()
                .zip(&b)
                .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()))
                / allowance;
            prop_assert!(worst <= 1.0, "{a:?}\n{b:?}");
            Ok(worst)
        },
    );
}

/// At constant velocity `v` from rest, every element sticks until it
/// meets its limit `α_i s(v)` and stays there: `F = Σ_i sgn(v) min(k_i |x|,
/// α_i s(v)) + σ2 v` (`s` written out here), to rounding (`4ε` per sample
/// of the force scale).
#[test]
fn gms_constant_velocity_closed_form() {
    measure_constant_velocity("gms", gms_params(), 1.0, 300, |p, v, n| {
        let s = p.f_c + (p.f_s - p.f_c) * (-(v.abs() / p.v_s).powf(p.delta)).exp();
        let scale = p.alpha.iter().sum::<f64>() * p.f_c.max(p.f_s) + p.sigma2 * v.abs();
        let mut op = ok(Gms::from_params(p.clone()))?;
        let mut worst = 0.0_f64;
        for j in 1..=n {
            let x = v * p.dt * j as f64;
            let y = ok(op.trial(x))?.output;
            op.commit();
            let elements: f64 =
                p.k.iter()
                    .zip(&p.alpha)
                    .map(|(k, a)| (k * x.abs()).min(a * s))
                    .sum();
            let expected = v.signum() * elements + p.sigma2 * v;
            let e = (y - expected).abs() / scale;
            prop_assert!(
                e <= 4.0 * EPS * (j as f64 + 4.0),
                "j={j}: {y} vs {expected}"
            );
            worst = worst.max(e);
        }
        Ok(worst)
    });
}

/// Frictional lag: sliding steadily at `v1` (every element slipping at
/// `α_i s(v1)`), a step to `v2` of the same sign relaxes each element as
/// `F_i = σ α_i (s2 + (s1 − s2) e^{−C t/(α_i s2)})` (the slip law's
/// solution at constant velocity), to rounding.
#[test]
fn gms_frictional_lag_after_a_velocity_step() {
    measure(
        "gms velocity step vs closed form (relative)",
        256,
        (gms_params(), 0.01..1.0f64, 0.01..1.0f64, any::<bool>()),
        |(p, v1, v2, negative)| {
            let sign = if negative { -1.0 } else { 1.0 };
            let (v1, v2) = (sign * v1, sign * v2);
            let s = |v: f64| p.f_c + (p.f_s - p.f_c) * (-(v.abs() / p.v_s).powf(p.delta)).exp();
            let (s1, s2) = (s(v1), s(v2));
            // long enough at v1 for every element to reach its limit
            let travel = p
                .alpha
                .iter()
                .zip(&p.k)
                .map(|(a, k)| a * p.f_c.max(p.f_s) / k)
                .fold(0.0, f64::max);
            let n1 = (travel / (v1.abs() * p.dt)).ceil() as usize + 2;
            prop_assume!(n1 < 100_000);
            let mut op = ok(Gms::from_params(p.clone()))?;
            let mut x = 0.0;
            for _ in 0..n1 {
                x += v1 * p.dt;
                ok(op.trial(x))?;
                op.commit();
            }
            prop_assert!(op.slipping().iter().all(|&s| s));
            let scale = p.alpha.iter().sum::<f64>() * p.f_c.max(p.f_s);
            let mut worst = 0.0_f64;
            for j in 1..=200 {
                x += v2 * p.dt;
                let y = ok(op.trial(x))?.output;
                op.commit();
                let t = j as f64 * p.dt;
                let elements: f64 = p
                    .alpha
                    .iter()
                    .map(|a| a * (s2 + (s1 - s2) * (-p.c * t / (a * s2)).exp()))
                    .sum();
                let expected = sign * elements + p.sigma2 * v2;
                let e = (y - expected).abs() / scale;
                // the velocity from differences of x carries ε|x|/(|v| dt)
                let allowance =
                    1e-12 + 4.0 * EPS * (j as f64 + 4.0) * (1.0 + x.abs() / (v2.abs() * p.dt));
                prop_assert!(e <= allowance, "j={j}: {y} vs {expected}");
                worst = worst.max(e);
            }
            Ok(worst)
        },
    );
}

/// `|F_i| ≤ max(|f0_i|, α_i max(F_c, F_s))` for every element, any input,
/// any `dt` (to one rounding of the limit).
#[test]
fn gms_element_forces_are_bounded() {
    measure(
        "gms max |F_i| / max(|f0_i|, α_i max(F_c, F_s))",
        256,
        (
            gms_params(),
            prop::collection::vec(-2.0..=2.0f64, 6),
            signal(1.0, 30),
            1e-4..1.0f64,
        ),
        |(p, preload, xs, amp)| {
            let n = p.k.len();
            let top = p.f_c.max(p.f_s);
            let p = GmsParams {
                f0: (0..n).map(|i| preload[i] * p.alpha[i] * top).collect(),
                ..p
            };
            let bounds: Vec<f64> = (0..n)
                .map(|i| p.f0[i].abs().max(p.alpha[i] * top))
                .collect();
            let mut op = ok(Gms::from_params(p.clone()))?;
            let mut worst = 0.0_f64;
            for &x in &xs {
                ok(op.trial(amp * x))?;
                op.commit();
                for (f, b) in op.element_forces().iter().zip(&bounds) {
                    prop_assert!(f.abs() <= b * (1.0 + 4.0 * EPS), "|{f}| > {b}");
                    worst = worst.max(f.abs() / b);
                }
            }
            Ok(worst)
        },
    );
}

// ---------------------------------------------------------------------------
// Specs
// ---------------------------------------------------------------------------

/// Each friction spec builds exactly the library's operator, round-trips
/// through JSON, and names the path of a bad value; `lugre` is
/// rate-dependent and takes its `dt` from `with_dt`.
#[test]
fn friction_specs_build_round_trip_and_report_errors() {
    let xs: Vec<f64> = (1..300).map(|k| 1.2 * (k as f64 * 0.04).sin()).collect();
    let cases: [(&str, Box<dyn Operator<f64>>); 4] = [
        (
            r#"{"type": "maxwell_slip", "k": [20, 5], "f_b": [0.4, 1.0], "f0": [0.1, -0.2]}"#,
            MaxwellSlip::from_params(MaxwellSlipParams {
                k: vec![20.0, 5.0],
                f_b: vec![0.4, 1.0],
                f0: vec![0.1, -0.2],
            })
            .unwrap()
            .boxed(),
        ),
        (
            r#"{"type": "dahl", "sigma": 30, "f_c": 1.2, "alpha": 1.5}"#,
            Dahl::new(30.0, 1.2, 1.5).unwrap().boxed(),
        ),
        (
            r#"{"type": "lugre", "sigma0": 1000, "sigma1": 5, "sigma2": 0.2,
                "f_c": 1, "f_s": 1.5, "v_s": 0.5, "dt": 0.01}"#,
            // delta = 2 and z0 = 0, the defaults the text leaves out
            LuGre::from_params(common::lugre_at_100_hz())
                .unwrap()
                .boxed(),
        ),
        (
            r#"{"type": "gms", "k": [20, 8], "alpha": [0.6, 0.4], "c": 15,
                "f_c": 1, "f_s": 1.4, "v_s": 0.5, "dt": 0.01}"#,
            Gms::from_params(GmsParams {
                k: vec![20.0, 8.0],
                alpha: vec![0.6, 0.4],
                f0: vec![],
                c: 15.0,
                f_c: 1.0,
                f_s: 1.4,
                v_s: 0.5,
                delta: 2.0,  // the default
                sigma2: 0.0, // the default
                dt: 0.01,
            })
            .unwrap()
            .boxed(),
        ),
    ];
    for (text, mut direct) in cases {
        let spec = Spec::from_json(text).unwrap_or_else(|e| panic!("{text}: {e}"));
        let back = Spec::from_json(&spec.to_json_pretty().unwrap()).unwrap();
        assert_eq!(back, spec);
        let mut model = spec.build().unwrap();
        assert_eq!(model.param_names(), direct.param_names());
        assert_eq!(bits(&model.params()), bits(&direct.params()));
        let ys = model.run(&xs).unwrap();
        assert_eq!(bits(&ys), bits(&direct.run(&xs).unwrap()), "{text}");
        assert!(ys.iter().any(|&y| y != 0.0));
        assert_eq!(spec.with_params(&model.params()).unwrap(), spec);
        assert_eq!(
            spec.is_rate_dependent(),
            ["lugre", "gms"].contains(&spec.kind()),
            "{text}"
        );
    }
    // lugre: with_dt sets its sample period, describe shows it
    let lugre = Spec::from_json(
        r#"{"type": "parallel", "left": {"type": "dahl", "sigma": 3, "f_c": 1, "alpha": 1},
            "right": {"type": "lugre", "sigma0": 1000, "sigma1": 5, "sigma2": 0.2,
                      "f_c": 1, "f_s": 1.5, "v_s": 0.5, "delta": 1.5, "dt": 0.01}}"#,
    )
    .unwrap();
    assert_eq!(lugre.describe(), "parallel(dahl, lugre[dt=0.01])");
    assert!(lugre.is_rate_dependent());
    let Spec::Parallel { right, .. } = lugre.with_dt(0.5) else {
        panic!()
    };
    let Some(p) = right.leaf_params::<hysteron::operators::LuGre<f64>>() else {
        panic!()
    };
    assert_eq!((p.dt, p.delta), (0.5, 1.5));
    // errors name the path
    for (text, message) in [
        (
            r#"{"type": "scaled", "w": 2, "inner": {"type": "maxwell_slip", "k": [1, -1], "f_b": [1, 1]}}"#,
            "scaled.inner.maxwell_slip.k[1]: must be > 0 (got -1)",
        ),
        (
            r#"{"type": "maxwell_slip", "k": [1, 2], "f_b": [1]}"#,
            "maxwell_slip.f_b: must have one entry per element of k, as must f0 if given (got 1)",
        ),
        (
            r#"{"type": "dahl", "sigma": 3, "f_c": 1, "alpha": -1}"#,
            "dahl.alpha: must be ≥ 0 (got -1)",
        ),
        (
            r#"{"type": "gms", "k": [20, 8], "alpha": [0.6, 0.4], "c": 15,
                "f_c": 1, "f_s": 1.4, "v_s": 0.5, "delta": 0.5, "dt": 0.01}"#,
            "gms.delta: must be ≥ 1 (got 0.5)",
        ),
        (
            r#"{"type": "lugre", "sigma0": 0, "sigma1": 5, "sigma2": 0.2,
                "f_c": 1, "f_s": 1.5, "v_s": 0.5, "dt": 0.01}"#,
            "lugre.sigma0: must be > 0 (got 0)",
        ),
        (
            r#"{"type": "lugre", "sigma0": 10, "sigma1": 5, "sigma2": 0.2,
                "f_c": 1, "f_s": 1.5, "v_s": 0.5, "dt": 0}"#,
            "lugre.dt: must be > 0 (got 0)",
        ),
    ] {
        let e = Spec::from_json(text).unwrap().build().unwrap_err();
        assert_eq!(e.to_string(), message);
    }
    for (text, path, message) in [
        (
            r#"{"type": "lugre", "sigma0": 10, "sigma1": 5, "sigma2": 0.2, "f_c": 1, "f_s": 1.5}"#,
            "lugre",
            "missing field `v_s`",
        ),
        (
            r#"{"type": "dahl", "sigma": 3, "f_c": 1, "alpha": 1, "beta": 2}"#,
            "beta",
            "unknown field `beta`",
        ),
        (
            r#"{"type": "maxwell_slip", "k": [1], "f_b": 1}"#,
            "f_b",
            "invalid type",
        ),
    ] {
        let e = Spec::from_json(text).unwrap_err();
        assert_eq!(e.path(), path, "{e}");
        assert!(e.to_string().contains(message), "{e}");
    }
    // dt may be left to the data: the spec reads, and building names it
    let pending = Spec::from_json(
        r#"{"type": "lugre", "sigma0": 10, "sigma1": 5, "sigma2": 0.2, "f_c": 1, "f_s": 1.5, "v_s": 0.5}"#,
    )
    .unwrap();
    assert_eq!(pending.build().unwrap_err().path(), "lugre.dt");
}

// ---------------------------------------------------------------------------
// f32
// ---------------------------------------------------------------------------

/// The models are generic over the float type: in `f32` they follow the
/// `f64` run to `f32` precision, relative to the force scale. The input
/// itself is rounded to `f32` (an error of stiffness × ulp(x), up to
/// 25 × 1.2 × 6e-8 ≈ 2e-6 for Maxwell-slip) and LuGre's bristle gathers one
/// rounding per sample: the bound allows 300 `f32` epsilons (3.6e-5).
#[test]
fn friction_models_run_in_f32() {
    let xs: Vec<f64> = (1..400)
        .map(|k| 1.2 * (k as f64 * 0.03).sin() + 0.1 * (k as f64 * 0.4).sin())
        .collect();
    let xs32: Vec<f32> = xs.iter().map(|&x| x as f32).collect();
    let lugre = |sigma0: f64| LuGreParams {
        sigma0,
        ..common::lugre_at_100_hz()
    };
    let l32 = common::lugre_at_100_hz::<f32>();
    let pairs: [(&str, Vec<f64>, Vec<f32>, f64); 3] = [
        (
            "maxwell-slip",
            MaxwellSlip::new(vec![25.0, 10.0, 4.0], vec![0.5, 0.4, 0.9])
                .unwrap()
                .run(&xs)
                .unwrap(),
            MaxwellSlip::new(vec![25.0_f32, 10.0, 4.0], vec![0.5, 0.4, 0.9])
                .unwrap()
                .run(&xs32)
                .unwrap(),
            1.8,
        ),
        (
            "dahl",
            Dahl::new(20.0, 1.0, 1.5).unwrap().run(&xs).unwrap(),
            Dahl::new(20.0_f32, 1.0, 1.5).unwrap().run(&xs32).unwrap(),
            1.0,
        ),
        (
            "lugre",
            LuGre::from_params(lugre(1e3)).unwrap().run(&xs).unwrap(),
            LuGre::from_params(l32).unwrap().run(&xs32).unwrap(),
            1.5 + 5.2 * 5.0,
        ),
    ];
    for (name, y64, y32, scale) in pairs {
        let worst = y64
            .iter()
            .zip(&y32)
            .fold(0.0_f64, |m, (a, b)| m.max((a - *b as f64).abs()))
            / scale;
        eprintln!("{name} f32 vs f64: max error {worst:.3e} of the force scale");
        assert!(worst < 300.0 * f32::EPSILON as f64, "{name}: {worst}");
    }
}
