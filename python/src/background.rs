//! Long solves run on a worker thread while the calling thread waits with the GIL
//! released, waking every 50 ms to let Python handle signals and to pass progress on.
//!
//! Ctrl-C (`KeyboardInterrupt` from the signal handler) sets the worker's
//! [`Cancel`]: its solver loops stop at their next step, so the core is free at once, not
//! when the abandoned solve would have ended. Progress callbacks are called on the calling
//! thread, never on the worker, so they may do anything Python allows (tqdm, prints).

use crate::errors::{panicked, to_py};
use beamflow::progress::{self, Bar, Cancel, Observer};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::panic::AssertUnwindSafe;
use std::rc::Rc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{channel, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// How often the waiting thread looks for a pending signal and for progress.
const POLL: Duration = Duration::from_millis(50);

/// How far the work is: the task running, and a counter of changes (0: nothing yet).
#[derive(Clone, Debug, Default)]
struct Report {
    task: String,
    done: u64,
    total: Option<u64>,
    unit: String,
    message: String,
    changes: u64,
}

/// Where the worker reports progress: the library's tasks of the worker thread (as the
/// command line's bars show them), or a driver's own count (a sweep's cases).
#[derive(Clone, Default)]
pub struct Progress(Arc<Mutex<Report>>);

impl Progress {
    fn with(&self, f: impl FnOnce(&mut Report)) {
        let mut r = self.0.lock().unwrap_or_else(|p| p.into_inner());
        f(&mut r);
        r.changes += 1;
    }

    /// A task begins: `total` steps (None: unknown) of `unit`.
    pub fn start(&self, task: &str, total: Option<u64>, unit: &str) {
        self.with(|r| {
            (r.task, r.done, r.total, r.unit) = (task.to_string(), 0, total, unit.to_string());
            r.message.clear();
        });
    }

    /// `done` steps of the current task are done.
    pub fn set(&self, done: u64, message: &str) {
        self.with(|r| (r.done, r.message) = (done, message.to_string()));
    }

    /// Starts `task` counted in finished steps (a sweep's cases, an optimisation's
    /// candidates): the function returned counts one more each time it is called.
    pub fn counter(&self, task: &str, total: Option<u64>, unit: &str) -> Arc<dyn Fn() + Send + Sync> {
        self.start(task, total, unit);
        let (done, r) = (AtomicU64::new(0), self.clone());
        Arc::new(move || r.set(done.fetch_add(1, Ordering::Relaxed) + 1, ""))
    }

    fn snapshot(&self) -> Report {
        self.0.lock().unwrap_or_else(|p| p.into_inner()).clone()
    }
}

struct TaskBar(Progress);

impl Observer for Progress {
    fn start(&self, label: &str, total: Option<u64>, unit: &str) -> Box<dyn Bar> {
        Progress::start(self, label, total, unit);
        Box::new(TaskBar(self.clone()))
    }
}

impl Bar for TaskBar {
    fn update(&self, position: u64, message: &str) {
        self.0.set(position, message);
    }
}

impl Drop for TaskBar {
    /// A task that ends has done all its steps (its last report is before its last step).
    fn drop(&mut self) {
        let total = self.0.snapshot().total;
        if let Some(t) = total {
            self.0.with(|r| r.done = t);
        }
    }
}

/// Calls `callback` with the report, as a dict (`task`, `done`, `total`, `unit`,
/// `message`), if it changed since `seen`.
fn tell(py: Python<'_>, callback: Option<&Bound<'_, PyAny>>, progress: &Progress, seen: &mut u64) -> PyResult<()> {
    let Some(cb) = callback else { return Ok(()) };
    let r = progress.snapshot();
    if r.changes == *seen {
        return Ok(());
    }
    *seen = r.changes;
    let d = PyDict::new(py);
    d.set_item("task", r.task)?;
    d.set_item("done", r.done)?;
    d.set_item("total", r.total)?;
    d.set_item("unit", r.unit)?;
    d.set_item("message", r.message)?;
    cb.call1((d,))?;
    Ok(())
}

/// What a Ctrl-C during the work does to its result.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum OnInterrupt {
    /// Raise at once; the work stops at its next step and its result is dropped.
    Drop,
    /// Stop the work, wait for what it finished (a sweep's rows) and return it with the
    /// exception; a second Ctrl-C raises at once.
    Keep,
}

/// Runs `job` on a worker thread and returns its result; Ctrl-C raises `KeyboardInterrupt`
/// at once and stops the job at its next step.
pub fn run<T: Send + 'static>(
    py: Python<'_>,
    job: impl FnOnce() -> beamflow::Result<T> + Send + 'static,
) -> PyResult<T> {
    watched(py, None, OnInterrupt::Drop, move |_| job()).map(|(t, _)| t)
}

/// Runs `job` on a worker thread, calling `callback` with its progress, and returns its
/// result with the `KeyboardInterrupt` that stopped it, if one did (only with
/// [`OnInterrupt::Keep`]; with `Drop` the exception is returned as the error).
pub fn watched<T: Send + 'static>(
    py: Python<'_>,
    callback: Option<&Bound<'_, PyAny>>,
    on_interrupt: OnInterrupt,
    job: impl FnOnce(&Progress) -> beamflow::Result<T> + Send + 'static,
) -> PyResult<(T, Option<PyErr>)> {
    let (cancel, report) = (Cancel::new(), Progress::default());
    let (c, p, observed) = (cancel.clone(), report.clone(), callback.is_some());
    let (tx, rx) = channel();
    std::thread::Builder::new()
        .name("beamflow-solve".into())
        .spawn(move || {
            let work = || match observed {
                true => progress::observe(Rc::new(p.clone()), || job(&p)),
                false => job(&p),
            };
            let _ = tx.send(std::panic::catch_unwind(AssertUnwindSafe(|| progress::cancellable(c, work))));
        })
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start a worker thread: {e}")))?;
    // Only this thread receives; the mutex makes the receiver shareable with `detach`.
    let rx = Mutex::new(rx);
    let (mut seen, mut interrupt) = (0, None);
    loop {
        match py.detach(|| rx.lock().unwrap_or_else(|p| p.into_inner()).recv_timeout(POLL)) {
            Ok(Ok(result)) => {
                if interrupt.is_none() {
                    tell(py, callback, &report, &mut seen)?;
                }
                return match (result, interrupt) {
                    (Err(beamflow::Error::Cancelled), Some(e)) => Err(e),
                    (result, interrupt) => Ok((result.map_err(to_py)?, interrupt)),
                };
            }
            Ok(Err(payload)) => return Err(panicked(payload)),
            Err(RecvTimeoutError::Timeout) => {
                // Once interrupted, the callback hears no more: a callback that raised to stop
                // the work would raise again at the next report, and lose the rows kept.
                let step = py.check_signals().and_then(|()| match interrupt {
                    None => tell(py, callback, &report, &mut seen),
                    Some(_) => Ok(()),
                });
                if let Err(e) = step {
                    cancel.cancel();
                    if on_interrupt == OnInterrupt::Drop || interrupt.is_some() {
                        return Err(e);
                    }
                    interrupt = Some(e);
                }
            }
            Err(RecvTimeoutError::Disconnected) => {
                return Err(PyRuntimeError::new_err("the worker thread ended without a result"))
            }
        }
    }
}
