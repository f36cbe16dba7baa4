//! The Prandtl-Ishlinskii batch loop for `f64` on AVX2 and AVX-512: the
//! same operations as the portable loop in [`pi_bank`](crate::pi_bank), in
//! the same order, four or eight plays per instruction, so the results are
//! bit-identical.
//!
//! Per play `y_j = max(min(y_j, x + r_j), x − r_j)` (`vminpd`/`vmaxpd`
//! return their second operand when the comparison is false, exactly the
//! compare-and-select of [`play_step`](hysteron_operators::play_step)), and
//! `Σ w_j y_j` in eight interleaved partial sums (lane `l` sums the plays
//! `j ≡ l mod 8`), each term added by a fused multiply-add (`vfmadd`, as
//! `f64::mul_add` in the portable loop: one rounding per play).

#![cfg(target_arch = "x86_64")]

use core::arch::x86_64::*;
pub(crate) use hysteron_operators::simd::{as_f64, as_f64_mut, Isa};
use hysteron_operators::{play_step, Error};

/// The bank's slices, all of the same length.
pub(crate) struct Bank<'a> {
    pub a0: f64,
    pub r: &'a [f64],
    pub w: &'a [f64],
    /// The committed play outputs.
    pub y: &'a mut [f64],
    /// Scratch of the same length: each sample reads the play outputs from
    /// one of `y`, `pending` and writes them to the other.
    pub pending: &'a mut [f64],
}

impl Bank<'_> {
    /// The plays every slice has: the least of the four lengths.
    fn plays(&self) -> usize {
        self.r
            .len()
            .min(self.w.len())
            .min(self.y.len())
            .min(self.pending.len())
    }
}

/// Runs `xs` through the bank into `ys` (same lengths). Returns the
/// number of samples applied and the error that stopped it, if any (a
/// non-finite input or output at that sample, which is not applied). The
/// play outputs after the applied samples are in `bank.y` if that number
/// is even, else in `bank.pending`.
pub(crate) fn process(
    isa: Isa,
    bank: &mut Bank<'_>,
    xs: &[f64],
    ys: &mut [f64],
) -> (usize, Option<Error>) {
    // SAFETY: `isa` was detected on this CPU; `resident` checks the
    // lengths its kernel needs.
    unsafe {
        match isa {
            Isa::Avx2 => process_avx2(bank, xs, ys),
            Isa::Avx512 => match resident_chunks(bank) {
                Some(1) => resident512::<1>(bank, xs, ys),
                Some(2) => resident512::<2>(bank, xs, ys),
                Some(3) => resident512::<3>(bank, xs, ys),
                Some(4) => resident512::<4>(bank, xs, ys),
                Some(5) => resident512::<5>(bank, xs, ys),
                Some(6) => resident512::<6>(bank, xs, ys),
                Some(7) => resident512::<7>(bank, xs, ys),
                Some(8) => resident512::<8>(bank, xs, ys),
                _ => process_avx512(bank, xs, ys),
            },
        }
    }
}

/// `Some(C)` if the bank is `8·C` plays, `1 ≤ C ≤ 8`, with every slice of
/// that length: then its plays, thresholds and weights fit in `3C ≤ 24` of
/// AVX-512's 32 registers for a whole batch.
fn resident_chunks(bank: &Bank<'_>) -> Option<usize> {
    let n = bank.r.len();
    let same = [bank.w.len(), bank.y.len(), bank.pending.len()]
        .iter()
        .all(|&l| l == n);
    (same && n.is_multiple_of(8) && (8..=64).contains(&n)).then_some(n / 8)
}

