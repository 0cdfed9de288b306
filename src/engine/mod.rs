//! The run engine under every method: one parallel executor, one run configuration, one
//! stopping rule.
//!
//! * [`Executor`]: fixed chunks of work on a rayon pool, outputs folded in chunk order (the
//!   same bits for any thread count), panics caught once and reported as one error, nested
//!   runs sharing the outer run's threads.
//! * [`RunConfig`] and `run_settings!`: the sampler (with its default and reseeding), seed,
//!   threads, points, replicates, tolerance and non-finite policy that every runner's builder
//!   holds, with setters written once.
//! * [`drive`]: the one stage loop: limits before each stage, the non-finite policy, the
//!   judgement of a run to a tolerance by [`Targets`], and how a run ended.
//! * `Cluster` (the `mpi` feature): the executor deals each window of chunks to MPI ranks
//!   and gathers their outputs to every rank before the fold, so every rank holds the state
//!   of a one-process run and takes the same decisions.

#[cfg(feature = "mpi")]
mod cluster;
mod config;
#[cfg(feature = "mpi")]
mod distributed;
mod drive;
mod executor;
mod limits;
mod settings;
mod targets;

/// For the runners that catch panics outside a chunk of the executor.
pub(crate) use crate::panics::guarded;
#[cfg(feature = "mpi")]
pub use cluster::Cluster;
pub(crate) use config::{
    DEFAULT_REPLICATES, RunConfig, RunSampler, TOLERANCE_REPLICATES, require_randomized,
    require_uniform_points,
};
pub(crate) use drive::{Drive, Next, NonFinite, StageEnd, Stages, Verdict, drive};
pub(crate) use executor::{ChunkJob, Executor, Grouping, RunScope};
pub use limits::CancelToken;
pub(crate) use limits::Limits;
pub(crate) use settings::run_settings;
pub(crate) use targets::Targets;
