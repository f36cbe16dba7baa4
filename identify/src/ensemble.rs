//! Many instances of one model structure, each with its own parameter
//! vector, run over one input: the leaves with a lane kernel
//! ([`hysteron_operators::lanes`]: play, the PI bank of fewer than 64
//! plays not a multiple of eight ([`PiLanes`](hysteron_composition::PiLanes)),
//! MMS, the Bouc-Wen spring with `n = 1`, and the mass-spring-damper
//! feedback of the Bouc-Wen benchmark system, [`MsdFeedback`]) eight
//! instances per vector instruction, every other model one instance at a
//! time; in parallel (rayon) over blocks of instances either way.
//!
//! Every instance's outputs are the bits it gives alone (`set_params` and
//! `run` on the model from its initial state). An instance whose
//! parameters are out of their domain, or whose run fails, reports its own
//! typed error with its index; the others finish.

use hysteron_composition::{MsdFeedback, PiBank};
use hysteron_models::Spec;
use hysteron_operators::lanes::{run_lanes, LaneLaw, WIDTH};
use hysteron_operators::{BoucWen, Error, Leaf, MassSpringDamper, Mms, Operator, Play};
use nalgebra::DMatrix;
use rayon::prelude::*;
use std::fmt;

/// Why an ensemble could not be built or run at all (one instance's
/// failure is an [`InstanceFailure`] instead).
#[derive(Debug, thiserror::Error)]
pub enum EnsembleError {
    /// The spec does not build (with its own parameters).
    #[error("model: {0}")]
    Model(String),
    /// The parameter matrix has no rows.
    #[error("the parameter matrix has no rows: give one row per instance")]
    NoInstances,
    /// A row's length is not the model's parameter count.
    #[error(
        "the parameter matrix has {got} columns, but the model has {expected} parameters ({names})"
    )]
    Columns {
        /// The model's parameter count.
        expected: usize,
        /// The matrix's column count.
        got: usize,
        /// The model's parameter names, in column order.
        names: String,
    },
    /// The input has no samples.
    #[error("input: no samples")]
    EmptyInput,
    /// An input sample is not finite (every instance refuses it).
    #[error("input: {0}")]
    Input(Error),
    /// The output buffer's length is not instances × samples.
    #[error("the output buffer holds {got} values, but the ensemble writes {expected} (instances × samples)")]
    OutputLength {
        /// Instances × samples.
        expected: usize,
        /// The buffer's length.
        got: usize,
    },
}

/// One instance's failure: its index (the parameter matrix's row) and the
/// error it gives alone.
#[derive(Debug, Clone, PartialEq)]
pub struct InstanceFailure {
    /// The instance (row of the parameter matrix).
    pub instance: usize,
    /// What its parameters or its run gave.
    pub error: Error,
}

impl fmt::Display for InstanceFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "instance {}: {}", self.instance, self.error)
    }
}

/// How an ensemble steps its instances.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kernel {
    /// [`WIDTH`] instances per vector instruction: the lane kernel of the
    /// leaf named.
    Lanes(&'static str),
    /// One instance at a time (any model).
    Instances,
}

/// The outputs of an ensemble run: one row of `samples` values per
/// instance, rows one after the other (NaN in the row of a failed
/// instance).
#[derive(Debug, Clone, PartialEq)]
pub struct EnsembleRun {
    /// `instances × samples` outputs, row by row.
    pub outputs: Vec<f64>,
    /// Samples per row (the input's length).
    pub samples: usize,
    /// The instances that failed, by index.
    pub failures: Vec<InstanceFailure>,
}

impl EnsembleRun {
    /// Instance `i`'s outputs (NaN if it failed), `None` past the last.
    pub fn row(&self, i: usize) -> Option<&[f64]> {
        let start = i.checked_mul(self.samples)?;
        self.outputs.get(start..start.checked_add(self.samples)?)
    }
}

/// The lane kernels an ensemble can use, by leaf, with every instance's
/// law (an instance whose parameters are refused runs a stand-in law, see
/// [`lane_set`], and its row is then cleared).
#[derive(Debug, Clone)]
enum Lanes {
    Play(Vec<<Play<f64> as Leaf<f64>>::Params>),
    Pi(Vec<<PiBank<f64> as Leaf<f64>>::Params>),
    Mms(Vec<<Mms<f64> as Leaf<f64>>::Params>),
    /// Every instance with `n = 1` (closed form).
    BoucWen(Vec<<BoucWen<f64> as Leaf<f64>>::Params>),
    /// `oversample(q, feedback(mass_spring_damper, bouc_wen))` (or the
    /// feedback alone), every spring with `n = 1` and a constant stiffness.
    MsdFeedback(Vec<MsdFeedback>),
}

