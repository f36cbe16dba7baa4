//! The `fmi3*` functions of the FMU binary: every function of the FMI 3.0
//! standard. Each checks its pointers, runs under a panic guard, and
//! reports an error through `logMessage` with `fmi3Error`; the instance
//! stays usable (its state is that before the failed call).
#![allow(non_snake_case)]

use super::description::VR_TIME;
use super::types::*;
use super::variables::Variables;
use crate::fmu::component::{self, Host as _, Outcome};
use crate::fmu::description::LOG_CATEGORY;
use crate::fmu::instance::{Instance, Mode};
use crate::fmu::pointers::{self, put, text};
use crate::fmu::{states, Fmi};
use std::borrow::Cow;
use std::cell::OnceCell;
use std::ffi::c_char;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

/// What an FMI 3.0 instance keeps beside its model: the host's logger and
/// the environment to pass it, and the instance's parameter variables.
struct Host {
    environment: fmi3InstanceEnvironment,
    log: Option<fmi3LogMessageCallback>,
    /// Worked out at the first call that needs them.
    variables: OnceCell<Variables>,
}

impl Host {
    fn new(environment: fmi3InstanceEnvironment, log: Option<fmi3LogMessageCallback>) -> Host {
        Host {
            environment,
            log,
            variables: OnceCell::new(),
        }
    }

    /// The parameter variables of `inst`.
    fn variables(&self, inst: &Instance) -> &Variables {
        self.variables.get_or_init(|| {
            let names = inst.start().names().iter();
            Variables::of(&names.map(|n| n.to_string_lossy()).collect::<Vec<_>>())
        })
    }
}

impl component::Host for Host {
    fn log(&self, outcome: Outcome, message: &str) {
        let Some(log) = self.log else {
            return;
        };
        let text = component::c_string(message);
        // SAFETY: the host's logger, with NUL-terminated strings that live
        // through the call (FMI 3.0 messages are plain text, no format).
        unsafe {
            log(
                self.environment,
                outcome.code(),
                LOG_CATEGORY.as_ptr(),
                text.as_ptr(),
            )
        };
    }
}

/// An FMI 3.0 instance: what an `fmi3Instance` points to.
type Component = component::Component<Host>;

/// Runs `body` on `instance` under the guard of [`component::with`].
fn with(
    instance: fmi3Instance,
    body: impl FnOnce(&mut Component) -> Result<(), String>,
) -> fmi3Status {
    component::with(instance, body).code()
}

/// What the pointers of a value-reference call are called in messages.
const VR_AND_VALUES: &str = "valueReferences or values";

/// The flat value references (those of the FMI 2.0 FMU) that the `nvr`
/// variables at `vr` hold, in the order of their values: an array's
/// elements in row-major order. There must be as many as the `n` values
/// at `values` (which are not read: an array to be written may be
/// uninitialized), and neither pointer may be NULL where it has elements.
/// Scalars alone (the input and output a host sets and gets every step)
/// are the host's own array.
///
/// # Safety
/// For `nvr > 0`, `vr` is NULL or valid for `nvr` elements.
unsafe fn flat_references<'a, T>(
    comp: &Component,
    vr: *const fmi3ValueReference,
    nvr: usize,
    values: *const T,
    n: usize,
) -> Result<Cow<'a, [u32]>, String> {
    // SAFETY: by the contract.
    let vrs = unsafe { pointers::references(vr, nvr, values, n, VR_AND_VALUES) }?;
    let variables = comp.host.variables(&comp.inst);
    // Made at the first array: until then each variable is its own
    // element.
    let mut arrays: Option<Vec<u32>> = None;
    for (k, &vr) in vrs.iter().enumerate() {
        let elements = variables.elements(vr)?;
        match &mut arrays {
            Some(flat) => flat.extend(elements),
            None if elements == (vr..vr + 1) => {}
            None => arrays = Some(vrs[..k].iter().copied().chain(elements).collect()),
        }
    }
    let flat = arrays.map_or(Cow::Borrowed(vrs), Cow::Owned);
    if flat.len() != n {
        return Err(format!(
            "{n} values for {nvr} value references holding {}",
            flat.len()
        ));
    }
    Ok(flat)
}

