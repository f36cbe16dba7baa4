//! Model specs: a serde data description of any composed model.
//!
//! A [`Spec`] is a tree: leaves are the operators of the open [`registry`]
//! (each with its declared parameter struct), inner nodes are the
//! combinators of `hysteron-composition`, and [`Spec::build`] turns it into
//! a boxed [`Operator`](hysteron_operators::Operator). In JSON every node is an object whose `type` field
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

mod build;
mod json;
mod model;
mod params;
pub mod reference;
pub mod registry;
#[cfg(test)]
mod tests;

use crate::TransmissionParams;
use hysteron_composition::{SolverOptions, TravelLimits};
use hysteron_operators::{BoucWen, Error, Leaf, Mms};
use registry::{leaf_kind, LeafKind};
use serde::Serialize;
use serde_json::Value;
use std::path::Path;

/// The combinators a spec can name (the leaves are in [`registry::LEAVES`]).
pub const COMBINATORS: &[&str] = &[
    "cascade",
    "parallel",
    "scaled",
    "feedback",
    "series",
    "inverse",
    "oversample",
    "transmission",
];

/// The `solver` field of the implicit combinators (`feedback`, `series`,
/// `inverse`), documented once.
const SOLVER_FIELD_DOC: (&str, &str) = ("solver", "optional: the implicit solve's options, an object of `rel_tol` (relative tolerance on the root, default `16 ε`), `abs_tol` (absolute tolerance, default the smallest positive normal number), `max_iter` (iterations once bracketed, default 200) and `max_expansions` (widenings of the bracket search, default 64); each may be left out");

