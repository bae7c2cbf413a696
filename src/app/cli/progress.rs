//! The command line's progress bars: the [`crate::progress`] tasks of the commands' own
//! thread, drawn on standard error (never with `--quiet` or when standard error is not a
//! terminal: `main` installs the observer only then). A bar appears only once its task
//! has run for [`DELAY`], so quick runs stay as quiet as before; nested tasks (a modal
//! basis inside a transient) stack below one another.

use crate::progress::{Bar, Observer};
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::cell::Cell;
use std::time::{Duration, Instant};

/// How long a task runs before its bar is drawn.
pub const DELAY: Duration = Duration::from_millis(500);

/// Draws the tasks of the thread it observes.
pub struct ConsoleBars {
    multi: MultiProgress,
}

impl ConsoleBars {
    pub fn new() -> Self {
        ConsoleBars { multi: MultiProgress::with_draw_target(ProgressDrawTarget::stderr()) }
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
            None => {
                (ProgressBar::hidden(), format!("{{spinner}} {{prefix}} [{{elapsed_precise}}] {{pos}} {unit} {{msg}}"))
            }
        };
        if let Ok(style) = ProgressStyle::with_template(&template) {
            bar.set_style(style);
        }
        bar.set_prefix(label.to_string());
        Box::new(ConsoleBar { bar, multi: self.multi.clone(), started: Instant::now(), shown: Cell::new(false) })
    }
}

struct ConsoleBar {
    bar: ProgressBar,
    multi: MultiProgress,
    started: Instant,
    shown: Cell<bool>,
}

impl Bar for ConsoleBar {
    fn update(&self, position: u64, message: &str) {
        self.bar.set_position(position);
        if !message.is_empty() {
            self.bar.set_message(message.to_string());
        }
        if !self.shown.get() && self.started.elapsed() >= DELAY {
            self.shown.set(true);
            self.multi.add(self.bar.clone());
        }
    }
}

impl Drop for ConsoleBar {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
        if self.shown.get() {
            self.multi.remove(&self.bar);
        }
    }
}
