//! Excitation signals and the experiments of the paper (its Figures 3, 9
//! and 10), reproduced with the transmission model.
//!
//! The model is rate-independent: a signal's timing does not change the
//! force at a given input path. What differs between the paper's runs is
//! the input **amplitude** a position-controlled drive reaches at each
//! frequency (limited bandwidth) and the **initial state**. The drive is
//! modelled as a first-order position loop, `A(f) = A0 / √(1 + (f/f_bw)²)`.

use crate::{paper_state, TransmissionParams, TransmissionState};
use hysteron_operators::{Error, Operator, Result};
use serde::Serialize;
use std::f64::consts::TAU;
use std::ops::Range;

/// A sampled input signal.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct Signal {
    /// Time (s).
    pub t: Vec<f64>,
    /// Input displacement (deg).
    pub x: Vec<f64>,
}

impl Signal {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// True when there are no samples.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Appends `other` after a pause of `pause ≥ 0` seconds during which
    /// the input holds its last value (sampled at `fs > 0`).
    pub fn then(mut self, pause: f64, fs: f64, other: &Signal) -> Result<Signal> {
        hysteron_operators::check::non_negative("pause", pause)?;
        check_positive("fs", fs)?;
        let t_end = self.t.last().copied().unwrap_or(0.0);
        let x_end = self.x.last().copied().unwrap_or(0.0);
        let n_pause = sample_count("pause", pause, fs)?;
        for k in 1..=n_pause {
            self.t.push(t_end + k as f64 / fs);
            self.x.push(x_end);
        }
        let t0 = t_end + n_pause as f64 / fs + if self.t.is_empty() { 0.0 } else { 1.0 / fs };
        self.t.extend(other.t.iter().map(|t| t0 + t));
        self.x.extend_from_slice(&other.x);
        Ok(self)
    }
}

fn check_positive(name: &str, v: f64) -> Result<()> {
    hysteron_operators::check::positive(name, v)
}

/// The most samples one generated signal may have (10⁹, 8 GB of `f64`).
pub const MAX_SAMPLES: f64 = 1e9;

/// `round(duration · fs)` as a count, or an error naming `name` when it is
/// not finite or above [`MAX_SAMPLES`].
fn sample_count(name: &str, duration: f64, fs: f64) -> Result<usize> {
    let n = (duration * fs).round();
    if n.is_finite() && (0.0..=MAX_SAMPLES).contains(&n) {
        Ok(n as usize)
    } else {
        Err(Error::InvalidParameter {
            name: name.into(),
            value: duration,
            reason: "gives more samples than MAX_SAMPLES at this sampling rate",
        })
    }
}

/// `x(t) = A sin(2π f t)` for `cycles` periods at sampling rate `fs`,
/// starting at `t = 0` (so `x` starts at 0, the models' initial input).
pub fn sine(freq: f64, amplitude: f64, cycles: f64, fs: f64) -> Result<Signal> {
    check_positive("freq", freq)?;
    hysteron_operators::check::finite("amplitude", amplitude)?;
    check_positive("cycles", cycles)?;
    check_positive("fs", fs)?;
    let n = sample_count("cycles", cycles / freq, fs)? + 1;
    let t: Vec<f64> = (0..n).map(|i| i as f64 / fs).collect();
    let x = t
        .iter()
        .map(|t| amplitude * (TAU * freq * t).sin())
        .collect();
    Ok(Signal { t, x })
}

/// A rate-independent input history: straight segments through `corners`
/// (the turning points of major and minor loops), from the first corner,
/// each cut into equal steps at most `step` apart, ending exactly on its
/// corner (the first corner itself is not a sample).
///
/// ```
/// use hysteron_models::experiments::through_corners;
/// let x = through_corners(&[0.0, 1.0, 0.5], 0.25).unwrap();
/// assert_eq!(x, vec![0.25, 0.5, 0.75, 1.0, 0.75, 0.5]);
/// ```
pub fn through_corners(corners: &[f64], step: f64) -> Result<Vec<f64>> {
    check_positive("step", step)?;
    for (i, &c) in corners.iter().enumerate() {
        hysteron_operators::check::finite(&format!("corners[{i}]"), c)?;
    }
    let mut x = Vec::new();
    for (i, w) in corners.windows(2).enumerate() {
        if let [from, to] = *w {
            let n = sample_count(
                &format!("corners[{}]", i + 1),
                (to - from).abs() / step,
                1.0,
            )?;
            let n = n.max(1);
            x.extend((1..=n).map(|k| from + (to - from) * k as f64 / n as f64));
        }
    }
    Ok(x)
}

