//! What the crate knows of threads: how many the machine offers, and the caches that a thread
//! keeps between fills.
//!
//! A module that keeps a per-thread cache (Owen-scrambled Halton's node tables) registers it
//! here when a thread first fills it; the engine, when a run ends, asks whether any thread may
//! hold one and releases them on every thread it ran on. So the engine knows no cache, and no
//! cache knows the engine.

use std::sync::{Mutex, PoisonError};

/// The number of threads the machine offers (1 if it cannot tell).
pub(crate) fn available_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// A cache that threads keep between fills.
pub(crate) struct ThreadCache {
    /// Whether some thread may hold this cache (cheap: asked at the end of every run).
    pub(crate) held: fn() -> bool,
    /// Frees the calling thread's cache (nothing if it holds none).
    pub(crate) release: fn(),
}

/// The caches registered so far.
static CACHES: Mutex<Vec<&'static ThreadCache>> = Mutex::new(Vec::new());

/// Registers `cache` (once: registering it again changes nothing).
pub(crate) fn register(cache: &'static ThreadCache) {
    let mut caches = CACHES.lock().unwrap_or_else(PoisonError::into_inner);
    if !caches.iter().any(|c| std::ptr::eq(*c, cache)) {
        caches.push(cache);
    }
}

/// Whether some thread may hold a registered cache.
pub(crate) fn caches_held() -> bool {
    registered().iter().any(|c| (c.held)())
}

/// Frees the calling thread's registered caches.
pub(crate) fn release_caches() {
    for cache in registered() {
        (cache.release)();
    }
}

/// A copy of the list, so that no lock is held while a cache runs.
fn registered() -> Vec<&'static ThreadCache> {
    CACHES
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .clone()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;
    use std::sync::atomic::{AtomicUsize, Ordering};

    thread_local! {
        static HELD: Cell<bool> = const { Cell::new(false) };
    }
    static HOLDERS: AtomicUsize = AtomicUsize::new(0);

    fn held() -> bool {
        HOLDERS.load(Ordering::Relaxed) > 0
    }

    fn release() {
        if HELD.with(|h| h.replace(false)) {
            HOLDERS.fetch_sub(1, Ordering::Relaxed);
        }
    }

    static CACHE: ThreadCache = ThreadCache { held, release };

    #[test]
    fn a_registered_cache_is_seen_and_released_once_however_often_registered() {
        register(&CACHE);
        register(&CACHE);
        let ours = registered()
            .iter()
            .filter(|c| std::ptr::eq(**c, &CACHE))
            .count();
        assert_eq!(ours, 1);
        HELD.with(|h| h.set(true));
        HOLDERS.fetch_add(1, Ordering::Relaxed);
        assert!(caches_held());
        release_caches();
        assert!(!held());
        assert!(!HELD.with(Cell::get));
    }
}
