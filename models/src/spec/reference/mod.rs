//! The reference of every registered leaf and combinator, rendered from
//! the [`registry`](super::registry) and [`COMBINATOR_LAWS`]: the tables of
//! README.md and of the crates' front pages, the listing of `hysteron
//! operators`, the Python constructors' docstrings and stubs, the guide's
//! reference pages ([`reference_pages`]) and the spec's JSON Schema ([`json_schema`]). Nothing
//! of it is written by hand: the test `tests/generated.rs` compares the
//! committed files with what these functions render, and
//! `scripts/generate.sh` writes them anew.

use super::registry::{LeafKind, Omitted, LEAVES};
use super::{Combinator, COMBINATOR_LAWS};
use hysteron_operators::{FieldInfo, FieldKind};
use serde_json::Value;

mod pages;
mod schema;

pub use pages::{combinator_page, leaf_page, reference_index, reference_pages, summary_entries};
pub use schema::json_schema;

/// A JSON value as a reader writes it: numbers shortest, an array whose
/// entries are all equal as `v each`, an empty array as `none`.
fn value_text(v: &Value) -> String {
    match v {
        Value::Array(items) => match items.split_first() {
            None => "none".into(),
            Some((first, rest)) if rest.iter().all(|x| x == first) => {
                format!("{} each", value_text(first))
            }
            Some(_) => v.to_string(),
        },
        Value::Number(n) => match n.as_f64() {
            Some(f) if f == f.trunc() && f.abs() < 1e15 => format!("{}", f as i64),
            Some(f) => format!("{f}"),
            None => n.to_string(),
        },
        Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// Rust documentation as plain text, the doc comment's lines joined: a
/// link `[`x`](path)` or `[`x`]` outside code spans keeps its text;
/// brackets inside code (`[0, 1]`) stay.
pub fn plain(doc: &[&str]) -> String {
    let text = doc.iter().map(|l| l.trim()).collect::<Vec<_>>().join(" ");
    let mut out = String::with_capacity(text.len());
    let mut in_code = false;
    let mut rest = text.as_str();
    while let Some(c) = rest.chars().next() {
        if c == '`' {
            in_code = !in_code;
        }
        if c == '[' && !in_code {
            if let Some((label, tail)) = link(&rest[1..]) {
                out.push_str(label);
                rest = tail;
                continue;
            }
        }
        out.push(c);
        rest = &rest[c.len_utf8()..];
    }
    out
}

/// The label of a rustdoc link whose `[` was just passed, and the text
/// after the link: `[`x`](path)`, `[`x`]`, or `[x](path)`; `None` for
/// other brackets.
fn link(after: &str) -> Option<(&str, &str)> {
    let close = after.find(']')?;
    let (label, tail) = (&after[..close], &after[close + 1..]);
    if let Some(target) = tail.strip_prefix('(') {
        let end = target.find(')')?;
        return Some((label, &target[end + 1..]));
    }
    (label.starts_with('`') && label.ends_with('`') && label.len() > 1).then_some((label, tail))
}

/// Whether the declaration's example gives the field as an array.
pub(crate) fn is_vector(leaf: &dyn LeafKind, field: &str) -> bool {
    leaf.example().get(field).is_some_and(Value::is_array)
}

/// A field as a constraint: `r ≥ 0`, `k[i] > 0`, `y0` (real), `dt`.
fn constraint(leaf: &dyn LeafKind, f: &FieldInfo) -> String {
    let name = if is_vector(leaf, f.name) {
        format!("{}[i]", f.name)
    } else {
        f.name.to_string()
    };
    match f.kind {
        FieldKind::Param(hysteron_operators::Domain::Real) | FieldKind::Fixed => name,
        FieldKind::Param(d) => format!("{name} {d}"),
        FieldKind::Nested => format!("{name} {{…}}"),
    }
}

/// What leaving the field out means, as a short phrase (empty when it is
/// required).
pub(crate) fn omitted_text(leaf: &dyn LeafKind, f: &FieldInfo) -> String {
    match leaf.omitted(f.name) {
        Omitted::Required => String::new(),
        Omitted::Default(v) => format!("default {}", value_text(&v)),
        Omitted::FromData => "from the data if left out".into(),
    }
}

/// The parameters column of a table row: each field as a constraint, with
/// its default; a setting marked as such.
fn params_cell(leaf: &dyn LeafKind) -> String {
    leaf.fields()
        .iter()
        .map(|f| {
            let mut s = format!("`{}`", constraint(leaf, f));
            let mut notes = Vec::new();
            if f.kind == FieldKind::Fixed {
                notes.push("a setting".to_string());
            }
            let omitted = omitted_text(leaf, f);
            if !omitted.is_empty() {
                notes.push(omitted);
            }
            if !notes.is_empty() {
                s.push_str(&format!(" ({})", notes.join(", ")));
            }
            s
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// Text for a markdown table cell.
pub(crate) fn cell(s: &str) -> String {
    s.replace('|', "\\|")
}

/// The markdown table of every registered leaf: spec `type` (Rust type),
/// equation, parameters.
pub fn leaf_table() -> String {
    let mut out =
        String::from("| spec `type` (Rust type) | equation | parameters |\n|---|---|---|\n");
    for leaf in LEAVES {
        out.push_str(&format!(
            "| `{}` (`{}`) | `{}` | {} |\n",
            leaf.kind(),
            leaf.type_name(),
            cell(leaf.equation()),
            cell(&params_cell(*leaf)),
        ));
    }
    out
}

/// The markdown table of every combinator: spec `type` (Rust), law,
/// fields, solved.
pub fn combinator_table() -> String {
    let mut out =
        String::from("| spec `type` (Rust) | law | spec fields | solved |\n|---|---|---|---|\n");
    for Combinator {
        kind,
        rust,
        law,
        fields,
        implicit,
        ..
    } in COMBINATOR_LAWS
    {
        let solved = if *implicit {
            "implicit, per sample"
        } else {
            "explicit"
        };
        out.push_str(&format!(
            "| `{kind}` (`{rust}`) | `{}` | {} | {solved} |\n",
            cell(law),
            cell(fields)
        ));
    }
    out
}

/// The rustdoc table of the leaves a crate defines (`hysteron_operators`),
/// each linked to its type, as `//!` lines.
pub fn rustdoc_table(crate_name: &str) -> String {
    let mut out = String::from("//! | operator | spec `type` | equation |\n//! |---|---|---|\n");
    for leaf in LEAVES.iter().filter(|l| l.crate_name() == crate_name) {
        out.push_str(&format!(
            "//! | [`{}`] | `{}` | `{}` |\n",
            leaf.type_name(),
            leaf.kind(),
            cell(leaf.equation())
        ));
    }
    out
}

/// The facade's list of every leaf and combinator, as `//!` lines.
pub fn facade_list() -> String {
    let leaves: Vec<String> = LEAVES
        .iter()
        .map(|l| {
            let module = l
                .crate_name()
                .strip_prefix("hysteron_")
                .unwrap_or("operators");
            format!("[`{}`]({module}::{})", l.kind(), l.type_name())
        })
        .collect();
    let combinators: Vec<String> = COMBINATOR_LAWS
        .iter()
        .map(|c| format!("`{}`", c.kind))
        .collect();
    let mut out = String::new();
    for (title, items) in [("Leaves", leaves), ("Combinators", combinators)] {
        let mut line = format!("//! * {title}:");
        for (i, item) in items.iter().enumerate() {
            let sep = if i + 1 == items.len() { "." } else { "," };
            if line.len() + item.len() + 2 > 78 {
                out.push_str(&line);
                out.push('\n');
                line = "//!  ".into();
            }
            line.push(' ');
            line.push_str(item);
            line.push_str(sep);
        }
        out.push_str(&line);
        out.push('\n');
    }
    out
}

/// The listing `hysteron operators` prints: every leaf with its equation
/// and each field with its constraint, default and documentation, then
/// the combinators.
pub fn listing() -> String {
    let mut out = String::new();
    for leaf in LEAVES {
        out.push_str(&format!(
            "{} ({}): {}\n",
            leaf.kind(),
            leaf.type_name(),
            leaf.equation()
        ));
        for f in leaf.fields() {
            let omitted = omitted_text(*leaf, f);
            let required = if omitted.is_empty() {
                "required".to_string()
            } else {
                omitted
            };
            out.push_str(&format!(
                "  {:<22} {:<28} {}\n",
                constraint(*leaf, f),
                required,
                plain(f.doc)
            ));
        }
    }
    out.push_str("\ncombinators:\n");
    for c in COMBINATOR_LAWS {
        out.push_str(&format!(
            "{} ({}): {}; fields: {}\n",
            c.kind, c.rust, c.law, c.fields
        ));
    }
    out
}

/// The Python constructor's docstring of a leaf: its equation, then each
/// parameter with its constraint, default and documentation.
pub fn python_docstring(leaf: &dyn LeafKind) -> String {
    let mut lines = vec![
        format!("The ``{}`` operator: {}.", leaf.kind(), leaf.equation()),
        String::new(),
        "Parameters:".into(),
    ];
    for f in leaf.fields() {
        let mut head = match f.kind {
            FieldKind::Param(d) => d.to_string(),
            FieldKind::Nested => "nested".into(),
            FieldKind::Fixed => "a setting".into(),
        };
        if is_vector(leaf, f.name) {
            head = format!("each {head}");
        }
        let omitted = omitted_text(leaf, f);
        if !omitted.is_empty() {
            head.push_str(&format!("; {omitted}"));
        }
        let mut doc = plain(f.doc);
        if f.kind == FieldKind::Fixed && !doc.to_lowercase().contains("not a fitted parameter") {
            doc.push_str(" Not a fitted parameter.");
        }
        lines.push(format!("    {} ({head}): {doc}", f.name));
    }
    let example = serde_json::to_string(&leaf.example()).unwrap_or_default();
    lines.push(String::new());
    lines.push(format!("Example: ``{}(**{example})``.", leaf.kind()));
    lines.join("\n")
}

/// The Python type of a constructor's argument.
fn python_type(leaf: &dyn LeafKind, f: &FieldInfo) -> &'static str {
    if f.kind == FieldKind::Nested {
        return if leaf.takes_a_number(f.name) {
            "Union[float, Mapping[str, Any]]"
        } else {
            "Mapping[str, Any]"
        };
    }
    match leaf.example().get(f.name) {
        Some(Value::Array(_)) => "Sequence[float]",
        Some(Value::String(_)) => "str",
        Some(Value::Object(_)) => "Mapping[str, Any]",
        _ => "float",
    }
}

/// The Python stubs of the constructors (`python/hysteron_rs/_operators.pyi`):
/// arguments in declaration order, optional ones `= None`, a required one
/// after an optional one keyword-only, each with its docstring.
pub fn python_stubs() -> String {
    let mut out = String::from(
        "\"\"\"Type stubs of the constructors made from the registry (generated by\n\
         scripts/generate.sh; checked by mypy's stubtest).\"\"\"\n\n\
         from typing import Any, Mapping, Optional, Sequence, Union\n\n\
         from ._native import Model\n\n__all__ = [\n",
    );
    for leaf in LEAVES {
        out.push_str(&format!("    \"{}\",\n", leaf.kind()));
    }
    out.push_str("]\n");
    for leaf in LEAVES {
        let mut args = Vec::new();
        let (mut seen_optional, mut keyword_only) = (false, false);
        for f in leaf.fields() {
            let optional = leaf.omitted(f.name) != Omitted::Required;
            if !optional && seen_optional && !keyword_only {
                keyword_only = true;
                args.push("*".to_string());
            }
            seen_optional |= optional;
            let ty = python_type(*leaf, f);
            args.push(if optional {
                format!("{}: Optional[{ty}] = None", f.name)
            } else {
                format!("{}: {ty}", f.name)
            });
        }
        let doc = python_docstring(*leaf)
            .lines()
            .map(|l| {
                if l.is_empty() {
                    String::new()
                } else {
                    format!("    {}", l.replace('\\', "\\\\"))
                }
            })
            .collect::<Vec<_>>()
            .join("\n");
        out.push_str(&format!(
            "\ndef {}({}) -> Model:\n    \"\"\"{}\n    \"\"\"\n",
            leaf.kind(),
            args.join(", "),
            doc.trim_start()
        ));
    }
    out
}

/// The names of the Python constructors, sorted (the package's imports
/// and `__all__`).
pub fn python_names() -> Vec<&'static str> {
    let mut names: Vec<&'static str> = LEAVES.iter().map(|l| l.kind()).collect();
    names.sort_unstable();
    names
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_text_drops_link_syntax() {
        assert_eq!(
            plain(&[
                "until ([`SamplePeriod::set_sample_period`](crate::SamplePeriod::set_sample_period))."
            ]),
            "until (`SamplePeriod::set_sample_period`)."
        );
        assert_eq!(plain(&["a [`Leaf`] and", " [x]"]), "a `Leaf` and [x]");
        assert_eq!(plain(&["`w ∈ [0, 1]` and [y](z)"]), "`w ∈ [0, 1]` and y");
    }

    #[test]
    fn values_read_as_a_person_writes_them() {
        assert_eq!(value_text(&serde_json::json!(0.0)), "0");
        assert_eq!(value_text(&serde_json::json!(2.5)), "2.5");
        assert_eq!(value_text(&serde_json::json!([0.0, 0.0])), "0 each");
        assert_eq!(value_text(&serde_json::json!([])), "none");
        assert_eq!(value_text(&serde_json::json!("from_below")), "from_below");
    }

    /// Every leaf's docstring names every field, and the omitted-field
    /// rules read the declarations right on known cases.
    #[test]
    fn docstrings_and_defaults_follow_the_declarations() {
        let leaf = |k| super::super::registry::leaf_kind(k).unwrap();
        assert_eq!(leaf("play").omitted("r"), Omitted::Required);
        assert_eq!(
            leaf("play").omitted("y0"),
            Omitted::Default(serde_json::json!(0.0))
        );
        assert_eq!(leaf("lugre").omitted("dt"), Omitted::FromData);
        assert!(leaf("bouc_wen").takes_a_number("stiffness"));
        assert!(!leaf("play").takes_a_number("nonexistent"));
        for l in LEAVES {
            let doc = python_docstring(*l);
            for f in l.fields() {
                assert!(doc.contains(&format!("    {} (", f.name)), "{doc}");
            }
            assert!(!doc.contains("]("), "{doc}");
        }
    }
}
