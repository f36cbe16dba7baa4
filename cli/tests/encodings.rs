//! Bytes a new user's tools write: a UTF-8 byte-order mark (spreadsheet
//! exports, some editors) is accepted in CSV and JSON files; bytes that are
//! not UTF-8 are an error naming the file and the row, exit code 1.

use std::fs;
use tempfile::TempDir;

mod common;
use common::simulate_files;

/// Runs `simulate` on `spec` and `csv` (raw bytes); the exit code, the
/// output file's text (empty if none) and stderr.
fn simulate(spec: &[u8], csv: &[u8]) -> (i32, String, String) {
    let dir = TempDir::new().expect("tempdir");
    let (model, input, output) = (
        dir.path().join("m.json"),
        dir.path().join("in.csv"),
        dir.path().join("out.csv"),
    );
    fs::write(&model, spec).expect("write spec");
    fs::write(&input, csv).expect("write csv");
    let (code, stderr) = simulate_files(&model, &input, &output);
    (
        code,
        fs::read_to_string(&output).unwrap_or_default(),
        stderr,
    )
}

const GAIN: &[u8] = br#"{"type": "gain", "k": 2.0}"#;

#[test]
fn a_byte_order_mark_is_skipped_in_csv_and_json() {
    let bom = b"\xef\xbb\xbf";
    let csv = [bom.as_slice(), b"x\n1\n2.5\n"].concat();
    let spec = [bom.as_slice(), GAIN].concat();
    for (spec, csv) in [(GAIN, csv.as_slice()), (spec.as_slice(), csv.as_slice())] {
        let (code, text, err) = simulate(spec, csv);
        assert_eq!(code, 0, "{err}");
        assert_eq!(text, "x,y\n1,2\n2.5,5\n");
    }
}

#[test]
fn bytes_that_are_not_utf8_are_an_error_naming_the_place() {
    let (code, text, err) = simulate(GAIN, b"x\n1\n\xff\xfe2\n");
    assert_eq!((code, text.as_str()), (1, ""), "{err}");
    assert!(err.contains("in.csv") && err.contains("row 2"), "{err}");
    assert!(err.contains("UTF-8"), "{err}");

    let (code, _, err) = simulate(b"{\"type\": \"gain\", \"k\": \xff1}", b"x\n1\n");
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("m.json") && err.contains("UTF-8"), "{err}");
}

/// A delimiter between the two bytes of one character (`\xd4,\xab` is `ԫ`
/// once the comma is gone): each field is invalid UTF-8 although the
/// concatenation is valid. In the header and in a row it is an error naming
/// the place, not a slicing panic (the `csv_read` fuzz target's finds, kept
/// in `fuzz/regressions/csv_read/`).
#[test]
fn a_delimiter_inside_a_character_is_an_error_not_a_panic() {
    for (csv, place) in [
        (&b"x,\xd4,\xab\n1,2,3\n"[..], "header"),
        (&b"x,q\n1,2\n\xcd,\xbf\n"[..], "row 2"),
    ] {
        let (code, text, err) = simulate(GAIN, csv);
        assert_eq!((code, text.as_str()), (1, ""), "{err}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(err.contains("in.csv") && err.contains(place), "{err}");
        assert!(err.contains("ends inside a multi-byte character"), "{err}");
    }
}
