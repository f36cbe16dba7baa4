//! # hysteron-operators
//!
//! The core of hysteron: the [`Operator`] trait (a scalar operator with
//! memory under a trial/commit protocol), the [`Error`] type, the [`Float`]
//! alias, and the elementary operators:
//!
//! <!-- BEGIN generated: operators (scripts/generate.sh) -->
//! | operator | spec `type` | equation |
//! |---|---|---|
//! | [`Play`] | `play` | `y_k = max(x_k − r, min(x_k + r, y_{k−1})), from y0` |
//! | [`Stop`] | `stop` | `s = x − play_r[x] ∈ [−r, r], from s0` |
//! | [`ElastoPlastic`] | `elastoplastic` | `F = k · stop_{F_b/k}[x]: slope k until \|F\| = F_b, then sliding at ±F_b` |
//! | [`DeadZone`] | `dead_zone` | `y = x − b_r above b_r, x − b_l below b_l, 0 in between` |
//! | [`Saturation`] | `saturation` | `y = clamp(x, lo, hi)` |
//! | [`Gain`] | `gain` | `y = k x` |
//! | [`Mms`] | `mms` | `y = y_r + (sgn(ẋ) F_c − y_r)(1 − exp(−K \|x − x_r\|)), (x_r, y_r) the last reversal` |
//! | [`BoucWen`] | `bouc_wen` | `H = w S(z) z + (1 − w) S(z) h, dh/dz = α − \|h\|^n (β sgn(ż h) + γ), z = x − z0` |
//! | [`Preisach`] | `preisach` | `y = ∬_{α≥β} μ(α, β) γ_{αβ}[x] dα dβ (relays γ_{αβ} switching up at α, down at β)` |
//! | [`MassSpringDamper`] | `mass_spring_damper` | `m ÿ + c ẏ + k y = u (input force u, output displacement y; Newmark average acceleration, step dt)` |
//! | [`ViscousDamper`] | `viscous_damper` | `F = c ẋ, ẋ the backward difference (x_k − x_{k−1})/dt` |
//! | [`MaxwellSlip`] | `maxwell_slip` | `F = Σ_i k_i · stop_{F_i/k_i}[x] (parallel elastoplastic elements)` |
//! | [`Dahl`] | `dahl` | `dF/dx = σ \|1 − (F/F_c) sgn ẋ\|^α sgn(1 − (F/F_c) sgn ẋ)` |
//! | [`LuGre`] | `lugre` | `ż = v − σ0 \|v\| z / g(v), g(v) = F_c + (F_s − F_c) exp(−\|v/v_s\|^δ), F = σ0 z + σ1 ż + σ2 v` |
//! | [`Gms`] | `gms` | `F = Σ F_i + σ2 v; stick Ḟ_i = k_i v until \|F_i\| = α_i s(v), slip Ḟ_i = sgn(v) C (1 − sgn(v) F_i/(α_i s(v)))` |
//! | [`Offset`] | `offset` | `y = x + c` |
//! | [`AsymmetricFriction`] | `asymmetric_friction` | `F = k · (x − x_p), x_p moving only to keep −f_neg ≤ F ≤ f_pos: slope k while sticking, sliding at f_pos or −f_neg` |
//! | [`TransientFriction`] | `transient_friction` | `F = k · (x − x_p), x_p moving only to keep −L_neg(u) ≤ F ≤ L_pos(u), L(u) = f (1 + a e^{−u/λ}) with u the slip since the last change of slip direction` |
//! | [`BacklashContact`] | `backlash_contact` | `u = x − c, d = max(\|u\| − b/2, 0), F = sgn(u)·(k1 d + k2 d² + k3 d³)` |
//! | [`Relay`] | `relay` | `y = a s, s = +1 once x ≥ h/2, −1 once x ≤ −h/2, held in between (from s0)` |
//! | [`BoucWenDegrading`] | `bouc_wen_degrading` | `F = α k0 x + (1 − α) k0 z, dz/dx = (A − \|z\|^n ν (γ + β sgn(ẋ z)))/η, de/dx = (1 − α) k0 z, A = a0 − δ_A e, ν = 1 + δ_ν e, η = 1 + δ_η e` |
//! | [`Energy`] | `bouc_wen_degrading_energy` | `e = ∫ (1 − α) k0 z dx of the bouc_wen_degrading model (its parameters and step; output e instead of F)` |
//! | [`Bwbn`] | `bwbn` | `F = α k0 x + (1 − α) k0 z, dz/dx = h (a0 − \|z\|^n (γ + β sgn(ẋ z))), h = 1 − ζ1 exp(−(z sgn ẋ − q z_u)²/ζ2²), ζ1 = ζ_s (1 − e^{−p e}), ζ2 = (ψ0 + δ_ψ e)(λ + ζ1), z_u = (1/(β + γ))^{1/n}, de/dx = (1 − α) k0 z` |
//! | [`Energy`] | `bwbn_energy` | `e = ∫ (1 − α) k0 z dx of the bwbn model (its parameters and step; output e instead of F)` |
//! | [`Duhem`] | `duhem` | `dy/dx = α sgn(ẋ) (a x − y) + b` |
//! | [`JilesAtherton`] | `jiles_atherton` | `M = c M_an + (1 − c) M_irr, M_an = Ms L((H + α M)/a), L(u) = coth u − 1/u, dM_irr/dH_e = δ_M (M_an − M_irr)/(δ k), δ = sgn Ḣ, δ_M = 1 where δ (M_an − M_irr) > 0 else 0` |
//! | [`Envelope`] | `envelope` | `y = tanh(b x) / (b (1 + s tanh(b x))), y = x for b = 0` |
//! | [`EnvelopeInverse`] | `envelope_inverse` | `x = φ⁻¹(y) = atanh(b y / (1 − b s y)) / b, x = y for b = 0 (the envelope's inverse)` |
//! | [`RateDependentPi`] | `rate_dependent_pi` | `y = a0 x + Σ_j w_j play_{r_j + λ\|ẋ\|}[x], ẋ = (x_k − x_{k−1})/dt` |
//! | [`KrasnoselskiiPokrovskii`] | `krasnoselskii_pokrovskii` | `y = Σ_{j≤i} μ_ij k_ij[x], k_ij = max(R_up(x − t_i), min(R_down(x − t_j), k_ij⁻)), R_up(u) = clamp(2u/a − 1, −1, 1), R_down(u) = clamp(2u/a + 1, −1, 1), from k = −1` |
//! <!-- END generated: operators -->
//!
//! Combinators live in `hysteron-composition`.

