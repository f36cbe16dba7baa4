//! Forward-mode dual numbers: a scalar that carries its derivatives with
//! respect to up to `N` parameters through any operator.

use core::cmp::Ordering;
use core::fmt;
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Rem, Sub, SubAssign};
use num_dual::{Dual64, DualNum};
use num_traits::{Float as NumFloat, FloatConst, Num, NumCast, One, ToPrimitive, Zero};

/// How many derivatives the library's dual scalar [`Dual`] carries at once.
pub const DUAL_WIDTH: usize = 8;

/// The dual scalar the library builds operators over for derivatives
/// ([`DualN`] with [`DUAL_WIDTH`] slots).
pub type Dual = DualN<DUAL_WIDTH>;

/// A dual number `a + Σ_i a_i ε_i` with `ε_i ε_j = 0`: the value `a` of a
/// quantity and its derivatives `a_i = ∂a/∂p_i` with respect to `N` seeds.
///
/// It implements [`num_traits::Float`], so it is a [`Float`](crate::Float)
/// and every operator and combinator runs over it; each arithmetic
/// operation applies the chain rule, `f(a + Σ a_i ε_i) = f(a) + f'(a) Σ a_i ε_i`
/// (the derivative rules of the elementary functions are those of the
/// `num-dual` crate, whose scalar `Dual64` this type calls). Seed a
/// parameter `p_i` with `DualN::variable(p_i, i)` and the outputs carry
/// `∂y/∂p_i`.
///
/// # Behaviour at kinks
/// Comparisons (`<`, `==`, `max`, `min`, `abs`, `signum`) look at the value
/// only: an operator takes the branch the value selects, and the
/// derivative is that branch's. At a kink (a play at its reversal point, a
/// saturation at its limit, a friction slider at its sliding level) the
/// result is the one-sided derivative of the branch taken, which is what a
/// forward-mode derivative of the program is; a central difference across
/// the kink averages the two sides instead. `floor`, `ceil`, `round`,
/// `trunc` and `signum` have derivative 0. A derivative slot that is zero
/// stays zero through any function, even where `f'` is infinite
/// (`sqrt(0)` of a constant has derivative 0, not NaN).
///
/// `is_nan`, `is_finite` and `is_infinite` test the value only; the
/// derivatives' own finiteness is [`DualN::derivatives_finite`].
///
/// ```
/// use hysteron_operators::{DualN, Operator, Play};
/// // a play of threshold r: y = x − r on a rising branch, so ∂y/∂r = −1
/// let mut play = Play::new(DualN::<1>::variable(0.5, 0)).unwrap();
/// let y = play.run(&[DualN::constant(1.0), DualN::constant(2.0)]).unwrap();
/// assert_eq!((y[1].re, y[1].eps[0]), (1.5, -1.0));
/// ```
#[derive(Clone, Copy, Debug)]
pub struct DualN<const N: usize> {
    /// The value.
    pub re: f64,
    /// The derivatives with respect to the `N` seeds.
    pub eps: [f64; N],
}

impl<const N: usize> DualN<N> {
    /// A constant: value `re`, every derivative 0.
    #[inline(always)]
    pub const fn constant(re: f64) -> Self {
        Self { re, eps: [0.0; N] }
    }

    /// The seed `i`: value `re`, derivative 1 in slot `i` (and 0 in the
    /// others; an `i ≥ N` seeds nothing).
    pub fn variable(re: f64, i: usize) -> Self {
        let mut d = Self::constant(re);
        if let Some(e) = d.eps.get_mut(i) {
            *e = 1.0;
        }
        d
    }

    /// Whether every derivative is finite.
    pub fn derivatives_finite(&self) -> bool {
        self.eps.iter().all(|e| e.is_finite())
    }

    /// The value `re` with derivatives `slope · eps` (chain rule), keeping
    /// zero slots zero whatever the slope.
    #[inline(always)]
    fn with_slope(self, re: f64, slope: f64) -> Self {
        Self {
            re,
            eps: self.eps.map(|e| if e == 0.0 { 0.0 } else { e * slope }),
        }
    }

