//! Building a [`Spec`] into a boxed operator, with every limit a spec
//! must respect.

use super::registry::LeafKind;
use super::{Spec, SpecError, MAX_DEPTH};
use crate::TransmissionParams;
use hysteron_composition::{OperatorExt, Oversample, SolverOptions, TravelLimits};
use hysteron_operators::{
    check, BoucWen, BoucWenParams, Dual, Error, Float, Leaf, Mms, MmsParams, Operator,
};
use serde::{de::DeserializeOwned, Serialize};
use serde_json::Value;

/// Largest `max_iter` / `max_expansions` a spec's solver may ask for (a
/// bound on the work per solve).
const MAX_SOLVER_ITER: usize = 100_000;

/// Most implicit combinators nested on one path: each level solves its
/// equation by probing the level inside it, so the work per sample grows
/// geometrically with the depth (about 8× per level, measured with nested
/// inverses).
const MAX_IMPLICIT_DEPTH: usize = 4;

// The nesting error's text names the limit.
const _: () = assert!(MAX_DEPTH == 120);

/// Largest `q` of an `oversample` spec (a bound on the work per sample).
const MAX_OVERSAMPLE: usize = 100_000;

impl Spec {
    /// Builds the model, validating every parameter.
    ///
    /// Errors are [`SpecError::Invalid`], naming the path through the tree
    /// (`series.right.bouc_wen.stiffness.s[3]`). Besides what the operators
    /// check, a `solver` must have `rel_tol, abs_tol ∈ [0, 1e-3]` and
    /// `max_iter, max_expansions` in `[1, 100000]`, at most
    /// [`MAX_DEPTH`] nodes may lie on one path (measured
    /// first, without recursion), and at most 4 implicit combinators.
    ///
    /// ```
    /// use hysteron_models::Spec;
    /// use hysteron_operators::{Play, PlayParams};
    /// let spec = Spec::Scaled {
    ///     w: 2.0,
    ///     inner: Box::new(Spec::leaf::<Play<f64>>(PlayParams { r: -1.0, y0: 0.0 })),
    /// };
    /// let err = spec.build().unwrap_err();
    /// assert_eq!(err.to_string(), "scaled.inner.play.r: must be ≥ 0 (got -1)");
    /// ```
    pub fn build(&self) -> Result<Box<dyn Operator<f64>>, SpecError> {
        self.check_nesting()?;
        let op = self.build_at(self.kind())?;
        Ok(Box::new(super::model::SpecModel::new(op, self.clone())))
    }

    /// Builds the model over the dual scalar [`Dual`], for derivatives:
    /// the same operators with the same parameters and settings as
    /// [`build`](Self::build) gives (every derivative 0 until
    /// [`Parameters::set_params`](hysteron_operators::Parameters::set_params) seeds some), with the same errors.
    ///
    /// ```
    /// use hysteron_models::Spec;
    /// use hysteron_operators::{Dual, Operator};
    /// let spec: Spec = serde_json::from_str(r#"{"type": "gain", "k": 3.0}"#).unwrap();
    /// let mut m = spec.build_dual().unwrap();
    /// m.set_params(&[Dual::variable(3.0, 0)]).unwrap(); // seed ∂/∂k in slot 0
    /// let y = m.run(&[Dual::constant(2.0)]).unwrap();
    /// assert_eq!((y[0].re, y[0].eps[0]), (6.0, 2.0)); // y = k x, ∂y/∂k = x
    /// ```
    pub fn build_dual(&self) -> Result<Box<dyn Operator<Dual>>, SpecError> {
        self.check_nesting()?;
        self.build_at(self.kind())
    }

