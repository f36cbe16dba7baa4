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
    path: String,
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
    let target = |path: &str, region, text| Target {
        path: path.to_string(),
        region,
        text,
    };
    let pages = reference::reference_pages()
        .into_iter()
        .map(|(name, text)| Target {
            path: format!("{REFERENCE}/{name}"),
            region: None,
            text,
        });
    let mut all_targets = vec![
        target("README.md", Some("leaves"), reference::leaf_table()),
        target(
            "README.md",
            Some("combinators"),
            reference::combinator_table(),
        ),
        target("docs/operators.md", Some("leaves"), reference::leaf_table()),
        target(
            "docs/composing.md",
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
        target(
            "docs/SUMMARY.md",
            Some("reference"),
            reference::summary_entries(),
        ),
    ];
    all_targets.extend(pages);
    all_targets
}

/// The folder of the generated reference pages.
const REFERENCE: &str = "docs/reference";

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
    let mut files: Vec<(String, String, String)> = Vec::new();
    for t in targets() {
        if !files.iter().any(|(p, _, _)| *p == t.path) {
            // a page of a new leaf does not exist yet: it is stale
            let text = std::fs::read_to_string(root.join(&t.path)).unwrap_or_default();
            files.push((t.path.clone(), text.clone(), text));
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
                if let Some(dir) = root.join(&path).parent() {
                    std::fs::create_dir_all(dir).unwrap();
                }
                std::fs::write(root.join(&path), new).unwrap();
            } else {
                stale.push(path);
            }
        }
    }
    // a page whose operator left the registry
    let generated: Vec<String> = reference::reference_pages()
        .into_iter()
        .map(|(name, _)| name)
        .collect();
    for entry in std::fs::read_dir(root.join(REFERENCE)).unwrap() {
        let entry = entry.unwrap();
        if entry.path().is_dir() {
            continue; // the figures, drawn by the CLI (cli/tests/reference_figures.rs)
        }
        let name = entry.file_name().to_string_lossy().into_owned();
        if !generated.contains(&name) {
            if regenerate {
                std::fs::remove_file(root.join(REFERENCE).join(&name)).unwrap();
            } else {
                stale.push(format!("{REFERENCE}/{name} (no such operator)"));
            }
        }
    }
    assert!(
        stale.is_empty(),
        "generated text differs from the registry in {stale:?}: run `bash scripts/generate.sh`"
    );
}

/// Every leaf's kind and parameter names are Python identifiers that are
/// not keywords: they become the Python constructors and their keyword
/// arguments (a parameter named `lambda` could not be passed).
#[test]
fn every_leaf_name_and_parameter_is_a_python_argument_name() {
    use hysteron::models::spec::registry::LEAVES;
    const KEYWORDS: [&str; 35] = [
        "False", "None", "True", "and", "as", "assert", "async", "await", "break", "class",
        "continue", "def", "del", "elif", "else", "except", "finally", "for", "from", "global",
        "if", "import", "in", "is", "lambda", "nonlocal", "not", "or", "pass", "raise", "return",
        "try", "while", "with", "yield",
    ];
    let usable = |name: &str| {
        let mut chars = name.chars();
        chars
            .next()
            .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
            && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
            && !KEYWORDS.contains(&name)
    };
    for leaf in LEAVES {
        assert!(usable(leaf.kind()), "the kind `{}`", leaf.kind());
        for f in leaf.fields() {
            assert!(
                usable(f.name),
                "{}: the parameter `{}`",
                leaf.kind(),
                f.name
            );
        }
    }
}

/// Every example spec of the reference (the leaves' pages and the
/// combinators') builds and runs a short signal to finite outputs.
#[test]
fn every_reference_example_builds_and_runs() {
    use hysteron::models::spec::registry::LEAVES;
    use hysteron::models::spec::COMBINATOR_LAWS;
    use hysteron::models::Spec;
    let x: Vec<f64> = (0..200).map(|i| (f64::from(i) * 0.05).sin()).collect();
    let specs =
        LEAVES
            .iter()
            .map(|l| (l.kind(), l.example_spec()))
            .chain(COMBINATOR_LAWS.iter().map(|c| {
                let spec = Spec::from_json(c.example).unwrap_or_else(|e| panic!("{}: {e}", c.kind));
                assert_eq!(spec.kind(), c.kind);
                (c.kind, spec)
            }));
    for (kind, spec) in specs {
        let mut model = spec.build().unwrap_or_else(|e| panic!("{kind}: {e}"));
        let y = model.run(&x).unwrap_or_else(|e| panic!("{kind}: {e}"));
        assert!(y.iter().all(|v| v.is_finite()), "{kind}");
    }
}

/// Each combinator documents exactly the fields its JSON example and its
/// summary name, and every field of its example is documented.
#[test]
fn every_combinator_field_is_documented() {
    use hysteron::models::spec::COMBINATOR_LAWS;
    for c in COMBINATOR_LAWS {
        let example: serde_json::Value = serde_json::from_str(c.example).unwrap();
        for key in example.as_object().unwrap().keys().filter(|k| *k != "type") {
            assert!(
                c.field_docs.iter().any(|(name, _)| name == key),
                "{}: `{key}` of the example is not documented",
                c.kind
            );
        }
        for (name, _) in c.field_docs {
            assert!(
                c.fields.contains(name),
                "{}: `{name}` not in `{}`",
                c.kind,
                c.fields
            );
        }
    }
}