    /// `f` applied by its derivative rule from `num-dual`.
    #[inline(always)]
    fn chain(self, f: impl FnOnce(Dual64) -> Dual64) -> Self {
        let d = f(Dual64::new(self.re, 1.0));
        self.with_slope(d.re, d.eps)
    }

    /// `a · self.eps + b · other.eps`, slot by slot (zero slots stay zero).
    #[inline(always)]
    fn combine(self, a: f64, other: Self, b: f64, re: f64) -> Self {
        let mut eps = [0.0; N];
        for ((e, x), y) in eps.iter_mut().zip(self.eps).zip(other.eps) {
            let l = if x == 0.0 { 0.0 } else { a * x };
            let r = if y == 0.0 { 0.0 } else { b * y };
            *e = l + r;
        }
        Self { re, eps }
    }
}

impl<const N: usize> Default for DualN<N> {
    fn default() -> Self {
        Self::constant(0.0)
    }
}

impl<const N: usize> fmt::Display for DualN<N> {
    /// The value (as `f64` prints it); the derivatives are in `{:?}`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&self.re, f)
    }
}

impl<const N: usize> PartialEq for DualN<N> {
    /// Compares values only (see [Behaviour at kinks](DualN#behaviour-at-kinks)).
    fn eq(&self, other: &Self) -> bool {
        self.re == other.re
    }
}

impl<const N: usize> PartialOrd for DualN<N> {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        self.re.partial_cmp(&other.re)
    }
}

impl<const N: usize> Neg for DualN<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self {
            re: -self.re,
            eps: self.eps.map(|e| -e),
        }
    }
}

/// Addition and subtraction act on the value and each derivative alike.
macro_rules! componentwise_ops {
    ($($tr:ident $f:ident $op:tt $assign:tt),*) => {$(
        impl<const N: usize> $tr for DualN<N> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                let mut eps = self.eps;
                for (e, x) in eps.iter_mut().zip(o.eps) {
                    *e $assign x;
                }
                Self {
                    re: self.re $op o.re,
                    eps,
                }
            }
        }
    )*};
}
componentwise_ops!(Add add + +=, Sub sub - -=);

impl<const N: usize> Mul for DualN<N> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        let mut eps = [0.0; N];
        for ((e, x), y) in eps.iter_mut().zip(self.eps).zip(o.eps) {
            *e = x * o.re + y * self.re;
        }
        Self {
            re: self.re * o.re,
            eps,
        }
    }
}

impl<const N: usize> Div for DualN<N> {
    type Output = Self;
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        let q = self.re / o.re;
        let inv = 1.0 / o.re;
        let mut eps = [0.0; N];
        for ((e, x), y) in eps.iter_mut().zip(self.eps).zip(o.eps) {
            *e = (x - q * y) * inv;
        }
        Self { re: q, eps }
    }
}

impl<const N: usize> Rem for DualN<N> {
    type Output = Self;
    /// `a − trunc(a/b) b`: derivative `a' − trunc(a/b) b'`.
    fn rem(self, o: Self) -> Self {
        let t = (self.re / o.re).trunc();
        self.combine(1.0, o, -t, self.re % o.re)
    }
}

macro_rules! assign_ops {
    ($($tr:ident $f:ident $op:tt),*) => {$(
        impl<const N: usize> $tr for DualN<N> {
            #[inline(always)]
            fn $f(&mut self, o: Self) {
                *self = *self $op o;
            }
        }
    )*};
}
assign_ops!(AddAssign add_assign +, SubAssign sub_assign -, MulAssign mul_assign *, DivAssign div_assign /);

impl<const N: usize> Zero for DualN<N> {
    fn zero() -> Self {
        Self::constant(0.0)
    }
    fn is_zero(&self) -> bool {
        self.re == 0.0
    }
}

impl<const N: usize> One for DualN<N> {
    fn one() -> Self {
        Self::constant(1.0)
    }
}

impl<const N: usize> Num for DualN<N> {
    type FromStrRadixErr = <f64 as Num>::FromStrRadixErr;
    fn from_str_radix(s: &str, radix: u32) -> Result<Self, Self::FromStrRadixErr> {
        f64::from_str_radix(s, radix).map(Self::constant)
    }
}

