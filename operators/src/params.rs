//! Declared parameter sets: each operator's parameters are written once,
//! in a [`declare_params!`](crate::declare_params) block, and everything
//! else (the flat vector of [`Parameters::params`](crate::Parameters::params),
//! names, domains, `set_params`, validation, the serde form of a spec)
//! derives from that declaration.
//!
//! A declared field is one of
//!
//! | kind | in the flat vector | example |
//! |---|---|---|
//! | a scalar `T` with a [`Domain`] | one entry, named by the field | `f_c` |
//! | a `Vec<T>` with a [`Domain`] for every element | one entry per element, `k[0]`, `k[1]`, … | Maxwell-slip `k` |
//! | a nested parameter set (`nested`) | the nested set's entries, prefixed `field.` | Bouc-Wen `stiffness.z[0]` |
//! | a fixed setting (`fixed`) | none: kept by `set_params` | a sample period `dt` |
//!
//! Parameters appear in the flat vector in declaration order.

use crate::{Domain, Error, Float, Result};
use core::fmt::Debug;

/// How a declared field takes part in the flat parameter vector.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FieldKind {
    /// A parameter (a scalar, or every element of a vector) in a domain.
    Param(Domain),
    /// A nested parameter set, whose own declaration gives the domains.
    Nested,
    /// A setting that is not a parameter (not in the flat vector, not
    /// fitted, kept by `set_params`).
    Fixed,
}

/// One declared field: its name, kind and one-line documentation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FieldInfo {
    /// The field name, as in the spec and in parameter paths.
    pub name: &'static str,
    /// How the field takes part in the flat vector.
    pub kind: FieldKind,
    /// The field's documentation, one entry per line of its doc comment.
    pub doc: &'static [&'static str],
}

impl FieldInfo {
    /// The first line of the field's documentation, trimmed.
    pub fn summary(&self) -> &'static str {
        self.doc.first().map_or("", |l| l.trim())
    }
}

/// A declared set of parameters (see the [module documentation](self)).
///
/// Implemented by [`declare_params!`](crate::declare_params); write it by
/// hand only for a set whose shape the macro cannot express (a Preisach
/// measure), keeping the same conventions.
pub trait ParamSet<T: Float>: Clone + Debug + PartialEq + Send + Sync + 'static {
    /// The declared fields, in declaration order.
    const FIELDS: &'static [FieldInfo];

    /// The number of entries in the flat vector.
    fn count(&self) -> usize;

    /// Appends the entry names, each prefixed by `prefix` (empty or ending
    /// in `.`), in flat order.
    fn names_into(&self, prefix: &str, out: &mut Vec<String>);

    /// Appends the entry domains in flat order.
    fn domains_into(&self, out: &mut Vec<Domain>);

    /// Appends the entry values in flat order.
    fn write(&self, out: &mut Vec<T>);

    /// The same set with its entries taken from the front of `p` (which is
    /// advanced past them); fixed settings and vector lengths are kept.
    /// Not validated. Errors if `p` is too short.
    fn read(&self, p: &mut &[T]) -> Result<Self>;

    /// Checks every entry against its domain (naming it, `k[3]`), then the
    /// constraints that tie entries together.
    fn validate(&self) -> Result<()>;

    /// A valid example set: the values declared with the fields (docs and
    /// the contract test run it).
    fn example() -> Self;

    /// The entry names in flat order.
    fn names(&self) -> Vec<String> {
        let mut v = Vec::with_capacity(self.count());
        self.names_into("", &mut v);
        v
    }

    /// The entry domains in flat order.
    fn domains(&self) -> Vec<Domain> {
        let mut v = Vec::with_capacity(self.count());
        self.domains_into(&mut v);
        v
    }

    /// The entry values in flat order.
    fn values(&self) -> Vec<T> {
        let mut v = Vec::with_capacity(self.count());
        self.write(&mut v);
        v
    }

    /// The same set with all entries replaced by `p` (exactly
    /// [`count`](ParamSet::count) values), validated.
    fn with_values(&self, p: &[T]) -> Result<Self> {
        crate::check::count(self.count(), p)?;
        let mut rest = p;
        let next = self.read(&mut rest)?;
        next.validate()?;
        Ok(next)
    }
}

