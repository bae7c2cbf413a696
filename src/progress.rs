//! Progress of long computations, for whoever watches.
//!
//! A solver announces a [`Task`] (a label, how many steps, what a step is) and moves it on;
//! what is shown is up to the [`Observer`] installed for the current thread with
//! [`observe`] — the command line's progress bars. Without one (sweep and optimiser
//! workers, the Python package, tests) a task is a no-op that costs one thread-local read,
//! so solvers report unconditionally and stay free of any terminal code.

use std::cell::RefCell;
use std::rc::Rc;

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
}

/// Runs `f` with `observer` watching this thread's tasks (the previous observer is restored
/// afterwards, also on a panic).
pub fn observe<T>(observer: Rc<dyn Observer>, f: impl FnOnce() -> T) -> T {
    struct Restore(Option<Rc<dyn Observer>>);
    impl Drop for Restore {
        fn drop(&mut self) {
            let prev = self.0.take();
            OBSERVER.with(|o| *o.borrow_mut() = prev);
        }
    }
    let _restore = Restore(OBSERVER.with(|o| o.borrow_mut().replace(observer)));
    f()
}

/// A running task: shown while it lives if an observer watches this thread.
pub struct Task {
    bar: Option<Box<dyn Bar>>,
}

impl Task {
    /// Begins a task of `total` steps (None: unknown) of `unit`.
    pub fn start(label: &str, total: Option<u64>, unit: &str) -> Task {
        let observer = OBSERVER.with(|o| o.borrow().clone());
        Task { bar: observer.map(|o| o.start(label, total, unit)) }
    }

    /// Whether anyone watches (messages that cost something to format are made only then).
    pub fn watched(&self) -> bool {
        self.bar.is_some()
    }

    /// `position` steps are done.
    pub fn set(&self, position: u64) {
        if let Some(b) = &self.bar {
            b.update(position, "");
        }
    }

    /// `position` steps are done; the message is made only if someone watches.
    pub fn set_with(&self, position: u64, message: impl FnOnce() -> String) {
        if let Some(b) = &self.bar {
            b.update(position, &message());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::RefCell;

    #[derive(Default)]
    struct Log(Rc<RefCell<Vec<String>>>);

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

    #[test]
    fn tasks_reach_the_observer_of_their_thread_only() {
        let log = Rc::new(RefCell::new(Vec::new()));
        let unwatched = Task::start("before", Some(1), "x");
        assert!(!unwatched.watched());
        unwatched.set_with(1, || panic!("no message is made without an observer"));
        observe(Rc::new(Log(log.clone())), || {
            let t = Task::start("periods", Some(3), "periods");
            t.set_with(2, || "settling 1e-3".into());
            std::thread::spawn(|| assert!(!Task::start("elsewhere", None, "x").watched())).join().unwrap();
        });
        assert!(!Task::start("after", None, "x").watched());
        assert_eq!(*log.borrow(), ["start periods Some(3) periods", "periods 2 settling 1e-3", "end periods"]);
    }
}
