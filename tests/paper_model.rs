//! The paper's transmission model: agreement with an independent per-sample
//! oracle, and the behaviours the paper reports.

use hysteron::models::experiments::{paper_experiments, simulate, sine, FS};
use hysteron::models::{paper_state, TransmissionParams};
use hysteron::prelude::*;
use proptest::prelude::*;

/// An independent, minimal implementation of DESIGN §3, written without the
/// combinators: per sample, bisection on the slider increment `Δr` between
/// 0 and `Δx` (clipped to the gap) of `g(Δr) = MMS(r + Δr) − H(z + Δx − Δr)`,
/// with its own MMS branch formula and its own closed-form Bouc-Wen state
/// (n = 1, constant-per-branch coefficients) and piecewise-linear S.
struct Oracle {
    p: TransmissionParams,
    x: f64,
    r: f64, // slider position in the gap
    // MMS
    m_x: f64,
    m_y: f64,
    m_xr: f64,
    m_yr: f64,
    m_dir: i8,
    // spring
    z: f64,
    h: f64,
}

impl Oracle {
    fn new(p: TransmissionParams) -> Self {
        assert_eq!(
            p.spring.n, 1.0,
            "the oracle's spring is the n = 1 closed form"
        );
        Oracle {
            x: 0.0,
            r: p.slider0,
            m_x: 0.0,
            m_y: p.friction.y0,
            m_xr: 0.0,
            m_yr: p.friction.y0,
            m_dir: 0,
            z: -p.slider0,
            h: p.spring.h0,
            p,
        }
    }

    /// MMS force if the slider moves by `d` (no state change).
    fn mms(&self, d: f64) -> (f64, f64, f64, i8) {
        let x = self.m_x + d;
        let dir = if d > 0.0 {
            1
        } else if d < 0.0 {
            -1
        } else {
            return (self.m_y, self.m_xr, self.m_yr, self.m_dir);
        };
        let (xr, yr) = if dir != self.m_dir {
            (self.m_x, self.m_y)
        } else {
            (self.m_xr, self.m_yr)
        };
        let target = dir as f64 * self.p.friction.f_c;
        let y = target + (yr - target) * (-self.p.friction.k * (x - xr).abs()).exp();
        (y, xr, yr, dir)
    }

    fn stiffness(&self, z: f64) -> f64 {
        let (zs, ss) = (
            self.p.spring.stiffness.knots_z(),
            self.p.spring.stiffness.knots_s(),
        );
        let a = z.abs();
        if a <= zs[0] {
            return ss[0];
        }
        for i in 1..zs.len() {
            if a <= zs[i] {
                return ss[i - 1] + (ss[i] - ss[i - 1]) * (a - zs[i - 1]) / (zs[i] - zs[i - 1]);
            }
        }
        *ss.last().unwrap()
    }

    /// Spring state after moving the deflection from `self.z` to `z`.
    fn h_at(&self, z: f64) -> f64 {
        let sp = &self.p.spring;
        let dz = z - self.z;
        if dz == 0.0 {
            return self.h;
        }
        let sgn = dz.signum();
        let mut g = sgn * self.h; // state seen in the direction of motion
        let mut s = dz.abs();
        // dg/ds = α − c g, c = β + γ (g > 0) or β − γ (g < 0)
        loop {
            let c = if g > 0.0 || (g == 0.0 && sp.alpha > 0.0) {
                sp.beta + sp.gamma
            } else {
                sp.beta - sp.gamma
            };
            let ginf = sp.alpha / c;
            if g < 0.0 && ginf > 0.0 {
                // time to reach 0: g(s) = ginf + (g − ginf) e^{−cs} = 0
                let s0 = ((ginf - g) / ginf).ln() / c;
                if s0 < s {
                    s -= s0;
                    g = 0.0;
                    continue;
                }
            }
            g = ginf + (g - ginf) * (-c * s).exp();
            break;
        }
        sgn * g
    }

    fn spring_force(&self, z: f64) -> f64 {
        let w = self.p.spring.w;
        let s = self.stiffness(z);
        w * s * z + (1.0 - w) * s * self.h_at(z)
    }

    fn step(&mut self, x: f64) -> f64 {
        let dx = x - self.x;
        let half = 0.5 * self.p.backlash;
        // Δr between 0 and Δx, clipped to the gap.
        let (mut lo, mut hi) = if dx >= 0.0 { (0.0, dx) } else { (dx, 0.0) };
        lo = lo.max(-half - self.r);
        hi = hi.min(half - self.r);
        let g = |d: f64| self.mms(d).0 - self.spring_force(self.z + dx - d);
        let d = if g(hi) <= 0.0 {
            hi
        } else if g(lo) >= 0.0 {
            lo
        } else {
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                if g(mid) > 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            0.5 * (lo + hi)
        };
        let force = self.spring_force(self.z + dx - d);
        // commit
        let (y, xr, yr, dir) = self.mms(d);
        self.m_x += d;
        self.m_y = y;
        self.m_xr = xr;
        self.m_yr = yr;
        self.m_dir = dir;
        self.h = self.h_at(self.z + dx - d);
        self.z += dx - d;
        self.r += d;
        self.x = x;
        force
    }
}

