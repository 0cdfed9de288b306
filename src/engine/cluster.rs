//! [`Cluster`]: the MPI processes (ranks) a run is spread over (the `mpi` feature).
//!
//! A run with a cluster deals each window of its chunks to the ranks in contiguous shares;
//! every rank evaluates its share on its own threads, the shares' outputs are gathered to every
//! rank, and every rank folds all of them in chunk order. Every rank therefore holds the state
//! a single process would hold, bit for bit, and takes the same decisions (stop, refine a
//! grid, stop on a limit) without further messages.

use std::ops::Range;

use mpi::datatype::PartitionMut;
use mpi::topology::SimpleCommunicator;
use mpi::traits::Communicator;
use mpi::traits::CommunicatorCollectives;

use crate::error::{Error, Result};

/// The MPI ranks of `MPI_COMM_WORLD`, over which a run spreads its work (the `mpi` feature).
///
/// Give it to a runner's `cluster` setting ([`Integrator::cluster`](crate::Integrator::cluster),
/// [`Vegas::cluster`](crate::adaptive::Vegas::cluster), ...) and call `run` on every rank: each
/// rank evaluates a share of the chunks on its own threads, and every rank returns the same
/// result as a single process would, bit for bit, for any number of ranks and threads. An
/// error on any rank (a panic of the integrand, say) ends the run on every rank with that
/// error. Initialize MPI first (threads other than the caller's never call MPI, so
/// [`Threading::Funneled`](mpi::Threading::Funneled) suffices) and call `run` from the thread
/// that initialized it, on every rank, with the same settings.
///
/// ```
/// use mcint::{Cluster, Integrator, pdf::UniformBox};
/// // One process (a singleton MPI job) when run without mpirun.
/// let _universe = mcint::mpi::initialize().unwrap();
/// let cluster = Cluster::world().unwrap();
/// let run = || Integrator::over_box(|x: &[f64]| x[0] * x[1], UniformBox::unit(2).unwrap())
///     .samples(100_000)
///     .seed(3);
/// let spread = run().cluster(cluster).run().unwrap();
/// assert_eq!(spread, run().run().unwrap());
/// if cluster.is_root() {
///     println!("{} over {} ranks", spread.mean, cluster.size());
/// }
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cluster {
    rank: usize,
    size: usize,
}

impl Cluster {
    /// Every rank of the MPI job (`MPI_COMM_WORLD`); an error if MPI is not initialized or
    /// already finalized.
    ///
    /// ```
    /// use mcint::Cluster;
    /// assert!(Cluster::world().is_err()); // before mpi::initialize
    /// let _universe = mcint::mpi::initialize().unwrap();
    /// assert_eq!(Cluster::world().unwrap().size(), 1);
    /// ```
    pub fn world() -> Result<Cluster> {
        usable()?;
        let world = SimpleCommunicator::world();
        Ok(Cluster {
            rank: usize::try_from(world.rank()).unwrap_or(0),
            size: usize::try_from(world.size()).unwrap_or(1).max(1),
        })
    }

    /// This process's rank, `0..size`.
    ///
    /// ```
    /// let _universe = mcint::mpi::initialize().unwrap();
    /// assert_eq!(mcint::Cluster::world().unwrap().rank(), 0);
    /// ```
    pub fn rank(&self) -> usize {
        self.rank
    }

    /// The number of ranks.
    ///
    /// ```
    /// let _universe = mcint::mpi::initialize().unwrap();
    /// assert!(mcint::Cluster::world().unwrap().size() >= 1);
    /// ```
    pub fn size(&self) -> usize {
        self.size
    }

    /// Whether this is rank 0, the one that usually prints.
    ///
    /// ```
    /// let _universe = mcint::mpi::initialize().unwrap();
    /// assert!(mcint::Cluster::world().unwrap().is_root());
    /// ```
    pub fn is_root(&self) -> bool {
        self.rank == 0
    }

    /// Whether `flag` holds on any rank: the same answer on every rank (every rank must call
    /// it), for decisions a program takes between runs, such as stopping after a signal that
    /// reached some ranks before others.
    ///
    /// ```
    /// let _universe = mcint::mpi::initialize().unwrap();
    /// let cluster = mcint::Cluster::world().unwrap();
    /// assert!(cluster.any(true).unwrap());
    /// assert!(!cluster.any(false).unwrap());
    /// ```
    pub fn any(&self, flag: bool) -> Result<bool> {
        let all = self.all_gather(&[u8::from(flag)])?;
        Ok(all.iter().any(|bytes| bytes.first() == Some(&1)))
    }

    /// This rank's share of `chunks`: contiguous, in rank order, sizes differing by at most
    /// one (empty when there are more ranks than chunks).
    pub(crate) fn share(&self, chunks: Range<u64>) -> Range<u64> {
        self.share_of(self.rank, chunks)
    }

    /// The share of `chunks` of rank `rank` (see [`share`](Self::share)).
    pub(crate) fn share_of(&self, rank: usize, chunks: Range<u64>) -> Range<u64> {
        let len = chunks.end - chunks.start;
        let (size, rank) = (self.size as u64, rank as u64);
        let bound = |r: u64| chunks.start + r * (len / size) + r.min(len % size);
        bound(rank)..bound(rank + 1)
    }

    /// `bytes` of every rank, in rank order, on every rank (`MPI_Allgatherv`). Every rank
    /// must call it, with its own bytes.
    pub(crate) fn all_gather(&self, bytes: &[u8]) -> Result<Vec<Vec<u8>>> {
        usable()?;
        let world = SimpleCommunicator::world();
        let too_large = || Error::IndexOutOfRange {
            what: "bytes one rank sends in one exchange",
            limit: i32::MAX as u64,
        };
        let len = i32::try_from(bytes.len()).unwrap_or(-1);
        let mut counts = vec![0i32; self.size];
        world.all_gather_into(&len, &mut counts[..]);
        // Every rank sees the same counts, so every rank refuses the same exchange.
        if counts.iter().any(|&c| c < 0) {
            return Err(too_large());
        }
        let mut displacements = Vec::with_capacity(self.size);
        let mut total = 0i32;
        for &count in &counts {
            displacements.push(total);
            total = total.checked_add(count).ok_or_else(too_large)?;
        }
        let mut all = vec![0u8; total as usize];
        {
            let mut partition = PartitionMut::new(&mut all[..], &counts[..], &displacements[..]);
            world.all_gather_varcount_into(bytes, &mut partition);
        }
        Ok(counts
            .iter()
            .zip(&displacements)
            .map(|(&count, &at)| all[at as usize..][..count as usize].to_vec())
            .collect())
    }
}

/// Refuses MPI calls before `MPI_Init` or after `MPI_Finalize`, which would abort the process.
fn usable() -> Result<()> {
    if !mpi::environment::is_initialized() || mpi::environment::is_finalized() {
        return Err(Error::Unsupported {
            operation: "cluster",
            reason: "MPI is not running in this process: initialize it first \
                     (mcint::mpi::initialize) and keep its Universe alive during the run"
                .to_string(),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_are_contiguous_balanced_and_cover_the_range() {
        for size in 1..=7 {
            for len in 0..=20u64 {
                let mut next = 5;
                for rank in 0..size {
                    let share = Cluster { rank, size }.share(5..5 + len);
                    assert_eq!(share.start, next);
                    let n = share.end - share.start;
                    assert!(n == len / size as u64 || n == len / size as u64 + 1);
                    next = share.end;
                }
                assert_eq!(next, 5 + len);
            }
        }
    }
}
