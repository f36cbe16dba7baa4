//! The C API: a model built from a JSON spec behind an opaque pointer.
//!
//! # Requirements
//! * Pointers passed in are NULL or valid for the access the function
//!   documents (a model from `hysteron_model_from_json` or
//!   `hysteron_model_clone` not yet freed; a buffer of `n` doubles).
//! * A model is used by one thread at a time; different models are
//!   independent and may run on different threads.
//!
//! Every function returns a [`HysteronStatus`]; on an error the message is
//! in `hysteron_last_error()` and nothing changed, except for a failed
//! sample in `hysteron_process`, after which the state is that before the
//! failing sample (the message names it).

use crate::model::Model;
use crate::status::{fail, guard, operator_failure, spec_failure, HysteronStatus};
use hysteron::Trial;
use std::ffi::{c_char, CStr};

/// A model: a spec and the operator built from it, with its running state.
pub struct HysteronModel(Model);

/// `*ptr` as a string, or the status to return.
///
/// # Safety
/// `ptr` is NULL or points to a NUL-terminated string.
unsafe fn text<'a>(ptr: *const c_char, what: &str) -> Result<&'a str, HysteronStatus> {
    if ptr.is_null() {
        return Err(fail(HysteronStatus::NullArgument, format!("{what}: NULL")));
    }
    // SAFETY: non-NULL and NUL-terminated by the caller's contract.
    unsafe { CStr::from_ptr(ptr) }.to_str().map_err(|e| {
        fail(
            HysteronStatus::InvalidUtf8,
            format!("{what}: not UTF-8 ({e})"),
        )
    })
}

/// `&mut *model`, or the status to return.
///
/// # Safety
/// `model` is NULL or a live model used by this thread only.
unsafe fn model_mut<'a>(model: *mut HysteronModel) -> Result<&'a mut Model, HysteronStatus> {
    // SAFETY: by the caller's contract.
    unsafe { model.as_mut() }
        .map(|m| &mut m.0)
        .ok_or_else(|| fail(HysteronStatus::NullArgument, "model: NULL"))
}

/// `&*model`, or the status to return.
///
/// # Safety
/// `model` is NULL or a live model.
unsafe fn model_ref<'a>(model: *const HysteronModel) -> Result<&'a Model, HysteronStatus> {
    // SAFETY: by the caller's contract.
    unsafe { model.as_ref() }
        .map(|m| &m.0)
        .ok_or_else(|| fail(HysteronStatus::NullArgument, "model: NULL"))
}

/// Writes `value` to `out` if `out` is not NULL.
///
/// # Safety
/// `out` is NULL or valid for a write.
unsafe fn put<T>(out: *mut T, value: T) {
    if let Some(slot) = unsafe { out.as_mut() } {
        *slot = value;
    }
}

/// Stores the model `make` gives in `*out` (NULL on error), under the
/// panic guard.
///
/// # Safety
/// `out` is NULL or writable; `make` is safe to call under the caller's
/// contract for its own pointers.
unsafe fn store(
    out: *mut *mut HysteronModel,
    make: impl FnOnce() -> Result<Model, HysteronStatus>,
) -> HysteronStatus {
    call(|| {
        // SAFETY: by the caller's contract.
        let slot = unsafe { out.as_mut() }
            .ok_or_else(|| fail(HysteronStatus::NullArgument, "out: NULL"))?;
        *slot = std::ptr::null_mut();
        *slot = Box::into_raw(Box::new(HysteronModel(make()?)));
        Ok(())
    })
}

/// The trial of `m` at input `x` from its committed state (pending until
/// a commit), or the status to return: a spec that cannot run yet, or an
/// operator error.
fn trial(m: &mut Model, x: f64) -> Result<Trial<f64>, HysteronStatus> {
    m.running()
        .map_err(spec_failure)?
        .trial(x)
        .map_err(operator_failure)
}

/// Runs `body` under the panic guard, mapping `Err(status)` to `status`.
fn call(body: impl FnOnce() -> Result<(), HysteronStatus>) -> HysteronStatus {
    guard(|| match body() {
        Ok(()) => HysteronStatus::Ok,
        Err(status) => status,
    })
}

