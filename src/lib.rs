//! # hysteron
//!
//! Hysteresis operators and their algebra, in Rust. This facade re-exports
//! the workspace crates:
//!
//! * [`operators`]: the [`Operator`] trait, errors and the elementary
//!   operators;
//! * [`composition`]: the combinators and their solver;
//! * [`models`]: model specs ([`Spec`](models::Spec): a model as JSON,
//!   built into an operator), the paper's transmission model, describing
//!   functions and loop energy, exact sensitivities;
//! * [`identify`]: parameter identification (Levenberg-Marquardt with
//!   exact Jacobians from forward-mode derivatives, multi-start,
//!   validation metrics) and the paper's two-stage identification.
//!
//! What a spec can name, by its `type` (`hysteron operators` lists each
//! with its equation and parameters):
//!
//! <!-- BEGIN generated: spec types (scripts/generate.sh) -->
//! * Leaves: [`play`](operators::Play), [`stop`](operators::Stop),
//!   [`elastoplastic`](operators::ElastoPlastic),
//!   [`dead_zone`](operators::DeadZone),
//!   [`saturation`](operators::Saturation), [`gain`](operators::Gain),
//!   [`mms`](operators::Mms), [`bouc_wen`](operators::BoucWen),
//!   [`preisach`](operators::Preisach),
//!   [`mass_spring_damper`](operators::MassSpringDamper),
//!   [`viscous_damper`](operators::ViscousDamper),
//!   [`maxwell_slip`](operators::MaxwellSlip), [`dahl`](operators::Dahl),
//!   [`lugre`](operators::LuGre), [`gms`](operators::Gms),
//!   [`offset`](operators::Offset),
//!   [`asymmetric_friction`](operators::AsymmetricFriction),
//!   [`transient_friction`](operators::TransientFriction),
//!   [`backlash_contact`](operators::BacklashContact),
//!   [`relay`](operators::Relay),
//!   [`bouc_wen_degrading`](operators::BoucWenDegrading),
//!   [`bouc_wen_degrading_energy`](operators::Energy),
//!   [`bwbn`](operators::Bwbn), [`bwbn_energy`](operators::Energy),
//!   [`duhem`](operators::Duhem),
//!   [`jiles_atherton`](operators::JilesAtherton),
//!   [`envelope`](operators::Envelope),
//!   [`envelope_inverse`](operators::EnvelopeInverse),
//!   [`rate_dependent_pi`](operators::RateDependentPi),
//!   [`krasnoselskii_pokrovskii`](operators::KrasnoselskiiPokrovskii),
//!   [`pi_bank`](composition::PiBank),
//!   [`pi_inverse`](composition::PiInverse).
//! * Combinators: `cascade`, `parallel`, `scaled`, `feedback`, `series`,
//!   `inverse`, `oversample`, `transmission`.
//! <!-- END generated: spec types -->
//!
//! ```
//! use hysteron::prelude::*;
//!
//! // Two linear springs in mechanical series: k1 k2 / (k1 + k2).
//! let mut springs = Gain::new(2.0_f64)?.series(Gain::new(3.0)?);
//! assert!((springs.run(&[1.0])?[0] - 1.2).abs() < 1e-14);
//!
//! // Backlash, then friction in series with a Bouc-Wen spring, boxed.
//! let spring = BoucWen::constant(10.0, 0.5, 1.0, 0.6, 0.4, 1.0)?;
//! let mut model = Play::new(0.05)?
//!     .then(Mms::new(2.0, 30.0)?.series(spring))
//!     .boxed();
//! let x: Vec<f64> = (0..200).map(|i| (i as f64 * 0.05).sin()).collect();
//! let f = model.run(&x)?;
//! assert_eq!(f.len(), 200);
//! # Ok::<(), hysteron::Error>(())
//! ```
//!
//! The same kind of model as a spec, as the command line, Python and C
//! read it:
//!
//! ```
//! use hysteron::models::Spec;
//! let spec = Spec::from_json(r#"{"type": "cascade",
//!     "first": {"type": "play", "r": 0.05},
//!     "second": {"type": "series",
//!         "left": {"type": "mms", "f_c": 2, "k": 30},
//!         "right": {"type": "bouc_wen", "w": 0.5, "alpha": 1, "beta": 0.6,
//!                   "gamma": 0.4, "n": 1, "stiffness": 10}}}"#)?;
//! let mut model = spec.build()?;
//! let x: Vec<f64> = (0..200).map(|i| (i as f64 * 0.05).sin()).collect();
//! assert_eq!(model.run(&x)?.len(), 200);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub use hysteron_composition as composition;
pub use hysteron_identify as identify;
pub use hysteron_models as models;
pub use hysteron_operators as operators;

pub use hysteron_operators::{
    Derivatives, Error, Float, Hints, Operator, Parameters, Result, SamplePeriod, Trial,
};

/// Everything needed to build and run models: the operator traits, every
/// leaf operator (from the list that registers them, so a new leaf is here
/// with no edit), the combinators, and the spec.
pub mod prelude {
    pub use hysteron_composition::{
        Cascade, Feedback, Inverse, MechanicalSeries, OperatorExt, Oversample, Parallel, PiBank,
        PiInverse, Scaled, SolverOptions, TravelLimits,
    };
    pub use hysteron_models::Spec;
    pub use hysteron_operators::{
        BoucWenParams, DahlParams, Derivatives, Error, Float, GmsParams, Hints, LuGreParams,
        MaxwellSlipParams, MmsParams, Operator, Parameters, PlayParams, PreisachMeasure,
        PreisachParams, PreisachStart, Result, SamplePeriod, StateSolver, StiffnessMap, Trial,
    };

    /// Re-exports every leaf type `for_each_leaf!` names.
    macro_rules! every_leaf {
        ($($leaf:ident),*) => {
            pub use hysteron_operators::{$($leaf),*};
        };
    }
    hysteron_operators::for_each_leaf!(every_leaf);
}

/// The README's Rust quickstart, compiled and run as a doctest.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

/// The user guide's chapters that hold Rust, each compiled and run as a
/// doctest (`tests/docs.rs` fails when a chapter with Rust is missing
/// here).
#[cfg(doctest)]
pub mod guide {
    /// `docs/concepts.md`
    #[doc = include_str!("../docs/concepts.md")]
    pub struct Concepts;
    /// `docs/composing.md`
    #[doc = include_str!("../docs/composing.md")]
    pub struct Composing;
    /// `docs/uncertainty.md`
    #[doc = include_str!("../docs/uncertainty.md")]
    pub struct Uncertainty;
}
