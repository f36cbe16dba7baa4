//! The elastoplastic (Maxwell-slip) element: a scaled stop.

use crate::{check, Domain, Float, Operator, Result, Stop, StopParams, Trial};
use serde::{Deserialize, Serialize};

/// Parameters of the [`ElastoPlastic`] element.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ElastoPlasticParams<T> {
    /// Spring stiffness `k > 0`.
    pub k: T,
    /// Break-away force `F_b ≥ 0`.
    pub f_b: T,
    /// Force at input `x = 0` before the first sample (default 0).
    #[serde(default)]
    pub f0: T,
}

impl<T: Float> ElastoPlasticParams<T> {
    /// Checks `k > 0`, `F_b ≥ 0`, finite `f0`.
    pub fn validate(&self) -> Result<()> {
        check::positive("k", self.k)?;
        check::non_negative("f_b", self.f_b)?;
        check::finite("f0", self.f0)?;
        // The element works through a stop of threshold F_b/k (and initial
        // output f0/k): those ratios must be representable.
        let (r, s0) = (self.f_b / self.k, self.f0 / self.k);
        if !r.is_finite() || (self.f_b > T::zero() && r == T::zero()) {
            return Err(crate::Error::InvalidParameter {
                name: "f_b".into(),
                value: self.f_b.as_f64(),
                reason: "F_b / k must be a finite, non-zero number when F_b > 0",
            });
        }
        if !s0.is_finite() {
            return Err(crate::Error::InvalidParameter {
                name: "f0".into(),
                value: self.f0.as_f64(),
                reason: "f0 / k must be finite",
            });
        }
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
/// with `s_r` the [`Stop`]: linear with slope `k` until `|F| = F_b`, then
/// sliding at `±F_b`. Parallel banks of these give the Maxwell-slip friction
/// model.
#[derive(Debug, Clone, PartialEq)]
pub struct ElastoPlastic<T> {
    p: ElastoPlasticParams<T>,
    stop: Stop<T>,
}

impl<T: Float> ElastoPlastic<T> {
    /// An element with stiffness `k` and break-away force `f_b`, unloaded.
    pub fn new(k: T, f_b: T) -> Result<Self> {
        Self::from_params(ElastoPlasticParams {
            k,
            f_b,
            f0: T::zero(),
        })
    }

    /// An element from validated parameters.
    pub fn from_params(p: ElastoPlasticParams<T>) -> Result<Self> {
        p.validate()?;
        Ok(Self {
            p,
            stop: Stop::from_params(p.stop())?,
        })
    }

    /// The parameters.
    pub fn parameters(&self) -> &ElastoPlasticParams<T> {
        &self.p
    }
}

impl<T: Float> Operator<T> for ElastoPlastic<T> {
    fn name(&self) -> &'static str {
        "elastoplastic"
    }

    #[inline]
    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        let t = self.stop.trial(x)?;
        Ok(Trial {
            output: self.p.k * t.output,
            tangent: self.p.k * t.tangent,
        })
    }

    #[inline]
    fn commit(&mut self) {
        self.stop.commit();
    }

    fn reset(&mut self) {
        self.stop.reset();
    }

    fn process(&mut self, xs: &[T], ys: &mut [T]) -> Result<()> {
        self.stop.process(xs, ys)?;
        let k = self.p.k;
        ys.iter_mut().for_each(|y| *y = k * *y);
        Ok(())
    }

    fn n_params(&self) -> usize {
        3
    }

    fn params_into(&self, out: &mut Vec<T>) {
        out.extend([self.p.k, self.p.f_b, self.p.f0]);
    }

    fn param_names(&self) -> Vec<String> {
        vec!["k".into(), "f_b".into(), "f0".into()]
    }

    fn param_domains(&self) -> Vec<Domain> {
        vec![Domain::Positive, Domain::NonNegative, Domain::Real]
    }

    fn set_params(&mut self, p: &[T]) -> Result<()> {
        check::count(3, p)?;
        *self = Self::from_params(ElastoPlasticParams {
            k: p[0],
            f_b: p[1],
            f0: p[2],
        })?;
        Ok(())
    }
}
