//! Stepping by delegation: the [`Operator`](hysteron_operators::Operator)
//! methods of a wrapper that steps exactly as one of its fields.

/// The stepping methods of [`Operator`](hysteron_operators::Operator)
/// (`trial`, `commit`, `reset` and `process`) for a wrapper that steps
/// exactly as its field `$field`, an `Operator<$t>`: each forwards to the
/// field. Written inside the wrapper's `impl Operator<$t>` block, beside
/// its own `name` (and any method it overrides besides these):
///
/// ```
/// use hysteron_composition::delegate_stepping;
/// use hysteron_operators::{Gain, Operator};
///
/// /// A gain under another name.
/// #[derive(Clone, Debug)]
/// struct Amplifier {
///     gain: Gain<f64>,
/// }
///
/// impl Operator<f64> for Amplifier {
///     delegate_stepping!(f64, gain);
///
///     fn name(&self) -> &'static str {
///         "amplifier"
///     }
/// }
/// # impl hysteron_operators::Hints<f64> for Amplifier {}
/// # impl hysteron_operators::SamplePeriod<f64> for Amplifier {}
/// # impl hysteron_operators::Derivatives<f64> for Amplifier {}
/// # impl hysteron_operators::Parameters<f64> for Amplifier {
/// #     fn n_params(&self) -> usize { 0 }
/// #     fn params_into(&self, _: &mut Vec<f64>) {}
/// #     fn param_names(&self) -> Vec<String> { Vec::new() }
/// #     fn set_params(&mut self, _: &[f64]) -> hysteron_operators::Result<()> { Ok(()) }
/// # }
///
/// let mut a = Amplifier { gain: Gain::new(2.0).unwrap() };
/// assert_eq!(a.trial(1.5).unwrap().output, 3.0);
/// ```
#[macro_export]
macro_rules! delegate_stepping {
    ($t:ty, $field:ident) => {
        #[inline]
        fn trial(&mut self, x: $t) -> $crate::__operators::Result<$crate::__operators::Trial<$t>> {
            $crate::__operators::Operator::<$t>::trial(&mut self.$field, x)
        }

        #[inline]
        fn commit(&mut self) {
            $crate::__operators::Operator::<$t>::commit(&mut self.$field)
        }

        fn reset(&mut self) {
            $crate::__operators::Operator::<$t>::reset(&mut self.$field)
        }

        fn process(&mut self, xs: &[$t], ys: &mut [$t]) -> $crate::__operators::Result<()> {
            $crate::__operators::Operator::<$t>::process(&mut self.$field, xs, ys)
        }
    };
}
