//! The open registry of leaf operators a spec can name.
//!
//! Every entry is a [`Leaf`] type behind [`Registered`]; its declared
//! parameters give the JSON form (serde), the build, the flat parameter
//! vector and the example the contract test runs. Adding a leaf operator
//! is its own file plus one line in the `leaves!` list of
//! `hysteron-operators` (see `CONTRIBUTING.md`).

use hysteron_composition::{PiBank, PiInverse};
use hysteron_operators::{Dual, Error, FieldInfo, FieldKind, Leaf, Operator, ParamSet};
use serde::{de::DeserializeOwned, Serialize};
use serde_json::Value;
use std::marker::PhantomData;
use std::sync::LazyLock;

/// Builds [`LEAVES`] from the leaves of `hysteron-operators` and those
/// of `hysteron-composition`.
macro_rules! registry {
    ($($leaf:ident),*) => {
        /// Every leaf operator a spec can name, by its `type`.
        pub static LEAVES: &[&dyn LeafKind] = &[
            $(&Registered::<hysteron_operators::$leaf<f64>>::NEW,)*
            &Registered::<PiBank<f64>>::NEW,
            &Registered::<PiInverse<f64>>::NEW,
        ];
    };
}

hysteron_operators::for_each_leaf!(registry);

/// The registered leaf named `kind`.
pub fn leaf_kind(kind: &str) -> Option<&'static dyn LeafKind> {
    LEAVES.iter().copied().find(|l| l.kind() == kind)
}

/// The names of every leaf and combinator, for "expected one of" messages.
pub(crate) fn all_kinds() -> &'static [&'static str] {
    static KINDS: LazyLock<Vec<&'static str>> = LazyLock::new(|| {
        LEAVES
            .iter()
            .map(|l| l.kind())
            .chain(super::COMBINATORS.iter().copied())
            .collect()
    });
    &KINDS
}

/// What a leaf's spec means when it leaves a field out.
#[derive(Debug, Clone, PartialEq)]
pub enum Omitted {
    /// It may not: the field is required.
    Required,
    /// The field takes this value (canonical JSON).
    Default(Value),
    /// The sample period `dt` of a rate-dependent leaf: it then comes from
    /// the data or the host ([`Spec::missing_period`](super::Spec::missing_period)).
    FromData,
}

/// A leaf operator as the spec layer sees it: parameters as canonical JSON
/// values (the declared struct's serde form), and everything else through
/// the operator's declaration.
pub trait LeafKind: Sync {
    /// The spec `type` (= [`Operator::name`]).
    fn kind(&self) -> &'static str;
    /// The Rust type's name, without its path and scalar (`"BoucWen"`).
    fn type_name(&self) -> &'static str;
    /// The crate that defines the Rust type (`"hysteron_operators"`).
    fn crate_name(&self) -> &'static str;
    /// The equation it implements ([`Leaf::EQUATION`]).
    fn equation(&self) -> &'static str;
    /// The declared fields.
    fn fields(&self) -> &'static [FieldInfo];
    /// Reads the parameter object (the node without `type`) into its
    /// canonical form; errors give serde's path inside the object.
    fn canonical(
        &self,
        params: Value,
    ) -> Result<Value, serde_path_to_error::Error<serde_json::Error>>;
    /// Builds the operator from canonical parameters.
    fn build(&self, params: &Value) -> Result<Box<dyn Operator<f64>>, Error>;
    /// Builds the operator from canonical parameters over the dual scalar
    /// [`Dual`] (values as given, derivatives 0: seed them with
    /// [`Parameters::set_params`](hysteron_operators::Parameters::set_params)).
    fn build_dual(&self, params: &Value) -> Result<Box<dyn Operator<Dual>>, Error>;
    /// The same parameters with the flat entries taken from the front of
    /// `p` (validated).
    fn with_values(&self, params: &Value, p: &mut &[f64]) -> Result<Value, Error>;
    /// The declaration's example, canonical.
    fn example(&self) -> Value;
    /// The declaration's example as a spec.
    fn example_spec(&self) -> super::Spec {
        super::Spec::Leaf(super::LeafSpec {
            kind: self.kind(),
            params: self.example(),
        })
    }
    /// The example built with `f32` as the scalar.
    fn example_f32(&self) -> Result<Box<dyn Operator<f32>>, Error>;
    /// Whether the operator is rate-dependent: it declares its default
    /// sample period as a fixed field `dt`.
    fn is_rate_dependent(&self) -> bool {
        self.fields()
            .iter()
            .any(|f| f.name == "dt" && f.kind == FieldKind::Fixed)
    }
    /// What the spec means when it leaves `field` out: read from the
    /// declaration's example without the field.
    fn omitted(&self, field: &str) -> Omitted {
        if field == "dt" && self.is_rate_dependent() {
            return Omitted::FromData;
        }
        let mut example = self.example();
        if let Some(m) = example.as_object_mut() {
            m.remove(field);
        }
        match self.canonical(example) {
            Ok(v) => v
                .get(field)
                .cloned()
                .map_or(Omitted::Required, Omitted::Default),
            Err(_) => Omitted::Required,
        }
    }
    /// Whether `field` may also be written as a bare number (a constant
    /// stiffness map), read from the declaration's example.
    fn takes_a_number(&self, field: &str) -> bool {
        let mut example = self.example();
        match example.as_object_mut() {
            Some(m) if m.contains_key(field) => {
                m.insert(field.into(), Value::from(1.0));
                self.canonical(example).is_ok()
            }
            _ => false,
        }
    }
}