fn params_strategy() -> impl Strategy<Value = TransmissionParams> {
    (
        0.05..0.6_f64,                             // backlash
        -1.0..1.0_f64,                             // slider0 fraction of b/2
        0.5..5.0_f64,                              // f_c
        5.0..80.0_f64,                             // k
        0.5..0.95_f64,                             // w
        1.0..4.0_f64,                              // beta
        -0.5..0.5_f64,                             // gamma fraction of beta
        1.0..20.0_f64,                             // S(0)
        prop::collection::vec(0.0..0.2_f64, 0..4), // relative stiffness increments
    )
        .prop_map(|(b, r0, f_c, k, w, beta, gf, s0, inc)| {
            // A spring whose force rises with z on every branch (a unique
            // equilibrium): w S ≥ 0.5 S dominates (1 − w) S' |h| with
            // |h| ≤ 1/(β + γ) ≤ 2 and S' ≤ 0.5 S. Steeper stiffness maps
            // make H non-monotone and the equilibrium ambiguous.
            let mut s = vec![s0];
            for u in inc {
                let last = *s.last().unwrap();
                s.push(last * (1.0 + u));
            }
            let z: Vec<f64> = (0..s.len()).map(|i| 0.4 * i as f64).collect();
            let d = TransmissionParams::default();
            let mut p = TransmissionParams {
                backlash: b,
                slider0: r0 * b / 2.0,
                friction: MmsParams { f_c, k, y0: 0.0 },
                spring: BoucWenParams {
                    w,
                    beta,
                    gamma: gf * beta,
                    stiffness: StiffnessMap::new(z, s).unwrap(),
                    ..d.spring
                },
            };
            // A consistent initial state: the friction holds the spring's
            // force at z = −slider0 (h0 = 0); otherwise start centred.
            let h = p.spring.w * p.spring.stiffness.eval(-p.slider0).0 * -p.slider0;
            if h.abs() <= p.friction.f_c {
                p.friction.y0 = h;
            } else {
                p.slider0 = 0.0;
            }
            p
        })
}

