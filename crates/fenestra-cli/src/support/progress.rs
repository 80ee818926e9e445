//! The terminal progress bar of every long command (hidden when stderr is not a terminal);
//! notes are printed unless the command is quiet. Or progress as lines, for programs.

use fenestra_render::Progress;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::Instant;

/// A progress bar on stderr.
pub struct Bar {
    bar: ProgressBar,
    quiet: bool,
}

impl Bar {
    /// A bar drawn on a terminal unless `quiet`.
    pub fn new(quiet: bool) -> Self {
        let bar = ProgressBar::hidden();
        if !quiet && std::io::stderr().is_terminal() {
            bar.set_draw_target(ProgressDrawTarget::stderr());
        }
        Bar { bar, quiet }
    }

    /// Clears the bar from the terminal.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

impl Progress for Bar {
    fn start(&self, total: Option<u64>) {
        self.bar.reset();
        match total {
            Some(t) => {
                self.bar.set_length(t);
                self.bar.set_style(
                    ProgressStyle::with_template(
                        "{spinner} [{elapsed_precise}] {wide_bar} {percent}% ({eta} left)",
                    )
                    .unwrap_or_else(|_| ProgressStyle::default_bar()),
                );
            }
            None => self.bar.set_style(
                ProgressStyle::with_template(
                    "{spinner} [{elapsed_precise}] {human_pos} samples ({per_sec})",
                )
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
            ),
        }
    }

    fn advance(&self, units: u64) {
        self.bar.inc(units);
    }

    fn note(&self, text: &str) {
        if !self.quiet {
            self.bar.suspend(|| eprintln!("{text}"));
        }
    }
}

/// Progress as lines `progress DONE TOTAL SECONDS` on stderr (TOTAL `-` when the work is not
/// known in advance, as with --time), at most five a second and once at each stage's start:
/// for programs that run fenestra and show its progress themselves (the Blender add-on).
pub struct Lines {
    start: Instant,
    total: Mutex<Option<u64>>,
    done: AtomicU64,
    /// Milliseconds since `start` of the last line printed.
    last_ms: AtomicU64,
}

/// The least time between two progress lines.
const LINE_INTERVAL_MS: u64 = 200;

impl Default for Lines {
    fn default() -> Self {
        Lines {
            start: Instant::now(),
            total: Mutex::new(None),
            done: AtomicU64::new(0),
            last_ms: AtomicU64::new(0),
        }
    }
}

impl Lines {
    fn print(&self) {
        let total = match *self.total.lock().unwrap_or_else(|e| e.into_inner()) {
            Some(t) => t.to_string(),
            None => "-".into(),
        };
        let done = self.done.load(Ordering::Relaxed);
        let secs = self.start.elapsed().as_secs_f64();
        eprintln!("progress {done} {total} {secs:.3}");
    }
}

impl Progress for Lines {
    fn start(&self, total: Option<u64>) {
        *self.total.lock().unwrap_or_else(|e| e.into_inner()) = total;
        self.done.store(0, Ordering::Relaxed);
        self.print();
    }

    fn advance(&self, units: u64) {
        self.done.fetch_add(units, Ordering::Relaxed);
        let now = self.start.elapsed().as_millis() as u64;
        let last = self.last_ms.load(Ordering::Relaxed);
        // One thread of those that pass the interval prints.
        if now >= last + LINE_INTERVAL_MS
            && self
                .last_ms
                .compare_exchange(last, now, Ordering::Relaxed, Ordering::Relaxed)
                .is_ok()
        {
            self.print();
        }
    }

    fn note(&self, text: &str) {
        eprintln!("{text}");
    }
}
