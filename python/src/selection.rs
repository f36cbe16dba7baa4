//! `compare`: candidate structures fitted on training records, scored on
//! held-out ones and ranked (the library's `identify::selection`, as
//! `hysteron compare` ranks them).

use crate::array::samples;
use crate::errors::{FitError, InputError, ParameterError};
use crate::model::Model;
use hysteron::identify::metrics::Lowpass;
use hysteron::identify::selection::{self, Candidate, Outcome, SelectionOptions};
use hysteron::identify::{FitOptions, MultiStart, Record};
use hysteron::Operator;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// A candidate as given: `{"name", "model", "free", "own"?}`.
struct Given {
    name: String,
    spec: hysteron::models::Spec,
    free: Vec<String>,
    own: Vec<String>,
}

/// A candidate ready to fit: its model at the sample period asked for,
/// and the indices of its free parameters.
struct Prepared {
    model: Model,
    free: Vec<usize>,
    own: Vec<usize>,
}

/// Reads `candidates[i]`; a missing or mistyped field is an error naming
/// it.
fn given(i: usize, c: &Bound<'_, PyDict>) -> PyResult<Given> {
    let field = |key: &str| -> PyResult<Bound<'_, PyAny>> {
        c.get_item(key)?
            .ok_or_else(|| ParameterError::new_err(format!("candidates[{i}]: missing `{key}`")))
    };
    let name: String = field("name")?
        .extract()
        .map_err(|_| ParameterError::new_err(format!("candidates[{i}].name: a string")))?;
    let model: PyRef<'_, Model> = field("model")?.extract().map_err(|_| {
        ParameterError::new_err(format!("candidates[{i}].model: a hysteron_rs.Model"))
    })?;
    let names = |value: Bound<'_, PyAny>, key: &str| -> PyResult<Vec<String>> {
        value
            .extract()
            .map_err(|_| ParameterError::new_err(format!("candidates[{i}].{key}: a list of names")))
    };
    let free = names(field("free")?, "free")?;
    if free.is_empty() {
        return Err(ParameterError::new_err(format!(
            "candidates[{i}].free: name at least one parameter"
        )));
    }
    let own = match c.get_item("own")? {
        None => Vec::new(),
        Some(v) => names(v, "own")?,
    };
    Ok(Given {
        name,
        spec: model.spec().clone(),
        free,
        own,
    })
}

/// The candidate's model at the period `dt` (where given) and its
/// parameters' indices; a model that does not build there, or a name that
/// matches no parameter, is the candidate's own failure.
fn prepare(g: &Given, dt: Option<f64>) -> Result<Prepared, String> {
    let spec = match dt {
        Some(dt) => g.spec.with_dt(dt),
        None => g.spec.clone(),
    };
    let model = Model::from_rust_spec(spec).map_err(|e| format!("model: {e}"))?;
    let free = model.indices(&g.free).map_err(|e| format!("free: {e}"))?;
    let own = model.indices(&g.own).map_err(|e| format!("own: {e}"))?;
    Ok(Prepared { model, free, own })
}

/// Reads records `[(x, y), …]` named `what`.
fn records(
    what: &str,
    list: &[(Bound<'_, PyAny>, Bound<'_, PyAny>)],
) -> PyResult<Vec<(Vec<f64>, Vec<f64>)>> {
    list.iter()
        .enumerate()
        .map(|(i, (x, y))| {
            let read = |obj: &Bound<'_, PyAny>, field: &str| -> PyResult<Vec<f64>> {
                let at = format!("{what}[{i}].{field}");
                let v = samples(obj, &at)?;
                match v.iter().position(|s| !s.is_finite()) {
                    Some(k) => Err(InputError::new_err(format!(
                        "{at}: sample {k} is not finite ({})",
                        v[k]
                    ))),
                    None => Ok(v),
                }
            };
            Ok((read(x, "x")?, read(y, "y")?))
        })
        .collect()
}

/// Records as the library takes them.
fn as_rust(d: &[(Vec<f64>, Vec<f64>, usize)]) -> Vec<Record<'_>> {
    d.iter()
        .map(|(x, y, skip)| Record { x, y, skip: *skip })
        .collect()
}

