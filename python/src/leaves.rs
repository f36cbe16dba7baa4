//! The registry of leaf operators seen from Python: one constructor per
//! registered leaf is made from it in `hysteron_rs/_operators.py`.

use crate::errors::SpecError as PySpecError;
use crate::model::Model;
use hysteron::models::spec::registry::{leaf_kind, LeafKind, LEAVES};
use hysteron::models::{Spec, TransmissionParams};
use hysteron::operators::FieldKind;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// Whether the leaf's spec can leave out `field`: it has a default (the
/// declaration's example without it still reads), or it is the sample
/// period `dt` of a rate-dependent leaf, which may come from the data
/// (`run(x, dt=...)`, `fit(..., time=...)`) instead.
fn optional(leaf: &dyn LeafKind, field: &str) -> bool {
    if field == "dt" && leaf.is_rate_dependent() {
        return true;
    }
    let mut example = leaf.example();
    match example.as_object_mut() {
        Some(m) => {
            m.remove(field);
            leaf.canonical(example).is_ok()
        }
        None => false,
    }
}

/// Every registered leaf: a list of dicts `{"type", "equation", "example",
/// "fields": [{"name", "kind", "doc", "required"}]}`, fields in
/// declaration order, `example` a valid parameter dict;
/// `kind` is `"param"`, `"nested"` or `"fixed"` (a setting, not a
/// parameter).
#[pyfunction]
pub fn leaf_kinds(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let out = PyList::empty(py);
    for leaf in LEAVES {
        let fields = PyList::empty(py);
        for f in leaf.fields() {
            let d = PyDict::new(py);
            d.set_item("name", f.name)?;
            d.set_item(
                "kind",
                match f.kind {
                    FieldKind::Param(_) => "param",
                    FieldKind::Nested => "nested",
                    FieldKind::Fixed => "fixed",
                },
            )?;
            let doc: Vec<&str> = f.doc.iter().map(|l| l.trim()).collect();
            d.set_item("doc", doc.join(" "))?;
            d.set_item("required", !optional(*leaf, f.name))?;
            fields.append(d)?;
        }
        let d = PyDict::new(py);
        d.set_item("type", leaf.kind())?;
        d.set_item("equation", leaf.equation())?;
        d.set_item("fields", fields)?;
        let example = serde_json::to_string(&leaf.example())
            .map_err(|e| PySpecError::new_err(e.to_string()))?;
        d.set_item(
            "example",
            py.import("json")?.call_method1("loads", (example,))?,
        )?;
        out.append(d)?;
    }
    Ok(out)
}

/// The leaf `kind` with the parameters `params` (a dict as in a spec).
#[pyfunction]
pub fn leaf(kind: &str, params: &Bound<'_, PyDict>) -> PyResult<Model> {
    if leaf_kind(kind).is_none() {
        return Err(PySpecError::new_err(format!(
            "unknown leaf operator `{kind}`"
        )));
    }
    let node = params.copy()?;
    node.set_item("type", kind)?;
    Model::py_new(node.as_any())
}

/// The paper's transmission model (a `transmission` spec) with its
/// default parameters; change them with `with_params`.
#[pyfunction]
pub fn paper_model() -> PyResult<Model> {
    Model::from_rust_spec(Spec::Transmission(TransmissionParams::default()))
}