/// A field type that a [`declare_params!`](crate::declare_params) block can
/// hold: `T`, `Vec<T>`, or a declared set (nested).
pub trait ParamField<T: Float>: Sized {
    /// Entries in the flat vector.
    fn count(&self, kind: FieldKind) -> usize;
    /// Appends the entry names (`name`, `name[i]`, or `name.inner`).
    fn names_into(&self, name: &str, kind: FieldKind, out: &mut Vec<String>);
    /// Appends the entry domains.
    fn domains_into(&self, kind: FieldKind, out: &mut Vec<Domain>);
    /// Appends the entry values.
    fn write(&self, kind: FieldKind, out: &mut Vec<T>);
    /// Takes the entries from the front of `p`.
    fn read(&self, kind: FieldKind, p: &mut &[T]) -> Result<Self>;
    /// Checks the entries against the domain, naming them.
    fn validate(&self, name: &str, kind: FieldKind) -> Result<()>;
    /// The example of a field declared without one: 0, empty, or a nested
    /// set's example.
    fn example_default() -> Self;
}

/// A field value from the example written in its declaration: a number for
/// `T`, a list of numbers for `Vec<T>`.
pub trait FromExample<T: Float, E> {
    /// The value.
    fn from_example(e: E) -> Self;
}

impl<T: Float> FromExample<T, f64> for T {
    fn from_example(e: f64) -> T {
        T::lit(e)
    }
}

impl<T: Float, const N: usize> FromExample<T, [f64; N]> for Vec<T> {
    fn from_example(e: [f64; N]) -> Vec<T> {
        e.iter().map(|&v| T::lit(v)).collect()
    }
}

/// Takes `n` values from the front of `p`.
fn take<'a, T>(p: &mut &'a [T], n: usize) -> Result<&'a [T]> {
    if p.len() < n {
        return Err(Error::ParamCount {
            expected: n,
            got: p.len(),
        });
    }
    let (head, tail) = p.split_at(n);
    *p = tail;
    Ok(head)
}

/// A parameter set, or a field of one, carried over to the scalar type
/// `U`: the same structure (vector lengths, fixed settings) with each value
/// `v` as the constant `U::lit(v.as_f64())` (a dual value's derivatives
/// are dropped). [`declare_params!`](crate::declare_params) implements it
/// for every declared set; [`Leaf::cast_leaf`](crate::Leaf::cast_leaf)
/// builds operators from it.
///
/// ```
/// use hysteron_operators::{CastScalar, Dual, MmsParams};
/// let p = MmsParams { f_c: 1.5, k: 30.0, y0: -0.4 };
/// let d: MmsParams<Dual> = p.cast_scalar();
/// assert_eq!((d.f_c.re, d.k.re, d.y0.re), (1.5, 30.0, -0.4));
/// assert_eq!(d.k.eps, [0.0; 8]);
/// ```
pub trait CastScalar<U: Float> {
    /// The same set or field over `U`.
    type Out;
    /// The values as constants of `U`.
    fn cast_scalar(&self) -> Self::Out;
}

impl<T: Float, U: Float> CastScalar<U> for T {
    type Out = U;
    #[inline]
    fn cast_scalar(&self) -> U {
        U::lit(self.as_f64())
    }
}

impl<T: Float, U: Float> CastScalar<U> for Vec<T> {
    type Out = Vec<U>;
    fn cast_scalar(&self) -> Vec<U> {
        self.iter().map(|v| U::lit(v.as_f64())).collect()
    }
}

impl<T: Float> ParamField<T> for T {
    fn count(&self, kind: FieldKind) -> usize {
        usize::from(matches!(kind, FieldKind::Param(_)))
    }
    fn names_into(&self, name: &str, kind: FieldKind, out: &mut Vec<String>) {
        if let FieldKind::Param(_) = kind {
            out.push(name.to_string());
        }
    }
    fn domains_into(&self, kind: FieldKind, out: &mut Vec<Domain>) {
        if let FieldKind::Param(d) = kind {
            out.push(d);
        }
    }
    fn write(&self, kind: FieldKind, out: &mut Vec<T>) {
        if let FieldKind::Param(_) = kind {
            out.push(*self);
        }
    }
    fn read(&self, kind: FieldKind, p: &mut &[T]) -> Result<Self> {
        Ok(match kind {
            FieldKind::Param(_) => {
                let (&v, tail) = p.split_first().ok_or(Error::ParamCount {
                    expected: 1,
                    got: 0,
                })?;
                *p = tail;
                v
            }
            _ => *self,
        })
    }
    fn validate(&self, name: &str, kind: FieldKind) -> Result<()> {
        match kind {
            FieldKind::Param(d) => d.check(name, *self),
            _ => Ok(()),
        }
    }
    fn example_default() -> Self {
        T::zero()
    }
}