#[no_mangle]
pub extern "C" fn fmi3GetVersion() -> *const c_char {
    c"3.0".as_ptr()
}

#[no_mangle]
pub extern "C" fn fmi3SetDebugLogging(
    instance: fmi3Instance,
    _loggingOn: fmi3Boolean,
    _nCategories: usize,
    _categories: *const fmi3String,
) -> fmi3Status {
    // Errors are always logged; there is nothing else to log.
    with(instance, |_| Ok(()))
}

/// # Safety
/// Pointers as FMI 3.0 specifies for `fmi3InstantiateCoSimulation`.
#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
    _instanceName: fmi3String,
    instantiationToken: fmi3String,
    resourcePath: fmi3String,
    _visible: fmi3Boolean,
    _loggingOn: fmi3Boolean,
    eventModeUsed: fmi3Boolean,
    _earlyReturnAllowed: fmi3Boolean,
    _requiredIntermediateVariables: *const fmi3ValueReference,
    nRequiredIntermediateVariables: usize,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: Option<fmi3LogMessageCallback>,
    _intermediateUpdate: Option<fmi3IntermediateUpdateCallback>,
) -> fmi3Instance {
    component::instantiate(Host::new(instanceEnvironment, logMessage), || {
        if eventModeUsed {
            return Err("eventModeUsed: the FMU has no Event Mode (hasEventMode is false)".into());
        }
        if nRequiredIntermediateVariables != 0 {
            return Err(
                "requiredIntermediateVariables: the FMU provides no intermediate updates".into(),
            );
        }
        // SAFETY: NULL or NUL-terminated by the contract.
        let token = unsafe { text(instantiationToken) }.ok_or("instantiationToken: NULL")?;
        // SAFETY: likewise.
        let resources = unsafe { text(resourcePath) }
            .ok_or("resourcePath: NULL (the FMU's spec is resources/model.json)")?;
        Instance::from_resource_dir(&PathBuf::from(resources), &token, Fmi::V3)
    })
}

/// Refuses an interface the FMU does not implement: NULL, with a message.
fn refuse_instance(
    environment: fmi3InstanceEnvironment,
    log: Option<fmi3LogMessageCallback>,
    what: &str,
) -> fmi3Instance {
    let host = Host::new(environment, log);
    // A panic in the host's logger must not cross back into C.
    let _ = catch_unwind(AssertUnwindSafe(|| {
        host.log(
            Outcome::Error,
            &format!("{what} is not supported by this FMU: it is a Co-Simulation FMU"),
        )
    }));
    std::ptr::null_mut()
}

/// The instantiation functions of the interfaces the FMU does not
/// implement: the arguments the standard gives them all, then each one's
/// own; each returns NULL with a message.
macro_rules! refused_interfaces {
    ($($name:ident($($arg:ident: $t:ty),*) => $what:literal;)*) => {$(
        #[no_mangle]
        pub extern "C" fn $name(
            _instanceName: fmi3String,
            _instantiationToken: fmi3String,
            _resourcePath: fmi3String,
            _visible: fmi3Boolean,
            _loggingOn: fmi3Boolean,
            instanceEnvironment: fmi3InstanceEnvironment,
            logMessage: Option<fmi3LogMessageCallback>,
            $($arg: $t),*
        ) -> fmi3Instance {
            refuse_instance(instanceEnvironment, logMessage, $what)
        }
    )*};
}

refused_interfaces! {
    fmi3InstantiateModelExchange() => "Model Exchange";
    fmi3InstantiateScheduledExecution(
        _clockUpdate: Option<fmi3ClockUpdateCallback>,
        _lockPreemption: Option<fmi3PreemptionCallback>,
        _unlockPreemption: Option<fmi3PreemptionCallback>
    ) => "Scheduled Execution";
}

/// # Safety
/// `instance` is NULL or an instance from `fmi3InstantiateCoSimulation`,
/// not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn fmi3FreeInstance(instance: fmi3Instance) {
    // SAFETY: by the contract.
    unsafe { component::free::<Host>(instance) }
}

