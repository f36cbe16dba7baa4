//! The Bouc-Wen model with Baber-Noori degradation of strength, stiffness
//! and energy, as OpenSees' `uniaxialMaterial BoucWen` defines it,
//! integrated in the input's travel to a tolerance instead of one implicit
//! step per sample.

use crate::energy_flow::{
    bouc_wen_family_params, energy_step_law, power_on_side, EnergyFlow, FamilyBase,
};
use crate::{Float, Stepped};

bouc_wen_family_params! {
    /// Parameters of the [`BoucWenDegrading`] model (OpenSees' names
    /// `alpha ko n gamma beta Ao deltaA deltaNu deltaEta`, written
    /// `alpha k0 n gamma beta a0 delta_a delta_nu delta_eta`).
    pub struct BoucWenDegradingParams<T>: Copy {
        /// Strength degradation `δ_A ≥ 0`: `A = a0 − δ_A e`.
        delta_a: T => NonNegative = 0.01,
        /// Strength degradation `δ_ν ≥ 0`: `ν = 1 + δ_ν e`.
        delta_nu: T => NonNegative = 0.01,
        /// Stiffness degradation `δ_η ≥ 0`: `η = 1 + δ_η e`.
        delta_eta: T => NonNegative = 0.01,
    }
    law: "bouc_wen_degrading", "F = α k0 x + (1 − α) k0 z, dz/dx = (A − |z|^n ν (γ + β sgn(ẋ z)))/η, de/dx = (1 − α) k0 z, A = a0 − δ_A e, ν = 1 + δ_ν e, η = 1 + δ_η e";
}

impl<T: Float> EnergyFlow<T> for BoucWenDegradingParams<T> {
    /// The ultimate `z`, `(a0 / (β + γ))^{1/n}` where `β + γ > 0`, else
    /// `a0`.
    fn z_scale(&self) -> f64 {
        let bound = (self.beta + self.gamma).as_f64();
        let a0 = self.a0.as_f64();
        if bound > 0.0 {
            (a0 / bound).powf(1.0 / self.n.as_f64())
        } else {
            a0
        }
    }

    /// `(A − |z|^n ν (γ ± β)) / η`, `γ + β` while loading (`ẋ z > 0`).
    #[inline(always)]
    fn rate(&self, dir: T, positive: bool, z: T, e: T) -> T {
        let a = self.a0 - self.delta_a * e;
        let nu = T::one() + self.delta_nu * e;
        let eta = T::one() + self.delta_eta * e;
        let psi = self.shape(dir, positive);
        (a - power_on_side(positive, z, self.n) * nu * psi) / eta
    }
}

/// The Bouc-Wen model with Baber-Noori degradation (Baber & Noori 1985;
/// OpenSees' `uniaxialMaterial BoucWen`), driven by a displacement `x`:
///
/// `F = α k0 x + (1 − α) k0 z`,
/// `dz/dx = (A − |z|^n ν (γ + β sgn(ẋ z))) / η`,
/// `de/dx = (1 − α) k0 z`,
/// `A = a0 − δ_A e`,  `ν = 1 + δ_ν e`,  `η = 1 + δ_η e`,
///
/// from `x = z = e = 0`. Strength degrades through `A` and `ν`, stiffness
/// through `η`, as the hysteretic energy `e` grows. With the three `δ` at
/// 0 it is the classical Bouc-Wen model (note OpenSees' convention: `γ +
/// β` applies while `ẋ z > 0`, loading).
///
/// **Integration.** Each sample integrates the pair `(z, e)` over the
/// input's travel from the last sample (the equations are
/// rate-independent: they depend on the path of `x`, not on time) by
/// adaptive Dormand–Prince 5(4), each sub-step's local error below `1e-11`
/// of the state's scale (`z`: its ultimate value `(a0/(β + γ))^{1/n}`;
/// `e`: the energy of a travel at that `z`), each sub-step ending where
/// `z` changes sign, where the flow is not smooth (`|z|^n`, `sgn z`), so
/// that the derivatives are as accurate as the values. Refining the input's sampling
/// therefore changes the output by the tolerance only. OpenSees instead
/// takes one backward-Euler step per strain increment, first order in the
/// increment. The tangent is `α k0 + (1 − α) k0 dz/dx` at the end of the
/// step, in the direction travelled.
///
/// ```
/// use hysteron_operators::{BoucWenDegrading, Operator};
/// let mut bw = BoucWenDegrading::<f64>::from_params(Default::default()).unwrap();
/// let x: Vec<f64> = (0..400).map(|i| 3.0 * (i as f64 * 0.05).sin()).collect();
/// let f = bw.run(&x).unwrap();
/// // the hysteretic energy has grown, and with it the strength has fallen
/// assert!(bw.state().e > 0.0);
/// assert!(f.iter().all(|v| v.is_finite()));
/// ```
pub type BoucWenDegrading<T> = Stepped<BoucWenDegradingParams<T>, T>;

