//! The host's strings and arrays, as the exported functions receive them:
//! NULL is refused where something must be read or written, and a count of
//! zero needs no pointer at all.

use std::ffi::{c_char, CStr};

/// `*ptr` as text (invalid UTF-8 replaced), `None` for NULL.
///
/// # Safety
/// `ptr` is NULL or NUL-terminated.
pub unsafe fn text(ptr: *const c_char) -> Option<String> {
    if ptr.is_null() {
        return None;
    }
    // SAFETY: NUL-terminated by the contract.
    Some(
        unsafe { CStr::from_ptr(ptr) }
            .to_string_lossy()
            .into_owned(),
    )
}

/// `(vr, nvr)` as a slice (empty for `nvr = 0`), with `values` checked
/// non-NULL for `n > 0` values but not read (an array to be written may
/// be uninitialized). A NULL pointer where there are elements is refused
/// as `"{names}: NULL"`.
///
/// # Safety
/// For `nvr > 0`, `vr` is NULL or valid for `nvr` elements.
pub unsafe fn references<'a, T>(
    vr: *const u32,
    nvr: usize,
    values: *const T,
    n: usize,
    names: &str,
) -> Result<&'a [u32], String> {
    if (nvr > 0 && vr.is_null()) || (n > 0 && values.is_null()) {
        return Err(format!("{names}: NULL"));
    }
    if nvr == 0 {
        return Ok(&[]);
    }
    // SAFETY: non-NULL and valid for nvr elements by the contract.
    Ok(unsafe { std::slice::from_raw_parts(vr, nvr) })
}

/// `(values, n)` as a slice, empty for `n = 0`.
///
/// # Safety
/// For `n > 0`, `values` is valid for `n` initialized elements (not NULL:
/// checked by [`references`]).
pub unsafe fn values<'a, T>(values: *const T, n: usize) -> &'a [T] {
    if n == 0 {
        return &[];
    }
    // SAFETY: by the contract.
    unsafe { std::slice::from_raw_parts(values, n) }
}

/// `(vr, nvr)` and `(values, n)` as slices, checked as by [`references`].
///
/// # Safety
/// For `nvr > 0` and `n > 0` the pointers are NULL or valid for `nvr` and
/// `n` initialized elements.
pub unsafe fn slices<'a, T>(
    vr: *const u32,
    nvr: usize,
    values: *const T,
    n: usize,
    names: &str,
) -> Result<(&'a [u32], &'a [T]), String> {
    // SAFETY: by the contract.
    let vrs = unsafe { references(vr, nvr, values, n, names) }?;
    // SAFETY: `values` is non-NULL where n > 0 (checked) and valid for n
    // initialized elements by the contract.
    Ok((vrs, unsafe { self::values(values, n) }))
}

/// Copies `values` to `out`.
///
/// # Safety
/// `out` is writable for `values.len()` elements (it may be NULL, or
/// dangling, only when `values` is empty).
pub unsafe fn write<T: Copy>(out: *mut T, values: &[T]) {
    if !values.is_empty() {
        // SAFETY: by the contract; the host's array is not ours.
        unsafe { std::ptr::copy_nonoverlapping(values.as_ptr(), out, values.len()) };
    }
}

/// Writes `value` to `*ptr` unless `ptr` is NULL.
///
/// # Safety
/// `ptr` is NULL or writable.
pub unsafe fn put<T>(ptr: *mut T, value: T) {
    // SAFETY: by the contract.
    if let Some(slot) = unsafe { ptr.as_mut() } {
        *slot = value;
    }
}
