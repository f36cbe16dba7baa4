//! The `fmi2*` functions of the FMU binary. Each checks its pointers,
//! runs under a panic guard, and reports an error through the logger with
//! `fmi2Error`; the instance stays usable (its state is that before the
//! failed call).
#![allow(non_snake_case)]

use super::types::*;
use crate::fmu::component::{self, Outcome};
use crate::fmu::description::LOG_CATEGORY;
use crate::fmu::instance::{Instance, Mode};
use crate::fmu::pointers::{self, text};
use crate::fmu::states;
use std::ffi::{c_char, CString};

/// What an FMI 2.0 instance keeps of its host: its name and callbacks.
struct Host {
    name: CString,
    callbacks: fmi2CallbackFunctions,
}

impl component::Host for Host {
    fn log(&self, outcome: Outcome, message: &str) {
        let Some(logger) = self.callbacks.logger else {
            return;
        };
        // The message is the format string (`%` doubled, no arguments): hosts
        // that format it printf-style and hosts that show it as it is (FMPy)
        // both read it.
        let text = component::c_string(&message.replace('%', "%%"));
        // SAFETY: the host's logger, with NUL-terminated strings and a format
        // that consumes no arguments.
        unsafe {
            logger(
                self.callbacks.componentEnvironment,
                self.name.as_ptr(),
                outcome.code(),
                LOG_CATEGORY.as_ptr(),
                text.as_ptr(),
            );
        }
    }
}

/// An FMI 2.0 component: what an `fmi2Component` points to.
type Component = component::Component<Host>;

/// Runs `body` on the component `c` under the guard of [`component::with`].
fn with(c: fmi2Component, body: impl FnOnce(&mut Component) -> Result<(), String>) -> fmi2Status {
    component::with(c, body).code()
}

/// What the pointers of a value-reference call are called in messages.
const VR_AND_VALUE: &str = "vr or value";

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
    let name = component::c_string(&name);
    component::instantiate(Host { name, callbacks }, || {
        if fmuType != FMI2_CO_SIMULATION {
            return Err(
                "only Co-Simulation is supported (fmuType must be fmi2CoSimulation)".into(),
            );
        }
        let guid = unsafe { text(fmuGUID) }.ok_or("fmuGUID: NULL")?;
        let resources = unsafe { text(fmuResourceLocation) }.ok_or("fmuResourceLocation: NULL")?;
        Instance::from_resources(&resources, &guid)
    })
}

/// # Safety
/// `c` is NULL or a component from `fmi2Instantiate`, not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    // SAFETY: by the contract.
    unsafe { component::free::<Host>(c) }
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
        let vrs = unsafe { pointers::references(vr, nvr, value.cast_const(), nvr, VR_AND_VALUE) }?;
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
        let (vrs, values) = unsafe { pointers::slices(vr, nvr, value, nvr, VR_AND_VALUE) }?;
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
/// `state` is NULL or points to NULL or to a state from this function or
/// `fmi2DeSerializeFMUstate`.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(c: fmi2Component, state: *mut fmi2FMUstate) -> fmi2Status {
    // SAFETY: by the contract.
    with(c, |comp| unsafe { states::save(&comp.inst, state) })
}

/// # Safety
/// `state` is NULL or a state from `fmi2GetFMUstate`.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, state: fmi2FMUstate) -> fmi2Status {
    // SAFETY: by the contract.
    with(c, |comp| unsafe { states::restore(&mut comp.inst, state) })
}

/// # Safety
/// `state` is NULL or points to NULL or to a state from `fmi2GetFMUstate`.
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(
    c: fmi2Component,
    state: *mut fmi2FMUstate,
) -> fmi2Status {
    with(c, |_| {
        // SAFETY: by the contract.
        unsafe { states::free(state) };
        Ok(())
    })
}

/// Refuses a call the FMU does not support.
fn unsupported(c: fmi2Component, what: &str) -> fmi2Status {
    with(c, |_| Err(format!("{what} is not supported by this FMU")))
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
    // SAFETY: by the contract.
    with(c, |comp| unsafe {
        states::serialized_size(&comp.inst, state, size)
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
    // SAFETY: by the contract.
    with(c, |comp| unsafe {
        states::serialize_into(&comp.inst, state, bytes.cast(), size)
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
    // SAFETY: by the contract.
    with(c, |comp| unsafe {
        states::deserialize_from(&comp.inst, bytes.cast(), size, state)
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
        let unknowns = unsafe {
            pointers::references(
                unknown,
                nUnknown,
                dvUnknown.cast_const(),
                nUnknown,
                VR_AND_VALUE,
            )
        }?;
        let (knowns, dv_known) =
            unsafe { pointers::slices(known, nKnown, dvKnown, nKnown, VR_AND_VALUE) }?;
        let dv = comp
            .inst
            .directional_derivative(unknowns, knowns, dv_known)?;
        // SAFETY: `dvUnknown` is valid for nUnknown = dv.len() doubles
        // (checked non-NULL).
        unsafe { pointers::write(dvUnknown, &dv) };
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
