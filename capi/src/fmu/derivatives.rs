//! Directional derivatives of the FMU's output
//! (`fmi2GetDirectionalDerivative`, `fmi3GetDirectionalDerivative`): the
//! exact partial derivatives of the output `y_k` at the current
//! communication point with respect to the input sample it took, `x_k`,
//! and to each parameter, by forward-mode dual numbers.
//!
//! `y_k = H[x_0, …, x_k; p]`: with respect to the input it is the slope of
//! the last step (the earlier samples held), `∂y_k/∂x_k`; with respect to a
//! parameter it is the total derivative along every sample committed since
//! the start, `dy_k/dp_i`, which a host would see by setting `p_i` and
//! stepping again from the start (as a parameter change does: it replays
//! the history). The dual model is replayed through the history with up
//! to [`DUAL_WIDTH`] knowns seeded per pass, so a call costs
//! `⌈knowns / 8⌉` dual runs over the steps taken. Before the first step
//! the output is the model's initial output, which depends on the
//! parameters but not on the input.
//!
//! # Reference
//! A. Griewank, A. Walther, *Evaluating Derivatives*, 2nd ed., SIAM 2008,
//! ch. 3 (forward mode); Modelica Association, *FMI 2.0.4*, §2.1.9
//! (partial derivatives).

use super::instance::Snapshot;
use hysteron::operators::{Dual, Operator, DUAL_WIDTH};

/// What a derivative is taken with respect to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Known {
    /// The input sample of the last step.
    Input,
    /// Parameter `i` (its index in the flat parameter vector).
    Param(usize),
}

