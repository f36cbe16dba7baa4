//! The registry of leaf operators seen from Python: one constructor per
//! registered leaf is made from it in `hysteron_rs/_operators.py`.

use crate::errors::SpecError as PySpecError;
use crate::model::Model;
use hysteron::models::spec::reference;
use hysteron::models::spec::registry::{leaf_kind, Omitted, LEAVES};
use hysteron::models::{Spec, TransmissionParams};
use hysteron::operators::FieldKind;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// Every registered leaf: a list of dicts `{"type", "equation", "doc",
/// "example", "fields": [{"name", "kind", "doc", "required"}]}`, fields in
/// declaration order, `doc` the constructor's docstring (rendered by
/// `hysteron::models::spec::reference`), `example` a valid parameter dict;
/// a field is not `required` when the spec may leave it out (it has a
/// default, or it is the sample period `dt` that the data may give);
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
            d.set_item("required", leaf.omitted(f.name) == Omitted::Required)?;
            fields.append(d)?;
        }
        let d = PyDict::new(py);
        d.set_item("type", leaf.kind())?;
        d.set_item("equation", leaf.equation())?;
        d.set_item("doc", reference::python_docstring(*leaf))?;
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
