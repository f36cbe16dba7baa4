//! The Prandtl-Ishlinskii operator: a weighted bank of plays.

use hysteron_operators::{
    check_input, check_lengths, check_output, declare_params, play_step, play_tangent, Error,
    Float, Operator, Result, Trial,
};

declare_params! {
    /// Parameters of a [`PiBank`].
    pub struct PiBankParams<T> {
        /// Weight of the linear term `a0 · x`.
        a0: T => Real = 0.5,
        /// Thresholds `r_j ≥ 0`.
        r: Vec<T> => NonNegative = [0.0, 0.3, 1.0],
        /// Weights `w_j` (finite, any sign).
        w: Vec<T> => Real = [1.0, 0.5, 0.25],
        /// Initial play outputs at `x = 0` (default all 0).
        #[serde(default)]
        y0: Vec<T> => Real = [0.0, 0.1, -0.2],
    }
    check = PiBankParams::shape;
}

impl<T: Float> PiBankParams<T> {
    /// `r`, `w` (and `y0` if given) of one length; an empty `y0` means
    /// all zero.
    fn shape(&self) -> Result<()> {
        if self.w.len() != self.r.len() || !(self.y0.is_empty() || self.y0.len() == self.r.len()) {
            return Err(Error::InvalidParameter {
                name: "w".into(),
                value: self.w.len() as f64,
                reason: "r, w (and y0 if given) must have the same length",
            });
        }
        Ok(())
    }
}

/// Prandtl-Ishlinskii operator (play type):
///
/// `y = a0 · x + Σ_j w_j · play_{r_j}[x]`.
///
/// The plays are stored as structure-of-arrays (thresholds, weights,
/// states), so the per-sample loop over the bank vectorizes. Wiping-out and
/// exact rate independence follow from the play's. Parameters:
/// `[a0, r_0..r_m, w_0..w_m, y0_0..y0_m]`.
///
/// ```
/// use hysteron_composition::PiBank;
/// use hysteron_operators::Operator;
/// let mut pi = PiBank::new(0.5_f64, vec![0.0, 1.0], vec![1.0, 2.0]).unwrap();
/// // x = 2: 0.5·2 + 1·2 + 2·(2 − 1) = 5
/// assert_eq!(pi.run(&[2.0]).unwrap(), vec![5.0]);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PiBank<T> {
    /// The parameters, `y0` written out in full.
    p: PiBankParams<T>,
    y: Vec<T>,
    pending: Vec<T>,
    has_pending: bool,
}

impl<T: Float> PiBank<T> {
    /// A bank with linear weight `a0`, thresholds `r` and weights `w`,
    /// all plays starting at 0.
    pub fn new(a0: T, r: Vec<T>, w: Vec<T>) -> Result<Self> {
        Self::from_params(PiBankParams {
            a0,
            r,
            w,
            y0: Vec::new(),
        })
    }

    /// A bank from validated parameters.
    pub fn from_params(p: PiBankParams<T>) -> Result<Self> {
        p.validate()?;
        let m = p.r.len();
        let y0 = if p.y0.is_empty() {
            vec![T::zero(); m]
        } else {
            p.y0
        };
        Ok(Self {
            y: y0.clone(),
            p: PiBankParams { y0, ..p },
            pending: vec![T::zero(); m],
            has_pending: false,
        })
    }

    /// The parameters.
    pub fn parameters(&self) -> &PiBankParams<T> {
        &self.p
    }

    /// Number of plays.
    pub fn len(&self) -> usize {
        self.p.r.len()
    }

    /// True for a bank without plays (a pure linear term).
    pub fn is_empty(&self) -> bool {
        self.p.r.is_empty()
    }

    /// The committed play outputs.
    pub fn play_outputs(&self) -> &[T] {
        &self.y
    }
}

/// Independent partial sums in the bank loop: breaks the serial dependency
/// of one running sum so the loop over plays vectorizes.
pub(crate) const LANES: usize = 8;

