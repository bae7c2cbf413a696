//! Progress of long computations, for whoever watches.
//!
//! A solver announces a [`Task`] (a label, how many steps, what a step is) and moves it on;
//! what is shown is up to the [`Observer`] installed for the current thread with
//! [`observe`] — the command line's progress bars. Without one (sweep and optimiser
//! workers, the Python package, tests) a task is a no-op that costs one thread-local read,
//! so solvers report unconditionally and stay free of any terminal code.
//!
//! Every step a task reports is also a cancellation point: a [`Cancel`] installed for the
//! thread with [`cancellable`] and then set (from any thread: Ctrl-C in Python, a stopped
//! sweep) makes the next [`Task::set`] return [`Error::Cancelled`], so the solver loops
//! (transient periods, steady-state harmonics, harmonic frequencies, Lanczos vectors) stop
//! within one step instead of running to the end for nobody.

use crate::error::{Error, Result};
use std::cell::RefCell;
use std::rc::Rc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::LocalKey;

/// Shows tasks as they run.
pub trait Observer {
    /// A task begins: `total` steps (None: unknown) of `unit` (e.g. "periods").
    fn start(&self, label: &str, total: Option<u64>, unit: &str) -> Box<dyn Bar>;
}

/// One task's display; dropping it ends the task.
pub trait Bar {
    /// `position` steps are done; `message` says how things stand (may be empty).
    fn update(&self, position: u64, message: &str);
}

thread_local! {
    static OBSERVER: RefCell<Option<Rc<dyn Observer>>> = const { RefCell::new(None) };
    static CANCEL: RefCell<Option<Cancel>> = const { RefCell::new(None) };
}

/// A request to stop, shared between whoever may ask (any thread) and the work that checks it.
#[derive(Clone, Debug, Default)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    pub fn new() -> Cancel {
        Cancel::default()
    }

    /// Asks the work to stop at its next check.
    pub fn cancel(&self) {
        self.0.store(true, Ordering::SeqCst);
    }

    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::SeqCst)
    }

    /// `Err(Error::Cancelled)` once cancelled.
    pub fn check(&self) -> Result<()> {
        if self.is_cancelled() {
            Err(Error::Cancelled)
        } else {
            Ok(())
        }
    }
}

/// Runs `f` with `cancel` stopping this thread's tasks (the previous one is restored
/// afterwards, also on a panic).
pub fn cancellable<T>(cancel: Cancel, f: impl FnOnce() -> T) -> T {
    installed(&CANCEL, cancel, f)
}

/// The cancellation installed for this thread, if any (to hand on to worker threads).
pub fn current_cancel() -> Option<Cancel> {
    CANCEL.with(|c| c.borrow().clone())
}

/// `a` here and `b` on a thread beside it (which sees this thread's cancellation, not its
/// observer), both results; a panic in `b` is raised here.
pub fn side_by_side<A, B: Send>(a: impl FnOnce() -> A, b: impl FnOnce() -> B + Send) -> (A, B) {
    let cancel = current_cancel();
    std::thread::scope(|scope| {
        let side = scope.spawn(|| match cancel {
            Some(c) => cancellable(c, b),
            None => b(),
        });
        let a = a();
        (a, side.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
    })
}

/// Runs `f` with `observer` watching this thread's tasks (the previous observer is restored
/// afterwards, also on a panic).
pub fn observe<T>(observer: Rc<dyn Observer>, f: impl FnOnce() -> T) -> T {
    installed(&OBSERVER, observer, f)
}

/// Runs `f` with `value` in the thread-local `slot`, restoring what was there afterwards.
fn installed<V: 'static, T>(slot: &'static LocalKey<RefCell<Option<V>>>, value: V, f: impl FnOnce() -> T) -> T {
    struct Restore<V: 'static>(&'static LocalKey<RefCell<Option<V>>>, Option<V>);
    impl<V: 'static> Drop for Restore<V> {
        fn drop(&mut self) {
            let prev = self.1.take();
            self.0.with(|s| *s.borrow_mut() = prev);
        }
    }
    let _restore = Restore(slot, slot.with(|s| s.borrow_mut().replace(value)));
    f()
}

