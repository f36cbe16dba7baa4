//! A model behind the C boundary: its spec, the operator built from it,
//! and its parameter paths as C strings. Shared by the C API and the FMU.

use crate::status::{fail, spec_failure, HysteronStatus};
use hysteron::identify::free_by_names;
use hysteron::models::{Spec, SpecError};
use hysteron::{Operator, Result};
use std::ffi::CString;

/// A spec and the operator built from it, in its running state.
pub struct Model {
    spec: Spec,
    op: Box<dyn Operator<f64>>,
    names: Vec<CString>,
}

impl Clone for Model {
    fn clone(&self) -> Self {
        Model {
            spec: self.spec.clone(),
            op: dyn_clone::clone_box(self.op.as_ref()),
            names: self.names.clone(),
        }
    }
}

impl Model {
    /// Builds the model of a spec.
    pub fn new(spec: Spec) -> std::result::Result<Model, SpecError> {
        let op = spec.build()?;
        let names = op
            .param_names()
            .into_iter()
            // Parameter paths are identifiers and dots: never a NUL.
            .map(|n| CString::new(n).unwrap_or_default())
            .collect();
        Ok(Model { spec, op, names })
    }

    /// Builds the model of a JSON spec.
    pub fn from_json(json: &str) -> std::result::Result<Model, SpecError> {
        Model::new(Spec::from_json(json)?)
    }

    /// The spec (with the current parameter values).
    pub fn spec(&self) -> &Spec {
        &self.spec
    }

    /// The operator.
    pub fn operator(&self) -> &dyn Operator<f64> {
        self.op.as_ref()
    }

    /// The operator, to run.
    pub fn operator_mut(&mut self) -> &mut dyn Operator<f64> {
        self.op.as_mut()
    }

    /// `trial(x)` then `commit()`: the output.
    pub fn step(&mut self, x: f64) -> Result<f64> {
        let y = self.op.trial(x)?.output;
        self.op.commit();
        Ok(y)
    }

    /// The parameter paths, in the order of the flat parameter vector.
    pub fn names(&self) -> &[CString] {
        &self.names
    }

    /// The index of parameter `name` (a path or a unique suffix).
    pub fn index(&self, name: &str) -> std::result::Result<usize, String> {
        free_by_names(self.op.as_ref(), &[name])
            .map(|i| i[0])
            .map_err(|e| e.to_string())
    }

    /// The value of parameter `name`.
    pub fn param(&self, name: &str) -> std::result::Result<f64, String> {
        let i = self.index(name)?;
        Ok(self.op.params()[i])
    }

    /// The model rebuilt with the flat parameter vector `p`, from its
    /// initial state; tied parameters must move together (as
    /// `Spec::with_params` demands).
    pub fn with_params(&self, p: &[f64]) -> std::result::Result<Model, SpecError> {
        Model::new(self.spec.with_params(p)?)
    }

    /// Sets parameter `name` to `value`: the model is rebuilt with it, from
    /// its initial state. A tied parameter or an invalid value is refused
    /// and nothing changes.
    pub fn set_param(&mut self, name: &str, value: f64) -> std::result::Result<(), HysteronStatus> {
        let i = self
            .index(name)
            .map_err(|e| fail(HysteronStatus::Parameter, e))?;
        let mut p = self.op.params();
        p[i] = value;
        *self = self.with_params(&p).map_err(spec_failure)?;
        Ok(())
    }
}
