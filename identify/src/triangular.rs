//! The triangular factor of a tall matrix, folded in row block by row block.
//!
//! For `A` (`m × c`, `m ≫ c`) with rows split into blocks `A₁, A₂, …`, the
//! factor after block `i` is the `R` of the Householder QR of `[R; Aᵢ]`
//! (`R` the factor before it, `0` at first). Orthogonal transformations
//! keep `RᵀR + AᵢᵀAᵢ`, so at the end `RᵀR = AᵀA`: `R` is the `R` of a QR of
//! `A` (made unique by a non-negative diagonal), and `Rx` has the norm of
//! `Ax` for every `x`. Blocks of [`ROWS`] rows stay in the first-level cache, and
//! `A` is never held whole: a fit's Jacobian of `m` rows is folded as the
//! dual passes hand it out.
//!
//! Each block costs `2 b c²` flops for `b` rows (one reflector per column,
//! built from the diagonal of `R` and the column of the block, applied to
//! the columns right of it), as the QR of the whole matrix does.
//!
//! # Reference
//! G. H. Golub and C. F. Van Loan, *Matrix Computations*, 4th ed., Johns
//! Hopkins 2013, §5.1–5.2 (Householder reflections, the QR factorization)
//! and §6.5.3 (updating a QR factorization by appended rows).

use nalgebra::{DMatrix, DVector};

/// Rows per block.
pub(crate) const ROWS: usize = 256;

/// An upper triangular `R` (`c × c`) with `RᵀR = AᵀA` for the rows `A`
/// pushed so far (see the module).
#[derive(Debug, Clone)]
pub(crate) struct Triangular {
    c: usize,
    /// `R`, row-major (the part below the diagonal stays 0).
    r: Vec<f64>,
    /// The pending rows, column-major `ROWS × c`; the first `rows` are in
    /// use.
    block: Vec<f64>,
    rows: usize,
    /// Rows pushed in all.
    pushed: usize,
}

impl Triangular {
    /// No rows yet: `R = 0`.
    pub fn new(c: usize) -> Self {
        Self {
            c,
            r: vec![0.0; c * c],
            block: vec![0.0; ROWS * c],
            rows: 0,
            pushed: 0,
        }
    }

    /// Rows pushed so far.
    pub fn pushed(&self) -> usize {
        self.pushed
    }

    /// Appends one row of `A` (`c` entries; entries beyond are ignored, and
    /// missing ones are 0).
    pub fn push(&mut self, row: &[f64]) {
        self.start_row(row.first().copied().unwrap_or(0.0));
        for (j, &v) in row.iter().enumerate().take(self.c).skip(1) {
            self.set(j, v);
        }
        self.end_row();
    }

    /// Starts a row whose first entry is `first` and whose others are 0
    /// until [`set`](Self::set); [`end_row`](Self::end_row) appends it.
    // `rows < ROWS` (a full block is folded at once), `j < c`.
    #[allow(clippy::indexing_slicing)]
    #[inline]
    pub fn start_row(&mut self, first: f64) {
        self.block[self.rows] = first;
        for j in 1..self.c {
            self.block[j * ROWS + self.rows] = 0.0;
        }
    }

    /// Sets entry `j` of the row started (ignored for `j ≥ c`).
    #[inline]
    pub fn set(&mut self, j: usize, v: f64) {
        if j < self.c {
            if let Some(e) = self.block.get_mut(j * ROWS + self.rows) {
                *e = v;
            }
        }
    }

    /// Appends the row started.
    #[inline]
    pub fn end_row(&mut self) {
        self.rows += 1;
        self.pushed += 1;
        if self.rows == ROWS {
            self.fold();
        }
    }

    /// Appends the rows of `other`'s factor (so the result is the factor of
    /// both sets of rows).
    pub fn absorb(&mut self, mut other: Triangular) {
        other.fold();
        let before = self.pushed;
        for row in other.r.chunks(other.c.max(1)) {
            self.push(row);
        }
        // its factor's rows stand for the rows it was given
        self.pushed = before + other.pushed;
    }

    /// Folds the pending rows into `R`: the Householder QR of `[R; B]`,
    /// one reflector per column `j`, made from `(R_jj, B_{·j})`.
    // Indices: `j, l < c`, `i < rows ≤ ROWS`; `r` is `c × c`, `block` is
    // `ROWS × c`.
    #[allow(clippy::indexing_slicing)]
    fn fold(&mut self) {
        let (c, b) = (self.c, self.rows);
        for j in 0..c {
            let (head, tail) = self.block.split_at_mut((j + 1) * ROWS);
            let v = &head[j * ROWS..j * ROWS + b];
            let s = dot(v, v);
            if s == 0.0 {
                continue;
            }
            let a = self.r[j * c + j];
            let norm = (a * a + s).sqrt();
            // the reflected diagonal, of the sign that avoids cancellation
            let alpha = if a > 0.0 { -norm } else { norm };
            let v0 = a - alpha;
            let tau = 2.0 / (v0 * v0 + s);
            for l in j + 1..c {
                let w = &mut tail[(l - j - 1) * ROWS..(l - j - 1) * ROWS + b];
                let f = tau * (v0 * self.r[j * c + l] + dot(v, w));
                self.r[j * c + l] -= f * v0;
                for (q, p) in w.iter_mut().zip(v) {
                    *q -= f * p;
                }
            }
            self.r[j * c + j] = alpha;
        }
        self.rows = 0;
    }

