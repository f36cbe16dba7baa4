//! One FMU instance: the model, its input and output, the samples
//! committed since the start (for parameter changes), and its mode. Safe
//! Rust; `fmi2::exports` and `fmi3::exports` put the C functions around
//! it. Its messages name the functions of the FMI version it serves.

use super::derivatives::{partials, Known};
use super::{guid, Fmi, VR_FIRST_PARAM, VR_X, VR_Y};
use crate::model::Model;
use std::path::{Path, PathBuf};

/// Relative difference below which a step size is the current sample
/// period (see [`Instance::do_step`]).
pub const SAME_PERIOD: f64 = 1e-9;

/// Where an instance is in the co-simulation state machine (FMI 3.0's
/// Step Mode is `Stepping`; the FMU has no Event Mode).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    Instantiated,
    Initialization,
    Stepping,
    Terminated,
}

/// What can be saved and restored: everything that changes while stepping.
#[derive(Clone)]
pub struct Snapshot {
    pub(super) model: Model,
    pub(super) x: f64,
    pub(super) y: f64,
    pub(super) time: f64,
    pub(super) period: Option<f64>,
    /// Each committed sample's input and the sample period it ran at.
    pub(super) history: Vec<(f64, f64)>,
    pub(super) mode: Mode,
}

/// An instance.
pub struct Instance {
    /// The model as instantiated (for `fmi2Reset`/`fmi3Reset`).
    start: Model,
    /// Whose function names the messages use.
    api: Fmi,
    now: Snapshot,
}

/// The path of a `file:` URI (`file:///a/b`, `file:/a/b`,
/// `file://localhost/a/b`), percent-decoded.
pub fn uri_path(uri: &str) -> Result<PathBuf, String> {
    let rest = uri
        .strip_prefix("file://localhost/")
        .map(|r| format!("/{r}"))
        .or_else(|| uri.strip_prefix("file:///").map(|r| format!("/{r}")))
        .or_else(|| uri.strip_prefix("file:/").map(|r| format!("/{r}")))
        .ok_or_else(|| format!("fmuResourceLocation `{uri}` is not a file: URI"))?;
    let bytes = rest.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            let hex = std::str::from_utf8(&bytes[i + 1..i + 3]).unwrap_or("");
            let v = u8::from_str_radix(hex, 16)
                .map_err(|_| format!("fmuResourceLocation `{uri}`: bad escape %{hex}"))?;
            out.push(v);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out)
        .map(PathBuf::from)
        .map_err(|_| format!("fmuResourceLocation `{uri}` is not UTF-8"))
}

impl Instance {
    /// The instance of the spec in `resources/model.json` under the
    /// resource URI (FMI 2.0), checked against the description's `guid`.
    pub fn from_resources(resources: &str, expected_guid: &str) -> Result<Instance, String> {
        Instance::from_resource_dir(&uri_path(resources)?, expected_guid, Fmi::V2)
    }

    /// The instance of the spec in `model.json` in the directory
    /// `resources` (FMI 3.0 passes it as a path), checked against the
    /// description's GUID (FMI 3.0: instantiation token).
    pub fn from_resource_dir(
        resources: &Path,
        expected_guid: &str,
        api: Fmi,
    ) -> Result<Instance, String> {
        let path = resources.join("model.json");
        let json = std::fs::read_to_string(&path)
            .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        let found = guid(&json);
        if found != expected_guid {
            return Err(format!(
                "GUID {expected_guid} does not match the FMU's resources/model.json ({found})"
            ));
        }
        let model = Model::from_json(&json).map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(Instance::new(model).speaking(api))
    }

    /// A fresh instance of `model`, speaking FMI 2.0.
    pub fn new(model: Model) -> Instance {
        Instance {
            api: Fmi::V2,
            now: Snapshot {
                model: model.clone(),
                x: 0.0,
                y: 0.0,
                time: 0.0,
                period: None,
                history: Vec::new(),
                mode: Mode::Instantiated,
            },
            start: model,
        }
    }

    /// The instance with messages naming the functions of `api`.
    pub fn speaking(mut self, api: Fmi) -> Instance {
        self.api = api;
        self
    }

    /// The FMI version whose function names the messages use.
    pub fn api(&self) -> Fmi {
        self.api
    }

    pub fn mode(&self) -> Mode {
        self.now.mode
    }

    /// The time of the last communication point.
    pub fn time(&self) -> f64 {
        self.now.time
    }