/// A running task: shown while it lives if an observer watches this thread.
pub struct Task {
    bar: Option<Box<dyn Bar>>,
    cancel: Option<Cancel>,
}

impl Task {
    /// Begins a task of `total` steps (None: unknown) of `unit`.
    pub fn start(label: &str, total: Option<u64>, unit: &str) -> Task {
        let observer = OBSERVER.with(|o| o.borrow().clone());
        Task { bar: observer.map(|o| o.start(label, total, unit)), cancel: current_cancel() }
    }

    /// Whether anyone watches (messages that cost something to format are made only then).
    pub fn watched(&self) -> bool {
        self.bar.is_some()
    }

    /// `position` steps are done; `Err(Error::Cancelled)` if the work is to stop.
    pub fn set(&self, position: u64) -> Result<()> {
        self.set_with(position, String::new)
    }

    /// `position` steps are done; the message is made only if someone watches.
    /// `Err(Error::Cancelled)` if the work is to stop.
    pub fn set_with(&self, position: u64, message: impl FnOnce() -> String) -> Result<()> {
        if let Some(b) = &self.bar {
            b.update(position, &message());
        }
        self.cancel.as_ref().map_or(Ok(()), Cancel::check)
    }
}

/// An observer that writes down what it sees, a line each: `start <label> <total> <unit>`,
/// `<label> <position> <message>`, `end <label>` (a transcript, for tests and logs).
#[derive(Clone, Default)]
pub struct Log(pub Rc<RefCell<Vec<String>>>);

struct LogBar(Rc<RefCell<Vec<String>>>, String);

impl Observer for Log {
    fn start(&self, label: &str, total: Option<u64>, unit: &str) -> Box<dyn Bar> {
        self.0.borrow_mut().push(format!("start {label} {total:?} {unit}"));
        Box::new(LogBar(self.0.clone(), label.to_string()))
    }
}

impl Bar for LogBar {
    fn update(&self, position: u64, message: &str) {
        self.0.borrow_mut().push(format!("{} {position} {message}", self.1));
    }
}

impl Drop for LogBar {
    fn drop(&mut self) {
        self.0.borrow_mut().push(format!("end {}", self.1));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::RefCell;

    #[test]
    fn tasks_reach_the_observer_of_their_thread_only() {
        let log = Rc::new(RefCell::new(Vec::new()));
        let unwatched = Task::start("before", Some(1), "x");
        assert!(!unwatched.watched());
        unwatched.set_with(1, || panic!("no message is made without an observer")).unwrap();
        observe(Rc::new(Log(log.clone())), || {
            let t = Task::start("periods", Some(3), "periods");
            t.set_with(2, || "settling 1e-3".into()).unwrap();
            std::thread::spawn(|| assert!(!Task::start("elsewhere", None, "x").watched())).join().unwrap();
        });
        assert!(!Task::start("after", None, "x").watched());
        assert_eq!(*log.borrow(), ["start periods Some(3) periods", "periods 2 settling 1e-3", "end periods"]);
    }

    #[test]
    fn a_cancelled_task_stops_at_its_next_step_on_its_thread_only() {
        let cancel = Cancel::new();
        let elsewhere = Task::start("unaffected", Some(2), "x");
        cancellable(cancel.clone(), || {
            let t = Task::start("periods", Some(3), "periods");
            t.set(1).unwrap();
            let other = cancel.clone();
            std::thread::spawn(move || other.cancel()).join().unwrap();
            assert!(matches!(t.set(2), Err(Error::Cancelled)));
            std::thread::spawn(|| Task::start("elsewhere", None, "x").set(1).unwrap()).join().unwrap();
        });
        elsewhere.set(1).unwrap();
        assert!(current_cancel().is_none());
    }
}
