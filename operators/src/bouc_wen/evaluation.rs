//! How a spring evaluates its samples, chosen once when it is built.

use super::{BoucWenParams, StateSolver};
use crate::flow_sensitivity::{SensitiveFlow, SensitivityHint};
use crate::flow_table::{FlowTable, Hint};
use crate::hysteretic_state::{Power, StateEquation};
use crate::Float;

/// The evaluation method of a [`BoucWen`](super::BoucWen) spring: one per
/// module of this folder, chosen from the exponent, the solver and the
/// scalar type when the spring is built, never per sample.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Evaluation<T> {
    /// `n = 1`: every sample in closed form from its branch start
    /// (`closed_form.rs`).
    ClosedForm,
    /// Over `f32`/`f64` with [`StateSolver::Tabulated`]: the flow
    /// tabulated (`tabulated.rs`), and where it has the lookups were (speed
    /// only; results do not depend on it). States outside the table are
    /// integrated.
    Table(FlowTable<T>, Hint),
    /// Over dual numbers with [`StateSolver::Tabulated`]: the flow of the
    /// parameters' values tabulated with its derivatives
    /// (`sensitive.rs`). Where it does not reach, the sample is
    /// integrated.
    Sensitive(Box<SensitiveFlow>, SensitivityHint),
    /// Dormand–Prince 5(4) from sample to sample ([`StateSolver::Adaptive`],
    /// and parameter sets no table covers).
    Adaptive,
}

impl<T: Float> Evaluation<T> {
    /// The method for parameters `p` whose state equation is `eq`, with
    /// tolerance `rtol` and `solver`.
    pub(super) fn choose(
        p: &BoucWenParams<T>,
        eq: &StateEquation<T>,
        rtol: T,
        solver: StateSolver,
    ) -> Self {
        if eq.power == Power::One {
            return Evaluation::ClosedForm;
        }
        if solver == StateSolver::Adaptive {
            return Evaluation::Adaptive;
        }
        if !T::CARRIES_DERIVATIVES {
            return FlowTable::new(eq).map_or(Evaluation::Adaptive, |table| {
                Evaluation::Table(table, Hint::default())
            });
        }
        // Over a dual scalar the flow of the values is tabulated with its
        // derivatives (those of the flow, not of the table's interpolant):
        // the same powers as the f64 spring (the same values), but at n = 1
        // the general one: ∂/∂n needs |g|^n ln |g|.
        let v = |t: T| t.as_f64();
        let power = match Power::new(v(p.n)) {
            Power::One => Power::Real(1.0),
            other => other,
        };
        let eq = StateEquation::with_power(v(p.alpha), v(p.beta), v(p.gamma), power, v(rtol));
        SensitiveFlow::new(eq).map_or(Evaluation::Adaptive, |flow| {
            Evaluation::Sensitive(Box::new(flow), SensitivityHint::default())
        })
    }

    /// The same method with its lookup hints reset, for a spring of the
    /// same flow (a fit that moves only `S`, `w` or the initial state
    /// builds no table).
    pub(super) fn reused(&self) -> Self {
        match self {
            Evaluation::Table(table, _) => Evaluation::Table(table.clone(), Hint::default()),
            Evaluation::Sensitive(flow, _) => {
                Evaluation::Sensitive(flow.clone(), SensitivityHint::default())
            }
            Evaluation::ClosedForm => Evaluation::ClosedForm,
            Evaluation::Adaptive => Evaluation::Adaptive,
        }
    }

    /// Whether the flow is tabulated.
    pub(super) fn is_tabulated(&self) -> bool {
        matches!(self, Evaluation::Table(..) | Evaluation::Sensitive(..))
    }
}