#[no_mangle]
pub extern "C" fn fmi3EnterInitializationMode(
    instance: fmi3Instance,
    _toleranceDefined: fmi3Boolean,
    _tolerance: fmi3Float64,
    startTime: fmi3Float64,
    _stopTimeDefined: fmi3Boolean,
    _stopTime: fmi3Float64,
) -> fmi3Status {
    with(instance, |comp| {
        comp.inst.setup(startTime)?;
        comp.inst.enter_initialization()
    })
}

#[no_mangle]
pub extern "C" fn fmi3ExitInitializationMode(instance: fmi3Instance) -> fmi3Status {
    with(instance, |comp| comp.inst.exit_initialization())
}

/// The FMU has no Event Mode: after `fmi3ExitInitializationMode` it is in
/// Step Mode already, and entering it again changes nothing.
#[no_mangle]
pub extern "C" fn fmi3EnterStepMode(instance: fmi3Instance) -> fmi3Status {
    with(instance, |comp| {
        if comp.inst.mode() == Mode::Stepping {
            Ok(())
        } else {
            Err("fmi3EnterStepMode: only after fmi3ExitInitializationMode".into())
        }
    })
}

#[no_mangle]
pub extern "C" fn fmi3Terminate(instance: fmi3Instance) -> fmi3Status {
    with(instance, |comp| {
        comp.inst.terminate();
        Ok(())
    })
}

#[no_mangle]
pub extern "C" fn fmi3Reset(instance: fmi3Instance) -> fmi3Status {
    with(instance, |comp| {
        comp.inst.reset();
        Ok(())
    })
}

/// # Safety
/// `valueReferences` is NULL or valid for `nValueReferences` elements,
/// `values` for `nValues`.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetFloat64(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *mut fmi3Float64,
    nValues: usize,
) -> fmi3Status {
    with(instance, |comp| {
        // SAFETY: by the contract; `values` is only written.
        let flat = unsafe {
            flat_references(
                comp,
                valueReferences,
                nValueReferences,
                values.cast_const(),
                nValues,
            )
        }?;
        let got = flat
            .iter()
            .map(|&vr| match vr {
                VR_TIME => Ok(comp.inst.time()),
                _ => comp.inst.get_real(vr),
            })
            .collect::<Result<Vec<f64>, String>>()?;
        // SAFETY: `values` is valid for nValues = got.len() doubles
        // (checked non-NULL).
        unsafe { pointers::write(values, &got) };
        Ok(())
    })
}

/// # Safety
/// `valueReferences` is NULL or valid for `nValueReferences` elements,
/// `values` for `nValues`.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetFloat64(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *const fmi3Float64,
    nValues: usize,
) -> fmi3Status {
    with(instance, |comp| {
        // SAFETY: by the contract.
        let flat =
            unsafe { flat_references(comp, valueReferences, nValueReferences, values, nValues) }?;
        if flat.contains(&VR_TIME) {
            return Err("time is the independent variable; it cannot be set".into());
        }
        // SAFETY: valid for nValues = flat.len() values (checked non-NULL
        // where there are any) by the contract.
        let values = unsafe { pointers::values(values, nValues) };
        comp.inst.set_real(&flat, values)
    })
}

/// Refuses a call on variables of a type the FMU does not have; with no
/// value references it has nothing to do and succeeds.
fn no_variables(instance: fmi3Instance, nvr: usize, what: &str) -> fmi3Status {
    with(instance, |_| {
        if nvr == 0 {
            Ok(())
        } else {
            Err(format!("the FMU has no {what} variables (all are Float64)"))
        }
    })
}

/// `fmi3Get<T>` and `fmi3Set<T>` for the types the FMU has no variables of.
macro_rules! no_variables_of {
    ($($get:ident, $set:ident, $t:ty, $what:literal;)*) => {$(
        #[no_mangle]
        pub extern "C" fn $get(
            instance: fmi3Instance,
            _valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            _values: *mut $t,
            _nValues: usize,
        ) -> fmi3Status {
            no_variables(instance, nValueReferences, $what)
        }

        #[no_mangle]
        pub extern "C" fn $set(
            instance: fmi3Instance,
            _valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            _values: *const $t,
            _nValues: usize,
        ) -> fmi3Status {
            no_variables(instance, nValueReferences, $what)
        }
    )*};
}

