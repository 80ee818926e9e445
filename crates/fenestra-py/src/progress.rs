//! Long work run from Python: on a thread of its own, while the caller's thread (the one
//! Python delivers Ctrl-C to) looks for Ctrl-C and hands the work's progress to a callback.

use crate::FenestraError;
use fenestra_render::Progress;
use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::Duration;

/// How often the caller's thread looks for Ctrl-C and reports progress.
const POLL: Duration = Duration::from_millis(50);

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

/// How watched work ended: its result, and whether Ctrl-C stopped it.
pub struct Watched<T> {
    pub result: T,
    pub interrupted: bool,
}

/// Runs `work(cancel, progress)` on a thread of its own with the interpreter released; every
/// 50 ms the caller's thread hands `progress`'s reading to `callback` and looks for Ctrl-C.
/// Ctrl-C sets `cancel` (the work stops and keeps what it has); an exception from the
/// callback sets it too and is raised once the work has stopped.
pub fn watched<T: Send>(
    py: Python<'_>,
    callback: Option<&Py<PyAny>>,
    work: impl FnOnce(&AtomicBool, &Polled) -> T + Send,
) -> PyResult<Watched<T>> {
    let (cancel, polled) = (AtomicBool::new(false), Polled::default());
    let report = |py: Python<'_>| -> PyResult<()> {
        match callback {
            Some(callback) => callback.call1(py, polled.read()).map(drop),
            None => Ok(()),
        }
    };
    let mut stopped: Option<PyErr> = None;
    let result = std::thread::scope(|s| -> PyResult<T> {
        let working = s.spawn(|| work(&cancel, &polled));
        while !working.is_finished() {
            py.detach(|| std::thread::sleep(POLL));
            if let Err(e) = py.check_signals().and_then(|()| report(py)) {
                cancel.store(true, Ordering::Relaxed);
                stopped.get_or_insert(e);
            }
        }
        py.detach(|| working.join())
            .map_err(|_| FenestraError::new_err("fenestra panicked (a bug: please report it)"))
    })?;
    match stopped {
        Some(e) if !e.is_instance_of::<PyKeyboardInterrupt>(py) => Err(e),
        stopped => {
            report(py)?;
            Ok(Watched {
                result,
                interrupted: stopped.is_some(),
            })
        }
    }
}
