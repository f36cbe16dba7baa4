//! Model specs: a serde data description of any composed model.
//!
//! A [`Spec`] is a tree: leaves are the elementary operators (with the
//! parameter structs of `hysteron-operators`), inner nodes are the
//! combinators of `hysteron-composition`, and [`Spec::build`] turns it into
//! a boxed [`Operator`]. In JSON every node is an object whose `type` field
//! names the variant (snake case) next to the variant's fields:
//!
//! ```json
//! {
//!   "type": "series",
//!   "left": { "type": "mms", "f_c": 1.5, "k": 30.0 },
//!   "right": { "type": "gain", "k": 10.0 },
//!   "limits": { "type": "gap", "b": 0.3, "r0": 0.0 }
//! }
//! ```
//!
//! Optional fields: `y0`, `s0`, `f0`, `h0`, `z0`, a PI bank's `y0` and a
//! Maxwell-slip or GMS bank's `f0` (default 0 / empty), a LuGre or GMS
//! model's `delta` (default 2), a GMS model's `sigma2` (default 0), a
//! Preisach model's `start` (default `"from_below"`), a series' `limits` (default none: `{"type": "none"}`),
//! an implicit combinator's `solver` (default [`SolverOptions::default`],
//! and each of its fields may be left out). Unknown fields are errors.
//!
//! Errors name where they are: a JSON error the path in the document
//! (`right.stiffness.s[3]`) with serde's message; a parameter rejected by
//! [`Spec::build`] the path through the tree, each node as `field.type`
//! (`series.right.bouc_wen.stiffness.s[3]: must be ≥ 0 (got -1)`).

use crate::TransmissionParams;
use hysteron_composition::{
    OperatorExt, Oversample, PiBank, PiBankParams, PiInverse, SolverOptions, TravelLimits,
};
use hysteron_operators::{
    check, BoucWen, BoucWenParams, Dahl, DahlParams, DeadZone, DeadZoneParams, ElastoPlastic,
    ElastoPlasticParams, Error, Gain, Gms, GmsParams, LuGre, LuGreParams, MassSpringDamper,
    MassSpringDamperParams, MaxwellSlip, MaxwellSlipParams, Mms, MmsParams, Operator, Play,
    PlayParams, Preisach, PreisachMeasure, PreisachParams, PreisachStart, Saturation,
    SaturationParams, StiffnessMap, Stop, StopParams, ViscousDamper,
};
use serde::{Deserialize, Deserializer, Serialize};
use std::path::Path;

/// A data description of a model: an elementary operator or a combinator
/// of specs. Serialized with an internal `type` tag (see the
/// [module documentation](self)).
///
/// ```
/// use hysteron_models::Spec;
///
/// let spec = Spec::from_json(r#"{
///     "type": "cascade",
///     "first": { "type": "play", "r": 0.5 },
///     "second": { "type": "dead_zone", "b_l": -1.0, "b_r": 1.0 }
/// }"#)?;
/// let mut model = spec.build()?;
/// assert_eq!(model.run(&[3.0])?, vec![1.5]); // play → 2.5, dead-zone → 1.5
/// // JSON round trip
/// assert_eq!(Spec::from_json(&spec.to_json_pretty()?)?, spec);
/// // errors name the path
/// let err = Spec::from_json(r#"{"type": "scaled", "w": 2, "inner": {"type": "gain"}}"#)
///     .unwrap_err();
/// assert_eq!(err.path(), "inner");
/// assert!(err.to_string().starts_with("inner: missing field `k`"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Serialize, Debug, Clone, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Spec {
    /// Play (backlash) operator, [`Play`].
    Play(PlayParams<f64>),
    /// Stop operator, [`Stop`].
    Stop(StopParams<f64>),
    /// Elastic-plastic (Maxwell-slip) element, [`ElastoPlastic`].
    Elastoplastic(ElastoPlasticParams<f64>),
    /// Dead-zone, [`DeadZone`].
    DeadZone(DeadZoneParams<f64>),
    /// Saturation, [`Saturation`].
    Saturation(SaturationParams<f64>),
    /// Linear gain `y = k x`, [`Gain`].
    Gain {
        /// The gain (finite).
        k: f64,
    },
    /// Modified Maxwell-slip friction, [`Mms`].
    Mms(MmsParams<f64>),
    /// Bouc-Wen-like spring, [`BoucWen`].
    BoucWen(BoucWenParams<f64>),
    /// Prandtl-Ishlinskii bank of plays, [`PiBank`].
    PiBank(PiBankParams<f64>),
    /// The analytic inverse [`PiInverse`] of the Prandtl-Ishlinskii bank
    /// with these (forward) parameters, same fields as `pi_bank`: the
    /// bank's cumulative weights must be positive and its initial states
    /// reachable (see [`PiInverse`]).
    PiInverse(PiBankParams<f64>),
    /// Preisach model, [`Preisach`]: `"measure"` is one of
    /// `{"grid": {"t": [..], "mu": [[..], ..]}}`,
    /// `{"table": {"x": [..], "e": [[..], ..]}}`,
    /// `{"uniform": {"mu", "x_min", "x_max"}}` or
    /// `{"tanh": {"amplitude", "hc", "w", "x_min", "x_max"}}`; `"start"` is
    /// `"from_below"` (default) or `"from_above"`.
    Preisach(PreisachParams<f64>),
    /// The paper's model from its named parameters (built by
    /// [`TransmissionParams::build`]); a convenience for the generic
    /// `series` that `Spec::from(&TransmissionParams)` gives.
    Transmission(TransmissionParams),
    /// Cascade `y = second[first[x]]`.
    Cascade {
        /// Applied first.
        first: Box<Spec>,
        /// Applied to the output of `first`.
        second: Box<Spec>,
    },
    /// Parallel `y = left[x] + right[x]`.
    Parallel {
        /// One branch.
        left: Box<Spec>,
        /// The other branch.
        right: Box<Spec>,
    },
    /// Weighted `y = w · inner[x]`.
    Scaled {
        /// The weight (finite).
        w: f64,
        /// The weighted operator.
        inner: Box<Spec>,
    },
    /// Negative feedback `y = forward[x − back[y]]`, solved each sample.
    Feedback {
        /// Forward path.
        forward: Box<Spec>,
        /// Return path.
        back: Box<Spec>,
        /// Solver tolerances (default [`SolverOptions::default`]).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        solver: Option<SolverOptions<f64>>,
    },
    /// Mechanical series: equal force, displacements add, optional travel
    /// limits on `left`.
    Series {
        /// The left element (the one the limits apply to).
        left: Box<Spec>,
        /// The right element.
        right: Box<Spec>,
        /// Travel limits on the left element (default none). In JSON
        /// `{"type": "none"}`, `{"type": "range", "lo", "hi"}` or
        /// `{"type": "gap", "b", "r0"}`.
        #[serde(
            default = "no_limits",
            skip_serializing_if = "is_no_limits",
            serialize_with = "LimitsSer::serialize"
        )]
        limits: TravelLimits<f64>,
        /// Solver tolerances (default [`SolverOptions::default`]).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        solver: Option<SolverOptions<f64>>,
    },
    /// Numerical inverse of a non-decreasing operator.
    Inverse {
        /// The operator inverted.
        inner: Box<Spec>,
        /// Solver tolerances (default [`SolverOptions::default`]).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        solver: Option<SolverOptions<f64>>,
    },
    /// Linear mass-spring-damper driven by force, [`MassSpringDamper`]
    /// (rate-dependent: `dt` is its sample period, not a parameter).
    MassSpringDamper(MassSpringDamperParams<f64>),
    /// Viscous damper `F = c ẋ`, [`ViscousDamper`] (rate-dependent).
    ViscousDamper {
        /// Damping coefficient `c ≥ 0`.
        c: f64,
        /// Sample period `dt > 0` (s), not a parameter.
        dt: f64,
    },
    /// `inner` run at `q` sub-steps per data sample, [`Oversample`].
    Oversample {
        /// The oversampled operator.
        inner: Box<Spec>,
        /// Sub-steps per data sample (`≥ 1`), not a parameter.
        q: usize,
    },
    /// Multi-element Maxwell-slip friction (parallel elastoplastic
    /// elements), [`MaxwellSlip`].
    MaxwellSlip(MaxwellSlipParams<f64>),
    /// Dahl friction, [`Dahl`].
    Dahl(DahlParams<f64>),
    /// LuGre friction, [`LuGre`] (rate-dependent: `dt` is its sample
    /// period, not a parameter).
    #[serde(rename = "lugre")]
    LuGre(LuGreParams<f64>),
    /// Generalized Maxwell-slip friction, [`Gms`] (rate-dependent: `dt` is
    /// its sample period, not a parameter).
    Gms(GmsParams<f64>),
}