/// The AVX-512 batch loop for a bank of exactly `8·C` plays with the plays
/// kept in registers from sample to sample (no store and reload of each
/// play per sample): the same operations in the same order as
/// [`process_avx512`], so the same bits.
///
/// Samples go in blocks of eight: the plays are updated in place, the
/// eight samples' partial sums are reduced together ([`totals8`], one lane
/// per sample) and the eight outputs are checked and stored at once. A
/// non-finite input always gives a non-finite output (`x ± r_j` and then
/// every play is NaN or infinite, and so is `a0 x + Σ`, `a0 x` included),
/// so a block whose outputs are all finite had finite inputs too. A block
/// with a non-finite output stores nothing and is run again one sample at
/// a time from the plays before it, which stops at its first bad sample.
///
/// At the end the plays go to the buffer the caller expects (`y` after an
/// even number of applied samples, `pending` after an odd one).
#[target_feature(enable = "avx512f,fma")]
unsafe fn resident512<const C: usize>(
    bank: &mut Bank<'_>,
    xs: &[f64],
    ys: &mut [f64],
) -> (usize, Option<Error>) {
    let load = |s: &[f64], c: usize| -> __m512d {
        // SAFETY: every slice of the bank holds 8·C values (`resident_chunks`)
        // and c < C.
        unsafe { _mm512_loadu_pd(s.as_ptr().add(8 * c)) }
    };
    let r: [__m512d; C] = core::array::from_fn(|c| load(bank.r, c));
    let w: [__m512d; C] = core::array::from_fn(|c| load(bank.w, c));
    let mut y: [__m512d; C] = core::array::from_fn(|c| load(bank.y, c));
    // one sample: the plays in place, and the eight partial sums
    let step = |y: &mut [__m512d; C], x: f64| -> __m512d {
        let xv = _mm512_set1_pd(x);
        let mut sum = _mm512_setzero_pd();
        for ((yc, &rc), &wc) in y.iter_mut().zip(&r).zip(&w) {
            *yc = _mm512_max_pd(
                _mm512_min_pd(*yc, _mm512_add_pd(xv, rc)),
                _mm512_sub_pd(xv, rc),
            );
            sum = _mm512_fmadd_pd(wc, *yc, sum);
        }
        sum
    };
    let a0 = _mm512_set1_pd(bank.a0);
    let mut applied = 0;
    for (xb, yb) in xs.chunks_exact(8).zip(ys.chunks_exact_mut(8)) {
        let before = y;
        let sums: [__m512d; 8] =
            core::array::from_fn(|k| step(&mut y, xb.get(k).copied().unwrap_or(0.0)));
        // SAFETY: `xb` and `yb` hold 8 values.
        let xv = unsafe { _mm512_loadu_pd(xb.as_ptr()) };
        // `a0 x + (Σ + 0)`, as `output(a0, x, total(&acc, 0.0))`
        let out = _mm512_add_pd(
            _mm512_mul_pd(a0, xv),
            _mm512_add_pd(totals8(sums), _mm512_setzero_pd()),
        );
        if !all_finite(out) {
            y = before;
            break;
        }
        // SAFETY: as above.
        unsafe { _mm512_storeu_pd(yb.as_mut_ptr(), out) };
        applied += 8;
    }
    let mut error = None;
    for (&x, out) in xs.iter().zip(ys.iter_mut()).skip(applied) {
        if !x.is_finite() {
            error = Some(Error::NonFiniteInput { value: x });
            break;
        }
        let mut next = y;
        let sum = step(&mut next, x);
        let mut acc = [0.0; 8];
        // SAFETY: `acc` holds 8 values.
        unsafe { _mm512_storeu_pd(acc.as_mut_ptr(), sum) };
        match output(bank.a0, x, total(&acc, 0.0)) {
            Ok(v) => *out = v,
            Err(e) => {
                error = Some(e);
                break;
            }
        }
        y = next;
        applied += 1;
    }
    let dest: &mut [f64] = if applied % 2 == 0 {
        bank.y
    } else {
        bank.pending
    };
    for (c, yc) in y.iter().enumerate() {
        // SAFETY: `dest` holds 8·C values and c < C.
        unsafe { _mm512_storeu_pd(dest.as_mut_ptr().add(8 * c), *yc) };
    }
    (applied, error)
}

