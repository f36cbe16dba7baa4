//! The guide's reference figures (`docs/reference/figures/`) are what
//! `hysteron operators --figures` draws now: one loop per registered
//! operator and combinator, byte for byte, and no figure of an operator
//! that left the registry (`bash scripts/generate.sh` draws them anew).

mod common;

use common::{assert_no_temp_files, assert_svg, hysteron};
use std::fs;
use std::path::Path;
use tempfile::TempDir;

fn names(dir: &Path) -> Vec<String> {
    let mut out: Vec<String> = fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    out.sort();
    out
}

#[test]
fn the_committed_figures_are_what_the_cli_draws() {
    let tmp = TempDir::new().unwrap();
    let out = tmp.path().join("figures");
    hysteron(tmp.path())
        .args(["operators", "--figures", "figures"])
        .assert()
        .success();
    let committed = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/reference/figures");
    let drawn = names(&out);
    assert!(drawn.len() >= 28, "{drawn:?}");
    assert_eq!(names(&committed), drawn, "run `bash scripts/generate.sh`");
    for name in &drawn {
        assert_svg(&out.join(name));
        assert!(
            fs::read(out.join(name)).unwrap() == fs::read(committed.join(name)).unwrap(),
            "docs/reference/figures/{name} differs from what the CLI draws: run `bash scripts/generate.sh`"
        );
    }
    assert_no_temp_files(&out);
}

#[test]
fn a_figure_directory_that_cannot_be_made_is_an_error_naming_it() {
    let tmp = TempDir::new().unwrap();
    fs::write(tmp.path().join("taken"), "a file").unwrap();
    let out = hysteron(tmp.path())
        .args(["operators", "--figures", "taken/figures"])
        .assert()
        .code(1)
        .get_output()
        .stderr
        .clone();
    let err = String::from_utf8_lossy(&out);
    assert!(err.contains("taken/figures"), "{err}");
}
