//! Helpers shared by the library's integration tests.
#![allow(dead_code, unused_macros)] // each test crate uses a subset

use hysteron::prelude::*;

/// The bit patterns of `v` (for bit-for-bit comparisons that show where
/// they differ).
pub fn bits<T: Float>(v: &[T]) -> Vec<u64> {
    v.iter().map(|y| y.as_f64().to_bits()).collect()
}

/// The reference loop every `process` must equal: `trial` then `commit`,
/// sample by sample.
pub fn trial_commit_loop<T: Float, O: Operator<T> + ?Sized>(op: &mut O, xs: &[T]) -> Vec<T> {
    xs.iter()
        .map(|&x| {
            let t = op.trial(x).expect("trial");
            op.commit();
            t.output
        })
        .collect()
}

/// The `trial`, `commit` and `reset` of an operator that wraps the operator
/// in its field `inner` and counts its trials in its `trials`
/// (`Arc<AtomicUsize>`): for a test's counting wrapper, in its
/// `impl Operator<T>` (`T` the sample type).
macro_rules! counted_trials {
    ($t:ty, $inner:ident) => {
        fn trial(&mut self, x: $t) -> hysteron::Result<hysteron::Trial<$t>> {
            self.trials
                .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            self.$inner.trial(x)
        }
        fn commit(&mut self) {
            self.$inner.commit()
        }
        fn reset(&mut self) {
            self.$inner.reset()
        }
    };
}
#[allow(unused_imports)] // each test crate uses a subset
pub(crate) use counted_trials;

/// The parameters of a wrapper, those of the operator in its field
/// `inner`: the body of its `impl Parameters<T>` (`T` the sample type).
macro_rules! parameters_of {
    ($t:ty, $inner:ident) => {
        fn n_params(&self) -> usize {
            self.$inner.n_params()
        }
        fn params_into(&self, out: &mut Vec<$t>) {
            self.$inner.params_into(out)
        }
        fn param_names(&self) -> Vec<String> {
            self.$inner.param_names()
        }
        fn set_params(&mut self, p: &[$t]) -> hysteron::Result<()> {
            self.$inner.set_params(p)
        }
    };
}
#[allow(unused_imports)] // each test crate uses a subset
pub(crate) use parameters_of;

/// The LuGre element of `examples/specs/lugre.json`, sampled at 100 Hz.
pub fn lugre_at_100_hz<T: Float>() -> hysteron::operators::LuGreParams<T> {
    hysteron::operators::LuGreParams {
        sigma0: T::lit(1e3),
        sigma1: T::lit(5.0),
        sigma2: T::lit(0.2),
        f_c: T::lit(1.0),
        f_s: T::lit(1.5),
        v_s: T::lit(0.5),
        delta: T::lit(2.0),
        z0: T::lit(0.0),
        dt: T::lit(0.01),
    }
}

/// LuGre parameters from the bristles `(sigma0, sigma1, sigma2)`, the
/// Stribeck curve `(f_c, f_s, v_s, delta)`, the start `z0` and the sample
/// period `dt` (as property strategies draw them).
pub fn lugre_of(
    (sigma0, sigma1, sigma2): (f64, f64, f64),
    (f_c, f_s, v_s, delta): (f64, f64, f64, f64),
    z0: f64,
    dt: f64,
) -> hysteron::operators::LuGreParams<f64> {
    hysteron::operators::LuGreParams {
        sigma0,
        sigma1,
        sigma2,
        f_c,
        f_s,
        v_s,
        delta,
        z0,
        dt,
    }
}

/// GMS parameters from the elements' `(k, alpha)`, the attraction rate and
/// Stribeck curve `(c, f_c, f_s, v_s)`, `(delta, sigma2, dt)` and the
/// start `f0` (as property strategies draw them).
pub fn gms_of(
    elements: &[(f64, f64)],
    (c, f_c, f_s, v_s): (f64, f64, f64, f64),
    (delta, sigma2, dt): (f64, f64, f64),
    f0: Vec<f64>,
) -> hysteron::operators::GmsParams<f64> {
    hysteron::operators::GmsParams {
        k: elements.iter().map(|e| e.0).collect(),
        alpha: elements.iter().map(|e| e.1).collect(),
        f0,
        c,
        f_c,
        f_s,
        v_s,
        delta,
        sigma2,
        dt,
    }
}
