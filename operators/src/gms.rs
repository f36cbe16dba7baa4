//! The generalized Maxwell-slip (GMS) friction model (rate-dependent),
//! solved exactly per sample.

use crate::{
    check, check_input, check_lengths, check_output, declare_params, Float, Operator, Result, Trial,
};

declare_params! {
    /// Parameters of the [`Gms`] friction model.
    pub struct GmsParams<T> {
        /// Attraction rate `C > 0` (force per second) of a slipping element
        /// towards its Stribeck limit.
        c: T => Positive = 50.0,
        /// Coulomb level `F_c > 0` of the Stribeck curve.
        f_c: T => Positive = 1.0,
        /// Static level `F_s > 0` of the Stribeck curve (`F_s < F_c` allowed).
        f_s: T => Positive = 1.5,
        /// Stribeck velocity `v_s > 0`.
        v_s: T => Positive = 0.01,
        /// Stribeck exponent `δ ≥ 1` (default 2; `δ ≥ 1` keeps the tangent at
        /// a standstill finite).
        #[serde(default = "two")]
        delta: T => AtLeast(1.0) = 2.0,
        /// Viscous friction `σ2 ≥ 0`.
        #[serde(default)]
        sigma2: T => NonNegative = 0.1,
        /// Element stiffnesses `k_i > 0`.
        k: Vec<T> => Positive = [100.0, 20.0],
        /// Element weights `α_i > 0`: element `i` slips at `α_i s(v)`.
        alpha: Vec<T> => Positive = [0.5, 0.5],
        /// Element forces at input `x = 0` before the first sample (default
        /// empty: all 0).
        #[serde(default)]
        f0: Vec<T> => Real = [0.1, -0.2],
        /// Sample period `dt > 0` (s) until the structure above sets one
        /// ([`SamplePeriod::set_sample_period`](crate::SamplePeriod::set_sample_period)). Not a fitted parameter.
        dt: T => fixed = 1e-3,
    }
    check = GmsParams::shape;
}

fn two<T: Float>() -> T {
    T::lit(2.0)
}

impl<T: Float> GmsParams<T> {
    /// At least one element; `k`, `alpha` (and `f0` if given) of one
    /// length; `dt > 0`.
    fn shape(&self) -> Result<()> {
        check::element_lengths(self.k.len(), ("alpha", self.alpha.len()), self.f0.len())?;
        check::positive("dt", self.dt)
    }
}

/// Generalized Maxwell-slip friction (Al-Bender, Lampaert, Swevers 2005),
/// in our reading: `N` elements in parallel, element `i` with stiffness
/// `k_i` and force `F_i`,
///
/// * **sticking**: `dF_i/dt = k_i v`, until `|F_i|` reaches `α_i s(v)`;
/// * **slipping**: `dF_i/dt = sgn(v) C (1 − sgn(v) F_i/(α_i s(v)))`
///   (attraction at rate `C` towards `sgn(v) α_i s(v)`; nothing changes
///   while `v = 0`), until the motion reverses;
///
/// `s(v) = F_c + (F_s − F_c) exp(−|v/v_s|^δ)` (the Stribeck curve) and
/// `F = Σ_i F_i + σ2 v`. With `F_s = F_c` every slipping element sits at
/// its limit and the model is the [`MaxwellSlip`](crate::MaxwellSlip) bank
/// with break-away forces `α_i F_c` (rate-independent); otherwise the
/// limits follow the velocity with a lag set by `C` (frictional memory).
///
/// **Rate-dependent**: it holds its sample period `dt`. As in
/// [`LuGre`](crate::LuGre) the input is a position taken as linear between
/// samples, so `v = Δx/dt` is constant over each sample, the limits are
/// constant there, and both laws are linear: each sample is solved
/// exactly. A sticking element moves by `k_i Δx` unless it meets its limit
/// within the sample, where it starts slipping — already at its target
/// `sgn(v) α_i s(v)`, so it stays there; a slipping element relaxes as
/// `F_i ← σ α_i s + (F_i − σ α_i s) exp(−C dt/(α_i s))`. An element
/// found beyond its (lowered) limit at the start of a sample slips from
/// there. A reversal of the input direction makes every element stick; at
/// a standstill (`Δx = 0`) nothing changes. Hence
/// `|F_i| ≤ max(|f0_i|, α_i max(F_c, F_s))`.
///
/// The tangent `dF/dx_{k+1}` is the exact derivative of this update; at a
/// standstill the one-sided derivative in the last direction (upward
/// before any motion). Note that the force jumps at `Δx = 0` when an
/// element slips away from its limit (any motion, however small, lasts a
/// whole sample of relaxation, while a standstill relaxes nothing): the
/// standstill tangent ignores that jump. Parameters `[c, f_c, f_s, v_s, delta, sigma2,
/// k_0.., alpha_0.., f0_0..]`; `dt` is fixed (its period is set by [`SamplePeriod::set_sample_period`](crate::SamplePeriod::set_sample_period)).
///
/// ```
/// use hysteron_operators::{Gms, GmsParams, Operator};
/// let p = GmsParams {
///     k: vec![100.0_f64, 20.0], alpha: vec![0.5, 0.5], f0: vec![],
///     c: 50.0, f_c: 1.0, f_s: 1.5, v_s: 0.01, delta: 2.0, sigma2: 0.0, dt: 1e-3,
/// };
/// let mut f = Gms::from_params(p.clone()).unwrap();
/// // constant velocity 0.04: both elements end up slipping at their limits
/// let x: Vec<f64> = (1..=2000).map(|i| 0.04e-3 * i as f64).collect();
/// let y = f.run(&x).unwrap();
/// let s = 1.0 + 0.5 * (-16.0_f64).exp();
/// assert!((y[1999] - s).abs() < 1e-12);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Gms<T> {
    p: GmsParams<T>,
    /// Committed element forces, slip flags and direction.
    x: T,
    f: Vec<T>,
    slip: Vec<bool>,
    dir: i8,
    pending_x: T,
    pending_f: Vec<T>,
    pending_slip: Vec<bool>,
    pending_dir: i8,
    has_pending: bool,
}

