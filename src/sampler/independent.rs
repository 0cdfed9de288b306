//! Independent uniform points from a PCG stream: plain Monte Carlo (Jarosz's A.14).

use super::{PassKind, Sampler, check_block, check_dims, check_point};
use crate::error::Result;
use crate::hash::{hash_words, unit_f64};
use crate::points::Points;
use rand_core::Rng;
use rand_pcg::Pcg64;

/// Generator copies a block fill steps in turn (see `fill`).
const STREAMS: usize = 2;
/// Points per run drawn into the fill's tile before they are copied to the columns.
const TILE: usize = 32;
/// Fewest points per copy worth the copies' jumps.
const MIN_RUN: usize = 64;

/// Independent uniform points: coordinate `j` of point `i` is value `i * dims + j` of one
/// PCG-64 stream (O'Neill 2014, from `rand_pcg`) selected by the seed.
///
/// PCG can jump ahead in O(log n) steps, so any point or block is reached directly: a block
/// jumps once and then draws sequentially, and any split of the index range over threads gives
/// the same values as one sequential pass.
///
/// ```
/// use mcint::sampler::{Independent, Sampler};
/// let s = Independent::new(2, 7).unwrap();
/// let mut p = [0.0; 2];
/// s.point(1_000_000, &mut p).unwrap();
/// assert!(p.iter().all(|&x| (0.0..1.0).contains(&x)));
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Independent {
    dims: usize,
    seed: u64,
    origin: Pcg64,
}

impl Independent {
    /// Independent points in `dims >= 1` dimensions.
    ///
    /// ```
    /// assert!(mcint::sampler::Independent::new(0, 1).is_err());
    /// ```
    pub fn new(dims: usize, seed: u64) -> Result<Self> {
        check_dims(dims)?;
        Ok(Independent {
            dims,
            seed,
            origin: stream_for(seed),
        })
    }

    /// Independent points in `dims` dimensions, seeded from a random number generator the
    /// caller already has (one `u64` drawn from it): any `rand_core::SeedableRng` seeded as
    /// the caller likes.
    ///
    /// ```
    /// use mcint::sampler::{Independent, Sampler};
    /// use rand_core::SeedableRng;
    /// let mut rng = rand_pcg::Pcg64::from_seed([7; 32]);
    /// let a = Independent::from_rng(3, &mut rng).unwrap();
    /// let b = Independent::from_rng(3, &mut rand_pcg::Pcg64::from_seed([7; 32])).unwrap();
    /// assert_eq!(a.random(4).unwrap(), b.random(4).unwrap());
    /// ```
    pub fn from_rng(dims: usize, rng: &mut dyn rand_core::Rng) -> Result<Self> {
        Independent::new(dims, rng.next_u64())
    }

    /// The generator positioned at value number `position` of the stream.
    fn at(&self, position: u128) -> Pcg64 {
        let mut rng = self.origin.clone();
        rng.advance(position);
        rng
    }
}

/// The PCG stream selected by a seed: both the state and the stream increment are hashed from
/// it, so nearby seeds give unrelated streams.
fn stream_for(seed: u64) -> Pcg64 {
    let state = (u128::from(hash_words(seed, &[1])) << 64) | u128::from(hash_words(seed, &[2]));
    let stream = (u128::from(hash_words(seed, &[3])) << 64) | u128::from(hash_words(seed, &[4]));
    Pcg64::new(state, stream)
}

impl Sampler for Independent {
    fn name(&self) -> &'static str {
        "independent"
    }

    fn dims(&self) -> usize {
        self.dims
    }

    fn passes(&self) -> PassKind {
        PassKind::Independent
    }

    fn seed(&self) -> u64 {
        self.seed
    }

    fn reseed(&mut self, seed: u64) {
        self.seed = seed;
        self.origin = stream_for(seed);
    }

    fn point(&self, index: u64, out: &mut [f64]) -> Result<()> {
        check_point(self.dims, out)?;
        let mut rng = self.at(u128::from(index) * self.dims as u128);
        for x in out.iter_mut() {
            *x = unit_f64(rng.next_u64());
        }
        Ok(())
    }

    fn fill(&self, start: u64, points: &mut Points) -> Result<()> {
        check_block(self.dims, start, points)?;
        let dims = self.dims;
        let len = points.len();
        let mut columns: Vec<&mut [f64]> = points.columns_mut().collect();
        // One PCG step is a serial chain of 128-bit multiplies, so the block is cut into
        // `STREAMS` runs of points, each drawn by its own copy of the generator jumped to the
        // run's first value, and the copies are stepped in turn: independent chains the CPU
        // overlaps. Each value is still value `index * dims + dim` of the one stream.
        let per_stream = if len >= STREAMS * MIN_RUN {
            len / STREAMS
        } else {
            0
        };
        let mut rngs: [Pcg64; STREAMS] = std::array::from_fn(|_| self.origin.clone());
        rngs[0] = self.at(u128::from(start) * dims as u128);
        for k in 1..STREAMS {
            rngs[k] = rngs[k - 1].clone();
            rngs[k].advance((per_stream * dims) as u128);
        }
        // The stream is point-major and the block column-major. Writing a value at a time
        // into `dims` columns that lie a multiple of 4 KiB apart makes the stores collide in
        // the same cache sets once `dims` is large, so `TILE` points per run are drawn into a
        // small column-major tile first and copied out as contiguous column segments.
        let whole_tiles = per_stream / TILE * TILE;
        // Only when it is used: a block of a few points in many dimensions (one path of a
        // deep multilevel level) drew them straight, but allocated the tile regardless.
        let tiles = if whole_tiles > 0 { STREAMS * dims } else { 0 };
        let mut tile = vec![[0.0; TILE]; tiles];
        for done in (0..whole_tiles).step_by(TILE) {
            // `t` indexes a different tile row for every (run, dimension): no single iterator.
            #[allow(clippy::needless_range_loop)]
            for t in 0..TILE {
                for dim in 0..dims {
                    for (k, rng) in rngs.iter_mut().enumerate() {
                        tile[k * dims + dim][t] = unit_f64(rng.next_u64());
                    }
                }
            }
            for (dim, column) in columns.iter_mut().enumerate() {
                for k in 0..STREAMS {
                    let to = k * per_stream + done;
                    column[to..to + TILE].copy_from_slice(&tile[k * dims + dim]);
                }
            }
        }
        for i in whole_tiles..per_stream {
            for column in columns.iter_mut() {
                for (k, rng) in rngs.iter_mut().enumerate() {
                    column[k * per_stream + i] = unit_f64(rng.next_u64());
                }
            }
        }
        // The last copy ends where the points after the runs begin.
        let rng = &mut rngs[STREAMS - 1];
        for i in STREAMS * per_stream..len {
            for column in columns.iter_mut() {
                column[i] = unit_f64(rng.next_u64());
            }
        }
        Ok(())
    }
}
