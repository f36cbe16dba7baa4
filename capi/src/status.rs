//! Status codes, the thread's last error message, and the guard that keeps
//! every panic on the Rust side of the C boundary.

use hysteron::models::SpecError;
use hysteron::Error;
use std::cell::RefCell;
use std::ffi::{c_char, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// What a call of the C API did. `HYSTERON_STATUS_OK` (0) is success; any
/// other value is an error whose message `hysteron_last_error` gives.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HysteronStatus {
    /// Success.
    Ok = 0,
    /// A pointer argument was NULL.
    NullArgument = 1,
    /// A string argument was not UTF-8.
    InvalidUtf8 = 2,
    /// The JSON text is not a valid model spec.
    Spec = 3,
    /// A parameter outside its domain (also a sample period that is not
    /// finite and positive), or an unknown, ambiguous or tied parameter
    /// name.
    Parameter = 4,
    /// A non-finite input sample.
    Input = 5,
    /// The model failed at a sample (an implicit solve, a non-finite
    /// output); its state is that before the sample.
    Solver = 6,
    /// An index past the end (a parameter index).
    OutOfRange = 7,
    /// A bug: the library panicked. The model must not be used again.
    Internal = 8,
}

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

/// Records `message` as this thread's last error and returns `status`.
pub(crate) fn fail(status: HysteronStatus, message: impl Into<String>) -> HysteronStatus {
    let text = message.into().replace('\0', " ");
    let c = CString::new(text).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = c);
    status
}

/// The status of an operator error, with its message recorded.
pub(crate) fn operator_failure(e: Error) -> HysteronStatus {
    let status = match &e {
        Error::AtSample { source, .. } => status_of(source),
        other => status_of(other),
    };
    fail(status, e.to_string())
}

fn status_of(e: &Error) -> HysteronStatus {
    match e {
        Error::InvalidParameter { .. } | Error::ParamCount { .. } => HysteronStatus::Parameter,
        Error::NonFiniteInput { .. } | Error::LengthMismatch { .. } => HysteronStatus::Input,
        _ => HysteronStatus::Solver,
    }
}

/// The status of a spec error, with its message recorded.
pub(crate) fn spec_failure(e: SpecError) -> HysteronStatus {
    let status = match e {
        SpecError::Invalid { .. } => HysteronStatus::Parameter,
        _ => HysteronStatus::Spec,
    };
    fail(status, e.to_string())
}

/// Runs `body`, turning a panic into `HysteronStatus::Internal` with its
/// message: no unwinding crosses the C boundary.
pub(crate) fn guard(body: impl FnOnce() -> HysteronStatus) -> HysteronStatus {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(status) => status,
        Err(payload) => fail(HysteronStatus::Internal, internal_error(&payload)),
    }
}

/// The message of a caught panic: an internal error, a bug in hysteron.
pub(crate) fn internal_error(payload: &Box<dyn std::any::Any + Send>) -> String {
    format!(
        "internal error (a bug in hysteron): {}",
        panic_text(payload)
    )
}

/// The text of a panic payload.
pub(crate) fn panic_text(payload: &Box<dyn std::any::Any + Send>) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "panic".to_string())
}

/// The message of the last failed call on this thread (an empty string if
/// none failed). The pointer stays valid until the next failing call on
/// the same thread.
#[no_mangle]
pub extern "C" fn hysteron_last_error() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}