/// What can go wrong reading or building a [`Spec`].
///
/// Every variant names where: `path` is a path in the JSON document
/// ([`Json`](SpecError::Json)), through the spec tree
/// ([`Invalid`](SpecError::Invalid)), or a file ([`Io`](SpecError::Io)).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SpecError {
    /// Malformed JSON or a document that is not a spec: syntax error,
    /// unknown `type`, missing or unknown field, wrong type.
    #[error("{path}: {message}")]
    Json {
        /// Where in the document, as `field.field[index]` (`.` for the root).
        path: String,
        /// Serde's message.
        message: String,
    },
    /// A parameter rejected when building the model.
    #[error("{path}: {message}")]
    Invalid {
        /// The path through the spec tree to the parameter, each node as
        /// `field.type`: `series.right.bouc_wen.stiffness.s[3]`.
        path: String,
        /// What the parameter must satisfy and its value:
        /// `must be ≥ 0 (got -1)`.
        message: String,
        /// The library's error, with the parameter name it gave.
        source: Error,
    },
    /// A spec file could not be read.
    #[error("{path}: {message}")]
    Io {
        /// The file.
        path: String,
        /// The operating system's message.
        message: String,
    },
}

impl SpecError {
    /// The path the error names (see the variants).
    pub fn path(&self) -> &str {
        match self {
            SpecError::Json { path, .. }
            | SpecError::Invalid { path, .. }
            | SpecError::Io { path, .. } => path,
        }
    }

    /// A build error of the node at `node` (a spec path): the parameter name
    /// the library gives is appended to the path.
    fn invalid(node: &str, source: Error) -> Self {
        let (path, message) = match &source {
            Error::InvalidParameter {
                name,
                value,
                reason,
            } => (format!("{node}.{name}"), format!("{reason} (got {value})")),
            other => (node.to_string(), other.to_string()),
        };
        SpecError::Invalid {
            path,
            message,
            source,
        }
    }

    fn json(e: &serde_path_to_error::Error<serde_json::Error>) -> Self {
        SpecError::Json {
            path: e.path().to_string(),
            message: e.inner().to_string(),
        }
    }
}

/// Largest `max_iter` / `max_expansions` a spec's solver may ask for (a
/// bound on the work per solve).
const MAX_SOLVER_ITER: usize = 100_000;

/// Most implicit combinators nested on one path: each level solves its
/// equation by probing the level inside it, so the work per sample grows
/// geometrically with the depth (about 8× per level, measured with nested
/// inverses).
const MAX_IMPLICIT_DEPTH: usize = 4;

/// Largest `q` of an `oversample` spec (a bound on the work per sample).
const MAX_OVERSAMPLE: usize = 100_000;

impl Spec {
    /// Builds the model, validating every parameter.
    ///
    /// Errors are [`SpecError::Invalid`], naming the path through the tree
    /// (`series.right.bouc_wen.stiffness.s[3]`). Besides what the operators
    /// check, a `solver` must have `rel_tol, abs_tol ∈ [0, 1e-3]` and
    /// `max_iter, max_expansions` in `[1, 100000]`, and at most 4 implicit
    /// combinators may be nested on one path.
    ///
    /// ```
    /// use hysteron_models::Spec;
    /// use hysteron_operators::PlayParams;
    /// let spec = Spec::Scaled {
    ///     w: 2.0,
    ///     inner: Box::new(Spec::Play(PlayParams { r: -1.0, y0: 0.0 })),
    /// };
    /// let err = spec.build().unwrap_err();
    /// assert_eq!(err.to_string(), "scaled.inner.play.r: must be ≥ 0 (got -1)");
    /// ```
    pub fn build(&self) -> Result<Box<dyn Operator<f64>>, SpecError> {
        let depth = self.implicit_depth();
        if depth > MAX_IMPLICIT_DEPTH {
            return Err(SpecError::invalid(
                self.kind(),
                Error::InvalidParameter {
                    name: "nesting".into(),
                    value: depth as f64,
                    reason: "at most 4 implicit combinators (feedback, series, inverse, transmission) may be nested on one path: each level multiplies the work per sample",
                },
            ));
        }
        self.build_at(self.kind())
    }

    /// The largest number of implicit combinators (solved per sample) on
    /// one path from the root to a leaf.
    pub fn implicit_depth(&self) -> usize {
        let own = usize::from(matches!(
            self,
            Spec::Feedback { .. }
                | Spec::Series { .. }
                | Spec::Inverse { .. }
                | Spec::Transmission(_)
        ));
        own + self
            .children()
            .into_iter()
            .map(|(_, c)| c.implicit_depth())
            .max()
            .unwrap_or(0)
    }

    fn build_at(&self, path: &str) -> Result<Box<dyn Operator<f64>>, SpecError> {
        let invalid = |e: Error| SpecError::invalid(path, e);
        let child =
            |field: &str, spec: &Spec| spec.build_at(&format!("{path}.{field}.{}", spec.kind()));
        let solver = |opts: &Option<SolverOptions<f64>>| -> Result<SolverOptions<f64>, SpecError> {
            let opts = opts.unwrap_or_default();
            check_solver(&opts).map_err(|e| invalid(e.in_path("solver")))?;
            Ok(opts)
        };
        Ok(match self {
            Spec::Play(p) => Play::from_params(*p).map_err(invalid)?.boxed(),
            Spec::Stop(p) => Stop::from_params(*p).map_err(invalid)?.boxed(),
            Spec::Elastoplastic(p) => ElastoPlastic::from_params(*p).map_err(invalid)?.boxed(),
            Spec::DeadZone(p) => DeadZone::from_params(*p).map_err(invalid)?.boxed(),
            Spec::Saturation(p) => Saturation::from_params(*p).map_err(invalid)?.boxed(),
            Spec::Gain { k } => Gain::new(*k).map_err(invalid)?.boxed(),
            Spec::Mms(p) => Mms::from_params(*p).map_err(invalid)?.boxed(),
            Spec::BoucWen(p) => BoucWen::from_params(p.clone()).map_err(invalid)?.boxed(),
            Spec::PiBank(p) => PiBank::from_params(p.clone()).map_err(invalid)?.boxed(),
            Spec::PiInverse(p) => PiInverse::from_params(p.clone()).map_err(invalid)?.boxed(),
            Spec::Preisach(p) => Preisach::from_params(p.clone()).map_err(invalid)?.boxed(),
            Spec::Transmission(p) => p
                .build()
                .map_err(|e| invalid(transmission_names(e)))?
                .boxed(),
            Spec::Cascade { first, second } => {
                let a = child("first", first)?;
                let b = child("second", second)?;
                a.then(b).boxed()
            }
            Spec::Parallel { left, right } => {
                let a = child("left", left)?;
                let b = child("right", right)?;
                a.plus(b).boxed()
            }
            Spec::Scaled { w, inner } => {
                check::finite("w", *w).map_err(invalid)?;
                child("inner", inner)?.scaled(*w).map_err(invalid)?.boxed()
            }
            Spec::Feedback {
                forward,
                back,
                solver: opts,
            } => {
                let opts = solver(opts)?;
                let a = child("forward", forward)?;
                let b = child("back", back)?;
                a.feedback(b).with_solver(opts).boxed()
            }
            Spec::Series {
                left,
                right,
                limits,
                solver: opts,
            } => {
                limits.validate().map_err(invalid)?;
                let opts = solver(opts)?;
                let a = child("left", left)?;
                let b = child("right", right)?;
                a.series(b)
                    .with_limits(*limits)
                    .map_err(invalid)?
                    .with_solver(opts)
                    .boxed()
            }
            Spec::Inverse {
                inner,
                solver: opts,
            } => {
                let opts = solver(opts)?;
                child("inner", inner)?.inverse().with_solver(opts).boxed()
            }
            Spec::MassSpringDamper(p) => {
                MassSpringDamper::from_params(*p).map_err(invalid)?.boxed()
            }
            Spec::ViscousDamper { c, dt } => ViscousDamper::new(*c, *dt).map_err(invalid)?.boxed(),
            Spec::MaxwellSlip(p) => MaxwellSlip::from_params(p.clone())
                .map_err(invalid)?
                .boxed(),
            Spec::Dahl(p) => Dahl::from_params(*p).map_err(invalid)?.boxed(),
            Spec::LuGre(p) => LuGre::from_params(*p).map_err(invalid)?.boxed(),
            Spec::Gms(p) => Gms::from_params(p.clone()).map_err(invalid)?.boxed(),
            Spec::Oversample { inner, q } => {
                if *q == 0 || *q > MAX_OVERSAMPLE {
                    return Err(invalid(Error::InvalidParameter {
                        name: "q".into(),
                        value: *q as f64,
                        reason: "must lie in [1, 100000]",
                    }));
                }
                let a = child("inner", inner)?;
                Oversample::new(a, *q).map_err(invalid)?.boxed()
            }
        })
    }

