//! The Bouc-Wen-Baber-Noori model with pinching, as OpenSees'
//! `uniaxialMaterial BWBN` defines it, integrated in the input's travel to
//! a tolerance instead of one implicit step per sample.

use crate::energy_flow::{
    bouc_wen_family_params, energy_step_law, power_on_side, EnergyFlow, FamilyBase,
};
use crate::{check, Float, Result, Stepped};

bouc_wen_family_params! {
    /// Parameters of the [`Bwbn`] model (OpenSees' names `alpha ko n gamma
    /// beta Ao q zetas p Shi deltaShi lamda`, written `alpha k0 n gamma beta
    /// a0 q zeta_s p psi0 delta_psi lam`).
    pub struct BwbnParams<T>: Copy {
        /// Where the pinching is centred, `q ≥ 0`: at `z = q z_u` in the
        /// direction of travel.
        q: T => NonNegative = 0.25,
        /// The pinching's final severity `ζ_s ∈ [0, 1]`.
        zeta_s: T => UnitInterval = 0.9,
        /// How fast the severity grows with the energy, `p ≥ 0`.
        p: T => NonNegative = 1.0,
        /// The pinching's initial spread `ψ0 > 0`.
        psi0: T => Positive = 0.2,
        /// The spread's growth with the energy, `δ_ψ ≥ 0`.
        delta_psi: T => NonNegative = 0.005,
        /// `λ > 0` (OpenSees' `lamda`; `lam`, as `lambda` is a keyword in
        /// Python): the spread's floor, `ζ2 = (ψ0 + δ_ψ e)(λ + ζ1)`.
        lam: T => Positive = 0.5,
    }
    check = BwbnParams::bounded;
    law: "bwbn", "F = α k0 x + (1 − α) k0 z, dz/dx = h (a0 − |z|^n (γ + β sgn(ẋ z))), h = 1 − ζ1 exp(−(z sgn ẋ − q z_u)²/ζ2²), ζ1 = ζ_s (1 − e^{−p e}), ζ2 = (ψ0 + δ_ψ e)(λ + ζ1), z_u = (1/(β + γ))^{1/n}, de/dx = (1 − α) k0 z";
}

impl<T: Float> BwbnParams<T> {
    /// `β + γ > 0`: the hysteretic displacement is bounded, and the
    /// pinching's centre `z_u = (1/(β + γ))^{1/n}` exists.
    fn bounded(&self) -> Result<()> {
        check::require(
            self.beta + self.gamma > T::zero(),
            "beta",
            self.beta,
            "beta + gamma must be > 0 (a bounded z, and the pinching's centre (1/(beta + gamma))^(1/n))",
        )
    }
}

impl<T: Float> EnergyFlow<T> for BwbnParams<T> {
    /// The ultimate `z`, `(a0 / (β + γ))^{1/n}`.
    fn z_scale(&self) -> f64 {
        (self.a0 / (self.beta + self.gamma))
            .as_f64()
            .powf(1.0 / self.n.as_f64())
    }

    /// `h (a0 − |z|^n (γ ± β))`, `γ + β` while loading (`ẋ z > 0`).
    #[inline(always)]
    fn rate(&self, dir: T, positive: bool, z: T, e: T) -> T {
        let psi = self.shape(dir, positive);
        let zeta1 = self.zeta_s * (T::one() - (-self.p * e).exp());
        let zeta2 = (self.psi0 + self.delta_psi * e) * (self.lam + zeta1);
        // the pinching's centre, without a power for the usual n = 1
        let bound = T::one() / (self.beta + self.gamma);
        let z_u = if self.n == T::one() {
            bound
        } else {
            bound.powf(T::one() / self.n)
        };
        let off = z * dir - self.q * z_u;
        let h = T::one() - zeta1 * (-(off * off) / (zeta2 * zeta2)).exp();
        h * (self.a0 - power_on_side(positive, z, self.n) * psi)
    }
}

