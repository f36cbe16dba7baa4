//! The rate-dependent Prandtl-Ishlinskii operator: a play bank whose
//! thresholds widen with the input's rate.

use crate::{check, declare_params, play_step, Error, Float, Result, StepLaw, Stepped, Trial};

declare_params! {
    /// Parameters of the [`RateDependentPi`] operator.
    pub struct RateDependentPiParams<T> {
        /// Weight of the linear term `a0 · x`.
        a0: T => Real = 0.5,
        /// Thresholds at rest `r_j ≥ 0`.
        r: Vec<T> => NonNegative = [0.0, 0.3, 1.0],
        /// Weights `w_j` (finite, any sign).
        w: Vec<T> => Real = [1.0, 0.5, 0.25],
        /// Rate sensitivity `λ ≥ 0` (seconds): every threshold widens by
        /// `λ |ẋ|`.
        lam: T => NonNegative = 0.002,
        /// Initial play outputs at `x = 0` (default empty: all 0).
        #[serde(default)]
        y0: Vec<T> => Real = [0.0, 0.1, -0.2],
        /// Sample period `dt > 0` (s) until the structure above sets one
        /// ([`SamplePeriod::set_sample_period`](crate::SamplePeriod::set_sample_period)).
        /// Not a fitted parameter.
        dt: T => fixed = 1e-3,
    }
    check = RateDependentPiParams::shape;
    law: "rate_dependent_pi", "y = a0 x + Σ_j w_j play_{r_j + λ|ẋ|}[x], ẋ = (x_k − x_{k−1})/dt";
}

impl<T: Float> RateDependentPiParams<T> {
    /// At least one play; `r`, `w` (and `y0` if given) of one length; a
    /// positive `dt`.
    fn shape(&self) -> Result<()> {
        let invalid = |name: &str, len: usize, reason| {
            Err(Error::InvalidParameter {
                name: name.into(),
                value: len as f64,
                reason,
            })
        };
        if self.r.is_empty() {
            return invalid("r", 0, "needs at least one play");
        }
        let n = self.r.len();
        if self.w.len() != n || !(self.y0.is_empty() || self.y0.len() == n) {
            return invalid(
                "w",
                self.w.len(),
                "r, w (and y0 if given) must have the same length",
            );
        }
        check::positive("dt", self.dt)
    }
}

/// The state between samples: the last input and the plays' outputs.
#[derive(Debug, Clone, PartialEq)]
pub struct RateDependentPiState<T> {
    /// The input of the last sample.
    pub x: T,
    /// The plays' outputs there.
    pub z: Vec<T>,
}

/// The rate-dependent Prandtl-Ishlinskii operator (Al Janaideh & Krejčí
/// 2013): a play bank whose thresholds widen with the input's rate,
///
/// `y = a0 x + Σ_j w_j z_j`,  `z_j = play_{r_j(v)}[x]`,
/// `r_j(v) = r_j + λ |v|`,  `v = (x_k − x_{k−1}) / dt`,
///
/// from the plays' outputs `y0` at `x = 0` (the first sample's rate is
/// from 0). With `λ = 0` it is the `pi_bank` operator, bit for
/// bit; with `λ > 0` faster inputs give wider loops, as piezoelectric
/// stacks show over frequency. The rate is the backward difference over
/// the sample period `dt` (a setting, from the data or the structure
/// above), so the output depends on the sampling: it is not
/// rate-independent by design. At a standstill the thresholds return to
/// `r_j`, and a play left outside its narrower band moves to its edge.
/// The tangent is `dy/dx` of the step, the thresholds' dependence on `x`
/// through `v` included (`d|v|/dx` taken upward at a standstill).
///
/// ```
/// use hysteron_operators::{Operator, RateDependentPi, RateDependentPiParams};
/// let p = |lam| RateDependentPiParams { a0: 0.0, r: vec![0.5], w: vec![1.0], lam, y0: vec![], dt: 0.01 };
/// let x: Vec<f64> = (0..=100).map(|i| (i as f64 * 0.1).sin()).collect();
/// let slow = RateDependentPi::from_params(p(0.0)).unwrap().run(&x).unwrap();
/// let fast = RateDependentPi::from_params(p(0.05)).unwrap().run(&x).unwrap();
/// // wider thresholds: the output lags further behind the rising input
/// assert!(fast[10] < slow[10]);
/// ```
///
/// Reference: M. Al Janaideh and P. Krejčí, "Inverse rate-dependent
/// Prandtl-Ishlinskii model for feedforward compensation of hysteresis in
/// a piezomicropositioning actuator", IEEE/ASME Trans. Mechatronics 18
/// (2013) 1498–1507.
pub type RateDependentPi<T> = Stepped<RateDependentPiParams<T>, T>;

impl<T: Float> StepLaw<T> for RateDependentPiParams<T> {
    type State = RateDependentPiState<T>;

    fn initial(&self) -> RateDependentPiState<T> {
        let z = if self.y0.is_empty() {
            vec![T::zero(); self.r.len()]
        } else {
            self.y0.clone()
        };
        RateDependentPiState { x: T::zero(), z }
    }

