//! The JSON form of a [`Spec`]: read by walking the parsed document, so
//! that every error names its path; written with `type` first.

use super::registry::{all_kinds, leaf_kind};
use super::{LeafSpec, Spec, SpecError, MAX_DEPTH};
use crate::TransmissionParams;
use hysteron_composition::{SolverOptions, TravelLimits};
use serde::de::{Error as _, Unexpected};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use serde_json::{Map, Value};

/// A path in the document: `""` is the root (named by its `type` once the
/// spec is read, see [`name_root`]).
fn join(path: &str, field: &str) -> String {
    if path.is_empty() {
        field.to_string()
    } else {
        format!("{path}.{field}")
    }
}

fn error(path: &str, message: impl ToString) -> SpecError {
    SpecError::Json {
        path: path.into(),
        message: message.to_string(),
    }
}

/// What an error at the root of a document is named: the root's `type`
/// where it has a readable one (`lugre: missing field `dt``), `spec`
/// otherwise; serde's own name for the root, `.`, means nothing to a
/// reader.
fn name_root(e: SpecError, document: Option<&Value>) -> SpecError {
    match e {
        SpecError::Json { path, message } if path.is_empty() || path == "." => {
            let kind = document
                .and_then(|v| v.get("type"))
                .and_then(Value::as_str)
                .filter(|k| all_kinds().contains(k));
            SpecError::Json {
                path: kind.unwrap_or("spec").to_string(),
                message,
            }
        }
        other => other,
    }
}

/// Serde's error for a value of the wrong JSON type.
fn unexpected(v: &Value) -> Unexpected<'_> {
    match v {
        Value::Null => Unexpected::Unit,
        Value::Bool(b) => Unexpected::Bool(*b),
        Value::Number(n) => match (n.as_u64(), n.as_i64(), n.as_f64()) {
            (Some(u), _, _) => Unexpected::Unsigned(u),
            (_, Some(i), _) => Unexpected::Signed(i),
            (_, _, f) => Unexpected::Float(f.unwrap_or(f64::NAN)),
        },
        Value::String(s) => Unexpected::Str(s),
        Value::Array(_) => Unexpected::Seq,
        Value::Object(_) => Unexpected::Map,
    }
}

/// An object's fields, or a type error naming `what` it should be.
fn object<'a>(v: &'a Value, path: &str, what: &str) -> Result<&'a Map<String, Value>, SpecError> {
    v.as_object()
        .ok_or_else(|| error(path, serde_json::Error::invalid_type(unexpected(v), &what)))
}

/// Deserializes `v` as `T`, the error's path under `path`.
fn typed<T: serde::de::DeserializeOwned>(v: &Value, path: &str) -> Result<T, SpecError> {
    serde_path_to_error::deserialize(v.clone()).map_err(|e| {
        let inner = e.path().to_string();
        let at = if inner == "." {
            path.to_string()
        } else if inner.starts_with('[') {
            format!("{path}{inner}")
        } else {
            join(path, &inner)
        };
        error(&at, e.inner())
    })
}

/// The fields of an object with a `type` tag, checked against `allowed`.
struct Tagged<'a> {
    fields: &'a Map<String, Value>,
    path: &'a str,
}

impl<'a> Tagged<'a> {
    fn check(&self, allowed: &'static [&'static str]) -> Result<(), SpecError> {
        for key in self.fields.keys() {
            if key != "type" && !allowed.contains(&key.as_str()) {
                return Err(error(
                    &join(self.path, key),
                    serde_json::Error::unknown_field(key, allowed),
                ));
            }
        }
        Ok(())
    }

    fn get(&self, field: &'static str) -> Result<&'a Value, SpecError> {
        self.fields
            .get(field)
            .ok_or_else(|| error(self.path, serde_json::Error::missing_field(field)))
    }

    fn child(&self, field: &'static str) -> Result<Box<Spec>, SpecError> {
        Ok(Box::new(from_value(
            self.get(field)?,
            &join(self.path, field),
        )?))
    }

    fn solver(&self) -> Result<Option<SolverOptions<f64>>, SpecError> {
        match self.fields.get("solver") {
            None => Ok(None),
            Some(v) => solver(v, &join(self.path, "solver")).map(Some),
        }
    }
}