/// `N` instances of the model of one spec, instance `i` with the
/// parameters of row `i` of a matrix (columns in the order of the model's
/// [`param_names`](hysteron_operators::Parameters::param_names)).
///
/// ```
/// use hysteron_identify::ensemble::{Ensemble, Kernel};
/// use hysteron_models::Spec;
/// use nalgebra::DMatrix;
///
/// let spec = Spec::from_json(r#"{"type": "play", "r": 0.5}"#)?;
/// // columns r, y0: three thresholds, and one out of its domain
/// let params = DMatrix::from_row_slice(4, 2, &[0.1, 0.0, 0.5, 0.0, 1.0, 0.0, -1.0, 0.0]);
/// let ensemble = Ensemble::new(&spec, &params)?;
/// assert_eq!(ensemble.kernel(), Kernel::Lanes("play"));
/// let run = ensemble.run(&[1.0, 2.0, 0.0])?;
/// assert_eq!(run.row(1), Some(&[0.5, 1.5, 0.5][..]));
/// assert_eq!(run.failures[0].instance, 3);
/// assert!(run.failures[0].to_string().starts_with("instance 3: "));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct Ensemble {
    model: Box<dyn Operator<f64>>,
    /// Each instance's parameters, or why they are refused.
    sets: Vec<Result<Vec<f64>, Error>>,
    lanes: Option<Lanes>,
}

impl Ensemble {
    /// The ensemble of `spec` with one instance per row of `params`.
    ///
    /// # Errors
    /// [`EnsembleError::Model`] if the spec does not build,
    /// [`EnsembleError::NoInstances`] for a matrix without rows, and
    /// [`EnsembleError::Columns`] if its column count is not the model's
    /// parameter count. A row out of the parameters' domains is not an
    /// error here: that instance reports it when run.
    pub fn new(spec: &Spec, params: &DMatrix<f64>) -> Result<Ensemble, EnsembleError> {
        let model = spec
            .build()
            .map_err(|e| EnsembleError::Model(e.to_string()))?;
        let mut ensemble = Ensemble::of_model(model.as_ref(), params)?;
        ensemble.lanes = lanes_for(spec, &ensemble.sets);
        Ok(ensemble)
    }

