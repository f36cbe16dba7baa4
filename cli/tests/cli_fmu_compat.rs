//! End-to-end tests of `hysteron fmu-compat`: the folder layout and files
//! of the compatibility information (with a stand-in FMU binary: the
//! FMUs themselves are simulated by capi/checks/test_fmu_compat.py), and
//! bad arguments as one-line errors with exit code 1.

use std::fs;
use std::path::Path;
use tempfile::TempDir;

mod common;
use common::*;

/// A file that passes for the FMU binary (export-fmu checks the ELF magic).
fn stand_in_library(dir: &Path) -> String {
    let path = dir.join("libhysteron_c.so");
    fs::write(&path, b"\x7fELF not really a library").unwrap();
    path.to_string_lossy().into_owned()
}

#[test]
fn writes_each_model_and_version_in_the_cross_check_layout() {
    if !(cfg!(target_os = "linux") && cfg!(target_arch = "x86_64")) {
        return;
    }
    let dir = TempDir::new().unwrap();
    let library = stand_in_library(dir.path());
    let out = succeeds_saying(
        hysteron(dir.path()).args(["fmu-compat", "compat", "--library", &library]),
        &["wrote 4 FMUs"],
    );
    let version = env!("CARGO_PKG_VERSION");
    for (fmi, platform) in [("2.0", "linux64"), ("3.0", "x86_64-linux")] {
        for model in ["PaperModel", "BoucWenBenchmark"] {
            let rel = format!("{fmi}/cs/{platform}/hysteron/{version}/{model}");
            assert!(out.contains(&rel), "{rel}: {out}");
            let folder = dir.path().join("compat/fmus").join(&rel);
            let mut names: Vec<String> = fs::read_dir(&folder)
                .unwrap()
                .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect();
            names.sort();
            let mut want = vec![
                "ReadMe.md".to_string(),
                format!("{model}.fmu"),
                format!("{model}_in.csv"),
                format!("{model}_ref.csv"),
                format!("{model}_ref.opt"),
            ];
            want.sort();
            assert_eq!(names, want);
            let read = |suffix: &str| fs::read_to_string(folder.join(format!("{model}{suffix}")));
            let opt = read("_ref.opt").unwrap();
            let keys: Vec<&str> = opt.lines().map(|l| l.split(',').next().unwrap()).collect();
            assert_eq!(keys, ["StartTime", "StopTime", "StepSize", "RelTol"]);
            for (suffix, header) in [
                ("_in.csv", "\"time\",\"x\""),
                ("_ref.csv", "\"time\",\"y\""),
            ] {
                let text = read(suffix).unwrap();
                assert_eq!(text.lines().next(), Some(header));
                assert_eq!(text.lines().count(), 1002, "{model}{suffix}");
            }
            let readme = fs::read_to_string(folder.join("ReadMe.md")).unwrap();
            assert!(
                readme.contains(&format!("from hysteron {version}")),
                "{readme}"
            );
        }
    }
}

#[test]
fn bad_arguments_are_one_line_errors() {
    let dir = TempDir::new().unwrap();
    let library = stand_in_library(dir.path());
    let (_, err) = exits_with(
        hysteron(dir.path()).args(["fmu-compat", "out", "--fmi", "4"]),
        1,
    );
    assert!(
        err.contains("invalid value '4' for '--fmi <VERSION>'"),
        "{err}"
    );
    assert!(err.contains("[possible values: 2, 3]"), "{err}");
    assert!(!dir.path().join("out").exists());

    // The one-line error of `fmu-compat OUT_DIR --library LIBRARY`.
    let fails = |out_dir: &str, library: &str| {
        let run = hysteron(dir.path())
            .args(["fmu-compat", out_dir, "--library", library])
            .assert()
            .code(1);
        one_line_error(&run.get_output().stderr)
    };
    // /proc accepts no new folders, even for root (Linux).
    if Path::new("/proc/self").exists() {
        let err = fails("/proc/hysteron-compat", &library);
        assert!(
            err.contains("cannot create the folder `/proc/hysteron-compat/fmus`"),
            "{err}"
        );
    }
    fs::write(dir.path().join("a-file"), "").unwrap();
    let err = fails("a-file", &library);
    assert!(
        err.contains("cannot create the folder `a-file/fmus`"),
        "{err}"
    );
    let err = fails("out", "missing.so");
    assert!(
        err.contains("missing.so") && err.contains("--library"),
        "{err}"
    );
}