/// The `type` of a tagged object at `path`.
fn tag<'a>(fields: &'a Map<String, Value>, path: &str) -> Result<&'a str, SpecError> {
    let v = fields
        .get("type")
        .ok_or_else(|| error(path, serde_json::Error::missing_field("type")))?;
    v.as_str().ok_or_else(|| {
        error(
            &join(path, "type"),
            serde_json::Error::invalid_type(unexpected(v), &"a string"),
        )
    })
}

/// Reads the spec at `path` of a parsed document.
pub(super) fn from_value(v: &Value, path: &str) -> Result<Spec, SpecError> {
    let fields = object(v, path, "a spec")?;
    let kind = tag(fields, path)?;
    let node = Tagged { fields, path };
    Ok(match kind {
        "cascade" => {
            node.check(&["first", "second"])?;
            Spec::Cascade {
                first: node.child("first")?,
                second: node.child("second")?,
            }
        }
        "parallel" => {
            node.check(&["left", "right"])?;
            Spec::Parallel {
                left: node.child("left")?,
                right: node.child("right")?,
            }
        }
        "scaled" => {
            node.check(&["w", "inner"])?;
            Spec::Scaled {
                w: typed(node.get("w")?, &join(path, "w"))?,
                inner: node.child("inner")?,
            }
        }
        "feedback" => {
            node.check(&["forward", "back", "solver"])?;
            Spec::Feedback {
                forward: node.child("forward")?,
                back: node.child("back")?,
                solver: node.solver()?,
            }
        }
        "series" => {
            node.check(&["left", "right", "limits", "solver"])?;
            Spec::Series {
                left: node.child("left")?,
                right: node.child("right")?,
                limits: match fields.get("limits") {
                    None => TravelLimits::None,
                    Some(v) => limits(v, &join(path, "limits"))?,
                },
                solver: node.solver()?,
            }
        }
        "inverse" => {
            node.check(&["inner", "solver"])?;
            Spec::Inverse {
                inner: node.child("inner")?,
                solver: node.solver()?,
            }
        }
        "oversample" => {
            node.check(&["inner", "q"])?;
            Spec::Oversample {
                inner: node.child("inner")?,
                q: typed(node.get("q")?, &join(path, "q"))?,
            }
        }
        "transmission" => {
            Spec::Transmission(typed::<TransmissionParams>(&without_type(fields), path)?)
        }
        other => {
            let entry = leaf_kind(other).ok_or_else(|| {
                error(
                    &join(path, "type"),
                    serde_json::Error::unknown_variant(other, all_kinds()),
                )
            })?;
            // A rate-dependent leaf may leave its period out (it then
            // comes from the data or the host): read with a stand-in.
            let mut raw = without_type(fields);
            let lacks_period = entry.is_rate_dependent() && !fields.contains_key("dt");
            if let (true, Value::Object(m)) = (lacks_period, &mut raw) {
                m.insert("dt".into(), Value::from(Spec::STAND_IN_DT));
            }
            let mut params = entry.canonical(raw).map_err(|e| {
                let inner = e.path().to_string();
                let at = if inner == "." {
                    path.to_string()
                } else {
                    join(path, &inner)
                };
                error(&at, e.inner())
            })?;
            if let (true, Value::Object(m)) = (lacks_period, &mut params) {
                m.remove("dt");
            }
            Spec::Leaf(LeafSpec {
                kind: entry.kind(),
                params,
            })
        }
    })
}

fn without_type(fields: &Map<String, Value>) -> Value {
    let mut m = fields.clone();
    m.remove("type");
    Value::Object(m)
}

