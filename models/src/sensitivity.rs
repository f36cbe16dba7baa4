//! Sensitivities `∂y_k/∂p_i` of a model's output sequence with respect to
//! chosen parameters, by forward-mode derivatives (dual numbers).

use crate::{Spec, SpecError};
use hysteron_operators::{Dual, Error, Operator, DUAL_WIDTH};

/// A model's output along an input and its derivatives with respect to
/// chosen parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct Sensitivity {
    /// The parameters, by name (as in [`Parameters::param_names`](hysteron_operators::Parameters::param_names)).
    pub names: Vec<String>,
    /// The output `y_k`: the `f64` model's, except where the model solves
    /// an implicit equation, whose root the dual model evaluates once more
    /// (a difference within the solver's tolerance, seen at 5e-12 on the
    /// paper's model, and varying as much with which parameters share a
    /// pass).
    pub output: Vec<f64>,
    /// `∂y_k/∂p_i`: one column per parameter, in the order of `names`.
    pub columns: Vec<Vec<f64>>,
}

/// What can go wrong computing sensitivities.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SensitivityError {
    /// The spec does not build.
    #[error(transparent)]
    Spec(#[from] SpecError),
    /// The input has no samples.
    #[error("the input is empty: sensitivities need at least one sample")]
    EmptyInput,
    /// No parameter was asked for.
    #[error("no parameter given: name at least one of {available}")]
    NoParameters {
        /// The model's parameter names, comma-separated.
        available: String,
    },
    /// A parameter name the model does not have.
    #[error("the model has no parameter `{name}` (it has {available})")]
    UnknownParameter {
        /// The name asked for.
        name: String,
        /// The model's parameter names, comma-separated.
        available: String,
    },
    /// A parameter asked for twice.
    #[error("parameter `{name}` is given twice")]
    Repeated {
        /// The name.
        name: String,
    },
    /// The model fails on the input (its error names the sample).
    #[error("{0}")]
    Model(Error),
    /// A derivative is not finite (an infinite slope, such as the inverse
    /// of an operator at a flat stretch).
    #[error("∂y/∂{param} is not finite at sample {sample}")]
    NonFiniteDerivative {
        /// The sample (0-based).
        sample: usize,
        /// The parameter.
        param: String,
    },
}

/// The sensitivities of the model `spec` builds, along `input` from its
/// initial state, with respect to the parameters named in `params`.
///
/// The model runs over [`Dual`] ([`Spec::build_dual`]) with
/// [`DUAL_WIDTH`] parameters seeded per pass (so `⌈k / 8⌉` passes for `k`
/// parameters). Every operator and combinator differentiates its own law;
/// implicit solves set their root's derivatives by the implicit function
/// theorem (`∂x/∂p = −r_p/r_x`), the Bouc-Wen spring differentiates its
/// flow (the solution of its variational equation, tabulated beside the
/// flow, or integrated where the flow is), never its table's interpolant,
/// and rate-dependent elements their per-sample update. At a kink the derivative is that of the branch the
/// model takes ([`DualN`](hysteron_operators::DualN)).
///
/// # Requirements
/// * `input` non-empty and finite (an error names the first bad sample);
/// * every name one of the model's parameters, none twice.
///
/// # Example
/// ```
/// use hysteron_models::{sensitivity::sensitivity, Spec};
/// // y = k·play_r(x): on the rising branch y = k (x − r)
/// let spec: Spec = serde_json::from_str(r#"{"type": "cascade",
///   "first": {"type": "play", "r": 0.5}, "second": {"type": "gain", "k": 2.0}}"#).unwrap();
/// let s = sensitivity(&spec, &[1.0, 2.0], &["first.play.r", "second.gain.k"]).unwrap();
/// assert_eq!(s.output, [1.0, 3.0]);
/// assert_eq!(s.columns[0], [-2.0, -2.0]); // ∂y/∂r = −k
/// assert_eq!(s.columns[1], [0.5, 1.5]); // ∂y/∂k = x − r
/// ```
///
/// # Reference
/// Forward-mode automatic differentiation with dual numbers: A. Griewank,
/// A. Walther, *Evaluating Derivatives*, 2nd ed., SIAM 2008, ch. 3.
pub fn sensitivity(
    spec: &Spec,
    input: &[f64],
    params: &[&str],
) -> Result<Sensitivity, SensitivityError> {
    let model = spec.build_dual()?;
    let names = model.param_names();
    let available = || names.join(", ");
    if params.is_empty() {
        return Err(SensitivityError::NoParameters {
            available: available(),
        });
    }
    let mut indices = Vec::with_capacity(params.len());
    for &p in params {
        let Some(i) = names.iter().position(|n| n == p) else {
            return Err(SensitivityError::UnknownParameter {
                name: p.to_string(),
                available: available(),
            });
        };
        if indices.contains(&i) {
            return Err(SensitivityError::Repeated {
                name: p.to_string(),
            });
        }
        indices.push(i);
    }
    let (output, columns) = derivatives(model.as_ref(), input, &indices).map_err(|e| match e {
        Failure::Model(e) => SensitivityError::Model(e),
        Failure::NonFinite { sample, column } => SensitivityError::NonFiniteDerivative {
            sample,
            param: params.get(column).copied().unwrap_or("?").to_string(),
        },
        Failure::Empty => SensitivityError::EmptyInput,
    })?;
    Ok(Sensitivity {
        names: params.iter().map(|s| s.to_string()).collect(),
        output,
        columns,
    })
}

/// Samples per block of a pass: dual buffers of 2048 samples (147 KB
/// each) stay in the L2 cache.
const BLOCK: usize = 2048;