/// The Bouc-Wen-Baber-Noori model with pinching (Baber & Noori 1985,
/// Foliente 1995; OpenSees' `uniaxialMaterial BWBN`), driven by a
/// displacement `x`:
///
/// `F = α k0 x + (1 − α) k0 z`,
/// `dz/dx = h(z, e) (a0 − |z|^n (γ + β sgn(ẋ z)))`,
/// `h = 1 − ζ1 exp(−(z sgn ẋ − q z_u)² / ζ2²)`,
/// `ζ1 = ζ_s (1 − e^{−p e})`,  `ζ2 = (ψ0 + δ_ψ e)(λ + ζ1)`,
/// `z_u = (1/(β + γ))^{1/n}`,  `de/dx = (1 − α) k0 z`,
///
/// from `x = z = e = 0`. The pinching function `h` slows the growth of `z`
/// near `z = q z_u` in the direction of travel, more as the hysteretic
/// energy `e` grows: the loops of a bolted joint, a cracked wall, a
/// timber connection narrow at the middle. (OpenSees writes `z_u` with 1,
/// not `a0`, under the root, and has no strength or stiffness degradation
/// in this material; both are kept as it defines them.)
///
/// **Integration** as [`BoucWenDegrading`](crate::BoucWenDegrading)'s:
/// `(z, e)` over each sample's travel by adaptive Dormand–Prince 5(4),
/// local error below `1e-11` of the state's scale, side by side of
/// `z = 0`; rate-independent to that tolerance. OpenSees takes one
/// backward-Euler step per strain increment, first order in it.
///
/// ```
/// use hysteron_operators::{Bwbn, BwbnParams, Operator};
/// let p = BwbnParams { alpha: 0.1, k0: 10.0, n: 1.0, gamma: 0.5, beta: 0.5, a0: 1.0,
///     q: 0.25, zeta_s: 0.9, p: 1.0, psi0: 0.2, delta_psi: 0.005, lam: 0.5 };
/// let mut m = Bwbn::from_params(p).unwrap();
/// let x: Vec<f64> = (0..400).map(|i| 3.0 * (i as f64 * 0.05).sin()).collect();
/// let f = m.run(&x).unwrap();
/// assert!(f.iter().all(|v| v.is_finite()) && m.state().e > 0.0);
/// ```
pub type Bwbn<T> = Stepped<BwbnParams<T>, T>;

energy_step_law!(BwbnParams<T>, EnergyFlow::energy_step);

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::indexing_slicing)]
    use super::*;
    use crate::test_support::{assert_refines_within, ramped_sine};
    use crate::{BoucWenDegrading, BoucWenDegradingParams, Operator};

    fn params(zeta_s: f64) -> BwbnParams<f64> {
        BwbnParams {
            alpha: 0.1,
            k0: 10.0,
            n: 1.0,
            gamma: 0.5,
            beta: 0.5,
            a0: 1.0,
            q: 0.25,
            zeta_s,
            p: 1.0,
            psi0: 0.2,
            delta_psi: 0.005,
            lam: 0.5,
        }
    }

    fn cycles() -> Vec<f64> {
        ramped_sine(2000, 1.0, 2.0, 5.0)
    }

    /// Without pinching (`ζ_s = 0`) it is the Bouc-Wen model without
    /// degradation, to the tolerance.
    #[test]
    fn without_pinching_it_is_the_plain_bouc_wen_model() {
        let x = cycles();
        let y = Bwbn::from_params(params(0.0)).unwrap().run(&x).unwrap();
        // the same α, k0, n, γ, β and a0
        let plain = BoucWenDegradingParams {
            delta_a: 0.0,
            delta_nu: 0.0,
            delta_eta: 0.0,
            ..Default::default()
        };
        let want = BoucWenDegrading::from_params(plain)
            .unwrap()
            .run(&x)
            .unwrap();
        for (i, (a, b)) in y.iter().zip(&want).enumerate() {
            assert!((a - b).abs() < 1e-12 * 30.0, "sample {i}: {a} vs {b}");
        }
    }

    /// Pinching narrows the loop near zero force: at the same input on
    /// the unloading branch the pinched model's force is smaller in
    /// magnitude at the pinch and it dissipates less per cycle.
    #[test]
    fn pinching_narrows_the_loops_and_dissipates_less() {
        let x = cycles();
        let mut pinched = Bwbn::from_params(params(0.95)).unwrap();
        let mut plain = Bwbn::from_params(params(0.0)).unwrap();
        pinched.run(&x).unwrap();
        plain.run(&x).unwrap();
        assert!(
            pinched.state().e < plain.state().e,
            "{} vs {}",
            pinched.state().e,
            plain.state().e
        );
    }

    /// Rate-independent: refining the sampling changes the output by the
    /// tolerance only.
    #[test]
    fn refining_the_sampling_changes_the_output_by_the_tolerance_only() {
        let coarse: Vec<f64> = cycles().into_iter().step_by(5).collect();
        assert_refines_within(&Bwbn::from_params(params(0.9)).unwrap(), &coarse, 8, 1e-8);
    }

    #[test]
    fn an_unbounded_shape_is_rejected() {
        let e = Bwbn::from_params(BwbnParams {
            beta: -0.5,
            ..params(0.5)
        })
        .unwrap_err();
        assert!(e.to_string().contains("beta"), "{e}");
    }
}