    /// The variant's name as written in the `type` field (`"bouc_wen"`).
    pub fn kind(&self) -> &'static str {
        match self {
            Spec::Play(_) => "play",
            Spec::Stop(_) => "stop",
            Spec::Elastoplastic(_) => "elastoplastic",
            Spec::DeadZone(_) => "dead_zone",
            Spec::Saturation(_) => "saturation",
            Spec::Gain { .. } => "gain",
            Spec::Mms(_) => "mms",
            Spec::BoucWen(_) => "bouc_wen",
            Spec::PiBank(_) => "pi_bank",
            Spec::PiInverse(_) => "pi_inverse",
            Spec::Preisach(_) => "preisach",
            Spec::Transmission(_) => "transmission",
            Spec::Cascade { .. } => "cascade",
            Spec::Parallel { .. } => "parallel",
            Spec::Scaled { .. } => "scaled",
            Spec::Feedback { .. } => "feedback",
            Spec::Series { .. } => "series",
            Spec::Inverse { .. } => "inverse",
            Spec::MassSpringDamper(_) => "mass_spring_damper",
            Spec::ViscousDamper { .. } => "viscous_damper",
            Spec::Oversample { .. } => "oversample",
            Spec::MaxwellSlip(_) => "maxwell_slip",
            Spec::Dahl(_) => "dahl",
            Spec::LuGre(_) => "lugre",
            Spec::Gms(_) => "gms",
        }
    }

    /// The child specs with their field names, in order (empty for leaves).
    pub fn children(&self) -> Vec<(&'static str, &Spec)> {
        match self {
            Spec::Cascade { first, second } => vec![("first", first), ("second", second)],
            Spec::Parallel { left, right } | Spec::Series { left, right, .. } => {
                vec![("left", left), ("right", right)]
            }
            Spec::Scaled { inner, .. }
            | Spec::Inverse { inner, .. }
            | Spec::Oversample { inner, .. } => vec![("inner", inner)],
            Spec::Feedback { forward, back, .. } => vec![("forward", forward), ("back", back)],
            _ => Vec::new(),
        }
    }

    /// A one-line outline of the tree:
    /// `series[gap b=0.3 r0=0](mms, bouc_wen)`.
    ///
    /// ```
    /// use hysteron_models::{Spec, TransmissionParams};
    /// let spec = Spec::from(&TransmissionParams::default());
    /// assert_eq!(spec.describe(), "series[gap b=0.3 r0=0](mms, bouc_wen)");
    /// ```
    pub fn describe(&self) -> String {
        let attrs = match self {
            Spec::Scaled { w, .. } => format!("[w={w}]"),
            Spec::MassSpringDamper(p) => format!("[dt={}]", p.dt),
            Spec::ViscousDamper { dt, .. } => format!("[dt={dt}]"),
            Spec::LuGre(p) => format!("[dt={}]", p.dt),
            Spec::Gms(p) => format!("[dt={}]", p.dt),
            Spec::Oversample { q, .. } => format!("[q={q}]"),
            Spec::Series { limits, .. } => match limits {
                TravelLimits::None => String::new(),
                TravelLimits::Range { lo, hi } => format!("[range lo={lo} hi={hi}]"),
                TravelLimits::Gap { b, r0 } => format!("[gap b={b} r0={r0}]"),
            },
            _ => String::new(),
        };
        let children = self.children();
        if children.is_empty() {
            return format!("{}{attrs}", self.kind());
        }
        let inner: Vec<String> = children.iter().map(|(_, c)| c.describe()).collect();
        format!("{}{attrs}({})", self.kind(), inner.join(", "))
    }

    /// Reads a spec from JSON.
    ///
    /// Errors are [`SpecError::Json`] with the path in the document and
    /// serde's message (syntax errors also give line and column).
    pub fn from_json(text: &str) -> Result<Spec, SpecError> {
        let mut de = serde_json::Deserializer::from_str(text);
        match serde_path_to_error::deserialize::<_, Spec>(&mut de) {
            Ok(spec) => {
                de.end().map_err(|e| SpecError::Json {
                    path: ".".into(),
                    message: e.to_string(),
                })?;
                Ok(spec)
            }
            Err(e) => Err(locate(text, &e)),
        }
    }

    /// Reads a spec from a JSON file ([`SpecError::Io`] if it cannot be
    /// read, otherwise as [`from_json`](Spec::from_json)).
    pub fn from_json_file(path: impl AsRef<Path>) -> Result<Spec, SpecError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|e| SpecError::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        Spec::from_json(&text)
    }

    /// Writes the spec as indented JSON (`type` first in every object;
    /// numbers in shortest round-trip form, so reading it back gives the
    /// same spec bit for bit).
    ///
    /// Serializing a spec cannot fail (non-finite numbers, which no valid
    /// spec has, are written as `null`); the error is there only so that
    /// nothing panics.
    pub fn to_json_pretty(&self) -> Result<String, SpecError> {
        serde_json::to_string_pretty(self).map_err(|e| SpecError::Json {
            path: ".".into(),
            message: e.to_string(),
        })
    }

    /// The same spec with the sample period of every rate-dependent node
    /// (`mass_spring_damper`, `viscous_damper`, `lugre`, `gms`) set to `dt`; the rest of
    /// the tree is kept. The value is checked by [`build`](Spec::build).
    ///
    /// ```
    /// use hysteron_models::Spec;
    /// let spec = Spec::from_json(r#"{"type": "oversample", "q": 4,
    ///     "inner": {"type": "viscous_damper", "c": 2, "dt": 0.1}}"#)?;
    /// assert_eq!(
    ///     spec.with_dt(0.01),
    ///     Spec::from_json(r#"{"type": "oversample", "q": 4,
    ///         "inner": {"type": "viscous_damper", "c": 2, "dt": 0.01}}"#)?
    /// );
    /// # Ok::<(), hysteron_models::SpecError>(())
    /// ```
    pub fn with_dt(&self, dt: f64) -> Spec {
        let b = |s: &Spec| Box::new(s.with_dt(dt));
        match self {
            Spec::MassSpringDamper(p) => {
                Spec::MassSpringDamper(MassSpringDamperParams { dt, ..*p })
            }
            Spec::ViscousDamper { c, .. } => Spec::ViscousDamper { c: *c, dt },
            Spec::LuGre(p) => Spec::LuGre(LuGreParams { dt, ..*p }),
            Spec::Gms(p) => Spec::Gms(GmsParams { dt, ..p.clone() }),
            Spec::Oversample { inner, q } => Spec::Oversample {
                inner: b(inner),
                q: *q,
            },
            Spec::Cascade { first, second } => Spec::Cascade {
                first: b(first),
                second: b(second),
            },
            Spec::Parallel { left, right } => Spec::Parallel {
                left: b(left),
                right: b(right),
            },
            Spec::Scaled { w, inner } => Spec::Scaled {
                w: *w,
                inner: b(inner),
            },
            Spec::Feedback {
                forward,
                back,
                solver,
            } => Spec::Feedback {
                forward: b(forward),
                back: b(back),
                solver: *solver,
            },
            Spec::Series {
                left,
                right,
                limits,
                solver,
            } => Spec::Series {
                left: b(left),
                right: b(right),
                limits: *limits,
                solver: *solver,
            },
            Spec::Inverse { inner, solver } => Spec::Inverse {
                inner: b(inner),
                solver: *solver,
            },
            Spec::Play(_)
            | Spec::Stop(_)
            | Spec::Elastoplastic(_)
            | Spec::DeadZone(_)
            | Spec::Saturation(_)
            | Spec::Gain { .. }
            | Spec::Mms(_)
            | Spec::BoucWen(_)
            | Spec::PiBank(_)
            | Spec::PiInverse(_)
            | Spec::Preisach(_)
            | Spec::MaxwellSlip(_)
            | Spec::Dahl(_)
            | Spec::Transmission(_) => self.clone(),
        }
    }

    /// Whether any node of the tree is rate-dependent (`mass_spring_damper`,
    /// `viscous_damper`, `lugre` or `gms`).
    pub fn is_rate_dependent(&self) -> bool {
        matches!(
            self,
            Spec::MassSpringDamper(_) | Spec::ViscousDamper { .. } | Spec::LuGre(_) | Spec::Gms(_)
        ) || self
            .children()
            .into_iter()
            .any(|(_, c)| c.is_rate_dependent())
    }

    /// The same spec with the parameters `p`, given in the order of the
    /// built operator's [`params`](Operator::params) (depth-first, as
    /// [`param_names`](Operator::param_names) lists them): the inverse of
    /// `spec.build()?.params()`. Everything that is not a parameter (the
    /// tree, solver options, the kind of travel limits, the number of
    /// knots or plays) is kept.
    ///
    /// * `spec.with_params(&spec.build()?.params())? == spec`;
    /// * `spec.with_params(&p)?.build()?.params() == p`.
    ///
    /// A PI bank given without `y0` keeps it left out when the new values
    /// are all zero. In a `transmission` spec the spring's initial
    /// deflection is not a parameter of its own (the model uses
    /// `z0 = −slider0`), so its entry in `p` must equal `−slider0`
    /// (otherwise an error naming `spring.z0`; a generic `series` spec,
    /// `Spec::from(&TransmissionParams)`, has no such tie).
    ///
    /// Errors: the spec itself does not build; `p` has the wrong length;
    /// the new spec does not build (a value outside its parameter's range),
    /// each as [`SpecError::Invalid`] naming the path like
    /// [`build`](Spec::build).
    ///
    /// ```
    /// use hysteron_models::Spec;
    /// let spec = Spec::from_json(r#"{"type": "scaled", "w": 2,
    ///     "inner": {"type": "play", "r": 0.5}}"#)?;
    /// let model = spec.build()?;
    /// assert_eq!(model.param_names(), ["w", "inner.play.r", "inner.play.y0"]);
    /// let fitted = spec.with_params(&[3.0, 0.25, 0.0])?;
    /// assert_eq!(fitted.build()?.params(), [3.0, 0.25, 0.0]);
    /// assert_eq!(spec.with_params(&model.params())?, spec);
    /// let err = spec.with_params(&[3.0, -1.0, 0.0]).unwrap_err();
    /// assert_eq!(err.to_string(), "scaled.inner.play.r: must be ≥ 0 (got -1)");
    /// # Ok::<(), hysteron_models::SpecError>(())
    /// ```
    pub fn with_params(&self, p: &[f64]) -> Result<Spec, SpecError> {
        let root = self.kind();
        let expected = self.build()?.n_params();
        if p.len() != expected {
            return Err(SpecError::invalid(
                root,
                Error::ParamCount {
                    expected,
                    got: p.len(),
                },
            ));
        }
        let mut rest = p;
        let spec = self.fill(root, &mut rest)?;
        if !rest.is_empty() {
            // Cannot happen for a spec that builds (the walk mirrors
            // `params_into`); an error rather than a panic all the same.
            return Err(SpecError::invalid(
                root,
                Error::ParamCount {
                    expected: p.len() - rest.len(),
                    got: p.len(),
                },
            ));
        }
        spec.build()?;
        Ok(spec)
    }

    /// [`with_params`](Spec::with_params) of the node at `path`, taking its
    /// parameters from the front of `rest` (in the order of `params_into`
    /// of the operator it builds).
    fn fill(&self, path: &str, rest: &mut &[f64]) -> Result<Spec, SpecError> {
        fn take<'a>(rest: &mut &'a [f64], n: usize) -> Result<&'a [f64], SpecError> {
            if rest.len() < n {
                return Err(SpecError::invalid(
                    ".",
                    Error::ParamCount {
                        expected: n,
                        got: rest.len(),
                    },
                ));
            }
            let (head, tail) = rest.split_at(n);
            *rest = tail;
            Ok(head)
        }
        let child = |field: &str, spec: &Spec, rest: &mut &[f64]| -> Result<Box<Spec>, SpecError> {
            Ok(Box::new(
                spec.fill(&format!("{path}.{field}.{}", spec.kind()), rest)?,
            ))
        };
        let knots = |at: &str, old: &StiffnessMap<f64>, rest: &mut &[f64]| {
            let m = old.len();
            let z = take(rest, m)?.to_vec();
            let s = take(rest, m)?.to_vec();
            StiffnessMap::new(z, s).map_err(|e| SpecError::invalid(at, e.in_path("stiffness")))
        };
        let bouc_wen = |at: &str,
                        old: &BoucWenParams<f64>,
                        rest: &mut &[f64]|
         -> Result<BoucWenParams<f64>, SpecError> {
            let v = take(rest, 7)?;
            Ok(BoucWenParams {
                w: v[0],
                alpha: v[1],
                beta: v[2],
                gamma: v[3],
                n: v[4],
                h0: v[5],
                z0: v[6],
                stiffness: knots(at, &old.stiffness, rest)?,
            })
        };
        let mms = |rest: &mut &[f64]| -> Result<MmsParams<f64>, SpecError> {
            let v = take(rest, 3)?;
            Ok(MmsParams {
                f_c: v[0],
                k: v[1],
                y0: v[2],
            })
        };
        Ok(match self {
            Spec::Play(_) => {
                let v = take(rest, 2)?;
                Spec::Play(PlayParams { r: v[0], y0: v[1] })
            }
            Spec::Stop(_) => {
                let v = take(rest, 2)?;
                Spec::Stop(StopParams { r: v[0], s0: v[1] })
            }
            Spec::Elastoplastic(_) => {
                let v = take(rest, 3)?;
                Spec::Elastoplastic(ElastoPlasticParams {
                    k: v[0],
                    f_b: v[1],
                    f0: v[2],
                })
            }
            Spec::DeadZone(_) => {
                let v = take(rest, 2)?;
                Spec::DeadZone(DeadZoneParams {
                    b_l: v[0],
                    b_r: v[1],
                })
            }
            Spec::Saturation(_) => {
                let v = take(rest, 2)?;
                Spec::Saturation(SaturationParams { lo: v[0], hi: v[1] })
            }
            Spec::Gain { .. } => Spec::Gain {
                k: take(rest, 1)?[0],
            },
            Spec::Mms(_) => Spec::Mms(mms(rest)?),
            Spec::BoucWen(old) => Spec::BoucWen(bouc_wen(path, old, rest)?),
            Spec::PiBank(old) | Spec::PiInverse(old) => {
                let m = old.r.len();
                let a0 = take(rest, 1)?[0];
                let r = take(rest, m)?.to_vec();
                let w = take(rest, m)?.to_vec();
                let y0 = take(rest, m)?;
                // An omitted y0 means all zero: keep it omitted if it still is.
                let y0 = if old.y0.is_empty() && y0.iter().all(|&v| v == 0.0) {
                    Vec::new()
                } else {
                    y0.to_vec()
                };
                let p = PiBankParams { a0, r, w, y0 };
                if matches!(self, Spec::PiInverse(_)) {
                    Spec::PiInverse(p)
                } else {
                    Spec::PiBank(p)
                }
            }
            Spec::Preisach(old) => {
                let v = take(rest, old.measure.n_params())?;
                let measure = old
                    .measure
                    .from_flat(v)
                    .map_err(|e| SpecError::invalid(path, e))?;
                Spec::Preisach(PreisachParams {
                    measure,
                    start: old.start,
                })
            }
            Spec::Transmission(old) => {
                // `TransmissionParams::build`: gap (b, r0), friction, spring
                // with z0 = −slider0.
                let gap = take(rest, 2)?;
                let (backlash, slider0) = (gap[0], gap[1]);
                let friction = mms(rest)?;
                let spring_at = format!("{path}.spring");
                let mut spring = bouc_wen(&spring_at, &old.spring, rest)?;
                if spring.z0 != 0.0 - slider0 {
                    return Err(SpecError::invalid(
                        path,
                        Error::InvalidParameter {
                            name: "spring.z0".into(),
                            value: spring.z0,
                            reason: "must equal −slider0 in a `transmission` spec \
                                     (use a generic `series` spec to set it on its own)",
                        },
                    ));
                }
                // Not used by the model: keep what the spec said.
                spring.z0 = old.spring.z0;
                Spec::Transmission(TransmissionParams {
                    backlash,
                    slider0,
                    friction,
                    spring,
                })
            }
            Spec::Cascade { first, second } => Spec::Cascade {
                first: child("first", first, rest)?,
                second: child("second", second, rest)?,
            },
            Spec::Parallel { left, right } => Spec::Parallel {
                left: child("left", left, rest)?,
                right: child("right", right, rest)?,
            },
            Spec::Scaled { inner, .. } => Spec::Scaled {
                w: take(rest, 1)?[0],
                inner: child("inner", inner, rest)?,
            },
            Spec::Feedback {
                forward,
                back,
                solver,
            } => Spec::Feedback {
                forward: child("forward", forward, rest)?,
                back: child("back", back, rest)?,
                solver: *solver,
            },
            Spec::Series {
                left,
                right,
                limits,
                solver,
            } => {
                let limits = match limits {
                    TravelLimits::None => TravelLimits::None,
                    TravelLimits::Range { .. } => {
                        let v = take(rest, 2)?;
                        TravelLimits::Range { lo: v[0], hi: v[1] }
                    }
                    TravelLimits::Gap { .. } => {
                        let v = take(rest, 2)?;
                        TravelLimits::Gap { b: v[0], r0: v[1] }
                    }
                };
                Spec::Series {
                    left: child("left", left, rest)?,
                    right: child("right", right, rest)?,
                    limits,
                    solver: *solver,
                }
            }
            Spec::Inverse { inner, solver } => Spec::Inverse {
                inner: child("inner", inner, rest)?,
                solver: *solver,
            },
            Spec::MassSpringDamper(old) => {
                let v = take(rest, 3)?;
                Spec::MassSpringDamper(MassSpringDamperParams {
                    m: v[0],
                    c: v[1],
                    k: v[2],
                    dt: old.dt,
                })
            }
            Spec::ViscousDamper { dt, .. } => Spec::ViscousDamper {
                c: take(rest, 1)?[0],
                dt: *dt,
            },
            Spec::Oversample { inner, q } => Spec::Oversample {
                inner: child("inner", inner, rest)?,
                q: *q,
            },
            Spec::MaxwellSlip(old) => {
                let n = old.k.len();
                let k = take(rest, n)?.to_vec();
                let f_b = take(rest, n)?.to_vec();
                let f0 = take(rest, n)?;
                // An omitted f0 means all zero: keep it omitted if it still is.
                let f0 = if old.f0.is_empty() && f0.iter().all(|&v| v == 0.0) {
                    Vec::new()
                } else {
                    f0.to_vec()
                };
                Spec::MaxwellSlip(MaxwellSlipParams { k, f_b, f0 })
            }
            Spec::Dahl(_) => {
                let v = take(rest, 4)?;
                Spec::Dahl(DahlParams {
                    sigma: v[0],
                    f_c: v[1],
                    alpha: v[2],
                    f0: v[3],
                })
            }
            Spec::LuGre(old) => {
                let v = take(rest, 8)?;
                Spec::LuGre(LuGreParams {
                    sigma0: v[0],
                    sigma1: v[1],
                    sigma2: v[2],
                    f_c: v[3],
                    f_s: v[4],
                    v_s: v[5],
                    delta: v[6],
                    z0: v[7],
                    dt: old.dt,
                })
            }
            Spec::Gms(old) => {
                let n = old.k.len();
                let v = take(rest, 6)?;
                let k = take(rest, n)?.to_vec();
                let alpha = take(rest, n)?.to_vec();
                let f0 = take(rest, n)?;
                let f0 = if old.f0.is_empty() && f0.iter().all(|&v| v == 0.0) {
                    Vec::new()
                } else {
                    f0.to_vec()
                };
                Spec::Gms(GmsParams {
                    k,
                    alpha,
                    f0,
                    c: v[0],
                    f_c: v[1],
                    f_s: v[2],
                    v_s: v[3],
                    delta: v[4],
                    sigma2: v[5],
                    dt: old.dt,
                })
            }
        })
    }
}