/// Why [`derivatives`] failed.
#[derive(Debug, Clone, PartialEq)]
pub enum Failure {
    /// The input is empty.
    Empty,
    /// The model's error (naming its sample).
    Model(Error),
    /// The derivative in column `column` is not finite at `sample`.
    NonFinite {
        /// The sample.
        sample: usize,
        /// The column (index into the parameters asked for).
        column: usize,
    },
}

/// The output of the dual model `model` along `input` from its initial
/// state, and the columns `∂y/∂p_i` for the parameter indices `indices`
/// (seeded on the model's current parameter values), [`DUAL_WIDTH`] per
/// pass. Each pass runs a clone; `model` itself is not changed.
pub fn derivatives(
    model: &(dyn Operator<Dual> + 'static),
    input: &[f64],
    indices: &[usize],
) -> Result<(Vec<f64>, Vec<Vec<f64>>), Failure> {
    let base: Vec<f64> = model.params().iter().map(|v| v.re).collect();
    derivatives_at(model, &base, input, indices)
}

/// [`derivatives`] at the parameter values `base` (all of the model's, in
/// the order of its names) instead of the model's own: each pass sets them
/// once, seeded, on a clone (a fit's Jacobian, whose model is a template).
pub fn derivatives_at(
    model: &(dyn Operator<Dual> + 'static),
    base: &[f64],
    input: &[f64],
    indices: &[usize],
) -> Result<(Vec<f64>, Vec<Vec<f64>>), Failure> {
    let n = input.len();
    let mut output = Vec::new();
    let mut columns: Vec<Vec<f64>> = indices.iter().map(|_| Vec::with_capacity(n)).collect();
    visit_derivatives(model, base, input, indices, |block| {
        for (slot, col) in columns.iter_mut().skip(block.first_column).enumerate() {
            if slot >= block.columns {
                break;
            }
            col.extend(
                block
                    .ys
                    .iter()
                    .map(|y| y.eps.get(slot).copied().unwrap_or(0.0)),
            );
        }
        if block.first_column == 0 {
            output.extend(block.ys.iter().map(|y| y.re));
        }
    })?;
    Ok((output, columns))
}

/// One block of a pass of [`visit_derivatives`]: the dual outputs of
/// `input[offset..offset + ys.len()]`, whose derivative slot `s <
/// columns` is the column `first_column + s`.
#[derive(Debug)]
pub struct Block<'a> {
    /// The first column this pass seeds (an index into the parameters
    /// asked for).
    pub first_column: usize,
    /// How many columns this pass seeds.
    pub columns: usize,
    /// The sample of `ys[0]`.
    pub offset: usize,
    /// The dual outputs.
    pub ys: &'a [Dual],
}

/// The passes of [`derivatives_at`], handing each block of dual outputs to
/// `visit` instead of collecting them (a fit writes its Jacobian from
/// them, without a copy of every column). Fails on the model's error or at
/// the first derivative that is not finite (after visiting its block).
pub fn visit_derivatives(
    model: &(dyn Operator<Dual> + 'static),
    base: &[f64],
    input: &[f64],
    indices: &[usize],
    mut visit: impl FnMut(Block<'_>),
) -> Result<(), Failure> {
    visit_derivatives_while(model, base, input, indices, |block| {
        visit(block);
        true
    })
    .map(|_| ())
}

/// [`visit_derivatives`] for as long as `visit` answers `true`: `Ok(false)`
/// where it answered `false` (the passes stop after that block; a fit
/// computing a Jacobian it no longer needs stops so).
pub fn visit_derivatives_while(
    model: &(dyn Operator<Dual> + 'static),
    base: &[f64],
    input: &[f64],
    indices: &[usize],
    mut visit: impl FnMut(Block<'_>) -> bool,
) -> Result<bool, Failure> {
    if input.is_empty() {
        return Err(Failure::Empty);
    }
    // The record runs in blocks through buffers that stay in cache (the
    // model resumes from its state at every block, as `process` does).
    let mut xs = Vec::with_capacity(BLOCK.min(input.len()));
    let mut ys = Vec::with_capacity(BLOCK.min(input.len()));
    for (pass, chunk) in indices.chunks(DUAL_WIDTH).enumerate() {
        let mut p: Vec<Dual> = base.iter().map(|&v| Dual::constant(v)).collect();
        for (slot, &i) in chunk.iter().enumerate() {
            if let Some(v) = p.get_mut(i) {
                *v = Dual::variable(v.re, slot);
            }
        }
        let mut m = dyn_clone::clone_box(model);
        m.set_params(&p).map_err(Failure::Model)?;
        let first_column = pass * DUAL_WIDTH;
        for (b, block) in input.chunks(BLOCK).enumerate() {
            let offset = b * BLOCK;
            xs.clear();
            xs.extend(block.iter().map(|&x| Dual::constant(x)));
            ys.clear();
            ys.resize(block.len(), Dual::constant(0.0));
            m.process(&xs, &mut ys)
                .map_err(|e| Failure::Model(e.offset_by(offset)))?;
            let go_on = visit(Block {
                first_column,
                columns: chunk.len(),
                offset,
                ys: &ys,
            });
            for (k, y) in ys.iter().enumerate() {
                if let Some(slot) = y.eps.iter().take(chunk.len()).position(|d| !d.is_finite()) {
                    return Err(Failure::NonFinite {
                        sample: offset + k,
                        column: first_column + slot,
                    });
                }
            }
            if !go_on {
                return Ok(false);
            }
        }
    }
    Ok(true)
}