/// One row of the table, as a dict.
fn row<'py>(
    py: Python<'py>,
    g: &Given,
    prepared: Option<&Prepared>,
    outcome: &Result<Outcome, String>,
    rank: Option<usize>,
    p_next: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("rank", rank)?;
    d.set_item("candidate", &g.name)?;
    match outcome {
        Ok(o) => {
            let (mean, worst) = o.full_band();
            let low_mw = o.lowpassed();
            d.set_item("k", o.k)?;
            d.set_item("n", o.n)?;
            d.set_item("training_cost", o.cost)?;
            d.set_item("aic", o.aic)?;
            d.set_item("bic", o.bic)?;
            d.set_item("heldout_nrmse_mean", mean)?;
            d.set_item("heldout_nrmse_worst", worst)?;
            d.set_item("heldout_lowpassed_mean", low_mw.map(|m| m.0))?;
            d.set_item("heldout_lowpassed_worst", low_mw.map(|m| m.1))?;
            d.set_item("p_vs_next", p_next)?;
            d.set_item("converged", o.converged)?;
            d.set_item("error", py.None())?;
            let full = o.held_out.iter().map(|h| h.0);
            let low: Option<Vec<f64>> = o.held_out.iter().map(|h| h.1).collect();
            d.set_item("heldout_nrmse", PyList::new(py, full)?)?;
            d.set_item("heldout_lowpassed", low)?;
            let model = match prepared {
                Some(p) => {
                    let fitted = p
                        .model
                        .spec()
                        .with_params(&o.params)
                        .map_err(crate::errors::spec_error)?;
                    Some(Py::new(py, Model::from_rust_spec(fitted)?)?)
                }
                None => None,
            };
            d.set_item("model", model)?;
        }
        Err(e) => {
            let columns = selection::COLUMNS
                .iter()
                .filter(|k| !matches!(**k, "rank" | "candidate" | "error"));
            for key in columns.chain(&["heldout_nrmse", "heldout_lowpassed", "model"]) {
                d.set_item(key, py.None())?;
            }
            d.set_item("error", e)?;
        }
    }
    Ok(d)
}

