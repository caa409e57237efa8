//! Work counted as it is done, by any thread: the CPU reference's phases
//! (its triangles set up, then its bands of rows), for a caller to show as
//! progress while the render runs (the CLI polls it).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

#[derive(Debug, Default)]
pub struct WorkCounter {
    phase: Mutex<&'static str>,
    done: AtomicU64,
    total: AtomicU64,
}

impl WorkCounter {
    /// Starts `phase` (what is counted: "triangles set up", "bands of
    /// rows"), of `total` units, none done.
    pub fn begin(&self, phase: &'static str, total: u64) {
        // Zero before the new total, so no reader sees the old count
        // against it.
        self.done.store(0, Ordering::Relaxed);
        self.total.store(total, Ordering::Relaxed);
        *self.phase.lock().unwrap_or_else(|e| e.into_inner()) = phase;
    }

    /// `n` more units done.
    pub fn add(&self, n: u64) {
        self.done.fetch_add(n, Ordering::Relaxed);
    }

    /// `(phase, done, total)`; `("", 0, 0)` before the work has begun.
    pub fn read(&self) -> (&'static str, u64, u64) {
        let phase = *self.phase.lock().unwrap_or_else(|e| e.into_inner());
        (
            phase,
            self.done.load(Ordering::Relaxed),
            self.total.load(Ordering::Relaxed),
        )
    }
}
