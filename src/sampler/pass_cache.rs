//! Passes that are built whole: a small cache of the last built passes, shared by threads,
//! and the copies from a cached pass (point-major) into points and blocks.
//!
//! A Poisson-disk or best-candidate pass is known only once all of its points are placed, so
//! these samplers build a pass on first use, keep it here, and serve points from it by index.

use std::sync::{Arc, Mutex, OnceLock, PoisonError};

use super::{check_block, check_point, pass_runs};
use crate::error::Result;
use crate::points::Points;

/// A slot that one thread builds and every thread then shares.
type Slot = Arc<OnceLock<Arc<[f64]>>>;

/// The last few built passes, keyed by `(seed, pass)`, least recently used first.
///
/// Lookups hold the lock only to find or create a slot; the build itself runs in
/// [`OnceLock::get_or_init`] outside the lock, so threads building different passes run in
/// parallel while threads wanting the same pass wait for one build. The capacity is twice the
/// number of available threads (at least 4, at most 16): each worker's current pass and the
/// one it left. A slot that a thread is building (or waiting on) is never evicted, however
/// long ago it was asked for: dropping it would have the builder's work thrown away and done
/// again at its next lookup; the list then grows past its capacity until the builds end. A
/// poisoned lock (a panic elsewhere while it was held) is recovered: the list is always in a
/// valid state.
pub(super) struct PassCache {
    capacity: usize,
    entries: Mutex<Vec<(u64, u64, Slot)>>,
}

/// A clone starts empty: its passes are rebuilt where they are used, so copies of a sampler
/// neither share nor copy built passes.
impl Clone for PassCache {
    fn clone(&self) -> Self {
        PassCache::new()
    }
}

impl PassCache {
    pub(super) fn new() -> Self {
        let capacity = (2 * crate::threads::available_threads()).clamp(4, 16);
        PassCache {
            capacity,
            entries: Mutex::new(Vec::new()),
        }
    }

    /// The pass `(seed, pass)`, built by `build` if it is not cached.
    pub(super) fn get_or_build(
        &self,
        seed: u64,
        pass: u64,
        build: impl FnOnce() -> Vec<f64>,
    ) -> Arc<[f64]> {
        let slot = {
            let mut entries = self.entries.lock().unwrap_or_else(PoisonError::into_inner);
            match entries.iter().position(|e| e.0 == seed && e.1 == pass) {
                Some(at) => {
                    let entry = entries.remove(at);
                    let slot = Arc::clone(&entry.2);
                    entries.push(entry);
                    slot
                }
                None => {
                    evict_idle(&mut entries, self.capacity - 1);
                    let slot = Slot::default();
                    entries.push((seed, pass, Arc::clone(&slot)));
                    slot
                }
            }
        };
        Arc::clone(slot.get_or_init(|| Arc::from(build())))
    }

    /// Drops every cached pass.
    pub(super) fn clear(&mut self) {
        self.entries
            .get_mut()
            .unwrap_or_else(PoisonError::into_inner)
            .clear();
    }
}

/// Drops the least recently used entries that no thread is building or waiting on (the list
/// holds the only handle to their slot) until at most `keep` are left, or none is idle.
fn evict_idle(entries: &mut Vec<(u64, u64, Slot)>, keep: usize) {
    while entries.len() > keep {
        match entries.iter().position(|e| Arc::strong_count(&e.2) == 1) {
            Some(at) => {
                entries.remove(at);
            }
            None => return,
        }
    }
}

impl std::fmt::Debug for PassCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PassCache")
            .field("capacity", &self.capacity)
            .finish_non_exhaustive()
    }
}

/// Copies point `index` (of pass `index / pass_size`) from its cached pass into `out`, which
/// must hold `dims` values.
pub(super) fn point_from_passes(
    dims: usize,
    pass_size: u64,
    index: u64,
    out: &mut [f64],
    pass_points: impl FnOnce(u64) -> Arc<[f64]>,
) -> Result<()> {
    check_point(dims, out)?;
    let (pass, i) = (index / pass_size, (index % pass_size) as usize);
    let data = pass_points(pass);
    out.copy_from_slice(&data[i * dims..(i + 1) * dims]);
    Ok(())
}

/// Copies points `start ..` from cached passes (point-major) into a column-major block of
/// `dims` dimensions, fetching each pass once per run of indices that share it.
pub(super) fn fill_from_passes(
    dims: usize,
    pass_size: u64,
    start: u64,
    points: &mut Points,
    mut pass_points: impl FnMut(u64) -> Arc<[f64]>,
) -> Result<()> {
    check_block(dims, start, points)?;
    let len = points.len();
    let mut columns: Vec<&mut [f64]> = points.columns_mut().collect();
    for (i, pass, offset, run) in pass_runs(start, len, pass_size) {
        let data = pass_points(pass);
        let first = offset as usize;
        for (dim, column) in columns.iter_mut().enumerate() {
            for (k, x) in column[i..i + run].iter_mut().enumerate() {
                *x = data[(first + k) * dims + dim];
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pass being built stays cached while later passes come and go: the least recently
    /// asked-for slot is kept while a thread holds it, and idle ones go first.
    #[test]
    fn a_slot_being_built_is_not_evicted() {
        let mut entries: Vec<(u64, u64, Slot)> =
            (0..4).map(|pass| (0, pass, Slot::default())).collect();
        let building = Arc::clone(&entries[0].2);
        evict_idle(&mut entries, 2);
        let passes: Vec<u64> = entries.iter().map(|e| e.1).collect();
        assert_eq!(passes, [0, 3]);
        drop(building);
        evict_idle(&mut entries, 1);
        assert_eq!(entries.iter().map(|e| e.1).collect::<Vec<_>>(), [3]);
        // Nothing idle: the list stays over its capacity.
        let held = Arc::clone(&entries[0].2);
        evict_idle(&mut entries, 0);
        assert_eq!(entries.len(), 1);
        drop(held);
    }

    #[test]
    fn cache_recovers_from_a_poisoned_lock() {
        let cache = PassCache::new();
        // A panic while the lock is held poisons it.
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let _guard = cache.entries.lock();
            panic!("poison the lock");
        }));
        assert!(cache.entries.is_poisoned());
        assert_eq!(&*cache.get_or_build(1, 2, || vec![0.5]), &[0.5]);
        assert_eq!(&*cache.get_or_build(1, 2, || vec![0.25]), &[0.5]);
    }
}
