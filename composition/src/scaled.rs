//! Scaling an operator's output by a weight.

use crate::pair::{prefixed, set_inner};
use crate::Child;
use hysteron_operators::{
    check, check_output, CastScalar, Derivatives, Dual, Error, Float, Hints, Operator, Parameters,
    Result, SamplePeriod, Trial,
};

/// Weighted operator `y = w · A[x]` (`a.scaled(w)`), `w` finite. Its
/// parameters are `[w, params of A]`.
///
/// ```
/// use hysteron_composition::OperatorExt;
/// use hysteron_operators::{Operator, Play};
/// let mut m = Play::new(0.0_f64).unwrap().scaled(3.0).unwrap();
/// assert_eq!(m.run(&[2.0]).unwrap(), vec![6.0]);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Scaled<T, A> {
    w: T,
    inner: A,
    pending: bool,
}

impl<T: Float, A> Scaled<T, A> {
    /// `y = w · inner[x]`.
    pub fn new(w: T, inner: A) -> Result<Self> {
        check::finite("w", w)?;
        Ok(Self {
            w,
            inner,
            pending: false,
        })
    }

    /// The weight.
    pub fn weight(&self) -> T {
        self.w
    }
}

impl<T: Float, A: Child<T>> Operator<T> for Scaled<T, A> {
    fn name(&self) -> &'static str {
        "scaled"
    }

    #[inline]
    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        self.pending = false;
        let a = self.inner.trial(x)?;
        let t = check_output("scaled", x, scale(self.w, a))?;
        self.pending = true;
        Ok(t)
    }

    crate::pair::commit_reset_children!(inner);
}

/// `y = w A`, `y' = w A'`.
#[inline(always)]
fn scale<T: Float>(w: T, a: Trial<T>) -> Trial<T> {
    Trial {
        output: w * a.output,
        tangent: w * a.tangent,
    }
}

/// Every hint of the inner operator, scaled.
impl<T: Float, A: Child<T>> Hints<T> for Scaled<T, A> {
    fn rests_when_held(&self) -> bool {
        self.inner.rests_when_held()
    }

    /// `y'' = w A''`.
    fn trial_curvature(&self) -> Option<T> {
        if !self.pending {
            return None;
        }
        Some(self.w * self.inner.trial_curvature()?)
    }

    fn trial_value(&mut self, x: f64) -> Option<Result<Trial<f64>>> {
        self.pending = false;
        let a = self.inner.trial_value(x)?;
        Some(a.and_then(|a| check_output("scaled", x, scale(self.w.as_f64(), a))))
    }

    /// The weight is a parameter: its probe slot is empty.
    fn fold_probe(&mut self, along: &T) -> bool {
        self.pending && self.inner.fold_probe(along)
    }
}

impl<T: Float, A: Child<T>> Derivatives<T> for Scaled<T, A> {
    fn to_dual(&self) -> Option<Box<dyn Operator<Dual>>> {
        let inner = self.inner.to_dual()?;
        Some(Box::new(Scaled::new(self.w.cast_scalar(), inner).ok()?))
    }
}

impl<T: Float, A: Child<T>> SamplePeriod<T> for Scaled<T, A> {
    fn set_sample_period(&mut self, dt: T) -> Result<()> {
        self.inner.set_sample_period(dt)
    }
}

impl<T: Float, A: Child<T>> Parameters<T> for Scaled<T, A> {
    fn n_params(&self) -> usize {
        1 + self.inner.n_params()
    }

    fn params_into(&self, out: &mut Vec<T>) {
        out.push(self.w);
        self.inner.params_into(out);
    }

    fn param_domains(&self) -> Vec<hysteron_operators::Domain> {
        let mut d = vec![hysteron_operators::Domain::Real];
        d.extend(self.inner.param_domains());
        d
    }

    fn param_names(&self) -> Vec<String> {
        std::iter::once("w".to_string())
            .chain(prefixed("inner", &self.inner))
            .collect()
    }

    fn set_params(&mut self, p: &[T]) -> Result<()> {
        check::count(self.n_params(), p)?;
        // (`n_params() ≥ 1`: `p` is not empty here)
        let (&w, rest) = p.split_first().ok_or(Error::ParamCount {
            expected: self.n_params(),
            got: 0,
        })?;
        check::finite("w", w)?;
        set_inner(&mut self.inner, rest)?;
        self.w = w;
        self.pending = false;
        Ok(())
    }
}
