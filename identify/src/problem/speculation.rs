//! A dual pass started beside each trial simulation, on another core.
//!
//! Levenberg-Marquardt simulates each trial point, and asks for the
//! Jacobian there only if it accepts the point. A fit of one record with
//! exact derivatives in one dual pass ([`Problem`](crate::problem::Problem))
//! hands that pass to rayon's pool as soon as the point is set, while the
//! simulation runs on the caller's thread; if the point is accepted, its
//! Jacobian rows are ready (or on their way) when asked for, and if it is
//! rejected, the pass is stopped at its next block. The rows are those
//! [`Plan::record_rows`] gives on the caller's thread, bit for bit: the
//! same function on the same model, parameters and record.

use super::plan::{Layout, Plan};
use crate::record::Record;
use crate::transform::Reparam;
use hysteron_operators::{Dual, Operator};
use nalgebra::DVector;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{sync_channel, Receiver};
use std::sync::{Arc, Mutex};

/// The Jacobian rows of the record at one point: row `q` holds
/// `∂r_q/∂θ_{cols[e]}` at `values[q · cols.len() + e]`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Rows {
    pub cols: Vec<usize>,
    pub values: Vec<f64>,
}

/// What every pass reads: the dual model, the plan and the record.
pub(crate) struct Work {
    pub dual: Box<dyn Operator<Dual>>,
    pub base: Vec<f64>,
    pub layout: Layout,
    pub maps: Vec<Reparam>,
    pub stride: usize,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub skip: usize,
}

/// The passes of one fit, and the one of its current point.
pub(crate) struct Speculator {
    work: Arc<Work>,
    /// The newest job; a pass for any other stops at its next block.
    latest: Arc<AtomicU64>,
    /// The current point's pass: its job, and where its rows arrive
    /// (`None` from a pass that failed or a derivative that is not
    /// finite).
    current: Mutex<Option<(u64, Receiver<Option<Rows>>)>>,
    /// Passes whose rows were taken.
    pub taken: AtomicU64,
}

/// No job: any pass stops.
const NONE: u64 = 0;

impl Speculator {
    /// The passes for `work`, or `None` where the caller is a thread of
    /// rayon's pool (it would wait for a pass queued behind itself) or the
    /// pool has fewer than two threads.
    pub fn start(work: Work) -> Option<Self> {
        if rayon::current_thread_index().is_some() || rayon::current_num_threads() < 2 {
            return None;
        }
        Some(Self {
            work: Arc::new(work),
            latest: Arc::new(AtomicU64::new(NONE)),
            current: Mutex::new(None),
            taken: AtomicU64::new(0),
        })
    }

    /// Hands the pass at `theta`, the new current point, to the pool
    /// (stopping any other).
    pub fn begin(&self, theta: &DVector<f64>) {
        let id = self.latest.load(Ordering::Relaxed).wrapping_add(1).max(1);
        self.latest.store(id, Ordering::Relaxed);
        let (sender, rows) = sync_channel(1);
        let (work, latest, theta) = (
            self.work.clone(),
            self.latest.clone(),
            theta.as_slice().to_vec(),
        );
        rayon::spawn(move || {
            if let Some(rows) = pass(&work, id, &theta, &latest) {
                // (the receiver is gone where the point was left)
                let _ = sender.send(rows);
            }
        });
        if let Ok(mut current) = self.current.lock() {
            *current = Some((id, rows));
        }
    }

    /// The current point has no pass (and any running pass stops).
    pub fn forget(&self) {
        self.latest.store(
            self.latest.load(Ordering::Relaxed).wrapping_add(1).max(1),
            Ordering::Relaxed,
        );
        if let Ok(mut current) = self.current.lock() {
            *current = None;
        }
    }

    /// The rows of the current point's pass, waiting for them: `None`
    /// where no pass was started for it, `Some(None)` where it failed.
    pub fn rows(&self) -> Option<Option<Rows>> {
        let (id, rows) = self.current.lock().ok()?.take()?;
        if self.latest.load(Ordering::Relaxed) != id {
            return None;
        }
        let rows = rows.recv().ok()?;
        if rows.is_some() {
            self.taken.fetch_add(1, Ordering::Relaxed);
        }
        Some(rows)
    }
}

impl Drop for Speculator {
    /// Stops any pass (at its next block).
    fn drop(&mut self) {
        self.latest.store(NONE, Ordering::Relaxed);
    }
}

/// The record's rows at `theta` for job `id`: `None` where a newer job
/// stopped the pass, `Some(None)` where it failed or a derivative is not
/// finite.
fn pass(work: &Work, id: u64, theta: &[f64], latest: &AtomicU64) -> Option<Option<Rows>> {
    let plan = Plan {
        base: &work.base,
        layout: &work.layout,
        maps: &work.maps,
        stride: work.stride,
    };
    let record = Record {
        x: &work.x,
        y: &work.y,
        skip: work.skip,
    };
    if latest.load(Ordering::Relaxed) != id {
        return None;
    }
    let mut rows = Rows {
        cols: Vec::new(),
        values: Vec::with_capacity(record.scored() * work.layout.shared.len().max(1)),
    };
    let mut next_row = 0;
    let mut in_order = true;
    let outcome = plan.record_rows(
        work.dual.as_ref(),
        theta,
        &record,
        0,
        |q, cols, ds| {
            if rows.cols.is_empty() {
                rows.cols = cols.to_vec();
            }
            in_order &= q == next_row && cols == rows.cols.as_slice();
            next_row += 1;
            rows.values.extend_from_slice(ds);
        },
        || latest.load(Ordering::Relaxed) == id,
    );
    match outcome {
        Some(false) => None,
        Some(true) if in_order && next_row == record.scored() => Some(Some(rows)),
        _ => Some(None),
    }
}