/// The paper's model as a generic spec: `left` the MMS slider, `right` the
/// spring (with its initial deflection `z0 = −slider0`, see
/// [`TransmissionParams::spring_params`]), the gap as travel limits
/// `{b: backlash, r0: slider0}`. Builds to the same model as
/// [`TransmissionParams::build`].
impl From<&TransmissionParams> for Spec {
    fn from(p: &TransmissionParams) -> Self {
        let mut spring = p.spring_params();
        if spring.z0 == 0.0 {
            spring.z0 = 0.0; // `−slider0` of a centred slider is −0
        }
        Spec::Series {
            left: Box::new(Spec::Mms(p.friction)),
            right: Box::new(Spec::BoucWen(spring)),
            limits: TravelLimits::Gap {
                b: p.backlash,
                r0: p.slider0,
            },
            solver: None,
        }
    }
}

impl From<TransmissionParams> for Spec {
    fn from(p: TransmissionParams) -> Self {
        Spec::from(&p)
    }
}

/// Checks a spec's solver options (see [`Spec::build`]).
fn check_solver(o: &SolverOptions<f64>) -> Result<(), Error> {
    check::non_negative("rel_tol", o.rel_tol)?;
    check::non_negative("abs_tol", o.abs_tol)?;
    // A loose tolerance silently returns wrong answers (rel_tol = 0.5
    // halves a spring): cap both.
    for (name, v, cap) in [("rel_tol", o.rel_tol, 1e-3), ("abs_tol", o.abs_tol, 1e-3)] {
        if v > cap {
            return Err(Error::InvalidParameter {
                name: name.into(),
                value: v,
                reason: "must be ≤ 1e-3",
            });
        }
    }
    for (name, v) in [
        ("max_iter", o.max_iter),
        ("max_expansions", o.max_expansions),
    ] {
        if !(1..=MAX_SOLVER_ITER).contains(&v) {
            return Err(Error::InvalidParameter {
                name: name.into(),
                value: v as f64,
                reason: "must lie in [1, 100000]",
            });
        }
    }
    Ok(())
}

