//! An instance behind the C handle a host holds (`fmi2Component`,
//! `fmi3Instance`), and the guard every exported function runs under: a
//! NULL handle is an error, an `Err` is logged as an error, and a panic is
//! caught, logged and fatal, so that none crosses the C boundary.
//!
//! Each FMI version supplies its [`Host`]: how it reaches the host's logger
//! (the callbacks of FMI 2.0, the `logMessage` of FMI 3.0), and turns the
//! [`Outcome`] of a call into its own status code.

use super::instance::Instance;
use crate::status::{internal_error, panic_text};
use std::ffi::{c_int, c_void, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// How a call ended. FMI 2.0 (§2.1.3, `fmi2Status`) and FMI 3.0 (§2.2.3,
/// `fmi3Status`) number their statuses alike (OK 0, Warning 1, Discard 2,
/// Error 3, Fatal 4), so [`code`](Outcome::code) is the status in both.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// It did what was asked (`fmi2OK`, `fmi3OK`).
    Ok = 0,
    /// It was refused (a bad argument or call); the instance is as before
    /// (`fmi2Error`, `fmi3Error`).
    Error = 3,
    /// A bug in hysteron: the instance should not be used further
    /// (`fmi2Fatal`, `fmi3Fatal`).
    Fatal = 4,
}

impl Outcome {
    /// The status code of either version.
    pub fn code(self) -> c_int {
        self as c_int
    }
}

/// What a version keeps of its host beside the instance.
pub trait Host {
    /// Passes `message` to the host's logger (if it gave one) with the
    /// status [`code`](Outcome::code) of `outcome`.
    fn log(&self, outcome: Outcome, message: &str);
}

/// `text` (a message or a name) as a C string for the host: a NUL, which
/// would cut it short, becomes a space.
pub fn c_string(text: &str) -> CString {
    CString::new(text.replace('\0', " ")).unwrap_or_default()
}

/// An instance with its host: what the C handle points to.
pub struct Component<H> {
    /// The host's side (its logger).
    pub host: H,
    /// The instance.
    pub inst: Instance,
}

/// A new component of `host` with the instance `make` builds, as a C
/// handle; NULL, with the reason logged, where `make` fails or panics.
pub fn instantiate<H: Host>(
    host: H,
    make: impl FnOnce() -> Result<Instance, String>,
) -> *mut c_void {
    match catch_unwind(AssertUnwindSafe(make)) {
        Ok(Ok(inst)) => Box::into_raw(Box::new(Component { host, inst })).cast(),
        Ok(Err(message)) => {
            host.log(Outcome::Error, &message);
            std::ptr::null_mut()
        }
        Err(payload) => {
            host.log(Outcome::Fatal, &panic_text(&payload));
            std::ptr::null_mut()
        }
    }
}

/// Frees the component behind `handle`.
///
/// # Safety
/// `handle` is NULL or a handle from [`instantiate`] with the same `H`,
/// not used afterwards.
pub unsafe fn free<H>(handle: *mut c_void) {
    if !handle.is_null() {
        // SAFETY: made by Box::into_raw in `instantiate`, freed once.
        drop(unsafe { Box::from_raw(handle.cast::<Component<H>>()) });
    }
}

/// Runs `body` on the component behind `handle`: NULL is
/// [`Outcome::Error`] (with no one to log to), an `Err` is logged and
/// [`Outcome::Error`], a panic is logged and [`Outcome::Fatal`].
///
/// `handle` is NULL or a handle from [`instantiate`] with the same `H`,
/// used by one thread at a time (FMI 2.0 §2.1.3, FMI 3.0 §2.2.1): the
/// contract of every exported function, which hands on its handle
/// unchecked.
pub fn with<H: Host>(
    handle: *mut c_void,
    body: impl FnOnce(&mut Component<H>) -> Result<(), String>,
) -> Outcome {
    // SAFETY: by the contract above.
    let Some(comp) = (unsafe { handle.cast::<Component<H>>().as_mut() }) else {
        return Outcome::Error;
    };
    match catch_unwind(AssertUnwindSafe(|| body(comp))) {
        Ok(Ok(())) => Outcome::Ok,
        Ok(Err(message)) => {
            comp.host.log(Outcome::Error, &message);
            Outcome::Error
        }
        Err(payload) => {
            comp.host.log(Outcome::Fatal, &internal_error(&payload));
            Outcome::Fatal
        }
    }
}