impl<T: Float> ParamField<T> for Vec<T> {
    fn count(&self, kind: FieldKind) -> usize {
        match kind {
            FieldKind::Param(_) => self.len(),
            _ => 0,
        }
    }
    fn names_into(&self, name: &str, kind: FieldKind, out: &mut Vec<String>) {
        if let FieldKind::Param(_) = kind {
            out.extend((0..self.len()).map(|i| format!("{name}[{i}]")));
        }
    }
    fn domains_into(&self, kind: FieldKind, out: &mut Vec<Domain>) {
        if let FieldKind::Param(d) = kind {
            out.extend(std::iter::repeat_n(d, self.len()));
        }
    }
    fn write(&self, kind: FieldKind, out: &mut Vec<T>) {
        if let FieldKind::Param(_) = kind {
            out.extend_from_slice(self);
        }
    }
    fn read(&self, kind: FieldKind, p: &mut &[T]) -> Result<Self> {
        Ok(match kind {
            FieldKind::Param(_) => take(p, self.len())?.to_vec(),
            _ => self.clone(),
        })
    }
    fn validate(&self, name: &str, kind: FieldKind) -> Result<()> {
        if let FieldKind::Param(d) = kind {
            for (i, &v) in self.iter().enumerate() {
                d.check(&format!("{name}[{i}]"), v)?;
            }
        }
        Ok(())
    }
    fn example_default() -> Self {
        Vec::new()
    }
}

