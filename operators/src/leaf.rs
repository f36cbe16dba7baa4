//! Leaf operators: the [`Leaf`] trait that a registry of specs builds
//! from, and the generic driver [`Stepped`] that gives a leaf defined by a
//! pure step function ([`StepLaw`]) the whole [`Operator`] protocol.

use crate::{
    check_input, check_lengths, check_output, Beyond, Derivatives, Float, Hints, Keep, Operator,
    ParamSet, Parameters, Result, SamplePeriod, Trial,
};
use core::fmt::Debug;

/// An elementary operator built from one declared parameter set.
///
/// `KIND` is the operator's one name everywhere: the spec `type`,
/// [`Operator::name`], parameter paths and the CLI
/// (`bouc_wen`, `dead_zone`, …).
///
/// # Requirements
/// * `from_params(p)` validates `p` ([`ParamSet::validate`]) and builds
///   the operator in its initial state;
/// * `parameters()` returns the set it was built from, so that
///   `from_params(op.parameters().clone())` is the same operator;
/// * [`example`](Leaf::example) is a valid set (the contract test runs it);
/// * [`cast_leaf`](Leaf::cast_leaf) over `f64` gives the same values, to
///   rounding, as the operator (the contract test runs its dual twin).
pub trait Leaf<T: Float>: Operator<T> + Sized {
    /// The operator's name (snake case).
    const KIND: &'static str;
    /// The equation it implements, one line of plain text (for Python
    /// docstrings and listings; the type's rustdoc says more).
    const EQUATION: &'static str;
    /// Its declared parameters.
    type Params: ParamSet<T>;
    /// The same operator for another scalar type.
    type With<U: Float>: Leaf<U> + 'static;

    /// Builds the operator from validated parameters.
    fn from_params(p: Self::Params) -> Result<Self>;

    /// The parameters it was built from.
    fn parameters(&self) -> &Self::Params;

    /// A valid example parameter set (for docs and the contract test); the
    /// default is the values declared with the parameters.
    fn example() -> Self::Params {
        <Self::Params as ParamSet<T>>::example()
    }

    /// The operator with new parameters and this one's settings that are
    /// not parameters (a solver tolerance, say), in its initial state. The
    /// default is [`from_params`](Leaf::from_params).
    fn with_parameters(&self, p: Self::Params) -> Result<Self> {
        Self::from_params(p)
    }

    /// The same operator over the scalar `U`: its parameters carried over
    /// as constants of `U` ([`CastScalar`](crate::CastScalar)) and its
    /// settings that are not parameters (a solver and its tolerance), in
    /// its initial state. Errors where a setting has no counterpart over
    /// `U` (a tolerance below `U`'s resolution). Over [`Dual`](crate::Dual)
    /// it is the leaf's [`Derivatives::to_dual`].
    fn cast_leaf<U: Float>(&self) -> Result<Self::With<U>>;
}

/// Implements [`Leaf`] for an operator `Op<T>` that has an inherent
/// `Op::from_params(Params<T>) -> Result<Op<T>>` and keeps its parameters
/// in a field:
/// `impl_leaf!(Gms, GmsParams, "gms", p, equation: "F = …");`, and
/// optionally `, with_parameters: Op::method` (an inherent
/// `fn(&self, Params<T>) -> Result<Self>` keeping settings that are not
/// parameters) and `, cast_leaf: Op::method` (an inherent generic
/// `fn<U: Float>(&self) -> Result<Op<U>>` carrying them to another scalar;
/// the default builds from the cast parameters).
#[macro_export]
macro_rules! impl_leaf {
    ($op:ident, $params:ident, $kind:literal, $field:ident, equation: $equation:literal
        $(, with_parameters: $with:path)? $(, cast_leaf: $cast:path)? $(,)?) => {
        impl<T: $crate::Float> $crate::Leaf<T> for $op<T> {
            const KIND: &'static str = $kind;
            const EQUATION: &'static str = $equation;
            type Params = $params<T>;
            type With<U: $crate::Float> = $op<U>;

            fn from_params(p: $params<T>) -> $crate::Result<Self> {
                $op::from_params(p)
            }

            fn parameters(&self) -> &$params<T> {
                &self.$field
            }

            $(
                fn with_parameters(&self, p: $params<T>) -> $crate::Result<Self> {
                    $with(self, p)
                }
            )?

            $crate::impl_leaf!(@cast $op, $field $(, $cast)?);
        }
    };
    (@cast $op:ident, $field:ident) => {
        fn cast_leaf<U: $crate::Float>(&self) -> $crate::Result<$op<U>> {
            $op::from_params($crate::CastScalar::<U>::cast_scalar(&self.$field))
        }
    };
    (@cast $op:ident, $field:ident, $cast:path) => {
        fn cast_leaf<U: $crate::Float>(&self) -> $crate::Result<$op<U>> {
            $cast(self)
        }
    };
}

