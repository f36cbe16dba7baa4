//! The stop operator (Prandtl-Ishlinskii stop).

use crate::{
    check, check_input, check_lengths, play_step, play_tangent, Domain, Error, Float, Operator,
    Result, Trial,
};
use serde::{Deserialize, Serialize};

/// Parameters of the [`Stop`] operator.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StopParams<T> {
    /// Threshold `r ≥ 0`: the output stays in `[−r, r]`.
    pub r: T,
    /// Output at input `x = 0` before the first sample (default 0).
    #[serde(default)]
    pub s0: T,
}

impl<T: Float> StopParams<T> {
    /// Checks `r ≥ 0` and finite `s0`.
    pub fn validate(&self) -> Result<()> {
        check::non_negative("r", self.r)?;
        check::finite("s0", self.s0)
    }
}

/// Stop operator with threshold `r`: `s_r[x] = x − p_r[x]`, with `p_r` the
/// [`Play`](crate::Play). In exact arithmetic equivalently
/// `s_k = clamp(s_{k−1} + Δx, −r, r)`; in floating point `s = x − p` carries
/// the rounding of `x`, so for `|x|` so large that `ulp(x) > r` the output
/// is resolved only to `ulp(x)`.
///
/// The state kept is the play position `q = x − s`, advanced by the play's
/// own step; this makes the operator exactly rate-independent in floating
/// point. The output `s` lies in `[−r, r]` from
/// the first sample on (an initial `s0` outside is clipped there). Tangent:
/// 1 inside, 0 at saturation.
///
/// ```
/// use hysteron_operators::{Operator, Stop};
/// let mut s = Stop::new(1.0_f64).unwrap();
/// assert_eq!(s.run(&[0.5, 2.0, 1.5]).unwrap(), vec![0.5, 1.0, 0.5]);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Stop<T> {
    p: StopParams<T>,
    /// Committed play position `x − s`.
    q: T,
    pending: Option<T>,
}

/// One stop step from play position `q`: returns `(s, q_new, tangent)`.
///
/// The play position is advanced exactly as the [`Play`](crate::Play)
/// advances its output (so the stop inherits its exact rate independence and
/// wiping-out), and the output is `clamp(x − q_new, −r, r)`.
#[inline(always)]
pub fn stop_step<T: Float>(r: T, q: T, x: T) -> (T, T, T) {
    let q_new = play_step(r, q, x);
    let tangent = T::one() - play_tangent(r, q, x);
    let e = x - q_new;
    let s = if e > r {
        r
    } else if e < -r {
        -r
    } else {
        e
    };
    (s, q_new, tangent)
}

impl<T: Float> Stop<T> {
    /// A stop with threshold `r`, starting at output 0.
    pub fn new(r: T) -> Result<Self> {
        Self::from_params(StopParams { r, s0: T::zero() })
    }

    /// A stop from validated parameters.
    pub fn from_params(p: StopParams<T>) -> Result<Self> {
        p.validate()?;
        Ok(Self {
            p,
            q: -p.s0,
            pending: None,
        })
    }

    /// The parameters.
    pub fn parameters(&self) -> &StopParams<T> {
        &self.p
    }
}

impl<T: Float> Operator<T> for Stop<T> {
    fn name(&self) -> &'static str {
        "stop"
    }

    #[inline]
    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        self.pending = None;
        let x = check_input(x)?;
        let (s, q, tangent) = stop_step(self.p.r, self.q, x);
        self.pending = Some(q);
        Ok(Trial { output: s, tangent })
    }

    #[inline]
    fn commit(&mut self) {
        if let Some(q) = self.pending.take() {
            self.q = q;
        }
    }

    fn reset(&mut self) {
        self.q = -self.p.s0;
        self.pending = None;
    }

    fn process(&mut self, xs: &[T], ys: &mut [T]) -> Result<()> {
        check_lengths(xs, ys)?;
        self.pending = None;
        let r = self.p.r;
        let mut q = self.q;
        for (i, (&x, out)) in xs.iter().zip(ys.iter_mut()).enumerate() {
            if !x.is_finite() {
                self.q = q;
                return Err(Error::NonFiniteInput { value: x.as_f64() }.at_sample(i));
            }
            let (s, qn, _) = stop_step(r, q, x);
            q = qn;
            *out = s;
        }
        self.q = q;
        Ok(())
    }

    fn n_params(&self) -> usize {
        2
    }

    fn params_into(&self, out: &mut Vec<T>) {
        out.extend([self.p.r, self.p.s0]);
    }

    fn param_names(&self) -> Vec<String> {
        vec!["r".into(), "s0".into()]
    }

    fn param_domains(&self) -> Vec<Domain> {
        vec![Domain::NonNegative, Domain::Real]
    }

    fn set_params(&mut self, p: &[T]) -> Result<()> {
        check::count(2, p)?;
        *self = Self::from_params(StopParams { r: p[0], s0: p[1] })?;
        Ok(())
    }
}