impl<T: Float> Default for BoucWenDegradingParams<T> {
    /// OpenSees' example of the manual's form: `α = 0.1, k0 = 10, n = 1,
    /// γ = β = 0.5, a0 = 1`, each `δ` 0.01.
    fn default() -> Self {
        let l = T::lit;
        BoucWenDegradingParams {
            alpha: l(0.1),
            k0: l(10.0),
            n: T::one(),
            gamma: l(0.5),
            beta: l(0.5),
            a0: T::one(),
            delta_a: l(0.01),
            delta_nu: l(0.01),
            delta_eta: l(0.01),
        }
    }
}

energy_step_law!(BoucWenDegradingParams<T>, EnergyFlow::energy_step);

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::indexing_slicing)]
    use super::*;
    use crate::test_support::{assert_refines_within, ramped_sine, step_difference};
    use crate::{EnergyState, Operator, StepLaw};

    fn params(delta: f64) -> BoucWenDegradingParams<f64> {
        BoucWenDegradingParams {
            delta_a: delta,
            delta_nu: delta,
            delta_eta: delta,
            ..Default::default()
        }
    }

    /// Without degradation and with `n = 1`, a monotone loading from rest
    /// has the closed form `z = (a0/(β + γ)) (1 − e^{−(β + γ) x})`.
    #[test]
    fn without_degradation_monotone_loading_is_the_closed_form() {
        let mut op = BoucWenDegrading::from_params(params(0.0)).unwrap();
        let x: Vec<f64> = (1..=300).map(|i| 0.01 * i as f64).collect();
        let f = op.run(&x).unwrap();
        for (&xi, &fi) in x.iter().zip(&f) {
            let z = 1.0 - (-xi).exp();
            let want = 0.1 * 10.0 * xi + 0.9 * 10.0 * z;
            assert!((fi - want).abs() < 1e-9, "x = {xi}: {fi} vs {want}");
        }
    }

    /// Rate-independent: the same path sampled 1× and 8× finer gives the same
    /// outputs at the shared samples, to the tolerance.
    #[test]
    fn refining_the_sampling_changes_the_output_by_the_tolerance_only() {
        let coarse = ramped_sine(300, 1.0, 4.0, 4.0);
        assert_refines_within(
            &BoucWenDegrading::from_params(params(0.02)).unwrap(),
            &coarse,
            8,
            1e-8,
        );
    }

    /// Degradation lowers the force of every later cycle at the same
    /// amplitude, and the energy only grows over full cycles.
    #[test]
    fn strength_falls_cycle_by_cycle() {
        let mut op = BoucWenDegrading::from_params(params(0.05)).unwrap();
        let cycle: Vec<f64> = (0..200)
            .map(|i| 2.0 * (std::f64::consts::TAU * i as f64 / 200.0).sin())
            .collect();
        let mut peaks = vec![];
        let mut energies = vec![];
        for _ in 0..5 {
            let f = op.run(&cycle).unwrap();
            peaks.push(f[50]);
            energies.push(op.state().e);
        }
        for w in peaks.windows(2) {
            assert!(w[1] < w[0], "peaks {peaks:?}");
        }
        for w in energies.windows(2) {
            assert!(w[1] > w[0], "energies {energies:?}");
        }
    }

    /// The tangent is the derivative of one step's output in the input.
    #[test]
    fn tangent_is_the_step_derivative() {
        let p = params(0.03);
        let s = EnergyState {
            x: 0.5,
            z: 0.3,
            e: 1.2,
        };
        for x in [0.9, 1.5, 0.1, -0.7] {
            let (_, t) = p.step(&s, x).unwrap();
            let fd = step_difference(&p, &s, x, 1e-6);
            assert!(
                (t.tangent - fd).abs() < 1e-5 * (1.0 + fd.abs()),
                "x = {x}: {} vs {fd}",
                t.tangent
            );
        }
    }
}
