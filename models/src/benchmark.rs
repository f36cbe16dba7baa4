//! The Bouc-Wen hysteretic benchmark (Noël & Schoukens, *Hysteretic
//! benchmark with a dynamic nonlinearity*, 2016) as a composed system.
//!
//! The benchmark system is a single-degree-of-freedom oscillator with a
//! hysteretic restoring force,
//!
//! `m ÿ + c ẏ + k y + z = u`, `ż = A ẏ − β' |ẏ| |z|^{n−1} z − γ' ẏ |z|^n`,
//!
//! force `u` in, displacement `y` out. It is built from the algebra, not
//! written by hand: a [`MassSpringDamper`] `G` (`m ÿ + c ẏ + k y = f`) in
//! the forward path and a purely hysteretic [`BoucWen`] spring in the
//! return path (`w = 0`, constant stiffness 1, so its output is its state,
//! `dz/dy = A − |z|^n (β' sgn(ẏ z) + γ')`, which is the equation above
//! divided by `ẏ`):
//!
//! `y = G[u − z]`, `z = BW[y]`, i.e. `G.feedback(BW)`,
//!
//! solved implicitly at every integration step ([`Feedback`]). The
//! mass-spring-damper integrates with Newmark's average-acceleration rule,
//! as the benchmark's reference does; the Bouc-Wen state is integrated
//! exactly along each step's displacement increment (the reference uses
//! the trapezoidal rule in time there). The published parameters are
//! [`BoucWenBenchmarkParams::published`].
//!
//! The reference integrates at 20 times the data rate (15 kHz for 750 Hz
//! data). [`boucwen_system`] is the system at that integration rate, to be
//! driven by an input upsampled to it (for a periodic multisine,
//! [`fft_upsample`](crate::signal::fft_upsample) reproduces the reference's
//! 15 kHz input exactly); [`boucwen_system_at_data_rate`] wraps it in an
//! [`Oversample`] so it takes data-rate samples directly (input interpolated
//! linearly between samples). [`periodic_steady_state`] runs a periodic
//! input until the response repeats. [`simulate_record`] does all of it for
//! a record of either kind ([`RecordKind`]: one steady-state period, or a
//! record from rest such as a sine sweep), decimating the output after the
//! record's [`DecimationPlan`].

use crate::composition::{Feedback, OperatorExt, Oversample};
use crate::operators::{
    check, BoucWen, BoucWenParams, Error, MassSpringDamper, Operator, Result, StiffnessMap,
};
use crate::signal::{DecimationPlan, RecordKind};
use serde::{Deserialize, Serialize};

/// Parameters of the Bouc-Wen benchmark system, in the Wen form
/// `ż = A ẏ − β' |ẏ| |z|^{n−1} z − γ' ẏ |z|^n` (SI units).
///
/// The benchmark description writes `ż = α ẏ − β (γ |ẏ| |z|^{ν−1} z + δ ẏ |z|^ν)`
/// with `α = 5e4`, `β = 1e3`, `γ = 0.8`, `δ = −1.1`, `ν = 1`; here
/// `A = α`, `β' = β γ = 800`, `γ' = β δ = −1100`, `n = ν`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BoucWenBenchmarkParams {
    /// Mass `m` (kg).
    pub m: f64,
    /// Viscous damping `c` (N s/m).
    pub c: f64,
    /// Linear stiffness `k` (N/m).
    pub k: f64,
    /// Bouc-Wen `A` (N/m).
    pub a: f64,
    /// Bouc-Wen `β'` (1/m for `n = 1`).
    pub beta: f64,
    /// Bouc-Wen `γ'` (1/m for `n = 1`).
    pub gamma: f64,
    /// Bouc-Wen exponent `n ≥ 1`.
    pub n: f64,
    /// Data sample rate (Hz).
    pub fs: f64,
    /// Integration steps per data sample (the integration rate is
    /// `fs · upsample`).
    pub upsample: usize,
}

impl BoucWenBenchmarkParams {
    /// The published system: `m = 2`, `c = 10`, `k = 5e4`, `A = 5e4`,
    /// `β' = 800`, `γ' = −1100`, `n = 1`, data at 750 Hz integrated at
    /// 20 × 750 = 15 kHz.
    pub fn published() -> Self {
        Self {
            m: 2.0,
            c: 10.0,
            k: 5e4,
            a: 5e4,
            beta: 800.0,
            gamma: -1100.0,
            n: 1.0,
            fs: 750.0,
            upsample: 20,
        }
    }