    /// The start time (`fmi2SetupExperiment`; in FMI 3.0 an argument of
    /// `fmi3EnterInitializationMode`).
    pub fn setup(&mut self, start_time: f64) -> Result<(), String> {
        let f = match self.api {
            Fmi::V2 => "fmi2SetupExperiment",
            Fmi::V3 => "fmi3EnterInitializationMode",
        };
        self.expect_mode(Mode::Instantiated, f, "only after instantiation or reset")?;
        if !start_time.is_finite() {
            return Err(format!("{f}: startTime {start_time} is not finite"));
        }
        self.now.time = start_time;
        Ok(())
    }

    /// `Ok` in `mode`; otherwise the error `"{function}: {otherwise}"`.
    fn expect_mode(&self, mode: Mode, function: &str, otherwise: &str) -> Result<(), String> {
        if self.now.mode == mode {
            Ok(())
        } else {
            Err(format!("{function}: {otherwise}"))
        }
    }

    pub fn enter_initialization(&mut self) -> Result<(), String> {
        let f = self.api.function("EnterInitializationMode");
        self.expect_mode(Mode::Instantiated, &f, "only after instantiation or reset")?;
        self.now.mode = Mode::Initialization;
        Ok(())
    }

    /// Leaves initialization: `y` is the model's initial output.
    pub fn exit_initialization(&mut self) -> Result<(), String> {
        let f = self.api.function("ExitInitializationMode");
        self.expect_mode(Mode::Initialization, &f, "not in initialization mode")?;
        self.now.y = self.initial_output()?;
        self.now.mode = Mode::Stepping;
        Ok(())
    }

    /// The output at input 0 from the initial state (nothing committed):
    /// a sample with no change of input, so it does not depend on the
    /// sample period (which a spec may leave to the step size).
    fn initial_output(&mut self) -> Result<f64, String> {
        let op = self.now.model.operator_mut();
        let y = op
            .trial(0.0)
            .map_err(|e| format!("the initial output: {e}"))?
            .output;
        op.reset();
        Ok(y)
    }

    pub fn terminate(&mut self) {
        self.now.mode = Mode::Terminated;
    }

    /// Back to the state after instantiation: the description's start
    /// values (parameters set since are forgotten), input 0, time 0.
    pub fn reset(&mut self) {
        *self = Instance::new(self.start.clone()).speaking(self.api);
    }

    /// One step: the current input is the sample at `t + h`. A step size
    /// `h` that differs from the current sample period by more than
    /// [`SAME_PERIOD`] (relative) becomes the new period.
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<(), String> {
        // (the name only on an error: a step allocates nothing)
        let api = self.api;
        let f = move || api.function("DoStep");
        if self.now.mode != Mode::Stepping {
            return Err(format!(
                "{}: only after {}",
                f(),
                self.api.function("ExitInitializationMode")
            ));
        }
        if !(h > 0.0 && h.is_finite() && t.is_finite()) {
            return Err(format!(
                "{}: communicationStepSize must be positive and finite (got {h} at t = {t})",
                f()
            ));
        }
        let s = &mut self.now;
        // Hosts compute a step as the difference of two rounded
        // communication points, so a constant step wobbles in its last
        // bits (relative 1e-12 after 10^4 steps): within SAME_PERIOD of the
        // current period it is that period.
        let same = s.period.is_some_and(|p| (h - p).abs() <= SAME_PERIOD * p);
        if !same {
            s.model
                .set_sample_period(h)
                .map_err(|e| format!("{} at t = {t}: step size {h}: {e}", f()))?;
            s.period = Some(h);
        }
        s.y = s
            .model
            .step(s.x)
            .map_err(|e| format!("{} at t = {t} (input x = {}): {e}", f(), s.x))?;
        // The period the sample ran at (not `h`, which may be a few ulps
        // off it): a replay then sets the very same periods.
        s.history.push((s.x, s.period.unwrap_or(h)));
        s.time = t + h;
        Ok(())
    }

    pub fn get_real(&self, vr: u32) -> Result<f64, String> {
        match vr {
            VR_X => Ok(self.now.x),
            VR_Y => Ok(self.now.y),
            _ => {
                let i = self.param_index(vr)?;
                Ok(self.now.model.operator().params()[i])
            }
        }
    }

    fn param_index(&self, vr: u32) -> Result<usize, String> {
        let n = self.now.model.names().len();
        vr.checked_sub(VR_FIRST_PARAM)
            .map(|i| i as usize)
            .filter(|&i| i < n)
            .ok_or_else(|| {
                format!(
                    "no {} variable with value reference {vr} (0 = x, 1 = y, 2..{} parameters)",
                    self.api.real(),
                    VR_FIRST_PARAM as usize + n
                )
            })
    }