impl<T: Float> Gms<T> {
    /// A GMS model from validated parameters (an empty `f0` means all 0).
    pub fn from_params(mut p: GmsParams<T>) -> Result<Self> {
        p.validate()?;
        let n = p.k.len();
        if p.f0.is_empty() {
            p.f0 = vec![T::zero(); n];
        }
        Ok(Self {
            x: T::zero(),
            pending_x: T::zero(),
            f: p.f0.clone(),
            slip: vec![false; n],
            dir: 0,
            pending_f: vec![T::zero(); n],
            pending_slip: vec![false; n],
            pending_dir: 0,
            has_pending: false,
            p,
        })
    }

    /// The parameters (with `f0` written out in full).
    pub fn parameters(&self) -> &GmsParams<T> {
        &self.p
    }

    /// The committed element forces.
    pub fn element_forces(&self) -> &[T] {
        &self.f
    }

    /// Which elements are slipping (committed).
    pub fn slipping(&self) -> &[bool] {
        &self.slip
    }

    /// One sample from the committed state to input `x`, written into the
    /// pending buffers: returns `(F, dF/dx)`.
    // `i < n = p.k.len()`, and `alpha`, `f`, `slip`, `pending_f`,
    // `pending_slip` all have `n` entries (`GmsParams::shape`, `from_params`;
    // `commit` only swaps equal-length buffers).
    #[allow(clippy::indexing_slicing)]
    #[inline(always)]
    fn step(&mut self, x: T) -> (T, T) {
        let p = &self.p;
        let (zero, one) = (T::zero(), T::one());
        let dx = x - self.x;
        let v = dx / p.dt;
        let dir = if dx > zero {
            1
        } else if dx < zero {
            -1
        } else {
            self.dir
        };
        let sign = if dir < 0 { -one } else { one };
        let reversal = dir != self.dir && self.dir != 0;
        // Stribeck curve s(v) (clamped between F_c and F_s against
        // rounding) and σ·ds/dx = σ s'(v)/dt (≤ 0 when F_s > F_c).
        let r = (v / p.v_s).abs();
        let e = (-r.powf(p.delta)).exp();
        let s = (p.f_c + (p.f_s - p.f_c) * e)
            .max(p.f_c.min(p.f_s))
            .min(p.f_c.max(p.f_s));
        let ds = if e == zero {
            zero
        } else {
            -(p.f_s - p.f_c) * p.delta * r.powf(p.delta - one) * e / (p.v_s * p.dt)
        };
        let mut force = p.sigma2 * v;
        let mut tangent = p.sigma2 / p.dt;
        for i in 0..p.k.len() {
            let (k, a, f0) = (p.k[i], p.alpha[i], self.f[i]);
            let slipping = self.slip[i] && !reversal;
            let lim = a * s;
            let target = sign * lim;
            let stick_travel = lim - sign * f0; // distance to the limit
            let (f, t, slip) = if !slipping && stick_travel > k * dx.abs() {
                // sticks through the sample (at a standstill: stays)
                (f0 + k * dx, k, false)
            } else if !slipping && stick_travel >= zero {
                // meets its limit within the sample and stays there
                if dx == zero {
                    (f0, a * ds, false)
                } else {
                    (target, a * ds, true)
                }
            } else {
                // slips: relaxes towards the target over the sample
                let decay = (-p.c * p.dt / lim).exp();
                let t = a * ds * (one - decay)
                    + (f0 - target) * decay * p.c * p.dt * a * sign * ds / (lim * lim);
                if dx == zero {
                    (f0, t, slipping)
                } else {
                    (target + (f0 - target) * decay, t, true)
                }
            };
            self.pending_f[i] = f;
            self.pending_slip[i] = slip;
            force = force + f;
            tangent = tangent + t;
        }
        self.pending_dir = dir;
        (force, tangent)
    }
}