    /// The integration step `1 / (fs · upsample)` (s).
    pub fn dt(&self) -> f64 {
        1.0 / (self.fs * self.upsample as f64)
    }

    /// Checks `fs > 0` and `upsample ≥ 1`; the oscillator and the spring
    /// check their own parameters when built.
    pub fn validate(&self) -> Result<()> {
        check::positive("fs", self.fs)?;
        if self.upsample == 0 {
            return Err(Error::InvalidParameter {
                name: "upsample".into(),
                value: 0.0,
                reason: "must be ≥ 1",
            });
        }
        Ok(())
    }

    /// The purely hysteretic spring `z = BW[y]` (`w = 0`, stiffness 1).
    pub fn spring(&self) -> Result<BoucWen<f64>> {
        BoucWen::from_params(BoucWenParams {
            w: 0.0,
            alpha: self.a,
            beta: self.beta,
            gamma: self.gamma,
            n: self.n,
            h0: 0.0,
            z0: 0.0,
            stiffness: StiffnessMap::constant(1.0)?,
        })
    }

    /// The linear part `G`, at the integration step [`dt`](Self::dt).
    pub fn oscillator(&self) -> Result<MassSpringDamper<f64>> {
        self.validate()?;
        MassSpringDamper::new(self.m, self.c, self.k, self.dt())
    }
}

impl Default for BoucWenBenchmarkParams {
    /// [`published`](Self::published).
    fn default() -> Self {
        Self::published()
    }
}

/// The benchmark system at the integration rate: `G.feedback(BW)`.
/// Its parameters are `forward.mass-spring-damper.{m, c, k}` then
/// `back.bouc_wen.{w, alpha, beta, gamma, n, h0, z0, stiffness…}`.
pub type BoucWenSystem = Feedback<f64, MassSpringDamper<f64>, BoucWen<f64>>;

/// Builds `y = G[u − z]`, `z = BW[y]` with `G` stepping at
/// `p.dt() = 1 / (fs · upsample)`: every sample of its input is one
/// integration step.
///
/// ```
/// use hysteron_models::benchmark::{boucwen_system, BoucWenBenchmarkParams};
/// use hysteron_models::operators::Operator;
/// let p = BoucWenBenchmarkParams::published();
/// let mut sys = boucwen_system(&p).unwrap();
/// // a constant 50 N force, held for 2 s at 15 kHz: the oscillator settles
/// // where k y + z(y) = 50, between the linear estimates 50/(k + A) and 50/k
/// let y = sys.run(&vec![50.0; 30_000]).unwrap();
/// let end = y[29_999];
/// assert!(end > 50.0 / (p.k + p.a) && end < 50.0 / p.k, "{end}");
/// ```
pub fn boucwen_system(p: &BoucWenBenchmarkParams) -> Result<BoucWenSystem> {
    p.validate()?;
    let g = p.oscillator().map_err(|e| e.in_path("oscillator"))?;
    let bw = p.spring().map_err(|e| e.in_path("spring"))?;
    Ok(g.feedback(bw))
}

/// The benchmark system at the data rate `fs`: [`boucwen_system`] wrapped
/// in an [`Oversample`] of `upsample` sub-steps per sample, the force
/// interpolated linearly between data samples. Linear interpolation is not
/// band-limited: for periodic data, upsampling the record with
/// [`fft_upsample`](crate::signal::fft_upsample) and driving
/// [`boucwen_system`] is closer to the reference.
pub fn boucwen_system_at_data_rate(
    p: &BoucWenBenchmarkParams,
) -> Result<Oversample<f64, BoucWenSystem>> {
    Oversample::new(boucwen_system(p)?, p.upsample)
}

/// The response to a periodic input once it repeats.
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodicResponse {
    /// The output over the last period simulated.
    pub output: Vec<f64>,
    /// Periods simulated.
    pub periods: usize,
    /// `max |y_last − y_previous|` over the last two periods (`∞` after one).
    pub change: f64,
    /// Whether `change ≤ tol` was reached within the period limit.
    pub converged: bool,
}

