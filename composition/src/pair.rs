//! Stepping and parameter plumbing shared by the combinators: those over
//! two children and those wrapping one `inner` child.

use hysteron_operators::{check, Domain, Float, Operator, Result};

/// A combinator's record of its pending trial: a `bool`, or an `Option` of
/// what it keeps of the trial; the default records none.
pub(crate) trait PendingTrial: Default {
    /// Whether a trial is pending.
    fn is_pending(&self) -> bool;
}

impl PendingTrial for bool {
    #[inline(always)]
    fn is_pending(&self) -> bool {
        *self
    }
}

impl<P> PendingTrial for Option<P> {
    #[inline(always)]
    fn is_pending(&self) -> bool {
        self.is_some()
    }
}

/// The `commit` and `reset` of a combinator whose state is its children's,
/// in the fields listed, with a field `pending` ([`PendingTrial`]) set
/// where its last trial was the children's and succeeded: `commit`
/// commits the children of a pending trial, `reset` forgets it and resets
/// them. Written inside the combinator's `impl Operator<T>` block:
/// `commit_reset_children!(left, right);`.
macro_rules! commit_reset_children {
    ($($child:ident),+) => {
        #[inline]
        fn commit(&mut self) {
            let pending = std::mem::take(&mut self.pending);
            if $crate::pair::PendingTrial::is_pending(&pending) {
                $(self.$child.commit();)+
            }
        }

        fn reset(&mut self) {
            self.pending = Default::default();
            $(self.$child.reset();)+
        }
    };
}
pub(crate) use commit_reset_children;

/// Sets `[params of a, params of b]` atomically: both children are
/// validated on copies before either is replaced. Errors name the child.
pub(crate) fn set_pair<T, A, B>(a: &mut A, b: &mut B, p: &[T], names: [&str; 2]) -> Result<()>
where
    T: Float,
    A: Operator<T> + Clone,
    B: Operator<T> + Clone,
{
    check::count(a.n_params() + b.n_params(), p)?;
    let (pa, pb) = p.split_at(a.n_params());
    let mut next_a = a.clone();
    next_a
        .set_params(pa)
        .map_err(|e| e.in_path(&format!("{}.{}", names[0], a.name())))?;
    let mut next_b = b.clone();
    next_b
        .set_params(pb)
        .map_err(|e| e.in_path(&format!("{}.{}", names[1], b.name())))?;
    *a = next_a;
    *b = next_b;
    Ok(())
}

/// Sets the parameters of a wrapped child atomically (validated on a copy
/// first); errors are named `inner.kind.…`.
pub(crate) fn set_inner<T: Float, O: Operator<T> + Clone>(inner: &mut O, p: &[T]) -> Result<()> {
    let mut next = inner.clone();
    next.set_params(p)
        .map_err(|e| e.in_path(&format!("inner.{}", inner.name())))?;
    *inner = next;
    Ok(())
}

/// Children's parameter domains, `a`'s then `b`'s.
pub(crate) fn pair_domains<T, A, B>(a: &A, b: &B) -> Vec<Domain>
where
    T: Float,
    A: Operator<T>,
    B: Operator<T>,
{
    let mut d = a.param_domains();
    d.extend(b.param_domains());
    d
}

/// Children's parameter names, prefixed with `names[i]` and their kind:
/// `first.play.r`.
pub(crate) fn pair_names<T, A, B>(a: &A, b: &B, names: [&str; 2]) -> Vec<String>
where
    T: Float,
    A: Operator<T>,
    B: Operator<T>,
{
    prefixed(names[0], a).chain(prefixed(names[1], b)).collect()
}

/// One child's parameter names prefixed with `label.kind.`.
pub(crate) fn prefixed<'a, T: Float, O: Operator<T>>(
    label: &'a str,
    op: &'a O,
) -> impl Iterator<Item = String> + 'a {
    let kind = op.name();
    op.param_names()
        .into_iter()
        .map(move |n| format!("{label}.{kind}.{n}"))
}

/// The [`Parameters`](hysteron_operators::Parameters) and
/// [`SamplePeriod`](hysteron_operators::SamplePeriod) of a combinator over
/// two children in fields `$a` and `$b` (named so in parameter paths:
/// `first.play.r`): the period reaches both, parameters are `$a`'s then
/// `$b`'s, set atomically, and `set_params` ends with `self.reset()`:
/// `pair_traits!(Cascade<T, A, B>, [T: Float, A: Child<T>, B: Child<T>], first, second);`.
macro_rules! pair_traits {
    ($ty:ty, [$($gen:tt)*], $a:ident, $b:ident) => {
        impl<$($gen)*> hysteron_operators::SamplePeriod<T> for $ty {
            fn set_sample_period(&mut self, dt: T) -> Result<()> {
                self.$a.set_sample_period(dt)?;
                self.$b.set_sample_period(dt)
            }
        }

        impl<$($gen)*> hysteron_operators::Parameters<T> for $ty {
            fn n_params(&self) -> usize {
                self.$a.n_params() + self.$b.n_params()
            }

            fn params_into(&self, out: &mut Vec<T>) {
                self.$a.params_into(out);
                self.$b.params_into(out);
            }

            fn param_domains(&self) -> Vec<hysteron_operators::Domain> {
                $crate::pair::pair_domains(&self.$a, &self.$b)
            }

            fn param_names(&self) -> Vec<String> {
                $crate::pair::pair_names(&self.$a, &self.$b, [stringify!($a), stringify!($b)])
            }

            fn set_params(&mut self, p: &[T]) -> Result<()> {
                $crate::pair::set_pair(
                    &mut self.$a,
                    &mut self.$b,
                    p,
                    [stringify!($a), stringify!($b)],
                )?;
                hysteron_operators::Operator::reset(self);
                Ok(())
            }
        }
    };
}
pub(crate) use pair_traits;

/// The [`Parameters`](hysteron_operators::Parameters) of a combinator that
/// wraps one child in the field `inner` and has no parameters of its own:
/// they are the child's, named `inner.kind.…`, set atomically, and
/// `set_params` ends with `self.reset()`:
/// `inner_parameters!(Inverse<T, A>, [T: Float, A: Child<T>]);`.
macro_rules! inner_parameters {
    ($ty:ty, [$($gen:tt)*]) => {
        impl<$($gen)*> hysteron_operators::Parameters<T> for $ty {
            fn n_params(&self) -> usize {
                self.inner.n_params()
            }

            fn params_into(&self, out: &mut Vec<T>) {
                self.inner.params_into(out);
            }

            fn param_domains(&self) -> Vec<hysteron_operators::Domain> {
                self.inner.param_domains()
            }

            fn param_names(&self) -> Vec<String> {
                $crate::pair::prefixed("inner", &self.inner).collect()
            }

            fn set_params(&mut self, p: &[T]) -> Result<()> {
                $crate::pair::set_inner(&mut self.inner, p)?;
                hysteron_operators::Operator::reset(self);
                Ok(())
            }
        }
    };
}
pub(crate) use inner_parameters;
