//! The watchdog: how long one queue submission may run before shadelab
//! gives up on it, and what it blames.
//!
//! Vulkan cannot cancel a submission. A shader that never ends (a lighting
//! hook's endless loop) keeps lavapipe's threads busy for ever, and a real
//! GPU's driver may take long to declare the device lost. So a fence is
//! waited for no longer than the limit; past it the device is marked stuck,
//! and from then on nothing made on it is destroyed or waited for (its
//! destructors would block on, or free memory under, the running shader):
//! the caller is expected to end the process (the CLI does, exit 3).
//!
//! The limit belongs to a render (its scene's `render.watchdog`) while the
//! waits happen deep in helpers that know no scene, so a renderer sets it
//! for its thread with [`watch`] around its work.

use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// A submission's limit where no render set one: long enough that no honest
/// submission comes near it (long work is batched into short submissions).
pub const DEFAULT_LIMIT: Duration = Duration::from_secs(120);

/// What the waits on this thread allow, and whom they blame.
#[derive(Debug, Clone)]
pub struct Watch {
    /// `None`: wait for ever.
    pub limit: Option<Duration>,
    /// The likely cause of a submission that does not end (a lighting
    /// hook, by its path), where the render knows one.
    pub cause: Option<Arc<str>>,
}

impl Default for Watch {
    fn default() -> Self {
        Watch {
            limit: Some(DEFAULT_LIMIT),
            cause: None,
        }
    }
}

thread_local! {
    static CURRENT: RefCell<Watch> = RefCell::new(Watch::default());
}

/// Set once any device is stuck: the process must not run the device's
/// destructors or wait for it at exit.
static ANY_STUCK: AtomicBool = AtomicBool::new(false);

/// Restores the thread's previous watch when dropped.
pub struct Guard {
    previous: Option<Watch>,
}

impl Drop for Guard {
    fn drop(&mut self) {
        if let Some(previous) = self.previous.take() {
            CURRENT.with(|c| *c.borrow_mut() = previous);
        }
    }
}

/// Sets this thread's watch until the guard is dropped.
pub fn watch(watch: Watch) -> Guard {
    let previous = CURRENT.with(|c| std::mem::replace(&mut *c.borrow_mut(), watch));
    Guard {
        previous: Some(previous),
    }
}

/// This thread's watch.
pub(crate) fn current() -> Watch {
    CURRENT.with(|c| c.borrow().clone())
}

/// The least limit a render's own estimate may tighten the watch to: a
/// shared, noisy machine can slow one batch several times over.
pub const TIGHTEST_LIMIT: Duration = Duration::from_secs(10);

/// How many times its expected time a batch may take before the watchdog
/// gives up on it, once the render has timed its first batch.
pub const EXPECTED_TIMES: u32 = 20;

/// The limit for a batch expected to take `expected` (from the render's
/// first batch): `EXPECTED_TIMES` that, at least `TIGHTEST_LIMIT`, and
/// never looser than `limit` (nor any limit where there is none).
pub fn tightened(limit: Option<Duration>, expected: Duration) -> Option<Duration> {
    let own = (expected * EXPECTED_TIMES).max(TIGHTEST_LIMIT);
    limit.map(|l| l.min(own))
}

/// The limit as `vkWaitForFences` takes it, in nanoseconds.
pub(crate) fn timeout_ns(limit: Option<Duration>) -> u64 {
    limit.map_or(u64::MAX, |l| {
        u64::try_from(l.as_nanos()).unwrap_or(u64::MAX)
    })
}

/// Records that a device is stuck, for [`any_device_stuck`].
pub(crate) fn mark_stuck() {
    ANY_STUCK.store(true, Ordering::SeqCst);
}

/// Whether a submission on any device of this process ran past its limit:
/// the process must end without waiting for the GPU (`std::process::exit`
/// runs the driver's exit handlers, which may wait for its threads).
pub fn any_device_stuck() -> bool {
    ANY_STUCK.load(Ordering::SeqCst)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_watch_holds_for_its_guard_and_nests() {
        assert_eq!(current().limit, Some(DEFAULT_LIMIT));
        {
            let _outer = watch(Watch {
                limit: Some(Duration::from_secs(2)),
                cause: Some("hook.glsl".into()),
            });
            {
                let _inner = watch(Watch {
                    limit: None,
                    cause: None,
                });
                assert_eq!(current().limit, None);
            }
            assert_eq!(current().limit, Some(Duration::from_secs(2)));
            assert_eq!(current().cause.as_deref(), Some("hook.glsl"));
        }
        assert_eq!(current().limit, Some(DEFAULT_LIMIT));
        assert_eq!(timeout_ns(None), u64::MAX);
        assert_eq!(timeout_ns(Some(Duration::from_secs(2))), 2_000_000_000);
    }

    /// After its first batch a render's later submissions are held to 20
    /// times their expected time, never under 10 s nor over the limit
    /// given, and not at all where none was given (`--watchdog 0`).
    #[test]
    fn a_render_tightens_its_limit_from_its_first_batch() {
        let s = Duration::from_secs;
        assert_eq!(
            tightened(Some(s(120)), Duration::from_millis(100)),
            Some(s(10))
        );
        assert_eq!(tightened(Some(s(120)), s(2)), Some(s(40)));
        assert_eq!(tightened(Some(s(120)), s(10)), Some(s(120)));
        assert_eq!(tightened(Some(s(5)), Duration::from_millis(1)), Some(s(5)));
        assert_eq!(tightened(None, s(1)), None);
    }
}