/// Runs `op` from its current state on one period `u` of a periodic input,
/// period after period, until the output of a period differs from that of
/// the one before by at most `tol` at every sample (or `max_periods`
/// periods have run; then `converged` is false).
///
/// Errors: an empty period, `max_periods = 0` or a negative or non-finite
/// `tol` is an [`Error::InvalidParameter`]; an operator error at some
/// sample is returned as it is (an [`Error::AtSample`] indexing into the
/// period).
pub fn periodic_steady_state<O: Operator<f64> + ?Sized>(
    op: &mut O,
    u: &[f64],
    tol: f64,
    max_periods: usize,
) -> Result<PeriodicResponse> {
    check::non_negative("tol", tol)?;
    if u.is_empty() || max_periods == 0 {
        return Err(Error::InvalidParameter {
            name: if u.is_empty() { "u" } else { "max_periods" }.into(),
            value: 0.0,
            reason: "must not be empty or zero",
        });
    }
    let mut previous = vec![0.0; u.len()];
    let mut output = vec![0.0; u.len()];
    let mut change = f64::INFINITY;
    for period in 1..=max_periods {
        std::mem::swap(&mut previous, &mut output);
        op.process(u, &mut output)?;
        if period > 1 {
            change = output
                .iter()
                .zip(&previous)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            if change <= tol {
                return Ok(PeriodicResponse {
                    output,
                    periods: period,
                    change,
                    converged: true,
                });
            }
        }
    }
    Ok(PeriodicResponse {
        output,
        periods: max_periods,
        change,
        converged: false,
    })
}

/// Steady state of a periodic record: the period-to-period change at
/// which [`simulate_record`] stops (m).
pub const STEADY_TOL: f64 = 1e-12;
/// Periods [`simulate_record`] runs at most on a periodic record.
pub const MAX_PERIODS: usize = 20;

/// The benchmark system's response to a record, as the record was made.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordResponse {
    /// The output decimated to the data rate after the record's plan
    /// (compare this with the record's `y`).
    pub decimated: Vec<f64>,
    /// Every `upsample`-th sample of the output at the integration rate,
    /// without a filter.
    pub picked: Vec<f64>,
    /// Periods simulated (1 for a record from rest).
    pub periods: usize,
    /// Whether the response reached its steady state (always true for a
    /// record from rest).
    pub converged: bool,
}

