//! `--mpi`: a run spread over the ranks of the MPI job this process belongs to (a build with
//! `--features mpi`, launched with `mpirun -n N`). Every rank runs the same command; rank 0
//! prints the result and writes checkpoints.

/// This process's place in the job: one rank of one without `--mpi`.
pub struct Ranks {
    /// Keeps MPI running until the run ends (dropping it finalizes MPI).
    #[cfg(feature = "mpi")]
    _universe: Option<mcint::mpi::environment::Universe>,
    pub spread: Spread,
}

/// What a runner needs to spread its work: the cluster, if any, and this rank.
#[derive(Clone, Copy)]
pub struct Spread {
    #[cfg(feature = "mpi")]
    pub cluster: Option<mcint::Cluster>,
    pub rank: usize,
    pub size: usize,
}

impl Spread {
    /// Whether this process prints and saves (rank 0, or the only process).
    pub fn is_root(&self) -> bool {
        self.rank == 0
    }

    /// Whether `flag` holds on any rank: the same answer on every rank, so that decisions
    /// taken outside the library's runs (stop after a cancellation) are taken together.
    pub fn any(&self, flag: bool) -> bool {
        #[cfg(feature = "mpi")]
        if let Some(cluster) = self.cluster {
            // MPI stays up for the whole run (Ranks holds it), so the exchange cannot fail;
            // if it did, stopping is the safe answer.
            return cluster.any(flag).unwrap_or(true);
        }
        flag
    }
}

impl Ranks {
    /// Joins the MPI job when `mpi` (the `--mpi` flag) is set.
    pub fn new(mpi: bool) -> Result<Ranks, String> {
        let alone = Spread {
            #[cfg(feature = "mpi")]
            cluster: None,
            rank: 0,
            size: 1,
        };
        if !mpi {
            return Ok(Ranks {
                #[cfg(feature = "mpi")]
                _universe: None,
                spread: alone,
            });
        }
        #[cfg(feature = "mpi")]
        {
            // Only this thread calls MPI; the worker threads never do.
            let (universe, _) =
                mcint::mpi::initialize_with_threading(mcint::mpi::Threading::Funneled)
                    .ok_or("MPI was already initialized in this process")?;
            let cluster = mcint::Cluster::world().map_err(crate::args::flag_error)?;
            Ok(Ranks {
                _universe: Some(universe),
                spread: Spread {
                    cluster: Some(cluster),
                    rank: cluster.rank(),
                    size: cluster.size(),
                },
            })
        }
        #[cfg(not(feature = "mpi"))]
        Err(
            "--mpi needs a build with MPI: cargo build --release -p mcint-cli --features mpi \
             (with Open MPI and libclang installed), then mpirun -n N target/release/..."
                .into(),
        )
    }
}

/// `$builder.cluster(..)` when the run is spread over ranks, `$builder` otherwise.
#[macro_export]
macro_rules! spread {
    ($builder:expr, $spread:expr) => {{
        #[cfg(feature = "mpi")]
        let spread = match $spread.cluster {
            Some(cluster) => $builder.cluster(cluster),
            None => $builder,
        };
        #[cfg(not(feature = "mpi"))]
        let spread = {
            let _ = &$spread;
            $builder
        };
        spread
    }};
}
