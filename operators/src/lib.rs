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

// `declare_params!` names this crate by its path in serde attributes.
extern crate self as hysteron_operators;

#[doc(hidden)]
pub use serde as __serde;

pub mod check;
mod domain;
mod error;
mod float;
mod leaf;
mod memoryless;
mod operator;
pub mod params;

mod bouc_wen;
mod dahl;
mod deadzone;
mod elastoplastic;
mod flow_table;
mod gain;
mod gms;
mod hysteretic_state;
mod lugre;
mod mass_spring_damper;
mod maxwell_slip;
mod mms;
mod play;
mod preisach;
mod saturation;
mod stiffness;
mod stop;
mod viscous_damper;

pub use bouc_wen::{BoucWen, BoucWenParams, StateSolver};
pub use dahl::{Dahl, DahlLaw, DahlParams, DahlState};
pub use deadzone::{dead_zone, DeadZone, DeadZoneLaw, DeadZoneParams};
pub use domain::Domain;
pub use elastoplastic::{ElastoPlastic, ElastoPlasticLaw, ElastoPlasticParams};
pub use error::{Error, Result};
pub use float::Float;
pub use gain::{Gain, GainLaw, GainParams};
pub use gms::{Gms, GmsParams};
pub use leaf::{checked_step, Leaf, StepLaw, Stepped};
pub use lugre::{LuGre, LuGreLaw, LuGreParams, LuGreState};
pub use mass_spring_damper::{
    MassSpringDamper, MassSpringDamperLaw, MassSpringDamperParams, MsdState,
};
pub use maxwell_slip::{MaxwellSlip, MaxwellSlipParams};
pub use mms::{Mms, MmsLaw, MmsParams, MmsState};
pub use operator::{
    check_input, check_lengths, check_output, process_by_trials, process_while_by_trials, Operator,
    Trial,
};
pub use params::{FieldInfo, FieldKind, ParamField, ParamSet};
pub use play::{play_step, play_tangent, Play, PlayLaw, PlayParams};
pub use preisach::{Preisach, PreisachMeasure, PreisachParams, PreisachStart};
pub use saturation::{Saturation, SaturationLaw, SaturationParams};
pub use stiffness::StiffnessMap;
pub use stop::{stop_step, Stop, StopLaw, StopParams};
pub use viscous_damper::{ViscousDamper, ViscousDamperLaw, ViscousDamperParams};
