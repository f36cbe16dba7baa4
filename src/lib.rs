//! # hysteron
//!
//! Hysteresis operators and their algebra, in Rust. This facade re-exports
//! the workspace crates:
//!
//! * [`operators`]: the [`Operator`] trait, errors and
//!   the elementary operators (play, stop, elastoplastic, dead-zone,
//!   saturation, gain, Modified Maxwell-slip friction, Bouc-Wen spring,
//!   Preisach model);
//! * [`composition`]: combinators (cascade, parallel, scaled, PI bank,
//!   feedback, mechanical series, inverse) and their solver;
//! * [`models`]: composed models;
//! * [`identify`]: parameter identification (Levenberg-Marquardt).
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

pub use hysteron_composition as composition;
pub use hysteron_identify as identify;
pub use hysteron_models as models;
pub use hysteron_operators as operators;

pub use hysteron_operators::{Error, Float, Operator, Result, Trial};

/// Everything needed to build and run models.
pub mod prelude {
    pub use hysteron_composition::{
        Cascade, Feedback, Inverse, MechanicalSeries, OperatorExt, Oversample, Parallel, PiBank,
        PiInverse, Scaled, SolverOptions, TravelLimits,
    };
    pub use hysteron_operators::{
        BoucWen, BoucWenParams, Dahl, DahlParams, DeadZone, ElastoPlastic, Error, Float, Gain, Gms,
        GmsParams, LuGre, LuGreParams, MassSpringDamper, MaxwellSlip, MaxwellSlipParams, Mms,
        MmsParams, Operator, Play, PlayParams, Preisach, PreisachMeasure, PreisachParams,
        PreisachStart, Result, Saturation, StateSolver, StiffnessMap, Stop, Trial, ViscousDamper,
    };
}

/// The README's API tour, compiled and run as a doctest.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
