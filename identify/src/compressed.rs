//! The least-squares problem as Levenberg-Marquardt sees it: the same
//! problem in `k + 1` residuals instead of `m`, by an orthogonal change of
//! basis at every Jacobian.
//!
//! At a point with residuals `r` (`m` of them) and Jacobian `J` (`m × k`),
//! let `Q` (`m × (k + 1)`, orthonormal columns) span `r` and the columns of
//! `J`, with `r/‖r‖` its first column: the Householder QR of `[r J]`,
//!
//! `[r J] = Q R`,  `R` upper triangular `(k + 1) × (k + 1)`,  `R₀₀ = ‖r‖`
//! (the first row's sign chosen so).
//!
//! The solver is handed `r̃ = Qᵀ r = (‖r‖, 0, …, 0)` and `J̃ = Qᵀ J` (the
//! last `k` columns of `R`). Every quantity of the Levenberg-Marquardt
//! iteration (MINPACK's `lmder`) is one of `J̃ᵀ J̃ = Jᵀ J`, `J̃ᵀ r̃ = Jᵀ r`, the
//! column norms of `J̃` (those of `J`) and the residual norm `‖r̃‖ = ‖r‖`, so
//! the iterates are the same in exact arithmetic. At a trial point the
//! solver only needs the norm of the residuals, and `(‖r‖, 0, …, 0)` is
//! in the basis of the next Jacobian, whose `Q` starts with `r/‖r‖`, if
//! the trial is accepted.
//!
//! The cost of the solver's own linear algebra (a pivoted QR of `J`, and
//! `Qᵀ r`, in scalar loops) drops from `O(m k²)` per iteration to `O(k³)`,
//! and the one QR of `[r J]` that replaces it (`bouc_wen_fit_5`, 20 000
//! residuals and 5 parameters: 28 → 20–22 ms on the machine of the
//! README's figures) is folded block by block as the dual passes hand out
//! the rows ([`Triangular`], `Problem::compressed_jacobian`): `J` is never
//! held whole. Problems with `m ≤ k + 1` residuals are passed through as
//! they are.
//!
//! # Reference
//! J. J. Moré, "The Levenberg-Marquardt algorithm: implementation and
//! theory", in *Numerical Analysis*, Lecture Notes in Mathematics 630,
//! Springer 1978 (the iteration depends on `J` through its QR alone).

use crate::problem::Problem;
use levenberg_marquardt::LeastSquaresProblem;
use nalgebra::{DMatrix, DVector, Dyn, Owned};

/// [`Problem`] in `k + 1` residuals (see the module).
pub(crate) struct Compressed<'a> {
    inner: Problem<'a>,
    /// Whether the problem is compressed (`m > k + 1`).
    on: bool,
}

impl<'a> Compressed<'a> {
    pub fn new(inner: Problem<'a>) -> Self {
        let on = inner.len() > inner.theta.len() + 1;
        Self { inner, on }
    }

    pub fn into_inner(self) -> Problem<'a> {
        self.inner
    }
}

/// `(‖r‖, 0, …, 0)`, `k + 1` long.
fn compress_residuals(r: &DVector<f64>, k: usize) -> DVector<f64> {
    let mut c = DVector::zeros(k + 1);
    if let Some(first) = c.get_mut(0) {
        *first = r.norm();
    }
    c
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Compressed<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, theta: &DVector<f64>) {
        self.inner.set_params(theta);
    }

    fn params(&self) -> DVector<f64> {
        self.inner.params()
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        let r = self.inner.residuals()?;
        Some(if self.on {
            compress_residuals(&r, self.inner.theta.len())
        } else {
            r
        })
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        if !self.on {
            return self.inner.jacobian();
        }
        self.inner
            .begin_jacobian()
            .then(|| self.inner.compressed_jacobian())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::triangular::compress_jacobian;

    /// `J̃ᵀ J̃ = Jᵀ J` and `J̃ᵀ r̃ = Jᵀ r` (to rounding), `r̃ = (‖r‖, 0, …)`.
    #[test]
    fn keeps_the_normal_equations_and_the_norm() {
        let (m, k) = (200, 4);
        let j = DMatrix::from_fn(m, k, |i, c| ((i * (c + 3)) as f64 * 0.37).sin() + c as f64);
        let r = DVector::from_fn(m, |i, _| ((i as f64) * 0.11).cos() - 0.3);
        let (jc, rc) = (compress_jacobian(&r, &j), compress_residuals(&r, k));
        assert_eq!((jc.nrows(), jc.ncols(), rc.len()), (k + 1, k, k + 1));
        let close = |a: &DMatrix<f64>, b: &DMatrix<f64>| {
            let scale = b.amax();
            (a - b).amax() <= 1e-12 * scale
        };
        assert!(close(&(jc.transpose() * &jc), &(j.transpose() * &j)));
        let (gc, g) = (jc.transpose() * &rc, j.transpose() * &r);
        assert!((gc - &g).amax() <= 1e-12 * g.amax(), "Jᵀr");
        assert!((rc.norm() - r.norm()).abs() <= 1e-14 * r.norm());
        assert!(rc.iter().skip(1).all(|&v| v == 0.0));
    }
}
