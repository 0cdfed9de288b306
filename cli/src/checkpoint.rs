//! `integrate --checkpoint FILE`: a fixed-budget run saved to FILE every few chunks and
//! resumed from it, with the same result as an uninterrupted run.
//!
//! Saves are atomic: the checkpoint is written to a temporary file `.NAME.tmp` in the same
//! directory, synced to disk, and renamed over FILE, so a process killed at any moment leaves
//! either the previous checkpoint or the new one. A symbolic link FILE is followed: saves
//! replace its target and keep the link. While a process runs from FILE it holds an advisory
//! lock on `.NAME.lock` beside it, so a second process on the same checkpoint is refused instead
//! of racing the first to the last save; holding it, it removes the temporary files of saves
//! killed midway. FILE, if it exists, must be a regular file: a pipe such as `/dev/stdout` would
//! block the read forever. A checkpoint is read up to [`MAX_CHECKPOINT_BYTES`]; the library
//! refuses a corrupted one (its checksum), an impossible one (its counts) or one of another run
//! (its fingerprint, which includes the integrand's label).

use crate::note;
use mcint::estimator::{Estimator, VectorEstimator};
use mcint::stats::StopReason;
use mcint::{CancelToken, Integrator, PartialRun, VectorEstimate, VectorRun};
use std::fs::{File, OpenOptions, TryLockError};
use std::io::{ErrorKind, Read, Write};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The largest checkpoint read: a checkpoint holds one accumulator per replicate and the
/// chunks finished out of order, far below this.
pub const MAX_CHECKPOINT_BYTES: u64 = 64 << 20;

/// Chunks (of 16384 points) evaluated between two saves.
pub const DEFAULT_SAVE_EVERY: u64 = 16;

/// `--checkpoint FILE [--save-every K] [--stop-after K]`.
pub struct Settings {
    pub path: PathBuf,
    pub save_every: u64,
    pub stop_after: Option<u64>,
    /// `--time-limit`: the instant the run stops by, leaving the checkpoint.
    pub deadline: Option<std::time::Instant>,
    /// The ranks of an MPI job, whose rank 0 writes the checkpoint and says so (all ranks
    /// hold the same part), or this process alone.
    pub spread: crate::ranks::Spread,
}

/// A run that can be split into parts: the scalar and the vector Integrator, each giving
/// every output's estimate.
pub trait Checkpointed {
    fn run_part(&self, range: Range<u64>) -> mcint::Result<PartialRun>;
    fn resume(&self, part: &mut PartialRun, max_chunks: u64) -> mcint::Result<()>;
    fn finish(&self, part: &PartialRun) -> mcint::Result<VectorEstimate>;
}

impl<E: Estimator> Checkpointed for Integrator<E> {
    fn run_part(&self, range: Range<u64>) -> mcint::Result<PartialRun> {
        <Integrator<E>>::run_part(self, range)
    }
    fn resume(&self, part: &mut PartialRun, max_chunks: u64) -> mcint::Result<()> {
        <Integrator<E>>::resume(self, part, max_chunks)
    }
    fn finish(&self, part: &PartialRun) -> mcint::Result<VectorEstimate> {
        <Integrator<E>>::finish(self, part).map(VectorEstimate::from)
    }
}

/// The vector Integrator, wrapped: a blanket implementation for it next to the scalar one
/// would overlap in the compiler's eyes.
pub struct VectorCheckpoint<E>(pub Integrator<VectorRun<E>>);

impl<E: VectorEstimator> Checkpointed for VectorCheckpoint<E> {
    fn run_part(&self, range: Range<u64>) -> mcint::Result<PartialRun> {
        self.0.run_part(range)
    }
    fn resume(&self, part: &mut PartialRun, max_chunks: u64) -> mcint::Result<()> {
        self.0.resume(part, max_chunks)
    }
    fn finish(&self, part: &PartialRun) -> mcint::Result<VectorEstimate> {
        self.0.finish(part)
    }
}