/// Travel limits: `{"type": "none" | "range" | "gap", …}`.
fn limits(v: &Value, path: &str) -> Result<TravelLimits<f64>, SpecError> {
    #[derive(Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Range {
        lo: f64,
        hi: f64,
    }
    #[derive(Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Gap {
        b: f64,
        #[serde(default)]
        r0: f64,
    }
    let fields = object(v, path, "travel limits: an object with a `type` field")?;
    let rest = without_type(fields);
    Ok(match tag(fields, path)? {
        "none" => {
            Tagged { fields, path }.check(&[])?;
            TravelLimits::None
        }
        "range" => {
            let Range { lo, hi } = typed(&rest, path)?;
            TravelLimits::Range { lo, hi }
        }
        "gap" => {
            let Gap { b, r0 } = typed(&rest, path)?;
            TravelLimits::Gap { b, r0 }
        }
        other => {
            return Err(error(
                &join(path, "type"),
                serde_json::Error::unknown_variant(other, &["none", "range", "gap"]),
            ))
        }
    })
}

/// Solver options, each field defaulting to [`SolverOptions::default`].
fn solver(v: &Value, path: &str) -> Result<SolverOptions<f64>, SpecError> {
    const FIELDS: &[&str] = &["rel_tol", "abs_tol", "max_iter", "max_expansions"];
    let fields = object(v, path, "solver options")?;
    let mut o = SolverOptions::<f64>::default();
    for (key, v) in fields {
        let at = join(path, key);
        match key.as_str() {
            "rel_tol" => o.rel_tol = typed(v, &at)?,
            "abs_tol" => o.abs_tol = typed(v, &at)?,
            "max_iter" => o.max_iter = typed(v, &at)?,
            "max_expansions" => o.max_expansions = typed(v, &at)?,
            _ => return Err(error(&at, serde_json::Error::unknown_field(key, FIELDS))),
        }
    }
    Ok(o)
}

