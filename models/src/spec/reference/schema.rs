//! The JSON Schema of a model spec (`docs/reference/spec.schema.json`),
//! from the registry.

use super::super::registry::{Omitted, LEAVES};
use super::super::COMBINATOR_LAWS;
use super::plain;
use hysteron_operators::FieldKind;
use serde_json::Value;

/// A JSON Schema of a number in `domain`.
fn number_schema(domain: Option<hysteron_operators::Domain>) -> Value {
    use hysteron_operators::Domain;
    let mut m = serde_json::Map::new();
    m.insert("type".into(), "number".into());
    match domain {
        Some(Domain::NonNegative) => {
            m.insert("minimum".into(), 0.into());
        }
        Some(Domain::Positive) => {
            m.insert("exclusiveMinimum".into(), 0.into());
        }
        Some(Domain::NonPositive) => {
            m.insert("maximum".into(), 0.into());
        }
        Some(Domain::AtLeast(v)) => {
            m.insert("minimum".into(), v.into());
        }
        Some(Domain::UnitInterval) => {
            m.insert("minimum".into(), 0.into());
            m.insert("maximum".into(), 1.into());
        }
        Some(Domain::Real) | None => {}
    }
    Value::Object(m)
}

/// An object schema tagged `"type": kind` with `properties`, of which
/// `required` must be given; no other field is accepted.
fn tagged_schema(kind: &str, properties: Vec<(String, Value)>, required: Vec<String>) -> Value {
    let mut props = serde_json::Map::new();
    props.insert("type".into(), serde_json::json!({ "const": kind }));
    props.extend(properties);
    let mut req = vec![Value::String("type".into())];
    req.extend(required.into_iter().map(Value::String));
    serde_json::json!({
        "type": "object",
        "properties": props,
        "required": req,
        "additionalProperties": false,
    })
}

/// Sets an object schema's `description`.
fn describe(schema: &mut Value, text: &str) {
    if let Value::Object(m) = schema {
        m.insert("description".into(), text.into());
    }
}

/// The JSON Schema (draft 2020-12) of a model spec, from the registry's
/// leaves (each field with its domain, default and documentation) and the
/// combinators' fields. Objects inside a leaf (a stiffness map, a
/// Preisach measure) are described, not constrained.
pub fn json_schema() -> String {
    let mut defs = serde_json::Map::new();
    let mut kinds = Vec::new();
    for leaf in LEAVES {
        let mut props = Vec::new();
        let mut required = Vec::new();
        for f in leaf.fields() {
            let mut schema = match (f.kind, leaf.example().get(f.name)) {
                (FieldKind::Nested, _) if leaf.takes_a_number(f.name) => {
                    serde_json::json!({ "type": ["number", "object"] })
                }
                (FieldKind::Nested, _) => serde_json::json!({ "type": "object" }),
                (FieldKind::Param(d), Some(Value::Array(_))) => {
                    serde_json::json!({ "type": "array", "items": number_schema(Some(d)) })
                }
                (FieldKind::Param(d), _) => number_schema(Some(d)),
                (FieldKind::Fixed, Some(Value::String(_))) => {
                    serde_json::json!({ "type": "string" })
                }
                (FieldKind::Fixed, _) => number_schema(None),
            };
            if let Value::Object(m) = &mut schema {
                m.insert("description".into(), plain(f.doc).into());
                if let Omitted::Default(v) = leaf.omitted(f.name) {
                    m.insert("default".into(), v);
                }
            }
            if leaf.omitted(f.name) == Omitted::Required {
                required.push(f.name.to_string());
            }
            props.push((f.name.to_string(), schema));
        }
        let mut def = tagged_schema(leaf.kind(), props, required);
        describe(&mut def, leaf.equation());
        defs.insert(leaf.kind().into(), def);
        kinds.push(leaf.kind());
    }
    let spec = serde_json::json!({ "$ref": "#/$defs/spec" });
    for c in COMBINATOR_LAWS {
        let mut props = Vec::new();
        let mut required = Vec::new();
        for (name, doc) in c.field_docs {
            let optional = doc.starts_with("optional");
            let mut schema = match (c.kind, *name) {
                (_, "solver") => serde_json::json!({ "$ref": "#/$defs/solver" }),
                (_, "limits") => serde_json::json!({ "$ref": "#/$defs/limits" }),
                (_, "q") => serde_json::json!({ "type": "integer", "minimum": 1 }),
                (_, "w") | ("transmission", "slider0") => number_schema(None),
                ("transmission", "backlash") => {
                    number_schema(Some(hysteron_operators::Domain::NonNegative))
                }
                ("transmission", _) => serde_json::json!({ "type": "object" }),
                _ => spec.clone(),
            };
            if let Value::Object(m) = &mut schema {
                m.insert("description".into(), plain(&[doc]).into());
            }
            if !optional {
                required.push(name.to_string());
            }
            props.push((name.to_string(), schema));
        }
        let mut def = tagged_schema(c.kind, props, required);
        describe(&mut def, c.law);
        defs.insert(c.kind.into(), def);
        kinds.push(c.kind);
    }
    defs.insert(
        "solver".into(),
        serde_json::json!({
            "type": "object",
            "properties": {
                "rel_tol": number_schema(Some(hysteron_operators::Domain::NonNegative)),
                "abs_tol": number_schema(Some(hysteron_operators::Domain::NonNegative)),
                "max_iter": { "type": "integer", "minimum": 1 },
                "max_expansions": { "type": "integer", "minimum": 0 },
            },
            "additionalProperties": false,
        }),
    );
    defs.insert(
        "limits".into(),
        serde_json::json!({ "oneOf": [
            tagged_schema("none", vec![], vec![]),
            tagged_schema("range", vec![("lo".into(), number_schema(None)), ("hi".into(), number_schema(None))], vec!["lo".into(), "hi".into()]),
            tagged_schema("gap", vec![("b".into(), number_schema(Some(hysteron_operators::Domain::NonNegative))), ("r0".into(), number_schema(None))], vec!["b".into(), "r0".into()]),
        ]}),
    );
    defs.insert(
        "spec".into(),
        serde_json::json!({ "oneOf": kinds.iter().map(|k| serde_json::json!({ "$ref": format!("#/$defs/{k}") })).collect::<Vec<_>>() }),
    );
    let schema = serde_json::json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "hysteron model spec",
        "description": "A model: a registered operator or a combinator of specs, tagged by `type`.",
        "$ref": "#/$defs/spec",
        "$defs": defs,
    });
    serde_json::to_string_pretty(&schema).unwrap_or_default() + "\n"
}