/// The transmission's gap is its `backlash` and `slider0`: rename the
/// library's `limits.b` / `limits.r0`.
fn transmission_names(e: Error) -> Error {
    match e {
        Error::InvalidParameter {
            name,
            value,
            reason,
        } => {
            let name = match name.as_str() {
                "limits.b" => "backlash".to_string(),
                "limits.r0" => "slider0".to_string(),
                _ => name,
            };
            Error::InvalidParameter {
                name,
                value,
                reason,
            }
        }
        other => other,
    }
}

fn no_limits() -> TravelLimits<f64> {
    TravelLimits::None
}

fn is_no_limits(l: &TravelLimits<f64>) -> bool {
    matches!(l, TravelLimits::None)
}

/// Finds the path of a data error precisely. Paths are tracked through the
/// `type` tag only when it comes first in its object (the usual order, and
/// the one [`Spec::to_json_pretty`] writes); otherwise the document is
/// re-read with `type` moved first and that error's path is used.
fn locate(text: &str, e: &serde_path_to_error::Error<serde_json::Error>) -> SpecError {
    let direct = SpecError::json(e);
    if e.inner().classify() != serde_json::error::Category::Data {
        return direct;
    }
    let Ok(value) = serde_json::from_str::<serde_json::Value>(text) else {
        return direct;
    };
    let Ok(canonical) = serde_json::to_string(&TypeFirst(&value)) else {
        return direct;
    };
    let mut de = serde_json::Deserializer::from_str(&canonical);
    match serde_path_to_error::deserialize::<_, Spec>(&mut de) {
        Err(c) if c.path().to_string() != e.path().to_string() => {
            // The position refers to the re-written text: drop it.
            let inner = c.inner();
            let message = inner.to_string();
            let suffix = format!(" at line {} column {}", inner.line(), inner.column());
            SpecError::Json {
                path: c.path().to_string(),
                message: message
                    .strip_suffix(&suffix)
                    .map_or(message.clone(), str::to_string),
            }
        }
        _ => direct,
    }
}

/// Serializes a JSON value with the `type` key first in every object.
struct TypeFirst<'a>(&'a serde_json::Value);

impl Serialize for TypeFirst<'_> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        use serde_json::Value;
        match self.0 {
            Value::Object(map) => {
                let mut m = s.serialize_map(Some(map.len()))?;
                if let Some(t) = map.get("type") {
                    m.serialize_entry("type", &TypeFirst(t))?;
                }
                for (k, v) in map.iter().filter(|(k, _)| k.as_str() != "type") {
                    m.serialize_entry(k, &TypeFirst(v))?;
                }
                m.end()
            }
            Value::Array(items) => s.collect_seq(items.iter().map(TypeFirst)),
            other => other.serialize(s),
        }
    }
}

// ---------------------------------------------------------------------------
// Deserialization.
//
// A derived internally tagged enum buffers the whole object before it looks
// at the tag, and loses the path of any error inside it (so
// serde_path_to_error would report every error at the root). Instead the
// tag is read first and the rest of the object is handed, unbuffered, to an
// externally tagged derive of the same enum (`#[serde(remote)]`): errors
// keep their full path. Every parameter struct gets a strict mirror
// (`deny_unknown_fields`), so a misspelt optional field is an error rather
// than a silent default.
// ---------------------------------------------------------------------------

