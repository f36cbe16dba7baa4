//! The hysteretic energy of the [`BoucWenDegrading`](crate::BoucWenDegrading)
//! model as an output.

use crate::energy_flow::{energy_output, Energy};
use crate::{BoucWenDegradingParams, Stepped};

energy_output!(
    BoucWenDegradingParams,
    "bouc_wen_degrading_energy",
    "e = ∫ (1 − α) k0 z dx of the bouc_wen_degrading model (its parameters and step; output e instead of F)"
);

/// The hysteretic energy `e = ∫ (1 − α) k0 z dx` of the
/// [`BoucWenDegrading`](crate::BoucWenDegrading) model, driven by the same
/// displacement, with the same parameters and the same step: OpenSees'
/// second output of `uniaxialMaterial BoucWen`. Over a closed loop its
/// growth is the energy the loop dissipated; it drives the model's
/// degradation. Tangent `de/dx = (1 − α) k0 z`.
///
/// ```
/// use hysteron_operators::{BoucWenDegradingEnergy, Energy, Operator};
/// let mut e = BoucWenDegradingEnergy::<f64>::from_params(Energy(Default::default())).unwrap();
/// let x: Vec<f64> = (0..=200).map(|i| 2.0 * (i as f64 * std::f64::consts::TAU / 100.0).sin()).collect();
/// let y = e.run(&x).unwrap();
/// assert!(y[200] > y[100] && y[100] > 0.0); // it grows over each closed cycle
/// ```
pub type BoucWenDegradingEnergy<T> = Stepped<Energy<BoucWenDegradingParams<T>>, T>;
