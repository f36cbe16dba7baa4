//! FMU states as bytes (`fmi2SerializeFMUstate`, `fmi3SerializeFMUState`):
//! what a host saves to a file or sends to another process, and restores
//! into any instance of the same FMU.
//!
//! A state is written as the parameters and the committed samples, not as
//! the model's internal variables: restoring it rebuilds the model with
//! those parameters and replays the samples, as a parameter change does
//! (so the restored instance continues bit for bit as the saved one would
//! have, and the bytes grow with the steps taken, 16 per step). Layout,
//! little-endian:
//!
//! | field | bytes |
//! |---|---|
//! | magic `hysteron-state` | 14 |
//! | format version (1) | 2 |
//! | the GUID of the FMU's spec (as instantiated) | 38 |
//! | parameter count `p`, then the parameters (f64) | 4 + 8p |
//! | mode (0 instantiated, 1 initialization, 2 stepping, 3 terminated) | 1 |
//! | input, output, time (f64) | 24 |
//! | sample period: 0 none, 1 then the f64 | 1 (+ 8) |
//! | samples `n`, then each input and period (f64, f64) | 8 + 16n |
//! | CRC-32 (IEEE) of every byte before | 4 |
//!
//! Bytes that are truncated, padded, of another FMU or of another format
//! version, whose checksum fails, or whose replay does not end where the
//! state says are refused with a message naming what is wrong.

use super::guid;
use super::instance::{replay, Mode, Snapshot};
use crate::model::Model;

const MAGIC: &[u8; 14] = b"hysteron-state";
const VERSION: u16 = 1;
const GUID_LEN: usize = 38;

/// The GUID that ties a state to its FMU: that of the spec as
/// instantiated.
fn fingerprint(start: &Model) -> Result<String, String> {
    let json = start
        .spec()
        .to_json_pretty()
        .map_err(|e| format!("the FMU's spec: {e}"))?;
    Ok(guid(&json))
}

fn mode_byte(mode: Mode) -> u8 {
    match mode {
        Mode::Instantiated => 0,
        Mode::Initialization => 1,
        Mode::Stepping => 2,
        Mode::Terminated => 3,
    }
}

/// The bytes of `state`, a state of an instance instantiated as `start`.
pub fn serialize(start: &Model, state: &Snapshot) -> Result<Vec<u8>, String> {
    let params = state.model.operator().params();
    let mut out = Vec::with_capacity(100 + 8 * params.len() + 16 * state.history.len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&VERSION.to_le_bytes());
    out.extend_from_slice(fingerprint(start)?.as_bytes());
    let count = u32::try_from(params.len()).map_err(|_| "too many parameters".to_string())?;
    out.extend_from_slice(&count.to_le_bytes());
    for p in &params {
        out.extend_from_slice(&p.to_le_bytes());
    }
    out.push(mode_byte(state.mode));
    for v in [state.x, state.y, state.time] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    match state.period {
        Some(h) => {
            out.push(1);
            out.extend_from_slice(&h.to_le_bytes());
        }
        None => out.push(0),
    }
    out.extend_from_slice(&(state.history.len() as u64).to_le_bytes());
    for &(x, h) in &state.history {
        out.extend_from_slice(&x.to_le_bytes());
        out.extend_from_slice(&h.to_le_bytes());
    }
    let crc = crc32fast::hash(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    Ok(out)
}

/// Reads fields off the front of the bytes, naming the field that is cut
/// short.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize, field: &str) -> Result<&'a [u8], String> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let Some(end) = end else {
            return Err(format!(
                "the state is truncated: {field} at byte {} needs {n} bytes, {} are left",
                self.at,
                self.bytes.len().saturating_sub(self.at)
            ));
        };
        let part = self.bytes.get(self.at..end).unwrap_or_default();
        self.at = end;
        Ok(part)
    }

    fn array<const N: usize>(&mut self, field: &str) -> Result<[u8; N], String> {
        let part = self.take(N, field)?;
        let mut a = [0; N];
        a.copy_from_slice(part);
        Ok(a)
    }

    fn f64(&mut self, field: &str) -> Result<f64, String> {
        Ok(f64::from_le_bytes(self.array(field)?))
    }

    fn u8(&mut self, field: &str) -> Result<u8, String> {
        Ok(self.array::<1>(field)?[0])
    }
}