/// The traits of a [`Leaf`] `Op<T>` that follow from its declaration:
/// [`Parameters`](crate::Parameters) from its declared parameter set and
/// [`Derivatives`](crate::Derivatives) by [`Leaf::cast_leaf`]. Use beside
/// `impl Operator<T> for Op<T>`: `leaf_traits!(Op);`.
#[macro_export]
macro_rules! leaf_traits {
    ($op:ident) => {
        impl<T: $crate::Float> $crate::Parameters<T> for $op<T> {
            fn n_params(&self) -> usize {
                $crate::ParamSet::<T>::count($crate::Leaf::<T>::parameters(self))
            }
            fn params_into(&self, out: &mut Vec<T>) {
                $crate::ParamSet::<T>::write($crate::Leaf::<T>::parameters(self), out)
            }
            fn param_names(&self) -> Vec<String> {
                $crate::ParamSet::<T>::names($crate::Leaf::<T>::parameters(self))
            }
            fn param_domains(&self) -> Vec<$crate::Domain> {
                $crate::ParamSet::<T>::domains($crate::Leaf::<T>::parameters(self))
            }
            fn set_params(&mut self, p: &[T]) -> $crate::Result<()> {
                let next =
                    $crate::ParamSet::<T>::with_values($crate::Leaf::<T>::parameters(self), p)?;
                *self = $crate::Leaf::<T>::with_parameters(self, next)?;
                Ok(())
            }
        }

        impl<T: $crate::Float> $crate::Derivatives<T> for $op<T> {
            fn to_dual(&self) -> Option<Box<dyn $crate::Operator<$crate::Dual>>> {
                let dual = $crate::Leaf::<T>::cast_leaf::<$crate::Dual>(self).ok()?;
                Some(Box::new(dual))
            }
        }
    };
}

/// What a law's declaration says once (`law: "kind", "equation";` in
/// [`declare_params!`](crate::declare_params)): its kind, its equation,
/// and the same parameters over another scalar. Written by the macro, never
/// by hand.
pub trait Declared<T: Float>: ParamSet<T> {
    /// The operator's name (see [`Leaf::KIND`]).
    const KIND: &'static str;
    /// The equation (see [`Leaf::EQUATION`]).
    const EQUATION: &'static str;
    /// The same law for another scalar type.
    type With<U: Float>: StepLaw<U> + 'static;
    /// The same parameters over the scalar `U`, as constants
    /// ([`CastScalar`](crate::CastScalar)).
    fn cast_law<U: Float>(&self) -> Self::With<U>;
}

/// The law of a plain leaf: its declared parameter set (with its kind and
/// equation, [`Declared`]), a small state and a pure step
/// `(state, x) → (state', y, dy/dx)`. [`Stepped`] turns it into an
/// [`Operator`] (validating the parameters first).
///
/// # Requirements
/// * `step` depends only on the parameters, the state and `x` (finite: the driver
///   checks inputs, and checks that the output is finite and the tangent
///   not NaN);
/// * an override of [`run`](StepLaw::run) is bit for bit the loop of
///   `step` it replaces, and leaves `s` at the state after the last
///   successful sample.
pub trait StepLaw<T: Float>: Declared<T> {
    /// The state between samples.
    type State: Clone + Debug + PartialEq + Send + Sync + 'static;

    /// Whether a step at the state's own input keeps the state and gives
    /// the committed output again, bit for bit (after one step there):
    /// [`Hints::rests_when_held`]. `false` unless the law says so.
    const RESTS_WHEN_HELD: bool = false;

