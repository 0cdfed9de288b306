//! The samplers' block fills on the crate's SIMD dispatch, and the switches that tests and
//! benchmarks use to compare the instruction sets (the dispatch itself lives in `crate::simd`,
//! below every module that has hot loops).

use crate::simd::{Kernel, dispatch};
pub use crate::simd::{active, force_portable};

/// The block fill of `sampler`'s points `start ..` into `points`: a sampler with a vectorized
/// fill implements [`Kernel`] for its own `BlockFill`.
pub(crate) struct BlockFill<'a, S> {
    pub(crate) sampler: &'a S,
    pub(crate) start: u64,
    pub(crate) points: &'a mut crate::points::Points,
}

/// Checks the block against the sampler's `dims` and runs `sampler`'s [`BlockFill`] kernel
/// on the widest instruction set.
pub(crate) fn dispatch_fill<'a, S>(
    sampler: &'a S,
    dims: usize,
    start: u64,
    points: &'a mut crate::points::Points,
) -> crate::error::Result<()>
where
    BlockFill<'a, S>: Kernel<Output = ()>,
{
    super::check_block(dims, start, points)?;
    dispatch(BlockFill {
        sampler,
        start,
        points,
    });
    Ok(())
}
