//! Oversampling: an operator run at an integer multiple of the data rate.

use crate::pair::inner_parameters;
use crate::Child;
use hysteron_operators::{
    check_input, Derivatives, Dual, Error, Float, Hints, Operator, Result, SamplePeriod, Trial,
};

/// Runs `inner` at `q` times the data rate (`Oversample::new(inner, q)`):
/// every data sample is `q` sub-steps of `inner`, the input interpolated
/// **linearly** between the previous data sample and the current one,
///
/// `x_i = x_prev + (x − x_prev) · i/q`, `i = 1 … q` (so `x_q = x`),
///
/// and the output is that of the last sub-step. This is what a
/// rate-dependent inner operator needs when its own sample period (for
/// example a [`MassSpringDamper`] with `dt = T/q`) is a
/// fraction of the data's: the inner operator then sees the data at its own
/// rate. `q = 1` is the inner operator itself, bit for bit.
///
/// * **Interpolation.** [`trial`](Operator::trial) sees only the current
///   sample, so the interpolation can only look back (to the committed
///   previous sample, `0` before the first, as for every operator): it is
///   linear, not band-limited. For band-limited periodic data, upsample the
///   record itself (`hysteron_models::signal::fft_upsample`) and run the
///   inner operator on it instead.
/// * **Trial/commit.** A trial runs its `q` sub-steps (each a trial +
///   commit of the inner operator) on a copy of the committed inner
///   operator; [`commit`](Operator::commit) makes that copy the committed
///   one. The committed state is never touched by a trial, so repeated,
///   discarded and failed trials leave no trace.
/// * **Tangent.** With `y = y_q` and `x_i` as above,
///   `dy/dx = Σ_i (∂y_q/∂x_i) · i/q`. The terms `i < q` act through the
///   inner state, which the trial interface does not expose, so the tangent
///   reported is the last term alone: the last sub-step's tangent
///   `∂y_q/∂x_q` with weight `q/q = 1` (not `1/q`: the last sub-step's
///   input is `x` itself). It is exact for `q = 1`, for memoryless inner
///   operators, and for rate-independent operators whose tangent is a
///   function of the end state along a monotone path (play, stop, the
///   Bouc-Wen spring with `n = 1`: `q` monotone sub-steps end where one step
///   does, with the same slope). For a dynamic inner operator it is only the
///   direct feed-through of the last sub-step (for a mass-spring-damper
///   whose oscillation period is long against the data period, of order
///   `1/q²` of the true value: `dt²/(4m)` against about `(q dt)²/(6m)`): a
///   usable hint for a safeguarded solver, not a derivative.
///
/// Parameters are those of `inner` (`q` is structural, not a parameter),
/// prefixed `inner.<kind>.`. A sample period set from above
/// ([`SamplePeriod::set_sample_period`]) reaches `inner` as `dt / q`.
///
/// [`MassSpringDamper`]: hysteron_operators::MassSpringDamper
///
/// ```
/// use hysteron_composition::Oversample;
/// use hysteron_operators::{Operator, Play};
/// // A play is rate-independent: oversampling a monotone step changes nothing.
/// let mut fine = Oversample::new(Play::new(0.5_f64).unwrap(), 10).unwrap();
/// let mut coarse = Play::new(0.5_f64).unwrap();
/// let xs = [1.0, 0.2, -1.0, 0.4];
/// let (a, b) = (fine.run(&xs).unwrap(), coarse.run(&xs).unwrap());
/// for (a, b) in a.iter().zip(&b) {
///     assert!((a - b).abs() < 1e-15);
/// }
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Oversample<T, A> {
    inner: A,
    q: usize,
    /// The committed previous data sample.
    x: T,
    /// The pending trial: its data sample and the inner operator advanced by
    /// `q − 1` committed sub-steps and a pending last one.
    pending: Option<(T, A)>,
}

impl<T: Float, A> Oversample<T, A> {
    /// Runs `inner` at `q ≥ 1` sub-steps per data sample.
    pub fn new(inner: A, q: usize) -> Result<Self> {
        if q == 0 {
            return Err(Error::InvalidParameter {
                name: "q".into(),
                value: 0.0,
                reason: "must be ≥ 1",
            });
        }
        Ok(Self {
            inner,
            q,
            x: T::zero(),
            pending: None,
        })
    }

    /// The oversampling factor `q`.
    pub fn factor(&self) -> usize {
        self.q
    }

