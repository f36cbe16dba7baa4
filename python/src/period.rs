//! The sample period of a rate-dependent model from Python: `dt=` (seconds)
//! or `time=` (an array of uniformly spaced time stamps, one per sample).

use crate::array::samples;
use crate::errors::{InputError, ParameterError};
use pyo3::prelude::*;

/// How far a step of `time` may differ from the first step, relative to
/// it: the rounding of written time stamps (the CLI's `--time-column`
/// takes the same).
pub const TIME_STEP_REL_TOL: f64 = 1e-3;

/// The period given by `dt` or `time` (at most one; `None` if neither):
/// `dt` must be positive and finite; `time` must have `n` samples (one per
/// input sample), at least two, increasing with every step within
/// [`TIME_STEP_REL_TOL`] of the first, and its period is the mean step.
/// Errors name the argument and the sample.
pub fn period(dt: Option<f64>, time: Option<&Bound<'_, PyAny>>, n: usize) -> PyResult<Option<f64>> {
    match (dt, time) {
        (Some(_), Some(_)) => Err(ParameterError::new_err(
            "give the sample period by dt= or by time=, not both",
        )),
        (Some(dt), None) if dt > 0.0 && dt.is_finite() => Ok(Some(dt)),
        (Some(dt), None) => Err(ParameterError::new_err(format!(
            "dt: the sample period must be positive and finite (got {dt})"
        ))),
        (None, Some(t)) => time_step(&samples(t, "time")?, n).map(Some),
        (None, None) => Ok(None),
    }
}

/// The period of the time stamps `t` of `n` samples.
fn time_step(t: &[f64], n: usize) -> PyResult<f64> {
    if t.len() != n {
        return Err(InputError::new_err(format!(
            "time: has {} stamps, but the input has {n} samples (one stamp per sample)",
            t.len()
        )));
    }
    let [t0, t1, ..] = t else {
        return Err(InputError::new_err(
            "time: needs at least two stamps to give a sample period",
        ));
    };
    let first = t1 - t0;
    if !(first > 0.0 && first.is_finite()) {
        return Err(InputError::new_err(format!(
            "time[1]: time does not increase ({t1} after {t0})"
        )));
    }
    for (i, w) in t.windows(2).enumerate() {
        let step = w[1] - w[0];
        if !step.is_finite() || (step - first).abs() > TIME_STEP_REL_TOL * first {
            return Err(InputError::new_err(format!(
                "time[{}]: the step {step} (from {} to {}) differs from the first step {first} \
                 by more than {TIME_STEP_REL_TOL} relative: time must be uniformly spaced",
                i + 1,
                w[0],
                w[1]
            )));
        }
    }
    Ok((t[n - 1] - t0) / (n - 1) as f64)
}