impl<T: Float> Operator<T> for Gms<T> {
    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        self.has_pending = false;
        let x = check_input(x)?;
        let (output, tangent) = self.step(x);
        let t = check_output("gms", x, Trial { output, tangent })?;
        self.pending_x = x;
        self.has_pending = true;
        Ok(t)
    }

    fn commit(&mut self) {
        if self.has_pending {
            std::mem::swap(&mut self.f, &mut self.pending_f);
            std::mem::swap(&mut self.slip, &mut self.pending_slip);
            self.dir = self.pending_dir;
            self.x = self.pending_x;
            self.has_pending = false;
        }
    }

    fn reset(&mut self) {
        self.f.copy_from_slice(&self.p.f0);
        self.slip.iter_mut().for_each(|s| *s = false);
        self.dir = 0;
        self.x = T::zero();
        self.has_pending = false;
    }

    fn process(&mut self, xs: &[T], ys: &mut [T]) -> Result<()> {
        check_lengths(xs, ys)?;
        self.has_pending = false;
        for (i, (&x, out)) in xs.iter().zip(ys.iter_mut()).enumerate() {
            let t = self.trial(x).map_err(|e| e.at_sample(i))?;
            self.commit();
            *out = t.output;
        }
        Ok(())
    }

    fn name(&self) -> &'static str {
        <Self as crate::Leaf<T>>::KIND
    }
}

crate::leaf_traits!(Gms);

/// No fast paths beyond the batch loop of `process` (it integrates over
/// time: holding the input still moves it).
impl<T: Float> crate::Hints<T> for Gms<T> {}

impl<T: Float> crate::SamplePeriod<T> for Gms<T> {
    fn set_sample_period(&mut self, dt: T) -> Result<()> {
        check::set_positive("dt", &mut self.p.dt, dt)
    }
}