    /// Sets the variables `vrs` to `values` together: the input, or
    /// parameters (one rebuild for all, so tied ones can move together).
    /// On an error nothing changes.
    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), String> {
        if self.now.mode == Mode::Terminated {
            return Err(format!(
                "{}: the instance is terminated",
                self.api.set_real()
            ));
        }
        let mut x = self.now.x;
        // Read only when a parameter is set: a host sets the input alone
        // before every step.
        let mut params: Option<Vec<f64>> = None;
        for (&vr, &v) in vrs.iter().zip(values) {
            match vr {
                VR_X => {
                    if !v.is_finite() {
                        return Err(format!("x: input {v} is not finite"));
                    }
                    x = v;
                }
                VR_Y => return Err("y is an output; it cannot be set".into()),
                _ => {
                    let i = self.param_index(vr)?;
                    params.get_or_insert_with(|| self.now.model.operator().params())[i] = v;
                }
            }
        }
        if let Some(p) = params {
            let current = self.now.model.operator().params();
            if p.iter()
                .zip(&current)
                .any(|(a, b)| a.to_bits() != b.to_bits())
            {
                self.change_params(&p)?;
            }
        }
        self.now.x = x;
        Ok(())
    }

    /// Rebuilds the model with `params` and replays the committed samples.
    fn change_params(&mut self, params: &[f64]) -> Result<(), String> {
        let model = self
            .now
            .model
            .with_params(params)
            .map_err(|e| e.to_string())?;
        let (model, period, y) = replay(model, &self.now.history, "with the new parameters")?;
        self.now.model = model;
        self.now.period = period;
        if let Some(y) = y {
            self.now.y = y;
        } else if self.now.mode == Mode::Stepping {
            self.now.y = self.initial_output()?;
        }
        Ok(())
    }

    /// `dvUnknown = J · dvKnown` at the current communication point:
    /// `J` the partial derivatives of the unknowns `unknown` (the output
    /// `y`) with respect to the knowns `known` (the input `x` and
    /// parameters; see [`derivatives`](super::derivatives)).
    pub fn directional_derivative(
        &self,
        unknown: &[u32],
        known: &[u32],
        dv_known: &[f64],
    ) -> Result<Vec<f64>, String> {
        if let Some(&vr) = unknown.iter().find(|&&vr| vr != VR_Y) {
            return Err(format!(
                "unknown {vr}: only the output y (value reference {VR_Y}) is an unknown"
            ));
        }
        let knowns = known
            .iter()
            .map(|&vr| match vr {
                VR_X => Ok(Known::Input),
                VR_Y => Err("y is an output, not a known".to_string()),
                _ => self.param_index(vr).map(Known::Param),
            })
            .collect::<Result<Vec<Known>, String>>()?;
        if let Some(v) = dv_known.iter().find(|v| !v.is_finite()) {
            return Err(format!("dvKnown: {v} is not finite"));
        }
        let partials = partials(&self.now, &knowns)?;
        let dy: f64 = partials.iter().zip(dv_known).map(|(d, v)| d * v).sum();
        Ok(vec![dy; unknown.len()])
    }

    /// The model as instantiated.
    pub(crate) fn start(&self) -> &Model {
        &self.start
    }

    pub fn snapshot(&self) -> Snapshot {
        self.now.clone()
    }

    pub fn restore(&mut self, s: &Snapshot) {
        self.now = s.clone();
    }
}