/// What each of [`COMBINATORS`] does, for the generated reference: its
/// spec `type`, how Rust builds it, its law and whether it is solved per
/// sample.
pub const COMBINATOR_LAWS: &[Combinator] = &[
    Combinator {
        kind: "cascade",
        rust: "a.then(b)",
        law: "y = B[A[x]]",
        fields: "first, second",
        implicit: false,
        field_docs: &[("first", "the operator applied to the input"), ("second", "the operator applied to the output of `first`")],
        example: r#"{"type": "cascade", "first": {"type": "play", "r": 0.2}, "second": {"type": "dead_zone", "b_l": -0.1, "b_r": 0.1}}"#,
    },
    Combinator {
        kind: "parallel",
        rust: "a.plus(b)",
        law: "y = A[x] + B[x]",
        fields: "left, right",
        implicit: false,
        field_docs: &[("left", "one branch, driven by the input"), ("right", "the other branch, driven by the same input; the outputs add")],
        example: r#"{"type": "parallel", "left": {"type": "gain", "k": 2.0}, "right": {"type": "play", "r": 0.5}}"#,
    },
    Combinator {
        kind: "scaled",
        rust: "a.scaled(w)",
        law: "y = w A[x]",
        fields: "w (a parameter), inner",
        implicit: false,
        field_docs: &[("w", "the weight, a finite number and a fitted parameter (`scaled.w`)"), ("inner", "the weighted operator")],
        example: r#"{"type": "scaled", "w": 0.5, "inner": {"type": "stop", "r": 1.0}}"#,
    },
    Combinator {
        kind: "feedback",
        rust: "a.feedback(b)",
        law: "y = A[x − B[y]]",
        fields: "forward, back, solver",
        implicit: true,
        field_docs: &[("forward", "the forward path `A`"), ("back", "the return path `B`, driven by the output"), SOLVER_FIELD_DOC],
        example: r#"{"type": "feedback", "forward": {"type": "mms", "f_c": 1.0, "k": 40.0}, "back": {"type": "gain", "k": 0.05}}"#,
    },
    Combinator {
        kind: "series",
        rust: "a.series(b)",
        law: "F = L[x_L] = R[x_R], x = x_L + x_R, optional travel limits on L",
        fields: "left, right, limits (none, range lo hi, gap b r0), solver",
        implicit: true,
        field_docs: &[("left", "the element the travel limits apply to (the slider, in the paper's model)"), ("right", "the other element; both carry the same force and their travels add"), ("limits", "optional, default `{\"type\": \"none\"}`: `{\"type\": \"range\", \"lo\", \"hi\"}` holds the left element's travel in `[lo, hi]`, `{\"type\": \"gap\", \"b\", \"r0\"}` in a gap of width `b ≥ 0` centred at `r0`; `b` and `r0` (or `lo`, `hi`) are fitted parameters (`limits.b`)"), SOLVER_FIELD_DOC],
        example: r#"{"type": "series", "left": {"type": "mms", "f_c": 1.5, "k": 30.0}, "right": {"type": "bouc_wen", "w": 0.6, "alpha": 1.0, "beta": 2.5, "gamma": 1.5, "n": 1.0, "stiffness": 10.0}, "limits": {"type": "gap", "b": 0.3, "r0": 0.0}}"#,
    },
    Combinator {
        kind: "inverse",
        rust: "a.inverse()",
        law: "u = A⁻¹[x] for a non-decreasing A",
        fields: "inner, solver",
        implicit: true,
        field_docs: &[("inner", "the operator inverted; it must be non-decreasing in its input (an error names the sample where it is not)"), SOLVER_FIELD_DOC],
        example: r#"{"type": "inverse", "inner": {"type": "parallel", "left": {"type": "gain", "k": 1.0}, "right": {"type": "play", "r": 0.3}}}"#,
    },
    Combinator {
        kind: "oversample",
        rust: "Oversample::new(a, q)",
        law: "A run at q sub-steps per sample, the input linear in between; rate-dependent nodes at dt/q",
        fields: "inner, q",
        implicit: false,
        field_docs: &[("inner", "the oversampled operator"), ("q", "sub-steps per data sample, an integer ≥ 1 (not a fitted parameter)")],
        example: r#"{"type": "oversample", "inner": {"type": "lugre", "sigma0": 1e5, "sigma1": 300.0, "sigma2": 0.4, "f_c": 1.0, "f_s": 1.5, "v_s": 0.01, "dt": 1e-3}, "q": 4}"#,
    },
    Combinator {
        kind: "transmission",
        rust: "TransmissionParams::build",
        law: "the paper's model: mms in a gap, in series with bouc_wen",
        fields: "backlash, slider0, friction, spring",
        implicit: true,
        field_docs: &[("backlash", "the gap `b ≥ 0` the slider moves in"), ("slider0", "optional, default 0: the slider's initial position, `|slider0| ≤ b/2`"), ("friction", "the slider's MMS friction: `f_c`, `k`, `y0` as the `mms` leaf"), ("spring", "the spring: the fields of the `bouc_wen` leaf")],
        example: r#"{"type": "transmission", "backlash": 0.3, "friction": {"f_c": 1.5, "k": 30.0, "y0": 0.0}, "spring": {"w": 0.6, "alpha": 1.0, "beta": 2.5, "gamma": 1.5, "n": 1.0, "h0": 0.0, "z0": 0.0, "stiffness": {"z": [0.0, 0.6], "s": [10.0, 14.0]}}}"#,
    },
];

/// One of [`COMBINATOR_LAWS`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Combinator {
    /// The spec `type`.
    pub kind: &'static str,
    /// How Rust code builds it.
    pub rust: &'static str,
    /// The law it implements.
    pub law: &'static str,
    /// Its spec fields.
    pub fields: &'static str,
    /// Whether it solves an equation every sample.
    pub implicit: bool,
    /// Each spec field and what it holds, in the order of `fields`.
    pub field_docs: &'static [(&'static str, &'static str)],
    /// A small spec of this combinator, as JSON (it builds and runs:
    /// tested).
    pub example: &'static str,
}

/// The most nodes a spec may have on one path from its root to a leaf.
///
/// Parsing, building, running and serializing a spec recurse once per
/// level, so a bound keeps every one of them far from the stack's end (a
/// 2 MiB thread stack holds a path of this length with a wide margin). JSON
/// text nested deeper than `MAX_DEPTH + 4` levels (a leaf's own objects and
/// arrays add at most 4) is refused before it is parsed; a spec built in
/// code is measured without recursion by [`Spec::build`]. Longer chains
/// fit in one node: a [`pi_bank`](registry) sums any number of plays.
/// (Dropping a spec built deeper in code recurses once per level.)
pub const MAX_DEPTH: usize = 120;

