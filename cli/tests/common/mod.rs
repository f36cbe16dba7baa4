//! Helpers shared by the end-to-end CLI tests.
#![allow(dead_code, unused_macros)] // each test crate uses a subset

use assert_cmd::Command;
use std::fs;
use std::path::{Path, PathBuf};
use tempfile::TempDir;

/// The standard output of a finished command, as text.
pub fn stdout_of(assert: &assert_cmd::assert::Assert) -> String {
    String::from_utf8(assert.get_output().stdout.clone()).expect("stdout is UTF-8")
}

/// The `hysteron` binary, run in `dir`.
pub fn hysteron(dir: &Path) -> Command {
    let mut cmd = Command::cargo_bin("hysteron").expect("binary built");
    cmd.current_dir(dir);
    cmd
}

/// Runs `cmd` expecting success and a standard output that contains every
/// `expect`ed fragment. Returns the standard output.
pub fn succeeds_saying(cmd: &mut Command, expect: &[&str]) -> String {
    let stdout = stdout_of(&cmd.assert().success());
    for e in expect {
        assert!(stdout.contains(e), "`{e}` not in: {stdout}");
    }
    stdout
}

/// Runs `cmd` expecting success, then reads the CSV file it wrote at
/// `path`: its header and records, as [`read_csv`] gives them.
pub fn succeeds_writing_csv(cmd: &mut Command, path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    cmd.assert().success();
    read_csv(path)
}

/// Runs `cmd` expecting success, then reads the CSV file it wrote at
/// `path`, checking its header is `t,x,y`: returns the `x` and `y` columns.
pub fn succeeds_writing_txy(cmd: &mut Command, path: &Path) -> (Vec<f64>, Vec<f64>) {
    let (headers, rows) = succeeds_writing_csv(cmd, path);
    assert_eq!(headers, ["t", "x", "y"], "{}", path.display());
    (column(&headers, &rows, "x"), column(&headers, &rows, "y"))
}

/// Two cycles of a sine of amplitude 1.2 in `samples` samples, as the text
/// of a CSV file with columns `i,x`, and the `x` values.
pub fn two_sine_cycles(samples: usize) -> (String, Vec<f64>) {
    let x: Vec<f64> = (0..samples)
        .map(|i| 1.2 * (std::f64::consts::TAU * 2.0 * i as f64 / samples as f64).sin())
        .collect();
    let mut text = String::from("i,x\n");
    for (i, v) in x.iter().enumerate() {
        text.push_str(&format!("{i},{v}\n"));
    }
    (text, x)
}

/// Runs `cmd` expecting the exit code `code`: its standard output and
/// standard error, as text.
pub fn exits_with(cmd: &mut Command, code: i32) -> (String, String) {
    let out = cmd.assert().code(code).get_output().clone();
    (
        String::from_utf8(out.stdout).expect("stdout is UTF-8"),
        String::from_utf8(out.stderr).expect("stderr is UTF-8"),
    )
}

/// Three names of the file `name` in `dir`: as it is, `./name` and
/// `sub/../name` (the subdirectory `sub` is made here).
pub fn spellings_of(dir: &Path, name: &str) -> [String; 3] {
    fs::create_dir(dir.join("sub")).unwrap();
    [
        name.to_string(),
        format!("./{name}"),
        format!("sub/../{name}"),
    ]
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
    one_line_error_in("", stderr)
}

/// [`one_line_error`], each message starting with `context` (which case
/// it is).
pub fn one_line_error_in(context: &str, stderr: &[u8]) -> String {
    let s = String::from_utf8(stderr.to_vec()).unwrap();
    assert!(!s.contains("panicked"), "{context}panic: {s}");
    assert!(s.starts_with("error: "), "{context}{s}");
    assert!(
        s.ends_with('\n') && s.lines().count() == 1,
        "{context}not one line: {s:?}"
    );
    s.trim_end().to_string()
}

/// The header and the records of a CSV file, as text.
pub fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut r = csv::Reader::from_path(path).expect("readable CSV");
    let headers = r.headers().unwrap().iter().map(String::from).collect();
    let rows = r
        .records()
        .map(|rec| rec.unwrap().iter().map(String::from).collect())
        .collect();
    (headers, rows)
}

/// The column `name` of a table read by [`read_csv`], as numbers.
pub fn column(headers: &[String], rows: &[Vec<String>], name: &str) -> Vec<f64> {
    let i = headers.iter().position(|h| h == name).expect("column");
    rows.iter().map(|r| r[i].parse().unwrap()).collect()
}

/// Runs `cmd` in `dir` expecting failure: exit code 1, one line on stderr
/// starting with `error:` and containing every `expect`ed fragment, nothing
/// on stdout, all files in `dir` unchanged and no new file (in particular no
/// output and no temporary file). Returns the error line. Every message
/// names the command.
pub fn fails_leaving_dir_unchanged(dir: &Path, cmd: &mut Command, expect: &[&str]) -> String {
    let context = format!("{cmd:?}: ");
    let before = snapshot(dir);
    let assert = cmd.assert().failure().code(1);
    let out = assert.get_output();
    let stderr = one_line_error_in(&context, &out.stderr);
    assert!(out.stdout.is_empty(), "{context}stdout: {:?}", out.stdout);
    for e in expect {
        assert!(stderr.contains(e), "{context}`{e}` not in: {stderr}");
    }
    assert_eq!(
        snapshot(dir),
        before,
        "{context}files changed by a failed run"
    );
    stderr
}

/// Runs `hysteron simulate --model MODEL --input INPUT --output OUTPUT`
/// (anywhere: the paths say where): its exit code and stderr.
pub fn simulate_files(model: &Path, input: &Path, output: &Path) -> (i32, String) {
    let out = Command::cargo_bin("hysteron")
        .expect("the hysteron binary")
        .arg("simulate")
        .arg("--model")
        .arg(model)
        .arg("--input")
        .arg(input)
        .arg("--output")
        .arg(output)
        .output()
        .expect("run");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Runs `cmd` expecting an argument error: exit code 1 and stderr starting
/// with `error: ` and containing `expected`. Returns stderr.
pub fn usage_error(cmd: &mut Command, expected: &str) -> String {
    let assert = cmd.assert().failure().code(1);
    let err = String::from_utf8_lossy(&assert.get_output().stderr).into_owned();
    assert!(
        err.starts_with("error: ") && err.contains(expected),
        "{cmd:?}: {err}"
    );
    err
}

/// Implements [`InTempDir`] for a setup struct that holds its directory in
/// its field `tmp`.
macro_rules! in_temp_dir {
    ($setup:ty) => {
        impl InTempDir for $setup {
            fn tmp(&self) -> &TempDir {
                &self.tmp
            }
        }
    };
}
#[allow(unused_imports)] // each test crate uses a subset
pub(crate) use in_temp_dir;

/// A test setup that owns a temporary directory: shortcuts to its files.
pub trait InTempDir {
    /// The directory.
    fn tmp(&self) -> &TempDir;

    /// Its path (where the commands run).
    fn dir(&self) -> &Path {
        self.tmp().path()
    }

    /// The path of the file `name` in it.
    fn path(&self, name: &str) -> PathBuf {
        self.dir().join(name)
    }

    /// Writes `contents` to the file `name` in it.
    fn write(&self, name: &str, contents: &str) {
        fs::write(self.path(name), contents).unwrap();
    }
}

/// A bare temporary directory is a setup of its own.
impl InTempDir for TempDir {
    fn tmp(&self) -> &TempDir {
        self
    }
}