    /// The ensemble of a built model (any [`Operator`], such as a fitted
    /// model or one of the caller's own) with one instance per row of
    /// `params`, each started from the model's initial state. It steps
    /// one instance at a time ([`Kernel::Instances`]): the lane kernels
    /// are chosen from a spec ([`new`](Self::new)).
    ///
    /// # Errors
    /// As [`new`](Self::new), without [`EnsembleError::Model`].
    pub fn of_model(
        model: &(dyn Operator<f64> + 'static),
        params: &DMatrix<f64>,
    ) -> Result<Ensemble, EnsembleError> {
        let mut model: Box<dyn Operator<f64>> = dyn_clone::clone_box(model);
        model.reset();
        let names = model.param_names();
        if params.nrows() == 0 {
            return Err(EnsembleError::NoInstances);
        }
        if params.ncols() != names.len() {
            return Err(EnsembleError::Columns {
                expected: names.len(),
                got: params.ncols(),
                names: names.join(", "),
            });
        }
        let sets: Vec<Result<Vec<f64>, Error>> = (0..params.nrows())
            .into_par_iter()
            .map(|i| {
                let row: Vec<f64> = params.row(i).iter().copied().collect();
                dyn_clone::clone_box(&*model).set_params(&row).map(|()| row)
            })
            .collect();
        Ok(Ensemble {
            model,
            sets,
            lanes: None,
        })
    }

    /// The number of instances.
    pub fn len(&self) -> usize {
        self.sets.len()
    }

    /// Whether there are no instances (never, once built).
    pub fn is_empty(&self) -> bool {
        self.sets.is_empty()
    }

    /// The model's parameter names: the columns of the parameter matrix.
    pub fn param_names(&self) -> Vec<String> {
        self.model.param_names()
    }

    /// How the instances are stepped.
    pub fn kernel(&self) -> Kernel {
        match &self.lanes {
            Some(Lanes::Play(_)) => Kernel::Lanes("play"),
            Some(Lanes::Pi(_)) => Kernel::Lanes("pi_bank"),
            Some(Lanes::Mms(_)) => Kernel::Lanes("mms"),
            Some(Lanes::BoucWen(_)) => Kernel::Lanes("bouc_wen"),
            Some(Lanes::MsdFeedback(_)) => Kernel::Lanes("msd_feedback"),
            None => Kernel::Instances,
        }
    }

    /// Runs every instance from its initial state over `x`.
    ///
    /// # Errors
    /// As [`run_into`](Self::run_into).
    pub fn run(&self, x: &[f64]) -> Result<EnsembleRun, EnsembleError> {
        let mut outputs = vec![0.0; self.len() * x.len()];
        let failures = self.run_into(x, &mut outputs)?;
        Ok(EnsembleRun {
            outputs,
            samples: x.len(),
            failures,
        })
    }

    /// Runs every instance from its initial state over `x` into `out`, one
    /// row of `x.len()` values per instance (NaN in a failed instance's
    /// row); returns the failed instances, by index.
    ///
    /// # Errors
    /// [`EnsembleError::EmptyInput`] for an input without samples,
    /// [`EnsembleError::Input`] for one with a sample that is not finite
    /// (naming the sample), and [`EnsembleError::OutputLength`] if `out`
    /// does not hold `len() · x.len()` values.
    pub fn run_into(
        &self,
        x: &[f64],
        out: &mut [f64],
    ) -> Result<Vec<InstanceFailure>, EnsembleError> {
        if x.is_empty() {
            return Err(EnsembleError::EmptyInput);
        }
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            let value = x.get(i).copied().unwrap_or(f64::NAN);
            return Err(EnsembleError::Input(
                Error::NonFiniteInput { value }.at_sample(i),
            ));
        }
        let expected = self.len() * x.len();
        if out.len() != expected {
            return Err(EnsembleError::OutputLength {
                expected,
                got: out.len(),
            });
        }
        let mut failures = match &self.lanes {
            Some(Lanes::Play(laws)) => self.run_lanes(laws, x, out),
            Some(Lanes::Pi(laws)) => self.run_lanes(laws, x, out),
            Some(Lanes::Mms(laws)) => self.run_lanes(laws, x, out),
            Some(Lanes::BoucWen(laws)) => self.run_lanes(laws, x, out),
            Some(Lanes::MsdFeedback(laws)) => self.run_lanes(laws, x, out),
            None => self.run_instances(x, out),
        };
        failures.sort_by_key(|f| f.instance);
        Ok(failures)
    }

    /// Each instance alone into its row; the failures.
    fn run_instances(&self, x: &[f64], out: &mut [f64]) -> Vec<InstanceFailure> {
        out.par_chunks_mut(x.len())
            .zip(self.sets.par_iter())
            .enumerate()
            .filter_map(|(instance, (row, set))| {
                let run = set.clone().and_then(|p| {
                    let mut m = dyn_clone::clone_box(&*self.model);
                    m.set_params(&p).and_then(|()| m.process(x, row))
                });
                run.err().map(|error| {
                    row.fill(f64::NAN);
                    InstanceFailure { instance, error }
                })
            })
            .collect()
    }

    /// The lane kernel over `x` for every instance, each block of
    /// [`WIDTH`] into its rows; the failures: the refused parameter sets,
    /// and the lanes with an output that is not finite, with the error
    /// each gives alone.
    fn run_lanes<L: LaneLaw + Sync>(
        &self,
        laws: &[L],
        x: &[f64],
        out: &mut [f64],
    ) -> Vec<InstanceFailure> {
        let t = x.len();
        let flagged: Vec<usize> = out
            .par_chunks_mut(WIDTH * t)
            .zip(laws.par_chunks(WIDTH))
            .enumerate()
            .flat_map_iter(|(b, (rows, laws))| {
                // (the input was checked and the rows fit: no error)
                let lanes = run_lanes(laws, x, rows).unwrap_or_default();
                lanes.into_iter().map(move |j| b * WIDTH + j)
            })
            .collect();
        let refused = self
            .sets
            .iter()
            .enumerate()
            .filter(|(_, s)| s.is_err())
            .map(|(i, _)| i);
        let mut failed: Vec<usize> = refused.chain(flagged).collect();
        failed.sort_unstable();
        failed.dedup();
        let failures: Vec<InstanceFailure> = failed
            .into_par_iter()
            .map(|instance| InstanceFailure {
                instance,
                error: self.error_alone(instance, x),
            })
            .collect();
        for f in &failures {
            if let Some(row) = out.get_mut(f.instance * t..(f.instance + 1) * t) {
                row.fill(f64::NAN);
            }
        }
        failures
    }