/// Builds a model from a JSON spec (`{"type": "play", "r": 0.5}`, the
/// documents `hysteron simulate --model` reads) and stores it in `*out`
/// (`NULL` on error). Free it with `hysteron_model_free`.
///
/// # Safety
/// `json` is NULL or a NUL-terminated string; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hysteron_model_from_json(
    json: *const c_char,
    out: *mut *mut HysteronModel,
) -> HysteronStatus {
    unsafe {
        store(out, || {
            let text = text(json, "json")?;
            Model::from_json(text).map_err(spec_failure)
        })
    }
}

/// An independent copy of `model`, in its current state, in `*out`.
///
/// # Safety
/// `model` is NULL or a live model; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hysteron_model_clone(
    model: *const HysteronModel,
    out: *mut *mut HysteronModel,
) -> HysteronStatus {
    unsafe { store(out, || Ok(model_ref(model)?.clone())) }
}

/// Frees a model (NULL is ignored).
///
/// # Safety
/// `model` is NULL or a live model, not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn hysteron_model_free(model: *mut HysteronModel) {
    if !model.is_null() {
        // SAFETY: made by Box::into_raw in this module, freed once.
        drop(unsafe { Box::from_raw(model) });
    }
}

/// One sample: `y = H[x]`, committed (`trial` then `commit`). `y` may be
/// NULL.
///
/// # Safety
/// `model` is NULL or a live model; `y` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hysteron_step(
    model: *mut HysteronModel,
    x: f64,
    y: *mut f64,
) -> HysteronStatus {
    call(|| {
        let m = unsafe { model_mut(model) }?;
        let out = trial(m, x)?.output;
        m.operator_mut().commit();
        unsafe { put(y, out) };
        Ok(())
    })
}

/// The output `y` and tangent `dy/dx` at input `x` from the committed
/// state, kept as pending: `hysteron_commit` keeps the last trial, another
/// trial replaces it. `y` and `tangent` may be NULL.
///
/// # Safety
/// `model` is NULL or a live model; `y` and `tangent` are NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hysteron_trial(
    model: *mut HysteronModel,
    x: f64,
    y: *mut f64,
    tangent: *mut f64,
) -> HysteronStatus {
    call(|| {
        let t = trial(unsafe { model_mut(model) }?, x)?;
        unsafe {
            put(y, t.output);
            put(tangent, t.tangent);
        }
        Ok(())
    })
}

/// Keeps the state of the last trial if it succeeded (nothing if there was
/// none, or if it failed: a failed trial leaves no trace).
///
/// # Safety
/// `model` is NULL or a live model.
#[no_mangle]
pub unsafe extern "C" fn hysteron_commit(model: *mut HysteronModel) -> HysteronStatus {
    call(|| {
        unsafe { model_mut(model) }?.operator_mut().commit();
        Ok(())
    })
}

/// Returns to the initial state (input 0).
///
/// # Safety
/// `model` is NULL or a live model.
#[no_mangle]
pub unsafe extern "C" fn hysteron_reset(model: *mut HysteronModel) -> HysteronStatus {
    call(|| {
        unsafe { model_mut(model) }?.operator_mut().reset();
        Ok(())
    })
}

/// Runs `n` samples `xs` from the current state into `ys`, committing
/// each. On an error at sample `i` (named in the message) the samples
/// before it are committed and `ys[i..]` is unspecified.
///
/// # Safety
/// `model` is NULL or a live model; for `n > 0`, `xs` and `ys` are NULL or
/// valid for `n` doubles and do not overlap.
#[no_mangle]
pub unsafe extern "C" fn hysteron_process(
    model: *mut HysteronModel,
    xs: *const f64,
    ys: *mut f64,
    n: usize,
) -> HysteronStatus {
    call(|| {
        let m = unsafe { model_mut(model) }?;
        if n == 0 {
            return Ok(());
        }
        if xs.is_null() || ys.is_null() {
            return Err(fail(HysteronStatus::NullArgument, "xs or ys: NULL"));
        }
        // SAFETY: valid for n doubles, not overlapping, by the contract.
        let (xs, ys) = unsafe {
            (
                std::slice::from_raw_parts(xs, n),
                std::slice::from_raw_parts_mut(ys, n),
            )
        };
        m.running()
            .map_err(spec_failure)?
            .process(xs, ys)
            .map_err(operator_failure)
    })
}

