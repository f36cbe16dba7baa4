//! Numerical inverse of a monotone operator.

use crate::pair::inner_parameters;
use crate::solve::{solve, SolverOptions, Start};
use crate::Child;
use hysteron_operators::{
    check_input, CastScalar, Derivatives, Dual, Error, Float, Hints, Operator, Result,
    SamplePeriod, Trial,
};

/// Inverse `u = A⁻¹[x]` of a non-decreasing operator `A` (`a.inverse()`):
/// every sample solves `A[u] = x` for `u` from `A`'s committed state (its
/// memory follows the inverse's output `u`, as in a compensator cascaded
/// before the plant). `A ∘ A⁻¹` is then the identity to the solver
/// tolerance. A target outside `A`'s range (a saturation, a friction
/// plateau) is an [`Error::NoBracket`](hysteron_operators::Error::NoBracket).
/// Where `A` is flat the inverse is not unique; the solver returns one
/// point of the flat set.
///
/// Where `A` jumps over the target (a relay, the staircase of a discrete
/// Preisach grid) there is no solution either: the solver closes in on the
/// jump, and the inverse reports an [`Error::Jump`](hysteron_operators::Error::Jump)
/// instead of the input at the jump. The test: at the returned `u` the
/// residual `|A(u) − x|` exceeds what the local slope allows over the
/// solver tolerance `τ = abs_tol + rel_tol · max(|u|, scale)`
/// (`2 |A'(u)| τ + 8 ε (|x| + |A(u)|)`); then `A` is probed at `u ∓ 2τ` on
/// the far side of the sign change, and a change of `A` there larger than
/// `8 max|A'| τ + √ε (max|A| + max|A'| max(|u|, scale, reach))` is a jump,
/// `reach` the largest `|u|` committed since the last reset (an operator
/// with memory carries rounding of the size its terms reached).
///
/// Tangent: `1 / A'(u)` (`+∞` where `A` is flat).
///
/// ```
/// use hysteron_composition::OperatorExt;
/// use hysteron_operators::{Gain, Operator};
/// let mut inv = Gain::new(4.0_f64).unwrap().inverse();
/// assert!((inv.run(&[2.0]).unwrap()[0] - 0.5).abs() < 1e-15);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Inverse<T, A> {
    inner: A,
    opts: SolverOptions<T>,
    x: T,
    u: T,
    /// The largest `|u|` committed since the last reset: the size of the
    /// terms `A`'s memory may still hold (see `check_jump`).
    reach: T,
    /// The pending trial: its input, root and tangent.
    pending: Option<(T, T, T)>,
}

impl<T: Float, A> Inverse<T, A> {
    /// The inverse of `inner`.
    pub fn new(inner: A) -> Self {
        Self {
            inner,
            opts: SolverOptions::default(),
            x: T::zero(),
            u: T::zero(),
            reach: T::zero(),
            pending: None,
        }
    }

    /// Uses the given solver tolerances.
    pub fn with_solver(mut self, opts: SolverOptions<T>) -> Self {
        self.opts = opts;
        self
    }

    /// The operator being inverted.
    pub fn inner(&self) -> &A {
        &self.inner
    }
}