    /// The state before the first sample.
    fn initial(&self) -> Self::State;
    /// One sample from state `s` to the finite input `x`: the new state and
    /// the output with its tangent.
    fn step(&self, s: &Self::State, x: T) -> Result<(Self::State, Trial<T>)>;

    /// The output and tangent of [`step`](StepLaw::step) at an input of
    /// value `x`, on values alone ([`Hints::trial_value`]), or `None`
    /// (the default: the operator has no such path).
    fn step_value(&self, s: &Self::State, x: f64) -> Option<Result<Trial<f64>>> {
        let _ = (s, x);
        None
    }

    /// The second derivative of the output at the state `s` a step left
    /// ([`Hints::trial_curvature`]), or `None` (the default).
    fn curvature(&self, s: &Self::State) -> Option<T> {
        let _ = s;
        None
    }

    /// Folds the probe slot of every scalar of the state `s` a step left
    /// ([`Hints::fold_probe`]) and says so; `false` (the default): the
    /// law does not, and the caller steps again. A law must also answer
    /// `false` where a scalar of its own that is not a parameter (a sample
    /// period) carries anything in the probe slot.
    fn fold_probe(&self, s: &mut Self::State, along: &T) -> bool {
        let _ = (s, along);
        false
    }

    /// Runs `xs` from state `s`, writing `ys` (equal lengths, checked by the
    /// driver). The default steps sample by sample; an error at sample `i`
    /// leaves `s` after sample `i − 1` and is returned with
    /// [`Error::at_sample`](crate::Error::at_sample).
    fn run(&self, s: &mut Self::State, xs: &[T], ys: &mut [T]) -> Result<()> {
        for (i, (&x, y)) in xs.iter().zip(ys.iter_mut()).enumerate() {
            let (next, t) = checked_step(self, s, x).map_err(|e| e.at_sample(i))?;
            *s = next;
            *y = t.output;
        }
        Ok(())
    }

    /// Sets the sample period `dt > 0` for a rate-dependent law (the
    /// default, for a rate-independent one, only checks it).
    fn set_sample_period(&mut self, dt: T) -> Result<()> {
        crate::check::positive("dt", dt)
    }
}

/// `step` with the driver's checks: a finite input, a finite output and a
/// tangent that is not NaN.
#[inline(always)]
pub fn checked_step<T: Float, L: StepLaw<T>>(
    law: &L,
    s: &L::State,
    x: T,
) -> Result<(L::State, Trial<T>)> {
    let x = check_input(x)?;
    let (next, t) = law.step(s, x)?;
    Ok((next, check_output(L::KIND, x, t)?))
}

/// The driver of a [`StepLaw`]: the committed state, the pending trial,
/// and the whole [`Operator`] protocol.
#[derive(Debug, Clone, PartialEq)]
pub struct Stepped<L: StepLaw<T>, T: Float> {
    law: L,
    s: L::State,
    pending: Option<L::State>,
}

impl<T: Float, L: StepLaw<T>> Stepped<L, T> {
    /// The operator for parameters `p` (validated), in its initial state
    /// ([`Leaf::from_params`]).
    pub fn from_params(law: L) -> Result<Self> {
        law.validate()?;
        let s = law.initial();
        Ok(Self {
            law,
            s,
            pending: None,
        })
    }

    /// The parameters ([`Leaf::parameters`]).
    pub fn parameters(&self) -> &L {
        &self.law
    }

    /// The committed state.
    pub fn state(&self) -> &L::State {
        &self.s
    }

    /// [`process_while`](crate::process_while) with any condition `keep` (inlined into
    /// the loop where it is a closure).
    #[inline(always)]
    fn run_while(
        &mut self,
        xs: &[T],
        ys: &mut [T],
        mut keep: impl FnMut(usize, T) -> bool,
    ) -> usize {
        self.pending = None;
        for (i, (&x, y)) in xs.iter().zip(ys.iter_mut()).enumerate() {
            match checked_step(&self.law, &self.s, x) {
                Ok((next, t)) if keep(i, t.output) => {
                    self.s = next;
                    *y = t.output;
                }
                Ok((next, _)) => {
                    self.pending = Some(next);
                    return i;
                }
                Err(_) => return i,
            }
        }
        xs.len().min(ys.len())
    }
}

