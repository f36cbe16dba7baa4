//! The stiffness map `S(z)` of the Bouc-Wen-like spring.

use crate::{
    check, CastScalar, Domain, Error, FieldInfo, FieldKind, Float, ParamField, ParamSet, Result,
};
use serde::{Deserialize, Serialize};

/// Maps with at most this many knots are searched by counting (see
/// `StiffnessMap::eval_by`).
const LINEAR_SEARCH_KNOTS: usize = 16;

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
///
/// Serialized as its knots, `{"z": [...], "s": [...]}`; a constant
/// stiffness `k` may also be read from a bare number, the map with the one
/// knot `(0, k)`:
///
/// ```
/// use hysteron_operators::StiffnessMap;
/// let k: StiffnessMap<f64> = serde_json::from_str("5.0").unwrap();
/// assert_eq!(k, StiffnessMap::constant(5.0).unwrap());
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StiffnessMap<T> {
    z: Vec<T>,
    s: Vec<T>,
}

/// The knots as they are written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Knots<T> {
    z: Vec<T>,
    s: Vec<T>,
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for StiffnessMap<T> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        use serde::de::{self, IntoDeserializer};
        struct Visit<T>(std::marker::PhantomData<T>);
        impl<'de, T: Deserialize<'de>> de::Visitor<'de> for Visit<T> {
            type Value = StiffnessMap<T>;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a constant stiffness (a number) or knots {\"z\": [...], \"s\": [...]}")
            }
            fn visit_f64<E: de::Error>(self, k: f64) -> std::result::Result<Self::Value, E> {
                Ok(StiffnessMap {
                    z: vec![T::deserialize(0.0_f64.into_deserializer())?],
                    s: vec![T::deserialize(k.into_deserializer())?],
                })
            }
            fn visit_i64<E: de::Error>(self, k: i64) -> std::result::Result<Self::Value, E> {
                self.visit_f64(k as f64)
            }
            fn visit_u64<E: de::Error>(self, k: u64) -> std::result::Result<Self::Value, E> {
                self.visit_f64(k as f64)
            }
            fn visit_map<A: de::MapAccess<'de>>(
                self,
                map: A,
            ) -> std::result::Result<Self::Value, A::Error> {
                let Knots { z, s } =
                    Knots::deserialize(de::value::MapAccessDeserializer::new(map))?;
                Ok(StiffnessMap { z, s })
            }
        }
        d.deserialize_any(Visit(std::marker::PhantomData))
    }
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
        let mut prev: Option<T> = None;
        for (i, (&z, &s)) in self.z.iter().zip(&self.s).enumerate() {
            check::non_negative(&format!("z[{i}]"), z)?;
            check::non_negative(&format!("s[{i}]"), s)?;
            if prev.is_some_and(|p| z <= p) {
                return Err(Error::InvalidParameter {
                    name: format!("z[{i}]"),
                    value: z.as_f64(),
                    reason: "knot positions must be strictly increasing",
                });
            }
            prev = Some(z);
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
        // (inlined, closure included: a call here made the Bouc-Wen trial
        // spill its live registers around it)
        self.eval_by(
            z,
            #[inline(always)]
            |i| slopes.get(i).copied().unwrap_or_else(|| self.slope(i)),
        )
    }

    // The map is public and `Deserialize` (unvalidated: `z` and `s` may
    // differ in length), so `slope` and `eval_by` look knots up with `get`
    // (the same one compare as an index) and give NaN for a missing one,
    // which the operators report as a non-finite output.
    #[inline(always)]
    fn slope(&self, i: usize) -> T {
        match (self.z.get(i..i + 2), self.s.get(i..i + 2)) {
            (Some(&[z0, z1]), Some(&[s0, s1])) => (s1 - s0) / (z1 - z0),
            _ => T::nan(),
        }
    }

    /// [`eval_with`](Self::eval_with), trying first the segment `*segment`
    /// (the number of knots at or below `|z|` at the call before, which
    /// it sets): consecutive samples mostly stay on one segment, and two
    /// comparisons confirm it where counting the knots takes one per
    /// knot. The same segment, so the same values.
    ///
    /// ```
    /// use hysteron_operators::StiffnessMap;
    /// let map = StiffnessMap::new(vec![0.0, 1.0, 2.0], vec![10.0, 20.0, 40.0]).unwrap();
    /// let slopes = map.slopes();
    /// let mut segment = 0; // any start gives the same values
    /// assert_eq!(map.eval_from(&slopes, -1.5, &mut segment), map.eval(-1.5));
    /// assert_eq!(segment, 2); // two knots at or below 1.5
    /// ```
    #[inline(always)]
    pub fn eval_from(&self, slopes: &[T], z: T, segment: &mut usize) -> (T, T) {
        if let [s] = self.s[..] {
            return (s, T::zero());
        }
        let a = z.abs();
        let i = *segment;
        // `i` knots at or below `a` (increasing knots): the one before it
        // at or below, the one at it (if any) not.
        let below = i
            .checked_sub(1)
            .is_none_or(|k| self.z.get(k).is_some_and(|&zk| zk <= a));
        // (`!(zi <= a)`: what the count does not count, NaN included)
        #[allow(clippy::neg_cmp_op_on_partial_ord)]
        let above = self.z.get(i).is_none_or(|&zi| !(zi <= a));
        let i = if below && above {
            i
        } else {
            self.knots_at_or_below(a)
        };
        *segment = i;
        self.on_segment(z, a, i, |k| {
            slopes.get(k).copied().unwrap_or_else(|| self.slope(k))
        })
    }

    /// The number of knots at or below `a` (the partition point of the
    /// increasing knots): for a few knots counted without branches, which
    /// costs less than a binary search's mispredictions.
    #[inline(always)]
    fn knots_at_or_below(&self, a: T) -> usize {
        if self.z.len() <= LINEAR_SEARCH_KNOTS {
            self.z.iter().fold(0, |n, &zi| n + usize::from(zi <= a))
        } else {
            self.z.partition_point(|&zi| zi <= a)
        }
    }

    #[inline(always)]
    fn eval_by(&self, z: T, slope_of: impl Fn(usize) -> T) -> (T, T) {
        if let [s] = self.s[..] {
            return (s, T::zero());
        }
        let a = z.abs();
        let i = self.knots_at_or_below(a);
        self.on_segment(z, a, i, slope_of)
    }

    /// `(S, dS/dz)` at `z` (`a = |z|`) on the segment after the first `i`
    /// knots.
    #[inline(always)]
    fn on_segment(&self, z: T, a: T, i: usize, slope_of: impl Fn(usize) -> T) -> (T, T) {
        let Some(k) = i.checked_sub(1) else {
            let s0 = self.s.first().copied().unwrap_or_else(T::nan);
            return (s0, T::zero());
        };
        let (Some(&z0), Some(&s0)) = (self.z.get(k), self.s.get(k)) else {
            return (T::nan(), T::nan());
        };
        if i == self.z.len() {
            return (s0, T::zero());
        }
        let slope = slope_of(k);
        let sign = if z < T::zero() { -T::one() } else { T::one() };
        (s0 + slope * (a - z0), slope * sign)
    }
}

