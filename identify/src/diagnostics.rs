//! Identifiability diagnostics of a fit: how well the data pin the free
//! parameters down.
//!
//! From the Jacobian `J` of the residuals at the solution (in the internal
//! parameters `θ` the optimizer works in, see [`Reparam`](crate::Reparam)):
//!
//! * the condition number `κ(JᵀJ) = λ_max / λ_min` of the Gauss-Newton
//!   matrix (eigenvalues of the symmetric `JᵀJ`); a large `κ` means some
//!   direction in parameter space barely changes the output;
//! * [`IdentifiabilityWarning`]s naming every parameter whose 95 %
//!   interval is wider than `|value|`, every pair whose correlation
//!   exceeds [`CORRELATED`] in magnitude, and a singular `JᵀJ` (no
//!   intervals at all).
//!
//! # Reference
//! Bates & Watts, *Nonlinear Regression Analysis and Its Applications*
//! (Wiley 1988), ch. 2–3: the linear approximation `C = σ² (JᵀJ)⁻¹` behind
//! the standard errors, intervals and correlations.

pub use crate::outcome::IdentifiabilityWarning;

use crate::outcome::FittedParam;
use nalgebra::{DMatrix, SymmetricEigen};

/// Correlations beyond this magnitude are reported.
pub const CORRELATED: f64 = 0.99;

/// A parameter belongs to a singular combination if its component in the
/// weakest direction (a unit vector) is at least this.
pub const IN_NULL_DIRECTION: f64 = 0.1;

/// A parameter whose column of `J` (in the internal parameters) has at
/// most this norm relative to the largest column is taken as not
/// determined by the data at the solution (`√ε`: its share of `JᵀJ` is at
/// the rounding of the others').
pub const UNDETERMINED: f64 = 1.5e-8;

/// Which free parameters the data determine at the solution: those whose
/// column of `J` has a norm above [`UNDETERMINED`] times the largest one's.
///
/// A parameter kept non-negative by `θ ↦ e^θ` that the fit drives towards
/// 0 has the column `e^θ ∂r/∂p`, which vanishes with it: `JᵀJ` is then
/// singular only to rounding, and inverting it as a whole would spread
/// that parameter's unbounded variance over every other parameter's error
/// (see [`inverse_of_determined`]).
pub fn determined(jac: &DMatrix<f64>) -> Vec<bool> {
    let norms: Vec<f64> = jac.column_iter().map(|c| c.norm()).collect();
    let largest = norms.iter().copied().fold(0.0, f64::max);
    norms
        .iter()
        .map(|&n| n.is_finite() && n > UNDETERMINED * largest)
        .collect()
}

/// `(JᵀJ)⁻¹` restricted to the `determined` parameters: the inverse of
/// their block of `jtj`, with NaN in the rows and columns of the others
/// (their variance is unbounded; they are held at their values). `None`
/// where that block is singular.
pub fn inverse_of_determined(jtj: &DMatrix<f64>, determined: &[bool]) -> Option<DMatrix<f64>> {
    let keep: Vec<usize> = (0..jtj.nrows())
        .filter(|&i| determined.get(i).copied().unwrap_or(false))
        .collect();
    let block = DMatrix::from_fn(keep.len(), keep.len(), |a, b| {
        keep.get(a)
            .zip(keep.get(b))
            .and_then(|(&i, &j)| jtj.get((i, j)).copied())
            .unwrap_or(f64::NAN)
    });
    let inverse = block.try_inverse()?;
    let mut full = DMatrix::from_element(jtj.nrows(), jtj.ncols(), f64::NAN);
    for (a, &i) in keep.iter().enumerate() {
        for (b, &j) in keep.iter().enumerate() {
            if let (Some(v), Some(out)) = (inverse.get((a, b)), full.get_mut((i, j))) {
                *out = *v;
            }
        }
    }
    Some(full)
}

