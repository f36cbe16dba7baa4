//! The play operator (backlash).

use crate::{check, check_input, check_lengths, Domain, Error, Float, Operator, Result, Trial};
use serde::{Deserialize, Serialize};

/// Parameters of the [`Play`] operator.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PlayParams<T> {
    /// Threshold (half the backlash gap) `r ≥ 0`.
    pub r: T,
    /// Output at input `x = 0` before the first sample (default 0).
    #[serde(default)]
    pub y0: T,
}

impl<T: Float> PlayParams<T> {
    /// Checks `r ≥ 0` and finite `y0`.
    pub fn validate(&self) -> Result<()> {
        check::non_negative("r", self.r)?;
        check::finite("y0", self.y0)
    }
}

/// Play (backlash) operator with threshold `r`:
///
/// `y_k = max(x_k − r, min(x_k + r, y_{k−1}))`,
///
/// starting from `y0` (so the first output is `y0` clipped into
/// `[x_1 − r, x_1 + r]`). Rate-independent, `|Δy| ≤ |Δx|`, and
/// `play_0 = identity`. Tangent: 1 while the input drags the output, 0 inside
/// the gap.
///
/// ```
/// use hysteron_operators::{Operator, Play};
/// let mut p = Play::new(1.0_f64).unwrap();
/// assert_eq!(p.run(&[2.0, 1.5, 0.0, -1.0]).unwrap(), vec![1.0, 1.0, 1.0, 0.0]);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Play<T> {
    p: PlayParams<T>,
    y: T,
    pending: Option<T>,
}

/// One play step: `max(x − r, min(x + r, y_prev))`.
///
/// Written as compare-and-select (inputs are finite, so NaN handling is not
/// needed), which the compiler turns into vector min/max in batch loops.
#[inline(always)]
pub fn play_step<T: Float>(r: T, y_prev: T, x: T) -> T {
    let (lo, hi) = (x - r, x + r);
    let clipped = if y_prev < hi { y_prev } else { hi };
    if clipped > lo {
        clipped
    } else {
        lo
    }
}

/// The tangent of one play step (1 while dragged, 0 inside the gap).
#[inline(always)]
pub fn play_tangent<T: Float>(r: T, y_prev: T, x: T) -> T {
    if x - r >= y_prev || x + r <= y_prev {
        T::one()
    } else {
        T::zero()
    }
}

impl<T: Float> Play<T> {
    /// A play with threshold `r`, starting at output 0.
    pub fn new(r: T) -> Result<Self> {
        Self::from_params(PlayParams { r, y0: T::zero() })
    }

    /// A play from validated parameters.
    pub fn from_params(p: PlayParams<T>) -> Result<Self> {
        p.validate()?;
        Ok(Self {
            p,
            y: p.y0,
            pending: None,
        })
    }

    /// The parameters.
    pub fn parameters(&self) -> &PlayParams<T> {
        &self.p
    }

    /// The committed output.
    pub fn output(&self) -> T {
        self.y
    }
}

impl<T: Float> Operator<T> for Play<T> {
    fn name(&self) -> &'static str {
        "play"
    }

    #[inline]
    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        self.pending = None;
        let x = check_input(x)?;
        let y = play_step(self.p.r, self.y, x);
        self.pending = Some(y);
        Ok(Trial {
            output: y,
            tangent: play_tangent(self.p.r, self.y, x),
        })
    }

    #[inline]
    fn commit(&mut self) {
        if let Some(y) = self.pending.take() {
            self.y = y;
        }
    }

    fn reset(&mut self) {
        self.y = self.p.y0;
        self.pending = None;
    }

    fn process(&mut self, xs: &[T], ys: &mut [T]) -> Result<()> {
        check_lengths(xs, ys)?;
        self.pending = None;
        let r = self.p.r;
        let mut y = self.y;
        for (i, (&x, out)) in xs.iter().zip(ys.iter_mut()).enumerate() {
            if !x.is_finite() {
                self.y = y;
                return Err(Error::NonFiniteInput { value: x.as_f64() }.at_sample(i));
            }
            y = play_step(r, y, x);
            *out = y;
        }
        self.y = y;
        Ok(())
    }

    fn n_params(&self) -> usize {
        2
    }

    fn params_into(&self, out: &mut Vec<T>) {
        out.extend([self.p.r, self.p.y0]);
    }

    fn param_names(&self) -> Vec<String> {
        vec!["r".into(), "y0".into()]
    }

    fn param_domains(&self) -> Vec<Domain> {
        vec![Domain::NonNegative, Domain::Real]
    }

    fn set_params(&mut self, p: &[T]) -> Result<()> {
        check::count(2, p)?;
        *self = Self::from_params(PlayParams { r: p[0], y0: p[1] })?;
        Ok(())
    }
}
