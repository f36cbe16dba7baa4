//! The front door's rules: README.md stays short, the documentation speaks
//! of the library only, every relative link resolves, every chapter is in
//! the guide's table of contents, and every chapter that holds Rust is
//! compiled as a doctest (`src/lib.rs`, module `guide`), and every test
//! the documentation cites exists.

use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Every markdown file under `dir`, recursively, sorted.
fn markdown_under(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "md") {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

/// README.md, the guide's chapters, and the top-level documents the guide
/// includes.
fn documents() -> Vec<PathBuf> {
    let mut docs = vec![root().join("README.md")];
    docs.extend(markdown_under(&root().join("docs")));
    for top in ["CONTRIBUTING.md", "DESIGN.md", "CHANGELOG.md"] {
        docs.push(root().join(top));
    }
    docs
}

/// The text outside fenced code blocks, line by line with line numbers.
fn prose(text: &str) -> Vec<(usize, &str)> {
    let mut fenced = false;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if !fenced {
            out.push((i + 1, line));
        }
    }
    out
}

/// The targets of the markdown links `[text](target)` and images of a
/// line, outside inline code.
fn links(line: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut in_code = false;
    let bytes = line.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'`' => in_code = !in_code,
            b']' if !in_code && bytes.get(i + 1) == Some(&b'(') => {
                if let Some(end) = line[i + 2..].find(')') {
                    out.push(&line[i + 2..i + 2 + end]);
                    i += 2 + end;
                }
            }
            _ => {}
        }
        i += 1;
    }
    out
}

/// The anchor mdBook and GitHub give a heading: lower case, spaces to
/// `-`, other punctuation dropped.
fn anchor(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

#[test]
fn readme_fits_on_a_few_screens() {
    let lines = read(&root().join("README.md")).lines().count();
    assert!(lines <= 200, "README.md has {lines} lines (at most 200)");
}

#[test]
fn the_documentation_speaks_of_the_library_only() {
    let banned = ["session", "../shared", "/work/"];
    let mut found = Vec::new();
    for path in
        std::iter::once(root().join("README.md")).chain(markdown_under(&root().join("docs")))
    {
        for (n, line) in read(&path).lines().enumerate() {
            let lower = line.to_lowercase();
            for word in banned {
                if lower.contains(word) {
                    found.push(format!("{}:{}: {word}", path.display(), n + 1));
                }
            }
        }
    }
    assert!(found.is_empty(), "{found:#?}");
}

#[test]
fn every_relative_link_resolves() {
    let mut broken = Vec::new();
    for path in documents() {
        let text = read(&path);
        let dir = path.parent().unwrap();
        for (n, line) in prose(&text) {
            for target in links(line) {
                let target = target.split_whitespace().next().unwrap_or("");
                if target.is_empty()
                    || target.starts_with("http://")
                    || target.starts_with("https://")
                    || target.starts_with("mailto:")
                {
                    continue;
                }
                let (file, fragment) = target.split_once('#').unwrap_or((target, ""));
                let file_path = if file.is_empty() {
                    path.clone()
                } else {
                    dir.join(file)
                };
                let at = format!("{}:{n}: {target}", path.display());
                if !file_path.exists() {
                    broken.push(format!("{at} (no such file)"));
                    continue;
                }
                if !fragment.is_empty() && file_path.extension().is_some_and(|e| e == "md") {
                    let headings: Vec<String> = prose(&read(&file_path))
                        .into_iter()
                        .filter_map(|(_, l)| l.strip_prefix('#'))
                        .map(|l| anchor(l.trim_start_matches('#')))
                        .collect();
                    if !headings.iter().any(|h| h == fragment) {
                        broken.push(format!("{at} (no such heading)"));
                    }
                }
            }
        }
    }
    assert!(broken.is_empty(), "{broken:#?}");
}

#[test]
fn links_are_checked_by_the_link_rules() {
    assert_eq!(
        links("see [a](b.md#c) and ![f](figures/x.svg), not `[x](y)`"),
        vec!["b.md#c", "figures/x.svg"]
    );
    assert_eq!(anchor(" Units and time"), "units-and-time");
    assert_eq!(
        anchor("The paper's model, step by step"),
        "the-papers-model-step-by-step"
    );
}

#[test]
fn every_chapter_is_in_the_table_of_contents() {
    let docs = root().join("docs");
    let summary = read(&docs.join("SUMMARY.md"));
    let listed: Vec<&str> = prose(&summary)
        .into_iter()
        .flat_map(|(_, l)| links(l))
        .collect();
    let missing: Vec<String> = markdown_under(&docs)
        .into_iter()
        .map(|p| {
            p.strip_prefix(&docs)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/")
        })
        .filter(|p| p != "SUMMARY.md" && !listed.contains(&p.as_str()))
        .collect();
    assert!(missing.is_empty(), "not in docs/SUMMARY.md: {missing:?}");
}

#[test]
fn every_chapter_with_rust_is_a_doctest() {
    let lib = read(&root().join("src/lib.rs"));
    for path in markdown_under(&root().join("docs")) {
        let text = read(&path);
        let has_rust = text.lines().any(|l| {
            let l = l.trim_start();
            l.starts_with("```rust") && !l.contains("ignore")
        });
        let rel = path
            .strip_prefix(root())
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        if has_rust {
            assert!(
                lib.contains(&format!("include_str!(\"../{rel}\")")),
                "{rel} holds Rust but is not included in src/lib.rs's `guide` module"
            );
        }
        // a fenced block without a language would be compiled as Rust by
        // rustdoc but shown as plain text by the guide
        let mut fenced = false;
        for (n, line) in text.lines().enumerate() {
            let t = line.trim_start();
            if t.starts_with("```") {
                if !fenced {
                    assert!(
                        t.len() > 3,
                        "{rel}:{}: a code block without a language",
                        n + 1
                    );
                }
                fenced = !fenced;
            }
        }
    }
}

/// The backticked spans of `line`.
fn code_spans(line: &str) -> Vec<&str> {
    line.split('`').skip(1).step_by(2).collect()
}

/// Every test or function the documentation cites as `path.rs::name` or
/// `path.py::name` (or `::name` after such a citation on the same line)
/// exists: its file defines `fn name` or `def name`. The changelog,
/// which records names as they were, is left out.
#[test]
fn every_cited_test_exists() {
    let mut missing = Vec::new();
    for doc in documents().iter().filter(|d| !d.ends_with("CHANGELOG.md")) {
        let text = read(doc);
        for (n, line) in prose(&text) {
            let mut file: Option<&str> = None;
            for span in code_spans(line) {
                let (path, name) = match span.split_once("::") {
                    Some(("", name)) => match file {
                        Some(path) => (path, name),
                        None => continue,
                    },
                    Some((path, name)) if path.ends_with(".rs") || path.ends_with(".py") => {
                        file = Some(path);
                        (path, name)
                    }
                    _ => continue,
                };
                if !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                    continue;
                }
                let source = std::fs::read_to_string(root().join(path)).unwrap_or_default();
                if !source.contains(&format!("fn {name}"))
                    && !source.contains(&format!("def {name}"))
                {
                    missing.push(format!("{}:{n}: `{path}::{name}`", doc.display()));
                }
            }
        }
    }
    assert!(
        missing.is_empty(),
        "cited but not defined:\n{}",
        missing.join("\n")
    );
}
