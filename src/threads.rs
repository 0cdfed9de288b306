//! Worker-thread settings shared by every parallel run: the thread count and the error for a
//! worker that panicked.

use crate::{Error, Result};

/// The thread count of a `.threads(..)` setting: at least 1; `None` means all available.
pub(crate) fn resolve(threads: Option<usize>) -> Result<usize> {
    match threads {
        Some(0) => Err(Error::invalid("threads", 0, "at least 1")),
        Some(t) => Ok(t),
        None => Ok(available()),
    }
}

/// The number of threads the machine offers (1 if it cannot tell).
pub(crate) fn available() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The error for a worker thread that panicked (the integrand, or a function it calls,
/// panicked).
pub(crate) fn worker_panicked() -> Error {
    Error::invalid(
        "worker thread",
        "panicked",
        "an integrand that does not panic",
    )
}
