//! The 8 × 8 transpose of a tile of lane outputs (`cols[j][k] =
//! tile[k][j]`), in registers: with AVX-512 three rounds of eight shuffles,
//! with AVX2 four 4 × 4 transposes of eight each; element by element
//! otherwise. Only moves: the values keep their bits.

use super::{TILE, WIDTH};

/// A tile: `TILE` samples of `WIDTH` lanes.
pub(super) type Tile = [[f64; WIDTH]; TILE];
/// Its transpose: `WIDTH` lanes of `TILE` samples.
pub(super) type Columns = [[f64; TILE]; WIDTH];

/// The transpose element by element.
// `k < TILE` (enumerating the tile's rows), the length of a column.
#[allow(clippy::indexing_slicing)]
#[inline(always)]
pub(super) fn portable(tile: &Tile) -> Columns {
    let mut cols = [[0.0; TILE]; WIDTH];
    for (k, lanes) in tile.iter().enumerate() {
        for (col, &v) in cols.iter_mut().zip(lanes) {
            col[k] = v;
        }
    }
    cols
}

/// The transpose in AVX-512 registers: pairs of rows interleaved, then
/// pairs of 128-bit lanes, then halves.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[inline]
pub(super) fn avx512(tile: &Tile) -> Columns {
    use core::arch::x86_64::*;
    let [r0, r1, r2, r3, r4, r5, r6, r7] =
        // SAFETY: a `[f64; 8]` holds the 8 values an unaligned load reads.
        tile.map(|row| unsafe { _mm512_loadu_pd(row.as_ptr()) });
    // (r[k][0], r[k+1][0], r[k][2], r[k+1][2], …) and the odd elements
    let (e01, o01) = (_mm512_unpacklo_pd(r0, r1), _mm512_unpackhi_pd(r0, r1));
    let (e23, o23) = (_mm512_unpacklo_pd(r2, r3), _mm512_unpackhi_pd(r2, r3));
    let (e45, o45) = (_mm512_unpacklo_pd(r4, r5), _mm512_unpackhi_pd(r4, r5));
    let (e67, o67) = (_mm512_unpacklo_pd(r6, r7), _mm512_unpackhi_pd(r6, r7));
    let lo128 = _mm512_set_epi64(13, 12, 5, 4, 9, 8, 1, 0);
    let hi128 = _mm512_set_epi64(15, 14, 7, 6, 11, 10, 3, 2);
    // four rows of elements {0, 4}, {2, 6}, {1, 5}, {3, 7}
    let q04 = _mm512_permutex2var_pd(e01, lo128, e23);
    let q26 = _mm512_permutex2var_pd(e01, hi128, e23);
    let q15 = _mm512_permutex2var_pd(o01, lo128, o23);
    let q37 = _mm512_permutex2var_pd(o01, hi128, o23);
    let p04 = _mm512_permutex2var_pd(e45, lo128, e67);
    let p26 = _mm512_permutex2var_pd(e45, hi128, e67);
    let p15 = _mm512_permutex2var_pd(o45, lo128, o67);
    let p37 = _mm512_permutex2var_pd(o45, hi128, o67);
    let lo256 = _mm512_set_epi64(11, 10, 9, 8, 3, 2, 1, 0);
    let hi256 = _mm512_set_epi64(15, 14, 13, 12, 7, 6, 5, 4);
    let columns = [
        _mm512_permutex2var_pd(q04, lo256, p04),
        _mm512_permutex2var_pd(q15, lo256, p15),
        _mm512_permutex2var_pd(q26, lo256, p26),
        _mm512_permutex2var_pd(q37, lo256, p37),
        _mm512_permutex2var_pd(q04, hi256, p04),
        _mm512_permutex2var_pd(q15, hi256, p15),
        _mm512_permutex2var_pd(q26, hi256, p26),
        _mm512_permutex2var_pd(q37, hi256, p37),
    ];
    let mut cols = [[0.0; TILE]; WIDTH];
    for (col, v) in cols.iter_mut().zip(columns) {
        // SAFETY: a `[f64; 8]` holds the 8 values an unaligned store writes.
        unsafe { _mm512_storeu_pd(col.as_mut_ptr(), v) };
    }
    cols
}

/// The transpose in AVX2 registers: four 4 × 4 blocks, each by pairs of
/// rows interleaved and then 128-bit halves exchanged.
// `samples + 3 < TILE` and `lanes < WIDTH`: the blocks' corners are 0 and 4.
#[allow(clippy::indexing_slicing)]
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
pub(super) fn avx2(tile: &Tile) -> Columns {
    use core::arch::x86_64::*;
    let mut cols = [[0.0; TILE]; WIDTH];
    for (lanes, samples) in [(0, 0), (0, 4), (4, 0), (4, 4)] {
        // SAFETY: each row holds `lanes + 4 ≤ WIDTH` values, the 4 from
        // `lanes` that an unaligned load reads.
        let (r0, r1, r2, r3) = unsafe {
            (
                _mm256_loadu_pd(tile[samples][lanes..].as_ptr()),
                _mm256_loadu_pd(tile[samples + 1][lanes..].as_ptr()),
                _mm256_loadu_pd(tile[samples + 2][lanes..].as_ptr()),
                _mm256_loadu_pd(tile[samples + 3][lanes..].as_ptr()),
            )
        };
        let (a, b) = (_mm256_unpacklo_pd(r0, r1), _mm256_unpackhi_pd(r0, r1));
        let (c, d) = (_mm256_unpacklo_pd(r2, r3), _mm256_unpackhi_pd(r2, r3));
        let out = [
            _mm256_permute2f128_pd(a, c, 0x20),
            _mm256_permute2f128_pd(b, d, 0x20),
            _mm256_permute2f128_pd(a, c, 0x31),
            _mm256_permute2f128_pd(b, d, 0x31),
        ];
        for (col, v) in cols.iter_mut().skip(lanes).zip(out) {
            // SAFETY: `samples + 4 ≤ TILE` values of the column.
            unsafe { _mm256_storeu_pd(col.as_mut_ptr().add(samples), v) };
        }
    }
    cols
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tile() -> Tile {
        core::array::from_fn(|k| core::array::from_fn(|j| (10 * k + j) as f64 + 0.5))
    }

    #[test]
    fn portable_is_the_transpose() {
        let cols = portable(&tile());
        for (j, col) in cols.iter().enumerate() {
            for (k, v) in col.iter().enumerate() {
                assert_eq!(*v, (10 * k + j) as f64 + 0.5);
            }
        }
    }

    /// Each vector version gives the element-by-element transpose, where
    /// the CPU has its instructions.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn vector_transposes_are_the_portable_one() {
        let t = tile();
        if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: detected above.
            assert_eq!(unsafe { avx512(&t) }, portable(&t));
        }
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: detected above.
            assert_eq!(unsafe { avx2(&t) }, portable(&t));
        }
    }
}