fn input_strategy() -> impl Strategy<Value = Vec<f64>> {
    // A random walk of ramps with reversals, steps from tiny to large.
    prop::collection::vec((-1.5..1.5_f64, 1_usize..40), 1..12).prop_map(|legs| {
        let mut xs = Vec::new();
        let mut x = 0.0;
        for (target, n) in legs {
            for k in 1..=n {
                xs.push(x + (target - x) * k as f64 / n as f64);
            }
            x = target;
        }
        xs
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    /// The composed model agrees with the oracle to 1e-9 relative.
    #[test]
    fn composed_model_agrees_with_oracle(p in params_strategy(), xs in input_strategy()) {
        let mut model = p.build().unwrap();
        let mut oracle = Oracle::new(p.clone());
        let scale = xs.iter().fold(1.0_f64, |m, x| m.max(x.abs()))
            * p.spring.stiffness.knots_s().iter().fold(p.friction.f_c, |m, s| m.max(*s));
        for (i, &x) in xs.iter().enumerate() {
            let f = model.trial(x).unwrap().output;
            model.commit();
            let o = oracle.step(x);
            prop_assert!((f - o).abs() <= 1e-9 * scale, "sample {}: model {} oracle {} (x = {})", i, f, o, x);
            let st = paper_state(&model, x);
            prop_assert!((st.slider - oracle.r).abs() <= 1e-9 * p.backlash, "slider {} vs {}", st.slider, oracle.r);
            prop_assert!(st.slider.abs() <= p.backlash / 2.0 * (1.0 + 1e-12));
        }
    }
}

fn default_run(signal: &[f64]) -> (Vec<f64>, Vec<hysteron::models::TransmissionState>) {
    let mut model = TransmissionParams::default().build().unwrap();
    let mut f = Vec::new();
    let mut st = Vec::new();
    for &x in signal {
        f.push(model.trial(x).unwrap().output);
        model.commit();
        st.push(paper_state(&model, x));
    }
    (f, st)
}

#[test]
fn major_loop_is_point_symmetric_at_low_frequency() {
    // 0.05 Hz, 3 cycles at 1 kHz: 20 000 samples per cycle.
    let s = sine(0.05, 1.5, 3.0, FS).unwrap();
    let (f, _) = default_run(&s.x);
    let n = 20_000;
    let last = &f[2 * n..3 * n];
    let peak = last.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    assert!(
        peak > 10.0 && peak < 25.0,
        "peak {peak} outside the paper's range"
    );
    let mut worst = 0.0_f64;
    for i in 0..n / 2 {
        // x(θ + π) = −x(θ) on the steady loop ⇒ F(θ + π) = −F(θ)
        worst = worst.max((last[i + n / 2] + last[i]).abs());
    }
    assert!(worst <= 1e-9 * peak, "asymmetry {worst}");
}

#[test]
fn two_initial_states_differ_at_first_then_share_the_steady_loop() {
    let exps = paper_experiments(&TransmissionParams::default()).unwrap();
    let run = |name: &str| {
        let e = exps.iter().find(|e| e.name == name).unwrap();
        simulate(&e.params, &e.signal).unwrap()
    };
    let (a, b) = (run("sine-5hz-I"), run("sine-5hz-II"));
    let n = 200; // samples per 5 Hz cycle at 1 kHz
    let diff = |range: std::ops::Range<usize>| {
        range
            .map(|i| (a.force[i] - b.force[i]).abs())
            .fold(0.0_f64, f64::max)
    };
    let first = diff(0..n);
    let last = diff(a.force.len() - n..a.force.len());
    let peak = a.force.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    assert!(
        first > 0.05 * peak,
        "initial states should give different outputs: max diff {first}, peak {peak}"
    );
    assert!(
        last < 1e-6 * first,
        "runs should converge to one loop: first {first}, last {last}"
    );
}

#[test]
fn force_plateaus_at_coulomb_level_inside_the_gap() {
    let p = TransmissionParams::default();
    let f_c = p.friction.f_c;
    let s = sine(0.5, 1.5, 2.0, FS).unwrap();
    let (f, st) = default_run(&s.x);
    let half = p.backlash / 2.0;
    let mut inside = 0;
    let mut plateau = 0;
    for (fi, si) in f.iter().zip(&st) {
        if si.slider.abs() < half * (1.0 - 1e-9) {
            inside += 1;
            assert!(
                fi.abs() <= f_c * (1.0 + 1e-9),
                "force {fi} above F_c while sliding"
            );
            assert!((fi - si.friction).abs() <= 1e-9 * f_c, "equilibrium broken");
            if fi.abs() > 0.99 * f_c {
                plateau += 1;
            }
        } else {
            // at a stop the contact only pushes: |F| ≥ friction it meets
            assert!(fi * si.slider.signum() >= si.friction * si.slider.signum() - 1e-9 * f_c);
        }
    }
    assert!(
        inside > 100 && plateau > 10,
        "inside {inside}, plateau {plateau}"
    );
}

#[test]
fn refined_sampling_does_not_change_the_force() {
    // n = 1: the spring is exact per step, so refinement changes F only by
    // rounding and the solver tolerance.
    let s = sine(0.5, 1.5, 2.0, 250.0).unwrap();
    let mut fine = Vec::new();
    let mut prev = 0.0;
    for &x in &s.x {
        for k in 1..=4 {
            fine.push(prev + (x - prev) * k as f64 / 4.0);
        }
        prev = x;
    }
    let (coarse, _) = default_run(&s.x);
    let (refined, _) = default_run(&fine);
    let peak = coarse.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let worst = coarse
        .iter()
        .enumerate()
        .map(|(i, f)| (refined[4 * i + 3] - f).abs())
        .fold(0.0_f64, f64::max);
    assert!(
        worst <= 1e-9 * peak,
        "refinement changed F by {worst} (peak {peak})"
    );
}

#[test]
fn swapping_parts_gives_a_working_model() {
    use hysteron::models::transmission;
    let spring = BoucWen::constant(8.0, 0.5, 1.0, 2.0, 1.0, 1.5).unwrap();
    let mut m = transmission(ElastoPlastic::new(40.0, 2.0).unwrap(), spring, 0.3, 0.0).unwrap();
    let s = sine(0.5, 1.5, 1.0, 200.0).unwrap();
    let f = m.run(&s.x).unwrap();
    assert!(f.iter().all(|v| v.is_finite()));
    assert!(f.iter().fold(0.0_f64, |a, v| a.max(v.abs())) > 2.0);
}

/// The `sines` run's parts are where its pieces landed: 0.05 Hz × 2 cycles
/// (40 s at 1 kHz, both ends: 40 001 samples), a 1 s pause (1000), 0.5 Hz
/// × 4 (8001), a pause, 5 Hz × 10 (2001); each starts at x = 0 on a whole
/// second. The other experiments are one part each.
#[test]
fn sines_parts_are_where_the_pieces_landed() {
    let exps = paper_experiments(&TransmissionParams::default()).unwrap();
    let sines = exps.iter().find(|e| e.name == "sines").unwrap();
    let got: Vec<(&str, std::ops::Range<usize>)> = sines
        .parts
        .iter()
        .map(|p| (p.label.as_str(), p.range.clone()))
        .collect();
    assert_eq!(
        got,
        [
            ("0.05 Hz", 0..40_001),
            ("0.5 Hz", 41_001..49_002),
            ("5 Hz", 50_002..52_003)
        ]
    );
    assert_eq!(sines.signal.len(), 52_003);
    for (p, t0) in sines.parts.iter().zip([0.0, 41.0, 50.0]) {
        let i = p.range.start;
        assert!(sines.signal.x[i].abs() < 1e-12, "{}", p.label);
        assert!(
            (sines.signal.t[i] - t0).abs() < 2e-3,
            "{}",
            sines.signal.t[i]
        );
    }
    for e in exps.iter().filter(|e| e.name != "sines") {
        assert_eq!(e.parts.len(), 1, "{}", e.name);
        assert_eq!(e.parts[0].range, 0..e.signal.len(), "{}", e.name);
    }
}
