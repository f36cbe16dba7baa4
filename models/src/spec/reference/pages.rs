//! The guide's reference (`docs/reference/`): one page per registered leaf
//! and combinator, an index, and the table of contents' entries.

use super::super::registry::{LeafKind, LEAVES};
use super::super::{Combinator, COMBINATOR_LAWS};
use super::{cell, is_vector, json_schema, omitted_text, plain};
use hysteron_operators::{FieldInfo, FieldKind};
use serde_json::Value;

/// A field's domain as a reader writes it: `≥ 0`, `real`, `nested`, `a
/// setting`, `each > 0` for a vector.
fn domain_text(leaf: &dyn LeafKind, f: &FieldInfo) -> String {
    let d = match f.kind {
        FieldKind::Param(d) => d.to_string(),
        FieldKind::Nested if leaf.takes_a_number(f.name) => "a number, or an object".into(),
        FieldKind::Nested => "an object".into(),
        FieldKind::Fixed => "a setting, not fitted".into(),
    };
    if is_vector(leaf, f.name) {
        format!("each {d}")
    } else {
        d
    }
}

/// The page's loop figure: the example spec over a decaying sine, drawn by
/// `hysteron operators --figures docs/reference/figures`.
fn figure(kind: &str) -> String {
    format!("![The example spec of `{kind}` driven by a sine whose amplitude decays from 2 to 0.4: y against x](figures/{kind}.svg)")
}

/// The reference page of a leaf (`docs/reference/KIND.md`): its equation,
/// a table of its fields (domain, what leaving it out means, meaning), an
/// example spec, and how Rust and Python name it.
pub fn leaf_page(leaf: &dyn LeafKind) -> String {
    let mut out = format!(
        "# `{kind}`\n\n`{eq}`\n\n{figure}\n\n| field | domain | if left out | meaning |\n|---|---|---|---|\n",
        figure = figure(leaf.kind()),
        kind = leaf.kind(),
        eq = leaf.equation(),
    );
    for f in leaf.fields() {
        let omitted = omitted_text(leaf, f);
        out.push_str(&format!(
            "| `{}` | {} | {} | {} |\n",
            f.name,
            cell(&domain_text(leaf, f)),
            if omitted.is_empty() {
                "required".to_string()
            } else {
                cell(&omitted)
            },
            cell(&plain(f.doc)),
        ));
    }
    let mut example = serde_json::Map::new();
    example.insert("type".into(), Value::String(leaf.kind().into()));
    if let Value::Object(m) = leaf.example() {
        example.extend(m);
    }
    let json = serde_json::to_string_pretty(&Value::Object(example)).unwrap_or_default();
    let module = leaf
        .crate_name()
        .strip_prefix("hysteron_")
        .unwrap_or("operators");
    out.push_str(&format!(
        "\nAn example spec (every spec in the reference builds and runs: \
         `tests/generated.rs`):\n\n```json\n{json}\n```\n\n\
         Rust: `hysteron::{module}::{ty}` (`{ty}::from_params`). \
         Python: `hysteron_rs.{kind}(...)`, whose docstring holds this table. \
         Command line: `\"type\": \"{kind}\"` in a spec; `hysteron operators` lists it.\n",
        ty = leaf.type_name(),
        kind = leaf.kind(),
    ));
    out
}

/// The reference page of a combinator (`docs/reference/KIND.md`): its law,
/// how Rust builds it, each field, and an example spec.
pub fn combinator_page(c: &Combinator) -> String {
    let solved = if c.implicit {
        "It solves its equation every sample (see [composing models](../composing.md))."
    } else {
        "It is explicit: one pass per sample."
    };
    let mut out = format!(
        "# `{kind}`\n\n`{law}`\n\n{solved} Rust: `{rust}`.\n\n{figure}\n\n| field | holds |\n|---|---|\n",
        figure = figure(c.kind),
        kind = c.kind,
        law = c.law,
        rust = c.rust,
    );
    for (name, doc) in c.field_docs {
        out.push_str(&format!("| `{name}` | {} |\n", cell(doc)));
    }
    let pretty = serde_json::from_str::<Value>(c.example)
        .ok()
        .and_then(|v| serde_json::to_string_pretty(&v).ok())
        .unwrap_or_else(|| c.example.to_string());
    out.push_str(&format!("\nAn example spec:\n\n```json\n{pretty}\n```\n"));
    out
}

/// The reference's index (`docs/reference/index.md`): every leaf and
/// combinator with its equation, each linked to its page.
pub fn reference_index() -> String {
    let mut out = String::from(
        "# Reference\n\nOne page per operator and combinator, generated from the \
         registry by `scripts/generate.sh` (a test fails when a page differs \
         from what the registry says). The Rust API is in `cargo doc`; \
         [the spec's JSON Schema](spec.schema.json) is generated too.\n\n\
         ## Operators\n\n| operator | equation |\n|---|---|\n",
    );
    for leaf in LEAVES {
        out.push_str(&format!(
            "| [`{k}`]({k}.md) | `{}` |\n",
            cell(leaf.equation()),
            k = leaf.kind()
        ));
    }
    out.push_str("\n## Combinators\n\n| combinator | law |\n|---|---|\n");
    for c in COMBINATOR_LAWS {
        out.push_str(&format!(
            "| [`{k}`]({k}.md) | `{}` |\n",
            cell(c.law),
            k = c.kind
        ));
    }
    out
}

/// The reference's entries of the guide's table of contents
/// (`docs/SUMMARY.md`), one line per page.
pub fn summary_entries() -> String {
    let mut out = String::from("- [Reference](reference/index.md)\n");
    let kinds = LEAVES
        .iter()
        .map(|l| l.kind())
        .chain(COMBINATOR_LAWS.iter().map(|c| c.kind));
    for k in kinds {
        out.push_str(&format!("  - [{k}](reference/{k}.md)\n"));
    }
    out
}

/// Every generated reference page: its path under `docs/reference/` and
/// its text.
pub fn reference_pages() -> Vec<(String, String)> {
    let mut pages = vec![("index.md".to_string(), reference_index())];
    for leaf in LEAVES {
        pages.push((format!("{}.md", leaf.kind()), leaf_page(*leaf)));
    }
    for c in COMBINATOR_LAWS {
        pages.push((format!("{}.md", c.kind), combinator_page(c)));
    }
    pages.push(("spec.schema.json".into(), json_schema()));
    pages
}
