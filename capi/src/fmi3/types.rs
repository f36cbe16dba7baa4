//! The C types of the FMI 3.0 API (`fmi3PlatformTypes.h`,
//! `fmi3FunctionTypes.h`), as the standard's headers declare them.
#![allow(non_camel_case_types, non_snake_case)]

use std::ffi::{c_char, c_int, c_uint, c_void};

pub type fmi3Instance = *mut c_void;
pub type fmi3InstanceEnvironment = *mut c_void;
pub type fmi3FMUState = *mut c_void;
pub type fmi3ValueReference = c_uint;
pub type fmi3Float32 = f32;
pub type fmi3Float64 = f64;
pub type fmi3Int8 = i8;
pub type fmi3UInt8 = u8;
pub type fmi3Int16 = i16;
pub type fmi3UInt16 = u16;
pub type fmi3Int32 = i32;
pub type fmi3UInt32 = u32;
pub type fmi3Int64 = i64;
pub type fmi3UInt64 = u64;
/// `fmi3Boolean` is C's `bool`.
pub type fmi3Boolean = bool;
pub type fmi3Char = c_char;
pub type fmi3String = *const fmi3Char;
pub type fmi3Byte = u8;
pub type fmi3Binary = *const fmi3Byte;
pub type fmi3Clock = bool;

/// `fmi3Status`, returned as a C `int`: the codes of
/// [`Outcome`](crate::fmu::component::Outcome).
pub type fmi3Status = c_int;

/// `fmi3DependencyKind` and `fmi3IntervalQualifier`, C enums: taken as
/// `int` (a value the FMU does not know must not be UB).
pub type fmi3DependencyKind = c_int;
pub type fmi3IntervalQualifier = c_int;

/// `fmi3LogMessageCallback`: the message is plain text (no format).
pub type fmi3LogMessageCallback =
    unsafe extern "C" fn(fmi3InstanceEnvironment, fmi3Status, fmi3String, fmi3String);

/// `fmi3IntermediateUpdateCallback` (never called: the FMU provides no
/// intermediate updates).
pub type fmi3IntermediateUpdateCallback = unsafe extern "C" fn(
    fmi3InstanceEnvironment,
    fmi3Float64,
    fmi3Boolean,
    fmi3Boolean,
    fmi3Boolean,
    fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Float64,
);

/// `fmi3ClockUpdateCallback` (Scheduled Execution, not supported).
pub type fmi3ClockUpdateCallback = unsafe extern "C" fn(fmi3InstanceEnvironment);

/// `fmi3LockPreemptionCallback` and `fmi3UnlockPreemptionCallback`
/// (Scheduled Execution, not supported).
pub type fmi3PreemptionCallback = unsafe extern "C" fn();