impl<const N: usize> ToPrimitive for DualN<N> {
    fn to_i64(&self) -> Option<i64> {
        self.re.to_i64()
    }
    fn to_u64(&self) -> Option<u64> {
        self.re.to_u64()
    }
    fn to_f64(&self) -> Option<f64> {
        Some(self.re)
    }
}

impl<const N: usize> NumCast for DualN<N> {
    fn from<P: ToPrimitive>(n: P) -> Option<Self> {
        n.to_f64().map(Self::constant)
    }
}

macro_rules! constants {
    ($($f:ident),*) => {$(
        fn $f() -> Self {
            Self::constant(f64::$f())
        }
    )*};
}

impl<const N: usize> FloatConst for DualN<N> {
    constants!(
        E,
        FRAC_1_PI,
        FRAC_1_SQRT_2,
        FRAC_2_PI,
        FRAC_2_SQRT_PI,
        FRAC_PI_2,
        FRAC_PI_3,
        FRAC_PI_4,
        FRAC_PI_6,
        FRAC_PI_8,
        LN_10,
        LN_2,
        LOG10_E,
        LOG2_E,
        PI,
        SQRT_2,
        TAU,
        LOG10_2,
        LOG2_10
    );
}

/// Functions of one argument, by their `num-dual` rule.
macro_rules! unary {
    ($($f:ident),*) => {$(
        #[inline(always)]
        fn $f(self) -> Self {
            self.chain(|d| d.$f())
        }
    )*};
}

/// Functions whose derivative is 0 (piecewise constant).
macro_rules! flat {
    ($($f:ident),*) => {$(
        fn $f(self) -> Self {
            Self::constant(self.re.$f())
        }
    )*};
}

impl<const N: usize> NumFloat for DualN<N> {
    constants!(
        nan,
        infinity,
        neg_infinity,
        neg_zero,
        min_value,
        min_positive_value,
        max_value,
        epsilon
    );
    unary!(
        sqrt, cbrt, exp, exp2, exp_m1, ln, ln_1p, log2, log10, sin, cos, tan, asin, acos, atan,
        sinh, cosh, tanh, asinh, acosh, atanh, recip
    );
    flat!(floor, ceil, round, trunc, signum);

    fn is_nan(self) -> bool {
        self.re.is_nan()
    }
    fn is_infinite(self) -> bool {
        self.re.is_infinite()
    }
    fn is_finite(self) -> bool {
        self.re.is_finite()
    }
    fn is_normal(self) -> bool {
        self.re.is_normal()
    }
    fn classify(self) -> core::num::FpCategory {
        self.re.classify()
    }
    fn fract(self) -> Self {
        Self {
            re: self.re.fract(),
            eps: self.eps,
        }
    }
    fn abs(self) -> Self {
        if self.re < 0.0 {
            -self
        } else {
            self
        }
    }
    fn is_sign_positive(self) -> bool {
        self.re.is_sign_positive()
    }
    fn is_sign_negative(self) -> bool {
        self.re.is_sign_negative()
    }
    fn mul_add(self, a: Self, b: Self) -> Self {
        let re = self.re.mul_add(a.re, b.re);
        let mut d = self.combine(a.re, a, self.re, re);
        for (e, x) in d.eps.iter_mut().zip(b.eps) {
            *e += x;
        }
        d
    }
    fn powi(self, n: i32) -> Self {
        self.chain(|d| d.powi(n))
    }
    /// `x^n`: `∂ = n x^{n−1} x' + x^n ln(x) n'`; the second term is 0 where
    /// `x^n = 0` (its limit for `n > 0`) or `n` carries no derivative.
    fn powf(self, n: Self) -> Self {
        let v = self.re.powf(n.re);
        let dx = if self.re == 0.0 {
            if n.re > 1.0 {
                0.0
            } else {
                n.re * self.re.powf(n.re - 1.0)
            }
        } else {
            // x^{n−1} = x^n / x: one `pow` instead of two
            n.re * v / self.re
        };
        let dn = if v == 0.0 || !n.has_derivatives() {
            0.0
        } else {
            v * self.re.ln()
        };
        self.combine(dx, n, dn, v)
    }
    fn log(self, base: Self) -> Self {
        self.ln() / base.ln()
    }
    fn max(self, o: Self) -> Self {
        if o.re > self.re || self.re.is_nan() {
            o
        } else {
            self
        }
    }
    fn min(self, o: Self) -> Self {
        if o.re < self.re || self.re.is_nan() {
            o
        } else {
            self
        }
    }
    fn abs_sub(self, o: Self) -> Self {
        if self.re <= o.re {
            Self::constant(0.0)
        } else {
            self - o
        }
    }
    fn hypot(self, o: Self) -> Self {
        let h = self.re.hypot(o.re);
        if h == 0.0 {
            return Self::constant(0.0);
        }
        self.combine(self.re / h, o, o.re / h, h)
    }
    fn atan2(self, x: Self) -> Self {
        let d = self.re * self.re + x.re * x.re;
        let re = self.re.atan2(x.re);
        if d == 0.0 {
            return Self::constant(re);
        }
        self.combine(x.re / d, x, -self.re / d, re)
    }
    fn sin_cos(self) -> (Self, Self) {
        (self.sin(), self.cos())
    }
    fn integer_decode(self) -> (u64, i16, i8) {
        self.re.integer_decode()
    }
}

