//! The `fmi2*` functions of the FMU binary. Each checks its pointers,
//! runs under a panic guard, and reports an error through the logger with
//! `fmi2Error`; the instance stays usable (its state is that before the
//! failed call).
#![allow(non_snake_case)]

use super::types::*;
use crate::fmu::instance::{Instance, Mode, Snapshot};
use crate::fmu::serial::{deserialize, serialize};
use crate::status::panic_text;
use std::ffi::{c_char, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// An instance with the host's callbacks.
struct Component {
    name: CString,
    callbacks: fmi2CallbackFunctions,
    inst: Instance,
}

impl Component {
    fn log(&self, status: fmi2Status, message: &str) {
        log_to(&self.callbacks, &self.name, status, message);
    }
}

fn log_to(callbacks: &fmi2CallbackFunctions, name: &CStr, status: fmi2Status, message: &str) {
    let Some(logger) = callbacks.logger else {
        return;
    };
    // The message is the format string (`%` doubled, no arguments): hosts
    // that format it printf-style and hosts that show it as it is (FMPy)
    // both read it.
    let text = CString::new(message.replace('\0', " ").replace('%', "%%")).unwrap_or_default();
    // SAFETY: the host's logger, with NUL-terminated strings and a format
    // that consumes no arguments.
    unsafe {
        logger(
            callbacks.componentEnvironment,
            name.as_ptr(),
            status,
            c"logStatusError".as_ptr(),
            text.as_ptr(),
        );
    }
}

/// Runs `body` on the component `c`: NULL is `fmi2Error`, an `Err` is
/// logged and `fmi2Error`, a panic is logged and `fmi2Fatal`.
fn with(c: fmi2Component, body: impl FnOnce(&mut Component) -> Result<(), String>) -> fmi2Status {
    // SAFETY: `c` is NULL or a component from fmi2Instantiate, used by one
    // thread at a time (FMI 2.0 §2.1.3).
    let Some(comp) = (unsafe { (c as *mut Component).as_mut() }) else {
        return FMI2_ERROR;
    };
    match catch_unwind(AssertUnwindSafe(|| body(comp))) {
        Ok(Ok(())) => FMI2_OK,
        Ok(Err(message)) => {
            comp.log(FMI2_ERROR, &message);
            FMI2_ERROR
        }
        Err(payload) => {
            comp.log(
                FMI2_FATAL,
                &format!(
                    "internal error (a bug in hysteron): {}",
                    panic_text(&payload)
                ),
            );
            FMI2_FATAL
        }
    }
}

/// `*ptr` as text, for messages and names.
///
/// # Safety
/// `ptr` is NULL or NUL-terminated.
unsafe fn text(ptr: fmi2String) -> Option<String> {
    if ptr.is_null() {
        return None;
    }
    Some(
        unsafe { CStr::from_ptr(ptr) }
            .to_string_lossy()
            .into_owned(),
    )
}

/// `(vr, n)` as a slice (empty for `n = 0`), with `values` checked
/// non-NULL for `n > 0` but not read (an array to be written may be
/// uninitialized).
///
/// # Safety
/// For `n > 0`, `vr` is NULL or valid for `n` elements.
unsafe fn references<'a, T>(
    vr: *const fmi2ValueReference,
    values: *const T,
    n: usize,
) -> Result<&'a [u32], String> {
    if n == 0 {
        return Ok(&[]);
    }
    if vr.is_null() || values.is_null() {
        return Err("vr or value: NULL".into());
    }
    // SAFETY: non-NULL and valid for n elements by the contract.
    Ok(unsafe { std::slice::from_raw_parts(vr, n) })
}

/// `(vr, n)` and `(value, n)` as slices (empty for `n = 0`).
///
/// # Safety
/// For `n > 0` the pointers are NULL or valid for `n` initialized
/// elements.
unsafe fn slices<'a, T>(
    vr: *const fmi2ValueReference,
    values: *const T,
    n: usize,
) -> Result<(&'a [u32], &'a [T]), String> {
    // SAFETY: by the contract.
    let vrs = unsafe { references(vr, values, n) }?;
    if vrs.is_empty() {
        return Ok((&[], &[]));
    }
    // SAFETY: `values` is non-NULL (checked) and valid for n initialized
    // elements by the contract.
    Ok((vrs, unsafe { std::slice::from_raw_parts(values, n) }))
}

#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}

#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}

