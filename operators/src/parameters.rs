//! The flat parameter vector of an operator: what fits, sensitivities and
//! hosts read and set.

use crate::{Domain, Dual, Float, Operator, Result};

/// An operator's parameters as one flat vector, depth-first through
/// combinators.
///
/// [`params`](Parameters::params) gives the vector that
/// [`set_params`](Parameters::set_params) accepts back. `set_params`
/// validates the whole vector first (on error nothing changes), then
/// replaces the parameters and resets the operator.
///
/// Every leaf derives it from its declared parameter set
/// ([`Leaf`](crate::Leaf)); a combinator lists its own parameters, then
/// its children's, named by a path (`first.play.r`).
///
/// ```
/// use hysteron_operators::{Parameters, Play};
/// let mut play = Play::new(0.5_f64).unwrap();
/// assert_eq!((play.params(), play.param_names()), (vec![0.5, 0.0], vec!["r".into(), "y0".into()]));
/// play.set_params(&[0.25, 0.0]).unwrap();
/// assert!(play.set_params(&[-1.0, 0.0]).is_err()); // r ≥ 0: unchanged
/// assert_eq!(play.params(), vec![0.25, 0.0]);
/// ```
pub trait Parameters<T: Float> {
    /// The number of parameters.
    fn n_params(&self) -> usize;

    /// Appends the parameters, depth-first, to `out`.
    fn params_into(&self, out: &mut Vec<T>);

    /// The parameters as a flat vector, depth-first through combinators.
    fn params(&self) -> Vec<T> {
        let mut v = Vec::with_capacity(self.n_params());
        self.params_into(&mut v);
        v
    }

    /// The parameter names, in the order of [`params`](Parameters::params);
    /// combinators prefix their children's names with a path.
    fn param_names(&self) -> Vec<String>;

    /// Validates and sets all parameters, then resets the operator.
    /// On error the operator is unchanged.
    fn set_params(&mut self, p: &[T]) -> Result<()>;

    /// The admissible range of each parameter, in the order of
    /// [`params`](Parameters::params) (for optimizers that must stay inside
    /// it). The default says every parameter is [`Domain::Real`].
    fn param_domains(&self) -> Vec<Domain> {
        vec![Domain::Real; self.n_params()]
    }
}

/// The sample period of the rate-dependent nodes of an operator.
///
/// ```
/// use hysteron_operators::{Operator, SamplePeriod, ViscousDamper};
/// let mut d = ViscousDamper::new(2.0_f64, 0.1).unwrap();
/// d.set_sample_period(0.5).unwrap();
/// assert_eq!(d.run(&[1.0]).unwrap(), vec![4.0]); // 2 · (1 − 0) / 0.5
/// assert!(d.set_sample_period(-1.0).is_err());
/// ```
pub trait SamplePeriod<T: Float> {
    /// Sets the sample period `dt > 0` (s) from the structure above: every
    /// rate-dependent node of the tree takes it as the time between the
    /// previous sample and the next; combinators forward it to their
    /// children, and an oversampling node forwards `dt / q`. It may change
    /// between samples (non-uniform records, a variable communication step
    /// in co-simulation). Rate-independent operators only check it (the
    /// default).
    fn set_sample_period(&mut self, dt: T) -> Result<()> {
        crate::check::positive("dt", dt)
    }
}

/// The same operator over dual numbers, for exact derivatives (`T` is the
/// operator's own scalar).
pub trait Derivatives<T: Float> {
    /// The same operator over the dual scalar [`Dual`], with the same
    /// parameters (as constants: seed them with
    /// [`set_params`](Parameters::set_params)) and settings, at its
    /// initial state; `None` where the operator cannot build one.
    ///
    /// Fits use it for exact Jacobians (forward-mode derivatives) and fall
    /// back to finite differences without it. Every leaf
    /// ([`Leaf::cast_leaf`](crate::Leaf::cast_leaf)) and combinator of the
    /// library has one, built from its children's, and so does a model
    /// built from a spec; the default, for an operator of your own, says
    /// `None`.
    fn to_dual(&self) -> Option<Box<dyn Operator<Dual>>> {
        None
    }
}

/// A boxed operator has its operator's parameters.
impl<T: Float> Parameters<T> for Box<dyn Operator<T>> {
    fn n_params(&self) -> usize {
        (**self).n_params()
    }
    fn params_into(&self, out: &mut Vec<T>) {
        (**self).params_into(out)
    }
    fn params(&self) -> Vec<T> {
        (**self).params()
    }
    fn param_names(&self) -> Vec<String> {
        (**self).param_names()
    }
    fn set_params(&mut self, p: &[T]) -> Result<()> {
        (**self).set_params(p)
    }
    fn param_domains(&self) -> Vec<Domain> {
        (**self).param_domains()
    }
}

impl<T: Float> SamplePeriod<T> for Box<dyn Operator<T>> {
    fn set_sample_period(&mut self, dt: T) -> Result<()> {
        (**self).set_sample_period(dt)
    }
}

impl<T: Float> Derivatives<T> for Box<dyn Operator<T>> {
    fn to_dual(&self) -> Option<Box<dyn Operator<Dual>>> {
        (**self).to_dual()
    }
}
