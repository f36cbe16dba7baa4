//! The hysteretic energy of the [`Bwbn`](crate::Bwbn) model as an output.

use crate::energy_flow::{energy_output, Energy};
use crate::{BwbnParams, Stepped};

energy_output!(
    BwbnParams,
    "bwbn_energy",
    "e = ∫ (1 − α) k0 z dx of the bwbn model (its parameters and step; output e instead of F)"
);

/// The hysteretic energy `e = ∫ (1 − α) k0 z dx` of the
/// [`Bwbn`](crate::Bwbn) model, driven by the same displacement, with the
/// same parameters and the same step: OpenSees' second output of
/// `uniaxialMaterial BWBN`. Over a closed loop its growth is the energy
/// the loop dissipated; it drives the model's pinching. Tangent
/// `de/dx = (1 − α) k0 z`.
///
/// ```
/// use hysteron_operators::{Bwbn, BwbnEnergy, BwbnParams, Energy, Operator, ParamSet};
/// let p = BwbnParams::<f64>::example();
/// let x: Vec<f64> = (0..400).map(|i| 3.0 * (i as f64 * 0.05).sin()).collect();
/// let mut force = Bwbn::from_params(p).unwrap();
/// force.run(&x).unwrap();
/// let e = BwbnEnergy::from_params(Energy(p)).unwrap().run(&x).unwrap();
/// assert_eq!(e[399], force.state().e);
/// ```
pub type BwbnEnergy<T> = Stepped<Energy<BwbnParams<T>>, T>;
