//! The files that say what the registry knows (the operator tables of
//! README.md and of the crates' front pages, the Python constructors'
//! imports, names and stubs) hold exactly what
//! `hysteron::models::spec::reference` renders from the registry now.
//! `bash scripts/generate.sh` writes them anew (it runs this test with
//! `HYSTERON_REGENERATE=1`).

use hysteron::models::spec::reference;
use std::path::Path;

/// Where generated text goes: a whole file, or the lines between a line
/// holding `BEGIN generated: NAME` and one holding `END generated: NAME`.
struct Target {
    path: &'static str,
    region: Option<&'static str>,
    text: String,
}

fn targets() -> Vec<Target> {
    let names = reference::python_names();
    let imports: String = std::iter::once("from ._operators import (\n".to_string())
        .chain(names.iter().map(|n| format!("    {n},\n")))
        .chain(std::iter::once(")\n".to_string()))
        .collect();
    let all: String = names.iter().map(|n| format!("    \"{n}\",\n")).collect();
    let target = |path, region, text| Target { path, region, text };
    vec![
        target("README.md", Some("leaves"), reference::leaf_table()),
        target(
            "README.md",
            Some("combinators"),
            reference::combinator_table(),
        ),
        target(
            "operators/src/lib.rs",
            Some("operators"),
            reference::rustdoc_table("hysteron_operators"),
        ),
        target("src/lib.rs", Some("spec types"), reference::facade_list()),
        target(
            "python/hysteron_rs/_operators.pyi",
            None,
            reference::python_stubs(),
        ),
        target(
            "python/hysteron_rs/__init__.py",
            Some("constructors"),
            imports,
        ),
        target(
            "python/hysteron_rs/__init__.py",
            Some("constructor names"),
            all,
        ),
    ]
}

/// `text` with the region `name` holding `content`; `None` if the
/// markers are missing.
fn with_region(text: &str, name: &str, content: &str) -> Option<String> {
    let begin = text
        .find(&format!("BEGIN generated: {name} "))
        .or_else(|| text.find(&format!("BEGIN generated: {name}\n")))?;
    let start = begin + text[begin..].find('\n')? + 1;
    let end_marker = text[start..].find(&format!("END generated: {name}"))? + start;
    let end = text[..end_marker].rfind('\n').map_or(0, |i| i + 1);
    if end < start {
        return None;
    }
    Some(format!("{}{content}{}", &text[..start], &text[end..]))
}

#[test]
fn regions_are_replaced_between_their_markers() {
    let text = "a\n<!-- BEGIN generated: x (how) -->\nold\n<!-- END generated: x -->\nb\n";
    assert_eq!(
        with_region(text, "x", "new\n").unwrap(),
        "a\n<!-- BEGIN generated: x (how) -->\nnew\n<!-- END generated: x -->\nb\n"
    );
    assert_eq!(with_region(text, "y", "new\n"), None);
    // a file edited by hand in its generated part differs from the render
    let edited = with_region(text, "x", "by hand\n").unwrap();
    assert_ne!(with_region(&edited, "x", "new\n").unwrap(), edited);
}

#[test]
fn generated_files_match_the_registry() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let regenerate = std::env::var_os("HYSTERON_REGENERATE").is_some();
    let mut stale = Vec::new();
    let mut files: Vec<(&str, String, String)> = Vec::new();
    for t in targets() {
        if !files.iter().any(|(p, _, _)| *p == t.path) {
            let text = std::fs::read_to_string(root.join(t.path)).unwrap();
            files.push((t.path, text.clone(), text));
        }
        let Some(file) = files.iter_mut().find(|(p, _, _)| *p == t.path) else {
            unreachable!()
        };
        file.2 = match t.region {
            None => t.text,
            Some(name) => with_region(&file.2, name, &t.text)
                .unwrap_or_else(|| panic!("{}: no region `{name}`", t.path)),
        };
    }
    for (path, old, new) in files {
        if old != new {
            if regenerate {
                std::fs::write(root.join(path), new).unwrap();
            } else {
                stale.push(path);
            }
        }
    }
    assert!(
        stale.is_empty(),
        "generated text differs from the registry in {stale:?}: run `bash scripts/generate.sh`"
    );
}
