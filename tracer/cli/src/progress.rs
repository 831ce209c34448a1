//! What `tracer render` tells the user while it works, on standard error: on a terminal
//! a progress bar (indicatif) through parsing, building and tracing, then a one-line
//! summary; elsewhere nothing, unless asked for plain lines (for logs); with `--quiet`
//! nothing at all. Errors and warnings are printed whatever this says.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};
use tracer::Progress;

/// How progress is shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Nothing.
    Silent,
    /// A progress bar redrawn in place (a terminal).
    Bar,
    /// Plain lines, at most one a second while tracing (a log).
    Lines,
}

impl Mode {
    /// The mode for `--quiet` and `--progress` with standard error a terminal or not:
    /// `--quiet` silences everything; a terminal gets the bar; elsewhere only
    /// `--progress` prints, as lines.
    pub fn choose(quiet: bool, progress: bool, terminal: bool) -> Self {
        match (quiet, terminal, progress) {
            (true, _, _) => Self::Silent,
            (false, true, _) => Self::Bar,
            (false, false, true) => Self::Lines,
            (false, false, false) => Self::Silent,
        }
    }

    /// [`Mode::choose`] for this process's standard error.
    pub fn for_stderr(quiet: bool, progress: bool) -> Self {
        Self::choose(quiet, progress, std::io::stderr().is_terminal())
    }
}

/// The bar's look before tracing (parsing, building): a spinner and the time so far.
const SPINNER: &str = "{msg:9} {spinner} {elapsed} elapsed";
/// The bar's look from tracing on.
const BAR: &str = "{msg:9} {bar:40} {pos}/{len} rows, {elapsed} elapsed, ETA {eta}";

fn set_template(bar: &ProgressBar, template: &str) {
    if let Ok(style) = ProgressStyle::with_template(template) {
        bar.set_style(style);
    }
}

/// Progress through the phases of a render, shown as [`Mode`] says.
pub struct Feedback {
    mode: Mode,
    bar: Option<ProgressBar>,
    start: Instant,
    done: AtomicU64,
    len: AtomicU64,
    last_line: Mutex<Instant>,
}

impl Feedback {
    /// Starts showing progress in `mode`.
    pub fn new(mode: Mode) -> Self {
        let bar = (mode == Mode::Bar).then(|| {
            let bar = ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::stderr());
            set_template(&bar, SPINNER);
            bar.enable_steady_tick(Duration::from_millis(200));
            bar
        });
        let now = Instant::now();
        Self {
            mode,
            bar,
            start: now,
            done: AtomicU64::new(0),
            len: AtomicU64::new(0),
            last_line: Mutex::new(now),
        }
    }

    /// The mode shown in.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// A new phase begins: `name` (`parsing`, `building`, `tracing`) and what it works on.
    pub fn phase(&self, name: &str, detail: &str) {
        match self.mode {
            Mode::Silent => {}
            Mode::Bar => {
                if let Some(bar) = &self.bar {
                    // Rows are counted from the first traced; before, a spinner.
                    if name == "tracing" {
                        set_template(bar, BAR);
                    }
                    bar.set_message(name.to_string());
                }
            }
            Mode::Lines => eprintln!("{:.1} s: {name} {detail}", self.secs()),
        }
    }

    /// Seconds since the start.
    fn secs(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }

    /// Clears the bar and prints the closing `line` (not when silent).
    pub fn summary(&self, line: &str) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
        if self.mode != Mode::Silent {
            eprintln!("{line}");
        }
    }

    /// Prints a warning, whatever the mode (above the bar, if there is one).
    pub fn warn(&self, line: &str) {
        match &self.bar {
            Some(bar) => bar.suspend(|| eprintln!("{line}")),
            None => eprintln!("{line}"),
        }
    }

    /// Clears the bar without a summary (on an error).
    pub fn abandon(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

impl Drop for Feedback {
    fn drop(&mut self) {
        self.abandon();
    }
}

impl Progress for Feedback {
    fn add_rows(&self, rows: u64) {
        self.len.fetch_add(rows, Ordering::Relaxed);
        if let Some(bar) = &self.bar {
            bar.inc_length(rows);
        }
    }

    fn advance(&self, rows: u64) {
        let done = self.done.fetch_add(rows, Ordering::Relaxed) + rows;
        if let Some(bar) = &self.bar {
            bar.inc(rows);
        }
        if self.mode == Mode::Lines {
            let mut last = self.last_line.lock().unwrap_or_else(|e| e.into_inner());
            if last.elapsed() >= Duration::from_secs(1) {
                *last = Instant::now();
                let len = self.len.load(Ordering::Relaxed);
                eprintln!("{:.1} s: tracing, {done} of {len} rows", self.secs());
            }
        }
    }

    fn finish(&self) {
        if self.mode == Mode::Lines {
            eprintln!("{:.1} s: traced", self.secs());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modes() {
        assert_eq!(Mode::choose(false, false, true), Mode::Bar);
        assert_eq!(Mode::choose(false, true, true), Mode::Bar);
        assert_eq!(Mode::choose(true, false, true), Mode::Silent);
        assert_eq!(Mode::choose(false, false, false), Mode::Silent);
        assert_eq!(Mode::choose(false, true, false), Mode::Lines);
    }
}