/// Compares candidate structures: each candidate, a dict
/// `{"name": str, "model": Model, "free": [names], "own": [names]}`
/// (`own` optional: parameters fitted per training record), is fitted on
/// the `train` records `[(x, y), …]` as `fit_records` fits it, and scored
/// on the `validate` records by its held-out NRMSE (RMS error over the RMS
/// of the measured output, from sample `skip` on), and with `lowpass`
/// (Hz; needs `dt`) after a zero-phase 4th-order Butterworth low-pass of
/// both signals. With `cross_validate=K` instead of `validate`, each
/// training record is scored by the fit on the folds without it (record
/// `i` in fold `i mod K`).
///
/// Returns one dict per candidate, best first, with the keys of
/// `hysteron compare --csv` (`rank`, `candidate`, `k`, `n`,
/// `training_cost`, `aic`, `bic`, `heldout_nrmse_mean`,
/// `heldout_nrmse_worst`, `heldout_lowpassed_mean`,
/// `heldout_lowpassed_worst`, `p_vs_next`, `converged`, `error`) and the
/// per-record `heldout_nrmse`, `heldout_lowpassed` and the fitted `model`;
/// `pandas.DataFrame(rows)` makes it a table. The ranking is by the
/// held-out mean (low-passed with `lowpass`); `p_vs_next` is a two-sided
/// sign test against the next rank over the per-record errors. A
/// candidate whose fit or score fails has its `error` and no rank; the
/// others go on. The GIL is released while the candidates run (in
/// parallel).
#[pyfunction]
#[pyo3(signature = (candidates, train, validate=None, *, cross_validate=None, skip=0, dt=None, lowpass=None, patience=200, max_seconds=None, starts=1, spread=1.3862943611198906, seed=0))]
#[allow(clippy::too_many_arguments)] // the Python keyword arguments
pub fn compare<'py>(
    py: Python<'py>,
    candidates: Vec<Bound<'py, PyDict>>,
    train: Vec<(Bound<'py, PyAny>, Bound<'py, PyAny>)>,
    validate: Option<Vec<(Bound<'py, PyAny>, Bound<'py, PyAny>)>>,
    cross_validate: Option<usize>,
    skip: usize,
    dt: Option<f64>,
    lowpass: Option<f64>,
    patience: usize,
    max_seconds: Option<f64>,
    starts: usize,
    spread: f64,
    seed: u64,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    if candidates.len() < 2 {
        return Err(ParameterError::new_err(format!(
            "candidates: give at least two to compare (got {})",
            candidates.len()
        )));
    }
    let dt = crate::period::period(dt, None, 0)?;
    let given = candidates
        .iter()
        .enumerate()
        .map(|(i, c)| given(i, c))
        .collect::<PyResult<Vec<_>>>()?;
    for (i, g) in given.iter().enumerate() {
        if given[..i].iter().any(|o| o.name == g.name) {
            return Err(ParameterError::new_err(format!(
                "candidates[{i}].name: `{}` is used twice",
                g.name
            )));
        }
    }
    let prepared: Vec<Result<Prepared, String>> = given.iter().map(|g| prepare(g, dt)).collect();
    let train = records("train", &train)?;
    let validate = records("validate", validate.as_deref().unwrap_or(&[]))?;
    let lowpass = match (lowpass, dt) {
        (None, _) => None,
        (Some(hz), Some(dt)) => Some(
            Lowpass::butterworth(hz, 1.0 / dt)
                .map_err(|e| InputError::new_err(format!("lowpass: {e}")))?,
        ),
        (Some(_), None) => {
            return Err(InputError::new_err(
                "lowpass needs the sample period: give dt (seconds)",
            ))
        }
    };
    let as_records = |data: &[(Vec<f64>, Vec<f64>)]| -> Vec<(Vec<f64>, Vec<f64>, usize)> {
        data.iter()
            .map(|(x, y)| (x.clone(), y.clone(), skip))
            .collect()
    };
    let (train, validate) = (as_records(&train), as_records(&validate));
    // the candidates that could be prepared run; the others keep their error
    let ready: Vec<(usize, &Prepared, Box<dyn Operator<f64>>)> = prepared
        .iter()
        .enumerate()
        .filter_map(|(i, p)| p.as_ref().ok().map(|p| (i, p)))
        .map(|(i, p)| Ok((i, p, dyn_clone::clone_box(p.model.operator()?))))
        .collect::<PyResult<_>>()?;
    let opts = SelectionOptions {
        fit: FitOptions {
            patience,
            max_seconds,
            ..FitOptions::default()
        },
        starts: MultiStart {
            starts,
            spread,
            seed,
        },
        lowpass,
        cross_validate,
    };
    let ran = py.detach(|| {
        let candidates: Vec<Candidate<'_>> = ready
            .iter()
            .map(|(_, p, op)| Candidate {
                model: op.as_ref(),
                free: p.free.clone(),
                own: p.own.clone(),
            })
            .collect();
        selection::compare(&candidates, &as_rust(&train), &as_rust(&validate), &opts)
    });
    // every candidate refused for the same reason: the request itself
    if let Some(Err(why)) = ran.first() {
        if ran.iter().all(|o| o.as_ref().err() == Some(why)) && !why.starts_with("fit") {
            return Err(FitError::new_err(why.clone()));
        }
    }
    let mut outcomes: Vec<Result<Outcome, String>> = prepared
        .iter()
        .map(|p| match p {
            Ok(_) => Err(String::new()),
            Err(e) => Err(e.clone()),
        })
        .collect();
    for ((i, _, _), o) in ready.iter().zip(ran) {
        if let Some(slot) = outcomes.get_mut(*i) {
            *slot = o;
        }
    }
    let errors: Vec<Option<Vec<f64>>> = outcomes
        .iter()
        .map(|o| o.as_ref().ok().map(Outcome::ranking_errors))
        .collect();
    let ranking = selection::rank(&errors);
    ranking
        .order
        .iter()
        .filter_map(|&i| Some((i, given.get(i)?, outcomes.get(i)?)))
        .map(|(i, g, o)| {
            row(
                py,
                g,
                prepared.get(i).and_then(|p| p.as_ref().ok()),
                o,
                ranking.rank.get(i).copied().flatten(),
                ranking.p_next.get(i).copied().flatten(),
            )
        })
        .collect()
}
