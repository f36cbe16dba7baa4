//! A viscous damper (rate-dependent).

use crate::{check, check_input, check_output, Domain, Float, Operator, Result, Trial};

/// Viscous damper, force from displacement: `F = c ẋ`, `c ≥ 0`.
///
/// **Rate-dependent**: it holds its sample period `dt`. The velocity is the
/// backward difference `v_{k+1} = (x_{k+1} − x_k)/dt` (first-order
/// accurate; the trapezoidal differentiator `2Δx/dt − v_k` would be
/// second-order but rings at the Nyquist frequency after any kink in the
/// input), so the tangent is `dF/dx = c/dt`. It starts at rest (`x = 0`).
/// Parameter `[c]`; `dt` is fixed.
///
/// ```
/// use hysteron_operators::{Operator, ViscousDamper};
/// // a ramp of slope 2: F = c·2
/// let mut d = ViscousDamper::new(3.0_f64, 0.01).unwrap();
/// let x: Vec<f64> = (1..=100).map(|i| 0.02 * i as f64).collect();
/// let f = d.run(&x).unwrap();
/// assert!((f[99] - 6.0).abs() < 1e-9);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct ViscousDamper<T> {
    c: T,
    dt: T,
    x: T,
    pending: Option<T>,
}

impl<T: Float> ViscousDamper<T> {
    /// A damper with coefficient `c ≥ 0` and sample period `dt > 0`.
    pub fn new(c: T, dt: T) -> Result<Self> {
        check::non_negative("c", c)?;
        check::positive("dt", dt)?;
        Ok(Self {
            c,
            dt,
            x: T::zero(),
            pending: None,
        })
    }
}

impl<T: Float> Operator<T> for ViscousDamper<T> {
    fn name(&self) -> &'static str {
        "viscous-damper"
    }

    #[inline]
    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        self.pending = None;
        let x = check_input(x)?;
        let v = (x - self.x) / self.dt;
        let t = check_output(
            "viscous-damper",
            x,
            Trial {
                output: self.c * v,
                tangent: self.c / self.dt,
            },
        )?;
        self.pending = Some(x);
        Ok(t)
    }

    #[inline]
    fn commit(&mut self) {
        if let Some(x) = self.pending.take() {
            self.x = x;
        }
    }

    fn reset(&mut self) {
        self.x = T::zero();
        self.pending = None;
    }

    fn n_params(&self) -> usize {
        1
    }

    fn params_into(&self, out: &mut Vec<T>) {
        out.push(self.c);
    }

    fn param_names(&self) -> Vec<String> {
        vec!["c".into()]
    }

    fn param_domains(&self) -> Vec<Domain> {
        vec![Domain::NonNegative]
    }

    fn set_params(&mut self, p: &[T]) -> Result<()> {
        check::count(1, p)?;
        *self = Self::new(p[0], self.dt)?;
        Ok(())
    }
}
