//! Progress on long jobs: a bar (frames) or a spinner with the elapsed time (simulations,
//! comparisons, diagnoses), drawn on stderr by indicatif.
//!
//! Hidden when stderr is not a terminal (CI, pipes, files), under `--quiet`
//! ([`set_quiet`]), and when the command prints JSON, so machine-readable output is never
//! mixed with progress. A hidden progress costs nothing but a few atomic operations.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

static QUIET: AtomicBool = AtomicBool::new(false);

/// Hides every progress from now on (`--quiet`).
pub fn set_quiet(quiet: bool) {
    QUIET.store(quiet, Ordering::Relaxed);
}

/// True under `--quiet`.
pub fn is_quiet() -> bool {
    QUIET.load(Ordering::Relaxed)
}

/// Whether progress would be drawn: stderr is a terminal and not `--quiet`.
pub fn visible() -> bool {
    !is_quiet() && std::io::stderr().is_terminal()
}

/// A progress bar or spinner, cleared when dropped.
pub struct Progress(ProgressBar);

impl Progress {
    /// A bar of `len` steps called `what` (e.g. `frames`); hidden when `hidden` or not
    /// [`visible`].
    pub fn bar(len: u64, what: &str, hidden: bool) -> Self {
        let bar = ProgressBar::with_draw_target(Some(len), target(hidden));
        bar.set_style(
            ProgressStyle::with_template(
                "{msg} [{bar:30}] {pos}/{len} {elapsed_precise} (eta {eta})",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
        );
        bar.set_message(what.to_string());
        Self(bar)
    }

    /// A spinner saying `what` is being done, with the elapsed time; hidden when `hidden` or
    /// not [`visible`].
    pub fn spinner(what: &str, hidden: bool) -> Self {
        let bar = ProgressBar::with_draw_target(None, target(hidden));
        bar.set_style(
            ProgressStyle::with_template("{spinner} {msg} {elapsed}")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        bar.set_message(what.to_string());
        if !bar.is_hidden() {
            bar.enable_steady_tick(Duration::from_millis(120));
        }
        Self(bar)
    }

    /// Advances by `n` steps.
    pub fn inc(&self, n: u64) {
        self.0.inc(n);
    }

    /// Sets the position.
    pub fn set(&self, pos: u64) {
        self.0.set_position(pos);
    }

    /// True when nothing is drawn.
    pub fn is_hidden(&self) -> bool {
        self.0.is_hidden()
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.0.finish_and_clear();
    }
}

fn target(hidden: bool) -> ProgressDrawTarget {
    if hidden || !visible() {
        ProgressDrawTarget::hidden()
    } else {
        ProgressDrawTarget::stderr()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quiet_and_json_hide_progress() {
        let p = Progress::bar(10, "frames", true);
        assert!(p.is_hidden());
        p.inc(3);
        set_quiet(true);
        assert!(Progress::spinner("diagnosing", false).is_hidden());
        assert!(Progress::bar(5, "frames", false).is_hidden());
        set_quiet(false);
    }
}