/// A checkpointed run that stopped before its last chunk, as `--json` reports it: it was
/// not finished, why it stopped, and the chunks saved so far.
#[derive(Debug, serde::Serialize)]
pub struct Unfinished {
    pub finished: bool,
    pub stop: &'static str,
    pub chunks_done: u64,
    pub total_chunks: u64,
}

impl Unfinished {
    fn of(part: &PartialRun, stop: &'static str) -> Unfinished {
        Unfinished {
            finished: false,
            stop,
            chunks_done: part.chunks_done(),
            total_chunks: part.total_chunks(),
        }
    }
}

/// Runs `integrator` from the checkpoint in `settings.path` (or from the start), saving after
/// every `save_every` chunks. Stops early after `stop_after` chunks, if given, or at the
/// deadline or a cancellation, leaving the checkpoint for the next call: an [`Unfinished`]
/// then.
pub fn run(
    integrator: &dyn Checkpointed,
    settings: &Settings,
    cancel: &CancelToken,
) -> Result<Result<VectorEstimate, Unfinished>, String> {
    let (path, save_every, stop_after) = (
        settings.path.as_path(),
        settings.save_every,
        settings.stop_after,
    );
    check_kind(path)?;
    let target =
        resolve(path).map_err(|e| format!("cannot follow checkpoint '{}': {e}", path.display()))?;
    // The process that saves holds the lock; every rank stops if it cannot.
    let lock = settings.spread.is_root().then(|| Lock::take(&target, path));
    if settings.spread.any(matches!(lock, Some(Err(_)))) {
        return Err(match lock {
            Some(Err(e)) => e,
            _ => format!("checkpoint '{}' is locked on rank 0", path.display()),
        });
    }
    if lock.is_some() {
        remove_stale_temporaries(&target);
    }
    // Reads and saves go to the link's target; messages name the path as given.
    let settings = &Settings {
        path: target,
        ..*settings
    };
    let mut fresh = false;
    let mut part = match read_bounded(&settings.path) {
        Ok(text) => {
            let part: PartialRun = serde_json::from_str(&text)
                .map_err(|e| format!("cannot read checkpoint '{}': {e}", path.display()))?;
            // A part of another run is refused by the first resume, before it is saved.
            if part.is_complete() {
                return integrator.finish(&part).map(Ok).map_err(|e| {
                    format!(
                        "checkpoint '{}' holds a finished run these flags cannot report ({}); \
                         delete it or repeat the flags of its run",
                        path.display(),
                        crate::args::flag_error(e)
                    )
                });
            }
            part
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            fresh = true;
            let first = integrator.run_part(0..1).map_err(crate::args::flag_error)?;
            save(settings, &first)?;
            first
        }
        Err(e) => return Err(format!("cannot read checkpoint '{}': {e}", path.display())),
    };
    let mut budget = stop_after.map(|n| n.saturating_sub(u64::from(fresh)));
    while !part.is_complete() {
        let step = budget.map_or(save_every, |left| left.min(save_every));
        if step == 0 {
            say(
                settings,
                format!(
                    "checkpoint: {} of {} chunks saved in '{}'; run the same command again to continue",
                    part.chunks_done(),
                    part.total_chunks(),
                    path.display()
                ),
            );
            return Ok(Err(Unfinished::of(&part, "stop after")));
        }
        integrator.resume(&mut part, step).map_err(|e| {
            format!(
                "checkpoint '{}' cannot continue with these flags ({e}); delete it or repeat \
                 the flags of its run",
                path.display()
            )
        })?;
        budget = budget.map(|left| left - step);
        save(settings, &part)?;
        // Every rank stops after the same step, even if the signal (or the clock) reached
        // some later.
        let late = settings
            .deadline
            .is_some_and(|deadline| Instant::now() >= deadline);
        let (why, stop) = if settings.spread.any(cancel.is_cancelled()) {
            ("cancelled", StopReason::Cancelled)
        } else if settings.spread.any(late) {
            ("time limit reached", StopReason::TimeLimit)
        } else {
            continue;
        };
        say(
            settings,
            format!(
                "checkpoint: {why}; {} of {} chunks saved in '{}'; run the same command again \
                 to continue",
                part.chunks_done(),
                part.total_chunks(),
                path.display()
            ),
        );
        return Ok(Err(Unfinished::of(&part, stop.name())));
    }
    integrator
        .finish(&part)
        .map(Ok)
        .map_err(crate::args::flag_error)
}

