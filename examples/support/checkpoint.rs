//! `integrate --checkpoint FILE`: a fixed-budget run saved to FILE every few chunks and
//! resumed from it, with the same result as an uninterrupted run.

use mcint::estimator::Estimator;
use mcint::{Estimate, Integrator, PartialRun};
use std::path::Path;

/// Chunks (of 16384 points) evaluated between two saves.
pub const DEFAULT_SAVE_EVERY: u64 = 16;

/// Runs `integrator` from the checkpoint in `path` (or from the start), saving after every
/// `save_every` chunks. Stops early after `stop_after` chunks, if given, leaving the
/// checkpoint for the next call: `Ok(None)` then.
pub fn run<E: Estimator>(
    integrator: &Integrator<E>,
    path: &Path,
    save_every: u64,
    stop_after: Option<u64>,
) -> Result<Option<Estimate>, String> {
    let mut fresh = false;
    let mut part = match std::fs::read_to_string(path) {
        Ok(text) => {
            let part: PartialRun = serde_json::from_str(&text)
                .map_err(|e| format!("cannot read checkpoint '{}': {e}", path.display()))?;
            // A part of another run is refused by the first resume, before it is saved.
            if part.is_complete() {
                return integrator
                    .finish(&part)
                    .map(Some)
                    .map_err(|e| e.to_string());
            }
            part
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            fresh = true;
            let first = integrator.run_part(0..1).map_err(|e| e.to_string())?;
            save(path, &first)?;
            first
        }
        Err(e) => return Err(format!("cannot read checkpoint '{}': {e}", path.display())),
    };
    let mut budget = stop_after.map(|n| n.saturating_sub(u64::from(fresh)));
    while !part.is_complete() {
        let step = budget.map_or(save_every, |left| left.min(save_every));
        if step == 0 {
            eprintln!(
                "checkpoint: {} of {} chunks saved in '{}'; run the same command again to continue",
                part.chunks_done(),
                part.total_chunks(),
                path.display()
            );
            return Ok(None);
        }
        integrator.resume(&mut part, step).map_err(|e| {
            format!(
                "checkpoint '{}' cannot continue with these flags ({e}); delete it or repeat \
                 the flags of its run",
                path.display()
            )
        })?;
        budget = budget.map(|left| left - step);
        save(path, &part)?;
    }
    integrator
        .finish(&part)
        .map(Some)
        .map_err(|e| e.to_string())
}

/// Writes the checkpoint next to `path` and renames it into place, so an interrupted write
/// never leaves a truncated checkpoint.
fn save(path: &Path, part: &PartialRun) -> Result<(), String> {
    let text = serde_json::to_string(part).map_err(|e| format!("cannot encode checkpoint: {e}"))?;
    let temporary = path.with_extension("partial");
    std::fs::write(&temporary, text)
        .and_then(|()| std::fs::rename(&temporary, path))
        .map_err(|e| format!("cannot write checkpoint '{}': {e}", path.display()))
}