    /// The committed inner operator.
    pub fn inner(&self) -> &A {
        &self.inner
    }
}
impl<T: Float, A: Child<T>> Operator<T> for Oversample<T, A> {
    fn name(&self) -> &'static str {
        "oversample"
    }

    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        self.pending = None;
        let x = check_input(x)?;
        let mut work = self.inner.clone();
        let (x0, dx) = (self.x, x - self.x);
        let q = T::lit(self.q as f64);
        let mut last = None;
        for i in 1..=self.q {
            let xi = if i == self.q {
                x
            } else {
                x0 + dx * (T::lit(i as f64) / q)
            };
            if i > 1 {
                work.commit();
            }
            last = Some(work.trial(xi)?);
        }
        // `q ≥ 1`, so the loop ran at least once.
        let t = last.ok_or(Error::NonFiniteOutput {
            operator: "oversample",
            input: x.as_f64(),
        })?;
        self.pending = Some((x, work));
        Ok(t)
    }

    fn commit(&mut self) {
        if let Some((x, mut work)) = self.pending.take() {
            work.commit();
            self.inner = work;
            self.x = x;
        }
    }

    fn reset(&mut self) {
        self.inner.reset();
        self.x = T::zero();
        self.pending = None;
    }
}

/// Holding the input holds every sub-step's input: it rests where the
/// inner operator does. The other hints are not taken through it: a trial
/// commits the inner operator between its sub-steps, which a value-only
/// trial, a curvature or a fold of one pending state cannot stand for.
impl<T: Float, A: Child<T>> Hints<T> for Oversample<T, A> {
    fn rests_when_held(&self) -> bool {
        self.inner.rests_when_held()
    }
}

impl<T: Float, A: Child<T>> Derivatives<T> for Oversample<T, A> {
    fn to_dual(&self) -> Option<Box<dyn Operator<Dual>>> {
        let inner = self.inner.to_dual()?;
        Some(Box::new(Oversample::new(inner, self.q).ok()?))
    }
}

impl<T: Float, A: Child<T>> SamplePeriod<T> for Oversample<T, A> {
    /// The inner operator runs `q` sub-steps per sample: its period is
    /// `dt / q`.
    fn set_sample_period(&mut self, dt: T) -> Result<()> {
        hysteron_operators::check::positive("dt", dt)?;
        self.inner.set_sample_period(dt / T::lit(self.q as f64))
    }
}

inner_parameters!(Oversample<T, A>, [T: Float, A: Child<T>]);

#[cfg(test)]
mod tests {
    use super::*;
    use hysteron_operators::{Gain, Play};

    #[test]
    fn q_zero_is_rejected() {
        assert!(Oversample::<f64, _>::new(Gain::new(1.0).unwrap(), 0).is_err());
    }

    #[test]
    fn q_one_is_the_inner_operator() {
        let xs: Vec<f64> = (0..50).map(|i| (0.3 * i as f64).sin()).collect();
        let mut a = Oversample::new(Play::new(0.2).unwrap(), 1).unwrap();
        let mut b = Play::new(0.2).unwrap();
        assert_eq!(a.run(&xs).unwrap(), b.run(&xs).unwrap());
    }

    /// A counter of committed sub-steps: the output is the number of
    /// committed steps plus one, so the sub-step count is visible.
    #[derive(Debug, Clone, PartialEq)]
    struct Steps {
        n: f64,
        pending: Option<f64>,
        inputs: Vec<f64>,
    }
    impl Operator<f64> for Steps {
        fn name(&self) -> &'static str {
            "steps"
        }
        fn trial(&mut self, x: f64) -> Result<Trial<f64>> {
            self.pending = Some(x);
            Ok(Trial {
                output: self.n + 1.0,
                tangent: 0.0,
            })
        }
        fn commit(&mut self) {
            if let Some(x) = self.pending.take() {
                self.n += 1.0;
                self.inputs.push(x);
            }
        }
        fn reset(&mut self) {
            self.n = 0.0;
            self.pending = None;
            self.inputs.clear();
        }
    }

    impl hysteron_operators::Hints<f64> for Steps {}

    impl hysteron_operators::SamplePeriod<f64> for Steps {}

    impl hysteron_operators::Parameters<f64> for Steps {
        fn n_params(&self) -> usize {
            0
        }
        fn params_into(&self, _: &mut Vec<f64>) {}
        fn param_names(&self) -> Vec<String> {
            Vec::new()
        }
        fn set_params(&mut self, _: &[f64]) -> Result<()> {
            Ok(())
        }
    }

    impl hysteron_operators::Derivatives<f64> for Steps {}

    #[test]
    fn sub_steps_interpolate_linearly_from_the_committed_sample() {
        let steps = Steps {
            n: 0.0,
            pending: None,
            inputs: Vec::new(),
        };
        let mut m = Oversample::new(steps, 4).unwrap();
        // discarded trials leave no trace
        assert_eq!(m.trial(9.0).unwrap().output, 4.0);
        assert_eq!(m.trial(1.0).unwrap().output, 4.0);
        m.commit();
        assert_eq!(m.inner().inputs, vec![0.25, 0.5, 0.75, 1.0]);
        assert_eq!(m.trial(3.0).unwrap().output, 8.0);
        m.commit();
        assert_eq!(m.inner().inputs[4..], [1.5, 2.0, 2.5, 3.0]);
    }
}