/// # Safety
/// Pointers as FMI 2.0 specifies for `fmi2Instantiate`.
#[no_mangle]
pub unsafe extern "C" fn fmi2Instantiate(
    instanceName: fmi2String,
    fmuType: std::ffi::c_int,
    fmuGUID: fmi2String,
    fmuResourceLocation: fmi2String,
    functions: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    _loggingOn: fmi2Boolean,
) -> fmi2Component {
    let Some(callbacks) = (unsafe { functions.as_ref() }).copied() else {
        return std::ptr::null_mut();
    };
    let name = unsafe { text(instanceName) }.unwrap_or_else(|| "hysteron".into());
    let c_name = CString::new(name.replace('\0', " ")).unwrap_or_default();
    let made = catch_unwind(AssertUnwindSafe(|| -> Result<Instance, String> {
        if fmuType != FMI2_CO_SIMULATION {
            return Err(
                "only Co-Simulation is supported (fmuType must be fmi2CoSimulation)".into(),
            );
        }
        let guid = unsafe { text(fmuGUID) }.ok_or("fmuGUID: NULL")?;
        let resources = unsafe { text(fmuResourceLocation) }.ok_or("fmuResourceLocation: NULL")?;
        Instance::from_resources(&resources, &guid)
    }));
    match made {
        Ok(Ok(inst)) => Box::into_raw(Box::new(Component {
            name: c_name,
            callbacks,
            inst,
        })) as fmi2Component,
        Ok(Err(message)) => {
            log_to(&callbacks, &c_name, FMI2_ERROR, &message);
            std::ptr::null_mut()
        }
        Err(payload) => {
            log_to(&callbacks, &c_name, FMI2_FATAL, &panic_text(&payload));
            std::ptr::null_mut()
        }
    }
}

/// # Safety
/// `c` is NULL or a component from `fmi2Instantiate`, not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    if !c.is_null() {
        // SAFETY: made by Box::into_raw in fmi2Instantiate, freed once.
        drop(unsafe { Box::from_raw(c as *mut Component) });
    }
}

#[no_mangle]
pub extern "C" fn fmi2SetDebugLogging(
    c: fmi2Component,
    _loggingOn: fmi2Boolean,
    _nCategories: usize,
    _categories: *const fmi2String,
) -> fmi2Status {
    // Errors are always logged; there is nothing else to log.
    with(c, |_| Ok(()))
}

#[no_mangle]
pub extern "C" fn fmi2SetupExperiment(
    c: fmi2Component,
    _toleranceDefined: fmi2Boolean,
    _tolerance: fmi2Real,
    startTime: fmi2Real,
    _stopTimeDefined: fmi2Boolean,
    _stopTime: fmi2Real,
) -> fmi2Status {
    with(c, |comp| comp.inst.setup(startTime))
}

#[no_mangle]
pub extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
    with(c, |comp| comp.inst.enter_initialization())
}

#[no_mangle]
pub extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
    with(c, |comp| comp.inst.exit_initialization())
}

#[no_mangle]
pub extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
    with(c, |comp| {
        comp.inst.terminate();
        Ok(())
    })
}

#[no_mangle]
pub extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
    with(c, |comp| {
        comp.inst.reset();
        Ok(())
    })
}

/// # Safety
/// `vr` and `value` are NULL or valid for `nvr` elements.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Real,
) -> fmi2Status {
    with(c, |comp| {
        // SAFETY: by the contract; `value` is only written.
        let vrs = unsafe { references(vr, value.cast_const(), nvr) }?;
        for (k, &r) in vrs.iter().enumerate() {
            // SAFETY: `value` is valid for nvr doubles (checked non-NULL).
            unsafe { *value.add(k) = comp.inst.get_real(r)? };
        }
        Ok(())
    })
}

/// # Safety
/// `vr` and `value` are NULL or valid for `nvr` elements.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Real,
) -> fmi2Status {
    with(c, |comp| {
        let (vrs, values) = unsafe { slices(vr, value, nvr) }?;
        comp.inst.set_real(vrs, values)
    })
}

/// Refuses a call on variables of a type the FMU does not have.
fn no_variables(c: fmi2Component, nvr: usize, what: &str) -> fmi2Status {
    with(c, |_| {
        if nvr == 0 {
            Ok(())
        } else {
            Err(format!("the FMU has no {what} variables"))
        }
    })
}

#[no_mangle]
pub extern "C" fn fmi2GetInteger(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    nvr: usize,
    _value: *mut fmi2Integer,
) -> fmi2Status {
    no_variables(c, nvr, "Integer")
}

#[no_mangle]
pub extern "C" fn fmi2SetInteger(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    nvr: usize,
    _value: *const fmi2Integer,
) -> fmi2Status {
    no_variables(c, nvr, "Integer")
}

#[no_mangle]
pub extern "C" fn fmi2GetBoolean(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    nvr: usize,
    _value: *mut fmi2Boolean,
) -> fmi2Status {
    no_variables(c, nvr, "Boolean")
}

