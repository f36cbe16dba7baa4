//! A [`Spec`] with new parameter values or sample periods: the spec-level
//! counterparts of [`Parameters::set_params`] and
//! [`SamplePeriod::set_sample_period`].

use super::build::{spring_at_rest, transmission_names};
use super::{LeafSpec, Spec, SpecError};
use hysteron_composition::TravelLimits;
use hysteron_operators::Error;
#[cfg(doc)]
use hysteron_operators::{Parameters, SamplePeriod};
use serde_json::Value;

/// Why a spring's `z0` in a series with a gap cannot move on its own.
const TIED_Z0: &str = "must equal −r0 of the series' gap: the spring is at rest at the input the \
                       gap gives it at x = 0 (move r0 and z0 together)";

impl Spec {
    /// The parameters (named as [`Parameters::param_names`] of the built
    /// model names them) that are tied to another and so cannot be set, or
    /// fitted, on their own: in a series with a gap whose right element is
    /// a `bouc_wen` spring, and in a `transmission`, the gap's `r0` and the
    /// spring's `z0 = −r0`.
    ///
    /// ```
    /// use hysteron_models::{Spec, TransmissionParams};
    /// let spec = Spec::from(&TransmissionParams::default());
    /// assert_eq!(spec.tied_params(), ["limits.r0", "right.bouc_wen.z0"]);
    /// let nested = Spec::Scaled { w: 2.0, inner: Box::new(spec) };
    /// assert_eq!(
    ///     nested.tied_params(),
    ///     ["inner.series.limits.r0", "inner.series.right.bouc_wen.z0"]
    /// );
    /// ```
    pub fn tied_params(&self) -> Vec<String> {
        let mut out = Vec::new();
        self.ties_into("", &mut out);
        out
    }

    fn ties_into(&self, prefix: &str, out: &mut Vec<String>) {
        let tied = match self {
            Spec::Transmission(_) => true,
            Spec::Series { right, limits, .. } => spring_at_rest(right, limits).is_some(),
            _ => false,
        };
        if tied {
            out.push(format!("{prefix}limits.r0"));
            out.push(format!("{prefix}right.bouc_wen.z0"));
        }
        for (field, child) in self.children() {
            // prefixed as the built model names its children (a
            // `transmission` builds a `series`)
            let name = match child {
                Spec::Transmission(_) => "series",
                other => other.kind(),
            };
            child.ties_into(&format!("{prefix}{field}.{name}."), out);
        }
    }

    /// The same spec with the sample period of every rate-dependent node
    /// set to `dt`, as [`SamplePeriod::set_sample_period`] sets it on the built
    /// model: the nodes inside an `oversample` of `q` sub-steps get
    /// `dt / q`. The rest of the tree is kept; the value is checked by
    /// [`build`](Spec::build).
    ///
    /// ```
    /// use hysteron_models::Spec;
    /// let spec = Spec::from_json(r#"{"type": "oversample", "q": 4,
    ///     "inner": {"type": "viscous_damper", "c": 2, "dt": 0.1}}"#)?;
    /// assert_eq!(
    ///     spec.with_dt(0.01),
    ///     Spec::from_json(r#"{"type": "oversample", "q": 4,
    ///         "inner": {"type": "viscous_damper", "c": 2, "dt": 0.0025}}"#)?
    /// );
    /// # Ok::<(), hysteron_models::SpecError>(())
    /// ```
    pub fn with_dt(&self, dt: f64) -> Spec {
        let mut spec = self.clone();
        spec.set_dt(dt, false);
        spec
    }

    /// Gives every rate-dependent leaf the period `dt` (at this node), or
    /// only those that [lack one](LeafSpec::lacks_period).
    pub(super) fn set_dt(&mut self, dt: f64, only_missing: bool) {
        match self {
            Spec::Leaf(leaf) => {
                let wanted = if only_missing {
                    leaf.lacks_period()
                } else {
                    leaf.entry().is_ok_and(|e| e.is_rate_dependent())
                };
                if wanted {
                    if let Value::Object(m) = &mut leaf.params {
                        m.insert("dt".into(), Value::from(dt));
                    }
                }
            }
            Spec::Oversample { inner, q } => inner.set_dt(dt / *q as f64, only_missing),
            Spec::Cascade {
                first: a,
                second: b,
            }
            | Spec::Parallel { left: a, right: b }
            | Spec::Series {
                left: a, right: b, ..
            }
            | Spec::Feedback {
                forward: a,
                back: b,
                ..
            } => {
                a.set_dt(dt, only_missing);
                b.set_dt(dt, only_missing);
            }
            Spec::Scaled { inner, .. } | Spec::Inverse { inner, .. } => {
                inner.set_dt(dt, only_missing)
            }
            Spec::Transmission(_) => {}
        }
    }

