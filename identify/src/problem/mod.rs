//! The least-squares problem a fit hands to Levenberg-Marquardt: residuals
//! `model(x_r; φ(θ)) − y_r` over the scored samples of every record, the
//! Jacobian (forward-mode derivatives through the model's dual twin, or
//! central finite differences), and the evaluation budget.

mod plan;
mod speculation;

pub(crate) use plan::{Layout, Plan};

use crate::options::{FitOptions, Jacobian, Progress};
use crate::record::Record;
use crate::transform::Reparam;
use crate::triangular::{compress_jacobian, Triangular};
use hysteron_operators::{Dual, Error, Operator, DUAL_WIDTH};
use levenberg_marquardt::LeastSquaresProblem;
use nalgebra::{DMatrix, DVector, Dyn, Owned};
use rayon::prelude::*;
use speculation::{Rows, Speculator, Work};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Samples per block of a simulation (an output buffer of 32 KiB).
const BLOCK: usize = 4096;

/// The shortest first simulation for which a fit starts its dual passes
/// beside its simulations (see `speculation`). Below it a pass handed to
/// another core saves about what it costs (each core builds its own flow
/// tables, and a pass at a rejected point stops only between blocks).
/// Above it, `cargo bench --bench identify -- "speculating|alone"` measures
/// the gain side by side: the paper's two stages (stage 2 simulates in
/// about 1 ms) and a fit of the Bouc-Wen benchmark system ran 10 % and 4 %
/// faster with it on a Zen 5 machine. Only the speed depends on it: the
/// results are the same bits either way.
#[cfg(not(test))]
const SPECULATE_FROM: Duration = Duration::from_micros(500);
/// (In this crate's unit tests every fit that can speculates, so they all
/// check it.)
#[cfg(test)]
const SPECULATE_FROM: Duration = Duration::ZERO;

/// The work a fit may still do: simulations and wall time.
#[derive(Debug, Clone, Copy)]
struct Budget {
    max_evaluations: Option<usize>,
    deadline: Option<(Instant, Duration)>,
}

impl Budget {
    /// Why `more` further simulations would exceed the budget after `done`.
    fn refuses(&self, done: usize, more: usize) -> Option<String> {
        if let Some(max) = self.max_evaluations {
            if done.saturating_add(more) > max {
                return Some(format!(
                    "evaluation budget of {max} simulations reached (max_evaluations)"
                ));
            }
        }
        match self.deadline {
            Some((end, limit)) if Instant::now() >= end => Some(format!(
                "time limit of {} s reached (max_seconds)",
                limit.as_secs_f64()
            )),
            _ => None,
        }
    }
}

/// A point the solver accepted, and its residuals (`None`: the penalty).
///
/// The solver comes back to it after a rejected trial step, and a fit's
/// report evaluates it once more: those simulations would repeat this one
/// bit for bit, so they are taken from here.
struct Accepted {
    theta: DVector<f64>,
    residuals: Option<DVector<f64>>,
}

/// A Jacobian, the point it was taken at, and whether it is the
/// compressed one.
type KeptJacobian = (DVector<f64>, bool, DMatrix<f64>);

/// Whether two parameter vectors are the same bit for bit.
fn same_point(a: &DVector<f64>, b: &DVector<f64>) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b.iter())
            .all(|(x, y)| x.to_bits() == y.to_bits())
}

/// The least-squares problem: residuals over every record's scored samples.
pub(crate) struct Problem<'a> {
    on_iteration: &'a (dyn Fn(Progress) + Sync),
    template: Box<dyn Operator<f64>>,
    /// The model over dual numbers, for exact Jacobians (`None`: finite
    /// differences).
    dual: Option<Box<dyn Operator<Dual>>>,
    base: Vec<f64>,
    layout: Layout,
    pub maps: Vec<Reparam>,
    pub theta: DVector<f64>,
    records: &'a [Record<'a>],
    /// Residuals in all (the scored samples of every record).
    m: usize,
    current: Option<DVector<f64>>,
    penalty: f64,
    step: f64,
    pub parallel: bool,
    stride: usize,
    budget: Budget,
    /// Why the budget stopped the search (then `residuals` and `jacobian`
    /// answer `None`, which ends it).
    stopped: Mutex<Option<String>>,
    /// The last point the solver accepted (where it asked for a Jacobian),
    /// with its residuals.
    accepted: Mutex<Accepted>,
    /// The last Jacobian, the point it was taken at, and whether it is
    /// the compressed one.
    last_jacobian: Mutex<Option<KeptJacobian>>,
    pub evaluations: AtomicUsize,
    pub jacobians: AtomicUsize,
    /// The dual pass started beside each trial simulation (one record,
    /// one pass, exact, parallel; see `speculation`).
    pub speculator: Option<Speculator>,
}