impl<const N: usize> serde::Serialize for DualN<N> {
    /// The value, as a number (a spec holds values, not derivatives).
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_f64(self.re)
    }
}

impl<'de, const N: usize> serde::Deserialize<'de> for DualN<N> {
    /// A number, as a constant.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        f64::deserialize(d).map(Self::constant)
    }
}

/// What a scalar says about the derivatives it carries: nothing for `f32`
/// and `f64`, the dual parts for [`DualN`]. Part of [`Float`](crate::Float).
///
/// Operators use it to take the path that differentiates well where a fast
/// path would differentiate an approximation (the Bouc-Wen spring reads
/// the derivatives of its flow from a table of their own, never
/// differentiating its flow table's interpolant), and implicit solvers to
/// set the derivatives of their root.
pub trait Differentiable: Copy {
    /// Whether values of this type carry derivatives.
    const CARRIES_DERIVATIVES: bool = false;

    /// Whether this value has a nonzero derivative.
    fn has_derivatives(&self) -> bool {
        false
    }

    /// This value with its derivatives set to 0.
    fn without_derivatives(self) -> Self {
        self
    }

    /// `c · self` for a constant `c` (value and derivatives scaled): the
    /// product with `c` as a value without derivatives, in fewer operations
    /// where derivatives are carried.
    fn mul_const(self, c: f64) -> Self;

    /// Whether the probe slot is zero: the last derivative slot, which an
    /// implicit combinator may borrow at its root for the derivative with
    /// respect to the root itself (see [`probe`](Self::probe)). `true` for
    /// a scalar without derivatives.
    fn probe_free(&self) -> bool {
        true
    }

    /// This value without derivatives but a 1 in the probe slot: `x + ε_N`
    /// for `x` the value (over a scalar without derivatives, `self`).
    fn probe(self) -> Self {
        self
    }

    /// Folds the probe slot into the others: with `d = ∂self/∂x` in the
    /// probe slot and `∂x/∂p_i` in `along`'s slots (the chain rule
    /// `∂self/∂p_i += ∂self/∂x · ∂x/∂p_i`), then clears the probe slot.
    /// A scalar without derivatives is left as it is.
    fn fold_probe(&mut self, along: &Self) {
        let _ = along;
    }
}

impl Differentiable for f64 {
    #[inline(always)]
    fn mul_const(self, c: f64) -> Self {
        c * self
    }
}

impl Differentiable for f32 {
    /// (`c` rounded to `f32` first, as `f32::lit(c) * self`.)
    #[inline(always)]
    #[allow(clippy::cast_possible_truncation)]
    fn mul_const(self, c: f64) -> Self {
        (c as f32) * self
    }
}

impl<const N: usize> Differentiable for DualN<N> {
    const CARRIES_DERIVATIVES: bool = true;

    fn has_derivatives(&self) -> bool {
        self.eps.iter().any(|&e| e != 0.0)
    }

