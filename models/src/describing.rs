//! The describing function of any operator: the first-harmonic gain of its
//! steady periodic response to a sine.
//!
//! An operator (cloned and reset, so the caller's is untouched) is driven
//! by `x_n = A sin θ_n`, `θ_n = 2π n / N` (`N = samples_per_period`),
//! for `settle_periods` whole periods from its initial state. The last
//! period is the steady cycle ([`SteadyCycle`]); the one before is compared
//! with it: if their first harmonics differ by more than
//! `steady_tol · max|y|` the output is not (yet) periodic and the analysis
//! is an [`AnalysisError::NotSteady`] error instead of a number.
//!
//! The Fourier coefficients of the steady cycle,
//!
//! `a_k = (2/N) Σ_n y_n cos(k θ_n)`,  `b_k = (2/N) Σ_n y_n sin(k θ_n)`,
//!
//! so that `y ≈ a_0/2 + Σ_k (a_k cos kθ + b_k sin kθ)`, are the rectangle
//! (equivalently, for a periodic integrand, trapezoid) rule applied to
//! `(1/π) ∮ y(θ) cos kθ dθ` and `(1/π) ∮ y(θ) sin kθ dθ`. The
//! **describing function** is
//!
//! `N(A) = (b_1 + i a_1) / A`,  gain `|N|`, phase `arg N`
//! (radians, negative = the output lags the input).
//!
//! **Quadrature error.** The rule is exact for any `y` whose harmonics
//! `m N ± k` (`m ≥ 1`) vanish, so for band-limited outputs (a linear gain:
//! `N = k` up to rounding); for a smooth periodic output it converges
//! faster than any power of `1/N` (spectrally). Hysteresis and saturation
//! outputs have kinks (a jump of `dy/dθ`), whose Fourier coefficients decay
//! like `k⁻²`; the aliased ones then make the error `O(N⁻²)`, with a
//! constant that depends on where the kinks fall between samples
//! (`tests/describing.rs` measures it: orders ≈ 2 for the play and the
//! saturation).
//!
//! The input samples are exactly symmetric: `x_{n+N/2} = −x_n`,
//! `x_{N/4±j}` equal, `x_{N/4} = A` and `x_{3N/4} = −A` exactly (the
//! sine is evaluated on the first quadrant only), so `N` must be a
//! multiple of 4. A rate-dependent model (one that holds a sample period
//! `dt`) sees the frequency `1 / (N dt)`.

use hysteron_operators::{Error, Operator};
use std::f64::consts::FRAC_PI_2;

/// Options of the sine-driven analyses ([`describing_function`],
/// [`loop_energy`](crate::energy::loop_energy)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SineOptions {
    /// Samples per period `N`: a multiple of 4 in `[8, 2²⁴]`
    /// (default 1024).
    pub samples_per_period: usize,
    /// Periods run from the initial state; the last one is analysed and
    /// compared with the one before, so at least 2, at most 10⁶
    /// (default 20).
    pub settle_periods: usize,
    /// Largest accepted change of the first harmonic `(a_1, b_1)` from the
    /// second-last to the last period, relative to the last period's
    /// `max |y|`; finite and `≥ 0` (default `1e-9`).
    pub steady_tol: f64,
    /// Number of harmonics reported, `k = 0..=harmonics` (capped at
    /// `N/2 − 1`; default 5).
    pub harmonics: usize,
}

impl Default for SineOptions {
    fn default() -> Self {
        Self {
            samples_per_period: 1024,
            settle_periods: 20,
            steady_tol: 1e-9,
            harmonics: 5,
        }
    }
}

/// Largest `samples_per_period`.
pub const MAX_SAMPLES_PER_PERIOD: usize = 1 << 24;
/// Largest `settle_periods`.
pub const MAX_SETTLE_PERIODS: usize = 1_000_000;

/// An error of the sine-driven analyses.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum AnalysisError {
    /// An argument is outside its range.
    #[error("invalid {name} = {value}: {reason}")]
    InvalidArgument {
        /// The argument's name.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What it must satisfy.
        reason: &'static str,
    },
    /// The operator failed while driven by the sine.
    #[error(
        "the operator failed in period {period} (of the sine of amplitude {amplitude}): {source}"
    )]
    Operator {
        /// The period (0-based) in which it failed.
        period: usize,
        /// The amplitude of the input.
        amplitude: f64,
        /// The operator's error (with the sample within the period).
        source: Error,
    },
    /// The output did not settle into a periodic cycle.
    #[error(
        "the output is not periodic (not in a steady state) after {periods} periods at \
         amplitude {amplitude}: its first harmonic changed by {change:.3e} (relative to max|y|) \
         over the last period, more than the tolerance {tol:.3e}; raise the number of settle \
         periods or the tolerance"
    )]
    NotSteady {
        /// Periods run.
        periods: usize,
        /// The amplitude of the input.
        amplitude: f64,
        /// The relative change of the first harmonic.
        change: f64,
        /// The tolerance.
        tol: f64,
    },
}