/// Linear chirp from `f0` to `f1` over `duration` seconds with an amplitude
/// that depends on the instantaneous frequency: `x(t) = A(f(t)) sin φ(t)`,
/// `f(t) = f0 + (f1 − f0) t / T`, `φ(t) = 2π (f0 t + (f1 − f0) t² / (2T))`.
pub fn chirp(
    f0: f64,
    f1: f64,
    duration: f64,
    fs: f64,
    amplitude: impl Fn(f64) -> f64,
) -> Result<Signal> {
    check_positive("f0", f0)?;
    check_positive("f1", f1)?;
    check_positive("duration", duration)?;
    check_positive("fs", fs)?;
    let n = sample_count("duration", duration, fs)? + 1;
    let t: Vec<f64> = (0..n).map(|i| i as f64 / fs).collect();
    let k = (f1 - f0) / duration;
    let x = t
        .iter()
        .map(|&t| amplitude(f0 + k * t) * (TAU * (f0 * t + 0.5 * k * t * t)).sin())
        .collect::<Vec<f64>>();
    if let Some(bad) = x.iter().find(|v| !v.is_finite()) {
        return Err(Error::InvalidParameter {
            name: "amplitude".into(),
            value: *bad,
            reason: "the amplitude function must be finite",
        });
    }
    Ok(Signal { t, x })
}

/// A position-controlled drive with first-order bandwidth `f_bw`: the
/// amplitude it reaches at frequency `f` for a command `a0`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Drive {
    /// Commanded amplitude (deg).
    pub a0: f64,
    /// Bandwidth (Hz).
    pub f_bw: f64,
}

impl Drive {
    /// `A(f) = a0 / √(1 + (f/f_bw)²)`.
    pub fn amplitude(&self, f: f64) -> f64 {
        self.a0 / (1.0 + (f / self.f_bw).powi(2)).sqrt()
    }
}

/// One experiment: a name, an input signal and the model parameters
/// (including the initial state) it starts from.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Experiment {
    /// Short name, usable as a file name.
    pub name: String,
    /// What the experiment reproduces.
    pub description: String,
    /// The input.
    pub signal: Signal,
    /// Model parameters, including initial states.
    pub params: TransmissionParams,
    /// The labelled stretches of `signal` (pauses between them excluded),
    /// in order; a single-piece experiment has one part covering it all.
    pub parts: Vec<Part>,
}

/// A labelled stretch of an experiment's signal: samples `range`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Part {
    /// Short label, e.g. `5 Hz`.
    pub label: String,
    /// Sample indices of the stretch in the experiment's signal.
    pub range: Range<usize>,
}

/// Pieces played one after the other with `pause` seconds of held input
/// between them: the joined signal and where each piece landed in it.
fn in_sequence(pieces: Vec<(&str, Signal)>, pause: f64, fs: f64) -> Result<(Signal, Vec<Part>)> {
    let mut joined = Signal::default();
    let mut parts = Vec::with_capacity(pieces.len());
    for (i, (label, piece)) in pieces.into_iter().enumerate() {
        joined = joined.then(if i == 0 { 0.0 } else { pause }, fs, &piece)?;
        let end = joined.len();
        parts.push(Part {
            label: label.into(),
            range: end - piece.len()..end,
        });
    }
    Ok((joined, parts))
}

fn whole(label: &str, signal: &Signal) -> Vec<Part> {
    vec![Part {
        label: label.into(),
        range: 0..signal.len(),
    }]
}

/// Sampling rate of the paper's experiments as reproduced here (Hz).
pub const FS: f64 = 1000.0;

/// The drive of the reproduced experiments: 1.5 deg commanded, 2 Hz
/// bandwidth (illustrative, like the model parameters): 1.50 deg at
/// 0.05 Hz, 1.46 deg at 0.5 Hz, 0.56 deg at 5 Hz.
pub const DRIVE: Drive = Drive { a0: 1.5, f_bw: 2.0 };

