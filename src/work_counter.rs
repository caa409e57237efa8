//! Work counted as it is done, by any thread: the CPU reference's rows, for
//! a caller to show as progress while the render runs (the CLI polls it).

use std::sync::atomic::{AtomicU64, Ordering};

#[derive(Debug, Default)]
pub struct WorkCounter {
    done: AtomicU64,
    total: AtomicU64,
}

impl WorkCounter {
    /// Starts a count of `total` units, none done.
    pub fn begin(&self, total: u64) {
        self.done.store(0, Ordering::Relaxed);
        self.total.store(total, Ordering::Relaxed);
    }

    /// `n` more units done.
    pub fn add(&self, n: u64) {
        self.done.fetch_add(n, Ordering::Relaxed);
    }

    /// `(done, total)`; `(0, 0)` before the work has counted its units.
    pub fn read(&self) -> (u64, u64) {
        (
            self.done.load(Ordering::Relaxed),
            self.total.load(Ordering::Relaxed),
        )
    }
}