/// The eight samples' totals, lane `k` of the result from `sums[k]`, each
/// summed in [`total`]'s order, `((s0 + s1) + (s2 + s3)) + ((s4 + s5) +
/// (s6 + s7))`: the pairs within each register, then the pairs of pairs,
/// then the halves, each level shuffling two registers into two and adding
/// them (an addition's operands commute exactly, so a pair may come in
/// either order).
#[target_feature(enable = "avx512f")]
#[inline]
fn totals8(s: [__m512d; 8]) -> __m512d {
    // lane 2i (2i + 1) of `pairs(a, b)` is a's (b's) pair i
    let pairs = |a, b| _mm512_add_pd(_mm512_unpacklo_pd(a, b), _mm512_unpackhi_pd(a, b));
    let [s0, s1, s2, s3, s4, s5, s6, s7] = s;
    let (p01, p23, p45, p67) = (pairs(s0, s1), pairs(s2, s3), pairs(s4, s5), pairs(s6, s7));
    // 128-bit blocks: `0x88` takes blocks 0 and 2 of each operand, `0xdd`
    // blocks 1 and 3. From p01 and p23: [s0, s1 low half | s0, s1 high
    // half | s2, s3 low | s2, s3 high].
    let halves = |a, b| {
        _mm512_add_pd(
            _mm512_shuffle_f64x2::<0x88>(a, b),
            _mm512_shuffle_f64x2::<0xdd>(a, b),
        )
    };
    let (h03, h47) = (halves(p01, p23), halves(p45, p67));
    // from h03 and h47: [s0..s3 low halves, s4..s7 low] + [the high halves]
    _mm512_add_pd(
        _mm512_shuffle_f64x2::<0x88>(h03, h47),
        _mm512_shuffle_f64x2::<0xdd>(h03, h47),
    )
}

/// `Σ` of the eight partial sums and the tail, in the portable loop's order.
#[inline(always)]
fn total(acc: &[f64; 8], tail: f64) -> f64 {
    ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7])) + tail
}

/// The scalar plays beyond the last full chunk of eight.
#[inline(always)]
fn tail(r: &[f64], w: &[f64], prev: &[f64], next: &mut [f64], x: f64) -> f64 {
    let mut sum = 0.0;
    for (((&r, &w), &p), y) in r.iter().zip(w).zip(prev).zip(next) {
        *y = play_step(r, p, x);
        sum = w.mul_add(*y, sum);
    }
    sum
}

/// The output `a0 x + Σ`, an error if not finite.
#[inline(always)]
fn output(a0: f64, x: f64, bank_sum: f64) -> Result<f64, Error> {
    let y = a0 * x + bank_sum;
    if y.is_finite() {
        Ok(y)
    } else {
        Err(Error::NonFiniteOutput {
            operator: "pi_bank",
            input: x,
        })
    }
}

/// The batch loop around a vector kernel: per sample it checks the input,
/// lets `chunks(x, r, w, prev, next)` update the plays of the full chunks
/// of eight (slices of a length that is a multiple of 8) and return the
/// eight partial sums, adds the scalar tail, checks the output and swaps
/// the two play buffers.
// Hot loop, kept free of checks: `n` is the least of the four lengths and
// `m = n / 8 * 8 ≤ n`, so `[..n]`, `[..m]` and `[m..]` are in range.
#[allow(clippy::indexing_slicing)]
#[inline(always)]
fn drive(
    bank: &mut Bank<'_>,
    xs: &[f64],
    ys: &mut [f64],
    mut chunks: impl FnMut(f64, &[f64], &[f64], &[f64], &mut [f64]) -> [f64; 8],
) -> (usize, Option<Error>) {
    let n = bank.plays();
    let m = n / 8 * 8;
    let (r, w) = (&bank.r[..n], &bank.w[..n]);
    let (mut prev, mut next) = (&mut bank.y[..n], &mut bank.pending[..n]);
    for (i, (&x, out)) in xs.iter().zip(ys.iter_mut()).enumerate() {
        if !x.is_finite() {
            return (i, Some(Error::NonFiniteInput { value: x }));
        }
        let acc = chunks(x, &r[..m], &w[..m], &prev[..m], &mut next[..m]);
        let t = tail(&r[m..], &w[m..], &prev[m..], &mut next[m..], x);
        match output(bank.a0, x, total(&acc, t)) {
            Ok(y) => *out = y,
            Err(e) => return (i, Some(e)),
        }
        core::mem::swap(&mut prev, &mut next);
    }
    (xs.len().min(ys.len()), None)
}