/// Runs `model` (from its initial state) through the committed samples
/// `history` as `do_step` ran them: the model, its sample period and its
/// last output (`None` for no samples). `why` says what the replay is for,
/// in an error.
pub(super) fn replay(
    mut model: Model,
    history: &[(f64, f64)],
    why: &str,
) -> Result<(Model, Option<f64>, Option<f64>), String> {
    let mut period = None;
    let mut y = None;
    for (k, &(x, h)) in history.iter().enumerate() {
        if period != Some(h) {
            model
                .set_sample_period(h)
                .map_err(|e| format!("replaying step {k} {why}: {e}"))?;
            period = Some(h);
        }
        y = Some(
            model
                .step(x)
                .map_err(|e| format!("replaying step {k} {why}: {e}"))?,
        );
    }
    Ok((model, period, y))
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    #[test]
    fn file_uris_of_every_common_form() {
        for uri in [
            "file:///a/b%20c",
            "file:/a/b%20c",
            "file://localhost/a/b%20c",
        ] {
            assert_eq!(uri_path(uri).unwrap(), PathBuf::from("/a/b c"), "{uri}");
        }
        assert!(uri_path("http://x/a").is_err());
        assert!(uri_path("file:///a%zz").is_err());
        assert!(uri_path("file:///a%2").unwrap().ends_with("a%2"));
    }

    /// An instance of `json` ready to step.
    pub(in crate::fmu) fn stepping(json: &str) -> Instance {
        let mut inst = Instance::new(Model::from_json(json).unwrap());
        inst.setup(0.0).unwrap();
        inst.enter_initialization().unwrap();
        inst.exit_initialization().unwrap();
        inst
    }

    /// Steps `inst` through `xs` with step `h`: the outputs.
    pub(in crate::fmu) fn run(inst: &mut Instance, xs: &[f64], h: f64) -> Vec<f64> {
        xs.iter()
            .map(|&x| {
                let t = inst.time();
                inst.set_real(&[VR_X], &[x]).unwrap();
                inst.do_step(t, h).unwrap();
                inst.get_real(VR_Y).unwrap()
            })
            .collect()
    }

    const PLAY: &str = r#"{"type": "play", "r": 0.5, "y0": 0.25}"#;

    #[test]
    fn steps_commit_the_input_as_a_sample() {
        let mut inst = stepping(PLAY);
        assert_eq!(inst.get_real(VR_Y).unwrap(), 0.25); // initial output
        assert_eq!(run(&mut inst, &[1.0, 0.8, -1.0], 0.1), [0.5, 0.5, -0.5]);
        assert!((inst.time() - 0.3).abs() < 1e-15);
    }

    #[test]
    fn the_step_size_is_the_period_of_a_rate_dependent_model() {
        let spec = r#"{"type": "mass_spring_damper", "m": 1, "c": 2, "k": 400, "dt": 1}"#;
        let xs: Vec<f64> = (0..40).map(|i| (i as f64 * 0.2).sin()).collect();
        let hs: Vec<f64> = (0..40)
            .map(|i| if i % 3 == 0 { 0.01 } else { 0.004 })
            .collect();
        let mut inst = stepping(spec);
        let mut want = Model::from_json(spec).unwrap();
        for (&x, &h) in xs.iter().zip(&hs) {
            let t = inst.time();
            inst.set_real(&[VR_X], &[x]).unwrap();
            inst.do_step(t, h).unwrap();
            want.operator_mut().set_sample_period(h).unwrap();
            assert_eq!(inst.get_real(VR_Y).unwrap(), want.step(x).unwrap());
        }
        // A step a few ulps off is the same period: bit for bit the same.
        let (mut a, mut b) = (stepping(spec), stepping(spec));
        for (k, &x) in xs.iter().enumerate() {
            let jitter = if k % 2 == 1 {
                1.0 + 4.0 * f64::EPSILON
            } else {
                1.0
            };
            for (inst, h) in [(&mut a, 0.004), (&mut b, 0.004 * jitter)] {
                let t = inst.time();
                inst.set_real(&[VR_X], &[x]).unwrap();
                inst.do_step(t, h).unwrap();
            }
            assert_eq!(a.get_real(VR_Y).unwrap(), b.get_real(VR_Y).unwrap());
        }
    }

    #[test]
    fn a_parameter_change_replays_the_history() {
        let xs = [1.0, 0.8, -1.0, 0.3];
        let mut inst = stepping(PLAY);
        run(&mut inst, &xs[..2], 0.1);
        inst.set_real(&[VR_FIRST_PARAM], &[0.1]).unwrap(); // r
        let after = run(&mut inst, &xs[2..], 0.1);
        let mut want = stepping(r#"{"type": "play", "r": 0.1, "y0": 0.25}"#);
        assert_eq!(after, run(&mut want, &xs, 0.1)[2..]);
        // Refused: outside the domain; nothing changed.
        assert!(inst.set_real(&[VR_FIRST_PARAM], &[-1.0]).is_err());
        assert_eq!(inst.get_real(VR_FIRST_PARAM).unwrap(), 0.1);
        assert!(inst.set_real(&[VR_Y], &[1.0]).is_err());
        assert!(inst.set_real(&[99], &[1.0]).is_err());
        assert!(inst.set_real(&[VR_X], &[f64::NAN]).is_err());
    }

    #[test]
    fn snapshots_replay_identically_and_reset_returns_to_the_start() {
        let xs: Vec<f64> = (0..50).map(|i| (i as f64 * 0.3).sin()).collect();
        let mut inst = stepping(PLAY);
        run(&mut inst, &xs[..20], 0.01);
        let snap = inst.snapshot();
        let first = run(&mut inst, &xs[20..], 0.01);
        inst.restore(&snap);
        assert_eq!(run(&mut inst, &xs[20..], 0.01), first);
        inst.set_real(&[VR_FIRST_PARAM], &[0.1]).unwrap();
        inst.reset();
        assert_eq!(inst.mode(), Mode::Instantiated);
        assert_eq!(inst.get_real(VR_FIRST_PARAM).unwrap(), 0.5); // the start value again
        assert!(inst.do_step(0.0, 0.1).is_err());
        assert!(stepping(PLAY).do_step(0.0, 0.0).is_err());
    }
}