    fn step(
        &self,
        s: &RateDependentPiState<T>,
        x: T,
    ) -> Result<(RateDependentPiState<T>, Trial<T>)> {
        let v = (x - s.x) / self.dt;
        let widen = self.lam * v.abs();
        // d(λ|v|)/dx, upward at a standstill
        let dwiden = if v < T::zero() { -self.lam } else { self.lam } / self.dt;
        let mut output = self.a0 * x;
        let mut tangent = self.a0;
        let mut z = Vec::with_capacity(s.z.len());
        for ((&r, &w), &prev) in self.r.iter().zip(&self.w).zip(&s.z) {
            let r = r + widen;
            let next = play_step(r, prev, x);
            // dragged from below (x − r), from above (x + r), or held
            let slope = if x - r >= prev {
                T::one() - dwiden
            } else if x + r <= prev {
                T::one() + dwiden
            } else {
                T::zero()
            };
            output = output + w * next;
            tangent = tangent + w * slope;
            z.push(next);
        }
        Ok((RateDependentPiState { x, z }, Trial { output, tangent }))
    }

    fn set_sample_period(&mut self, dt: T) -> Result<()> {
        check::set_positive("dt", &mut self.dt, dt)
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::indexing_slicing)]
    use super::*;
    use crate::test_support::{ramped_sine, rejected_field, step_difference};
    use crate::Operator;

    fn params(lam: f64) -> RateDependentPiParams<f64> {
        RateDependentPiParams {
            a0: 0.5,
            r: vec![0.0, 0.3, 1.0],
            w: vec![1.0, 0.5, 0.25],
            lam,
            y0: vec![0.0, 0.1, -0.2],
            dt: 1e-3,
        }
    }

    fn sine(periods: f64, n: usize) -> Vec<f64> {
        ramped_sine(n, 2.0, 0.0, periods)
    }

    /// With `λ = 0` it is the PI bank `a0 x + Σ w_j play_{r_j}[x]`.
    #[test]
    fn without_rate_sensitivity_it_is_the_pi_bank() {
        let p = params(0.0);
        let x = sine(3.0, 900);
        let y = RateDependentPi::from_params(p.clone())
            .unwrap()
            .run(&x)
            .unwrap();
        let mut z = p.y0.clone();
        for (&xi, &yi) in x.iter().zip(&y) {
            let mut want = p.a0 * xi;
            for ((zj, &r), &w) in z.iter_mut().zip(&p.r).zip(&p.w) {
                *zj = play_step(r, *zj, xi);
                want += w * *zj;
            }
            assert_eq!(yi.to_bits(), want.to_bits());
        }
    }

    /// The loop widens with frequency: the same sine sampled at the same
    /// `dt`, run faster, dissipates more per cycle.
    #[test]
    fn faster_inputs_give_wider_loops() {
        let area = |periods: f64| {
            let x = sine(periods, 4000);
            let y = RateDependentPi::from_params(params(0.002))
                .unwrap()
                .run(&x)
                .unwrap();
            // the last cycle's |∮ y dx|, trapezoid rule
            let per = (4000.0 / periods) as usize;
            let (xs, ys) = (&x[4000 - per..], &y[4000 - per..]);
            xs.windows(2)
                .zip(ys.windows(2))
                .map(|(a, b)| 0.5 * (b[0] + b[1]) * (a[1] - a[0]))
                .sum::<f64>()
                .abs()
        };
        let (slow, fast) = (area(2.0), area(20.0));
        assert!(fast > 1.2 * slow, "{slow} {fast}");
    }

    /// The tangent is the step's derivative in the input, the thresholds'
    /// rate dependence included.
    #[test]
    fn tangent_matches_a_central_difference() {
        let p = params(0.002);
        let mut op = RateDependentPi::from_params(p.clone()).unwrap();
        for (i, &x) in sine(7.0, 500).iter().enumerate() {
            let s = op.state().clone();
            let t = op.trial(x).unwrap();
            let fd = step_difference(&p, &s, x, 1e-7);
            // a play's branch can change within ±h: skip those samples
            let kink = p.r.iter().zip(&s.z).any(|(&r, &z)| {
                let r = r + p.lam * ((x - s.x) / p.dt).abs();
                (x - r - z).abs() < 1e-5 || (x + r - z).abs() < 1e-5
            });
            if !kink && (x - s.x).abs() > 1e-5 {
                assert!(
                    (t.tangent - fd).abs() < 1e-5,
                    "sample {i}: {} vs {fd}",
                    t.tangent
                );
            }
            op.commit();
        }
    }

    #[test]
    fn mismatched_lengths_and_bad_rates_are_typed_errors() {
        let named = |p: RateDependentPiParams<f64>| rejected_field(RateDependentPi::from_params(p));
        assert_eq!(
            named(RateDependentPiParams {
                w: vec![1.0],
                ..params(0.1)
            }),
            "w"
        );
        assert_eq!(
            named(RateDependentPiParams {
                r: vec![],
                w: vec![],
                y0: vec![],
                ..params(0.1)
            }),
            "r"
        );
        assert_eq!(
            named(RateDependentPiParams {
                lam: -1.0,
                ..params(0.1)
            }),
            "lam"
        );
        assert_eq!(
            named(RateDependentPiParams {
                dt: 0.0,
                ..params(0.1)
            }),
            "dt"
        );
    }
}
