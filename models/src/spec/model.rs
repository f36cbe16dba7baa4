//! A model built from a spec: the operator, and the spec it was built from,
//! which gives its twin over dual numbers.

use super::Spec;
use hysteron_operators::{
    Beyond, Derivatives, Domain, Dual, Hints, Keep, Operator, Parameters, Result, SamplePeriod,
    Trial,
};
use std::sync::Arc;

/// What [`Spec::build`] returns: the built operator, which it runs, and the
/// spec, from which [`Derivatives::to_dual`] builds the same model over
/// [`Dual`] (with the current parameters) for exact derivatives.
///
/// Every method of [`Operator`] and its traits is the built operator's, so a spec model
/// runs as fast and gives the same bits as the operator alone.
#[derive(Debug, Clone)]
pub(super) struct SpecModel {
    op: Box<dyn Operator<f64>>,
    spec: Arc<Spec>,
}

impl SpecModel {
    pub(super) fn new(op: Box<dyn Operator<f64>>, spec: Spec) -> Self {
        Self {
            op,
            spec: Arc::new(spec),
        }
    }
}

impl Operator<f64> for SpecModel {
    fn name(&self) -> &'static str {
        self.op.name()
    }
    crate::composition::delegate_stepping!(f64, op);
    fn run(&mut self, xs: &[f64]) -> Result<Vec<f64>> {
        self.op.run(xs)
    }
}

impl Hints<f64> for SpecModel {
    fn batch_while(
        &mut self,
        xs: &[f64],
        ys: &mut [f64],
        keep: &mut Keep<'_, f64>,
    ) -> Option<usize> {
        self.op.batch_while(xs, ys, keep)
    }
    fn batch_while_beyond(
        &mut self,
        xs: &[f64],
        ys: &mut [f64],
        beyond: Beyond<f64>,
    ) -> Option<usize> {
        self.op.batch_while_beyond(xs, ys, beyond)
    }
    fn rests_when_held(&self) -> bool {
        self.op.rests_when_held()
    }
    fn trial_curvature(&self) -> Option<f64> {
        self.op.trial_curvature()
    }
    fn trial_value(&mut self, x: f64) -> Option<Result<Trial<f64>>> {
        self.op.trial_value(x)
    }
    fn fold_probe(&mut self, along: &f64) -> bool {
        self.op.fold_probe(along)
    }
}

impl SamplePeriod<f64> for SpecModel {
    fn set_sample_period(&mut self, dt: f64) -> Result<()> {
        self.op.set_sample_period(dt)
    }
}

impl Parameters<f64> for SpecModel {
    fn n_params(&self) -> usize {
        self.op.n_params()
    }
    fn params_into(&self, out: &mut Vec<f64>) {
        self.op.params_into(out)
    }
    fn params(&self) -> Vec<f64> {
        self.op.params()
    }
    fn param_names(&self) -> Vec<String> {
        self.op.param_names()
    }
    fn set_params(&mut self, p: &[f64]) -> Result<()> {
        self.op.set_params(p)
    }
    fn param_domains(&self) -> Vec<Domain> {
        self.op.param_domains()
    }
}

impl Derivatives<f64> for SpecModel {
    /// The spec with the current parameters, built over [`Dual`] (the
    /// spec's sample period, not one set since with `set_sample_period`).
    fn to_dual(&self) -> Option<Box<dyn Operator<Dual>>> {
        let spec = self.spec.with_params(&self.op.params()).ok()?;
        spec.build_dual().ok()
    }
}