/// The state that `bytes` hold, restored for an instance instantiated as
/// `start` (see the module docs for what is refused).
pub fn deserialize(start: &Model, bytes: &[u8]) -> Result<Snapshot, String> {
    let body_len = bytes
        .len()
        .checked_sub(4)
        .filter(|&n| n >= MAGIC.len())
        .ok_or_else(|| format!("the state is truncated: {} bytes", bytes.len()))?;
    let mut r = Reader { bytes, at: 0 };
    if r.take(MAGIC.len(), "the magic")? != MAGIC {
        return Err("these bytes are not a hysteron FMU state (no `hysteron-state` magic)".into());
    }
    let version = u16::from_le_bytes(r.array("the format version")?);
    if version != VERSION {
        return Err(format!(
            "the state has format version {version}; this FMU reads version {VERSION}"
        ));
    }
    let (body, tail) = bytes.split_at(body_len);
    let stored = u32::from_le_bytes(
        tail.try_into()
            .map_err(|_| "the state is truncated: no checksum".to_string())?,
    );
    if crc32fast::hash(body) != stored {
        return Err(
            "the state is corrupted or truncated: its CRC-32 does not match its bytes".into(),
        );
    }
    let r = &mut Reader {
        bytes: body,
        at: r.at,
    };
    let own = fingerprint(start)?;
    if r.take(GUID_LEN, "the GUID")? != own.as_bytes() {
        return Err(format!(
            "the state is of another model: this FMU's GUID is {own}"
        ));
    }
    let count = u32::from_le_bytes(r.array("the parameter count")?) as usize;
    let expected = start.names().len();
    if count != expected {
        return Err(format!(
            "the state has {count} parameters; the model has {expected}"
        ));
    }
    let params = (0..count)
        .map(|i| r.f64(&format!("parameter {i}")))
        .collect::<Result<Vec<f64>, String>>()?;
    let mode = match r.u8("the mode")? {
        0 => Mode::Instantiated,
        1 => Mode::Initialization,
        2 => Mode::Stepping,
        3 => Mode::Terminated,
        m => return Err(format!("the state has an unknown mode {m}")),
    };
    let (x, y, time) = (
        r.f64("the input")?,
        r.f64("the output")?,
        r.f64("the time")?,
    );
    let period = match r.u8("the sample period's flag")? {
        0 => None,
        1 => Some(r.f64("the sample period")?),
        f => return Err(format!("the state has a bad sample period flag {f}")),
    };
    let n = u64::from_le_bytes(r.array("the sample count")?);
    let left = (body.len() - r.at) as u64;
    if n.checked_mul(16) != Some(left) {
        return Err(format!(
            "the state says {n} samples but holds {left} bytes of them (16 per sample)"
        ));
    }
    let history = (0..n)
        .map(|k| {
            Ok((
                r.f64(&format!("sample {k}"))?,
                r.f64(&format!("period {k}"))?,
            ))
        })
        .collect::<Result<Vec<(f64, f64)>, String>>()?;
    let model = start
        .with_params(&params)
        .map_err(|e| format!("the state's parameters: {e}"))?;
    let (model, replayed_period, replayed_y) = replay(model, &history, "of the state")?;
    if let Some(last) = replayed_y {
        if last.to_bits() != y.to_bits() || replayed_period != period {
            return Err(
                "the state does not replay: its samples do not end at its output and period".into(),
            );
        }
    }
    Ok(Snapshot {
        model,
        x,
        y,
        time,
        period,
        history,
        mode,
    })
}

#[cfg(test)]
mod tests {
    use super::super::instance::tests::{run, stepping};
    use super::super::instance::Instance;
    use super::super::{VR_FIRST_PARAM, VR_X};
    use super::*;

