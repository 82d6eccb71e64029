//! The progress bar of long runs (`render`, `sample`): on standard error, only on a terminal,
//! and only once the run has taken longer than [`PROGRESS_DELAY`], so quick runs print nothing.

use std::io::IsTerminal;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// How long a run goes before its progress bar appears.
pub const PROGRESS_DELAY: Duration = Duration::from_secs(1);

/// A progress bar counting units of work, updated from any thread.
pub struct DelayedProgress {
    bar: Option<ProgressBar>,
    started: Instant,
    shown: AtomicBool,
    show_lock: Mutex<()>,
}

impl DelayedProgress {
    /// A bar labelled `label` over `length` units (0 when not known yet); `wanted` is false for
    /// quiet runs.
    pub fn new(label: &str, length: u64, wanted: bool) -> Self {
        let bar = (wanted && std::io::stderr().is_terminal()).then(|| {
            let bar = ProgressBar::with_draw_target(Some(length), ProgressDrawTarget::hidden());
            if let Ok(style) = ProgressStyle::with_template(&format!(
                "{label} {{bar:40}} {{percent}}% ({{eta}} left)"
            )) {
                bar.set_style(style);
            }
            bar
        });
        Self {
            bar,
            started: Instant::now(),
            shown: AtomicBool::new(false),
            show_lock: Mutex::new(()),
        }
    }

    /// `n` more units to do, found on the way.
    pub fn add_length(&self, n: u64) {
        if let Some(bar) = &self.bar {
            bar.inc_length(n);
        }
    }

    /// `n` more units are done.
    pub fn inc(&self, n: u64) {
        let Some(bar) = &self.bar else {
            return;
        };
        bar.inc(n);
        if !self.shown.load(Ordering::Relaxed) && self.started.elapsed() > PROGRESS_DELAY {
            let _guard = self.show_lock.lock();
            if !self.shown.swap(true, Ordering::Relaxed) {
                bar.set_draw_target(ProgressDrawTarget::stderr());
            }
        }
    }

    /// Clears the bar from the terminal.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}
