//! The multi-element Maxwell-slip friction model: a parallel bank of
//! elastoplastic elements.

use crate::{
    check, check_input, check_lengths, check_output, declare_params, stop_step, Error, Float,
    Operator, Result, Trial,
};

declare_params! {
    /// Parameters of a [`MaxwellSlip`] bank.
    pub struct MaxwellSlipParams<T> {
        /// Element stiffnesses `k_i > 0`.
        k: Vec<T> => Positive = [40.0, 10.0, 4.0],
        /// Element break-away forces `F_i > 0`.
        f_b: Vec<T> => Positive = [0.2, 0.3, 0.5],
        /// Element forces at input `x = 0` before the first sample (default
        /// empty: all 0). A value outside `[−F_i, F_i]` is clipped there at the
        /// first sample, as in the [`ElastoPlastic`](crate::ElastoPlastic)
        /// element.
        #[serde(default)]
        f0: Vec<T> => Real = [0.1, -0.3, 0.0],
    }
    check = MaxwellSlipParams::shape;
}

impl<T: Float> MaxwellSlipParams<T> {
    /// At least one element; `k`, `f_b` (and `f0` if given) of one
    /// length; the element thresholds `F_i/k_i` finite and non-zero and
    /// `f0_i/k_i` finite.
    fn shape(&self) -> Result<()> {
        check::element_lengths(self.k.len(), ("f_b", self.f_b.len()), self.f0.len())?;
        for (i, (&f, &k)) in self.f_b.iter().zip(&self.k).enumerate() {
            let r = f / k;
            if !r.is_finite() || r == T::zero() {
                return Err(check::invalid(
                    &format!("f_b[{i}]"),
                    f,
                    "F_i / k_i must be a finite, non-zero number",
                ));
            }
        }
        for (i, (&f, &k)) in self.f0.iter().zip(&self.k).enumerate() {
            if !(f / k).is_finite() {
                return Err(check::invalid(
                    &format!("f0[{i}]"),
                    f,
                    "f0_i / k_i must be finite",
                ));
            }
        }
        Ok(())
    }
}

/// Multi-element Maxwell-slip friction: `N` elastoplastic elements (a
/// spring of stiffness `k_i` pulling a block that slips at the break-away
/// force `F_i`) in parallel,
///
/// `F = Σ_i k_i · s_{F_i/k_i}[x]`,
///
/// with `s_r` the [`Stop`](crate::Stop) of threshold `r`. Each element
/// follows `F_i` linearly with slope `k_i` until `|F_i|` reaches the
/// break-away force, then slides at `±F_i`; the bank is a stop-type
/// Prandtl-Ishlinskii operator with weights `k_i` and thresholds
/// `F_i/k_i`. Consequences, each property-tested in `tests/friction.rs`:
///
/// * **non-local memory with wiping-out**: every element remembers its
///   own last reversal; an input extremum beyond earlier ones erases them;
/// * **virgin curve** (from the unloaded state, `x ≥ 0` increasing)
///   `φ(x) = Σ_i min(k_i x, F_i)`: piecewise linear with breakpoints at
///   `F_i/k_i`;
/// * **Masing rule**: after a reversal at `(x_r, F_r)` on the virgin curve
///   the branch is the virgin curve scaled by two,
///   `F − F_r = −2 φ((x_r − x)/2)` for `x` decreasing from `x_r`;
/// * `|F| ≤ Σ_i F_i` from the first sample on;
/// * exact rate independence in floating point (inherited from the stop)
///   when every `|f0_i| ≤ F_i` (a force beyond is clipped at the first
///   sample, and where that sample lies then matters).
///
/// The elements are stored as structure-of-arrays (thresholds, stiffnesses,
/// play positions); the forces are summed in element order
/// `((F_0 + F_1) + F_2) + …`, the order of a left-nested
/// [`Parallel`](https://docs.rs/hysteron-composition) of
/// [`ElastoPlastic`](crate::ElastoPlastic) elements, whose output this
/// equals bit for bit (as does the tangent `Σ_i k_i · [element i
/// sticks]`). [`process`](Operator::process) is bit-identical to the
/// trial + commit loop. Parameters: `[k_0..k_{N−1}, F_0..F_{N−1},
/// f0_0..f0_{N−1}]`.
///
/// ```
/// use hysteron_operators::{MaxwellSlip, Operator};
/// let mut ms = MaxwellSlip::new(vec![8.0_f64, 4.0], vec![1.0, 2.0]).unwrap();
/// // virgin curve: breakpoints at F_i/k_i = 0.125 and 0.5
/// let f = ms.run(&[0.0625, 0.25, 1.0]).unwrap();
/// assert_eq!(f, vec![8.0 * 0.0625 + 4.0 * 0.0625, 1.0 + 4.0 * 0.25, 1.0 + 2.0]);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct MaxwellSlip<T> {
    /// The parameters, `f0` written out in full.
    p: MaxwellSlipParams<T>,
    /// Element thresholds `F_i/k_i`.
    r: Vec<T>,
    /// Initial play positions `−f0_i/k_i`.
    q0: Vec<T>,
    /// Committed play positions `x − s_i`.
    q: Vec<T>,
    pending: Vec<T>,
    has_pending: bool,
}

