//! `Failure`: the first exception that stops a run (the user's function raising, or Ctrl-C),
//! kept for the caller to raise once the run has returned.

use std::sync::{Mutex, MutexGuard};

use mcint::CancelToken;
use pyo3::PyErr;

/// The exception that stopped a run, and the token through which it stopped it.
pub struct Failure {
    slot: Mutex<Option<PyErr>>,
    cancel: CancelToken,
}

impl Failure {
    /// No failure yet; a failure cancels the runs holding `cancel`.
    pub fn new(cancel: CancelToken) -> Self {
        Failure {
            slot: Mutex::new(None),
            cancel,
        }
    }

    /// Stops the run with `error` (the first one wins).
    pub fn fail(&self, error: PyErr) {
        self.lock().get_or_insert(error);
        self.cancel.cancel();
    }

    /// The exception that stopped the run, if any (taken once).
    pub fn take(&self) -> Option<PyErr> {
        self.lock().take()
    }

    /// Whether the run has failed.
    pub fn happened(&self) -> bool {
        self.lock().is_some()
    }

    fn lock(&self) -> MutexGuard<'_, Option<PyErr>> {
        // A poisoned lock only means another thread panicked while holding it; the slot is
        // still a plain Option.
        self.slot.lock().unwrap_or_else(|e| e.into_inner())
    }
}
