//! The elastoplastic (Maxwell-slip) element: a scaled stop.

use crate::{check, declare_params, stop_step, Float, Result, StepLaw, Stepped, StopParams, Trial};

declare_params! {
    /// Parameters of the [`ElastoPlastic`] element.
    pub struct ElastoPlasticParams<T>: Copy {
        /// Spring stiffness `k > 0`.
        k: T => Positive = 4.0,
        /// Break-away force `F_b ≥ 0`.
        f_b: T => NonNegative = 1.5,
        /// Force at input `x = 0` before the first sample (default 0).
        #[serde(default)]
        f0: T => Real = -0.5,
    }
    check = ElastoPlasticParams::ratios;
    law: "elastoplastic", "F = k · stop_{F_b/k}[x]: slope k until |F| = F_b, then sliding at ±F_b";
}

impl<T: Float> ElastoPlasticParams<T> {
    /// The element works through a stop of threshold `F_b/k` (and initial
    /// output `f0/k`): those ratios must be representable.
    fn ratios(&self) -> Result<()> {
        check::level_over_stiffness("f_b", self.f_b, self.k)?;
        check::start_over_stiffness(self.f0, self.k)?;
        Ok(())
    }

    fn stop(&self) -> StopParams<T> {
        StopParams {
            r: self.f_b / self.k,
            s0: self.f0 / self.k,
        }
    }
}

/// Elastoplastic (Maxwell-slip) element: a massless block on a rubbing
/// surface pulled through a linear spring,
///
/// `F = k · s_{F_b/k}[x]`,
///
/// with `s_r` the [`Stop`](crate::Stop): linear with slope `k` until `|F| = F_b`, then
/// sliding at `±F_b`. Parallel banks of these give the Maxwell-slip friction
/// model.
pub type ElastoPlastic<T> = Stepped<ElastoPlasticParams<T>, T>;

impl<T: Float> ElastoPlastic<T> {
    /// An element with stiffness `k` and break-away force `f_b`, unloaded.
    pub fn new(k: T, f_b: T) -> Result<Self> {
        Self::from_params(ElastoPlasticParams {
            k,
            f_b,
            f0: T::zero(),
        })
    }
}

impl<T: Float> StepLaw<T> for ElastoPlasticParams<T> {
    // At an unchanged input the clamp that moves the state leaves it.
    const RESTS_WHEN_HELD: bool = true;
    type State = T;

    fn initial(&self) -> T {
        -self.stop().s0
    }

    #[inline(always)]
    fn step(&self, q: &T, x: T) -> Result<(T, Trial<T>)> {
        let (s, q, tangent) = stop_step(self.stop().r, *q, x);
        let k = self.k;
        Ok((
            q,
            Trial {
                output: k * s,
                tangent: k * tangent,
            },
        ))
    }
}