no_variables_of! {
    fmi3GetFloat32, fmi3SetFloat32, fmi3Float32, "Float32";
    fmi3GetInt8, fmi3SetInt8, fmi3Int8, "Int8";
    fmi3GetUInt8, fmi3SetUInt8, fmi3UInt8, "UInt8";
    fmi3GetInt16, fmi3SetInt16, fmi3Int16, "Int16";
    fmi3GetUInt16, fmi3SetUInt16, fmi3UInt16, "UInt16";
    fmi3GetInt32, fmi3SetInt32, fmi3Int32, "Int32";
    fmi3GetUInt32, fmi3SetUInt32, fmi3UInt32, "UInt32";
    fmi3GetInt64, fmi3SetInt64, fmi3Int64, "Int64";
    fmi3GetUInt64, fmi3SetUInt64, fmi3UInt64, "UInt64";
    fmi3GetBoolean, fmi3SetBoolean, fmi3Boolean, "Boolean";
    fmi3GetString, fmi3SetString, fmi3String, "String";
}

#[no_mangle]
pub extern "C" fn fmi3GetBinary(
    instance: fmi3Instance,
    _valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    _valueSizes: *mut usize,
    _values: *mut fmi3Binary,
    _nValues: usize,
) -> fmi3Status {
    no_variables(instance, nValueReferences, "Binary")
}

#[no_mangle]
pub extern "C" fn fmi3SetBinary(
    instance: fmi3Instance,
    _valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    _valueSizes: *const usize,
    _values: *const fmi3Binary,
    _nValues: usize,
) -> fmi3Status {
    no_variables(instance, nValueReferences, "Binary")
}

#[no_mangle]
pub extern "C" fn fmi3GetClock(
    instance: fmi3Instance,
    _valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    _values: *mut fmi3Clock,
) -> fmi3Status {
    no_variables(instance, nValueReferences, "Clock")
}

#[no_mangle]
pub extern "C" fn fmi3SetClock(
    instance: fmi3Instance,
    _valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    _values: *const fmi3Clock,
) -> fmi3Status {
    no_variables(instance, nValueReferences, "Clock")
}

/// # Safety
/// `FMUState` is NULL or points to NULL or to a state from this function
/// or `fmi3DeserializeFMUState`.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    // SAFETY: by the contract.
    with(instance, |comp| unsafe {
        states::save(&comp.inst, FMUState)
    })
}

/// # Safety
/// `FMUState` is NULL or a state from `fmi3GetFMUState` or
/// `fmi3DeserializeFMUState`.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
) -> fmi3Status {
    // SAFETY: by the contract.
    with(instance, |comp| unsafe {
        states::restore(&mut comp.inst, FMUState)
    })
}

/// # Safety
/// `FMUState` is NULL or points to NULL or to a state from
/// `fmi3GetFMUState` or `fmi3DeserializeFMUState`.
#[no_mangle]
pub unsafe extern "C" fn fmi3FreeFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    with(instance, |_| {
        // SAFETY: by the contract.
        unsafe { states::free(FMUState) };
        Ok(())
    })
}

/// # Safety
/// `FMUState` is NULL or a state of this instance; `size` is NULL or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    size: *mut usize,
) -> fmi3Status {
    // SAFETY: by the contract.
    with(instance, |comp| unsafe {
        states::serialized_size(&comp.inst, FMUState, size)
    })
}

/// # Safety
/// `FMUState` is NULL or a state of this instance; `serializedState` is
/// NULL or writable for `size` bytes.
#[no_mangle]
pub unsafe extern "C" fn fmi3SerializeFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    serializedState: *mut fmi3Byte,
    size: usize,
) -> fmi3Status {
    // SAFETY: by the contract.
    with(instance, |comp| unsafe {
        states::serialize_into(&comp.inst, FMUState, serializedState, size)
    })
}

/// # Safety
/// `serializedState` is NULL or valid for `size` bytes; `FMUState` is NULL
/// or points to NULL or to a state of this instance.
#[no_mangle]
pub unsafe extern "C" fn fmi3DeserializeFMUState(
    instance: fmi3Instance,
    serializedState: *const fmi3Byte,
    size: usize,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    // SAFETY: by the contract.
    with(instance, |comp| unsafe {
        states::deserialize_from(&comp.inst, serializedState, size, FMUState)
    })
}

