//! The generic Duhem model `ẏ = f(x, y) ẋ⁺ − g(x, y) ẋ⁻` with functions of
//! the user's, integrated in the input's travel.

use crate::ode::dopri5;
use crate::{
    check, check_input, check_output, Derivatives, Domain, Float, Hints, Operator, Parameters,
    Result, SamplePeriod, Trial,
};
use core::fmt;

/// The local error held per sub-step, relative to the output's scale.
const RTOL: f64 = 1e-11;

/// The generic Duhem model (Duhem 1897; Macki, Nistri & Zecca 1993):
///
/// `ẏ = f(x, y) ẋ⁺ − g(x, y) ẋ⁻`,  i.e. `dy/dx = f(x, y)` while `x`
/// increases and `g(x, y)` while it decreases,
///
/// from `y = y0` at `x = 0`, with functions `f` and `g` of the user's. It
/// is rate-independent: the output depends on the path of `x`, not on
/// time. The Coleman-Hodgdon model is the instance
/// `f = α (F(x) − y) + G(x)`, `g = −α (F(x) − y) + G(x)`; with `F(x) = a x`
/// and `G = b` it is the [`Duhem`](crate::Duhem) leaf, solved there in
/// closed form and registered for specs. This type takes any `f` and `g`
/// (closures), so it lives in Rust only: a spec cannot carry a function.
///
/// **Integration.** Each sample integrates `(x, y)` over the input's
/// travel from the last sample by adaptive Dormand–Prince 5(4), each
/// sub-step's local error below `1e-11 · max(|y|, scale)` (`scale` given
/// at construction: the output's order of magnitude). Refining the
/// sampling changes the output by that tolerance only. The tangent is
/// `f` or `g` at the end of the step, in the direction travelled (`f` at a
/// standstill). A function value that is not finite is an error at its
/// sample.
///
/// ```
/// use hysteron_operators::{Duhem, DuhemFn, Operator};
/// // Coleman-Hodgdon with a linear anhysteretic curve: the `duhem` leaf
/// let (alpha, a, b) = (2.0_f64, 1.0, 0.2);
/// let f = move |x: f64, y: f64| alpha * (a * x - y) + b;
/// let g = move |x: f64, y: f64| -alpha * (a * x - y) + b;
/// let mut generic = DuhemFn::new(f, g, 0.0, 1.0).unwrap();
/// let x: Vec<f64> = (0..300).map(|i| 2.0 * (i as f64 * 0.05).sin()).collect();
/// let y = generic.run(&x).unwrap();
/// let closed = Duhem::new(alpha, a, b).unwrap().run(&x).unwrap();
/// assert!(y.iter().zip(&closed).all(|(p, q)| (p - q).abs() < 1e-9));
/// ```
///
/// Reference: J. W. Macki, P. Nistri and P. Zecca, "Mathematical models
/// for hysteresis", SIAM Review 35 (1993) 94–123.
#[derive(Clone)]
pub struct DuhemFn<T, F, G> {
    f: F,
    g: G,
    y0: T,
    scale: f64,
    /// The committed `(x, y)`.
    state: (T, T),
    /// The last trial's `(x, y)`.
    pending: Option<(T, T)>,
}

impl<T: Float, F, G> DuhemFn<T, F, G>
where
    F: Fn(T, T) -> T + Clone + Send + Sync + 'static,
    G: Fn(T, T) -> T + Clone + Send + Sync + 'static,
{
    /// The model `dy/dx = f(x, y)` increasing, `g(x, y)` decreasing, from
    /// `y0` at `x = 0`; `scale > 0` is the output's order of magnitude, for
    /// the error control.
    pub fn new(f: F, g: G, y0: T, scale: f64) -> Result<Self> {
        check::finite("y0", y0)?;
        check::positive("scale", scale)?;
        Ok(DuhemFn {
            f,
            g,
            y0,
            scale,
            state: (T::zero(), y0),
            pending: None,
        })
    }

    /// `dy/dx` at `(x, y)` travelling in direction `dir`.
    fn slope(&self, dir: T, x: T, y: T) -> T {
        if dir < T::zero() {
            (self.g)(x, y)
        } else {
            (self.f)(x, y)
        }
    }
}

impl<T: Float, F, G> fmt::Debug for DuhemFn<T, F, G> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("DuhemFn")
            .field("y0", &self.y0)
            .field("state", &self.state)
            .finish_non_exhaustive()
    }
}