/// A data description of a model: a registered leaf operator or a
/// combinator of specs. Serialized with an internal `type` tag (see the
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
#[derive(Debug, Clone, PartialEq)]
pub enum Spec {
    /// A leaf operator of the [`registry`], [`LeafSpec`].
    Leaf(LeafSpec),
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
        limits: TravelLimits<f64>,
        /// Solver tolerances (default [`SolverOptions::default`]).
        solver: Option<SolverOptions<f64>>,
    },
    /// Numerical inverse of a non-decreasing operator.
    Inverse {
        /// The operator inverted.
        inner: Box<Spec>,
        /// Solver tolerances (default [`SolverOptions::default`]).
        solver: Option<SolverOptions<f64>>,
    },
    /// `inner` run at `q` sub-steps per data sample,
    /// [`Oversample`](hysteron_composition::Oversample); a
    /// sample period set from above reaches `inner` as `dt / q`.
    Oversample {
        /// The oversampled operator.
        inner: Box<Spec>,
        /// Sub-steps per data sample (`≥ 1`), not a parameter.
        q: usize,
    },
}

/// A leaf of a spec: a registered operator's `type` and its parameters in
/// canonical JSON form (the declared struct's serde form, with optional
/// vectors written out in full).
#[derive(Debug, Clone, PartialEq)]
pub struct LeafSpec {
    kind: &'static str,
    params: Value,
}

impl LeafSpec {
    /// The operator's name (`"bouc_wen"`).
    pub fn kind(&self) -> &'static str {
        self.kind
    }

    /// The parameters as a JSON object.
    pub fn params(&self) -> &Value {
        &self.params
    }

    /// The declared parameters as their typed struct (`None` if `L` is not
    /// this leaf's operator).
    ///
    /// ```
    /// use hysteron_models::Spec;
    /// use hysteron_operators::{Play, PlayParams};
    /// let spec = Spec::leaf::<Play<f64>>(PlayParams { r: 0.5, y0: 0.0 });
    /// let Spec::Leaf(leaf) = &spec else { unreachable!() };
    /// assert_eq!(leaf.typed::<Play<f64>>(), Some(PlayParams { r: 0.5, y0: 0.0 }));
    /// ```
    pub fn typed<L: Leaf<f64>>(&self) -> Option<L::Params>
    where
        L::Params: serde::de::DeserializeOwned,
    {
        if L::KIND != self.kind {
            return None;
        }
        serde_json::from_value(self.params.clone()).ok()
    }

    /// The sample period `dt` the leaf gives (`None` for a rate-independent
    /// leaf, and for a rate-dependent one whose spec leaves it out).
    pub fn dt(&self) -> Option<f64> {
        self.params.get("dt").and_then(Value::as_f64)
    }

    /// Whether the leaf is rate-dependent and its spec leaves out `dt`
    /// (the period then comes from the data or the host).
    pub fn lacks_period(&self) -> bool {
        self.params.get("dt").is_none() && self.entry().is_ok_and(|e| e.is_rate_dependent())
    }

    /// The parameters with `dt` where the leaf [lacks a
    /// period](Self::lacks_period), as the declared struct needs them.
    fn params_or_dt(&self, dt: f64) -> Value {
        let mut params = self.params.clone();
        if self.lacks_period() {
            if let Value::Object(m) = &mut params {
                m.insert("dt".into(), Value::from(dt));
            }
        }
        params
    }

    fn entry(&self) -> Result<&'static dyn LeafKind, Error> {
        leaf_kind(self.kind).ok_or(Error::InvalidParameter {
            name: "type".into(),
            value: f64::NAN,
            reason: "is not a registered operator",
        })
    }
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
        /// Where in the document, as `field.field[index]`; the root is
        /// named by its `type` (`spec` where it has none).
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
    /// A rate-dependent leaf whose spec gives no sample period `dt`, built
    /// without one from the data or the host. Such a spec reads, writes and
    /// takes new parameters; it builds once [`with_dt`](Spec::with_dt) has
    /// given the period.
    #[error(
        "{path}: the sample period is not given: write `dt` in the spec, or take it from \
         the data (--dt SECONDS or --time-column NAME on the command line; dt= or time= in \
         Python) or from the host (hysteron_set_sample_period in C; the step size in FMI)"
    )]
    MissingPeriod {
        /// The path through the spec tree to the missing field, each node
        /// as `field.type`: `oversample.inner.lugre.dt`.
        path: String,
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
            | SpecError::MissingPeriod { path }
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
}