/// The last segment of a Rust path, without generics:
/// `hysteron_operators::bouc_wen::BoucWen<f64>` → `BoucWen`. A leaf
/// written as a step law, `Stepped<PlayParams<f64>, f64>`, is named by its
/// alias, its parameters' name without `Params`: `Play`.
fn short_type_name(full: &'static str) -> &'static str {
    let last = |path: &'static str| path.rsplit("::").next().unwrap_or(path);
    let (outer, generics) = full.split_once('<').unwrap_or((full, ""));
    if last(outer) == "Stepped" {
        let params = generics.split([',', '<']).next().unwrap_or(generics);
        let name = last(params.trim());
        return name.strip_suffix("Params").unwrap_or(name);
    }
    last(outer)
}

/// A [`Leaf`] type in the registry.
pub struct Registered<L>(PhantomData<fn() -> L>);

impl<L> Registered<L> {
    /// The entry (a constant, for the static [`LEAVES`]).
    pub const NEW: Self = Registered(PhantomData);
}

/// The typed parameters of a canonical value (checked when it was read,
/// so this cannot fail; an error rather than a panic all the same).
fn typed<P: DeserializeOwned>(v: &Value) -> Result<P, Error> {
    P::deserialize(v).map_err(|_| Error::InvalidParameter {
        name: "parameters".into(),
        value: f64::NAN,
        reason: "do not match the operator's declaration",
    })
}

fn to_value<P: Serialize>(p: &P) -> Value {
    // Serializing a declared struct of numbers cannot fail; non-finite
    // numbers (which validation rejects) would become `null`.
    serde_json::to_value(p).unwrap_or(Value::Null)
}

impl<L> LeafKind for Registered<L>
where
    L: Leaf<f64> + 'static,
    L::Params: Serialize + DeserializeOwned,
    <L::With<Dual> as Leaf<Dual>>::Params: DeserializeOwned,
{
    fn kind(&self) -> &'static str {
        L::KIND
    }

    fn type_name(&self) -> &'static str {
        short_type_name(std::any::type_name::<L>())
    }

    fn crate_name(&self) -> &'static str {
        let full = std::any::type_name::<L>();
        full.split("::").next().unwrap_or(full)
    }

    fn equation(&self) -> &'static str {
        L::EQUATION
    }

    fn fields(&self) -> &'static [FieldInfo] {
        <L::Params as ParamSet<f64>>::FIELDS
    }

    fn canonical(
        &self,
        params: Value,
    ) -> Result<Value, serde_path_to_error::Error<serde_json::Error>> {
        let p: L::Params = serde_path_to_error::deserialize(params)?;
        // What the built operator reports (optional vectors written out),
        // or the set as given if it does not build (`build` says why).
        Ok(match L::from_params(p.clone()) {
            Ok(op) => to_value(op.parameters()),
            Err(_) => to_value(&p),
        })
    }

    fn build(&self, params: &Value) -> Result<Box<dyn Operator<f64>>, Error> {
        Ok(Box::new(L::from_params(typed(params)?)?))
    }

    fn build_dual(&self, params: &Value) -> Result<Box<dyn Operator<Dual>>, Error> {
        Ok(Box::new(<L::With<Dual> as Leaf<Dual>>::from_params(
            typed(params)?,
        )?))
    }

    fn with_values(&self, params: &Value, p: &mut &[f64]) -> Result<Value, Error> {
        let old = L::from_params(typed(params)?)?.parameters().clone();
        let new = old.read(p)?;
        new.validate()?;
        Ok(to_value(&new))
    }

    fn example(&self) -> Value {
        to_value(&L::example())
    }

    fn example_f32(&self) -> Result<Box<dyn Operator<f32>>, Error> {
        let p = <L::With<f32> as Leaf<f32>>::example();
        Ok(Box::new(<L::With<f32> as Leaf<f32>>::from_params(p)?))
    }
}
