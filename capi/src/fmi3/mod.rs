//! FMI 3.0 co-simulation: the `fmi3*` functions of the FMU binary, and the
//! `modelDescription.xml` that goes with them.
//!
//! `hysteron export-fmu --fmi 3` packs this library as
//! `binaries/x86_64-linux/<id>.so`, the model's spec as
//! `resources/model.json` (read by `fmi3InstantiateCoSimulation` from the
//! resource path it is given), and a description whose variables are
//! those of the FMI 2.0 FMU under the same value references, a vector
//! parameter as one array, plus the independent variable FMI 3.0
//! requires:
//!
//! | value reference | name | causality |
//! |---|---|---|
//! | 0 | `x` | input (continuous Float64, start 0) |
//! | 1 | `y` | output (continuous Float64) |
//! | 2 + i | parameter path `i` (`left.mms.f_c`) | tunable Float64 parameter, start = the spec's value |
//! | 2 + i | a vector parameter's path (`pi_bank.w`), `i` the index of its first element | tunable Float64 array of fixed size (`<Dimension start="n"/>`), start = the spec's values |
//! | 2147483647 | `time` | independent |
//!
//! The instantiation token is the FMI 2.0 GUID of the spec.
//!
//! # Semantics
//! Those of the FMI 2.0 FMU ([`fmi2`](crate::fmi2)), through the FMI 3.0
//! functions: `fmi3EnterInitializationMode` takes the start time,
//! `fmi3DoStep(t, h)` commits the input set last as the sample at `t + h`
//! and never asks for events, terminates or returns early
//! (`lastSuccessfulTime` is `t + h`, or the time before a failed step);
//! parameters set between steps replay the history; FMU states are saved,
//! restored, serialized and deserialized bit for bit (the bytes are those
//! of the FMI 2.0 FMU); `fmi3GetDirectionalDerivative` gives the exact
//! partial derivatives of `y`. `fmi3GetFloat64` of `time` is the last
//! communication point; it cannot be set. The FMU has no Event Mode
//! (`hasEventMode` is false, so `eventModeUsed` is refused);
//! `fmi3EnterStepMode` after initialization is accepted and changes
//! nothing.
//!
//! Every other function of the standard is exported: those of Model
//! Exchange, Scheduled Execution, Event and Configuration Mode, clocks,
//! intervals, adjoint and output derivatives return `fmi3Error` with a
//! message through `logMessage` (Model Exchange and Scheduled Execution
//! instantiation return NULL); getters and setters of the types the FMU
//! has no variables of succeed with no value references and fail with any.
//! No panic crosses the C boundary; instances are independent.
//!
//! An array's values are read and written through its value reference,
//! all at once, in row-major order: `nValues` of `fmi3GetFloat64` and
//! `fmi3SetFloat64` is the sum of the sizes of the variables asked for,
//! and the seed and sensitivity of `fmi3GetDirectionalDerivative` have one
//! value per element of the knowns and unknowns. Any other count, and the
//! value reference of an array's later element or of no variable, is
//! `fmi3Error` with a message. Which parameters become arrays: see
//! `variables`.
//!
//! # Reference
//! Modelica Association, *Functional Mock-up Interface Specification*,
//! version 3.0 (2022).

mod description;
mod exports;
mod types;
mod variables;

pub use description::{model_description, VR_TIME};
