//! The C types of the FMI 2.0 API (`fmi2TypesPlatform.h`,
//! `fmi2FunctionTypes.h`), as the standard's headers declare them.
#![allow(non_camel_case_types, non_snake_case)]

use std::ffi::{c_char, c_int, c_uint, c_void};

pub type fmi2Component = *mut c_void;
pub type fmi2ComponentEnvironment = *mut c_void;
pub type fmi2FMUstate = *mut c_void;
pub type fmi2ValueReference = c_uint;
pub type fmi2Real = f64;
pub type fmi2Integer = c_int;
pub type fmi2Boolean = c_int;
pub type fmi2String = *const c_char;
pub type fmi2Byte = c_char;

/// `fmi2Status`, passed as a C `int` (as `fmi2Type` and
/// `fmi2StatusKind`: a value the FMU does not know must not be UB); the
/// FMU's are the codes of [`Outcome`](crate::fmu::component::Outcome).
pub type fmi2Status = c_int;

/// `fmi2Type`: only co-simulation is supported.
pub const FMI2_CO_SIMULATION: c_int = 1;

/// `fmi2StatusKind`.
pub type fmi2StatusKind = c_int;
pub const FMI2_LAST_SUCCESSFUL_TIME: fmi2StatusKind = 2;
pub const FMI2_TERMINATED: fmi2StatusKind = 3;

/// `fmi2CallbackLogger`: `printf`-style, so the message goes through `"%s"`.
pub type fmi2CallbackLogger = unsafe extern "C" fn(
    fmi2ComponentEnvironment,
    fmi2String,
    fmi2Status,
    fmi2String,
    fmi2String,
    ...
);

/// `fmi2CallbackFunctions`.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct fmi2CallbackFunctions {
    pub logger: Option<fmi2CallbackLogger>,
    pub allocateMemory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    pub freeMemory: Option<unsafe extern "C" fn(*mut c_void)>,
    pub stepFinished: Option<unsafe extern "C" fn(fmi2ComponentEnvironment, fmi2Status)>,
    pub componentEnvironment: fmi2ComponentEnvironment,
}