/// The text of the checkpoint `path`, or `None` when there is none yet: a path that is not a
/// regular file, or a file larger than [`MAX_CHECKPOINT_BYTES`], is refused.
pub fn read_text(path: &Path) -> Result<Option<String>, String> {
    check_kind(path)?;
    match read_bounded(path) {
        Ok(text) => Ok(Some(text)),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(format!("cannot read checkpoint '{}': {e}", path.display())),
    }
}

/// The text of `path`, refusing a file larger than [`MAX_CHECKPOINT_BYTES`] (such as
/// `/dev/zero`) without reading more than that.
fn read_bounded(path: &Path) -> std::io::Result<String> {
    let mut text = String::new();
    std::fs::File::open(path)?
        .take(MAX_CHECKPOINT_BYTES + 1)
        .read_to_string(&mut text)?;
    if text.len() as u64 > MAX_CHECKPOINT_BYTES {
        return Err(std::io::Error::other(format!(
            "larger than {MAX_CHECKPOINT_BYTES} bytes, which no checkpoint is"
        )));
    }
    Ok(text)
}

/// Prints `message` on stderr from the process that saves.
fn say(settings: &Settings, message: String) {
    if settings.spread.is_root() {
        note!("{message}");
    }
}

/// Saves `part` to the checkpoint (from the process that saves; see `write`).
fn save(settings: &Settings, part: &PartialRun) -> Result<(), String> {
    if !settings.spread.is_root() {
        return Ok(());
    }
    write(&settings.path, part)
}

/// Writes the checkpoint to its temporary file next to `path`, syncs it and renames it into
/// place, so an interrupted save never leaves a truncated checkpoint.
fn write(path: &Path, part: &PartialRun) -> Result<(), String> {
    let text = serde_json::to_string(part).map_err(|e| format!("cannot encode checkpoint: {e}"))?;
    write_text(path, &text)
}

/// Writes `text` to the checkpoint `path` atomically (see `write`): for the programs whose
/// checkpoints are not partial runs (`mlmc`).
pub fn write_text(path: &Path, text: &str) -> Result<(), String> {
    let temporary = beside(path, "tmp");
    let written = (|| {
        let mut file = File::create(&temporary)?;
        file.write_all(text.as_bytes())?;
        file.sync_all()?;
        std::fs::rename(&temporary, path)?;
        // The rename itself reaches the disk with the directory.
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            File::open(dir)?.sync_all()?;
        }
        Ok::<(), std::io::Error>(())
    })();
    written.map_err(|e| {
        let _ = std::fs::remove_file(&temporary);
        format!("cannot write checkpoint '{}': {e}", path.display())
    })
}

/// `.NAME.EXTENSION` next to the checkpoint `path`: its temporary file (one at a time, under
/// the lock) and its lock file.
fn beside(path: &Path, extension: &str) -> PathBuf {
    let name = path
        .file_name()
        .map_or("checkpoint".into(), |n| n.to_string_lossy());
    path.with_file_name(format!(".{name}.{extension}"))
}

/// Refuses a checkpoint `path` that exists and is not a regular file: a directory, a device,
/// or a pipe such as `/dev/stdout`, whose read would never end.
fn check_kind(path: &Path) -> Result<(), String> {
    let what = crate::input::irregular(path)
        .map_err(|e| format!("cannot read checkpoint '{}': {e}", path.display()))?;
    match what {
        None => Ok(()),
        Some(what) => Err(format!(
            "checkpoint '{}' is {what}: --checkpoint takes a regular file, or a path where one \
             can be created",
            path.display()
        )),
    }
}

