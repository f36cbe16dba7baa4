//! Where the fit's parameters sit in the model's, and a record's Jacobian
//! rows from one dual pass.

use crate::record::Record;
use crate::transform::Reparam;
use hysteron_models::sensitivity::visit_derivatives_while;
use hysteron_operators::{Dual, Operator, DUAL_WIDTH};

/// Where the fit's parameters sit in the vector `θ` the solver moves: the
/// shared free parameters first, then, record after record, each record's
/// own copy of the per-record parameters.
#[derive(Debug, Clone)]
pub(crate) struct Layout {
    /// Model indices of the shared free parameters.
    pub shared: Vec<usize>,
    /// Model indices of the per-record parameters.
    pub own: Vec<usize>,
    /// Number of records.
    pub records: usize,
}

impl Layout {
    /// `(model index, record)` of each entry of `θ`.
    pub fn entries(&self) -> Vec<(usize, Option<usize>)> {
        let shared = self.shared.iter().map(|&i| (i, None));
        let own = (0..self.records).flat_map(|r| self.own.iter().map(move |&i| (i, Some(r))));
        shared.chain(own).collect()
    }
}

/// What a record's dual pass needs besides `θ` and the record: the
/// model's parameters, where `θ` goes in them and how, and the stride of
/// the scored samples.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Plan<'p> {
    pub base: &'p [f64],
    pub layout: &'p Layout,
    pub maps: &'p [Reparam],
    pub stride: usize,
}

impl Plan<'_> {
    /// The model's parameter vector for record `r` at `theta`.
    // Every layout index is `< base.len()` (checked by the caller), and
    // `theta.len() = layout.len()`.
    #[allow(clippy::indexing_slicing)]
    pub fn full_params(&self, theta: &[f64], r: usize) -> Vec<f64> {
        let mut p = self.base.to_vec();
        let k = self.layout.shared.len();
        let n_own = self.layout.own.len();
        for ((&i, map), &t) in self.layout.shared.iter().zip(self.maps).zip(theta) {
            p[i] = map.to_external(t);
        }
        let at = k + r * n_own;
        for (j, &i) in self.layout.own.iter().enumerate() {
            p[i] = self.maps[at + j].to_external(theta[at + j]);
        }
        p
    }

    /// The Jacobian rows of `record` (record `r` of the layout) at
    /// `theta`: `put(row, cols, ds)` with `ds[e] = ∂r_row/∂θ_{cols[e]}` for
    /// every scored sample (rows counted from the record's first, in
    /// order) and every pass, each pass giving up to [`DUAL_WIDTH`] of the
    /// `θ_j` the record depends on; after each block of samples the passes
    /// go on while `go_on()` says so. `Some(true)` when done, `Some(false)`
    /// when stopped, `None` where a pass fails or a derivative is not
    /// finite.
    // Indices: `j < theta.len() = maps.len()`, layout indices `< base.len()`
    // (checked by the caller), `first_column + columns ≤ entries.len()`,
    // `scored_in` gives `i < ys.len()`.
    #[allow(clippy::indexing_slicing)]
    pub fn record_rows(
        &self,
        dual: &(dyn Operator<Dual> + 'static),
        theta: &[f64],
        record: &Record<'_>,
        r: usize,
        mut put: impl FnMut(usize, &[usize], &[f64]),
        mut go_on: impl FnMut() -> bool,
    ) -> Option<bool> {
        let (k, n_own) = (self.layout.shared.len(), self.layout.own.len());
        // θ entries of record r, and their model indices
        let entries: Vec<(usize, usize)> = (self.layout.shared.iter().enumerate())
            .map(|(j, &i)| (j, i))
            .chain((self.layout.own.iter().enumerate()).map(|(o, &i)| (k + r * n_own + o, i)))
            .collect();
        let indices: Vec<usize> = entries.iter().map(|&(_, i)| i).collect();
        let thetas: Vec<usize> = entries.iter().map(|&(j, _)| j).collect();
        let dp: Vec<f64> = entries
            .iter()
            .map(|&(j, _)| self.maps[j].derivative(theta[j]))
            .collect();
        let params = self.full_params(theta, r);
        let mut ds = [0.0; DUAL_WIDTH];
        visit_derivatives_while(dual, &params, record.x, &indices, |block| {
            let columns = block.first_column..block.first_column + block.columns;
            let (cols, dp) = (&thetas[columns.clone()], &dp[columns]);
            let ds = &mut ds[..cols.len()];
            for (i, q) in record.scored_in(self.stride, block.offset, block.ys.len()) {
                for ((d, &e), &s) in ds.iter_mut().zip(&block.ys[i].eps).zip(dp) {
                    *d = e * s;
                }
                put(q - record.skip, cols, ds);
            }
            go_on()
        })
        .ok()
    }
}
