//! `spec_json`: fuzzer bytes → JSON text (up to the first NUL byte) and an
//! input sequence (the rest, see `samples_from_bytes`) →
//! `Spec::from_json` → `build` → run. Checks that every failure is a typed
//! `Err` (never a panic), that a spec that reads also writes and reads back
//! to itself, and the trial/commit contract (`check_contract`: finite
//! outputs or an error, `process` = trial + commit bit for bit).
#![no_main]

use hysteron::models::Spec;
use hysteron_fuzz::{check_contract, samples_from_bytes};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let split = data.iter().position(|&b| b == 0).unwrap_or(data.len());
    let Ok(text) = std::str::from_utf8(&data[..split]) else {
        return;
    };
    let xs = samples_from_bytes(data.get(split + 1..).unwrap_or(&[]), 64);
    let Ok(spec) = Spec::from_json(text) else {
        return;
    };
    let json = spec.to_json_pretty().expect("a spec that reads writes");
    assert_eq!(
        Spec::from_json(&json).expect("a written spec reads back"),
        spec,
        "JSON round trip"
    );
    let Ok(op) = spec.build() else {
        return;
    };
    check_contract("spec", &op, &xs);
});