/// `|x|` up to which no output of the bank can overflow: every play
/// output lies in `[x − r_j, x + r_j]`, so `|a0 x + Σ w_j y_j| ≤ S |x| + R`
/// with `S = |a0| + Σ |w_j|`, `R = Σ |w_j| r_j`, kept below `1e300` (far
/// from `f64::MAX`, so rounding cannot cross it). Negative (no such `x`)
/// when `S` or `R` is not finite or `R` is already that large.
fn pair_limit(a0: f64, r: &[f64], w: &[f64]) -> f64 {
    let s = a0.abs() + w.iter().map(|w| w.abs()).sum::<f64>();
    let big: f64 = r.iter().zip(w).map(|(r, w)| w.abs() * r.abs()).sum();
    if !(s.is_finite() && big.is_finite()) {
        -1.0
    } else if s > 0.0 {
        (1e300 - big) / s
    } else {
        f64::MAX
    }
}

/// The scalar plays beyond the last full chunk of eight, two samples in a
/// row, updated in place; each sample's sum in [`tail`]'s order.
#[inline(always)]
fn tail_pair(r: &[f64], w: &[f64], y: &mut [f64], x0: f64, x1: f64) -> (f64, f64) {
    let (mut s0, mut s1) = (0.0, 0.0);
    for ((&r, &w), y) in r.iter().zip(w).zip(y) {
        let a = play_step(r, *y, x0);
        let b = play_step(r, a, x1);
        *y = b;
        s0 = w.mul_add(a, s0);
        s1 = w.mul_add(b, s1);
    }
    (s0, s1)
}

/// One sample on AVX2: the plays of the full chunks of eight from `prev`
/// to `next`, and the eight partial sums.
#[target_feature(enable = "avx2,fma")]
#[inline]
fn avx2_step(x: f64, r: &[f64], w: &[f64], prev: &[f64], next: &mut [f64]) -> [f64; 8] {
    let m = r.len().min(w.len()).min(prev.len()).min(next.len()) / 8 * 8;
    let mut acc = [0.0; 8];
    let xv = _mm256_set1_pd(x);
    let (mut acc0, mut acc1) = (_mm256_setzero_pd(), _mm256_setzero_pd());
    let mut j = 0;
    while j < m {
        // SAFETY: j + 8 ≤ m, the least length of the four slices.
        unsafe {
            let (rp, wp) = (r.as_ptr().add(j), w.as_ptr().add(j));
            let (yp, np) = (prev.as_ptr().add(j), next.as_mut_ptr().add(j));
            let (r0, r1) = (_mm256_loadu_pd(rp), _mm256_loadu_pd(rp.add(4)));
            let (p0, p1) = (_mm256_loadu_pd(yp), _mm256_loadu_pd(yp.add(4)));
            let y0 = clamp4(p0, xv, r0);
            let y1 = clamp4(p1, xv, r1);
            _mm256_storeu_pd(np, y0);
            _mm256_storeu_pd(np.add(4), y1);
            acc0 = _mm256_fmadd_pd(_mm256_loadu_pd(wp), y0, acc0);
            acc1 = _mm256_fmadd_pd(_mm256_loadu_pd(wp.add(4)), y1, acc1);
        }
        j += 8;
    }
    // SAFETY: `acc` holds 8 values.
    unsafe {
        _mm256_storeu_pd(acc.as_mut_ptr(), acc0);
        _mm256_storeu_pd(acc.as_mut_ptr().add(4), acc1);
    }
    acc
}

/// Four plays `max(min(p, x + r), x − r)`.
#[target_feature(enable = "avx2,fma")]
#[inline]
fn clamp4(p: __m256d, xv: __m256d, r: __m256d) -> __m256d {
    _mm256_max_pd(_mm256_min_pd(p, _mm256_add_pd(xv, r)), _mm256_sub_pd(xv, r))
}