    /// `R` with a non-negative diagonal (each row's sign flipped where
    /// needed): for `A` of full column rank the one such factor.
    pub fn finish(mut self) -> DMatrix<f64> {
        self.fold();
        let c = self.c;
        let mut r = DMatrix::from_row_slice(c, c, &self.r);
        for i in 0..c {
            if r.get((i, i)).is_some_and(|&d| d < 0.0) {
                r.row_mut(i).neg_mut();
            }
        }
        r
    }
}

/// `Qᵀ J` for the QR `[r J] = Q R` with `R₀₀ ≥ 0`: the last `k` columns
/// of `R`, folded row by row ([`Triangular`]).
pub(crate) fn compress_jacobian(r: &DVector<f64>, j: &DMatrix<f64>) -> DMatrix<f64> {
    let k = j.ncols();
    let mut t = Triangular::new(k + 1);
    let mut row = vec![0.0; k + 1];
    for (ri, ji) in r.iter().zip(j.row_iter()) {
        for (v, &x) in row.iter_mut().zip(std::iter::once(ri).chain(ji.iter())) {
            *v = x;
        }
        t.push(&row);
    }
    t.finish().columns(1, k).into_owned()
}

/// `Σ aᵢ bᵢ` in eight interleaved sums (so that it vectorises), added
/// pairwise at the end.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0; 8];
    let (ca, cb) = (a.chunks_exact(8), b.chunks_exact(8));
    let tail: f64 = (ca.remainder().iter().zip(cb.remainder()))
        .map(|(x, y)| x * y)
        .sum();
    for (x, y) in ca.zip(cb) {
        for ((s, p), q) in acc.iter_mut().zip(x).zip(y) {
            *s += p * q;
        }
    }
    let [a0, a1, a2, a3, a4, a5, a6, a7] = acc;
    ((a0 + a4) + (a1 + a5)) + ((a2 + a6) + (a3 + a7)) + tail
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tall(m: usize, c: usize) -> DMatrix<f64> {
        DMatrix::from_fn(m, c, |i, j| {
            ((i * (j + 3)) as f64 * 0.37).sin()
                + j as f64
                + if j == 2 { 1e-6 * i as f64 } else { 0.0 }
        })
    }

    /// `RᵀR = AᵀA`, `R` upper triangular, and `R` is nalgebra's QR factor
    /// up to row signs, for row counts below, at and beyond a block, and
    /// for factors absorbed from another set of rows.
    #[test]
    fn the_factor_is_that_of_the_qr() {
        for m in [3, ROWS, ROWS + 1, 5 * ROWS + 17] {
            let a = tall(m, 6);
            let mut t = Triangular::new(6);
            let split = m / 3;
            let mut other = Triangular::new(6);
            for (i, row) in a.row_iter().enumerate() {
                let row: Vec<f64> = row.iter().copied().collect();
                if i < split {
                    t.push(&row);
                } else {
                    other.push(&row);
                }
            }
            t.absorb(other);
            assert_eq!(t.pushed(), m);
            let r = t.finish();
            for i in 0..6 {
                for j in 0..i {
                    assert_eq!(r[(i, j)], 0.0);
                }
            }
            let (rr, aa) = (r.transpose() * &r, a.transpose() * &a);
            assert!((&rr - &aa).amax() <= 1e-13 * aa.amax(), "m = {m}");
            assert!((0..6).all(|i| r[(i, i)] >= 0.0));
            if m >= 6 {
                let q = a.clone().qr().r();
                for i in 0..6 {
                    let sign = if (q[(i, i)] < 0.0) == (r[(i, i)] < 0.0) {
                        1.0
                    } else {
                        -1.0
                    };
                    let d = (q.row(i) * sign - r.row(i)).amax();
                    assert!(d <= 1e-12 * aa.amax().sqrt(), "m = {m}, row {i}: {d:e}");
                }
            }
        }
    }

    /// Rows of zeros change nothing, and no rows give `R = 0`.
    #[test]
    fn zero_rows_leave_the_factor() {
        let mut t = Triangular::new(3);
        t.push(&[0.0, 0.0, 0.0]);
        assert_eq!(t.clone().finish(), DMatrix::zeros(3, 3));
        t.push(&[3.0, 4.0, 0.0]);
        t.push(&[0.0; 3]);
        let r = t.finish();
        assert_eq!(r[(0, 0)], 3.0);
        assert_eq!(r[(0, 1)], 4.0);
        assert_eq!(r.rows(1, 2).amax(), 0.0);
    }
}
