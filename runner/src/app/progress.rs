//! A progress bar on stderr, for the long headless commands (bench, soak).

use std::io::Write;
use std::time::Instant;

/// A progress bar of `total` steps.
pub struct Progress {
    total: usize,
    start: Instant,
}

impl Progress {
    /// Starts the clock.
    pub fn new(total: usize) -> Self {
        Self {
            total,
            start: Instant::now(),
        }
    }

    /// Redraws the bar at `done` steps, with a word on what runs.
    pub fn show(&self, done: usize, what: &str) {
        let width = 30;
        let filled = (done * width / self.total.max(1)).min(width);
        eprint!(
            "\r[{}{}] {done}/{} {:.0} s, {what}          ",
            "#".repeat(filled),
            "-".repeat(width - filled),
            self.total,
            self.start.elapsed().as_secs_f64()
        );
        let _ = std::io::stderr().flush();
    }

    /// The full bar, and a new line.
    pub fn done(&self, total: usize) {
        self.show(total, "done");
        eprintln!();
    }

    /// Seconds since the start.
    pub fn seconds(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }
}
