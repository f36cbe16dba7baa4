//! Scaling an operator's output by a weight.

use crate::pair::{prefixed, set_inner};
use crate::Child;
use hysteron_operators::{
    check, check_output, CastScalar, Dual, Error, Float, Operator, Result, Trial,
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

    fn to_dual(&self) -> Option<Box<dyn Operator<Dual>>> {
        let inner = self.inner.to_dual()?;
        Some(Box::new(Scaled::new(self.w.cast_scalar(), inner).ok()?))
    }

    #[inline]
    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        self.pending = false;
        let a = self.inner.trial(x)?;
        let t = check_output(
            "scaled",
            x,
            Trial {
                output: self.w * a.output,
                tangent: self.w * a.tangent,
            },
        )?;
        self.pending = true;
        Ok(t)
    }

    #[inline]
    fn commit(&mut self) {
        if std::mem::take(&mut self.pending) {
            self.inner.commit();
        }
    }

    fn reset(&mut self) {
        self.pending = false;
        self.inner.reset();
    }

    fn set_sample_period(&mut self, dt: T) -> Result<()> {
        self.inner.set_sample_period(dt)
    }

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
