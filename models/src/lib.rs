//! # hysteron-models
//!
//! Composed models built from `hysteron-operators` and
//! `hysteron-composition`:
//!
//! * [`transmission`]: the structural hysteresis model of Ruderman &
//!   Bertram (2015), a damped bedstop (MMS friction slider in a backlash
//!   gap) in mechanical series with a Bouc-Wen-like spring, composed from
//!   the algebra, with any friction element or spring swappable;
//! * [`experiments`]: the excitation signals of the paper and a simulation
//!   loop that records the internal states;
//! * [`benchmark`]: the Bouc-Wen hysteretic benchmark of Noël & Schoukens
//!   (2016), a mass-spring-damper in feedback with a Bouc-Wen spring;
//! * [`describing`]: the describing function (first-harmonic gain) of any
//!   operator driven by a sine, in steady state;
//! * [`energy`]: the work per closed loop `∮ y dx` of the same steady
//!   cycle, and closed forms (PI bank, Bouc-Wen with `n = 1`);
//! * [`signal`]: band-limited upsampling (FFT for periodic records,
//!   polyphase for records from rest) and MATLAB's FIR decimation after a
//!   chosen stage plan.

#![warn(missing_docs)]
// The library promises never to panic on user input: no unwrap/expect/panic
// and no unchecked indexing outside tests (the lints are in the workspace
// Cargo.toml; each exception is an `allow` with the invariant that makes it safe).

pub mod benchmark;
pub mod describing;
pub mod energy;
pub mod experiments;
pub mod sensitivity;
pub mod signal;
pub mod spec;
mod transmission;

pub use hysteron_composition as composition;
pub use hysteron_operators as operators;
pub use spec::{Spec, SpecError};
pub use transmission::{
    paper_state, transmission, PaperModel, Transmission, TransmissionParams, TransmissionState,
};
