//! A panic in work the crate runs for a caller (an integrand, a pdf, a user's function)
//! becomes an error naming where it happened, instead of unwinding through the caller.

use std::any::Any;
use std::panic::{AssertUnwindSafe, catch_unwind};

use crate::error::{Error, Result};

/// Runs `work`, turning a panic into the error of a panic at `origin` (a replicate, or an
/// iteration, stratum or pass, and the first sample index of the work).
pub(crate) fn guarded<T>(origin: (u64, u64), work: impl FnOnce() -> Result<T>) -> Result<T> {
    catch_unwind(AssertUnwindSafe(work)).unwrap_or_else(|payload| Err(panicked(origin, payload)))
}

/// The error for a panic caught in the work that starts at `origin`.
fn panicked((replicate, first_index): (u64, u64), payload: Box<dyn Any + Send>) -> Error {
    let message = if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "(a panic without a message)".to_string()
    };
    Error::IntegrandPanicked {
        message,
        replicate,
        first_index,
    }
}