#[no_mangle]
pub extern "C" fn fmi2SetBoolean(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    nvr: usize,
    _value: *const fmi2Boolean,
) -> fmi2Status {
    no_variables(c, nvr, "Boolean")
}

#[no_mangle]
pub extern "C" fn fmi2GetString(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    nvr: usize,
    _value: *mut fmi2String,
) -> fmi2Status {
    no_variables(c, nvr, "String")
}

#[no_mangle]
pub extern "C" fn fmi2SetString(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    nvr: usize,
    _value: *const fmi2String,
) -> fmi2Status {
    no_variables(c, nvr, "String")
}

/// # Safety
/// `state` is NULL or points to NULL or to a state from this function.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(c: fmi2Component, state: *mut fmi2FMUstate) -> fmi2Status {
    with(c, |comp| {
        // SAFETY: by the contract.
        let slot = unsafe { state.as_mut() }.ok_or("FMUstate: NULL")?;
        let snap = comp.inst.snapshot();
        match unsafe { (*slot as *mut Snapshot).as_mut() } {
            Some(old) => *old = snap,
            None => *slot = Box::into_raw(Box::new(snap)) as fmi2FMUstate,
        }
        Ok(())
    })
}

/// # Safety
/// `state` is NULL or a state from `fmi2GetFMUstate`.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, state: fmi2FMUstate) -> fmi2Status {
    with(c, |comp| {
        // SAFETY: by the contract.
        let snap = unsafe { (state as *const Snapshot).as_ref() }.ok_or("FMUstate: NULL")?;
        comp.inst.restore(snap);
        Ok(())
    })
}

/// # Safety
/// `state` is NULL or points to NULL or to a state from `fmi2GetFMUstate`.
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(
    c: fmi2Component,
    state: *mut fmi2FMUstate,
) -> fmi2Status {
    with(c, |_| {
        if let Some(slot) = unsafe { state.as_mut() } {
            if !slot.is_null() {
                // SAFETY: made by Box::into_raw in fmi2GetFMUstate, freed once.
                drop(unsafe { Box::from_raw(*slot as *mut Snapshot) });
                *slot = std::ptr::null_mut();
            }
        }
        Ok(())
    })
}

/// Refuses a call the FMU does not support.
fn unsupported(c: fmi2Component, what: &str) -> fmi2Status {
    with(c, |_| Err(format!("{what} is not supported by this FMU")))
}

/// The bytes of `state` ([`serial`](crate::fmu::serial)).
///
/// # Safety
/// `state` is NULL or a state from `fmi2GetFMUstate` or
/// `fmi2DeSerializeFMUstate`.
unsafe fn state_bytes(comp: &Component, state: fmi2FMUstate) -> Result<Vec<u8>, String> {
    // SAFETY: by the contract.
    let snap = unsafe { (state as *const Snapshot).as_ref() }.ok_or("FMUstate: NULL")?;
    serialize(comp.inst.start(), snap)
}

/// # Safety
/// `state` is NULL or a state of this instance; `size` is NULL or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    state: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    with(c, |comp| {
        let bytes = unsafe { state_bytes(comp, state) }?;
        // SAFETY: by the contract.
        *unsafe { size.as_mut() }.ok_or("size: NULL")? = bytes.len();
        Ok(())
    })
}

/// # Safety
/// `state` is NULL or a state of this instance; `bytes` is NULL or
/// writable for `size` bytes.
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    state: fmi2FMUstate,
    bytes: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    with(c, |comp| {
        let data = unsafe { state_bytes(comp, state) }?;
        if bytes.is_null() {
            return Err("serializedState: NULL".into());
        }
        if size != data.len() {
            return Err(format!(
                "size is {size}, but the state is {} bytes (fmi2SerializedFMUstateSize)",
                data.len()
            ));
        }
        // SAFETY: `bytes` is writable for `size` = data.len() bytes.
        unsafe { std::ptr::copy_nonoverlapping(data.as_ptr(), bytes.cast::<u8>(), size) };
        Ok(())
    })
}

/// # Safety
/// `bytes` is NULL or valid for `size` bytes; `state` is NULL or points to
/// NULL or to a state of this instance.
#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: fmi2Component,
    bytes: *const fmi2Byte,
    size: usize,
    state: *mut fmi2FMUstate,
) -> fmi2Status {
    with(c, |comp| {
        // SAFETY: by the contract.
        let slot = unsafe { state.as_mut() }.ok_or("FMUstate: NULL")?;
        let data: &[u8] = match size {
            0 => &[],
            _ if bytes.is_null() => return Err("serializedState: NULL".into()),
            // SAFETY: valid for `size` bytes by the contract.
            _ => unsafe { std::slice::from_raw_parts(bytes.cast::<u8>(), size) },
        };
        let snap = deserialize(comp.inst.start(), data)?;
        match unsafe { (*slot as *mut Snapshot).as_mut() } {
            Some(old) => *old = snap,
            None => *slot = Box::into_raw(Box::new(snap)) as fmi2FMUstate,
        }
        Ok(())
    })
}