/// Declares a parameter set once: the struct (with its serde form), and
/// its [`ParamSet`] implementation, from one list of fields. A set of
/// scalars is `Copy` when its header says so: `struct NameParams<T>: Copy`.
///
/// Each field is written
/// `/// doc` … `name: Type => Kind = example,` (the example value
/// optional: a number, or `[numbers]` for a vector; 0, empty or the nested
/// set's example without it) where `Kind` is a [`Domain`] variant
/// (`Positive`, `AtLeast(1.0)`, …), `nested` or `fixed` (see the
/// [module documentation](crate::params)), optionally preceded by
/// `#[serde(...)]` attributes (after the doc comment), typically
/// `#[serde(default)]` for an optional field. Cross-field constraints go
/// in an optional `check` function after the fields, run after every
/// entry passed its domain.
///
/// ```
/// use hysteron_operators::{declare_params, ParamSet};
///
/// declare_params! {
///     /// Parameters of a two-sided friction level.
///     pub struct LevelsParams<T>: Copy {
///         /// Level in the positive direction, `> 0`.
///         up: T => Positive = 1.0,
///         /// Level in the negative direction, `> 0`.
///         down: T => Positive = 2.0,
///         /// Initial output (default 0).
///         #[serde(default)]
///         y0: T => Real,
///     }
///     check = |p: &LevelsParams<_>| hysteron_operators::check::finite("up", p.up / p.down);
/// }
///
/// let p = LevelsParams::<f64>::example();
/// assert_eq!(p, LevelsParams { up: 1.0, down: 2.0, y0: 0.0 });
/// assert_eq!(p.names(), ["up", "down", "y0"]);
/// assert_eq!(p.values(), [1.0, 2.0, 0.0]);
/// let err = p.with_values(&[1.0, -2.0, 0.0]).unwrap_err();
/// assert_eq!(err.to_string(), "invalid parameter `down` = -2: must be > 0");
/// ```
#[macro_export]
macro_rules! declare_params {
    (
        $(#[$sm:meta])*
        $vis:vis struct $name:ident<T> $(: $copy:ident)? {
            $(
                $(#[doc = $doc:literal])*
                $(#[serde($($serde:tt)*)])*
                $field:ident : $ty:ty => $kind:ident $(($arg:expr))? $(= $example:expr)?
            ),* $(,)?
        }
        $(check = $check:expr;)?
        $(law: $law_kind:literal, $law_equation:literal;)?
    ) => {
        $(#[$sm])*
        #[derive(Debug, Clone, $($copy,)? PartialEq, $crate::__serde::Serialize, $crate::__serde::Deserialize)]
        #[serde(crate = "hysteron_operators::__serde", deny_unknown_fields)]
        #[serde(bound(
            serialize = "T: hysteron_operators::__serde::Serialize",
            deserialize = "T: hysteron_operators::Float + hysteron_operators::__serde::Deserialize<'de>"
        ))]
        $vis struct $name<T> {
            $(
                $(#[doc = $doc])*
                $(#[serde($($serde)*)])*
                pub $field: $ty,
            )*
        }

        impl<T: $crate::Float> $crate::ParamSet<T> for $name<T> {
            const FIELDS: &'static [$crate::FieldInfo] = &[
                $($crate::FieldInfo {
                    name: stringify!($field),
                    kind: $crate::declare_params!(@kind $kind $(($arg))?),
                    doc: &[$($doc),*],
                }),*
            ];

            fn count(&self) -> usize {
                0 $(+ $crate::ParamField::<T>::count(
                    &self.$field,
                    $crate::declare_params!(@kind $kind $(($arg))?),
                ))*
            }

            fn names_into(&self, prefix: &str, out: &mut Vec<String>) {
                $($crate::ParamField::<T>::names_into(
                    &self.$field,
                    &format!("{prefix}{}", stringify!($field)),
                    $crate::declare_params!(@kind $kind $(($arg))?),
                    out,
                );)*
            }

            fn domains_into(&self, out: &mut Vec<$crate::Domain>) {
                $($crate::ParamField::<T>::domains_into(
                    &self.$field,
                    $crate::declare_params!(@kind $kind $(($arg))?),
                    out,
                );)*
            }

            fn write(&self, out: &mut Vec<T>) {
                $($crate::ParamField::<T>::write(
                    &self.$field,
                    $crate::declare_params!(@kind $kind $(($arg))?),
                    out,
                );)*
            }

            fn read(&self, p: &mut &[T]) -> $crate::Result<Self> {
                Ok(Self {
                    $($field: $crate::ParamField::<T>::read(
                        &self.$field,
                        $crate::declare_params!(@kind $kind $(($arg))?),
                        p,
                    )?,)*
                })
            }

            fn example() -> Self {
                Self {
                    $($field: $crate::declare_params!(@example T, $ty $(, $example)?),)*
                }
            }

            fn validate(&self) -> $crate::Result<()> {
                $($crate::ParamField::<T>::validate(
                    &self.$field,
                    stringify!($field),
                    $crate::declare_params!(@kind $kind $(($arg))?),
                )?;)*
                $(
                    let check: fn(&Self) -> $crate::Result<()> = $check;
                    check(self)?;
                )?
                Ok(())
            }
        }

        impl<T: $crate::Float> $name<T> {
            /// Checks every parameter against its domain, then the
            /// constraints between them ([`ParamSet::validate`]($crate::ParamSet::validate)).
            pub fn validate(&self) -> $crate::Result<()> {
                $crate::ParamSet::<T>::validate(self)
            }
        }

        $crate::nested_param_field!($name);

        impl<T: $crate::Float, U: $crate::Float> $crate::CastScalar<U> for $name<T> {
            type Out = $name<U>;
            fn cast_scalar(&self) -> $name<U> {
                $name {
                    $($field: $crate::CastScalar::<U>::cast_scalar(&self.$field),)*
                }
            }
        }

        $(
            impl<T: $crate::Float> $crate::Declared<T> for $name<T> {
                const KIND: &'static str = $law_kind;
                const EQUATION: &'static str = $law_equation;
                type With<U: $crate::Float> = $name<U>;

                fn cast_law<U: $crate::Float>(&self) -> $name<U> {
                    $crate::CastScalar::<U>::cast_scalar(self)
                }
            }
        )?
    };
    (@example $t:ident, $ty:ty) => { <$ty as $crate::ParamField<$t>>::example_default() };
    (@example $t:ident, $ty:ty, $e:expr) => {
        <$ty as $crate::params::FromExample<$t, _>>::from_example($e)
    };
    (@kind nested) => { $crate::FieldKind::Nested };
    (@kind fixed) => { $crate::FieldKind::Fixed };
    (@kind $d:ident $(($arg:expr))?) => { $crate::FieldKind::Param($crate::Domain::$d $(($arg))?) };
}

/// Implements a declared set's [`ParamField`] for use as a `nested` field
/// when its [`ParamSet`] is written by hand.
#[macro_export]
macro_rules! nested_param_field {
    ($name:ident) => {
        impl<T: $crate::Float> $crate::ParamField<T> for $name<T> {
            fn count(&self, _: $crate::FieldKind) -> usize {
                $crate::ParamSet::<T>::count(self)
            }
            fn names_into(&self, name: &str, _: $crate::FieldKind, out: &mut Vec<String>) {
                $crate::ParamSet::<T>::names_into(self, &format!("{name}."), out)
            }
            fn domains_into(&self, _: $crate::FieldKind, out: &mut Vec<$crate::Domain>) {
                $crate::ParamSet::<T>::domains_into(self, out)
            }
            fn write(&self, _: $crate::FieldKind, out: &mut Vec<T>) {
                $crate::ParamSet::<T>::write(self, out)
            }
            fn read(&self, _: $crate::FieldKind, p: &mut &[T]) -> $crate::Result<Self> {
                $crate::ParamSet::<T>::read(self, p)
            }
            fn validate(&self, name: &str, _: $crate::FieldKind) -> $crate::Result<()> {
                $crate::ParamSet::<T>::validate(self).map_err(|e| e.in_path(name))
            }
            fn example_default() -> Self {
                <Self as $crate::ParamSet<T>>::example()
            }
        }
    };
}