impl Spec {
    /// A leaf of operator `L` with parameters `p` (`L` must be in the
    /// [`registry`] for the spec to build).
    ///
    /// ```
    /// use hysteron_models::Spec;
    /// use hysteron_operators::{Mms, MmsParams};
    /// let spec = Spec::leaf::<Mms<f64>>(MmsParams { f_c: 1.5, k: 30.0, y0: 0.0 });
    /// assert_eq!(spec.to_json_pretty()?.replace([' ', '\n'], ""),
    ///            r#"{"type":"mms","f_c":1.5,"k":30.0,"y0":0.0}"#);
    /// # Ok::<(), hysteron_models::SpecError>(())
    /// ```
    pub fn leaf<L: Leaf<f64>>(p: L::Params) -> Spec
    where
        L::Params: Serialize,
    {
        // The canonical form: what the built operator reports (optional
        // vectors written out), or the set as given if it does not build.
        let p = match L::from_params(p.clone()) {
            Ok(op) => op.parameters().clone(),
            Err(_) => p,
        };
        Spec::Leaf(LeafSpec {
            kind: L::KIND,
            params: serde_json::to_value(&p).unwrap_or(Value::Null),
        })
    }

    /// The declared parameters of a leaf of operator `L` (`None` for any
    /// other node).
    ///
    /// ```
    /// use hysteron_models::Spec;
    /// use hysteron_operators::{Gain, GainParams, Play};
    /// let spec = Spec::from_json(r#"{"type": "gain", "k": 2}"#)?;
    /// assert_eq!(spec.leaf_params::<Gain<f64>>(), Some(GainParams { k: 2.0 }));
    /// assert_eq!(spec.leaf_params::<Play<f64>>(), None);
    /// # Ok::<(), hysteron_models::SpecError>(())
    /// ```
    pub fn leaf_params<L: Leaf<f64>>(&self) -> Option<L::Params>
    where
        L::Params: serde::de::DeserializeOwned,
    {
        match self {
            Spec::Leaf(leaf) => leaf.typed::<L>(),
            _ => None,
        }
    }

