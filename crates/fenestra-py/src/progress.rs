//! A render's progress as the Python side polls it: the render thread counts, the thread
//! that holds the interpreter reads the counts and hands them to a callback.

use fenestra_render::Progress;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

/// Progress counted for polling.
#[derive(Default)]
pub struct Polled {
    /// Stages begun so far.
    stage: AtomicU64,
    /// The current stage's total (`u64::MAX`: unknown).
    total: AtomicU64,
    done: AtomicU64,
    notes: Mutex<Vec<String>>,
}

/// What a poll finds: (stage, units done, total if known, notes since the last poll).
pub type Reading = (u64, u64, Option<u64>, Vec<String>);

impl Polled {
    /// The counts now, and the notes given since the last reading.
    pub fn read(&self) -> Reading {
        let total = self.total.load(Ordering::Relaxed);
        let notes = self
            .notes
            .lock()
            .map(|mut n| std::mem::take(&mut *n))
            .unwrap_or_default();
        (
            self.stage.load(Ordering::Relaxed),
            self.done.load(Ordering::Relaxed),
            (total != u64::MAX).then_some(total),
            notes,
        )
    }
}

impl Progress for Polled {
    fn start(&self, total: Option<u64>) {
        self.done.store(0, Ordering::Relaxed);
        self.total
            .store(total.unwrap_or(u64::MAX), Ordering::Relaxed);
        self.stage.fetch_add(1, Ordering::Relaxed);
    }

    fn advance(&self, units: u64) {
        self.done.fetch_add(units, Ordering::Relaxed);
    }

    fn note(&self, text: &str) {
        if let Ok(mut notes) = self.notes.lock() {
            notes.push(text.to_string());
        }
    }
}