/// The paper's experiments with the given model parameters:
///
/// * `sines`: 0.05 Hz (2 cycles), 0.5 Hz (4 cycles) and 5 Hz (10 cycles) in
///   sequence with 1 s pauses (Figure 3), its [`Part`]s labelled `0.05 Hz`,
///   `0.5 Hz` and `5 Hz`;
/// * `sine-5hz-I`, `sine-5hz-II`: 5 Hz from two opposite initial states:
///   the slider at either stop, the spring state `h0` at its bound
///   `±(α/(β+γ))^{1/n}` and the friction holding the spring's force
///   (Figure 3, H(0)I and H(0)II);
/// * `chirp`: linear down-chirp 5 → 0.1 Hz over 20 s with the drive's
///   amplitude growing as the frequency falls (Figure 10).
pub fn paper_experiments(params: &TransmissionParams) -> Result<Vec<Experiment>> {
    let a = |f: f64| DRIVE.amplitude(f);
    // Validate first: the initial states below are derived from the
    // parameters.
    params.build()?;
    let (sines, sines_parts) = in_sequence(
        vec![
            ("0.05 Hz", sine(0.05, a(0.05), 2.0, FS)?),
            ("0.5 Hz", sine(0.5, a(0.5), 4.0, FS)?),
            ("5 Hz", sine(5.0, a(5.0), 10.0, FS)?),
        ],
        1.0,
        FS,
    )?;
    let five = sine(5.0, a(5.0), 10.0, FS)?;
    let down_chirp = chirp(5.0, 0.1, 20.0, FS, a)?;
    let loaded = |sign: f64| {
        let mut p = params.clone();
        p.slider0 = sign * 0.5 * p.backlash;
        let bound = (p.spring.alpha / (p.spring.beta + p.spring.gamma)).abs();
        p.spring.h0 = sign * bound.powf(1.0 / p.spring.n);
        // In equilibrium at x = 0: the spring sits at z = −slider0 and the
        // friction holds its force H = w S z + (1 − w) S h0 (within the
        // Coulomb level; at the stop the contact takes any excess).
        let z = -p.slider0;
        let s = p.spring.stiffness.eval(z).0;
        let h_force = p.spring.w * s * z + (1.0 - p.spring.w) * s * p.spring.h0;
        p.friction.y0 = h_force.clamp(-p.friction.f_c, p.friction.f_c);
        p
    };
    Ok(vec![
        Experiment {
            name: "sines".into(),
            description: "0.05, 0.5 and 5 Hz sines in sequence (Figure 3)".into(),
            signal: sines,
            params: params.clone(),
            parts: sines_parts,
        },
        Experiment {
            name: "sine-5hz-I".into(),
            description: "5 Hz from initial state I: slider at the upper stop, spring state at +bound".into(),
            parts: whole("5 Hz", &five),
            signal: five.clone(),
            params: loaded(1.0),
        },
        Experiment {
            name: "sine-5hz-II".into(),
            description: "5 Hz from initial state II: slider at the lower stop, spring state at -bound".into(),
            parts: whole("5 Hz", &five),
            signal: five,
            params: loaded(-1.0),
        },
        Experiment {
            name: "chirp".into(),
            description: "linear down-chirp 5 -> 0.1 Hz over 20 s, amplitude growing as frequency falls (Figure 10)".into(),
            parts: whole("5 -> 0.1 Hz", &down_chirp),
            signal: down_chirp,
            params: params.clone(),
        },
    ])
}

/// A simulated record: the input, the transmitted force and the internal
/// states at every sample.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct Record {
    /// Time (s).
    pub t: Vec<f64>,
    /// Input (deg).
    pub x: Vec<f64>,
    /// Transmitted force (Nm).
    pub force: Vec<f64>,
    /// Internal states after each sample.
    pub state: Vec<TransmissionState>,
}

/// Runs the paper's model with `params` over `signal`, recording the
/// internal states.
pub fn simulate(params: &TransmissionParams, signal: &Signal) -> Result<Record> {
    let mut model = params.build()?;
    let mut rec = Record {
        t: signal.t.clone(),
        x: signal.x.clone(),
        force: Vec::with_capacity(signal.len()),
        state: Vec::with_capacity(signal.len()),
    };
    for (i, &x) in signal.x.iter().enumerate() {
        let f = model.trial(x).map_err(|e| e.at_sample(i))?.output;
        model.commit();
        rec.force.push(f);
        rec.state.push(paper_state(&model, x));
    }
    Ok(rec)
}
