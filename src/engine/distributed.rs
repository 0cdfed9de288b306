//! The executor's window over a [`Cluster`]: each rank evaluates its share of the window's
//! chunks, the shares travel to every rank in one `MPI_Allgatherv`, and every rank hands the
//! same outputs, in chunk order, to the same fold.
//!
//! A rank never leaves before the exchange: a failure of its share (an error, a panic caught
//! as one, a limit reached) is part of its message, so every rank learns it in the same
//! exchange and returns the same error or stop, and no rank waits for one that has left.

use std::ops::Range;

use serde::{Deserialize, Serialize};

use super::Limits;
use super::cluster::Cluster;
use super::executor::{Transfer, WindowOutputs};
use crate::error::{Error, Result};
use crate::stats::StopReason;

/// One rank's message for a window.
#[derive(Serialize, Deserialize)]
enum Share<T> {
    /// The outputs of its chunks in order (`None` where a limit skipped a chunk) and, if it
    /// skipped any, the limit it reached.
    Done {
        outputs: Vec<Option<T>>,
        stop: Option<StopReason>,
    },
    /// The first error of its chunks, in chunk order.
    Failed(Failure),
}

/// An [`Error`] on its way to the other ranks: the errors that say where an integrand failed
/// travel whole, the others as their message.
#[derive(Serialize, Deserialize)]
enum Failure {
    Panicked {
        message: String,
        replicate: u64,
        first_index: u64,
    },
    Interrupted {
        stop: StopReason,
        evaluations: u64,
    },
    NonFinite {
        count: u64,
        first_index: u64,
        first_replicate: u64,
        first_output: Option<usize>,
        first_value: f64,
        first_point: Vec<f64>,
    },
    Other(String),
}

impl From<Error> for Failure {
    fn from(error: Error) -> Failure {
        match error {
            Error::IntegrandPanicked {
                message,
                replicate,
                first_index,
            } => Failure::Panicked {
                message,
                replicate,
                first_index,
            },
            Error::Interrupted { stop, evaluations } => Failure::Interrupted { stop, evaluations },
            Error::NonFiniteContribution {
                count,
                first_index,
                first_replicate,
                first_output,
                first_value,
                first_point,
            } => Failure::NonFinite {
                count,
                first_index,
                first_replicate,
                first_output,
                first_value,
                first_point,
            },
            other => Failure::Other(other.to_string()),
        }
    }
}

impl Failure {
    /// The error every rank reports for this failure of rank `rank`.
    fn into_error(self, rank: usize) -> Error {
        match self {
            Failure::Panicked {
                message,
                replicate,
                first_index,
            } => Error::IntegrandPanicked {
                message,
                replicate,
                first_index,
            },
            Failure::Interrupted { stop, evaluations } => Error::Interrupted { stop, evaluations },
            Failure::NonFinite {
                count,
                first_index,
                first_replicate,
                first_output,
                first_value,
                first_point,
            } => Error::NonFiniteContribution {
                count,
                first_index,
                first_replicate,
                first_output,
                first_value,
                first_point,
            },
            Failure::Other(message) => Error::OnRank { rank, message },
        }
    }
}

/// Each rank's share of the chunks `units`, with the outputs `local` computed from it on that
/// rank, in rank order, and the limit the first stopped rank reached; the first error in
/// chunk order (that of the lowest failed rank) on every rank.
pub(super) fn gathered<T: Transfer>(
    cluster: Cluster,
    units: Range<u64>,
    local: impl FnOnce(Range<u64>) -> Result<Vec<Option<T>>>,
    limits: &Limits,
) -> Result<WindowOutputs<T>> {
    let share = match local(cluster.share(units.clone())) {
        Ok(outputs) => {
            let skipped = outputs.iter().any(Option::is_none);
            let stop = skipped.then(|| limits.reached().unwrap_or(StopReason::Cancelled));
            Share::Done { outputs, stop }
        }
        Err(error) => Share::Failed(error.into()),
    };
    // Encoding cannot fail for these types; if it did, the rank says so in its message.
    let message = encode(&share).or_else(|e| {
        encode(&Share::<T>::Failed(Failure::Other(format!(
            "its results could not be encoded ({e})"
        ))))
    });
    let message = message.unwrap_or_default();
    let mut shares = Vec::with_capacity(cluster.size());
    let mut stop = None;
    for (rank, bytes) in cluster.all_gather(&message)?.iter().enumerate() {
        match ciborium::from_reader::<Share<T>, _>(&bytes[..]) {
            Ok(Share::Done {
                outputs: theirs,
                stop: their_stop,
            }) => {
                stop = stop.or(their_stop);
                shares.push((cluster.share_of(rank, units.clone()), theirs));
            }
            Ok(Share::Failed(failure)) => return Err(failure.into_error(rank)),
            Err(e) => {
                return Err(Error::OnRank {
                    rank,
                    message: format!("its results could not be read ({e})"),
                });
            }
        }
    }
    Ok((shares, stop))
}

/// `value` in CBOR, exact for every float (NaN and infinities included).
fn encode<T: Serialize>(value: &T) -> std::result::Result<Vec<u8>, String> {
    let mut bytes = Vec::new();
    ciborium::into_writer(value, &mut bytes).map_err(|e| e.to_string())?;
    Ok(bytes)
}

/// The first reading of the ranks' limits in rank order (`local` is this rank's), the same on
/// every rank.
pub(super) fn agreed(cluster: Cluster, local: Option<StopReason>) -> Result<Option<StopReason>> {
    let code = |reason: Option<StopReason>| match reason {
        None => 0u8,
        Some(StopReason::TimeLimit) => 1,
        Some(_) => 2,
    };
    let readings = cluster.all_gather(&[code(local)])?;
    Ok(readings.iter().find_map(|r| match r.first() {
        Some(1) => Some(StopReason::TimeLimit),
        Some(2) => Some(StopReason::Cancelled),
        _ => None,
    }))
}