impl<'de> Deserialize<'de> for Spec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        tagged::deserialize(d)
    }
}

impl tagged::Tagged for Spec {
    const EXPECTING: &'static str = "a spec: an object with a `type` field";
    fn from_enum<'de, D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        SpecDef::deserialize(d)
    }
}

impl tagged::Tagged for TravelLimits<f64> {
    const EXPECTING: &'static str = "travel limits: an object with a `type` field";
    fn from_enum<'de, D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        LimitsDe::deserialize(d)
    }
}

#[derive(Deserialize)]
#[serde(remote = "Spec", rename_all = "snake_case", deny_unknown_fields)]
enum SpecDef {
    Play(#[serde(deserialize_with = "PlayDef::deserialize")] PlayParams<f64>),
    Stop(#[serde(deserialize_with = "StopDef::deserialize")] StopParams<f64>),
    Elastoplastic(
        #[serde(deserialize_with = "ElastoPlasticDef::deserialize")] ElastoPlasticParams<f64>,
    ),
    DeadZone(#[serde(deserialize_with = "DeadZoneDef::deserialize")] DeadZoneParams<f64>),
    Saturation(#[serde(deserialize_with = "SaturationDef::deserialize")] SaturationParams<f64>),
    Gain {
        k: f64,
    },
    Mms(#[serde(deserialize_with = "MmsDef::deserialize")] MmsParams<f64>),
    BoucWen(#[serde(deserialize_with = "BoucWenDef::deserialize")] BoucWenParams<f64>),
    PiBank(#[serde(deserialize_with = "PiBankDef::deserialize")] PiBankParams<f64>),
    PiInverse(#[serde(deserialize_with = "PiBankDef::deserialize")] PiBankParams<f64>),
    Preisach(#[serde(deserialize_with = "PreisachDef::deserialize")] PreisachParams<f64>),
    Transmission(#[serde(deserialize_with = "TransmissionDef::deserialize")] TransmissionParams),
    Cascade {
        first: Box<Spec>,
        second: Box<Spec>,
    },
    Parallel {
        left: Box<Spec>,
        right: Box<Spec>,
    },
    Scaled {
        w: f64,
        inner: Box<Spec>,
    },
    Feedback {
        forward: Box<Spec>,
        back: Box<Spec>,
        #[serde(default, deserialize_with = "solver")]
        solver: Option<SolverOptions<f64>>,
    },
    Series {
        left: Box<Spec>,
        right: Box<Spec>,
        #[serde(default = "no_limits", deserialize_with = "tagged::deserialize")]
        limits: TravelLimits<f64>,
        #[serde(default, deserialize_with = "solver")]
        solver: Option<SolverOptions<f64>>,
    },
    Inverse {
        inner: Box<Spec>,
        #[serde(default, deserialize_with = "solver")]
        solver: Option<SolverOptions<f64>>,
    },
    MassSpringDamper(
        #[serde(deserialize_with = "MassSpringDamperDef::deserialize")] MassSpringDamperParams<f64>,
    ),
    ViscousDamper {
        c: f64,
        dt: f64,
    },
    Oversample {
        inner: Box<Spec>,
        q: usize,
    },
    MaxwellSlip(#[serde(deserialize_with = "MaxwellSlipDef::deserialize")] MaxwellSlipParams<f64>),
    Dahl(#[serde(deserialize_with = "DahlDef::deserialize")] DahlParams<f64>),
    #[serde(rename = "lugre")]
    LuGre(#[serde(deserialize_with = "LuGreDef::deserialize")] LuGreParams<f64>),
    Gms(#[serde(deserialize_with = "GmsDef::deserialize")] GmsParams<f64>),
}

#[derive(Deserialize)]
#[serde(
    remote = "TravelLimits<f64>",
    rename_all = "snake_case",
    deny_unknown_fields
)]
enum LimitsDe {
    None,
    Range {
        lo: f64,
        hi: f64,
    },
    Gap {
        b: f64,
        #[serde(default)]
        r0: f64,
    },
}

#[derive(Serialize)]
#[serde(remote = "TravelLimits<f64>", tag = "type", rename_all = "snake_case")]
enum LimitsSer {
    None,
    Range { lo: f64, hi: f64 },
    Gap { b: f64, r0: f64 },
}

#[derive(Deserialize)]
#[serde(remote = "PlayParams<f64>", deny_unknown_fields)]
struct PlayDef {
    r: f64,
    #[serde(default)]
    y0: f64,
}

#[derive(Deserialize)]
#[serde(remote = "StopParams<f64>", deny_unknown_fields)]
struct StopDef {
    r: f64,
    #[serde(default)]
    s0: f64,
}

#[derive(Deserialize)]
#[serde(remote = "ElastoPlasticParams<f64>", deny_unknown_fields)]
struct ElastoPlasticDef {
    k: f64,
    f_b: f64,
    #[serde(default)]
    f0: f64,
}

#[derive(Deserialize)]
#[serde(remote = "DeadZoneParams<f64>", deny_unknown_fields)]
struct DeadZoneDef {
    b_l: f64,
    b_r: f64,
}

#[derive(Deserialize)]
#[serde(remote = "SaturationParams<f64>", deny_unknown_fields)]
struct SaturationDef {
    lo: f64,
    hi: f64,
}

#[derive(Deserialize)]
#[serde(remote = "MassSpringDamperParams<f64>", deny_unknown_fields)]
struct MassSpringDamperDef {
    m: f64,
    c: f64,
    k: f64,
    dt: f64,
}

#[derive(Deserialize)]
#[serde(remote = "MmsParams<f64>", deny_unknown_fields)]
struct MmsDef {
    f_c: f64,
    k: f64,
    #[serde(default)]
    y0: f64,
}

#[derive(Deserialize)]
#[serde(remote = "BoucWenParams<f64>", deny_unknown_fields)]
struct BoucWenDef {
    w: f64,
    alpha: f64,
    beta: f64,
    gamma: f64,
    n: f64,
    #[serde(default)]
    h0: f64,
    #[serde(default)]
    z0: f64,
    #[serde(deserialize_with = "stiffness")]
    stiffness: StiffnessMap<f64>,
}

#[derive(Deserialize)]
#[serde(remote = "MaxwellSlipParams<f64>", deny_unknown_fields)]
struct MaxwellSlipDef {
    k: Vec<f64>,
    f_b: Vec<f64>,
    #[serde(default)]
    f0: Vec<f64>,
}

#[derive(Deserialize)]
#[serde(remote = "DahlParams<f64>", deny_unknown_fields)]
struct DahlDef {
    sigma: f64,
    f_c: f64,
    alpha: f64,
    #[serde(default)]
    f0: f64,
}

#[derive(Deserialize)]
#[serde(remote = "LuGreParams<f64>", deny_unknown_fields)]
struct LuGreDef {
    sigma0: f64,
    sigma1: f64,
    sigma2: f64,
    f_c: f64,
    f_s: f64,
    v_s: f64,
    #[serde(default = "default_delta")]
    delta: f64,
    #[serde(default)]
    z0: f64,
    dt: f64,
}

fn default_delta() -> f64 {
    2.0
}

#[derive(Deserialize)]
#[serde(remote = "GmsParams<f64>", deny_unknown_fields)]
struct GmsDef {
    k: Vec<f64>,
    alpha: Vec<f64>,
    #[serde(default)]
    f0: Vec<f64>,
    c: f64,
    f_c: f64,
    f_s: f64,
    v_s: f64,
    #[serde(default = "default_delta")]
    delta: f64,
    #[serde(default)]
    sigma2: f64,
    dt: f64,
}

#[derive(Deserialize)]
#[serde(remote = "PiBankParams<f64>", deny_unknown_fields)]
struct PiBankDef {
    a0: f64,
    r: Vec<f64>,
    w: Vec<f64>,
    #[serde(default)]
    y0: Vec<f64>,
}

#[derive(Deserialize)]
#[serde(remote = "PreisachParams<f64>", deny_unknown_fields)]
struct PreisachDef {
    #[serde(deserialize_with = "PreisachMeasureDef::deserialize")]
    measure: PreisachMeasure<f64>,
    #[serde(default)]
    start: PreisachStart,
}

#[derive(Deserialize)]
#[serde(
    remote = "PreisachMeasure<f64>",
    rename_all = "snake_case",
    deny_unknown_fields
)]
enum PreisachMeasureDef {
    Grid {
        t: Vec<f64>,
        mu: Vec<Vec<f64>>,
    },
    Table {
        x: Vec<f64>,
        e: Vec<Vec<f64>>,
    },
    Uniform {
        mu: f64,
        x_min: f64,
        x_max: f64,
    },
    Tanh {
        amplitude: f64,
        hc: f64,
        w: f64,
        x_min: f64,
        x_max: f64,
    },
}

#[derive(Deserialize)]
#[serde(remote = "TransmissionParams", deny_unknown_fields)]
struct TransmissionDef {
    backlash: f64,
    #[serde(default)]
    slider0: f64,
    #[serde(deserialize_with = "MmsDef::deserialize")]
    friction: MmsParams<f64>,
    #[serde(deserialize_with = "BoucWenDef::deserialize")]
    spring: BoucWenParams<f64>,
}

#[derive(Deserialize)]
#[serde(remote = "SolverOptions<f64>", deny_unknown_fields)]
struct SolverDef {
    #[serde(default = "default_rel_tol")]
    rel_tol: f64,
    #[serde(default = "default_abs_tol")]
    abs_tol: f64,
    #[serde(default = "default_max_iter")]
    max_iter: usize,
    #[serde(default = "default_max_expansions")]
    max_expansions: usize,
}

fn default_rel_tol() -> f64 {
    SolverOptions::<f64>::default().rel_tol
}

fn default_abs_tol() -> f64 {
    SolverOptions::<f64>::default().abs_tol
}

fn default_max_iter() -> usize {
    SolverOptions::<f64>::default().max_iter
}

fn default_max_expansions() -> usize {
    SolverOptions::<f64>::default().max_expansions
}

/// An optional solver, each field defaulting to [`SolverOptions::default`].
fn solver<'de, D: Deserializer<'de>>(d: D) -> Result<Option<SolverOptions<f64>>, D::Error> {
    #[derive(Deserialize)]
    struct Strict(#[serde(deserialize_with = "SolverDef::deserialize")] SolverOptions<f64>);
    Ok(Option::<Strict>::deserialize(d)?.map(|s| s.0))
}

/// The knots of a stiffness map, unvalidated (checked by `build`, which
/// names the bad knot).
fn stiffness<'de, D: Deserializer<'de>>(d: D) -> Result<StiffnessMap<f64>, D::Error> {
    use serde::de::value::MapDeserializer;
    #[derive(Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Knots {
        z: Vec<f64>,
        s: Vec<f64>,
    }
    let Knots { z, s } = Knots::deserialize(d)?;
    // `StiffnessMap::new` would validate here; its derived `Deserialize`
    // does not, so the check (with the knot's name) happens at build time.
    StiffnessMap::deserialize(MapDeserializer::<_, D::Error>::new(
        [("z", z), ("s", s)].into_iter(),
    ))
}

/// Internally tagged deserialization that keeps error paths.
mod tagged {
    use serde::de::value::MapAccessDeserializer;
    use serde::de::{
        self, DeserializeSeed, Deserializer, EnumAccess, IntoDeserializer, MapAccess,
        VariantAccess, Visitor,
    };
    use std::fmt;
    use std::marker::PhantomData;

    /// A type deserialized from an object with a `type` tag through an
    /// externally tagged derive: `from_enum` is given a deserializer whose
    /// enum is the tag (the variant) and the rest of the object (its
    /// content).
    pub(super) trait Tagged: Sized {
        /// What the visitor expects, for messages.
        const EXPECTING: &'static str;
        /// Deserializes through the externally tagged derive.
        fn from_enum<'de, D: Deserializer<'de>>(d: D) -> Result<Self, D::Error>;
    }

    /// Deserializes a [`Tagged`] type from an object with a `type` field.
    pub(super) fn deserialize<'de, D: Deserializer<'de>, T: Tagged>(d: D) -> Result<T, D::Error> {
        d.deserialize_map(TaggedVisitor(PhantomData))
    }

    struct TaggedVisitor<T>(PhantomData<T>);

    impl<'de, T: Tagged> Visitor<'de> for TaggedVisitor<T> {
        type Value = T;

        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            f.write_str(T::EXPECTING)
        }

        fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<T, A::Error> {
            // Fields before the tag are kept as JSON values (their errors
            // are reported with the field name in the message).
            let mut before = Vec::new();
            loop {
                match map.next_key::<String>()? {
                    None => return Err(de::Error::missing_field("type")),
                    Some(key) if key == "type" => break,
                    Some(key) => {
                        let value: serde_json::Value = map.next_value()?;
                        before.push((key, value));
                    }
                }
            }
            T::from_enum(Content {
                rest: Rest {
                    before: before.into_iter(),
                    value: None,
                    map,
                },
            })
        }
    }

    /// The fields of the object other than the tag: first those read
    /// before it, then the rest of the live map (whose errors keep their
    /// path).
    struct Rest<A> {
        before: std::vec::IntoIter<(String, serde_json::Value)>,
        value: Option<(String, serde_json::Value)>,
        map: A,
    }

    impl<'de, A: MapAccess<'de>> MapAccess<'de> for Rest<A> {
        type Error = A::Error;

        fn next_key_seed<K: DeserializeSeed<'de>>(
            &mut self,
            seed: K,
        ) -> Result<Option<K::Value>, A::Error> {
            if let Some((key, value)) = self.before.next() {
                let k = seed.deserialize(key.clone().into_deserializer())?;
                self.value = Some((key, value));
                return Ok(Some(k));
            }
            self.map.next_key_seed(seed)
        }

        fn next_value_seed<V: DeserializeSeed<'de>>(
            &mut self,
            seed: V,
        ) -> Result<V::Value, A::Error> {
            match self.value.take() {
                Some((key, value)) => seed
                    .deserialize(value)
                    .map_err(|e| de::Error::custom(format_args!("in `{key}`: {e}"))),
                None => self.map.next_value_seed(seed),
            }
        }
    }

    /// The object as an enum: the variant is the value of `type` (read
    /// next from the live map), the content the other fields.
    struct Content<A> {
        rest: Rest<A>,
    }

    impl<'de, A: MapAccess<'de>> Deserializer<'de> for Content<A> {
        type Error = A::Error;

        fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, A::Error> {
            visitor.visit_enum(self)
        }

        serde::forward_to_deserialize_any! {
            bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string
            bytes byte_buf option unit unit_struct newtype_struct seq tuple
            tuple_struct map struct enum identifier ignored_any
        }
    }

    impl<'de, A: MapAccess<'de>> EnumAccess<'de> for Content<A> {
        type Error = A::Error;
        type Variant = Self;

        fn variant_seed<S: DeserializeSeed<'de>>(
            mut self,
            seed: S,
        ) -> Result<(S::Value, Self), A::Error> {
            // The live map stands right after the `type` key.
            let variant = self.rest.map.next_value_seed(seed)?;
            Ok((variant, self))
        }
    }

    impl<'de, A: MapAccess<'de>> VariantAccess<'de> for Content<A> {
        type Error = A::Error;

        fn unit_variant(mut self) -> Result<(), A::Error> {
            match self.rest.next_key::<String>()? {
                None => Ok(()),
                Some(key) => Err(de::Error::unknown_field(&key, &[])),
            }
        }

        fn newtype_variant_seed<S: DeserializeSeed<'de>>(
            self,
            seed: S,
        ) -> Result<S::Value, A::Error> {
            seed.deserialize(MapAccessDeserializer::new(self.rest))
        }

        fn tuple_variant<V: Visitor<'de>>(self, _len: usize, _v: V) -> Result<V::Value, A::Error> {
            Err(de::Error::custom("tuple variants cannot be tagged"))
        }

        fn struct_variant<V: Visitor<'de>>(
            self,
            _fields: &'static [&'static str],
            visitor: V,
        ) -> Result<V::Value, A::Error> {
            visitor.visit_map(self.rest)
        }
    }
}