    const MSD: &str = r#"{"type": "cascade", "first": {"type": "play", "r": 0.1},
        "second": {"type": "mass_spring_damper", "m": 1, "c": 2, "k": 400, "dt": 1}}"#;

    fn input(n: usize) -> Vec<f64> {
        (0..n).map(|i| (i as f64 * 0.21).sin() * 1.3).collect()
    }

    /// An instance of MSD stepped with changing step sizes and a
    /// parameter change: the bytes of its state.
    fn stepped() -> (Instance, Vec<u8>) {
        let xs = input(60);
        let mut inst = stepping(MSD);
        run(&mut inst, &xs[..20], 0.004);
        run(&mut inst, &xs[20..30], 0.01);
        inst.set_real(&[VR_FIRST_PARAM], &[0.2]).unwrap();
        run(&mut inst, &xs[30..40], 0.004 * (1.0 + 4.0 * f64::EPSILON));
        inst.set_real(&[VR_X], &[0.7]).unwrap();
        let bytes = serialize(inst.start(), &inst.snapshot()).unwrap();
        (inst, bytes)
    }

    #[test]
    fn a_restored_state_continues_bit_for_bit_in_a_fresh_instance() {
        let (mut saved, bytes) = stepped();
        assert_eq!(
            bytes.len(),
            14 + 2 + 38 + 4 + 8 * 5 + 1 + 24 + 9 + 8 + 16 * 40 + 4
        );
        let mut fresh = Instance::new(Model::from_json(MSD).unwrap());
        let snap = deserialize(fresh.start(), &bytes).unwrap();
        fresh.restore(&snap);
        assert_eq!(fresh.time().to_bits(), saved.time().to_bits());
        let rest = input(100);
        for h in [0.004, 0.02] {
            let (a, b) = (run(&mut saved, &rest, h), run(&mut fresh, &rest, h));
            let same = a.iter().zip(&b).all(|(u, v)| u.to_bits() == v.to_bits());
            assert!(same, "step {h}: {a:?} vs {b:?}");
        }
        // and a state before the first step
        let early = stepping(MSD).snapshot();
        let start = Model::from_json(MSD).unwrap();
        let back = deserialize(&start, &serialize(&start, &early).unwrap()).unwrap();
        assert_eq!(back.history.len(), 0);
        assert_eq!(back.mode, Mode::Stepping);
    }

    #[test]
    fn every_truncation_and_every_flipped_byte_is_refused() {
        let (saved, bytes) = stepped();
        let start = saved.start().clone();
        for n in 0..bytes.len() {
            let err = deserialize(&start, &bytes[..n]).err();
            assert!(err.is_some(), "{n} of {} bytes were accepted", bytes.len());
        }
        for k in 0..bytes.len() {
            let mut bad = bytes.clone();
            bad[k] ^= 0x10;
            let err = deserialize(&start, &bad).err().unwrap_or_default();
            assert!(!err.is_empty(), "byte {k} flipped was accepted");
        }
        let mut padded = bytes.clone();
        padded.push(0);
        assert!(deserialize(&start, &padded).is_err());
        assert!(deserialize(&start, b"not a state at all")
            .err()
            .unwrap_or_default()
            .contains("magic"));
    }

    #[test]
    fn a_state_of_another_model_or_version_is_refused_by_name() {
        let (saved, bytes) = stepped();
        let other = Model::from_json(r#"{"type": "play", "r": 0.5}"#).unwrap();
        assert!(deserialize(&other, &bytes)
            .err()
            .unwrap_or_default()
            .contains("another model"));
        // Altered with a valid checksum: another format version, and an
        // output its samples do not replay to (at byte 107, after the
        // magic, version, GUID, 5 parameters, mode and input).
        let altered = |at: usize, with: &[u8]| {
            let mut b = bytes.clone();
            b[at..at + with.len()].copy_from_slice(with);
            let body = b.len() - 4;
            let crc = crc32fast::hash(&b[..body]).to_le_bytes();
            b[body..].copy_from_slice(&crc);
            deserialize(saved.start(), &b).err().unwrap_or_default()
        };
        let err = altered(14, &[2]);
        assert!(err.contains("format version 2"), "{err}");
        let y = f64::from_le_bytes(bytes[107..115].try_into().unwrap());
        assert_eq!(y, saved.get_real(super::super::VR_Y).unwrap());
        let err = altered(107, &(y + 1e-9).to_le_bytes());
        assert!(err.contains("does not replay"), "{err}");
    }
}