    /// The same spec with the parameters `p`, given in the order of the
    /// built operator's [`params`](Parameters::params) (depth-first, as
    /// [`param_names`](Parameters::param_names) lists them): the inverse of
    /// `spec.build()?.params()`. Everything that is not a parameter (the
    /// tree, solver options, the kind of travel limits, the number of
    /// knots or plays, sample periods) is kept.
    ///
    /// * `spec.with_params(&spec.build()?.params())? == spec`;
    /// * `spec.with_params(&p)?.build()?.params() == p`.
    ///
    /// Tied parameters ([`tied_params`](Spec::tied_params)) must keep
    /// their tie: in a `transmission` spec the spring's entry must equal
    /// `−slider0` (otherwise an error naming `spring.z0`), in a series with
    /// a gap the spring's `z0` must equal `−r0` (an error naming the
    /// spring's `z0`). The spec keeps the `z0` it was written with.
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
        // The period is not a parameter: a spec that leaves it out is
        // counted and checked with a stand-in, and keeps leaving it out.
        let expected = self.or_dt(Spec::STAND_IN_DT).build()?.n_params();
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
        spec.or_dt(Spec::STAND_IN_DT).build()?;
        Ok(spec)
    }

    /// [`with_params`](Spec::with_params) of the node at `path`, taking its
    /// parameters from the front of `rest` (in the order of `params_into`
    /// of the operator it builds).
    fn fill(&self, path: &str, rest: &mut &[f64]) -> Result<Spec, SpecError> {
        let invalid = |e: Error| SpecError::invalid(path, e);
        // The next `N` values of `rest` (a count error if fewer).
        fn take<const N: usize>(path: &str, rest: &mut &[f64]) -> Result<[f64; N], SpecError> {
            let Some((head, tail)) = rest.split_first_chunk::<N>() else {
                return Err(SpecError::invalid(
                    path,
                    Error::ParamCount {
                        expected: N,
                        got: rest.len(),
                    },
                ));
            };
            *rest = tail;
            Ok(*head)
        }
        let child = |field: &str, spec: &Spec, rest: &mut &[f64]| -> Result<Box<Spec>, SpecError> {
            Ok(Box::new(
                spec.fill(&format!("{path}.{field}.{}", spec.kind()), rest)?,
            ))
        };
        Ok(match self {
            Spec::Leaf(leaf) => {
                let mut params = leaf
                    .entry()
                    .and_then(|e| e.with_values(&leaf.params_or_dt(Spec::STAND_IN_DT), rest))
                    .map_err(invalid)?;
                if leaf.lacks_period() {
                    if let Value::Object(m) = &mut params {
                        m.remove("dt");
                    }
                }
                Spec::Leaf(LeafSpec {
                    kind: leaf.kind,
                    params,
                })
            }
            Spec::Transmission(old) => Spec::Transmission(
                old.with_values(rest)
                    .map_err(|e| invalid(transmission_names(e)))?,
            ),
            Spec::Cascade { first, second } => Spec::Cascade {
                first: child("first", first, rest)?,
                second: child("second", second, rest)?,
            },
            Spec::Parallel { left, right } => Spec::Parallel {
                left: child("left", left, rest)?,
                right: child("right", right, rest)?,
            },
            Spec::Scaled { inner, .. } => Spec::Scaled {
                w: take::<1>(path, rest)?[0],
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
                        let [lo, hi] = take(path, rest)?;
                        TravelLimits::Range { lo, hi }
                    }
                    TravelLimits::Gap { .. } => {
                        let [b, r0] = take(path, rest)?;
                        TravelLimits::Gap { b, r0 }
                    }
                };
                let left = child("left", left, rest)?;
                let right = match spring_at_rest(right, &limits) {
                    // The spring's z0 is tied to the gap's r0: its entry
                    // must keep the tie; the spec keeps the z0 it had.
                    Some(_) => {
                        let at = format!("{path}.right.{}", right.kind());
                        let new = child("right", right, rest)?;
                        let (TravelLimits::Gap { r0, .. }, Spec::Leaf(leaf)) = (&limits, &*new)
                        else {
                            return Err(invalid(Error::ParamCount {
                                expected: 0,
                                got: rest.len(),
                            }));
                        };
                        let z0 = leaf.params.get("z0").and_then(Value::as_f64);
                        if z0 != Some(0.0 - r0) {
                            return Err(SpecError::invalid(
                                &at,
                                Error::InvalidParameter {
                                    name: "z0".into(),
                                    value: z0.unwrap_or(f64::NAN),
                                    reason: TIED_Z0,
                                },
                            ));
                        }
                        let mut leaf = leaf.clone();
                        if let (Value::Object(m), Spec::Leaf(old)) = (&mut leaf.params, &**right) {
                            m.insert(
                                "z0".into(),
                                old.params.get("z0").cloned().unwrap_or_default(),
                            );
                        }
                        Box::new(Spec::Leaf(leaf))
                    }
                    None => child("right", right, rest)?,
                };
                Spec::Series {
                    left,
                    right,
                    limits,
                    solver: *solver,
                }
            }
            Spec::Inverse { inner, solver } => Spec::Inverse {
                inner: child("inner", inner, rest)?,
                solver: *solver,
            },
            Spec::Oversample { inner, q } => Spec::Oversample {
                inner: child("inner", inner, rest)?,
                q: *q,
            },
        })
    }
}
