//! The semilinear Duhem model (Coleman-Hodgdon with a linear anhysteretic
//! curve and a constant slope), solved exactly per sample.

use crate::{declare_params, Float, Result, StepLaw, Stepped, Trial};

declare_params! {
    /// Parameters of the [`Duhem`] model.
    pub struct DuhemParams<T>: Copy {
        /// Rate `α > 0` (per input unit) at which the output approaches the
        /// anhysteretic line while the input moves.
        alpha: T => Positive = 2.0,
        /// Slope `a` of the anhysteretic line `y = a x` (finite).
        a: T => Real = 1.0,
        /// Slope `b` the output keeps on the line's two sides (finite):
        /// the branches approach `y = a x ± (b − a)/α`.
        b: T => Real = 0.2,
        /// Output `y0` at input `x = 0` before the first sample (default 0).
        #[serde(default)]
        y0: T => Real = 0.0,
    }
    law: "duhem", "dy/dx = α sgn(ẋ) (a x − y) + b";
}

/// The state between samples: the input and output of the last sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DuhemState<T> {
    /// The input of the last sample.
    pub x: T,
    /// The output there.
    pub y: T,
}

/// The semilinear Duhem model (Oh & Bernstein 2005), the Coleman-Hodgdon
/// model with the linear anhysteretic curve `f(x) = a x` and the constant
/// `g = b`:
///
/// `ẏ = α |ẋ| (a x − y) + b ẋ`,  i.e.  `dy/dx = α sgn(ẋ) (a x − y) + b`,
///
/// from `y = y0` at `x = 0`. Rate-independent: the output depends on the
/// path of `x`, not on time. On each sample's travel `s = |x − x_prev|` in
/// direction `d = ±1` the distance to the line, `u = y − a x`, relaxes
/// exactly:
///
/// `u = u_∞ + (u_prev − u_∞) e^{−α s}`,  `u_∞ = d (b − a)/α`,
///
/// evaluated as `u_prev − (u_∞ − u_prev) expm1(−α s)` (no integration
/// error; rounding only, so refining the sampling changes the output by
/// rounding). The branches of a cycle approach the lines
/// `y = a x + d (b − a)/α`; the tangent is `α d (a x − y) + b`.
///
/// ```
/// use hysteron_operators::{Duhem, Operator};
/// let mut d = Duhem::new(2.0_f64, 1.0, 0.2).unwrap();
/// let y = d.run(&[10.0]).unwrap();
/// // far along an increasing input the output is on y = a x + (b − a)/α
/// assert!((y[0] - (10.0 - 0.4)).abs() < 1e-7);
/// ```
pub type Duhem<T> = Stepped<DuhemParams<T>, T>;

impl<T: Float> Duhem<T> {
    /// A model of rate `alpha`, line slope `a` and side slope `b`, from
    /// `y = 0`.
    pub fn new(alpha: T, a: T, b: T) -> Result<Self> {
        Self::from_params(DuhemParams {
            alpha,
            a,
            b,
            y0: T::zero(),
        })
    }
}

impl<T: Float> StepLaw<T> for DuhemParams<T> {
    type State = DuhemState<T>;
    const RESTS_WHEN_HELD: bool = true;

    fn initial(&self) -> DuhemState<T> {
        DuhemState {
            x: T::zero(),
            y: self.y0,
        }
    }

    fn step(&self, s: &DuhemState<T>, x: T) -> Result<(DuhemState<T>, Trial<T>)> {
        let travel = x - s.x;
        let dir = if travel < T::zero() {
            -T::one()
        } else {
            T::one()
        };
        let y = if travel == T::zero() {
            s.y
        } else {
            let u_prev = s.y - self.a * s.x;
            let u_inf = dir * (self.b - self.a) / self.alpha;
            let u = u_prev - (u_inf - u_prev) * (-self.alpha * travel.abs()).exp_m1();
            self.a * x + u
        };
        Ok((
            DuhemState { x, y },
            Trial {
                output: y,
                tangent: self.alpha * dir * (self.a * x - y) + self.b,
            },
        ))
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::indexing_slicing)]
    use super::*;
    use crate::test_support::{refinement_difference, step_difference};
    use crate::Operator;

    /// On an increasing ramp from rest the closed form
    /// `y = a x + (b − a)/α (1 − e^{−α x})`.
    #[test]
    fn a_ramp_follows_the_closed_form() {
        let mut d = Duhem::new(2.0, 1.0, 0.2).unwrap();
        let x: Vec<f64> = (1..=500).map(|i| 0.01 * i as f64).collect();
        let y = d.run(&x).unwrap();
        for (&xi, &yi) in x.iter().zip(&y) {
            let want = xi + (0.2 - 1.0) / 2.0 * (1.0 - (-2.0 * xi).exp());
            assert!((yi - want).abs() < 1e-13, "x = {xi}: {yi} vs {want}");
        }
    }

    /// Refining the sampling of a path changes the output by rounding.
    #[test]
    fn refining_the_sampling_changes_the_output_by_rounding_only() {
        let coarse: Vec<f64> = (0..400)
            .map(|i| {
                let t = i as f64 / 400.0;
                2.0 * (std::f64::consts::TAU * 3.0 * t).sin() + 0.3 * (50.0 * t).sin()
            })
            .collect();
        let (i, d) = refinement_difference(&Duhem::new(2.0, 1.0, 0.2).unwrap(), &coarse, 8);
        assert!(d < 1e-13, "sample {i}: {d:e}");
    }

    /// The tangent is the derivative of one step's output.
    #[test]
    fn tangent_is_the_step_derivative() {
        let p = *Duhem::<f64>::new(1.5, 0.8, -0.3).unwrap().parameters();
        let s = DuhemState { x: 0.4, y: -0.2 };
        for x in [0.9, 2.0, 0.1, -1.0] {
            let (_, t) = p.step(&s, x).unwrap();
            let fd = step_difference(&p, &s, x, 1e-6);
            assert!(
                (t.tangent - fd).abs() < 1e-7,
                "x = {x}: {} vs {fd}",
                t.tangent
            );
        }
    }
}