#[cfg(test)]
mod with_params_tests {
    use super::*;

    /// The example specs of the repository (`examples/specs/*.json`).
    fn example_specs() -> Vec<(String, Spec)> {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/specs");
        let mut paths: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "json"))
            .collect();
        paths.sort();
        assert!(paths.len() >= 4, "{paths:?}");
        paths
            .into_iter()
            .map(|p| {
                let spec = Spec::from_json_file(&p).unwrap();
                (p.display().to_string(), spec)
            })
            .collect()
    }

    /// One tree with every variant and every kind of travel limits.
    fn every_variant() -> Spec {
        let b = Box::new;
        let spring = BoucWenParams {
            w: 0.6,
            alpha: 1.0,
            beta: 2.5,
            gamma: 1.5,
            n: 1.5,
            h0: 0.1,
            z0: -0.05,
            stiffness: StiffnessMap::new(vec![0.0, 0.4, 1.0], vec![10.0, 12.0, 18.0]).unwrap(),
        };
        let transmission = TransmissionParams {
            slider0: 0.05,
            ..TransmissionParams::default()
        };
        Spec::Cascade {
            first: b(Spec::Parallel {
                left: b(Spec::Scaled {
                    w: 0.5,
                    inner: b(Spec::Play(PlayParams { r: 0.2, y0: 0.1 })),
                }),
                right: b(Spec::Cascade {
                    first: b(Spec::Stop(StopParams { r: 0.3, s0: -0.1 })),
                    second: b(Spec::Elastoplastic(ElastoPlasticParams {
                        k: 20.0,
                        f_b: 1.0,
                        f0: 0.2,
                    })),
                }),
            }),
            second: b(Spec::Parallel {
                left: b(Spec::Feedback {
                    forward: b(Spec::DeadZone(DeadZoneParams {
                        b_l: -0.1,
                        b_r: 0.2,
                    })),
                    back: b(Spec::Saturation(SaturationParams { lo: -1.0, hi: 2.0 })),
                    solver: Some(SolverOptions::default()),
                }),
                right: b(Spec::Parallel {
                    left: b(Spec::Series {
                        left: b(Spec::Mms(MmsParams {
                            f_c: 1.5,
                            k: 30.0,
                            y0: 0.2,
                        })),
                        right: b(Spec::BoucWen(spring.clone())),
                        limits: TravelLimits::Range { lo: -0.2, hi: 0.3 },
                        solver: None,
                    }),
                    right: b(Spec::Parallel {
                        left: b(Spec::Series {
                            left: b(Spec::Gain { k: 3.0 }),
                            right: b(Spec::PiBank(PiBankParams {
                                a0: 0.5,
                                r: vec![0.0, 0.1, 0.4],
                                w: vec![1.0, -0.5, 2.0],
                                y0: Vec::new(),
                            })),
                            limits: TravelLimits::None,
                            solver: None,
                        }),
                        right: b(Spec::Parallel {
                            left: b(Spec::Inverse {
                                inner: b(Spec::Gain { k: 2.0 }),
                                solver: None,
                            }),
                            right: b(Spec::Parallel {
                                left: b(Spec::Transmission(transmission)),
                                right: b(Spec::PiBank(PiBankParams {
                                    a0: 0.0,
                                    r: vec![0.2],
                                    w: vec![1.0],
                                    y0: vec![0.1],
                                })),
                            }),
                        }),
                    }),
                }),
            }),
        }
    }

    fn all_specs() -> Vec<(String, Spec)> {
        let mut specs = example_specs();
        specs.push(("every variant".into(), every_variant()));
        specs.push((
            "transmission".into(),
            Spec::Transmission(TransmissionParams::default()),
        ));
        specs.push((
            "paper as series".into(),
            Spec::from(&TransmissionParams::default()),
        ));
        specs.push((
            "rate-dependent".into(),
            Spec::Parallel {
                left: Box::new(Spec::Oversample {
                    inner: Box::new(Spec::MassSpringDamper(MassSpringDamperParams {
                        m: 0.5,
                        c: 3.0,
                        k: 200.0,
                        dt: 0.0025,
                    })),
                    q: 4,
                }),
                right: Box::new(Spec::ViscousDamper { c: 2.0, dt: 0.01 }),
            },
        ));
        specs.push((
            "friction models".into(),
            Spec::Parallel {
                left: Box::new(Spec::MaxwellSlip(MaxwellSlipParams {
                    k: vec![20.0, 8.0, 3.0],
                    f_b: vec![0.2, 0.5, 0.8],
                    f0: vec![],
                })),
                right: Box::new(Spec::Parallel {
                    left: Box::new(Spec::Dahl(DahlParams {
                        sigma: 30.0,
                        f_c: 1.2,
                        alpha: 1.5,
                        f0: 0.3,
                    })),
                    right: Box::new(Spec::LuGre(LuGreParams {
                        sigma0: 1e3,
                        sigma1: 5.0,
                        sigma2: 0.4,
                        f_c: 1.0,
                        f_s: 1.3,
                        v_s: 0.05,
                        delta: 2.0,
                        z0: 1e-4,
                        dt: 0.01,
                    })),
                }),
            },
        ));
        specs.push((
            "gms".into(),
            Spec::Gms(GmsParams {
                k: vec![20.0, 8.0],
                alpha: vec![0.6, 0.4],
                f0: vec![0.1, 0.0],
                c: 15.0,
                f_c: 1.0,
                f_s: 1.4,
                v_s: 0.5,
                delta: 2.0,
                sigma2: 0.2,
                dt: 0.01,
            }),
        ));
        specs
    }

    fn bits(p: &[f64]) -> Vec<u64> {
        p.iter().map(|v| v.to_bits()).collect()
    }

    #[test]
    fn with_params_of_own_params_is_the_same_spec() {
        for (name, spec) in all_specs() {
            let p = spec.build().unwrap().params();
            let back = spec.with_params(&p).unwrap();
            assert_eq!(back, spec, "{name}");
            // bit for bit, signed zeros included
            assert_eq!(
                back.to_json_pretty().unwrap(),
                spec.to_json_pretty().unwrap(),
                "{name}"
            );
            assert_eq!(bits(&back.build().unwrap().params()), bits(&p), "{name}");
        }
    }

    /// Each parameter changed on its own ends up in the place `params()`
    /// reads it from: the new spec builds to exactly `p`.
    #[test]
    fn every_parameter_is_written_to_its_own_field() {
        for (name, spec) in all_specs() {
            let model = spec.build().unwrap();
            let p = model.params();
            let names = model.param_names();
            let domains = model.param_domains();
            let mut checked = 0;
            for i in 0..p.len() {
                let candidates = [p[i] * 0.9375, p[i] * 1.0625, p[i] + 0.0625, p[i] - 0.0625];
                let Some(v) = candidates
                    .into_iter()
                    .find(|&v| v != p[i] && domains[i].contains(v))
                else {
                    continue;
                };
                let mut q = p.clone();
                q[i] = v;
                let accepted = model.clone().set_params(&q).is_ok();
                match spec.with_params(&q) {
                    Ok(new) => {
                        assert!(accepted, "{name}: {} = {v} accepted", names[i]);
                        assert_eq!(
                            bits(&new.build().unwrap().params()),
                            bits(&q),
                            "{name}: {}",
                            names[i]
                        );
                        assert_ne!(new, spec, "{name}: {}", names[i]);
                        checked += 1;
                    }
                    Err(e) => assert!(
                        !accepted || e.to_string().contains("spring.z0"),
                        "{name}: {} = {v}: {e}",
                        names[i]
                    ),
                }
            }
            assert!(
                checked * 4 >= p.len() * 3,
                "{name}: {checked} of {}",
                p.len()
            );
        }
    }

    #[test]
    fn with_params_errors_name_the_path() {
        let spec = Spec::from(&TransmissionParams::default());
        let p = spec.build().unwrap().params();
        let e = spec.with_params(&p[1..]).unwrap_err();
        assert!(e.to_string().contains("parameter vector has"), "{e}");
        let mut q = p.clone();
        q[0] = -0.3; // limits.b
        assert_eq!(
            spec.with_params(&q).unwrap_err().to_string(),
            "series.limits.b: must be > 0 (got -0.3)"
        );
        let names = spec.build().unwrap().param_names();
        let s1 = names
            .iter()
            .position(|n| n == "right.bouc_wen.stiffness.s[1]")
            .unwrap();
        let mut q = p.clone();
        q[s1] = -1.0;
        assert_eq!(
            spec.with_params(&q).unwrap_err().to_string(),
            "series.right.bouc_wen.stiffness.s[1]: must be ≥ 0 (got -1)"
        );
        // A transmission spec ties the spring's z0 to −slider0.
        let spec = Spec::Transmission(TransmissionParams::default());
        let mut q = spec.build().unwrap().params();
        q[1] = 0.1; // slider0, z0 left at 0
        let e = spec.with_params(&q).unwrap_err().to_string();
        assert!(
            e.starts_with("transmission.spring.z0: must equal −slider0"),
            "{e}"
        );
        let z0 = spec
            .build()
            .unwrap()
            .param_names()
            .iter()
            .position(|n| n == "right.bouc_wen.z0")
            .unwrap();
        q[z0] = -0.1;
        let new = spec.with_params(&q).unwrap();
        assert_eq!(bits(&new.build().unwrap().params()), bits(&q));
        let Spec::Transmission(t) = new else {
            panic!("{new:?}")
        };
        assert_eq!(t.slider0, 0.1);
        // and a spec that does not build is an error, not a panic
        let bad = Spec::Play(PlayParams { r: -1.0, y0: 0.0 });
        assert!(bad.with_params(&[1.0, 0.0]).is_err());
    }
}