    fn without_derivatives(self) -> Self {
        Self::constant(self.re)
    }

    #[inline(always)]
    fn mul_const(self, c: f64) -> Self {
        Self {
            re: c * self.re,
            eps: self.eps.map(|e| c * e),
        }
    }

    #[inline(always)]
    fn probe_free(&self) -> bool {
        self.eps.last().is_none_or(|&e| e == 0.0)
    }

    #[inline(always)]
    fn probe(self) -> Self {
        Self::variable(self.re, N.wrapping_sub(1))
    }

    #[inline(always)]
    fn fold_probe(&mut self, along: &Self) {
        if let Some(&d) = self.eps.last() {
            if d != 0.0 {
                // (a slot `along` leaves at zero stays as it is, even where
                // `d` is infinite: see "Behaviour at kinks" above)
                for (e, &a) in self.eps.iter_mut().zip(&along.eps) {
                    if a != 0.0 {
                        *e += d * a;
                    }
                }
            }
            if let Some(last) = self.eps.last_mut() {
                *last = 0.0;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Folding applies the chain rule through the probe slot, clears it,
    /// and leaves a slot whose derivative in `along` is zero as it is, even
    /// where the probe's derivative is infinite.
    #[test]
    fn fold_probe_is_the_chain_rule_through_the_last_slot() {
        let mut v = DualN::<3> {
            re: 2.0,
            eps: [1.0, 5.0, 3.0],
        };
        let along = DualN::<3> {
            re: 7.0,
            eps: [0.5, 0.0, 0.0],
        };
        v.fold_probe(&along);
        assert_eq!((v.re, v.eps), (2.0, [2.5, 5.0, 0.0]));
        let mut w = DualN::<3> {
            re: 2.0,
            eps: [1.0, 5.0, f64::INFINITY],
        };
        w.fold_probe(&along);
        assert_eq!(w.eps, [f64::INFINITY, 5.0, 0.0]);
        assert!(DualN::<3>::constant(1.0).probe().eps == [0.0, 0.0, 1.0]);
        assert!(!DualN::<3>::constant(1.0).probe().probe_free());
        assert!(v.probe_free());
    }

    type D = DualN<2>;

    /// `mul_const(c)` is the product with `c` as a constant, bit for bit, for
    /// nonzero finite parts (signed zeros aside, where the product adds
    /// `0 · re`), on each scalar.
    #[test]
    fn mul_const_is_the_product_with_a_constant() {
        let mut x = D::variable(-1.75, 0);
        x.eps[1] = 3.0e-7;
        for c in [2.5, -0.3, 1e-300, 7.0] {
            let (a, b) = (x.mul_const(c), D::constant(c) * x);
            assert_eq!(a.re.to_bits(), b.re.to_bits(), "{c}");
            for (p, q) in a.eps.iter().zip(b.eps) {
                assert_eq!(p.to_bits(), q.to_bits(), "{c}");
            }
            assert_eq!((-1.75f64).mul_const(c), c * -1.75);
            assert_eq!((-1.75f32).mul_const(c), (c as f32) * -1.75);
        }
    }

    /// `f` at `x` seeded in slot 0 against a central difference of its value.
    fn check(name: &str, f: impl Fn(D) -> D, x: f64) {
        let d = f(D::variable(x, 0));
        let h = 1e-6 * x.abs().max(1.0);
        let fd = (f(D::constant(x + h)).re - f(D::constant(x - h)).re) / (2.0 * h);
        assert!(
            (d.eps[0] - fd).abs() <= 1e-6 * fd.abs().max(1.0),
            "{name} at {x}: {} vs {fd}",
            d.eps[0]
        );
        assert_eq!(d.eps[1], 0.0, "{name}: an unseeded slot moved");
    }

    #[test]
    fn every_function_follows_its_derivative() {
        let c = D::constant;
        type Case<'a> = (&'a str, &'a dyn Fn(D) -> D, f64);
        let cases: &[Case] = &[
            ("sqrt", &|x| x.sqrt(), 0.7),
            ("cbrt", &|x| x.cbrt(), 0.7),
            ("exp", &|x| x.exp(), 0.7),
            ("exp2", &|x| x.exp2(), 0.7),
            ("exp_m1", &|x| x.exp_m1(), -0.3),
            ("ln", &|x| x.ln(), 0.7),
            ("ln_1p", &|x| x.ln_1p(), 0.7),
            ("log2", &|x| x.log2(), 0.7),
            ("log10", &|x| x.log10(), 0.7),
            ("log", &|x| x.log(c(3.0)), 0.7),
            ("sin", &|x| x.sin(), 0.7),
            ("cos", &|x| x.cos(), 0.7),
            ("tan", &|x| x.tan(), 0.7),
            ("asin", &|x| x.asin(), 0.3),
            ("acos", &|x| x.acos(), 0.3),
            ("atan", &|x| x.atan(), 0.7),
            ("sinh", &|x| x.sinh(), 0.7),
            ("cosh", &|x| x.cosh(), 0.7),
            ("tanh", &|x| x.tanh(), 0.7),
            ("asinh", &|x| x.asinh(), 0.7),
            ("acosh", &|x| x.acosh(), 1.7),
            ("atanh", &|x| x.atanh(), 0.3),
            ("recip", &|x| x.recip(), 0.7),
            ("powi", &|x| x.powi(3), 0.7),
            ("powf base", &|x| x.powf(c(1.5)), 0.7),
            ("powf exponent", &|x| c(0.7).powf(x), 1.5),
            ("powf both", &|x| x.powf(x), 0.7),
            ("abs negative", &|x| x.abs(), -0.7),
            ("mul_add", &|x| x.mul_add(x, c(2.0)), 0.7),
            ("hypot", &|x| x.hypot(c(2.0)), 0.7),
            ("atan2", &|x| x.atan2(c(2.0)), 0.7),
            ("atan2 x", &|x| c(2.0).atan2(x), 0.7),
            ("div", &|x| c(2.0) / x, 0.7),
            ("rem", &|x| x % c(0.5), 1.7),
            ("max", &|x| x.max(c(0.0)), 0.7),
            ("min", &|x| x.min(c(0.0)), -0.7),
            ("fract", &|x| x.fract(), 1.7),
        ];
        for (name, f, x) in cases {
            check(name, f, *x);
        }
    }

    #[test]
    fn slots_are_independent_and_products_follow_the_product_rule() {
        let (a, b) = (D::variable(2.0, 0), D::variable(3.0, 1));
        let y = a * b + a / b;
        assert_eq!(y.re, 6.0 + 2.0 / 3.0);
        assert!((y.eps[0] - (3.0 + 1.0 / 3.0)).abs() < 1e-15);
        assert!((y.eps[1] - (2.0 - 2.0 / 9.0)).abs() < 1e-15);
    }

    #[test]
    fn a_constant_stays_constant_where_the_slope_is_infinite() {
        let y = D::constant(0.0).sqrt() + D::constant(0.0).powf(D::constant(0.5));
        assert_eq!(y.eps, [0.0, 0.0]);
        // while a seeded slot there is infinite, and says so
        assert!(!D::variable(0.0, 0).sqrt().derivatives_finite());
    }

    #[test]
    fn the_exponent_term_of_a_zero_power_is_its_limit() {
        // 0^n = 0 for every n > 0: ∂/∂n = 0, not 0 · ln 0 = NaN
        let y = D::constant(0.0).powf(D::variable(1.5, 0));
        assert_eq!((y.re, y.eps[0]), (0.0, 0.0));
    }

    #[test]
    fn comparisons_and_kinks_follow_the_value() {
        let a = D::variable(1.0, 0);
        let b = D::variable(1.0, 1);
        assert!(a == b && a <= b && a.partial_cmp(&b) == Some(core::cmp::Ordering::Equal));
        // max of equal values keeps the first; signum is flat
        assert_eq!(a.max(b).eps, [1.0, 0.0]);
        assert_eq!(a.signum().eps, [0.0, 0.0]);
        assert!(D::CARRIES_DERIVATIVES && a.has_derivatives());
        assert!(!1.0_f64.has_derivatives() && !1.0_f32.has_derivatives());
        assert!(!a.without_derivatives().has_derivatives());
    }
}
