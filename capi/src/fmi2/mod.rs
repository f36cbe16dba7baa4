//! FMI 2.0 co-simulation: the `fmi2*` functions of the FMU binary, and the
//! `modelDescription.xml` that goes with them.
//!
//! An FMU made by `hysteron export-fmu` holds this library as
//! `binaries/linux64/<id>.so`, the model's spec as `resources/model.json`
//! (read by `fmi2Instantiate`), and a description whose variables are:
//!
//! | value reference | name | causality |
//! |---|---|---|
//! | 0 | `x` | input (continuous Real, start 0) |
//! | 1 | `y` | output (continuous Real) |
//! | 2 + i | parameter path `i` (`left.mms.f_c`) | tunable parameter, start = the spec's value |
//!
//! # Semantics
//! * `fmi2DoStep(t, h)` takes the input set last as the sample at the end
//!   of the step, `t + h`, and commits one sample: `y = H[x]`. A
//!   rate-dependent model gets `h` as its sample period
//!   (`SamplePeriod::set_sample_period`), which may change from step to step.
//!   Before the first step `y` is the model's initial output (its output
//!   at input 0 from the initial state).
//! * A parameter set between steps rebuilds the model with the new value
//!   and replays the samples committed since the start (inputs and step
//!   sizes), so the outputs go on as those of the spec with that value
//!   would have; the cost grows with the number of steps taken. Tied
//!   parameters (a gap's `r0` and its spring's `z0`) are set together in
//!   one `fmi2SetReal` call.
//! * `fmi2GetFMUstate` takes a snapshot (a clone of the model, its input,
//!   output, time and history); `fmi2SetFMUstate` restores it, and replay
//!   from it is identical. `fmi2SerializeFMUstate` writes a state as bytes
//!   (its parameters and committed samples, 16 bytes per step; see
//!   `fmu::serial`), and `fmi2DeSerializeFMUstate` restores them in any
//!   instance of the same FMU by replaying the samples: bit for bit the
//!   saved instance's continuation. Bytes that are corrupted, truncated or
//!   of another FMU are refused with a logged message.
//! * `fmi2GetDirectionalDerivative` gives the exact partial derivatives
//!   of `y` at the current communication point with respect to the input
//!   of the last step and to every parameter (the total derivative along
//!   the samples committed since the start), from a dual-number replay of
//!   those samples (see `fmu::derivatives`).
//! * `fmi2Reset` returns to the state after instantiation (the start
//!   values). Calls the FMU does not support (Model Exchange, input
//!   derivatives, asynchronous steps, Integer, Boolean or String
//!   variables) return `fmi2Error` with a message through the
//!   logger. No panic crosses the C boundary; instances are independent.
//!
//! # Reference
//! Modelica Association, *Functional Mock-up Interface for Model Exchange
//! and Co-Simulation*, version 2.0.4 (2022).

mod description;
mod exports;
mod types;

pub use crate::fmu::{guid, VR_FIRST_PARAM, VR_X, VR_Y};
pub use description::model_description;