#![warn(missing_docs)]
// The library promises never to panic on user input: no unwrap/expect/panic
// and no unchecked indexing outside tests (the lints are in the workspace
// Cargo.toml; each exception is an `allow` with the invariant that makes it safe).

// `declare_params!` names this crate by its path in serde attributes.
extern crate self as hysteron_operators;

#[doc(hidden)]
pub use serde as __serde;

pub mod check;
mod domain;
mod dual;
mod duhem_fn;
mod energy_flow;
mod error;
pub mod exp_kernel;
mod float;
mod hints;
pub mod lanes;
mod leaf;
#[doc(hidden)]
pub mod memoryless;
mod ode;
mod operator;
mod parameters;
pub mod params;
mod reversal;
pub mod simd;
mod staged;
#[cfg(test)]
mod test_support;

mod flow_sensitivity;
mod flow_table;
mod hysteretic_state;
mod stiffness;

pub use bouc_wen::StateSolver;
pub use domain::Domain;
pub use dual::{Differentiable, Dual, DualN, DUAL_WIDTH};
pub use duhem_fn::DuhemFn;
pub use energy_flow::{Energy, EnergyState};
pub use error::{Error, Result};
pub use float::Float;
pub use hints::{
    process_while, process_while_beyond, process_while_by_trials, Beyond, Hints, Keep,
};
pub use leaf::{checked_step, Declared, Leaf, StepLaw, Stepped};
pub use memoryless::Memoryless;
pub use operator::{check_input, check_lengths, check_output, process_by_trials, Operator, Trial};
pub use parameters::{Derivatives, Parameters, SamplePeriod};
pub use params::{CastScalar, FieldInfo, FieldKind, ParamField, ParamSet};
pub use staged::Staged;
pub use stiffness::StiffnessMap;

/// Declares the leaf operators of this crate: each line is a module (its
/// own file), whose public items are re-exported, and the [`Leaf`] type it
/// defines. `for_each_leaf!(callback)` calls `callback!(Type, …)` with every
/// one of them; the spec registry of `hysteron-models` is built that way,
/// so a line here is all that registers a new leaf (see
/// `CONTRIBUTING.md`).
macro_rules! leaves {
    ($d:tt; $($module:ident => $leaf:ident,)*) => {
        $(
            mod $module;
            pub use $module::*;
        )*

        /// Calls `callback!(Play, Stop, …)` with every leaf operator type
        /// of `hysteron-operators` (each generic over its scalar).
        #[macro_export]
        macro_rules! for_each_leaf {
            ($d callback:ident) => {
                $d callback! { $($leaf),* }
            };
        }
    };
}

leaves! { $;
    play => Play,
    stop => Stop,
    elastoplastic => ElastoPlastic,
    deadzone => DeadZone,
    saturation => Saturation,
    gain => Gain,
    mms => Mms,
    bouc_wen => BoucWen,
    preisach => Preisach,
    mass_spring_damper => MassSpringDamper,
    viscous_damper => ViscousDamper,
    maxwell_slip => MaxwellSlip,
    dahl => Dahl,
    lugre => LuGre,
    gms => Gms,
    offset => Offset,
    asymmetric_friction => AsymmetricFriction,
    transient_friction => TransientFriction,
    backlash_contact => BacklashContact,
    relay => Relay,
    bouc_wen_degrading => BoucWenDegrading,
    bouc_wen_degrading_energy => BoucWenDegradingEnergy,
    bwbn => Bwbn,
    bwbn_energy => BwbnEnergy,
    duhem => Duhem,
    jiles_atherton => JilesAtherton,
    envelope => Envelope,
    envelope_inverse => EnvelopeInverse,
    rate_dependent_pi => RateDependentPi,
    krasnoselskii_pokrovskii => KrasnoselskiiPokrovskii,
}