impl<T: Float, F, G> Operator<T> for DuhemFn<T, F, G>
where
    F: Fn(T, T) -> T + Clone + Send + Sync + 'static,
    G: Fn(T, T) -> T + Clone + Send + Sync + 'static,
{
    fn name(&self) -> &'static str {
        "duhem_fn"
    }

    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        let x = check_input(x)?;
        let (x0, y0) = self.state;
        let travel = x - x0;
        let dir = if travel < T::zero() {
            -T::one()
        } else {
            T::one()
        };
        let y = if travel == T::zero() {
            y0
        } else {
            let scale = self.scale;
            let [_, y] = dopri5(
                |s: &[T; 2], _| [dir, dir * self.slope(dir, s[0], s[1])],
                (|_: &[T; 2]| true, |_: &[T; 2]| 1.0, 0.0),
                [x0, y0],
                travel.abs(),
                |s: &[T; 2]| [s[0].as_f64().abs().max(1.0), s[1].as_f64().abs().max(scale)],
                RTOL,
                "duhem_fn",
            )?;
            y
        };
        let trial = check_output(
            "duhem_fn",
            x,
            Trial {
                output: y,
                tangent: self.slope(dir, x, y),
            },
        )?;
        self.pending = Some((x, y));
        Ok(trial)
    }

    fn commit(&mut self) {
        if let Some(p) = self.pending.take() {
            self.state = p;
        }
    }

    fn reset(&mut self) {
        self.state = (T::zero(), self.y0);
        self.pending = None;
    }
}

/// No parameters: the functions are the model.
impl<T: Float, F, G> Parameters<T> for DuhemFn<T, F, G> {
    fn n_params(&self) -> usize {
        0
    }
    fn params_into(&self, _: &mut Vec<T>) {}
    fn param_names(&self) -> Vec<String> {
        Vec::new()
    }
    fn set_params(&mut self, p: &[T]) -> Result<()> {
        check::count(0, p)
    }
    fn param_domains(&self) -> Vec<Domain> {
        Vec::new()
    }
}

impl<T: Float, F, G> SamplePeriod<T> for DuhemFn<T, F, G> {}
impl<T: Float, F, G> Derivatives<T> for DuhemFn<T, F, G> {}
impl<T: Float, F, G> Hints<T> for DuhemFn<T, F, G> {}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::test_support::ramped_sine;
    use crate::{Duhem, Error};

    fn cycles() -> Vec<f64> {
        ramped_sine(600, 0.5, 2.0, 3.0)
    }

    /// With the semilinear Coleman-Hodgdon functions it is the closed-form
    /// `duhem` leaf; a standstill and a reset keep to it.
    #[test]
    fn coleman_hodgdon_is_the_duhem_leaf() {
        let (alpha, a, b, y0) = (2.0, 1.0, 0.2, 0.3);
        let f = move |x: f64, y: f64| alpha * (a * x - y) + b;
        let g = move |x: f64, y: f64| -alpha * (a * x - y) + b;
        let mut generic = DuhemFn::new(f, g, y0, 1.0).unwrap();
        let mut x = cycles();
        x[100] = x[99];
        let leaf = crate::DuhemParams { alpha, a, b, y0 };
        let want = Duhem::from_params(leaf).unwrap().run(&x).unwrap();
        for _ in 0..2 {
            let y = generic.run(&x).unwrap();
            for (i, (p, q)) in y.iter().zip(&want).enumerate() {
                assert!((p - q).abs() < 1e-10, "sample {i}: {p} vs {q}");
            }
            generic.reset();
        }
    }

    /// A nonlinear instance: `F(x) = tanh x`, `G = 0.2 / (1 + x²)`;
    /// refining the sampling 8× changes the output by the tolerance only.
    #[test]
    fn a_nonlinear_instance_is_rate_independent() {
        let f = |x: f64, y: f64| 1.5 * (x.tanh() - y) + 0.2 / (1.0 + x * x);
        let g = |x: f64, y: f64| -1.5 * (x.tanh() - y) + 0.2 / (1.0 + x * x);
        let coarse = cycles();
        let mut fine = vec![];
        let mut last = 0.0;
        for &v in &coarse {
            fine.extend((1..=8).map(|k| last + (v - last) * k as f64 / 8.0));
            last = v;
        }
        let y = DuhemFn::new(f, g, 0.0, 1.0).unwrap().run(&coarse).unwrap();
        let z = DuhemFn::new(f, g, 0.0, 1.0).unwrap().run(&fine).unwrap();
        for (i, p) in y.iter().enumerate() {
            let q = z[8 * i + 7];
            assert!((p - q).abs() < 1e-9, "sample {i}: {p} vs {q}");
        }
    }

    /// A function that leaves the finite numbers is an error at the sample;
    /// a bad `y0` or `scale` is refused.
    #[test]
    fn bad_functions_and_settings_are_typed_errors() {
        let f = |x: f64, _: f64| 1.0 / (x - 1.0);
        let mut op = DuhemFn::new(f, f, 0.0, 1.0).unwrap();
        assert!(op.run(&[0.5, 2.0]).is_err());
        assert!(matches!(
            DuhemFn::new(f, f, f64::NAN, 1.0),
            Err(Error::InvalidParameter { .. })
        ));
        assert!(matches!(
            DuhemFn::new(f, f, 0.0, 0.0),
            Err(Error::InvalidParameter { .. })
        ));
    }
}