    /// The depth limits of [`build`](Self::build).
    fn check_nesting(&self) -> Result<(), SpecError> {
        let too_deep = |depth: usize, reason| {
            let nesting = Error::InvalidParameter {
                name: "nesting".into(),
                value: depth as f64,
                reason,
            };
            Err(SpecError::invalid(self.kind(), nesting))
        };
        let depth = self.depth();
        if depth > MAX_DEPTH {
            return too_deep(depth, "at most 120 operators may be nested on one path from the root (hysteron_models::spec::MAX_DEPTH)");
        }
        // only once the depth is bounded: `implicit_depth` recurses
        let depth = self.implicit_depth();
        if depth > MAX_IMPLICIT_DEPTH {
            return too_deep(depth, "at most 4 implicit combinators (feedback, series, inverse, transmission) may be nested on one path: each level multiplies the work per sample");
        }
        Ok(())
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

    fn build_at<T: SpecScalar>(&self, path: &str) -> Result<Box<dyn Operator<T>>, SpecError> {
        let invalid = |e: Error| SpecError::invalid(path, e);
        let child = |field: &str, spec: &Spec| {
            spec.build_at::<T>(&format!("{path}.{field}.{}", spec.kind()))
        };
        let solver = |opts: &Option<SolverOptions<f64>>| -> Result<SolverOptions<T>, SpecError> {
            let opts = opts.unwrap_or_default();
            check_solver(&opts).map_err(|e| invalid(e.in_path("solver")))?;
            Ok(SolverOptions {
                rel_tol: T::lit(opts.rel_tol),
                abs_tol: T::lit(opts.abs_tol),
                max_iter: opts.max_iter,
                max_expansions: opts.max_expansions,
            })
        };
        Ok(match self {
            Spec::Leaf(leaf) if leaf.lacks_period() => {
                return Err(SpecError::MissingPeriod {
                    path: format!("{path}.dt"),
                })
            }
            Spec::Leaf(leaf) => leaf
                .entry()
                .and_then(|e| T::leaf(e, &leaf.params))
                .map_err(invalid)?,
            Spec::Transmission(p) => {
                T::transmission(p).map_err(|e| invalid(transmission_names(e)))?
            }
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
                child("inner", inner)?
                    .scaled(T::lit(*w))
                    .map_err(invalid)?
                    .boxed()
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
                let b = match spring_at_rest(right, limits) {
                    Some(tied) => child("right", &tied)?,
                    None => child("right", right)?,
                };
                a.series(b)
                    .with_limits(cast_limits(limits))
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
}

/// A scalar a spec builds over: `f64` ([`Spec::build`]) and [`Dual`]
/// ([`Spec::build_dual`]).
pub(super) trait SpecScalar: Float + DeserializeOwned {
    /// The registered leaf `kind` with canonical `params`.
    fn leaf(kind: &dyn LeafKind, params: &Value) -> Result<Box<dyn Operator<Self>>, Error>;
    /// The paper's model.
    fn transmission(p: &TransmissionParams) -> Result<Box<dyn Operator<Self>>, Error>;
}

impl SpecScalar for f64 {
    fn leaf(kind: &dyn LeafKind, params: &Value) -> Result<Box<dyn Operator<f64>>, Error> {
        kind.build(params)
    }
    fn transmission(p: &TransmissionParams) -> Result<Box<dyn Operator<f64>>, Error> {
        Ok(p.build()?.boxed())
    }
}

impl SpecScalar for Dual {
    fn leaf(kind: &dyn LeafKind, params: &Value) -> Result<Box<dyn Operator<Dual>>, Error> {
        kind.build_dual(params)
    }
    fn transmission(p: &TransmissionParams) -> Result<Box<dyn Operator<Dual>>, Error> {
        let friction: MmsParams<Dual> = cast(&p.friction)?;
        let spring: BoucWenParams<Dual> = cast(&p.spring_params())?;
        let friction = Mms::from_params(friction).map_err(|e| e.in_path("friction"))?;
        let spring = BoucWen::from_params(spring).map_err(|e| e.in_path("spring"))?;
        let model = crate::transmission(
            friction,
            spring,
            Dual::constant(p.backlash),
            Dual::constant(p.slider0),
        )?;
        Ok(model.boxed())
    }
}

/// A parameter set of `f64` as the same set over another scalar (through
/// its serde form, which holds the values exactly).
fn cast<P: Serialize, Q: DeserializeOwned>(p: &P) -> Result<Q, Error> {
    serde_json::to_value(p)
        .and_then(serde_json::from_value)
        .map_err(|_| Error::InvalidParameter {
            name: "parameters".into(),
            value: f64::NAN,
            reason: "cannot be carried over to the dual scalar",
        })
}

/// The limits of a series over the scalar `T`.
fn cast_limits<T: Float>(l: &TravelLimits<f64>) -> TravelLimits<T> {
    match *l {
        TravelLimits::None => TravelLimits::None,
        TravelLimits::Range { lo, hi } => TravelLimits::Range {
            lo: T::lit(lo),
            hi: T::lit(hi),
        },
        TravelLimits::Gap { b, r0 } => TravelLimits::Gap {
            b: T::lit(b),
            r0: T::lit(r0),
        },
    }
}

/// The tie a series with a gap creates: its right element is driven by
/// `x − r`, which is `−r0` at `x = 0`, so a `bouc_wen` spring there starts
/// at rest at `z0 = −r0` (as the paper's model does, see
/// [`TransmissionParams::spring_params`](crate::TransmissionParams::spring_params)).
/// The spring with that `z0`, or `None` where there is no such tie.
pub(super) fn spring_at_rest(right: &Spec, limits: &TravelLimits<f64>) -> Option<Spec> {
    let (TravelLimits::Gap { r0, .. }, Spec::Leaf(leaf)) = (limits, right) else {
        return None;
    };
    if leaf.kind != <BoucWen<f64> as Leaf<f64>>::KIND {
        return None;
    }
    let mut leaf = leaf.clone();
    if let Value::Object(m) = &mut leaf.params {
        m.insert("z0".into(), Value::from(0.0 - r0));
    }
    Some(Spec::Leaf(leaf))
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
pub(super) fn transmission_names(e: Error) -> Error {
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