/// # Safety
/// `unknowns` is NULL or valid for `nUnknowns` elements, `knowns` for
/// `nKnowns`, `seed` for `nSeed` and `sensitivity` for `nSensitivity`.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetDirectionalDerivative(
    instance: fmi3Instance,
    unknowns: *const fmi3ValueReference,
    nUnknowns: usize,
    knowns: *const fmi3ValueReference,
    nKnowns: usize,
    seed: *const fmi3Float64,
    nSeed: usize,
    sensitivity: *mut fmi3Float64,
    nSensitivity: usize,
) -> fmi3Status {
    with(instance, |comp| {
        // SAFETY: by the contract; `sensitivity` is only written.
        let unknown = unsafe {
            flat_references(
                comp,
                unknowns,
                nUnknowns,
                sensitivity.cast_const(),
                nSensitivity,
            )
        }
        .map_err(|e| format!("unknowns and sensitivity: {e}"))?;
        // SAFETY: by the contract.
        let known = unsafe { flat_references(comp, knowns, nKnowns, seed, nSeed) }
            .map_err(|e| format!("knowns and seed: {e}"))?;
        // SAFETY: valid for nSeed = known.len() values (checked non-NULL
        // where there are any) by the contract.
        let seed = unsafe { pointers::values(seed, nSeed) };
        let dv = comp.inst.directional_derivative(&unknown, &known, seed)?;
        // SAFETY: `sensitivity` is valid for nSensitivity = unknown.len() =
        // dv.len() doubles (checked non-NULL).
        unsafe { pointers::write(sensitivity, &dv) };
        Ok(())
    })
}

/// # Safety
/// The out-parameters are NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi3DoStep(
    instance: fmi3Instance,
    currentCommunicationPoint: fmi3Float64,
    communicationStepSize: fmi3Float64,
    _noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
    eventHandlingNeeded: *mut fmi3Boolean,
    terminateSimulation: *mut fmi3Boolean,
    earlyReturn: *mut fmi3Boolean,
    lastSuccessfulTime: *mut fmi3Float64,
) -> fmi3Status {
    with(instance, |comp| {
        let done = comp
            .inst
            .do_step(currentCommunicationPoint, communicationStepSize);
        // No events, no early return; a failed step left the time where
        // it was.
        // SAFETY: NULL or writable by the contract.
        unsafe {
            put(eventHandlingNeeded, false);
            put(terminateSimulation, false);
            put(earlyReturn, false);
            put(lastSuccessfulTime, comp.inst.time());
        }
        done
    })
}

/// Refuses a call the FMU does not support.
fn unsupported(instance: fmi3Instance, what: &str) -> fmi3Status {
    with(instance, |_| {
        Err(format!("{what} is not supported by this FMU"))
    })
}

/// Functions of the interfaces and features the FMU does not implement
/// (Model Exchange, Scheduled Execution, Event and Configuration Mode,
/// clocks, adjoint derivatives, output derivatives, dependencies): each
/// `fmi3Error` with a message.
macro_rules! unsupported {
    ($($name:ident($($arg:ident: $t:ty),*) => $why:literal;)*) => {$(
        #[no_mangle]
        pub extern "C" fn $name(instance: fmi3Instance, $($arg: $t),*) -> fmi3Status {
            unsupported(instance, concat!(stringify!($name), " (", $why, ")"))
        }
    )*};
}

