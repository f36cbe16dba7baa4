//! The modules of this crate import each other without circles: no module
//! imports one that imports it back, at any distance. The options, the
//! record, the error and the report's types import nothing else of the
//! crate but the options. Imports name the module that defines an item
//! (`crate::fit::fit`), never the crate root's re-export, so the graph read
//! here is the real one.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic
)]

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// `module path → source`, for every file under `src/` but `lib.rs`.
fn modules() -> BTreeMap<String, String> {
    fn walk(dir: &Path, prefix: &str, out: &mut BTreeMap<String, String>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            let stem = path.file_stem().unwrap().to_str().unwrap().to_string();
            if path.is_dir() {
                walk(&path, &format!("{prefix}{stem}::"), out);
            } else if stem == "mod" {
                out.insert(
                    prefix.trim_end_matches("::").to_string(),
                    std::fs::read_to_string(&path).unwrap(),
                );
            } else if !(prefix.is_empty() && stem == "lib") {
                out.insert(
                    format!("{prefix}{stem}"),
                    std::fs::read_to_string(&path).unwrap(),
                );
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        "",
        &mut out,
    );
    out
}

/// The modules `source` (the module `name`) refers to outside comments:
/// by `crate::…`, by `super::…` (its parent; `super::*` in an inline test
/// module is the module itself), or by a path that starts with one of its
/// own submodules (`use plan::Layout`); `Err` names a path through the
/// crate root that is not a module.
fn imports(
    name: &str,
    source: &str,
    all: &BTreeMap<String, String>,
) -> Result<BTreeSet<String>, String> {
    let parent = name.rsplit_once("::").map_or("", |(p, _)| p);
    let mut found = BTreeSet::new();
    for line in source.lines() {
        let code = line.split("//").next().unwrap_or("");
        let code = code.trim();
        if code.starts_with("use super::*") {
            continue;
        }
        if let Some(rest) = code
            .strip_prefix("pub(crate) use ")
            .or_else(|| code.strip_prefix("pub use "))
            .or_else(|| code.strip_prefix("use "))
        {
            let first = rest.split("::").next().unwrap_or("");
            let child = format!("{name}::{first}");
            if all.contains_key(&child) {
                found.insert(child);
            }
        }
        for (start, base) in [("crate::", String::new()), ("super::", parent.to_string())] {
            for (at, _) in code.match_indices(start) {
                let rest = &code[at + start.len()..];
                let path: Vec<&str> = rest
                    .split(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
                    .next()
                    .unwrap_or("")
                    .split("::")
                    .filter(|s| !s.is_empty())
                    .collect();
                // the longest prefix of the path that is a module
                let mut module = base.clone();
                for seg in &path {
                    let next = if module.is_empty() {
                        seg.to_string()
                    } else {
                        format!("{module}::{seg}")
                    };
                    if all.contains_key(&next) {
                        module = next;
                    } else {
                        break;
                    }
                }
                if module.is_empty() {
                    if start == "crate::" && !path.is_empty() {
                        return Err(format!(
                            "{name}: `crate::{}` goes through the crate root; name the module",
                            path.join("::")
                        ));
                    }
                } else if module != name {
                    found.insert(module);
                }
            }
        }
    }
    Ok(found)
}

fn graph() -> BTreeMap<String, BTreeSet<String>> {
    let all = modules();
    all.iter()
        .map(|(name, source)| {
            let to = imports(name, source, &all).unwrap_or_else(|e| panic!("{e}"));
            (name.clone(), to)
        })
        .collect()
}

#[test]
fn no_module_imports_one_that_imports_it_back() {
    let graph = graph();
    assert!(graph.len() >= 15, "{:?}", graph.keys());
    // depth-first search for a cycle, reporting it
    fn visit(
        node: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) {
        if let Some(i) = path.iter().position(|n| n == node) {
            panic!("import circle: {} → {node}", path[i..].join(" → "));
        }
        if done.contains(node) {
            return;
        }
        path.push(node.to_string());
        for next in graph.get(node).into_iter().flatten() {
            visit(next, graph, path, done);
        }
        path.pop();
        done.insert(node.to_string());
    }
    let mut done = BTreeSet::new();
    for node in graph.keys() {
        visit(node, &graph, &mut Vec::new(), &mut done);
    }
}

#[test]
fn options_and_public_types_import_nothing_else_of_the_crate() {
    let graph = graph();
    for (module, allowed) in [
        ("options", &[][..]),
        ("record", &[]),
        ("error", &[]),
        ("outcome", &["options"]),
    ] {
        let to: Vec<&String> = graph[module]
            .iter()
            .filter(|m| !allowed.contains(&m.as_str()))
            .collect();
        assert!(to.is_empty(), "{module} imports {to:?}");
    }
}

/// The check reads a circle where there is one.
#[test]
fn a_circle_is_seen() {
    let mut all = BTreeMap::new();
    all.insert("a".to_string(), "use crate::b::X;".to_string());
    all.insert("b".to_string(), "use crate::a::Y; // crate::c".to_string());
    assert_eq!(
        imports("b", &all["b"], &all).unwrap(),
        BTreeSet::from(["a".to_string()])
    );
    assert!(imports("a", "use crate::Fit;", &all).is_err());
    // a submodule used by its parent, and the parent by the submodule
    all.insert("a::c".to_string(), "use super::Z;".to_string());
    assert_eq!(
        imports("a", "mod c;\npub(crate) use c::W;\nuse super::*;", &all).unwrap(),
        BTreeSet::from(["a::c".to_string()])
    );
    assert_eq!(
        imports("a::c", &all["a::c"], &all).unwrap(),
        BTreeSet::from(["a".to_string()])
    );
}
