//! FMU states behind the host's handles (`fmi2FMUstate`, `fmi3FMUState`):
//! each is a boxed [`Snapshot`], made by getting or deserializing a state,
//! overwritten in place when the host passes it again, and freed once. The
//! exported `Get`, `Set`, `Free`, `SerializedSize`, `Serialize` and
//! `Deserialize` functions of both versions are these, under their names
//! (the messages name the version's functions and its spelling of
//! `FMUstate`).

use super::instance::{Instance, Snapshot};
use super::serial::{deserialize, serialize};
use std::ffi::c_void;

/// `"FMUstate: NULL"` (FMI 3.0: `FMUState`) for `inst`'s version.
fn null_state(inst: &Instance) -> String {
    format!("{}: NULL", inst.api().fmu_state())
}

/// Stores `snap` in the slot `*slot`: over the state there, or new.
///
/// # Safety
/// `*slot` is NULL or a state from this module.
unsafe fn store(slot: &mut *mut c_void, snap: Snapshot) {
    // SAFETY: NULL or a Snapshot made by Box::into_raw below.
    match unsafe { slot.cast::<Snapshot>().as_mut() } {
        Some(old) => *old = snap,
        None => *slot = Box::into_raw(Box::new(snap)).cast(),
    }
}

/// The snapshot behind the handle `state`.
///
/// # Safety
/// `state` is NULL or a state from this module.
unsafe fn snapshot<'a>(inst: &Instance, state: *mut c_void) -> Result<&'a Snapshot, String> {
    // SAFETY: by the contract.
    unsafe { state.cast::<Snapshot>().as_ref() }.ok_or_else(|| null_state(inst))
}

/// Saves `inst`'s state in `*slot`.
///
/// # Safety
/// `slot` is NULL or points to NULL or to a state from this module.
pub unsafe fn save(inst: &Instance, slot: *mut *mut c_void) -> Result<(), String> {
    // SAFETY: by the contract.
    let slot = unsafe { slot.as_mut() }.ok_or_else(|| null_state(inst))?;
    // SAFETY: `*slot` is NULL or a state of this module by the contract.
    unsafe { store(slot, inst.snapshot()) };
    Ok(())
}

/// Restores `inst` to the state `state`.
///
/// # Safety
/// `state` is NULL or a state from this module.
pub unsafe fn restore(inst: &mut Instance, state: *mut c_void) -> Result<(), String> {
    // SAFETY: by the contract.
    let snap = unsafe { snapshot(inst, state) }?;
    inst.restore(snap);
    Ok(())
}

/// Frees the state in `*slot` and sets the slot to NULL; nothing for a
/// NULL `slot` or a NULL state.
///
/// # Safety
/// `slot` is NULL or points to NULL or to a state from this module, not
/// used afterwards.
pub unsafe fn free(slot: *mut *mut c_void) {
    // SAFETY: by the contract.
    if let Some(slot) = unsafe { slot.as_mut() } {
        if !slot.is_null() {
            // SAFETY: made by Box::into_raw in `store`, freed once.
            drop(unsafe { Box::from_raw(slot.cast::<Snapshot>()) });
            *slot = std::ptr::null_mut();
        }
    }
}

/// The bytes of `state` ([`serial`](super::serial)).
///
/// # Safety
/// `state` is NULL or a state from this module.
unsafe fn bytes_of(inst: &Instance, state: *mut c_void) -> Result<Vec<u8>, String> {
    // SAFETY: by the contract.
    let snap = unsafe { snapshot(inst, state) }?;
    serialize(inst.start(), snap)
}

/// Writes the size in bytes of the serialized `state` to `*size`.
///
/// # Safety
/// `state` is NULL or a state from this module; `size` is NULL or
/// writable.
pub unsafe fn serialized_size(
    inst: &Instance,
    state: *mut c_void,
    size: *mut usize,
) -> Result<(), String> {
    // SAFETY: by the contract.
    let bytes = unsafe { bytes_of(inst, state) }?;
    // SAFETY: `size` is NULL or writable by the contract.
    *unsafe { size.as_mut() }.ok_or("size: NULL")? = bytes.len();
    Ok(())
}

/// Writes the bytes of `state` to `out`, which must hold exactly `size`
/// bytes (the serialized size).
///
/// # Safety
/// `state` is NULL or a state from this module; `out` is NULL or writable
/// for `size` bytes.
pub unsafe fn serialize_into(
    inst: &Instance,
    state: *mut c_void,
    out: *mut u8,
    size: usize,
) -> Result<(), String> {
    // SAFETY: by the contract.
    let data = unsafe { bytes_of(inst, state) }?;
    if out.is_null() {
        return Err("serializedState: NULL".into());
    }
    if size != data.len() {
        let api = inst.api();
        return Err(format!(
            "size is {size}, but the state is {} bytes ({})",
            data.len(),
            api.function(&format!("Serialized{}Size", api.fmu_state()))
        ));
    }
    // SAFETY: `out` is writable for `size` = data.len() bytes.
    unsafe { std::ptr::copy_nonoverlapping(data.as_ptr(), out, size) };
    Ok(())
}

/// Stores the state that the `size` bytes at `bytes` hold in `*slot`.
///
/// # Safety
/// `bytes` is NULL or valid for `size` bytes; `slot` is NULL or points to
/// NULL or to a state from this module.
pub unsafe fn deserialize_from(
    inst: &Instance,
    bytes: *const u8,
    size: usize,
    slot: *mut *mut c_void,
) -> Result<(), String> {
    // SAFETY: by the contract.
    let slot = unsafe { slot.as_mut() }.ok_or_else(|| null_state(inst))?;
    let data: &[u8] = match size {
        0 => &[],
        _ if bytes.is_null() => return Err("serializedState: NULL".into()),
        // SAFETY: valid for `size` bytes by the contract.
        _ => unsafe { std::slice::from_raw_parts(bytes, size) },
    };
    let snap = deserialize(inst.start(), data)?;
    // SAFETY: `*slot` is NULL or a state of this module by the contract.
    unsafe { store(slot, snap) };
    Ok(())
}