impl<T: Float> StiffnessMap<T> {
    /// The two declared vectors with their declarations.
    // `FIELDS` is the two-entry literal below.
    #[allow(clippy::indexing_slicing)]
    fn fields(&self) -> [(&Vec<T>, &'static FieldInfo); 2] {
        let f = <Self as ParamSet<T>>::FIELDS;
        [(&self.z, &f[0]), (&self.s, &f[1])]
    }
}

/// The same knots over the scalar `U` (see [`CastScalar`]).
impl<T: Float, U: Float> CastScalar<U> for StiffnessMap<T> {
    type Out = StiffnessMap<U>;
    fn cast_scalar(&self) -> StiffnessMap<U> {
        StiffnessMap {
            z: self.z.cast_scalar(),
            s: self.s.cast_scalar(),
        }
    }
}

/// The map's parameters are its knots: `z[0..m]`, then `s[0..m]`.
impl<T: Float> ParamSet<T> for StiffnessMap<T> {
    const FIELDS: &'static [FieldInfo] = &[
        FieldInfo {
            name: "z",
            kind: FieldKind::Param(Domain::NonNegative),
            doc: &["Knot positions `z_i ≥ 0`, strictly increasing."],
        },
        FieldInfo {
            name: "s",
            kind: FieldKind::Param(Domain::NonNegative),
            doc: &["Stiffness values `s_i ≥ 0` at the knots."],
        },
    ];

    fn count(&self) -> usize {
        2 * self.len()
    }

    fn names_into(&self, prefix: &str, out: &mut Vec<String>) {
        for (v, f) in self.fields() {
            v.names_into(&format!("{prefix}{}", f.name), f.kind, out);
        }
    }

    fn domains_into(&self, out: &mut Vec<Domain>) {
        for (v, f) in self.fields() {
            ParamField::<T>::domains_into(v, f.kind, out);
        }
    }

    fn write(&self, out: &mut Vec<T>) {
        for (v, f) in self.fields() {
            v.write(f.kind, out);
        }
    }

    fn read(&self, p: &mut &[T]) -> Result<Self> {
        let [(z, fz), (s, fs)] = self.fields();
        Ok(Self {
            z: z.read(fz.kind, p)?,
            s: s.read(fs.kind, p)?,
        })
    }