/// Advances every play from `prev` to `next` for input `x` and returns
/// `Σ w_j next_j`, summed in `LANES` interleaved partial sums, each term
/// added by a fused multiply-add (a fixed order and one rounding per play,
/// so `trial` and `process` agree bit for bit, and the vector kernels do
/// the same; where the CPU has no FMA, `mul_add` is the C library's exact
/// `fma`, slower but the same bits).
// Hot loop, kept free of checks: `n` is the least of the four lengths and
// `m ≤ n`, so every `[..n]`, `[..m]`, `[m..]` is in range, and `l < LANES`
// indexes the `[T; LANES]` arrays.
#[allow(clippy::indexing_slicing)]
#[inline(always)]
fn bank_step<T: Float>(r: &[T], w: &[T], prev: &[T], next: &mut [T], x: T) -> T {
    let n = r.len().min(w.len()).min(prev.len()).min(next.len());
    let (r, w, prev, next) = (&r[..n], &w[..n], &prev[..n], &mut next[..n]);
    let m = n / LANES * LANES;
    let mut acc = [T::zero(); LANES];
    for (((r, w), prev), next) in r[..m]
        .chunks_exact(LANES)
        .zip(w[..m].chunks_exact(LANES))
        .zip(prev[..m].chunks_exact(LANES))
        .zip(next[..m].chunks_exact_mut(LANES))
    {
        // Each chunk as arrays: independent lanes the compiler maps onto
        // vector registers.
        let r: [T; LANES] = r.try_into().unwrap_or([T::zero(); LANES]);
        let w: [T; LANES] = w.try_into().unwrap_or([T::zero(); LANES]);
        let prev: [T; LANES] = prev.try_into().unwrap_or([T::zero(); LANES]);
        let y: [T; LANES] = core::array::from_fn(|l| play_step(r[l], prev[l], x));
        acc = core::array::from_fn(|l| w[l].mul_add(y[l], acc[l]));
        next.copy_from_slice(&y);
    }
    let mut tail = T::zero();
    for (((&r, &w), &prev), next) in r[m..]
        .iter()
        .zip(&w[m..])
        .zip(&prev[m..])
        .zip(&mut next[m..])
    {
        *next = play_step(r, prev, x);
        tail = w.mul_add(*next, tail);
    }
    ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7])) + tail
}

/// [`bank_step`] over `f64` compiled for AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn bank_step_fma(r: &[f64], w: &[f64], prev: &[f64], next: &mut [f64], x: f64) -> f64 {
    bank_step(r, w, prev, next, x)
}

impl<T: Float> PiBank<T> {
    /// This bank as a bank of `f64` (for the vectorized batch loop).
    #[cfg(target_arch = "x86_64")]
    fn as_f64_mut(&mut self) -> Option<&mut PiBank<f64>> {
        (self as &mut dyn core::any::Any).downcast_mut::<PiBank<f64>>()
    }

    /// [`bank_step`] from the committed plays into `pending`; over `f64`
    /// on a CPU with AVX2 and FMA compiled for them (the portable code
    /// would call the C library's `fma` once per play).
    fn bank_step(&mut self, x: T) -> T {
        #[cfg(target_arch = "x86_64")]
        if let (Some(_), Some(r), Some(w), Some(prev), Some(next)) = (
            crate::pi_avx2::Isa::detect(),
            crate::pi_avx2::as_f64(&self.p.r),
            crate::pi_avx2::as_f64(&self.p.w),
            crate::pi_avx2::as_f64(&self.y),
            crate::pi_avx2::as_f64_mut(&mut self.pending),
        ) {
            // SAFETY: AVX2 and FMA were detected on this CPU (`Isa`).
            return T::lit(unsafe { bank_step_fma(r, w, prev, next, x.as_f64()) });
        }
        bank_step(&self.p.r, &self.p.w, &self.y, &mut self.pending, x)
    }

