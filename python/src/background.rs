//! Long solves run on a worker thread while the calling thread waits with the GIL
//! released, waking every 50 ms to let Python handle signals: Ctrl-C raises
//! `KeyboardInterrupt` at once, and other Python threads run meanwhile.

use crate::errors::{panicked, to_py};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use std::panic::AssertUnwindSafe;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{channel, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// How often the waiting thread looks for a pending signal.
const POLL: Duration = Duration::from_millis(50);

/// Runs `job` on a worker thread and returns its result. If a signal handler raises
/// (Ctrl-C: `KeyboardInterrupt`) while it runs, `cancel` is set — the job stops at its next
/// check — and the exception is returned without waiting for the job.
pub fn run<T: Send + 'static>(
    py: Python<'_>,
    cancel: Option<Arc<AtomicBool>>,
    job: impl FnOnce() -> beamflow::Result<T> + Send + 'static,
) -> PyResult<T> {
    let (tx, rx) = channel();
    std::thread::Builder::new()
        .name("beamflow-solve".into())
        .spawn(move || {
            let _ = tx.send(std::panic::catch_unwind(AssertUnwindSafe(job)));
        })
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start a worker thread: {e}")))?;
    // Only this thread receives; the mutex makes the receiver shareable with `detach`.
    let rx = Mutex::new(rx);
    loop {
        match py.detach(|| rx.lock().unwrap_or_else(|p| p.into_inner()).recv_timeout(POLL)) {
            Ok(Ok(result)) => return result.map_err(to_py),
            Ok(Err(payload)) => return Err(panicked(payload)),
            Err(RecvTimeoutError::Timeout) => {
                if let Err(e) = py.check_signals() {
                    if let Some(c) = &cancel {
                        c.store(true, Ordering::SeqCst);
                    }
                    return Err(e);
                }
            }
            Err(RecvTimeoutError::Disconnected) => {
                return Err(PyRuntimeError::new_err("the worker thread ended without a result"))
            }
        }
    }
}
