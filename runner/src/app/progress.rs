//! A progress bar on stderr for the long headless commands (bench, soak, record),
//! through `indicatif` (hidden where stderr is not a terminal).

use indicatif::{ProgressBar, ProgressStyle};

/// A progress bar of `total` steps.
pub struct Progress {
    bar: ProgressBar,
}

impl Progress {
    /// Starts the clock and shows the bar.
    pub fn new(total: usize) -> Self {
        let bar = ProgressBar::new(total as u64);
        let style = ProgressStyle::with_template(
            "[{bar:30}] {pos}/{len} {elapsed}, {msg} (about {eta} left)",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("#>-");
        bar.set_style(style);
        Self { bar }
    }

    /// Moves the bar to `done` steps, with a word on what runs.
    pub fn show(&self, done: usize, what: &str) {
        self.bar.set_position(done as u64);
        self.bar.set_message(what.to_owned());
    }

    /// The full bar, left on the screen.
    pub fn done(&self, total: usize) {
        self.bar.set_position(total as u64);
        self.bar.finish_with_message("done");
    }

    /// Seconds since the start.
    pub fn seconds(&self) -> f64 {
        self.bar.elapsed().as_secs_f64()
    }
}