impl<T: Float, L: StepLaw<T>> Leaf<T> for Stepped<L, T> {
    const KIND: &'static str = L::KIND;
    const EQUATION: &'static str = L::EQUATION;
    type Params = L;
    type With<U: Float> = Stepped<L::With<U>, U>;

    fn from_params(p: L) -> Result<Self> {
        Stepped::from_params(p)
    }

    fn parameters(&self) -> &L {
        &self.law
    }

    fn example() -> L {
        L::example()
    }

    fn cast_leaf<U: Float>(&self) -> Result<Stepped<L::With<U>, U>> {
        Stepped::from_params(self.law.cast_law())
    }
}

impl<T: Float, L: StepLaw<T>> Operator<T> for Stepped<L, T> {
    // Always inlined, as `BoucWen::trial` is and for the same reason (its
    // comment: a `Trial` returned through memory stalls the caller).
    #[inline(always)]
    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        self.pending = None;
        let (next, t) = checked_step(&self.law, &self.s, x)?;
        self.pending = Some(next);
        Ok(t)
    }

    #[inline]
    fn commit(&mut self) {
        if let Some(s) = self.pending.take() {
            self.s = s;
        }
    }

    fn reset(&mut self) {
        self.s = self.law.initial();
        self.pending = None;
    }

    fn name(&self) -> &'static str {
        L::KIND
    }

    fn process(&mut self, xs: &[T], ys: &mut [T]) -> Result<()> {
        check_lengths(xs, ys)?;
        self.pending = None;
        self.law.run(&mut self.s, xs, ys)
    }
}

impl<T: Float, L: StepLaw<T>> Hints<T> for Stepped<L, T> {
    fn batch_while(&mut self, xs: &[T], ys: &mut [T], keep: &mut Keep<'_, T>) -> Option<usize> {
        Some(self.run_while(xs, ys, keep))
    }

    fn batch_while_beyond(&mut self, xs: &[T], ys: &mut [T], beyond: Beyond<T>) -> Option<usize> {
        Some(self.run_while(xs, ys, |_, y| beyond.admits(y)))
    }

    fn rests_when_held(&self) -> bool {
        L::RESTS_WHEN_HELD
    }

    fn trial_curvature(&self) -> Option<T> {
        self.pending.as_ref().and_then(|s| self.law.curvature(s))
    }

    #[inline]
    fn trial_value(&mut self, x: f64) -> Option<Result<Trial<f64>>> {
        self.pending = None;
        if !(crate::float::values_are_f64::<T>() && x.is_finite()) {
            return None;
        }
        let t = self.law.step_value(&self.s, x)?;
        Some(t.and_then(|t| check_output(L::KIND, x, t)))
    }

    #[inline]
    fn fold_probe(&mut self, along: &T) -> bool {
        self.pending
            .as_mut()
            .is_some_and(|s| self.law.fold_probe(s, along))
    }
}

impl<T: Float, L: StepLaw<T>> SamplePeriod<T> for Stepped<L, T> {
    fn set_sample_period(&mut self, dt: T) -> Result<()> {
        self.law.set_sample_period(dt)
    }
}

impl<T: Float, L: StepLaw<T>> Parameters<T> for Stepped<L, T> {
    fn n_params(&self) -> usize {
        self.law.count()
    }
    fn params_into(&self, out: &mut Vec<T>) {
        self.law.write(out)
    }
    fn param_names(&self) -> Vec<String> {
        self.law.names()
    }
    fn param_domains(&self) -> Vec<crate::Domain> {
        self.law.domains()
    }
    fn set_params(&mut self, p: &[T]) -> Result<()> {
        *self = Stepped::from_params(self.law.with_values(p)?)?;
        Ok(())
    }
}

impl<T: Float, L: StepLaw<T>> Derivatives<T> for Stepped<L, T> {
    fn to_dual(&self) -> Option<Box<dyn Operator<crate::Dual>>> {
        Some(Box::new(self.cast_leaf::<crate::Dual>().ok()?))
    }
}
