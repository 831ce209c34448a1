//! The progress bar of `tracer render`: [`tracer::Progress`] drawn by indicatif on
//! the terminal's standard error (hidden when it is not a terminal).

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use tracer::Progress;

/// A progress bar with ETA.
pub struct Bar(ProgressBar);

impl Bar {
    /// A bar on standard error; indicatif draws nothing when it is not a terminal.
    pub fn stderr() -> Self {
        let bar = ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::stderr());
        if let Ok(style) =
            ProgressStyle::with_template("{bar:40} {pos}/{len} rows, {elapsed} elapsed, ETA {eta}")
        {
            bar.set_style(style);
        }
        Self(bar)
    }
}

impl Progress for Bar {
    fn add_rows(&self, rows: u64) {
        self.0.inc_length(rows);
    }

    fn advance(&self, rows: u64) {
        self.0.inc(rows);
    }

    fn finish(&self) {
        self.0.finish_and_clear();
    }
}