/// Two samples on AVX2 in one pass over the plays: each chunk of eight is
/// loaded once, stepped by `x0` then `x1` in registers and stored once, in
/// place; the two samples' sums over the full chunks, each in
/// [`avx2_step`]'s lanes and [`total`]'s order (lane 0 for `x0`, lane 1
/// for `x1`; [`pair_totals`]).
#[target_feature(enable = "avx2,fma")]
#[inline]
fn avx2_pair(x0: f64, x1: f64, r: &[f64], w: &[f64], y: &mut [f64]) -> __m128d {
    let m = r.len().min(w.len()).min(y.len()) / 8 * 8;
    let (xa, xb) = (_mm256_set1_pd(x0), _mm256_set1_pd(x1));
    let (mut a0, mut a1) = (_mm256_setzero_pd(), _mm256_setzero_pd());
    let (mut b0, mut b1) = (_mm256_setzero_pd(), _mm256_setzero_pd());
    let mut j = 0;
    while j < m {
        // SAFETY: j + 8 ≤ m, the least length of the three slices.
        unsafe {
            let (rp, wp, yp) = (r.as_ptr().add(j), w.as_ptr().add(j), y.as_mut_ptr().add(j));
            let (r0, r1) = (_mm256_loadu_pd(rp), _mm256_loadu_pd(rp.add(4)));
            let (w0, w1) = (_mm256_loadu_pd(wp), _mm256_loadu_pd(wp.add(4)));
            let (p0, p1) = (_mm256_loadu_pd(yp), _mm256_loadu_pd(yp.add(4)));
            let (u0, u1) = (clamp4(p0, xa, r0), clamp4(p1, xa, r1));
            let (v0, v1) = (clamp4(u0, xb, r0), clamp4(u1, xb, r1));
            _mm256_storeu_pd(yp, v0);
            _mm256_storeu_pd(yp.add(4), v1);
            a0 = _mm256_fmadd_pd(w0, u0, a0);
            a1 = _mm256_fmadd_pd(w1, u1, a1);
            b0 = _mm256_fmadd_pd(w0, v0, b0);
            b1 = _mm256_fmadd_pd(w1, v1, b1);
        }
        j += 8;
    }
    pair_totals([a0, a1], [b0, b1])
}

/// Two samples' totals of their eight partial sums (lanes 0–3 of `a[0]`,
/// 4–7 of `a[1]`, and the same for `b`), lane 0 from `a` and lane 1 from
/// `b`, each summed in [`total`]'s order without its tail, `((s0 + s1) +
/// (s2 + s3)) + ((s4 + s5) + (s6 + s7))`: the pairs within each register,
/// then the pairs of pairs, then the halves, each level shuffling two
/// registers into two and adding them (an addition's operands commute
/// exactly, so a pair may come in either order).
#[target_feature(enable = "avx2")]
#[inline]
fn pair_totals(a: [__m256d; 2], b: [__m256d; 2]) -> __m128d {
    // [a01, b01, a23, b23] and [a45, b45, a67, b67]
    let pairs = |a, b| _mm256_add_pd(_mm256_unpacklo_pd(a, b), _mm256_unpackhi_pd(a, b));
    let (low, high) = (pairs(a[0], b[0]), pairs(a[1], b[1]));
    // [a0123, b0123, a4567, b4567]
    let halves = _mm256_add_pd(
        _mm256_permute2f128_pd::<0x20>(low, high),
        _mm256_permute2f128_pd::<0x31>(low, high),
    );
    _mm_add_pd(
        _mm256_castpd256_pd128(halves),
        _mm256_extractf128_pd::<1>(halves),
    )
}