/// # Safety
/// `unknown` and `dvUnknown` are NULL or valid for `nUnknown` elements,
/// `known` and `dvKnown` for `nKnown`.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: fmi2Component,
    unknown: *const fmi2ValueReference,
    nUnknown: usize,
    known: *const fmi2ValueReference,
    nKnown: usize,
    dvKnown: *const fmi2Real,
    dvUnknown: *mut fmi2Real,
) -> fmi2Status {
    with(c, |comp| {
        // SAFETY: by the contract; `dvUnknown` is only written.
        let unknowns = unsafe { references(unknown, dvUnknown.cast_const(), nUnknown) }?;
        let (knowns, dv_known) = unsafe { slices(known, dvKnown, nKnown) }?;
        let dv = comp
            .inst
            .directional_derivative(unknowns, knowns, dv_known)?;
        for (k, v) in dv.into_iter().enumerate() {
            // SAFETY: `dvUnknown` is valid for nUnknown doubles (checked
            // non-NULL).
            unsafe { *dvUnknown.add(k) = v };
        }
        Ok(())
    })
}

#[no_mangle]
pub extern "C" fn fmi2SetRealInputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _nvr: usize,
    _order: *const fmi2Integer,
    _value: *const fmi2Real,
) -> fmi2Status {
    unsupported(c, "input derivatives (canInterpolateInputs is false)")
}

#[no_mangle]
pub extern "C" fn fmi2GetRealOutputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _nvr: usize,
    _order: *const fmi2Integer,
    _value: *mut fmi2Real,
) -> fmi2Status {
    unsupported(c, "output derivatives (maxOutputDerivativeOrder is 0)")
}

#[no_mangle]
pub extern "C" fn fmi2DoStep(
    c: fmi2Component,
    currentCommunicationPoint: fmi2Real,
    communicationStepSize: fmi2Real,
    _noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
) -> fmi2Status {
    with(c, |comp| {
        comp.inst
            .do_step(currentCommunicationPoint, communicationStepSize)
    })
}

#[no_mangle]
pub extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
    unsupported(c, "fmi2CancelStep (steps are never asynchronous)")
}

#[no_mangle]
pub extern "C" fn fmi2GetStatus(
    c: fmi2Component,
    _kind: fmi2StatusKind,
    _value: *mut fmi2Status,
) -> fmi2Status {
    unsupported(c, "fmi2GetStatus (steps are never asynchronous)")
}

/// Writes `read(instance)` to `*value` for the one status `kind` that has
/// a value of this type.
///
/// # Safety
/// `value` is NULL or writable.
unsafe fn status_value<V>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    (wanted, function): (fmi2StatusKind, &str),
    value: *mut V,
    read: impl FnOnce(&Instance) -> V,
) -> fmi2Status {
    with(c, |comp| {
        if kind != wanted {
            return Err(format!(
                "{function}: status kind {kind} has no value of this type"
            ));
        }
        let slot = unsafe { value.as_mut() }.ok_or("value: NULL")?;
        *slot = read(&comp.inst);
        Ok(())
    })
}

/// # Safety
/// `value` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2Real,
) -> fmi2Status {
    let wanted = (FMI2_LAST_SUCCESSFUL_TIME, "fmi2GetRealStatus");
    unsafe { status_value(c, kind, wanted, value, |inst| inst.time()) }
}

#[no_mangle]
pub extern "C" fn fmi2GetIntegerStatus(
    c: fmi2Component,
    _kind: fmi2StatusKind,
    _value: *mut fmi2Integer,
) -> fmi2Status {
    unsupported(c, "fmi2GetIntegerStatus")
}

/// # Safety
/// `value` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    let wanted = (FMI2_TERMINATED, "fmi2GetBooleanStatus");
    unsafe {
        status_value(c, kind, wanted, value, |inst| {
            fmi2Boolean::from(inst.mode() == Mode::Terminated)
        })
    }
}

#[no_mangle]
pub extern "C" fn fmi2GetStringStatus(
    c: fmi2Component,
    _kind: fmi2StatusKind,
    _value: *mut fmi2String,
) -> fmi2Status {
    unsupported(c, "fmi2GetStringStatus")
}