impl SineOptions {
    /// Checks the ranges given in the field documentation.
    pub fn validate(&self) -> Result<(), AnalysisError> {
        let n = self.samples_per_period;
        if n < 8 || !n.is_multiple_of(4) || n > MAX_SAMPLES_PER_PERIOD {
            return Err(AnalysisError::InvalidArgument {
                name: "samples_per_period",
                value: n as f64,
                reason: "must be a multiple of 4 in [8, 16777216]",
            });
        }
        if self.settle_periods < 2 || self.settle_periods > MAX_SETTLE_PERIODS {
            return Err(AnalysisError::InvalidArgument {
                name: "settle_periods",
                value: self.settle_periods as f64,
                reason:
                    "must lie in [2, 1000000] (the last period is compared with the one before)",
            });
        }
        if !(self.steady_tol.is_finite() && self.steady_tol >= 0.0) {
            return Err(AnalysisError::InvalidArgument {
                name: "steady_tol",
                value: self.steady_tol,
                reason: "must be finite and ≥ 0",
            });
        }
        Ok(())
    }
}

/// `sin(2π n / N)` with exact symmetries: evaluated as `±sin` of an angle
/// in the first quadrant, `[0, π/2]`, folded so that `s(N/4 + j) =
/// s(N/4 − j)` and `s(n + N/2) = −s(n)` hold bit for bit. `N % 4 == 0`.
pub(crate) fn unit_sine(n: usize, big_n: usize) -> f64 {
    let quarter = big_n / 4;
    let q = n % big_n;
    let (quadrant, r) = (q / quarter, q % quarter);
    let j = if quadrant % 2 == 0 { r } else { quarter - r };
    let s = (FRAC_PI_2 * j as f64 / quarter as f64).sin();
    if quadrant < 2 {
        s
    } else {
        -s
    }
}

/// The steady periodic response of an operator to `x = A sin θ`: the
/// input and output samples of the last period (`θ_n = 2π n/N`,
/// `n = 0..N`) after `settle_periods` periods, and the first harmonic of
/// the period before (for the steadiness check).
#[derive(Debug, Clone, PartialEq)]
pub struct SteadyCycle {
    /// The amplitude `A`.
    pub amplitude: f64,
    /// Input samples of one period, `x_n = A sin(2π n/N)`.
    pub x: Vec<f64>,
    /// Output samples of the last period.
    pub y: Vec<f64>,
    /// The relative change of the first harmonic over the last period,
    /// `|(a_1, b_1)_last − (a_1, b_1)_previous| / max|y|` (0 for a zero
    /// output).
    pub change: f64,
    /// Periods run.
    pub periods: usize,
}

impl SteadyCycle {
    /// Runs a clone of `op` (reset to its initial state) over
    /// `opts.settle_periods` periods of `A sin θ` and keeps the last one.
    ///
    /// Errors: `A` not finite or `≤ 0`, invalid options
    /// ([`AnalysisError::InvalidArgument`]); an operator error
    /// ([`AnalysisError::Operator`]); a first harmonic that still changes
    /// by more than `steady_tol · max|y|` ([`AnalysisError::NotSteady`]).
    pub fn compute<O>(op: &O, amplitude: f64, opts: &SineOptions) -> Result<Self, AnalysisError>
    where
        O: Operator<f64> + Clone,
    {
        if !(amplitude.is_finite() && amplitude > 0.0) {
            return Err(AnalysisError::InvalidArgument {
                name: "amplitude",
                value: amplitude,
                reason: "must be finite and > 0",
            });
        }
        opts.validate()?;
        let n = opts.samples_per_period;
        let x: Vec<f64> = (0..n).map(|i| amplitude * unit_sine(i, n)).collect();
        let mut model = op.clone();
        model.reset();
        let mut y = vec![0.0; n];
        let mut previous = (0.0, 0.0);
        let mut last = (0.0, 0.0);
        for period in 0..opts.settle_periods {
            model
                .process(&x, &mut y)
                .map_err(|source| AnalysisError::Operator {
                    period,
                    amplitude,
                    source,
                })?;
            previous = last;
            last = harmonic(&y, 1);
        }
        let scale = y.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let diff = (last.0 - previous.0).hypot(last.1 - previous.1);
        let change = if scale > 0.0 { diff / scale } else { diff };
        if change > opts.steady_tol || !change.is_finite() {
            return Err(AnalysisError::NotSteady {
                periods: opts.settle_periods,
                amplitude,
                change,
                tol: opts.steady_tol,
            });
        }
        Ok(Self {
            amplitude,
            x,
            y,
            change,
            periods: opts.settle_periods,
        })
    }

    /// Samples per period.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Always false (a cycle has at least 8 samples).
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// The Fourier coefficients `(a_k, b_k)` of the cycle (see the
    /// [module documentation](self)).
    pub fn harmonic(&self, k: usize) -> (f64, f64) {
        harmonic(&self.y, k)
    }