    fn validate(&self) -> Result<()> {
        StiffnessMap::validate(self)
    }

    /// Two knots: `S = 2` at `|z| = 0` rising to `3` at `|z| = 1`.
    fn example() -> Self {
        Self {
            z: vec![T::zero(), T::one()],
            s: vec![T::lit(2.0), T::lit(3.0)],
        }
    }
}

crate::nested_param_field!(StiffnessMap);

#[cfg(test)]
mod tests {
    use super::*;

    /// A map as `Deserialize` builds it, without validation: `eval` used to
    /// index past the end of `s` (a panic); now the value is NaN, which the
    /// operators report as an error.
    #[test]
    fn unvalidated_map_does_not_panic() {
        for (z, s) in [
            (vec![0.0, 1.0], vec![1.0]),
            (vec![0.0, 1.0, 2.0], vec![1.0, 2.0]),
            (vec![], vec![]),
            (vec![0.5], vec![]),
        ] {
            let map = StiffnessMap::<f64> { z, s };
            assert!(map.validate().is_err());
            for x in [-3.0, 0.0, 0.25, 0.5, 1.5, 3.0] {
                let _ = map.eval(x);
                let _ = map.eval_with(&map.slopes(), x);
            }
        }
        let map = StiffnessMap::<f64> {
            z: vec![0.0, 1.0, 2.0],
            s: vec![1.0, 2.0],
        };
        assert_eq!(map.eval(0.5), (1.5, 1.0));
        assert!(map.eval(1.5).0.is_nan());
        assert!(map.eval(2.5).0.is_nan());
        assert!(map.slopes()[1].is_nan());
    }

    /// Counting the knots at or below `|z|` (small maps) finds the segment
    /// that a binary search finds: the values and slopes are those of the
    /// interpolation on that segment, at knots, between them, below the
    /// first and beyond the last, on maps with fewer and more knots than
    /// [`LINEAR_SEARCH_KNOTS`].
    #[test]
    fn eval_is_the_interpolation_on_the_segment_of_z() {
        for n in [1, 2, 6, LINEAR_SEARCH_KNOTS, LINEAR_SEARCH_KNOTS + 1, 40] {
            let z: Vec<f64> = (0..n).map(|i| 0.1 + 0.3 * i as f64).collect();
            let s: Vec<f64> = (0..n).map(|i| 10.0 + (i * i) as f64).collect();
            let map = StiffnessMap::new(z.clone(), s.clone()).unwrap();
            let slopes = map.slopes();
            let mut probes = vec![0.0, 0.05, 1e9];
            for &zi in &z {
                probes.extend([zi, zi + 0.1, f64::from_bits(zi.to_bits() - 1)]);
            }
            for a in probes {
                let k = z.partition_point(|&zi| zi <= a);
                let want = match k {
                    0 => (s[0], 0.0),
                    k if k == n => (s[n - 1], 0.0),
                    k => {
                        let slope = (s[k] - s[k - 1]) / (z[k] - z[k - 1]);
                        (s[k - 1] + slope * (a - z[k - 1]), slope)
                    }
                };
                for x in [a, -a] {
                    let sign = if x < 0.0 { -1.0 } else { 1.0 };
                    let want = (want.0, want.1 * sign);
                    assert_eq!(map.eval(x), want, "{n} knots, z = {x}");
                    assert_eq!(map.eval_with(&slopes, x), want, "{n} knots, z = {x}");
                    // From every segment, the right one or not (and one
                    // past the knots), and then from the one it set.
                    for start in 0..=n + 1 {
                        let mut segment = start;
                        let got = map.eval_from(&slopes, x, &mut segment);
                        assert_eq!(got, want, "{n} knots, z = {x}, from segment {start}");
                        if n > 1 {
                            assert_eq!(segment, k, "{n} knots, z = {x}, from segment {start}");
                        }
                        assert_eq!(map.eval_from(&slopes, x, &mut segment), want);
                    }
                }
            }
        }
    }

    /// A NaN input gives what `eval` gives from any segment tried first.
    #[test]
    fn eval_from_a_segment_keeps_nan_as_eval_does() {
        let map = StiffnessMap::new(vec![0.0, 0.5, 1.0], vec![1.0, 2.0, 4.0]).unwrap();
        let slopes = map.slopes();
        let (s, ds) = map.eval(f64::NAN);
        for start in 0..5 {
            let mut segment = start;
            let (t, dt) = map.eval_from(&slopes, f64::NAN, &mut segment);
            assert_eq!((t.to_bits(), dt.to_bits()), (s.to_bits(), ds.to_bits()));
        }
    }
}
