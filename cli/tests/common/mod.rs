//! Helpers shared by the end-to-end CLI tests.
#![allow(dead_code)] // each test crate uses a subset

use assert_cmd::Command;
use std::fs;
use std::path::{Path, PathBuf};

/// The `hysteron` binary, run in `dir`.
pub fn hysteron(dir: &Path) -> Command {
    let mut cmd = Command::cargo_bin("hysteron").expect("binary built");
    cmd.current_dir(dir);
    cmd
}

/// A well-formed SVG with lines and labels.
pub fn assert_svg(path: &Path) {
    let svg = fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(svg.starts_with("<svg"), "{}", path.display());
    assert!(svg.trim_end().ends_with("</svg>"), "{}", path.display());
    assert!(svg.contains("<polyline"), "{}: no lines", path.display());
    assert!(svg.contains("<text"), "{}: no labels", path.display());
    // Well-formed enough: every opened element is closed (plotters writes
    // only self-closing elements besides <svg> and <text>).
    assert_eq!(svg.matches("<text").count(), svg.matches("</text>").count());
}

/// No temporary files left behind by atomic writes.
pub fn assert_no_temp_files(dir: &Path) {
    for e in fs::read_dir(dir).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!name.starts_with(".hysteron-"), "leftover {name}");
    }
}

/// All files in `dir` (recursively) with their contents.
pub fn snapshot(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.push((p.clone(), fs::read(&p).unwrap()));
            }
        }
    }
    out.sort();
    out
}

/// The error text, checked to be exactly one line `error: ...` with no
/// panic message.
pub fn one_line_error(stderr: &[u8]) -> String {
    let s = String::from_utf8(stderr.to_vec()).unwrap();
    assert!(!s.contains("panicked"), "panic: {s}");
    assert!(s.starts_with("error: "), "{s}");
    assert!(
        s.ends_with('\n') && s.lines().count() == 1,
        "not one line: {s:?}"
    );
    s.trim_end().to_string()
}
