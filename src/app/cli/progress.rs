//! The command line's progress bars: the [`crate::progress`] tasks of the commands' own
//! thread, drawn on standard error (never with `--quiet` or when standard error is not a
//! terminal: `main` installs the observer only then). A bar appears only once its task
//! has run for [`DELAY`], whether or not it has reported a step since, so quick runs stay
//! as quiet as before and every longer one shows; nested tasks (a modal basis inside a
//! transient) stack below one another.

use crate::progress::{Bar, Observer};
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::sync::{Arc, Mutex, Weak};
use std::time::{Duration, Instant};

/// How long a task runs before its bar is drawn.
pub const DELAY: Duration = Duration::from_millis(500);

/// How often a shown bar redraws by itself, and how often waiting bars are looked at.
const TICK: Duration = Duration::from_millis(100);

/// Draws the tasks of the thread it observes. A task that runs past [`DELAY`] is shown
/// then, also when it reports no step for a long time (a run's figures, one period of a
/// fine transient): one thread looks at the waiting bars every [`TICK`], and a shown bar
/// keeps its spinner and elapsed time moving by itself.
pub struct ConsoleBars {
    multi: MultiProgress,
    waiting: Arc<Mutex<Vec<Weak<Shared>>>>,
}

impl ConsoleBars {
    pub fn new() -> Self {
        let multi = MultiProgress::with_draw_target(ProgressDrawTarget::stderr());
        let waiting: Arc<Mutex<Vec<Weak<Shared>>>> = Arc::default();
        let (watch, bars) = (Arc::downgrade(&waiting), multi.clone());
        // Ends with the observer (the list is gone) or the process.
        std::thread::spawn(move || {
            while let Some(waiting) = watch.upgrade() {
                std::thread::sleep(TICK);
                let mut list = waiting.lock().unwrap_or_else(|e| e.into_inner());
                list.retain(|w| w.upgrade().is_some_and(|bar| !bar.show_if_due(&bars)));
            }
        });
        ConsoleBars { multi, waiting }
    }
}

impl Default for ConsoleBars {
    fn default() -> Self {
        ConsoleBars::new()
    }
}

impl Observer for ConsoleBars {
    fn start(&self, label: &str, total: Option<u64>, unit: &str) -> Box<dyn Bar> {
        let unit = unit.replace('{', "{{").replace('}', "}}");
        let (bar, template) = match total {
            Some(n) => (
                ProgressBar::with_draw_target(Some(n), ProgressDrawTarget::hidden()),
                format!("{{spinner}} {{prefix}} [{{elapsed_precise}}] {{wide_bar}} {{pos}}/{{len}} {unit} {{msg}}"),
            ),
            // A task without steps (drawing figures) shows how long it has run.
            None if unit.is_empty() => (ProgressBar::hidden(), "{spinner} {prefix} [{elapsed_precise}] {msg}".into()),
            None => {
                (ProgressBar::hidden(), format!("{{spinner}} {{prefix}} [{{elapsed_precise}}] {{pos}} {unit} {{msg}}"))
            }
        };
        if let Ok(style) = ProgressStyle::with_template(&template) {
            bar.set_style(style);
        }
        bar.set_prefix(label.to_string());
        let shared = Arc::new(Shared { bar, started: Instant::now(), state: Mutex::default() });
        self.waiting.lock().unwrap_or_else(|e| e.into_inner()).push(Arc::downgrade(&shared));
        Box::new(ConsoleBar { shared, multi: self.multi.clone() })
    }
}

/// A bar, shared by its task and the thread that shows it when due.
struct Shared {
    bar: ProgressBar,
    started: Instant,
    state: Mutex<State>,
}

#[derive(Default)]
struct State {
    shown: bool,
    done: bool,
}

impl Shared {
    /// Shows the bar once its task has run for [`DELAY`]; whether it is shown (or done).
    fn show_if_due(&self, multi: &MultiProgress) -> bool {
        let mut state = self.state.lock().unwrap_or_else(|e| e.into_inner());
        if !state.shown && !state.done && self.started.elapsed() >= DELAY {
            state.shown = true;
            multi.add(self.bar.clone());
            self.bar.enable_steady_tick(TICK);
        }
        state.shown || state.done
    }
}

struct ConsoleBar {
    shared: Arc<Shared>,
    multi: MultiProgress,
}

impl Bar for ConsoleBar {
    fn update(&self, position: u64, message: &str) {
        let bar = &self.shared.bar;
        bar.set_position(position);
        if !message.is_empty() {
            bar.set_message(message.to_string());
        }
        self.shared.show_if_due(&self.multi);
    }
}

impl Drop for ConsoleBar {
    fn drop(&mut self) {
        let mut state = self.shared.state.lock().unwrap_or_else(|e| e.into_inner());
        state.done = true;
        self.shared.bar.finish_and_clear();
        if state.shown {
            self.multi.remove(&self.shared.bar);
        }
    }
}