    /// The portable batch loop (lengths checked by the caller).
    fn process_loop(&mut self, xs: &[T], ys: &mut [T]) -> Result<()> {
        for (i, (&x, out)) in xs.iter().zip(ys.iter_mut()).enumerate() {
            if !x.is_finite() {
                return Err(Error::NonFiniteInput { value: x.as_f64() }.at_sample(i));
            }
            let y = self.p.a0 * x + bank_step(&self.p.r, &self.p.w, &self.y, &mut self.pending, x);
            if !y.is_finite() {
                return Err(Error::NonFiniteOutput {
                    operator: "pi_bank",
                    input: x.as_f64(),
                }
                .at_sample(i));
            }
            std::mem::swap(&mut self.y, &mut self.pending);
            *out = y;
        }
        Ok(())
    }
}

impl<T: Float> Operator<T> for PiBank<T> {
    fn trial(&mut self, x: T) -> Result<Trial<T>> {
        self.has_pending = false;
        let x = check_input(x)?;
        let output = self.p.a0 * x + self.bank_step(x);
        let mut tangent = self.p.a0;
        for ((&r, &w), &y) in self.p.r.iter().zip(&self.p.w).zip(&self.y) {
            tangent = tangent + w * play_tangent(r, y, x);
        }
        let t = check_output("pi_bank", x, Trial { output, tangent })?;
        self.has_pending = true;
        Ok(t)
    }

    fn commit(&mut self) {
        if self.has_pending {
            std::mem::swap(&mut self.y, &mut self.pending);
            self.has_pending = false;
        }
    }

    fn reset(&mut self) {
        self.y.copy_from_slice(&self.p.y0);
        self.has_pending = false;
    }

    fn process(&mut self, xs: &[T], ys: &mut [T]) -> Result<()> {
        check_lengths(xs, ys)?;
        self.has_pending = false;
        #[cfg(target_arch = "x86_64")]
        if let (Some(isa), Some(xs), Some(ys), Some(bank)) = (
            crate::pi_avx2::Isa::detect(),
            crate::pi_avx2::as_f64(xs),
            crate::pi_avx2::as_f64_mut(ys),
            self.as_f64_mut(),
        ) {
            let mut b = crate::pi_avx2::Bank {
                a0: bank.p.a0,
                r: &bank.p.r,
                w: &bank.p.w,
                y: &mut bank.y,
                pending: &mut bank.pending,
            };
            let (applied, error) = crate::pi_avx2::process(isa, &mut b, xs, ys);
            if applied % 2 == 1 {
                std::mem::swap(&mut bank.y, &mut bank.pending);
            }
            return match error {
                Some(e) => Err(e.at_sample(applied)),
                None => Ok(()),
            };
        }
        self.process_loop(xs, ys)
    }

    fn name(&self) -> &'static str {
        <Self as hysteron_operators::Leaf<T>>::KIND
    }
}

/// The traits of a rate-independent leaf `$op<T>` with no fast paths (the
/// PI bank and its inverse): [`Leaf`](hysteron_operators::Leaf) by
/// `impl_leaf!($op, …)` with the arguments given, the parameters and the
/// dual twin by `leaf_traits!`, the default
/// [`Hints`](hysteron_operators::Hints) (no fast paths beyond the batch
/// loop of `process`) and the default
/// [`SamplePeriod`](hysteron_operators::SamplePeriod) (rate-independent: the
/// period is only checked).
macro_rules! rate_independent_leaf {
    ($op:ident, $($leaf:tt)*) => {
        hysteron_operators::leaf_traits!($op);

        impl<T: Float> hysteron_operators::Hints<T> for $op<T> {}

        impl<T: Float> hysteron_operators::SamplePeriod<T> for $op<T> {}

        hysteron_operators::impl_leaf!($op, $($leaf)*);
    };
}
pub(crate) use rate_independent_leaf;

rate_independent_leaf!(
    PiBank,
    PiBankParams,
    "pi_bank",
    p,
    equation: "y = a0 x + Σ_j w_j play_{r_j}[x] (Prandtl-Ishlinskii)"
);