unsupported! {
    fmi3EnterEventMode() => "the FMU has no Event Mode";
    fmi3EvaluateDiscreteStates() => "the FMU has no discrete states";
    fmi3UpdateDiscreteStates(
        _discreteStatesNeedUpdate: *mut fmi3Boolean,
        _terminateSimulation: *mut fmi3Boolean,
        _nominalsOfContinuousStatesChanged: *mut fmi3Boolean,
        _valuesOfContinuousStatesChanged: *mut fmi3Boolean,
        _nextEventTimeDefined: *mut fmi3Boolean,
        _nextEventTime: *mut fmi3Float64
    ) => "the FMU has no Event Mode";
    fmi3EnterConfigurationMode() => "the FMU has no structural parameters";
    fmi3ExitConfigurationMode() => "the FMU has no structural parameters";
    fmi3GetNumberOfVariableDependencies(
        _valueReference: fmi3ValueReference,
        _nDependencies: *mut usize
    ) => "the dependencies are in modelDescription.xml";
    fmi3GetVariableDependencies(
        _dependent: fmi3ValueReference,
        _elementIndicesOfDependent: *mut usize,
        _independents: *mut fmi3ValueReference,
        _elementIndicesOfIndependents: *mut usize,
        _dependencyKinds: *mut fmi3DependencyKind,
        _nDependencies: usize
    ) => "the dependencies are in modelDescription.xml";
    fmi3GetAdjointDerivative(
        _unknowns: *const fmi3ValueReference,
        _nUnknowns: usize,
        _knowns: *const fmi3ValueReference,
        _nKnowns: usize,
        _seed: *const fmi3Float64,
        _nSeed: usize,
        _sensitivity: *mut fmi3Float64,
        _nSensitivity: usize
    ) => "providesAdjointDerivatives is false; use fmi3GetDirectionalDerivative";
    fmi3GetOutputDerivatives(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: usize,
        _orders: *const fmi3Int32,
        _values: *mut fmi3Float64,
        _nValues: usize
    ) => "maxOutputDerivativeOrder is 0";
    fmi3GetIntervalDecimal(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: usize,
        _intervals: *mut fmi3Float64,
        _qualifiers: *mut fmi3IntervalQualifier
    ) => "the FMU has no clocks";
    fmi3GetIntervalFraction(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: usize,
        _counters: *mut fmi3UInt64,
        _resolutions: *mut fmi3UInt64,
        _qualifiers: *mut fmi3IntervalQualifier
    ) => "the FMU has no clocks";
    fmi3GetShiftDecimal(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: usize,
        _shifts: *mut fmi3Float64
    ) => "the FMU has no clocks";
    fmi3GetShiftFraction(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: usize,
        _counters: *mut fmi3UInt64,
        _resolutions: *mut fmi3UInt64
    ) => "the FMU has no clocks";
    fmi3SetIntervalDecimal(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: usize,
        _intervals: *const fmi3Float64
    ) => "the FMU has no clocks";
    fmi3SetIntervalFraction(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: usize,
        _counters: *const fmi3UInt64,
        _resolutions: *const fmi3UInt64
    ) => "the FMU has no clocks";
    fmi3SetShiftDecimal(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: usize,
        _shifts: *const fmi3Float64
    ) => "the FMU has no clocks";
    fmi3SetShiftFraction(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: usize,
        _counters: *const fmi3UInt64,
        _resolutions: *const fmi3UInt64
    ) => "the FMU has no clocks";
    fmi3ActivateModelPartition(
        _clockReference: fmi3ValueReference,
        _activationTime: fmi3Float64
    ) => "Scheduled Execution is not implemented";
    fmi3EnterContinuousTimeMode() => "Model Exchange is not implemented";
    fmi3CompletedIntegratorStep(
        _noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
        _enterEventMode: *mut fmi3Boolean,
        _terminateSimulation: *mut fmi3Boolean
    ) => "Model Exchange is not implemented";
    fmi3SetTime(_time: fmi3Float64) => "Model Exchange is not implemented";
    fmi3SetContinuousStates(
        _continuousStates: *const fmi3Float64,
        _nContinuousStates: usize
    ) => "Model Exchange is not implemented";
    fmi3GetContinuousStateDerivatives(
        _derivatives: *mut fmi3Float64,
        _nContinuousStates: usize
    ) => "Model Exchange is not implemented";
    fmi3GetEventIndicators(
        _eventIndicators: *mut fmi3Float64,
        _nEventIndicators: usize
    ) => "Model Exchange is not implemented";
    fmi3GetContinuousStates(
        _continuousStates: *mut fmi3Float64,
        _nContinuousStates: usize
    ) => "Model Exchange is not implemented";
    fmi3GetNominalsOfContinuousStates(
        _nominals: *mut fmi3Float64,
        _nContinuousStates: usize
    ) => "Model Exchange is not implemented";
    fmi3GetNumberOfEventIndicators(_nEventIndicators: *mut usize) => "Model Exchange is not implemented";
    fmi3GetNumberOfContinuousStates(_nContinuousStates: *mut usize) => "Model Exchange is not implemented";
}