/// An object with `type` first, then `fields`.
fn tagged(kind: &str, fields: impl IntoIterator<Item = (&'static str, Value)>) -> Value {
    let mut m = Map::new();
    m.insert("type".into(), Value::String(kind.into()));
    for (k, v) in fields {
        m.insert(k.into(), v);
    }
    Value::Object(m)
}

fn value<T: Serialize>(v: &T) -> Value {
    // Numbers and plain structs always serialize; non-finite numbers (no
    // valid spec has them) become `null`.
    serde_json::to_value(v).unwrap_or(Value::Null)
}

impl Spec {
    /// The spec as a JSON value (`type` first in every object).
    pub fn to_value(&self) -> Value {
        let child = |s: &Spec| s.to_value();
        let solver = |s: &Option<SolverOptions<f64>>| s.as_ref().map(|o| ("solver", value(o)));
        match self {
            Spec::Leaf(leaf) => {
                let mut m = Map::new();
                m.insert("type".into(), Value::String(leaf.kind.into()));
                if let Value::Object(p) = &leaf.params {
                    m.extend(p.clone());
                }
                Value::Object(m)
            }
            Spec::Transmission(p) => {
                let Value::Object(fields) = value(p) else {
                    return Value::Null;
                };
                let mut m = Map::new();
                m.insert("type".into(), Value::String("transmission".into()));
                m.extend(fields);
                Value::Object(m)
            }
            Spec::Cascade { first, second } => tagged(
                "cascade",
                [("first", child(first)), ("second", child(second))],
            ),
            Spec::Parallel { left, right } => {
                tagged("parallel", [("left", child(left)), ("right", child(right))])
            }
            Spec::Scaled { w, inner } => {
                tagged("scaled", [("w", value(w)), ("inner", child(inner))])
            }
            Spec::Feedback {
                forward,
                back,
                solver: s,
            } => tagged(
                "feedback",
                [("forward", child(forward)), ("back", child(back))]
                    .into_iter()
                    .chain(solver(s)),
            ),
            Spec::Series {
                left,
                right,
                limits,
                solver: s,
            } => {
                let limits = match limits {
                    TravelLimits::None => None,
                    TravelLimits::Range { lo, hi } => {
                        Some(tagged("range", [("lo", value(lo)), ("hi", value(hi))]))
                    }
                    TravelLimits::Gap { b, r0 } => {
                        Some(tagged("gap", [("b", value(b)), ("r0", value(r0))]))
                    }
                };
                tagged(
                    "series",
                    [("left", child(left)), ("right", child(right))]
                        .into_iter()
                        .chain(limits.map(|l| ("limits", l)))
                        .chain(solver(s)),
                )
            }
            Spec::Inverse { inner, solver: s } => tagged(
                "inverse",
                [("inner", child(inner))].into_iter().chain(solver(s)),
            ),
            Spec::Oversample { inner, q } => {
                tagged("oversample", [("inner", child(inner)), ("q", value(q))])
            }
        }
    }

    /// Reads a spec from JSON (a leading byte-order mark is skipped).
    ///
    /// Errors are [`SpecError::Json`] with the path in the document and
    /// serde's message (syntax errors also give line and column).
    pub fn from_json(text: &str) -> Result<Spec, SpecError> {
        // A byte-order mark (as some editors write UTF-8) is not content.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        if let Some((line, column)) = nested_beyond(text, MAX_DEPTH + 4) {
            return Err(SpecError::Json {
                path: "spec".into(),
                message: format!(
                    "nested deeper than {} levels at line {line} column {column}: a spec may nest at most {MAX_DEPTH} operators on one path",
                    MAX_DEPTH + 4
                ),
            });
        }
        let mut de = serde_json::Deserializer::from_str(text);
        let value: Value = serde_path_to_error::deserialize(&mut de)
            .map_err(|e| name_root(error(&e.path().to_string(), e.inner()), None))?;
        de.end().map_err(|e| name_root(error("", e), None))?;
        from_value(&value, "").map_err(|e| name_root(e, Some(&value)))
    }

    /// Writes the spec as indented JSON (`type` first in every object;
    /// numbers in shortest round-trip form, so reading it back gives the
    /// same spec bit for bit).
    ///
    /// Serializing a spec cannot fail (non-finite numbers, which no valid
    /// spec has, are written as `null`); the error is there only so that
    /// nothing panics.
    pub fn to_json_pretty(&self) -> Result<String, SpecError> {
        serde_json::to_string_pretty(&self.to_value()).map_err(|e| error(self.kind(), e))
    }
}

impl Serialize for Spec {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.to_value().serialize(s)
    }
}

impl<'de> Deserialize<'de> for Spec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = Value::deserialize(d)?;
        from_value(&v, "")
            .map_err(|e| name_root(e, Some(&v)))
            .map_err(D::Error::custom)
    }
}

/// Where the JSON text first nests its objects and arrays more than
/// `limit` levels deep (line and column, 1-based, of the opening bracket),
/// skipping strings; `None` if it never does. A linear scan without
/// recursion, run before the recursive parse.
fn nested_beyond(text: &str, limit: usize) -> Option<(usize, usize)> {
    let (mut depth, mut line, mut column) = (0usize, 1, 0);
    let (mut in_string, mut escaped) = (false, false);
    for c in text.chars() {
        column += 1;
        if in_string {
            match c {
                _ if escaped => escaped = false,
                '\\' => escaped = true,
                '"' => in_string = false,
                _ => {}
            }
            continue;
        }
        match c {
            '"' => in_string = true,
            '{' | '[' => {
                depth += 1;
                if depth > limit {
                    return Some((line, column));
                }
            }
            '}' | ']' => depth = depth.saturating_sub(1),
            '\n' => {
                line += 1;
                column = 0;
            }
            _ => {}
        }
    }
    None
}