    /// The describing function of the cycle, with the harmonics
    /// `k = 0..=harmonics` (capped at `N/2 − 1`).
    pub fn describing_function(&self, harmonics: usize) -> DescribingFunction {
        let (a1, b1) = self.harmonic(1);
        let (re, im) = (b1 / self.amplitude, a1 / self.amplitude);
        let top = harmonics.min(self.len() / 2 - 1);
        DescribingFunction {
            amplitude: self.amplitude,
            re,
            im,
            gain: re.hypot(im),
            phase: im.atan2(re),
            harmonics: (0..=top).map(|k| self.harmonic(k)).collect(),
            change: self.change,
        }
    }
}

/// `(a_k, b_k) = (2/N) Σ y_n (cos kθ_n, sin kθ_n)`, with the same exactly
/// symmetric sine table as the input.
fn harmonic(y: &[f64], k: usize) -> (f64, f64) {
    let big_n = y.len();
    let quarter = big_n / 4;
    let (mut a, mut b) = (0.0, 0.0);
    for (i, &v) in y.iter().enumerate() {
        let m = ((k % big_n) as u64 * i as u64 % big_n as u64) as usize;
        a += v * unit_sine(m + quarter, big_n);
        b += v * unit_sine(m, big_n);
    }
    let f = 2.0 / big_n as f64;
    (a * f, b * f)
}

/// The describing function `N(A) = (b_1 + i a_1)/A` of an operator at one
/// amplitude (see the [module documentation](self)).
#[derive(Debug, Clone, PartialEq)]
pub struct DescribingFunction {
    /// The input amplitude `A`.
    pub amplitude: f64,
    /// `Re N = b_1 / A` (the in-phase gain).
    pub re: f64,
    /// `Im N = a_1 / A` (negative: the output lags).
    pub im: f64,
    /// `|N|`.
    pub gain: f64,
    /// `arg N` in radians, in `(−π, π]`; negative = lag.
    pub phase: f64,
    /// `(a_k, b_k)` for `k = 0, 1, …`: `y ≈ a_0/2 + Σ a_k cos kθ + b_k sin kθ`.
    pub harmonics: Vec<(f64, f64)>,
    /// The steadiness measure of the cycle ([`SteadyCycle::change`]).
    pub change: f64,
}

/// The describing function of `op` at amplitude `amplitude`: runs
/// [`SteadyCycle::compute`] and takes its first harmonic.
///
/// ```
/// use hysteron_models::describing::{describing_function, SineOptions};
/// use hysteron_operators::Play;
/// let play = Play::new(0.5_f64).unwrap();
/// let n = describing_function(&play, 2.0, &SineOptions::default()).unwrap();
/// assert!(n.phase < 0.0 && n.gain < 1.0); // backlash: a lag and a loss
/// ```
pub fn describing_function<O: Operator<f64> + Clone>(
    op: &O,
    amplitude: f64,
    opts: &SineOptions,
) -> Result<DescribingFunction, AnalysisError> {
    Ok(SteadyCycle::compute(op, amplitude, opts)?.describing_function(opts.harmonics))
}

/// The exact describing function of a play (backlash) with threshold `r`
/// and unit slope at amplitude `A`, as `(Re N, Im N)`: with `ρ = r/A`,
/// `s = 1 − 2ρ`, for `A > r`
///
/// `Re N = (1/π) (π/2 + asin s + s √(1 − s²))`,
/// `Im N = −(4/π) ρ (1 − ρ)`,
///
/// and `N = 0` for `A ≤ r` (the steady output is constant). Derivation: in
/// the steady cycle the output is `A − r` from `θ = π/2` until the input has
/// fallen by `2r` (`sin θ₁ = s`), then `x + r` down to `−A`, and
/// antisymmetric after; integrate `y cos θ` and `y sin θ` over the half
/// period. `A` and `r` are taken as given (no checks).
pub fn play_describing_function(r: f64, amplitude: f64) -> (f64, f64) {
    if amplitude <= r {
        return (0.0, 0.0);
    }
    let rho = r / amplitude;
    let s = 1.0 - 2.0 * rho;
    let re = (FRAC_PI_2 + s.asin() + s * (1.0 - s * s).sqrt()) / std::f64::consts::PI;
    let im = -4.0 / std::f64::consts::PI * rho * (1.0 - rho);
    (re, im)
}

/// The exact describing function of a saturation of slope `k` and limits
/// `±k δ` (a real gain):
/// `N(A) = (2k/π) (asin(δ/A) + (δ/A) √(1 − (δ/A)²))` for `A > δ`, `k` for
/// `A ≤ δ`. As `k → ∞` with `k δ = M` fixed it tends to the ideal relay's
/// `4M / (π A)`.
pub fn saturation_describing_function(k: f64, delta: f64, amplitude: f64) -> f64 {
    if amplitude <= delta {
        return k;
    }
    let u = delta / amplitude;
    2.0 * k / std::f64::consts::PI * (u.asin() + u * (1.0 - u * u).sqrt())
}