/// Sets the sample period `dt > 0` (seconds) of every rate-dependent node
/// (those inside an `oversample` of `q` get `dt / q`); it may change from
/// sample to sample. Rate-independent models check it and ignore it. A
/// period that is not finite and positive is `HYSTERON_STATUS_PARAMETER`
/// (naming `dt`).
///
/// # Safety
/// `model` is NULL or a live model.
#[no_mangle]
pub unsafe extern "C" fn hysteron_set_sample_period(
    model: *mut HysteronModel,
    dt: f64,
) -> HysteronStatus {
    call(|| {
        let m = unsafe { model_mut(model) }?;
        m.set_sample_period(dt).map_err(operator_failure)
    })
}

/// The sample period (seconds) the model runs at, in `*dt`: the spec's
/// `dt`, or the last one given by `hysteron_set_sample_period`; `0` for a
/// rate-independent model. A spec that leaves the period out, with none
/// given yet, is `HYSTERON_STATUS_SPEC` (naming the node), as is every
/// step, trial or run of it until then.
///
/// # Safety
/// `model` is NULL or a live model; `dt` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hysteron_sample_period(
    model: *const HysteronModel,
    dt: *mut f64,
) -> HysteronStatus {
    call(|| {
        let m = unsafe { model_ref(model) }?;
        let period = m.sample_period().map_err(spec_failure)?;
        if dt.is_null() {
            return Err(fail(HysteronStatus::NullArgument, "dt: NULL"));
        }
        unsafe { put(dt, period.unwrap_or(0.0)) };
        Ok(())
    })
}

/// The number of parameters, in `*n`.
///
/// # Safety
/// `model` is NULL or a live model; `n` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hysteron_param_count(
    model: *const HysteronModel,
    n: *mut usize,
) -> HysteronStatus {
    call(|| {
        let m = unsafe { model_ref(model) }?;
        unsafe { put(n, m.names().len()) };
        Ok(())
    })
}

/// The path of parameter `i` (`left.mms.f_c`), in `*name`: a
/// NUL-terminated string owned by the model, valid until the model is
/// freed or a parameter is set.
///
/// # Safety
/// `model` is NULL or a live model; `name` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hysteron_param_name(
    model: *const HysteronModel,
    i: usize,
    name: *mut *const c_char,
) -> HysteronStatus {
    call(|| {
        let m = unsafe { model_ref(model) }?;
        let names = m.names();
        let Some(text) = names.get(i) else {
            return Err(fail(
                HysteronStatus::OutOfRange,
                format!(
                    "parameter index {i}: the model has {} parameters",
                    names.len()
                ),
            ));
        };
        unsafe { put(name, text.as_ptr()) };
        Ok(())
    })
}

/// The value of parameter `name` (its path, or a suffix after a `.` that
/// only one parameter has: `f_c`), in `*value`.
///
/// # Safety
/// `model` is NULL or a live model; `name` is NULL or a NUL-terminated
/// string; `value` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hysteron_get_param(
    model: *const HysteronModel,
    name: *const c_char,
    value: *mut f64,
) -> HysteronStatus {
    call(|| {
        let m = unsafe { model_ref(model) }?;
        let name = unsafe { text(name, "name") }?;
        let v = m
            .param(name)
            .map_err(|e| fail(HysteronStatus::Parameter, e))?;
        unsafe { put(value, v) };
        Ok(())
    })
}

/// Sets parameter `name` (as for `hysteron_get_param`) to `value`. The
/// model is rebuilt with it and returns to its initial state, as a spec
/// with that value would start. A value outside the parameter's domain, or
/// a parameter tied to another (a gap's `r0` and its spring's `z0`), is
/// refused and nothing changes.
///
/// # Safety
/// `model` is NULL or a live model; `name` is NULL or a NUL-terminated
/// string.
#[no_mangle]
pub unsafe extern "C" fn hysteron_set_param(
    model: *mut HysteronModel,
    name: *const c_char,
    value: f64,
) -> HysteronStatus {
    call(|| {
        let m = unsafe { model_mut(model) }?;
        let name = unsafe { text(name, "name") }?;
        m.set_param(name, value)
    })
}