/// Simulates the benchmark system on a record's input `u` (sampled at
/// `p.fs`) the way the reference made the record: `u` upsampled
/// `p.upsample` times as `kind` needs ([`RecordKind::upsampling`]), the
/// system integrated at `p.fs · p.upsample` (from rest; a periodic record
/// period after period until the response repeats to [`STEADY_TOL`], at
/// most [`MAX_PERIODS`] periods), its output decimated after `plan`
/// ([`RecordKind::decimate`]).
///
/// Errors: `plan.factor()` other than `p.upsample` is an
/// [`Error::InvalidParameter`] naming `plan`; a bad record or system is
/// the error of the step that found it.
pub fn simulate_record(
    p: &BoucWenBenchmarkParams,
    u: &[f64],
    kind: RecordKind,
    plan: &DecimationPlan,
) -> Result<RecordResponse> {
    p.validate()?;
    if plan.factor() != p.upsample {
        return Err(Error::InvalidParameter {
            name: "plan".into(),
            value: plan.factor() as f64,
            reason: "must decimate by the system's upsampling factor",
        });
    }
    let fine = kind.upsampling().upsample(u, p.upsample)?;
    let mut system = boucwen_system(p)?;
    let (output, periods, converged) = match kind {
        RecordKind::Periodic => {
            let r = periodic_steady_state(&mut system, &fine, STEADY_TOL, MAX_PERIODS)?;
            (r.output, r.periods, r.converged)
        }
        RecordKind::FromRest => (system.run(&fine)?, 1, true),
    };
    Ok(RecordResponse {
        decimated: kind.decimate(&output, plan)?,
        picked: output.iter().step_by(p.upsample).copied().collect(),
        periods,
        converged,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::composition::OperatorExt;
    use crate::operators::Gain;
    use crate::operators::Parameters;

    #[test]
    fn published_parameters_and_json() {
        let p = BoucWenBenchmarkParams::published();
        assert_eq!(p, BoucWenBenchmarkParams::default());
        assert!((p.dt() - 1.0 / 15000.0).abs() < 1e-20);
        let json = serde_json::to_string(&p).unwrap();
        let back: BoucWenBenchmarkParams = serde_json::from_str(&json).unwrap();
        assert_eq!(back, p);
        let sys = boucwen_system(&p).unwrap();
        let names = sys.param_names();
        assert_eq!(names[0], "forward.mass_spring_damper.m");
        assert_eq!(names[4], "back.bouc_wen.alpha");
        let params = sys.params();
        assert_eq!(params[..7], [2.0, 10.0, 5e4, 0.0, 5e4, 800.0, -1100.0]);
        assert_eq!(
            boucwen_system_at_data_rate(&p).unwrap().factor(),
            p.upsample
        );
    }

    #[test]
    fn invalid_parameters_name_the_field() {
        let published = BoucWenBenchmarkParams::published;
        for (bad, field) in [
            (
                BoucWenBenchmarkParams {
                    upsample: 0,
                    ..published()
                },
                "upsample",
            ),
            (
                BoucWenBenchmarkParams {
                    m: -1.0,
                    ..published()
                },
                "oscillator.m",
            ),
            (
                BoucWenBenchmarkParams {
                    n: 0.5,
                    ..published()
                },
                "spring.n",
            ),
        ] {
            assert!(
                matches!(
                    boucwen_system(&bad),
                    Err(Error::InvalidParameter { ref name, .. }) if name == field
                ),
                "{field}"
            );
        }
    }

    /// With `A = β' = γ' = 0` the spring is silent and the system is the
    /// oscillator alone; with `β' = γ' = 0` it is a linear spring `A y` in
    /// parallel with `k`.
    #[test]
    fn linear_limits() {
        let u: Vec<f64> = (0..3000).map(|i| 40.0 * (0.01 * i as f64).sin()).collect();
        let p = BoucWenBenchmarkParams::published();
        let mut plain = p.oscillator().unwrap();
        let silent = BoucWenBenchmarkParams {
            a: 0.0,
            beta: 0.0,
            gamma: 0.0,
            ..p
        };
        let y0 = plain.run(&u).unwrap();
        let y1 = boucwen_system(&silent).unwrap().run(&u).unwrap();
        // (the loop's root is the oscillator's output to the solver's
        // stopping rule: a Newton step within `16 ε` of the root itself)
        for (a, b) in y0.iter().zip(&y1) {
            assert!(
                (a - b).abs() <= 16.0 * f64::EPSILON * a.abs().max(1e-9),
                "{a} {b}"
            );
        }
        let linear = BoucWenBenchmarkParams {
            beta: 0.0,
            gamma: 0.0,
            ..p
        };
        let stiff = MassSpringDamper::new(p.m, p.c, p.k + p.a, p.dt()).unwrap();
        let y2 = stiff.clone().run(&u).unwrap();
        let y3 = boucwen_system(&linear).unwrap().run(&u).unwrap();
        // (equal to rounding and the loop's solver tolerance, `16 ε |u|`)
        for (a, b) in y2.iter().zip(&y3) {
            assert!((a - b).abs() <= 1e-13, "{a} {b}");
        }
        // and the loop is the same as one written with a gain
        let y4 = p
            .oscillator()
            .unwrap()
            .feedback(Gain::new(p.a).unwrap())
            .run(&u)
            .unwrap();
        for (a, b) in y4.iter().zip(&y3) {
            assert!((a - b).abs() <= 1e-13, "{a} {b}");
        }
    }

    #[test]
    fn steady_state_of_a_damped_oscillator() {
        // A damped oscillator under a periodic force settles to a periodic
        // response; a memoryless gain repeats from the first period.
        let u: Vec<f64> = (0..100)
            .map(|i| (std::f64::consts::TAU * i as f64 / 100.0).sin())
            .collect();
        let mut g = Gain::new(2.0).unwrap();
        let r = periodic_steady_state(&mut g, &u, 0.0, 5).unwrap();
        assert!(r.converged && r.periods == 2 && r.change == 0.0);
        let mut msd = MassSpringDamper::new(1.0, 20.0, 400.0, 0.01).unwrap();
        let r = periodic_steady_state(&mut msd, &u, 1e-12, 200).unwrap();
        assert!(r.converged && r.change <= 1e-12 && r.periods > 2, "{r:?}");
        let r = periodic_steady_state(&mut msd.clone(), &u, 0.0, 1).unwrap();
        assert!(!r.converged && r.change.is_infinite());
        assert!(periodic_steady_state(&mut g, &[], 1e-9, 3).is_err());
        assert!(periodic_steady_state(&mut g, &u, -1.0, 3).is_err());
        assert!(periodic_steady_state(&mut g, &u, 1e-9, 0).is_err());
    }
}