    /// The node's name as written in the `type` field (`"bouc_wen"`).
    pub fn kind(&self) -> &'static str {
        match self {
            Spec::Leaf(leaf) => leaf.kind,
            Spec::Transmission(_) => "transmission",
            Spec::Cascade { .. } => "cascade",
            Spec::Parallel { .. } => "parallel",
            Spec::Scaled { .. } => "scaled",
            Spec::Feedback { .. } => "feedback",
            Spec::Series { .. } => "series",
            Spec::Inverse { .. } => "inverse",
            Spec::Oversample { .. } => "oversample",
        }
    }

    /// The number of nodes on the longest path from this node to a leaf
    /// (1 for a leaf), counted with an explicit stack (no recursion), so
    /// that any depth is measured safely.
    pub fn depth(&self) -> usize {
        let mut deepest = 0;
        let mut stack = vec![(self, 1)];
        while let Some((spec, d)) = stack.pop() {
            deepest = deepest.max(d);
            stack.extend(spec.children().into_iter().map(|(_, c)| (c, d + 1)));
        }
        deepest
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
            Spec::Leaf(_) | Spec::Transmission(_) => Vec::new(),
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
            Spec::Leaf(leaf) => match leaf.dt() {
                Some(dt) => format!("[dt={dt}]"),
                None => String::new(),
            },
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

    /// The path of the first rate-dependent leaf whose spec leaves out its
    /// sample period `dt` (`oversample.inner.lugre`), or `None` if every
    /// one gives it. Such a spec builds only once the period is given
    /// ([`with_dt`](Spec::with_dt)); [`build`](Spec::build) names the
    /// same path in [`SpecError::MissingPeriod`].
    ///
    /// ```
    /// use hysteron_models::Spec;
    /// let spec = Spec::from_json(r#"{"type": "oversample", "q": 4,
    ///     "inner": {"type": "viscous_damper", "c": 2}}"#)?;
    /// assert_eq!(spec.missing_period().as_deref(), Some("oversample.inner.viscous_damper"));
    /// assert!(spec.build().is_err());
    /// assert_eq!(spec.with_dt(0.01).missing_period(), None);
    /// assert_eq!(spec.with_dt(0.01).stated_periods(), [0.01]);
    /// # Ok::<(), hysteron_models::SpecError>(())
    /// ```
    pub fn missing_period(&self) -> Option<String> {
        let mut stack = vec![(self, self.kind().to_string())];
        while let Some((spec, path)) = stack.pop() {
            if let Spec::Leaf(leaf) = spec {
                if leaf.lacks_period() {
                    return Some(path);
                }
            }
            // pushed in reverse, so that the first child is visited first
            for (field, child) in spec.children().into_iter().rev() {
                stack.push((child, format!("{path}.{field}.{}", child.kind())));
            }
        }
        None
    }

    /// The sample periods (s) the spec's rate-dependent leaves give, as
    /// periods of the data at the root: a leaf's `dt` times the `q` of
    /// every `oversample` above it. Distinct values in the order of the
    /// tree; empty for a rate-independent spec and for one that leaves
    /// every `dt` out. A spec made by [`with_dt`](Spec::with_dt) gives
    /// the one period it was given (to rounding).
    pub fn stated_periods(&self) -> Vec<f64> {
        let mut out: Vec<f64> = Vec::new();
        let mut stack = vec![(self, 1.0)];
        while let Some((spec, scale)) = stack.pop() {
            match spec {
                Spec::Leaf(leaf) => {
                    if let Some(dt) = leaf.dt() {
                        let root = dt * scale;
                        if !out.iter().any(|&p| (p - root).abs() <= 1e-12 * p.abs()) {
                            out.push(root);
                        }
                    }
                }
                Spec::Oversample { inner, q } => stack.push((inner, scale * *q as f64)),
                other => {
                    for (_, child) in other.children().into_iter().rev() {
                        stack.push((child, scale));
                    }
                }
            }
        }
        out
    }

    /// The period (s) given, only to build it, to a spec that leaves its
    /// period out: the model is then checked and its parameters listed,
    /// and it runs only once the real period replaces this one (every
    /// face refuses to run it before).
    pub const STAND_IN_DT: f64 = 1.0;

    /// The same spec with the sample period `dt` given to every
    /// rate-dependent leaf that [lacks one](LeafSpec::lacks_period) (as
    /// [`with_dt`](Spec::with_dt) gives it, `dt / q` inside an
    /// `oversample`); leaves that give their own keep it.
    pub fn or_dt(&self, dt: f64) -> Spec {
        let mut spec = self.clone();
        spec.set_dt(dt, true);
        spec
    }

    /// Whether any node of the tree is rate-dependent (a registered leaf
    /// that declares a sample period `dt`: `mass_spring_damper`,
    /// `viscous_damper`, `lugre`, `gms`).
    pub fn is_rate_dependent(&self) -> bool {
        let own = match self {
            Spec::Leaf(leaf) => leaf.entry().is_ok_and(|e| e.is_rate_dependent()),
            _ => false,
        };
        own || self
            .children()
            .into_iter()
            .any(|(_, c)| c.is_rate_dependent())
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
            left: Box::new(Spec::leaf::<Mms<f64>>(p.friction)),
            right: Box::new(Spec::leaf::<BoucWen<f64>>(spring)),
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