    /// The error instance `i` gives alone over `x` (its refused parameters,
    /// or its run's).
    fn error_alone(&self, i: usize, x: &[f64]) -> Error {
        let run = match self.sets.get(i) {
            Some(Ok(p)) => {
                let mut m = dyn_clone::clone_box(&*self.model);
                m.set_params(p).and_then(|()| m.run(x))
            }
            Some(Err(e)) => Err(e.clone()),
            None => Err(Error::ParamCount {
                expected: self.len(),
                got: i,
            }),
        };
        // (a lane flagged by its kernel fails alone too: the kernel gives
        // the instance's bits)
        run.err().unwrap_or(Error::NonFiniteOutput {
            operator: "ensemble",
            input: f64::NAN,
        })
    }
}

/// The lane kernel for `spec` if it is a leaf or a structure that has
/// one, with the laws of the instances whose parameters are accepted.
fn lanes_for(spec: &Spec, sets: &[Result<Vec<f64>, Error>]) -> Option<Lanes> {
    match spec.kind() {
        "play" => lane_set(spec, sets, Spec::leaf_params::<Play<f64>>).map(Lanes::Play),
        "pi_bank" => lane_set(spec, sets, Spec::leaf_params::<PiBank<f64>>)
            // (a bank alone steps each whole group of eight plays eight per
            // instruction, and the rest one play at a time: the lanes gain
            // on the rest, 1.1-2.5x on AVX-512 from 2 to 43 plays, and
            // lose 2-9 % on whole groups alone and on 8 groups and more)
            .filter(|laws| {
                laws.iter()
                    .all(|p| !p.r.len().is_multiple_of(8) && p.r.len() < 64)
            })
            .map(Lanes::Pi),
        "mms" => lane_set(spec, sets, Spec::leaf_params::<Mms<f64>>).map(Lanes::Mms),
        "bouc_wen" => lane_set(spec, sets, Spec::leaf_params::<BoucWen<f64>>)
            // (springs with `n ≠ 1` step in lanes too, each on its table,
            // but were no faster than one at a time on the benchmark input:
            // each lane leaves its table piece at a third of its samples,
            // and a reversal's branch start is a Newton search per lane)
            .filter(|laws| laws.iter().all(|p| p.n == 1.0))
            .map(Lanes::BoucWen),
        "oversample" | "feedback" => lane_set(spec, sets, msd_feedback)
            .filter(|laws| {
                laws.iter()
                    .all(|l| l.back.n == 1.0 && l.back.stiffness.len() == 1)
            })
            .map(Lanes::MsdFeedback),
        _ => None,
    }
}

/// The loop of a mass-spring-damper and a Bouc-Wen spring that `spec`
/// is, `oversample(q, feedback(mass_spring_damper, bouc_wen))` or the
/// feedback alone (`q = 1`).
fn msd_feedback(spec: &Spec) -> Option<MsdFeedback> {
    let (inner, q) = match spec {
        Spec::Oversample { inner, q } => (&**inner, *q),
        other => (other, 1),
    };
    let Spec::Feedback {
        forward,
        back,
        solver,
    } = inner
    else {
        return None;
    };
    Some(MsdFeedback {
        forward: forward.leaf_params::<MassSpringDamper<f64>>()?,
        back: back.leaf_params::<BoucWen<f64>>()?,
        q,
        solver: solver.unwrap_or_default(),
    })
}

/// The law `law` gives for every instance of `spec`; where the instance's
/// parameters are refused, the first accepted instance's (or the spec's
/// own), so that its lane is like the others of its block.
fn lane_set<L: Clone>(
    spec: &Spec,
    sets: &[Result<Vec<f64>, Error>],
    law: impl Fn(&Spec) -> Option<L>,
) -> Option<Vec<L>> {
    let mut laws = Vec::with_capacity(sets.len());
    for p in sets {
        laws.push(match p {
            Ok(p) => Some(law(&spec.with_params(p).ok()?)?),
            Err(_) => None,
        });
    }
    let stand_in = match laws.iter().flatten().next() {
        Some(l) => l.clone(),
        None => law(spec)?,
    };
    Some(
        laws.into_iter()
            .map(|l| l.unwrap_or_else(|| stand_in.clone()))
            .collect(),
    )
}