impl<T: Float> MaxwellSlip<T> {
    /// A bank with stiffnesses `k` and break-away forces `f_b`, unloaded.
    pub fn new(k: Vec<T>, f_b: Vec<T>) -> Result<Self> {
        Self::from_params(MaxwellSlipParams {
            k,
            f_b,
            f0: Vec::new(),
        })
    }

    /// A bank from validated parameters.
    pub fn from_params(p: MaxwellSlipParams<T>) -> Result<Self> {
        p.validate()?;
        let n = p.k.len();
        let f0 = if p.f0.is_empty() {
            vec![T::zero(); n]
        } else {
            p.f0
        };
        let r: Vec<T> = p.f_b.iter().zip(&p.k).map(|(&f, &k)| f / k).collect();
        // The same initial play position as `Stop::from_params` gives the
        // element's stop (`q = −s0`, `s0 = f0/k`).
        let q0: Vec<T> = f0.iter().zip(&p.k).map(|(&f, &k)| -(f / k)).collect();
        Ok(Self {
            p: MaxwellSlipParams { f0, ..p },
            r,
            q: q0.clone(),
            q0,
            pending: vec![T::zero(); n],
            has_pending: false,
        })
    }

    /// The parameters (with `f0` written out in full).
    pub fn parameters(&self) -> &MaxwellSlipParams<T> {
        &self.p
    }

    /// Number of elements `N ≥ 1`.
    pub fn len(&self) -> usize {
        self.p.k.len()
    }

    /// Always false: a bank has at least one element.
    pub fn is_empty(&self) -> bool {
        self.p.k.is_empty()
    }
}

/// Advances every element from `prev` to `next` for input `x`; returns the
/// force `Σ k_i s_i` and the tangent `Σ k_i t_i`, summed in element order
/// starting from element 0 (so a left-nested parallel of elastoplastic
/// elements gives the same bits; starting from 0 would turn a lone `−0`
/// into `+0`).
#[inline(always)]
fn bank_step<T: Float>(r: &[T], k: &[T], prev: &[T], next: &mut [T], x: T) -> (T, T) {
    let mut force = T::zero();
    let mut tangent = T::zero();
    for (i, (((&r, &k), &q), qn)) in r.iter().zip(k).zip(prev).zip(next.iter_mut()).enumerate() {
        let (s, q_new, t) = stop_step(r, q, x);
        *qn = q_new;
        let (f, kt) = (k * s, k * t);
        if i == 0 {
            force = f;
            tangent = kt;
        } else {
            force = force + f;
            tangent = tangent + kt;
        }
    }
    (force, tangent)
}

