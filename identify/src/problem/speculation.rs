//! A dual pass started beside each trial simulation, on another core.
//!
//! Levenberg-Marquardt simulates each trial point, and asks for the
//! Jacobian there only if it accepts the point. A fit of one record with
//! exact derivatives in one dual pass ([`Problem`](crate::problem::Problem))
//! starts that pass on a worker thread as soon as the point is set, while
//! the simulation runs on the caller's; if the point is accepted, its
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
use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::{Arc, Condvar, Mutex};
use std::thread::JoinHandle;
use std::time::Duration;

/// The Jacobian rows of the record at one point: row `q` holds
/// `∂r_q/∂θ_{cols[e]}` at `values[q · cols.len() + e]`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Rows {
    pub cols: Vec<usize>,
    pub values: Vec<f64>,
}

/// What the worker owns: the dual model, the plan and the record.
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

/// A finished pass: its job, and its rows (`None`: the pass failed or a
/// derivative is not finite).
type Finished = Option<(u64, Option<Rows>)>;

/// The worker thread and how to talk to it.
pub(crate) struct Speculator {
    jobs: Option<Sender<(u64, Vec<f64>)>>,
    /// The newest job; a pass for any other stops at its next block.
    latest: Arc<AtomicU64>,
    done: Arc<(Mutex<Finished>, Condvar)>,
    worker: Option<JoinHandle<()>>,
    /// The job of the current point (0: none).
    current: AtomicU64,
    /// Passes whose rows were taken.
    pub taken: AtomicU64,
}

/// No job: the current point has no pass started, and any pass stops.
const NONE: u64 = 0;

impl Speculator {
    /// The worker for `work`, or `None` where the machine has one core or
    /// no thread can be started.
    pub fn start(work: Work) -> Option<Self> {
        if std::thread::available_parallelism().map_or(1, |n| n.get()) < 2 {
            return None;
        }
        let (jobs, rx) = channel();
        let latest = Arc::new(AtomicU64::new(NONE));
        let done = Arc::new((Mutex::new(None), Condvar::new()));
        let (l, d) = (latest.clone(), done.clone());
        let worker = std::thread::Builder::new()
            .name("hysteron-jacobian".into())
            .spawn(move || serve(&work, &rx, &l, &d))
            .ok()?;
        Some(Self {
            jobs: Some(jobs),
            latest,
            done,
            worker: Some(worker),
            current: AtomicU64::new(NONE),
            taken: AtomicU64::new(0),
        })
    }

    /// Starts the pass at `theta`, the new current point (stopping any
    /// other).
    pub fn begin(&self, theta: &DVector<f64>) {
        let id = self.latest.load(Ordering::Relaxed).wrapping_add(1).max(1);
        self.latest.store(id, Ordering::Relaxed);
        let sent = self
            .jobs
            .as_ref()
            .is_some_and(|jobs| jobs.send((id, theta.as_slice().to_vec())).is_ok());
        self.current
            .store(if sent { id } else { NONE }, Ordering::Relaxed);
    }

    /// The current point has no pass (and any running pass stops).
    pub fn forget(&self) {
        self.latest.store(
            self.latest.load(Ordering::Relaxed).wrapping_add(1).max(1),
            Ordering::Relaxed,
        );
        self.current.store(NONE, Ordering::Relaxed);
    }

    /// The rows of the current point's pass, waiting for them: `None`
    /// where no pass was started for it (or the worker is gone),
    /// `Some(None)` where it failed.
    pub fn rows(&self) -> Option<Option<Rows>> {
        let id = self.current.swap(NONE, Ordering::Relaxed);
        if id == NONE {
            return None;
        }
        let (lock, ready) = &*self.done;
        let mut finished = lock.lock().ok()?;
        loop {
            if let Some((done_id, _)) = finished.as_ref() {
                if *done_id == id {
                    let rows = finished.take().map(|(_, rows)| rows);
                    if let Some(Some(_)) = &rows {
                        self.taken.fetch_add(1, Ordering::Relaxed);
                    }
                    return rows;
                }
            }
            if self.worker.as_ref().is_none_or(JoinHandle::is_finished) {
                return None;
            }
            finished = ready
                .wait_timeout(finished, Duration::from_millis(20))
                .ok()?
                .0;
        }
    }
}

impl Drop for Speculator {
    /// Stops any pass and joins the worker.
    fn drop(&mut self) {
        self.latest.store(NONE, Ordering::Relaxed);
        self.jobs = None;
        if let Some(worker) = self.worker.take() {
            let _ = worker.join();
        }
    }
}

/// The worker: for each job (the newest one queued), the record's rows,
/// published unless a newer job stopped the pass.
fn serve(
    work: &Work,
    jobs: &Receiver<(u64, Vec<f64>)>,
    latest: &AtomicU64,
    done: &(Mutex<Finished>, Condvar),
) {
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
    while let Ok(mut job) = jobs.recv() {
        while let Ok(newer) = jobs.try_recv() {
            job = newer;
        }
        let (id, theta) = job;
        if latest.load(Ordering::Relaxed) != id {
            continue;
        }
        let mut rows = Rows {
            cols: Vec::new(),
            values: Vec::with_capacity(record.scored() * work.layout.shared.len().max(1)),
        };
        let mut next_row = 0;
        let mut in_order = true;
        let outcome = plan.record_rows(
            work.dual.as_ref(),
            &theta,
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
        let rows = match outcome {
            Some(false) => continue,
            Some(true) if in_order && next_row == record.scored() => Some(rows),
            _ => None,
        };
        let (lock, ready) = done;
        if let Ok(mut finished) = lock.lock() {
            *finished = Some((id, rows));
            ready.notify_all();
        }
    }
}