impl<T, A> Inverse<T, A>
where
    T: Float,
    A: Operator<T>,
{
    /// After a solve that ended at `u` with `A(u) = out`, `A'(u) = slope`:
    /// fails with [`Error::Jump`] if `A` jumps across `x` there (see the
    /// type's documentation), and leaves `A`'s pending trial at `u`.
    fn check_jump(&mut self, x: T, u: T, out: T, slope: T, scale: T) -> Result<()> {
        let r = out - x;
        let tau = self.opts.abs_tol + self.opts.rel_tol * u.abs().max(scale);
        let eps = T::epsilon();
        let two = T::lit(2.0);
        let small = two * slope.abs() * tau + T::lit(8.0) * eps * (x.abs() + out.abs());
        // `!(a <= b)` also probes when the bound is NaN.
        if r == T::zero() || r.abs() <= small {
            return Ok(());
        }
        let u2 = if r > T::zero() {
            u - two * tau
        } else {
            u + two * tau
        };
        let far = self.inner.trial(u2)?;
        let lip = slope.abs().max(far.tangent.abs());
        // Continuous operators may differ from monotone by their own
        // accuracy (rounding, an integrator's rtol) relative to the size of
        // their terms, which near an output of 0 is not |out| but about
        // slope · |u|, and for an operator with memory slope · the largest
        // |u| it was driven to (a Bouc-Wen state built up there and
        // returned to 0 keeps rounding of that size): all enter the noise
        // allowance.
        let reach = u.abs().max(scale).max(self.reach);
        let noise = out.abs().max(far.output.abs()) + lip * reach;
        let bound = T::lit(8.0) * lip * tau + eps.sqrt() * noise;
        let across = (far.output - x) * r < T::zero();
        if across && (far.output - out).abs() > bound {
            let (lo, hi) = if far.output < out {
                (far.output, out)
            } else {
                (out, far.output)
            };
            return Err(Error::Jump {
                solver: "inverse",
                at: u.as_f64(),
                below: lo.as_f64(),
                above: hi.as_f64(),
            });
        }
        // Leave the inner operator's pending trial at the root.
        self.inner.trial(u)?;
        Ok(())
    }
}

impl<T: Float, A: Child<T>> Operator<T> for Inverse<T, A> {
    fn name(&self) -> &'static str {
        "inverse"
    }

    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        self.pending = None;
        let x = check_input(x)?;
        let inner = &mut self.inner;
        let mut slope = T::zero();
        let mut out = T::zero();
        let residual = |u: T| -> Result<(T, T)> {
            let a = inner.trial(u)?;
            slope = a.tangent;
            out = a.output;
            Ok((a.output - x, a.tangent))
        };
        let start = Start::at_committed(self.u, self.x, x);
        let u = solve("inverse", residual, start, &self.opts)?.value();
        self.check_jump(x, u, out, slope, start.scale)?;
        let tangent = T::one() / slope;
        self.pending = Some((x, u, tangent));
        Ok(Trial { output: u, tangent })
    }

    fn commit(&mut self) {
        if let Some((x, u, _)) = self.pending.take() {
            self.inner.commit();
            self.x = x;
            self.u = u;
            self.reach = self.reach.max(u.abs());
        }
    }

    fn reset(&mut self) {
        self.inner.reset();
        self.x = T::zero();
        self.u = T::zero();
        self.reach = T::zero();
        self.pending = None;
    }
}

/// The curvature, from the inner operator's at the root. The root is found
/// to a tolerance, so a second search at a held input may move it within
/// that tolerance: the inverse does not claim to rest, and its value-only
/// trials and folds would be searches of their own (not taken).
impl<T: Float, A: Child<T>> Hints<T> for Inverse<T, A> {
    /// `u'' = −A''(u) · u'³`, `u' = 1/A'(u)` (the inner operator's pending
    /// trial is at the root).
    fn trial_curvature(&self) -> Option<T> {
        let (_, _, tangent) = self.pending?;
        let bend = self.inner.trial_curvature()?;
        Some(-bend * tangent * tangent * tangent)
    }
}

impl<T: Float, A: Child<T>> Derivatives<T> for Inverse<T, A> {
    fn to_dual(&self) -> Option<Box<dyn Operator<Dual>>> {
        let inner = self.inner.to_dual()?;
        Some(Box::new(
            Inverse::new(inner).with_solver(self.opts.cast_scalar()),
        ))
    }
}

impl<T: Float, A: Child<T>> SamplePeriod<T> for Inverse<T, A> {
    fn set_sample_period(&mut self, dt: T) -> Result<()> {
        self.inner.set_sample_period(dt)
    }
}

inner_parameters!(Inverse<T, A>, [T: Float, A: Child<T>]);