/// `path` with symbolic links followed to the file they name, which may not exist yet: saves
/// replace that file and keep the links.
fn resolve(path: &Path) -> std::io::Result<PathBuf> {
    let mut path = path.to_path_buf();
    // As many links as Linux follows in one path.
    for _ in 0..40 {
        match std::fs::symlink_metadata(&path) {
            Ok(meta) if meta.file_type().is_symlink() => {
                let target = std::fs::read_link(&path)?;
                // A relative target is relative to the link's directory.
                path = path.parent().unwrap_or(Path::new("")).join(target);
            }
            _ => return Ok(path),
        }
    }
    Err(std::io::Error::other("too many levels of symbolic links"))
}

/// An exclusive advisory lock on the checkpoint's `.NAME.lock`, held while a process runs
/// from the checkpoint and saves it. The system releases it when the process ends, however it
/// ends; the file is removed when the run ends.
struct Lock {
    _file: File,
    path: PathBuf,
}

impl Lock {
    /// Locks the lock file of the checkpoint at `target` (`shown` as given), or refuses with a
    /// one-line message when another process holds it.
    fn take(target: &Path, shown: &Path) -> Result<Lock, String> {
        let path = beside(target, "lock");
        let cannot = |e: std::io::Error| {
            format!(
                "cannot lock checkpoint '{}' with '{}': {e}",
                shown.display(),
                path.display()
            )
        };
        // A run that ends removes its lock file, maybe just after this process opened it:
        // the lock then holds a file no other process will find, so lock the new one.
        for _ in 0..100 {
            let file = OpenOptions::new()
                .write(true)
                .create(true)
                .truncate(false)
                .open(&path)
                .map_err(cannot)?;
            match file.try_lock() {
                Ok(()) => {}
                Err(TryLockError::WouldBlock) => {
                    return Err(format!(
                        "checkpoint '{}' is in use by another process, which holds its lock \
                         '{}': let that run end, or give another --checkpoint",
                        shown.display(),
                        path.display()
                    ));
                }
                Err(TryLockError::Error(e)) => return Err(cannot(e)),
            }
            if still_named(&file, &path).map_err(cannot)? {
                return Ok(Lock { _file: file, path });
            }
        }
        Err(cannot(std::io::Error::other(
            "other processes keep replacing it",
        )))
    }
}

impl Drop for Lock {
    fn drop(&mut self) {
        // Removed while still locked, so no process locks it in between (see `take`); where
        // that cannot be checked, the file stays.
        if cfg!(unix) {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

/// Whether `file` is still the file at `path`.
#[cfg(unix)]
fn still_named(file: &File, path: &Path) -> std::io::Result<bool> {
    use std::os::unix::fs::MetadataExt;
    let held = file.metadata()?;
    match std::fs::metadata(path) {
        Ok(named) => Ok((named.dev(), named.ino()) == (held.dev(), held.ino())),
        Err(e) if e.kind() == ErrorKind::NotFound => Ok(false),
        Err(e) => Err(e),
    }
}

#[cfg(not(unix))]
fn still_named(_: &File, _: &Path) -> std::io::Result<bool> {
    Ok(true)
}

/// Removes the temporary files of the checkpoint at `target` that saves killed midway left
/// (the lock is held: no other process is saving it): `.NAME.tmp`, and the
/// `.NAME.PID.N.tmp` of earlier versions.
fn remove_stale_temporaries(target: &Path) {
    let Some(name) = target.file_name().and_then(|n| n.to_str()) else {
        return;
    };
    let prefix = format!(".{name}");
    let dir = target
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let file = entry.file_name();
        let Some(middle) = file
            .to_str()
            .and_then(|f| f.strip_prefix(&prefix))
            .and_then(|f| f.strip_suffix(".tmp"))
        else {
            continue;
        };
        let numbers = |ids: &str| {
            ids.split('.')
                .all(|id| !id.is_empty() && id.bytes().all(|b| b.is_ascii_digit()))
        };
        if middle.is_empty() || middle.strip_prefix('.').is_some_and(numbers) {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}
