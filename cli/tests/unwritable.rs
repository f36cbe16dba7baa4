//! An output that cannot be written (a directory, a read-only file
//! system) is an error naming it, exit code 1, with nothing left behind.

use std::fs;
use tempfile::TempDir;

mod common;
use common::simulate_files;

/// `simulate` of a gain on a two-row CSV into `output`: exit code and
/// stderr.
fn simulate_into(dir: &TempDir, output: &std::path::Path) -> (i32, String) {
    let (model, input) = (dir.path().join("m.json"), dir.path().join("in.csv"));
    fs::write(&model, r#"{"type": "gain", "k": 2.0}"#).expect("spec");
    fs::write(&input, "x\n1\n2\n").expect("csv");
    simulate_files(&model, &input, output)
}

#[test]
fn an_output_that_is_a_directory_is_an_error_naming_it() {
    let dir = TempDir::new().expect("tempdir");
    let target = dir.path().join("out");
    fs::create_dir(&target).expect("mkdir");
    let (code, err) = simulate_into(&dir, &target);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("output `") && err.contains("out`"), "{err}");
    assert!(err.lines().count() == 1, "one line: {err}");
    // Nothing was written beside it.
    let names: Vec<_> = fs::read_dir(dir.path()).expect("ls").flatten().collect();
    assert_eq!(names.len(), 3, "{names:?}");
}

#[test]
fn an_output_on_a_read_only_file_system_is_an_error_naming_it() {
    // /proc accepts no new files, even for root (Linux).
    if !std::path::Path::new("/proc/self").exists() {
        return;
    }
    let dir = TempDir::new().expect("tempdir");
    let (code, err) = simulate_into(&dir, std::path::Path::new("/proc/hysteron-out.csv"));
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("output `/proc/hysteron-out.csv`"), "{err}");
}