impl<T: Float> Operator<T> for MaxwellSlip<T> {
    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        self.has_pending = false;
        let x = check_input(x)?;
        let (output, tangent) = bank_step(&self.r, &self.p.k, &self.q, &mut self.pending, x);
        let t = check_output("maxwell_slip", x, Trial { output, tangent })?;
        self.has_pending = true;
        Ok(t)
    }

    fn commit(&mut self) {
        if self.has_pending {
            std::mem::swap(&mut self.q, &mut self.pending);
            self.has_pending = false;
        }
    }

    fn reset(&mut self) {
        self.q.copy_from_slice(&self.q0);
        self.has_pending = false;
    }

    fn process(&mut self, xs: &[T], ys: &mut [T]) -> Result<()> {
        check_lengths(xs, ys)?;
        self.has_pending = false;
        for (i, (&x, out)) in xs.iter().zip(ys.iter_mut()).enumerate() {
            if !x.is_finite() {
                return Err(Error::NonFiniteInput { value: x.as_f64() }.at_sample(i));
            }
            let (y, _) = bank_step(&self.r, &self.p.k, &self.q, &mut self.pending, x);
            if !y.is_finite() {
                return Err(Error::NonFiniteOutput {
                    operator: "maxwell_slip",
                    input: x.as_f64(),
                }
                .at_sample(i));
            }
            std::mem::swap(&mut self.q, &mut self.pending);
            *out = y;
        }
        Ok(())
    }

    fn name(&self) -> &'static str {
        <Self as crate::Leaf<T>>::KIND
    }
}

crate::leaf_traits!(MaxwellSlip);

/// No fast paths beyond the batch loop of `process`.
impl<T: Float> crate::Hints<T> for MaxwellSlip<T> {}

/// Rate-independent: the period is only checked.
impl<T: Float> crate::SamplePeriod<T> for MaxwellSlip<T> {}

crate::impl_leaf!(
    MaxwellSlip,
    MaxwellSlipParams,
    "maxwell_slip",
    p,
    equation: "F = Σ_i k_i · stop_{F_i/k_i}[x] (parallel elastoplastic elements)"
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn invalid_parameters_are_typed_errors() {
        let bad = |k: Vec<f64>, f_b: Vec<f64>, f0: Vec<f64>| {
            MaxwellSlip::from_params(MaxwellSlipParams { k, f_b, f0 }).unwrap_err()
        };
        for (e, name) in [
            (bad(vec![], vec![], vec![]), "k"),
            (bad(vec![1.0], vec![1.0, 2.0], vec![]), "f_b"),
            (bad(vec![1.0], vec![1.0], vec![0.0, 0.0]), "f_b"),
            (bad(vec![1.0, 0.0], vec![1.0, 1.0], vec![]), "k[1]"),
            (bad(vec![1.0, f64::NAN], vec![1.0, 1.0], vec![]), "k[1]"),
            (bad(vec![1.0], vec![0.0], vec![]), "f_b[0]"),
            (bad(vec![1.0], vec![f64::INFINITY], vec![]), "f_b[0]"),
            (bad(vec![1e300], vec![1e-300], vec![]), "f_b[0]"),
            (bad(vec![1.0], vec![1.0], vec![f64::NAN]), "f0[0]"),
            (bad(vec![1e-300], vec![1e-300], vec![1e300]), "f0[0]"),
        ] {
            match e {
                Error::InvalidParameter { name: n, .. } => assert_eq!(n, name),
                other => panic!("{other}"),
            }
        }
    }

    #[test]
    fn tangent_is_the_stiffness_of_the_sticking_elements() {
        let mut ms = MaxwellSlip::new(vec![8.0_f64, 4.0], vec![1.0, 2.0]).unwrap();
        assert_eq!(ms.trial(0.0625).unwrap().tangent, 12.0);
        assert_eq!(ms.trial(0.25).unwrap().tangent, 4.0);
        assert_eq!(ms.trial(1.0).unwrap().tangent, 0.0);
        ms.commit();
        // reversal: both elements stick again
        let t = ms.trial(0.875).unwrap();
        assert_eq!((t.output, t.tangent), (3.0 - 12.0 * 0.125, 12.0));
    }
}