/// Four plays per instruction, two registers per chunk of eight; two
/// samples per pass over the plays while no output can overflow
/// ([`pair_limit`]), else one (where a non-finite input or output stops
/// the batch at its sample, as in [`drive`]). Pairs update the plays in
/// place and do not swap the buffers, so the buffer holding the plays
/// still follows the parity of the samples applied.
// Hot loop, kept free of checks: `n` is the least of the four lengths,
// `m = n / 8 * 8 ≤ n`, and `i + 1 < len ≤ xs.len(), ys.len()` for a pair.
#[allow(clippy::indexing_slicing)]
#[target_feature(enable = "avx2,fma")]
unsafe fn process_avx2(bank: &mut Bank<'_>, xs: &[f64], ys: &mut [f64]) -> (usize, Option<Error>) {
    let n = bank.plays();
    let m = n / 8 * 8;
    let a0 = bank.a0;
    let (r, w) = (&bank.r[..n], &bank.w[..n]);
    let limit = pair_limit(a0, r, w);
    let (mut prev, mut next) = (&mut bank.y[..n], &mut bank.pending[..n]);
    let len = xs.len().min(ys.len());
    let mut i = 0;
    while i < len {
        let x0 = xs[i];
        if i + 1 < len && x0.abs() <= limit && xs[i + 1].abs() <= limit {
            let x1 = xs[i + 1];
            let sums = avx2_pair(x0, x1, &r[..m], &w[..m], &mut prev[..m]);
            let (t0, t1) = tail_pair(&r[m..], &w[m..], &mut prev[m..], x0, x1);
            // `a0 x + total(.., t)` for both samples at once
            let xv = _mm_set_pd(x1, x0);
            let out = _mm_add_pd(
                _mm_mul_pd(_mm_set1_pd(a0), xv),
                _mm_add_pd(sums, _mm_set_pd(t1, t0)),
            );
            // SAFETY: i + 1 < len ≤ ys.len().
            unsafe { _mm_storeu_pd(ys.as_mut_ptr().add(i), out) };
            i += 2;
            continue;
        }
        if !x0.is_finite() {
            return (i, Some(Error::NonFiniteInput { value: x0 }));
        }
        let acc = avx2_step(x0, &r[..m], &w[..m], &prev[..m], &mut next[..m]);
        let t = tail(&r[m..], &w[m..], &prev[m..], &mut next[m..], x0);
        match output(a0, x0, total(&acc, t)) {
            Ok(y) => ys[i] = y,
            Err(e) => return (i, Some(e)),
        }
        core::mem::swap(&mut prev, &mut next);
        i += 1;
    }
    (len, None)
}