crate::impl_leaf!(
    Gms,
    GmsParams,
    "gms",
    p,
    equation: "F = Σ F_i + σ2 v; stick Ḟ_i = k_i v until |F_i| = α_i s(v), slip Ḟ_i = sgn(v) C (1 − sgn(v) F_i/(α_i s(v)))"
);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::assert_trial_tangent;
    use crate::Error;

    fn params() -> GmsParams<f64> {
        GmsParams {
            k: vec![3e3, 1e3, 2e2],
            alpha: vec![0.3, 0.5, 0.2],
            f0: vec![0.1, -0.2, 0.0],
            c: 20.0,
            f_c: 1.0,
            f_s: 1.6,
            v_s: 0.02,
            delta: 2.0,
            sigma2: 0.5,
            dt: 1e-3,
        }
    }

    /// The tangent is the derivative of the update away from switches:
    /// after a few samples of motion (some elements sticking, some at or
    /// relaxing to their limits), central differences with a step of 1e-6
    /// of the sample's travel (truncation O(h²), rounding ~1e-16 F/h) agree
    /// to 1e-6 relative.
    #[test]
    fn tangent_is_the_derivative_of_the_update() {
        // 100 samples at v = 0.02 = v_s
        let slow: Vec<f64> = (1..=100).map(|i| 2e-5 * i as f64).collect();
        for delta in [1.0, 2.0, 3.5] {
            for (history, dx) in [
                (&[1e-5, 2e-5, 3e-5][..], 1e-5),
                (&[2e-4, 4e-4, 6e-4, 8e-4][..], 1.5e-4),
                (&[2e-4, 4e-4, 6e-4, 8e-4, 1e-3, 1.2e-3][..], 3e-4),
                (&[2e-4, 4e-4, 6e-4, 8e-4][..], 5e-5),
                (&[2e-4, 4e-4, 6e-4, 8e-4][..], -1e-5),
                (&[-3e-4, -6e-4, -9e-4][..], -0.7e-4),
                (&slow[..], 3e-5),
                (&slow[..], 1.3e-5),
            ] {
                let mut g = Gms::from_params(GmsParams { delta, ..params() }).unwrap();
                g.run(history).unwrap();
                if history.len() == slow.len() {
                    // all elements slip, near the Stribeck velocity
                    assert!(g.slipping().iter().all(|&s| s));
                }
                let x = history[history.len() - 1] + dx;
                let case = format!("δ={delta} {history:?} + {dx}");
                assert_trial_tangent(&mut g, x, 1e-6 * dx.abs(), 1e-6, &case);
            }
        }
    }

    #[test]
    fn invalid_parameters_are_typed_errors() {
        let p = params();
        for (q, name) in [
            (
                GmsParams {
                    k: vec![],
                    alpha: vec![],
                    f0: vec![],
                    ..p.clone()
                },
                "k",
            ),
            (
                GmsParams {
                    alpha: vec![0.5],
                    ..p.clone()
                },
                "alpha",
            ),
            (
                GmsParams {
                    f0: vec![0.0],
                    ..p.clone()
                },
                "alpha",
            ),
            (
                GmsParams {
                    k: vec![1.0, 0.0, 1.0],
                    ..p.clone()
                },
                "k[1]",
            ),
            (
                GmsParams {
                    alpha: vec![0.3, 0.5, -0.2],
                    ..p.clone()
                },
                "alpha[2]",
            ),
            (
                GmsParams {
                    f0: vec![0.0, f64::NAN, 0.0],
                    ..p.clone()
                },
                "f0[1]",
            ),
            (
                GmsParams {
                    c: 0.0,
                    ..p.clone()
                },
                "c",
            ),
            (
                GmsParams {
                    f_c: -1.0,
                    ..p.clone()
                },
                "f_c",
            ),
            (
                GmsParams {
                    f_s: 0.0,
                    ..p.clone()
                },
                "f_s",
            ),
            (
                GmsParams {
                    v_s: 0.0,
                    ..p.clone()
                },
                "v_s",
            ),
            (
                GmsParams {
                    delta: 0.5,
                    ..p.clone()
                },
                "delta",
            ),
            (
                GmsParams {
                    sigma2: -1.0,
                    ..p.clone()
                },
                "sigma2",
            ),
            (
                GmsParams {
                    dt: 0.0,
                    ..p.clone()
                },
                "dt",
            ),
        ] {
            match Gms::from_params(q).unwrap_err() {
                Error::InvalidParameter { name: n, .. } => assert_eq!(n, name),
                other => panic!("{other}"),
            }
        }
    }

    /// A reversal makes every element stick: right after it the tangent is
    /// `Σ k_i + σ2/dt`.
    #[test]
    fn a_reversal_makes_every_element_stick() {
        let p = params();
        let mut g = Gms::from_params(p.clone()).unwrap();
        let xs: Vec<f64> = (1..=100).map(|i| 1e-4 * i as f64).collect();
        g.run(&xs).unwrap();
        assert!(g.slipping().iter().all(|&s| s), "{:?}", g.slipping());
        let t = g.trial(xs[99] - 1e-7).unwrap();
        let k: f64 = p.k.iter().sum();
        assert!(
            (t.tangent - (k + p.sigma2 / p.dt)).abs() < 1e-9 * k,
            "{t:?}"
        );
        g.commit();
        assert!(g.slipping().iter().all(|&s| !s));
    }
}
