//! The stiffness map `S(z)` of the Bouc-Wen-like spring.

use crate::{check, Error, Float, Result};
use serde::{Deserialize, Serialize};

/// Symmetric stiffness map `S(z) = σ(|z|)`, with `σ` piecewise linear
/// through knots `(z_i, s_i)` (linear interpolation, constant below the
/// first and beyond the last knot). One knot is a constant stiffness.
///
/// Knot positions are finite, `≥ 0` and strictly increasing; stiffness
/// values are finite and `≥ 0`.
///
/// ```
/// use hysteron_operators::StiffnessMap;
/// let s = StiffnessMap::new(vec![0.0, 1.0], vec![10.0, 20.0]).unwrap();
/// assert_eq!(s.eval(-0.5_f64).0, 15.0); // symmetric in z
/// assert_eq!(s.eval(3.0).0, 20.0);      // constant beyond the last knot
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StiffnessMap<T> {
    z: Vec<T>,
    s: Vec<T>,
}

impl<T: Float> StiffnessMap<T> {
    /// A piecewise-linear map through knots `(z[i], s[i])`.
    pub fn new(z: Vec<T>, s: Vec<T>) -> Result<Self> {
        let map = Self { z, s };
        map.validate()?;
        Ok(map)
    }

    /// A constant stiffness `k ≥ 0`.
    pub fn constant(k: T) -> Result<Self> {
        Self::new(vec![T::zero()], vec![k])
    }

    /// Checks the knots (see the type's documentation).
    pub fn validate(&self) -> Result<()> {
        if self.z.is_empty() || self.z.len() != self.s.len() {
            return Err(Error::InvalidParameter {
                name: "knots".into(),
                value: self.z.len() as f64,
                reason: "need at least one knot, with as many stiffness values as positions",
            });
        }
        for (i, (&z, &s)) in self.z.iter().zip(&self.s).enumerate() {
            check::non_negative(&format!("z[{i}]"), z)?;
            check::non_negative(&format!("s[{i}]"), s)?;
            if i > 0 && z <= self.z[i - 1] {
                return Err(Error::InvalidParameter {
                    name: format!("z[{i}]"),
                    value: z.as_f64(),
                    reason: "knot positions must be strictly increasing",
                });
            }
        }
        Ok(())
    }

    /// Knot positions `z_i`.
    pub fn knots_z(&self) -> &[T] {
        &self.z
    }

    /// Knot stiffness values `s_i`.
    pub fn knots_s(&self) -> &[T] {
        &self.s
    }

    /// Number of knots.
    pub fn len(&self) -> usize {
        self.z.len()
    }

    /// Always false: a valid map has at least one knot.
    pub fn is_empty(&self) -> bool {
        self.z.is_empty()
    }

    /// `(S(z), dS/dz)` at `z` (the derivative is one-sided at knots, taken
    /// on the segment to the right of `|z|`).
    #[inline]
    pub fn eval(&self, z: T) -> (T, T) {
        self.eval_by(z, |i| self.slope(i))
    }

    /// The slope `(S_{i+1} − S_i)/(z_{i+1} − z_i)` of every segment, for
    /// [`eval_with`](Self::eval_with).
    pub fn slopes(&self) -> Vec<T> {
        (0..self.len().saturating_sub(1))
            .map(|i| self.slope(i))
            .collect()
    }

    /// [`eval`](Self::eval) with the segment slopes precomputed by
    /// [`slopes`](Self::slopes) (the same values, without a division).
    #[inline]
    pub fn eval_with(&self, slopes: &[T], z: T) -> (T, T) {
        self.eval_by(z, |i| {
            slopes.get(i).copied().unwrap_or_else(|| self.slope(i))
        })
    }

    #[inline(always)]
    fn slope(&self, i: usize) -> T {
        (self.s[i + 1] - self.s[i]) / (self.z[i + 1] - self.z[i])
    }

    #[inline(always)]
    fn eval_by(&self, z: T, slope_of: impl Fn(usize) -> T) -> (T, T) {
        if let [s] = self.s[..] {
            return (s, T::zero());
        }
        let a = z.abs();
        let i = self.z.partition_point(|&zi| zi <= a);
        if i == 0 {
            return (self.s[0], T::zero());
        }
        if i == self.z.len() {
            return (self.s[i - 1], T::zero());
        }
        let (z0, s0) = (self.z[i - 1], self.s[i - 1]);
        let slope = slope_of(i - 1);
        let sign = if z < T::zero() { -T::one() } else { T::one() };
        (s0 + slope * (a - z0), slope * sign)
    }

    /// Appends `z_0..z_m, s_0..s_m` to `out`.
    pub fn params_into(&self, out: &mut Vec<T>) {
        out.extend_from_slice(&self.z);
        out.extend_from_slice(&self.s);
    }

    /// A map with the same number of knots from `z_0..z_m, s_0..s_m`.
    pub fn from_flat(&self, p: &[T]) -> Result<Self> {
        check::count(2 * self.len(), p)?;
        let (z, s) = p.split_at(self.len());
        Self::new(z.to_vec(), s.to_vec())
    }

    /// Parameter names `z[i]` then `s[i]`.
    pub fn param_names(&self) -> Vec<String> {
        (0..self.len())
            .map(|i| format!("z[{i}]"))
            .chain((0..self.len()).map(|i| format!("s[{i}]")))
            .collect()
    }
}