/// Eight plays per instruction, for a bank of any length: samples in
/// blocks of eight, each chunk of eight plays loaded once per block,
/// stepped by the block's eight samples in turn in a register and stored
/// once, in place (so after a block the plays are in `y`, as the parity of
/// its eight samples asks); each sample's partial sums in a register of
/// its own, chunk after chunk as in [`drive`], and the scalar tail plays
/// stepped the same way ([`tail`]'s order for each sample). The eight
/// totals are reduced together ([`totals8`]) and the eight outputs checked
/// and stored at once, as in [`resident512`]: a block with a non-finite
/// output takes the plays back from their copy in `pending` and stores
/// nothing, and the samples from it on go one at a time ([`drive`]), which
/// stops at the first bad one. The same operations in the same order as
/// [`drive`] with [`process_avx512_step`], so the same bits.
// Hot loop, kept free of checks: `n` is the least of the four lengths,
// `m = n / 8 * 8 ≤ n`, `j + 8 ≤ m` in the chunk loop and `k < 8` for a
// block of eight.
#[allow(clippy::indexing_slicing)]
#[target_feature(enable = "avx512f,fma")]
unsafe fn process_avx512(
    bank: &mut Bank<'_>,
    xs: &[f64],
    ys: &mut [f64],
) -> (usize, Option<Error>) {
    let n = bank.plays();
    let m = n / 8 * 8;
    let (r, w) = (&bank.r[..n], &bank.w[..n]);
    let a0 = _mm512_set1_pd(bank.a0);
    let mut applied = 0;
    {
        let (y, saved) = (&mut bank.y[..n], &mut bank.pending[..n]);
        for (xb, yb) in xs.chunks_exact(8).zip(ys.chunks_exact_mut(8)) {
            saved.copy_from_slice(y);
            let x: [__m512d; 8] = core::array::from_fn(|k| _mm512_set1_pd(xb[k]));
            let mut sums = [_mm512_setzero_pd(); 8];
            let mut j = 0;
            while j < m {
                // SAFETY: j + 8 ≤ m ≤ n, the length of `r`, `w` and `y`.
                unsafe {
                    let (rc, wc) = (
                        _mm512_loadu_pd(r.as_ptr().add(j)),
                        _mm512_loadu_pd(w.as_ptr().add(j)),
                    );
                    let mut yc = _mm512_loadu_pd(y.as_ptr().add(j));
                    for (s, &xv) in sums.iter_mut().zip(&x) {
                        yc = _mm512_max_pd(
                            _mm512_min_pd(yc, _mm512_add_pd(xv, rc)),
                            _mm512_sub_pd(xv, rc),
                        );
                        *s = _mm512_fmadd_pd(wc, yc, *s);
                    }
                    _mm512_storeu_pd(y.as_mut_ptr().add(j), yc);
                }
                j += 8;
            }
            let mut tails = [0.0; 8];
            for ((&r, &w), y) in r[m..].iter().zip(&w[m..]).zip(&mut y[m..]) {
                for (t, &x) in tails.iter_mut().zip(xb) {
                    *y = play_step(r, *y, x);
                    *t = w.mul_add(*y, *t);
                }
            }
            // SAFETY: `xb`, `yb` and `tails` hold 8 values.
            let (xv, tv) = unsafe {
                (
                    _mm512_loadu_pd(xb.as_ptr()),
                    _mm512_loadu_pd(tails.as_ptr()),
                )
            };
            // `a0 x + total(.., t)` for the eight samples
            let out = _mm512_add_pd(_mm512_mul_pd(a0, xv), _mm512_add_pd(totals8(sums), tv));
            if !all_finite(out) {
                y.copy_from_slice(saved);
                break;
            }
            // SAFETY: as above.
            unsafe { _mm512_storeu_pd(yb.as_mut_ptr(), out) };
            applied += 8;
        }
    }
    let (rest, error) = drive(bank, &xs[applied..], &mut ys[applied..], |x, r, w, p, n| {
        process_avx512_step(x, r, w, p, n)
    });
    (applied + rest, error)
}

/// Whether all eight values are finite.
#[target_feature(enable = "avx512f")]
#[inline]
fn all_finite(v: __m512d) -> bool {
    _mm512_cmp_pd_mask::<_CMP_LE_OQ>(_mm512_abs_pd(v), _mm512_set1_pd(f64::MAX)) == 0xff
}

/// One sample on AVX-512 for [`drive`]: the plays of the full chunks of
/// eight from `prev` to `next`, and the eight partial sums.
#[target_feature(enable = "avx512f,fma")]
#[inline]
fn process_avx512_step(x: f64, r: &[f64], w: &[f64], prev: &[f64], next: &mut [f64]) -> [f64; 8] {
    let m = r.len().min(w.len()).min(prev.len()).min(next.len()) / 8 * 8;
    let mut acc = [0.0; 8];
    let xv = _mm512_set1_pd(x);
    let mut acc0 = _mm512_setzero_pd();
    let mut j = 0;
    while j < m {
        // SAFETY: j + 8 ≤ m, the least length of the four slices.
        unsafe {
            let (rp, wp) = (r.as_ptr().add(j), w.as_ptr().add(j));
            let (yp, np) = (prev.as_ptr().add(j), next.as_mut_ptr().add(j));
            let r0 = _mm512_loadu_pd(rp);
            let p0 = _mm512_loadu_pd(yp);
            let y0 = _mm512_max_pd(
                _mm512_min_pd(p0, _mm512_add_pd(xv, r0)),
                _mm512_sub_pd(xv, r0),
            );
            _mm512_storeu_pd(np, y0);
            acc0 = _mm512_fmadd_pd(_mm512_loadu_pd(wp), y0, acc0);
        }
        j += 8;
    }
    // SAFETY: `acc` holds 8 values.
    unsafe { _mm512_storeu_pd(acc.as_mut_ptr(), acc0) };
    acc
}