/// `∂y/∂known` for each of `knowns` at the communication point of
/// `state`.
pub fn partials(state: &Snapshot, knowns: &[Known]) -> Result<Vec<f64>, String> {
    let op = state.model.operator();
    let dual = op
        .to_dual()
        .ok_or("this model has no exact derivatives (no dual twin)")?;
    let base = op.params();
    let mut out = Vec::with_capacity(knowns.len());
    for chunk in knowns.chunks(DUAL_WIDTH) {
        let mut model = dyn_clone::clone_box(&*dual);
        let mut p: Vec<Dual> = base.iter().map(|&v| Dual::constant(v)).collect();
        let mut input_slots = Vec::new();
        for (slot, known) in chunk.iter().enumerate() {
            match *known {
                Known::Input => input_slots.push(slot),
                Known::Param(i) => {
                    let v = p.get_mut(i).ok_or_else(|| format!("no parameter {i}"))?;
                    *v = Dual::variable(v.re, slot);
                }
            }
        }
        model
            .set_params(&p)
            .map_err(|e| format!("seeding the parameters: {e}"))?;
        let y = match state.history.split_last() {
            None => {
                model
                    .trial(Dual::constant(0.0))
                    .map_err(|e| format!("the initial output: {e}"))?
                    .output
            }
            Some((&(x_last, h_last), earlier)) => {
                let mut period = None;
                let mut set_period = |model: &mut Box<dyn Operator<Dual>>, h: f64| {
                    if period != Some(h) {
                        period = Some(h);
                        model.set_sample_period(Dual::constant(h))
                    } else {
                        Ok(())
                    }
                };
                for (k, &(x, h)) in earlier.iter().enumerate() {
                    set_period(&mut model, h)
                        .and_then(|()| model.trial(Dual::constant(x)))
                        .map_err(|e| format!("replaying step {k}: {e}"))?;
                    model.commit();
                }
                let mut x = Dual::constant(x_last);
                for &slot in &input_slots {
                    if let Some(e) = x.eps.get_mut(slot) {
                        *e = 1.0;
                    }
                }
                set_period(&mut model, h_last)
                    .and_then(|()| model.trial(x))
                    .map_err(|e| format!("replaying the last step: {e}"))?
                    .output
            }
        };
        for (slot, known) in chunk.iter().enumerate() {
            let d = y.eps.get(slot).copied().unwrap_or(f64::NAN);
            if !d.is_finite() {
                let what = match *known {
                    Known::Input => "x".to_string(),
                    Known::Param(i) => state
                        .model
                        .names()
                        .get(i)
                        .map_or(format!("parameter {i}"), |n| {
                            n.to_string_lossy().into_owned()
                        }),
                };
                return Err(format!("∂y/∂{what} is not finite here"));
            }
            out.push(d);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::super::instance::tests::{run, stepping};
    use super::super::instance::Instance;
    use super::super::{VR_FIRST_PARAM, VR_X, VR_Y};

    /// The central differences' step, relative to the value (absolute for
    /// a value of 0, see [`scale_of`]): small enough that the sample at which the
    /// Bouc-Wen benchmark's velocity changes sign does not move within
    /// ±step (at 1e-4 it does, and the difference is off by 0.5 %), large
    /// enough that the feedback solver's tolerance stays below 1e-6 of it.
    const STEP: f64 = 1e-6;

    /// The scale of a value's changes: its magnitude, or 1 for 0 (an
    /// initial state).
    fn scale_of(magnitude: f64) -> f64 {
        if magnitude > 0.0 {
            magnitude
        } else {
            1.0
        }
    }

    /// `y` after the samples of `inst`'s history, with the values `v` set
    /// on `vrs` together (as a host would: the history replays), or `None`
    /// where the values are refused; `inst` is left as it was.
    fn y_with(inst: &mut Instance, vrs: &[u32], v: &[f64]) -> Option<f64> {
        let snap = inst.snapshot();
        let y = inst
            .set_real(vrs, v)
            .ok()
            .map(|()| inst.get_real(VR_Y).unwrap());
        inst.restore(&snap);
        y
    }

    /// Checks the directional derivatives of `json`'s FMU after `n`
    /// samples of step `h` and amplitude `a` against central differences
    /// of the instance itself: every parameter (tied ones moved together),
    /// and the input of the last step. The comparison is norm-wise on the
    /// scaled derivatives `s_i = ∂y/∂p_i · δ_i/STEP` (the output's change
    /// per relative change of `p_i`): `|s_i − s_i^fd| ≤ 1e-6 max_j |s_j|`,
    /// so that a parameter the output barely depends on (the Bouc-Wen
    /// benchmark's `h0`, 2e-5 of the largest) is not held to a relative
    /// accuracy below the difference's own noise (the feedback solver's
    /// tolerance over the step). Returns how many were compared and the
    /// largest component-wise relative difference.
    fn check(json: &str, n: usize, h: f64, a: f64) -> (usize, f64) {
        let xs: Vec<f64> = (0..n)
            .map(|i| a * (i as f64 * 0.05).sin() * (1.0 + 0.3 * (i as f64 * 0.011).cos()))
            .collect();
        let mut inst = stepping(json);
        run(&mut inst, &xs[..n - 1], h);
        let before = inst.snapshot();
        run(&mut inst, &xs[n - 1..], h);
        let spec = inst.start().spec().clone();
        let names: Vec<String> = inst
            .start()
            .names()
            .iter()
            .map(|c| c.to_string_lossy().into_owned())
            .collect();
        let tied = spec.tied_params();
        let tied_idx: Vec<usize> = (0..names.len())
            .filter(|&i| tied.contains(&names[i]))
            .collect();
        let mut groups: Vec<Vec<usize>> = Vec::new();
        if !tied_idx.is_empty() {
            groups.push(tied_idx.clone());
        }
        groups.extend(
            (0..names.len())
                .filter(|i| !tied_idx.contains(i))
                .map(|i| vec![i]),
        );
        let p: Vec<f64> = (0..names.len())
            .map(|i| inst.get_real(VR_FIRST_PARAM + i as u32).unwrap())
            .collect();
        // (what, exact, central difference, scale)
        let mut rows: Vec<(String, f64, f64, f64)> = Vec::new();
        for group in groups {
            let vrs: Vec<u32> = group.iter().map(|&i| VR_FIRST_PARAM + i as u32).collect();
            let scale = scale_of(group.iter().map(|&i| p[i].abs()).fold(0.0, f64::max));
            let delta = STEP * scale;
            let at = |s: f64| -> Vec<f64> { group.iter().map(|&i| p[i] + s * delta).collect() };
            let (Some(up), Some(down)) = (
                y_with(&mut inst, &vrs, &at(1.0)),
                y_with(&mut inst, &vrs, &at(-1.0)),
            ) else {
                continue; // at the edge of a domain (Bouc-Wen's n = 1)
            };
            let exact = inst
                .directional_derivative(&[VR_Y], &vrs, &vec![1.0; vrs.len()])
                .unwrap()[0];
            let what = group
                .iter()
                .map(|&i| names[i].as_str())
                .collect::<Vec<_>>()
                .join("+");
            rows.push((what, exact, (up - down) / (2.0 * delta), scale));
        }
        // the input of the last step
        let x = xs[n - 1];
        let scale = scale_of(x.abs());
        let delta = STEP * scale;
        let y_at = |v: f64| {
            let mut again = stepping(json);
            again.restore(&before);
            again.set_real(&[VR_X], &[v]).unwrap();
            again.do_step(again.time(), h).unwrap();
            again.get_real(VR_Y).unwrap()
        };
        let fd = (y_at(x + delta) - y_at(x - delta)) / (2.0 * delta);
        let exact = inst
            .directional_derivative(&[VR_Y], &[VR_X], &[1.0])
            .unwrap()[0];
        rows.push(("x".into(), exact, fd, scale));
        let norm = rows.iter().map(|r| (r.1 * r.3).abs()).fold(0.0, f64::max);
        let mut worst: f64 = 0.0;
        for (what, exact, fd, scale) in &rows {
            assert!(
                ((exact - fd) * scale).abs() <= 1e-6 * norm,
                "∂y/∂{what}: exact {exact}, central difference {fd} (scale {scale}, norm {norm})"
            );
            if exact.abs() * scale > 1e-3 * norm {
                worst = worst.max((exact - fd).abs() / exact.abs());
            }
        }
        (rows.len(), worst)
    }

    #[test]
    fn the_paper_model_agrees_with_central_differences() {
        let json = include_str!("../../../examples/specs/paper.json");
        let (compared, worst) = check(json, 700, 1e-3, 1.4);
        assert!(compared >= 20, "{compared}");
        eprintln!("paper model: {compared} derivatives, worst relative difference {worst:e}");
    }

    #[test]
    fn the_boucwen_benchmark_system_agrees_with_central_differences() {
        // From a preloaded spring, z0 = 0.01: at z = 0 the law has a kink
        // (|z|), where the exact derivative is that of the branch taken and
        // a central difference averages the two.
        let json = include_str!("../../../examples/specs/boucwen-benchmark.json")
            .replace(r#""n": 1.0,"#, r#""n": 1.0, "z0": 0.01,"#);
        assert!(json.contains("z0"));
        let (compared, worst) = check(&json, 400, 1.0 / 750.0, 60.0);
        assert!(compared >= 6, "{compared}");
        eprintln!(
            "Bouc-Wen benchmark: {compared} derivatives, worst relative difference {worst:e}"
        );
    }

    #[test]
    fn a_linear_combination_and_bad_references_are_handled() {
        let mut inst = stepping(
            r#"{"type": "cascade", "first": {"type": "play", "r": 0.5},
            "second": {"type": "gain", "k": 2.0}}"#,
        );
        // before the first step: the initial output, not the input
        assert_eq!(
            inst.directional_derivative(&[VR_Y], &[VR_X], &[1.0])
                .unwrap(),
            [0.0]
        );
        run(&mut inst, &[1.0, 2.0], 0.1);
        // y = k (x − r) on the rising branch: ∂y/∂x = k, ∂y/∂r = −k, ∂y/∂k = x − r
        let (r, k) = (VR_FIRST_PARAM, VR_FIRST_PARAM + 2);
        let dv = inst
            .directional_derivative(&[VR_Y, VR_Y], &[VR_X, r, k], &[1.0, 0.5, 2.0])
            .unwrap();
        assert_eq!(dv, [2.0 - 0.5 * 2.0 + 2.0 * 1.5; 2]);
        assert!(inst
            .directional_derivative(&[VR_X], &[VR_X], &[1.0])
            .is_err());
        assert!(inst
            .directional_derivative(&[VR_Y], &[VR_Y], &[1.0])
            .is_err());
        assert!(inst.directional_derivative(&[VR_Y], &[99], &[1.0]).is_err());
        assert!(inst
            .directional_derivative(&[VR_Y], &[VR_X], &[f64::NAN])
            .is_err());
    }
}
