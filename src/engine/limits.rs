//! [`CancelToken`] and [`Limits`]: what stops a run early, checked before every chunk of work.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crate::stats::StopReason;

/// A flag that stops a run from another thread: the run finishes the chunks it is working
/// on and returns what it has, with [`StopReason::Cancelled`] (or the error
/// [`Error::Interrupted`](crate::Error::Interrupted) when it has no estimate yet). Clones share
/// the flag.
///
/// ```
/// use mcint::{CancelToken, Integrator, pdf::UniformBox, stats::StopReason};
/// let token = CancelToken::new();
/// let stopper = token.clone();
/// // The integrand cancels its own run after a while, as another thread might.
/// let calls = std::sync::atomic::AtomicU64::new(0);
/// let f = |x: &[f64]| {
///     if calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed) == 100_000 {
///         stopper.cancel();
///     }
///     x[0]
/// };
/// let e = Integrator::over_box(f, UniformBox::unit(1).unwrap())
///     .samples(10_000_000)
///     .threads(1)
///     .cancel_token(token.clone())
///     .run()
///     .unwrap();
/// assert_eq!(e.stop, StopReason::Cancelled);
/// assert!(e.n < 200_000 && token.is_cancelled());
/// ```
#[derive(Debug, Clone, Default)]
pub struct CancelToken(Arc<AtomicBool>);

impl CancelToken {
    /// A token not yet cancelled.
    ///
    /// ```
    /// assert!(!mcint::CancelToken::new().is_cancelled());
    /// ```
    pub fn new() -> Self {
        CancelToken::default()
    }

    /// Asks every run holding this token (or a clone) to stop.
    ///
    /// ```
    /// let t = mcint::CancelToken::new();
    /// t.clone().cancel();
    /// assert!(t.is_cancelled());
    /// ```
    pub fn cancel(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// Whether [`cancel`](Self::cancel) was called.
    ///
    /// ```
    /// assert!(!mcint::CancelToken::new().is_cancelled());
    /// ```
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// When a run must stop: a deadline and a cancellation token, either optional.
#[derive(Debug, Clone, Default)]
pub(crate) struct Limits {
    deadline: Option<Instant>,
    cancel: Option<CancelToken>,
}

impl Limits {
    /// Limits that start now: `time_limit` from now or `deadline`, whichever comes first,
    /// and `cancel`. A limit past the last instant the clock can represent (`Duration::MAX`)
    /// is no limit.
    pub(crate) fn new(
        time_limit: Option<Duration>,
        deadline: Option<Instant>,
        cancel: Option<CancelToken>,
    ) -> Limits {
        let from_now = time_limit.and_then(|limit| Instant::now().checked_add(limit));
        let deadline = match (from_now, deadline) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        Limits { deadline, cancel }
    }

    /// Why the run must stop now, if it must.
    pub(crate) fn reached(&self) -> Option<StopReason> {
        if self.cancel.as_ref().is_some_and(CancelToken::is_cancelled) {
            return Some(StopReason::Cancelled);
        }
        if self.deadline.is_some_and(|d| Instant::now() >= d) {
            return Some(StopReason::TimeLimit);
        }
        None
    }
}
