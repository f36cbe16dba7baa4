//! A model behind the C boundary: its spec, the operator built from it,
//! and its parameter paths as C strings. Shared by the C API and the FMU.

use crate::status::{fail, spec_failure, HysteronStatus};
use hysteron::identify::free_by_names;
use hysteron::models::{Spec, SpecError};
use hysteron::{Operator, Result};
use std::ffi::CString;

/// A spec and the operator built from it, in its running state.
///
/// A spec may leave the sample period of its rate-dependent nodes out
/// ([`Spec::missing_period`]): the model then runs once the host gives the
/// period ([`set_sample_period`](Model::set_sample_period), the FMU's step
/// size), and [`step`](Model::step) and [`running`](Model::running) say
/// what is missing until then.
pub struct Model {
    spec: Spec,
    op: Box<dyn Operator<f64>>,
    names: Vec<CString>,
    /// `spec.missing_period()`, kept with the spec: every step asks it,
    /// and walking the spec costs several times the step itself.
    missing_period: Option<String>,
}

impl Clone for Model {
    fn clone(&self) -> Self {
        Model {
            spec: self.spec.clone(),
            op: dyn_clone::clone_box(self.op.as_ref()),
            names: self.names.clone(),
            missing_period: self.missing_period.clone(),
        }
    }
}

impl Model {
    /// Builds the model of a spec (with a stand-in period where it leaves
    /// the period out, until one is given).
    pub fn new(spec: Spec) -> std::result::Result<Model, SpecError> {
        let missing_period = spec.missing_period();
        let op = match missing_period {
            Some(_) => spec.or_dt(Spec::STAND_IN_DT).build()?,
            None => spec.build()?,
        };
        let names = op
            .param_names()
            .into_iter()
            // Parameter paths are identifiers and dots: never a NUL.
            .map(|n| CString::new(n).unwrap_or_default())
            .collect();
        Ok(Model {
            spec,
            op,
            names,
            missing_period,
        })
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

    /// The operator, to run samples through: an error naming the node
    /// whose sample period is still missing, if one is.
    pub fn running(&mut self) -> std::result::Result<&mut dyn Operator<f64>, SpecError> {
        if let Some(node) = &self.missing_period {
            return Err(SpecError::MissingPeriod {
                path: format!("{node}.dt"),
            });
        }
        Ok(self.op.as_mut())
    }

    /// `trial(x)` then `commit()`: the output.
    pub fn step(&mut self, x: f64) -> std::result::Result<f64, String> {
        let op = self.running().map_err(|e| e.to_string())?;
        let y = op.trial(x).map_err(|e| e.to_string())?.output;
        op.commit();
        Ok(y)
    }

    /// Sets the sample period `dt` (s) of every rate-dependent node (`dt /
    /// q` inside an `oversample`), in the running operator and in the
    /// spec; a rate-independent model checks it and ignores it.
    pub fn set_sample_period(&mut self, dt: f64) -> Result<()> {
        self.op.set_sample_period(dt)?;
        if self.spec.is_rate_dependent() {
            self.spec = self.spec.with_dt(dt);
            self.missing_period = self.spec.missing_period();
        }
        Ok(())
    }

    /// The sample period (s) a rate-dependent model runs at, `Ok(None)`
    /// for a rate-independent one, and an error if the spec leaves it out
    /// and none was given.
    pub fn sample_period(&self) -> std::result::Result<Option<f64>, SpecError> {
        if let Some(node) = self.spec.missing_period() {
            return Err(SpecError::MissingPeriod {
                path: format!("{node}.dt"),
            });
        }
        Ok(self.spec.stated_periods().first().copied())
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