impl Problem<'_> {
    /// The model's parameter vector for record `r` at `theta`.
    // Every layout index is `< base.len()` (checked by the caller), and
    // `theta.len() = layout.len()`.
    pub fn full_params(&self, theta: &[f64], r: usize) -> Vec<f64> {
        self.plan().full_params(theta, r)
    }

    /// What a record's dual pass needs besides `θ`.
    fn plan(&self) -> Plan<'_> {
        Plan {
            base: &self.base,
            layout: &self.layout,
            maps: &self.maps,
            stride: self.stride,
        }
    }

    /// Residuals at `theta`, or the model's error there with its record.
    ///
    /// Each record runs in blocks of [`BLOCK`] samples through one small
    /// buffer (the model resumes from its state at every block, as
    /// `process` does): a fit simulates dozens of times, and an output
    /// buffer as long as the record, allocated and freed each time, made
    /// the allocator hand pages back to the system and fault them in again.
    // `scored_in` gives `i < out.len()` and `q < record.y.len()`.
    #[allow(clippy::indexing_slicing)]
    pub fn simulate(&self, theta: &[f64]) -> Result<DVector<f64>, (usize, Error)> {
        self.evaluations.fetch_add(1, Ordering::Relaxed);
        let mut residuals = Vec::with_capacity(self.m);
        let longest = self.records.iter().map(|r| r.x.len()).max().unwrap_or(0);
        let mut out = vec![0.0; BLOCK.min(longest)];
        for (r, record) in self.records.iter().enumerate() {
            let mut model = self.template.clone();
            model
                .set_params(&self.full_params(theta, r))
                .map_err(|e| (r, e))?;
            for (b, xs) in record.x.chunks(BLOCK).enumerate() {
                let offset = b * BLOCK;
                let out = &mut out[..xs.len()];
                model
                    .process(xs, out)
                    .map_err(|e| (r, e.offset_by(offset)))?;
                for (i, q) in record.scored_in(self.stride, offset, out.len()) {
                    residuals.push(out[i] - record.y[q]);
                }
            }
        }
        Ok(DVector::from_vec(residuals))
    }

    /// Central difference of the residuals along `θ_j` (one-sided where
    /// one side is outside the model's valid set, zero where both are).
    // `j < self.theta.len()`: the callers iterate `0..self.theta.len()`.
    #[allow(clippy::indexing_slicing)]
    fn column(&self, j: usize) -> DVector<f64> {
        let t = self.theta.as_slice();
        let h = self.step * t[j].abs().max(1.0);
        let shifted = |d: f64| {
            let mut v = t.to_vec();
            v[j] += d;
            self.simulate(&v).ok()
        };
        match (shifted(h), shifted(-h), &self.current) {
            (Some(p), Some(m), _) => (p - m) / (2.0 * h),
            (Some(p), None, Some(c)) => (p - c) / h,
            (None, Some(m), Some(c)) => (c - m) / h,
            _ => DVector::zeros(self.m),
        }
    }

    /// The Jacobian at the current `θ`: exact through the dual twin where
    /// there is one (falling back to finite differences if a derivative is
    /// not finite), else [`fd_jacobian`](Self::fd_jacobian).
    ///
    /// Asked again at the point of the last Jacobian (a fit's report, after
    /// a search that ended on a rejected step), it returns that Jacobian:
    /// the model is deterministic, so computing it again would give the
    /// same bits.
    pub fn jacobian_matrix(&self) -> DMatrix<f64> {
        self.kept_jacobian(false, || self.full_jacobian())
    }

    /// The Jacobian `J̃ = QᵀJ` of the compressed problem at the current
    /// `θ`, for `[r J] = QR` with `r` the current residuals (see
    /// `compressed`): the last `k` columns of `R`, `k + 1` rows, with
    /// `J̃ᵀJ̃ = JᵀJ` and the column norms of `J`. Where one dual pass per
    /// record gives every column, the rows are folded into `R` as the pass
    /// hands them out, and `J` is never held whole; otherwise `[r J]` is
    /// folded once computed. Kept like [`jacobian_matrix`](Self::jacobian_matrix)'s.
    pub fn compressed_jacobian(&self) -> DMatrix<f64> {
        self.kept_jacobian(true, || {
            let r = self.current_residuals();
            let k = self.theta.len();
            let speculated = self.speculator.as_ref().and_then(Speculator::rows);
            if let Some(Some(rows)) = speculated {
                if let Some(big_r) = self.fold_rows(&rows, &r) {
                    return big_r.columns(1, k).into_owned();
                }
            }
            let j = match &self.dual {
                Some(dual) if self.one_pass_per_record() => {
                    match self.exact_triangular(dual.as_ref(), &r) {
                        Some(big_r) => return big_r.columns(1, k).into_owned(),
                        // (the same pass would fail again)
                        None => self.fd_jacobian(),
                    }
                }
                _ => self.full_jacobian(),
            };
            compress_jacobian(&r, &j)
        })
    }

    /// The Jacobian kept from the last call if it was taken at the current
    /// `θ` (the model is deterministic: computing it again would give the
    /// same bits), else `compute`'s, kept.
    fn kept_jacobian(
        &self,
        compressed: bool,
        compute: impl FnOnce() -> DMatrix<f64>,
    ) -> DMatrix<f64> {
        self.jacobians.fetch_add(1, Ordering::Relaxed);
        if let Ok(last) = self.last_jacobian.lock() {
            if let Some((theta, c, j)) = last.as_ref() {
                if *c == compressed && same_point(theta, &self.theta) {
                    return j.clone();
                }
            }
        }
        let j = compute();
        if let Ok(mut last) = self.last_jacobian.lock() {
            *last = Some((self.theta.clone(), compressed, j.clone()));
        }
        j
    }

    /// The Jacobian, exact where the dual twin gives finite derivatives,
    /// else by differences.
    fn full_jacobian(&self) -> DMatrix<f64> {
        self.dual
            .as_ref()
            .and_then(|dual| self.exact_jacobian(dual.as_ref()))
            .unwrap_or_else(|| self.fd_jacobian())
    }

    /// Whether one dual pass gives every column a record has (at most
    /// [`DUAL_WIDTH`] parameters, at least one).
    fn one_pass_per_record(&self) -> bool {
        (1..=DUAL_WIDTH).contains(&(self.layout.shared.len() + self.layout.own.len()))
    }

    /// `R` of `[r J]` by folding each record's rows as its dual pass hands
    /// them out (records in parallel where the problem is), for
    /// [`one_pass_per_record`](Self::one_pass_per_record); `None` where a
    /// pass fails or a derivative is not finite.
    // `first + row < r.len()`: each record's rows follow the rows before.
    #[allow(clippy::indexing_slicing)]
    fn exact_triangular(
        &self,
        dual: &(dyn Operator<Dual> + 'static),
        r: &DVector<f64>,
    ) -> Option<DMatrix<f64>> {
        let k = self.theta.len();
        self.evaluations
            .fetch_add(self.jacobian_cost(), Ordering::Relaxed);
        let rows: Vec<usize> = self.records.iter().map(Record::scored).collect();
        let firsts: Vec<usize> = rows
            .iter()
            .scan(0, |at, &n| {
                let first = *at;
                *at += n;
                Some(first)
            })
            .collect();
        let fold = |rec: usize| -> Option<Triangular> {
            let mut t = Triangular::new(k + 1);
            let first = firsts[rec];
            // one pass: each row comes once, with all its entries
            self.record_jacobian(dual, rec, |q, cols, ds| {
                t.start_row(r[first + q]);
                for (&j, &d) in cols.iter().zip(ds) {
                    t.set(j + 1, d);
                }
                t.end_row();
            })?;
            // every scored row once (one pass, in order)
            (t.pushed() == rows[rec]).then_some(t)
        };
        let parts: Vec<Option<Triangular>> = if self.parallel && self.records.len() > 1 {
            (0..self.records.len()).into_par_iter().map(fold).collect()
        } else {
            (0..self.records.len()).map(fold).collect()
        };
        let mut all = Triangular::new(k + 1);
        for part in parts {
            all.absorb(part?);
        }
        Some(all.finish())
    }

    /// `R` of `[r J]` from the rows of a speculated pass (one record), in
    /// the order and with the operations of
    /// [`exact_triangular`](Self::exact_triangular): the same bits.
    // `q < rows`: `r` has one residual per scored sample, and the worker
    // checked that the pass gave exactly those rows.
    #[allow(clippy::indexing_slicing)]
    fn fold_rows(&self, rows: &Rows, r: &DVector<f64>) -> Option<DMatrix<f64>> {
        let k = self.theta.len();
        let width = rows.cols.len();
        if width == 0 || rows.values.len() != width * r.len() {
            return None;
        }
        self.evaluations
            .fetch_add(self.jacobian_cost(), Ordering::Relaxed);
        let mut t = Triangular::new(k + 1);
        for (q, ds) in rows.values.chunks(width).enumerate() {
            t.start_row(r[q]);
            for (&j, &d) in rows.cols.iter().zip(ds) {
                t.set(j + 1, d);
            }
            t.end_row();
        }
        let mut all = Triangular::new(k + 1);
        all.absorb(t);
        Some(all.finish())
    }

    /// Which Jacobian the problem computes.
    pub fn jacobian_kind(&self) -> Jacobian {
        if self.dual.is_some() {
            Jacobian::Exact
        } else {
            Jacobian::FiniteDifferences
        }
    }

    /// The simulations one Jacobian costs: one dual pass per
    /// [`DUAL_WIDTH`] parameters of a record, or two per column.
    pub fn jacobian_cost(&self) -> usize {
        match &self.dual {
            Some(_) => {
                let per_record = self.layout.shared.len() + self.layout.own.len();
                per_record.div_ceil(DUAL_WIDTH).max(1)
            }
            None => 2 * self.theta.len(),
        }
    }

    /// `∂r/∂θ` by forward-mode derivatives: each record runs through the
    /// dual model with the parameters it depends on (the shared ones and
    /// its own) seeded, [`DUAL_WIDTH`] at a time, and the chain rule of the
    /// reparametrization, `∂r/∂θ_j = (∂y/∂p_i) dφ/dθ_j`. `None` where a
    /// dual simulation fails or a derivative is not finite.
    // Rows: each record's block of `m` starts at the sum of the rows before.
    #[allow(clippy::indexing_slicing)]
    fn exact_jacobian(&self, dual: &(dyn Operator<Dual> + 'static)) -> Option<DMatrix<f64>> {
        self.evaluations
            .fetch_add(self.jacobian_cost(), Ordering::Relaxed);
        let k = self.theta.len();
        let rows: Vec<usize> = self.records.iter().map(Record::scored).collect();
        let mut jac = DMatrix::zeros(self.m, k);
        if self.parallel && self.records.len() > 1 {
            // each record into a block of its own, in parallel, then copied
            let blocks: Vec<Option<DMatrix<f64>>> = (0..self.records.len())
                .into_par_iter()
                .map(|r| {
                    let mut b = DMatrix::zeros(rows[r], k);
                    self.record_jacobian(dual, r, |row, cols, ds| {
                        for (&j, &d) in cols.iter().zip(ds) {
                            b[(row, j)] = d;
                        }
                    })?;
                    Some(b)
                })
                .collect();
            let mut first_row = 0;
            for (b, &n) in blocks.into_iter().zip(&rows) {
                jac.rows_mut(first_row, n).copy_from(&b?);
                first_row += n;
            }
        } else {
            // straight into the Jacobian: no copy of the columns
            let mut first_row = 0;
            for (r, &n) in rows.iter().enumerate() {
                self.record_jacobian(dual, r, |row, cols, ds| {
                    for (&j, &d) in cols.iter().zip(ds) {
                        jac[(first_row + row, j)] = d;
                    }
                })?;
                first_row += n;
            }
        }
        Some(jac)
    }

    /// The rows of record `r` in [`exact_jacobian`](Self::exact_jacobian),
    /// at the current `θ` ([`Plan::record_rows`]).
    fn record_jacobian(
        &self,
        dual: &(dyn Operator<Dual> + 'static),
        r: usize,
        put: impl FnMut(usize, &[usize], &[f64]),
    ) -> Option<()> {
        let record = self.records.get(r)?;
        self.plan()
            .record_rows(dual, self.theta.as_slice(), record, r, put, || true)
            .map(|_| ())
    }

    /// The Jacobian by central differences (`2k` simulations).
    pub fn fd_jacobian(&self) -> DMatrix<f64> {
        let k = self.theta.len();
        let cols: Vec<DVector<f64>> = if self.parallel {
            (0..k).into_par_iter().map(|j| self.column(j)).collect()
        } else {
            (0..k).map(|j| self.column(j)).collect()
        };
        DMatrix::from_columns(&cols)
    }

    /// Whether `more` simulations may start; records why not.
    fn allows(&self, more: usize) -> bool {
        let done = self.evaluations.load(Ordering::Relaxed);
        let Ok(mut stopped) = self.stopped.lock() else {
            return false;
        };
        if stopped.is_none() {
            *stopped = self.budget.refuses(done, more);
        }
        stopped.is_none()
    }

    /// Why the budget ended the search, if it did.
    pub fn stopped(&self) -> Option<String> {
        self.stopped.lock().ok().and_then(|s| s.clone())
    }

    /// The last point the solver accepted.
    pub fn accepted(&self) -> DVector<f64> {
        match self.accepted.lock() {
            Ok(a) => a.theta.clone(),
            Err(_) => self.theta.clone(),
        }
    }

    /// The residuals at `theta` if it is the accepted point (see
    /// [`Accepted`]).
    fn known_residuals(&self, theta: &DVector<f64>) -> Option<DVector<f64>> {
        let a = self.accepted.lock().ok()?;
        if same_point(&a.theta, theta) {
            a.residuals.clone()
        } else {
            None
        }
    }

    /// The current residuals (the penalty outside the valid set).
    pub fn current_residuals(&self) -> DVector<f64> {
        self.current
            .clone()
            .unwrap_or_else(|| DVector::from_element(self.m, self.penalty))
    }

    /// Residuals in all.
    pub fn len(&self) -> usize {
        self.m
    }

    /// Moves to `theta` and simulates there, whatever the budget (for the
    /// report at the end).
    pub fn evaluate_at(&mut self, theta: &DVector<f64>) {
        self.theta.copy_from(theta);
        self.current = match self.known_residuals(theta) {
            Some(known) => {
                self.speculate(false);
                Some(known)
            }
            None => {
                self.speculate(true);
                self.simulate(theta.as_slice()).ok()
            }
        };
    }

    /// Starts the dual pass at the current `θ` beside its simulation
    /// (`start`), or says that there is none for it; nothing without a
    /// speculator.
    fn speculate(&self, start: bool) {
        if let Some(s) = &self.speculator {
            match self.kept_at_current_point() {
                false if start => s.begin(&self.theta),
                _ => s.forget(),
            }
        }
    }

    /// Whether the last Jacobian kept was taken at the current `θ`.
    fn kept_at_current_point(&self) -> bool {
        self.last_jacobian.lock().ok().is_some_and(|last| {
            last.as_ref()
                .is_some_and(|(t, _, _)| same_point(t, &self.theta))
        })
    }

    /// The worker of [`speculate`](Self::speculate), for a fit of one
    /// record whose Jacobian is one dual pass, in parallel.
    fn speculator_for(&self, opts: &FitOptions) -> Option<Speculator> {
        let dual = self.dual.as_ref()?;
        let [record] = self.records else {
            return None;
        };
        // (inside rayon's pool, where the starts of a multistart fit run
        // side by side, the other cores are taken)
        if !(opts.parallel && self.one_pass_per_record()) || rayon::current_thread_index().is_some()
        {
            return None;
        }
        Speculator::start(Work {
            dual: dyn_clone::clone_box(dual.as_ref()),
            base: self.base.clone(),
            layout: self.layout.clone(),
            maps: self.maps.clone(),
            stride: self.stride,
            x: record.x.to_vec(),
            y: record.y.to_vec(),
            skip: record.skip,
        })
    }

    /// What the solver's request for a Jacobian starts: the current point
    /// becomes the accepted one, the progress callback hears of it, and
    /// the budget is asked; `false` if it is spent.
    pub fn begin_jacobian(&self) -> bool {
        // The solver asks for a Jacobian only at an accepted point.
        if let Ok(mut a) = self.accepted.lock() {
            a.theta.copy_from(&self.theta);
            a.residuals.clone_from(&self.current);
        }
        (self.on_iteration)(Progress {
            iteration: self.jacobians.load(Ordering::Relaxed),
            evaluations: self.evaluations.load(Ordering::Relaxed),
            cost: self
                .current
                .as_ref()
                .map_or(f64::INFINITY, |r| 0.5 * r.norm_squared()),
        });
        self.allows(self.jacobian_cost())
    }
}

impl<'a> Problem<'a> {
    /// The problem at the model's current parameters; fails with the
    /// record and the model's error if the model cannot be simulated there.
    // Every layout index is `< base.len()` and `< domains.len()` (checked
    // by the caller).
    #[allow(clippy::indexing_slicing)]
    pub fn new(
        model: &(dyn Operator<f64> + 'static),
        records: &'a [Record<'a>],
        layout: Layout,
        opts: &FitOptions,
        on_iteration: &'a (dyn Fn(Progress) + Sync),
    ) -> Result<Self, (usize, Error)> {
        let base = model.params();
        let domains = model.param_domains();
        let entries = layout.entries();
        let maps: Vec<Reparam> = entries.iter().map(|&(i, _)| Reparam(domains[i])).collect();
        let theta0 = DVector::from_iterator(
            entries.len(),
            entries
                .iter()
                .zip(&maps)
                .map(|(&(i, _), m)| m.to_internal(base[i])),
        );
        let scale = records
            .iter()
            .flat_map(|r| r.y)
            .fold(1.0_f64, |a, v| a.max(v.abs()));
        let m = records.iter().map(Record::scored).sum();
        let started = Instant::now();
        let deadline = opts
            .max_seconds
            .map(Duration::from_secs_f64)
            .map(|d| (started + d, d));
        let mut problem = Problem {
            on_iteration,
            template: dyn_clone::clone_box(model),
            dual: match opts.jacobian {
                Jacobian::Exact => model.to_dual(),
                Jacobian::FiniteDifferences => None,
            },
            base,
            layout,
            maps,
            theta: theta0.clone(),
            records,
            m,
            current: None,
            penalty: 1e3 * scale,
            step: opts.step,
            parallel: opts.parallel,
            stride: opts.stride.max(1),
            budget: Budget {
                max_evaluations: opts.max_evaluations,
                deadline,
            },
            stopped: Mutex::new(None),
            accepted: Mutex::new(Accepted {
                theta: theta0.clone(),
                residuals: None,
            }),
            last_jacobian: Mutex::new(None),
            evaluations: AtomicUsize::new(0),
            jacobians: AtomicUsize::new(0),
            speculator: None,
        };
        let clock = Instant::now();
        problem.current = Some(problem.simulate(theta0.as_slice())?);
        if clock.elapsed() >= SPECULATE_FROM {
            problem.speculator = problem.speculator_for(opts);
        }
        Ok(problem)
    }
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, theta: &DVector<f64>) {
        self.theta.copy_from(theta);
        if let Some(known) = self.known_residuals(theta) {
            self.current = Some(known);
            self.speculate(false);
            return;
        }
        self.speculate(true);
        self.current = if self.allows(1) {
            self.simulate(theta.as_slice()).ok()
        } else {
            None
        };
    }

    fn params(&self) -> DVector<f64> {
        self.theta.clone()
    }

    /// Outside the model's valid set (a rejected parameter combination, a
    /// loop without solution) the residuals are a large constant, so the
    /// solver rejects the step and shrinks its trust region. Once the
    /// budget is spent: `None`, which ends the search.
    fn residuals(&self) -> Option<DVector<f64>> {
        if self.stopped().is_some() {
            return None;
        }
        Some(self.current_residuals())
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        self.begin_jacobian().then(|| self.jacobian_matrix())
    }
}