/// `κ = λ_max / λ_min` of the symmetric positive semi-definite `jtj`
/// (`None` where it is empty, `λ_min ≤ 0` (singular) or the eigenvalues
/// are not finite), and the unit eigenvector of `λ_min`: the direction in
/// parameter space the data determine least.
pub fn conditioning(jtj: &DMatrix<f64>) -> (Option<f64>, Vec<f64>) {
    if jtj.is_empty() || jtj.iter().any(|v| !v.is_finite()) {
        return (None, Vec::new());
    }
    let eigen = SymmetricEigen::new(jtj.clone());
    let weakest = eigen.eigenvalues.imin();
    let direction = eigen.eigenvectors.column(weakest).iter().copied().collect();
    let max = eigen.eigenvalues.max();
    let min = eigen.eigenvalues.min();
    (
        (min > 0.0 && max.is_finite()).then_some(max / min),
        direction,
    )
}

/// The warnings for `params` with their correlation matrix (`None` where
/// `JᵀJ` is singular) and the weakest direction of `JᵀJ` (from
/// [`conditioning`]): [`Singular`](IdentifiabilityWarning::Singular)
/// alone in the singular case, else every wide interval, then every
/// correlated pair `(i < j)` in the order of `params`.
pub fn warnings(
    params: &[FittedParam],
    correlation: Option<&[Vec<f64>]>,
    weakest: &[f64],
) -> Vec<IdentifiabilityWarning> {
    let Some(correlation) = correlation else {
        let names = params
            .iter()
            .zip(weakest)
            .filter(|(_, v)| v.abs() >= IN_NULL_DIRECTION)
            .map(|(p, _)| p.label())
            .collect();
        return if params.is_empty() {
            Vec::new()
        } else {
            vec![IdentifiabilityWarning::Singular { names }]
        };
    };
    let wide = params.iter().filter_map(|p| match p.ci95 {
        Some((a, b)) if b - a > p.value.abs() => Some(IdentifiabilityWarning::WideInterval {
            name: p.label(),
            value: p.value,
            interval: (a, b),
        }),
        _ => None,
    });
    let pairs = params.iter().enumerate().flat_map(|(i, p)| {
        params
            .iter()
            .enumerate()
            .skip(i + 1)
            .filter_map(move |(j, q)| {
                let rho = correlation.get(i)?.get(j).copied()?;
                (rho.abs() > CORRELATED).then(|| IdentifiabilityWarning::Correlated {
                    first: p.label(),
                    second: q.label(),
                    rho,
                })
            })
    });
    wide.chain(pairs).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn param(name: &str, value: f64, ci95: Option<(f64, f64)>) -> FittedParam {
        FittedParam {
            name: name.into(),
            index: 0,
            start: value,
            value,
            std_error: None,
            ci95,
            record: None,
        }
    }

    #[test]
    fn condition_number_is_the_eigenvalue_ratio() {
        let m = DMatrix::from_row_slice(2, 2, &[4.0, 0.0, 0.0, 0.25]);
        let (k, weakest) = conditioning(&m);
        assert_eq!(k, Some(16.0));
        assert_eq!(
            weakest.iter().map(|v| v.abs()).collect::<Vec<_>>(),
            [0.0, 1.0]
        );
        // [[2, 1], [1, 2]]: eigenvalues 3 and 1, the weakest along (1, −1)/√2
        let m = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 2.0]);
        let (k, weakest) = conditioning(&m);
        assert!((k.unwrap() - 3.0).abs() < 1e-12, "{k:?}");
        let h = std::f64::consts::FRAC_1_SQRT_2;
        assert!((weakest[0].abs() - h).abs() < 1e-12 && (weakest[0] + weakest[1]).abs() < 1e-12);
        // singular: [[1, 1], [1, 1]] does not see (1, −1)
        let singular = DMatrix::from_row_slice(2, 2, &[1.0, 1.0, 1.0, 1.0]);
        let (k, weakest) = conditioning(&singular);
        assert_eq!(k, None);
        assert!((weakest[0] + weakest[1]).abs() < 1e-12, "{weakest:?}");
        assert_eq!(conditioning(&DMatrix::zeros(0, 0)), (None, vec![]));
        let nan = DMatrix::from_row_slice(1, 1, &[f64::NAN]);
        assert_eq!(conditioning(&nan).0, None);
    }

    /// A column at `√ε` of the largest or below is undetermined; the
    /// inverse is the determined block's, NaN elsewhere (and the whole
    /// matrix's inverse where every column counts).
    #[test]
    fn undetermined_columns_are_left_out_of_the_inverse() {
        // Columns of norms 2, 1e-9 and 1 (the second below √ε · 2).
        let jac = DMatrix::from_row_slice(3, 3, &[2.0, 1e-9, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]);
        let d = determined(&jac);
        assert_eq!(d, vec![true, false, true]);
        let jtj = jac.transpose() * &jac;
        let inv = inverse_of_determined(&jtj, &d).unwrap();
        assert_eq!(inv[(0, 0)], 0.25);
        assert_eq!(inv[(2, 2)], 1.0);
        assert_eq!(inv[(0, 2)], 0.0);
        for i in 0..3 {
            assert!(inv[(1, i)].is_nan() && inv[(i, 1)].is_nan());
        }
        // A column just above the threshold counts, and the full inverse
        // is returned.
        let jac = DMatrix::from_row_slice(2, 2, &[2.0, 0.0, 0.0, 1e-7]);
        assert_eq!(determined(&jac), vec![true, true]);
        let jtj = jac.transpose() * &jac;
        let inv = inverse_of_determined(&jtj, &[true, true]).unwrap();
        assert!((inv[(1, 1)] * 1e-14 - 1.0).abs() < 1e-9);
        // A singular determined block is still singular.
        let jac = DMatrix::from_row_slice(2, 2, &[1.0, 1.0, 1.0, 1.0]);
        assert_eq!(
            inverse_of_determined(&(jac.transpose() * &jac), &determined(&jac)),
            None
        );
        // No columns at all.
        assert_eq!(determined(&DMatrix::zeros(4, 0)), Vec::<bool>::new());
    }

    #[test]
    fn warnings_name_wide_intervals_and_correlated_pairs() {
        let params = [
            param("a", 1.0, Some((0.9, 1.1))),
            param("b", -0.5, Some((-1.2, 0.2))),
            param("c", 2.0, Some((1.0, 3.0))),
        ];
        let rho = vec![
            vec![1.0, 0.2, -0.995],
            vec![0.2, 1.0, 0.5],
            vec![-0.995, 0.5, 1.0],
        ];
        let w = warnings(&params, Some(&rho), &[]);
        assert_eq!(
            w,
            [
                IdentifiabilityWarning::WideInterval {
                    name: "b".into(),
                    value: -0.5,
                    interval: (-1.2, 0.2)
                },
                IdentifiabilityWarning::Correlated {
                    first: "a".into(),
                    second: "c".into(),
                    rho: -0.995
                },
            ]
        );
        // an interval exactly |value| wide is not flagged ("wider than")
        assert!(warnings(&params[2..], Some(&[vec![1.0]]), &[]).is_empty());
        // singular along (a − c): those two are named, not b
        let s = 0.5_f64.sqrt();
        let singular = warnings(&params, None, &[s, 0.05, -s]);
        assert_eq!(
            singular,
            [IdentifiabilityWarning::Singular {
                names: vec!["a".into(), "c".into()]
            }]
        );
        assert!(singular[0]
            .to_string()
            .contains("a combination of `a`, `c`"));
        assert!(warnings(&[], None, &[]).is_empty());
        let text = w[1].to_string();
        assert!(
            text.contains("`a` and `c`") && text.contains("-0.995"),
            "{text}"
        );
    }
}
