//! # hysteron-operators
//!
//! The core of hysteron: the [`Operator`] trait (a scalar operator with
//! memory under a trial/commit protocol), the [`Error`] type, the [`Float`]
//! alias, and the elementary operators:
//!
//! | operator | equation |
//! |---|---|
//! | [`Play`] | `y = max(x − r, min(x + r, y_prev))` |
//! | [`Stop`] | `s = x − play_r[x]`, in `[−r, r]` |
//! | [`ElastoPlastic`] | `F = k · stop_{F_b/k}[x]` (Maxwell-slip element) |
//! | [`AsymmetricFriction`] | `F = k (x − x_p)`, `x_p` moving only to keep `−f_neg ≤ F ≤ f_pos` |
//! | [`BacklashContact`] | `F = sgn(u)(k1 d + k2 d² + k3 d³)`, `u = x − c`, `d = max(\|u\| − b/2, 0)` |
//! | [`DeadZone`] | `x − b_r` above `b_r`, `x − b_l` below `b_l`, 0 between |
//! | [`Saturation`] | `clamp(x, lo, hi)` |
//! | [`Gain`] | `k x` |
//! | [`MaxwellSlip`] | `F = Σ_i k_i · stop_{F_i/k_i}[x]` (bank of elastoplastic elements) |
//! | [`Dahl`] | `dF/dx = σ \|1 − (F/F_c) sgn ẋ\|^α sgn(1 − (F/F_c) sgn ẋ)` |
//! | [`LuGre`] | `ż = v − σ0 \|v\| z / g(v)`, `F = σ0 z + σ1 ż + σ2 v` (rate-dependent, exact per sample) |
//! | [`Gms`] | generalized Maxwell-slip: stick `Ḟ_i = k_i v`, slip `Ḟ_i = sgn(v) C (1 − sgn(v) F_i/(α_i s(v)))` (rate-dependent, exact per sample) |
//! | [`Mms`] | `y = y_r + (sgn(ẋ) F_c − y_r)(1 − e^{−K|x − x_r|})` |
//! | [`BoucWen`] | `H = w S(z) z + (1 − w) S(z) h`, `dh/dz = α − \|h\|^n (β sgn(ż h) + γ)` |
//! | [`Preisach`] | `y = ∬_{α≥β} μ(α,β) γ_{αβ}[x] dα dβ = −E₀ + 2 Σ_k s_k E(p_k, p_{k−1})` |
//! | [`MassSpringDamper`] | `m ÿ + c ẏ + k y = u` (rate-dependent, Newmark) |
//! | [`ViscousDamper`] | `F = c ẋ` (rate-dependent, trapezoidal) |
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
mod error;
mod exp_m1;
mod float;
mod leaf;
mod memoryless;
mod operator;
pub mod params;
pub mod simd;
mod staged;

mod flow_sensitivity;
mod flow_table;
mod hysteretic_state;
mod stiffness;

pub use bouc_wen::StateSolver;
pub use domain::Domain;
pub use dual::{Differentiable, Dual, DualN, DUAL_WIDTH};
pub use error::{Error, Result};
pub use float::Float;
pub use leaf::{checked_step, Leaf, StepLaw, Stepped};
pub use operator::{
    check_input, check_lengths, check_output, process_by_trials, process_while_by_trials, Beyond,
    Keep, Operator, Trial,
};
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
    backlash_contact => BacklashContact,
}
