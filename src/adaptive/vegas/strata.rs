//! The hypercubes of VEGAS+'s `y`-space, how many points each gets in an iteration, and the
//! cut of an iteration's index range into chunks of work.

/// An iteration is cut into equal chunks (units of work handed to a thread) of at least
/// `MIN_CHUNK` points, at most `CHUNKS` of them while they fit in `MAX_CHUNK` points, and
/// never more than `MAX_CHUNKS`. Each chunk carries an array of grid training data (two
/// values per increment), whose cost is small against `MIN_CHUNK` points; four chunks of a
/// `10^4`-point iteration keep two or four threads equally busy, and up to 64 chunks keep
/// the thread that finishes last at most a sixty-fourth of the iteration behind.
const CHUNKS: u64 = 64;
const MIN_CHUNK: u64 = 2500;
const MAX_CHUNK: u64 = 1 << 16;
const MAX_CHUNKS: u64 = 1 << 16;
/// Most hypercubes in the stratification: bounds the two per-hypercube arrays (64 MiB).
const MAX_HYPERCUBES: u64 = 1 << 22;
/// Keeps the proportional allocation from exceeding its budget through rounding.
pub(super) const ALLOCATION_SAFETY: f64 = 1.0 - 1e-12;

/// The hypercubes of `y`-space, the fixed part of the allocation, and the grid's increments.
pub(super) struct Strata {
    /// Strata per axis, `s_d`.
    pub(super) per_axis: Vec<u64>,
    /// `1 / s_d`.
    pub(super) inverse: Vec<f64>,
    /// `prod_d s_d`.
    pub(super) cubes: u64,
    /// Volume of one hypercube in `y`-space, `1 / cubes`.
    pub(super) cube_volume: f64,
    /// Evaluations every hypercube gets whatever its variance.
    pub(super) min_per_cube: u64,
    /// Evaluations shared in proportion to `sigma_h^beta` (VEGAS+ only).
    pub(super) allocation_budget: Option<f64>,
    /// Grid increments per axis.
    pub(super) increments: Vec<usize>,
    /// Points per chunk of work.
    pub(super) chunk: u64,
}

impl Strata {
    /// The rules of the Python `vegas` package (version 6). With adaptive allocation a
    /// quarter of the `N` evaluations is spread evenly with at least two per hypercube (so
    /// at most `N / 8` hypercubes) and three quarters follow `sigma_h^beta`; with a fixed
    /// uniform allocation (`beta = 0`), up to `N / 2` hypercubes of two points or more.
    /// Strata are as equal as possible across axes (one more on the first axes where that
    /// still fits), so high dimensions cut some axes in two and leave the rest whole. Each
    /// axis then gets a multiple of its strata as increments (`max_increments` rounded
    /// down), or one increment per stratum when strata outnumber increments, so that no
    /// stratum straddles a jump of the Jacobian; past `increments_cap` strata the strata
    /// are rounded down to a multiple of the increments instead.
    pub(super) fn new(
        dims: usize,
        evaluations: u64,
        stratified: bool,
        beta: f64,
        max_increments: usize,
        increments_cap: usize,
    ) -> Strata {
        let adaptive = stratified && beta > 0.0;
        let even = if adaptive {
            evaluations / 4
        } else {
            evaluations
        };
        let max_cubes = if stratified {
            (even / 2).clamp(1, MAX_HYPERCUBES)
        } else {
            1
        };
        let mut base = (max_cubes as f64).powf(1.0 / dims as f64).floor().max(1.0) as u64;
        while base > 1 && product(base, dims) > max_cubes {
            base -= 1;
        }
        while product(base + 1, dims) <= max_cubes {
            base += 1;
        }
        let mut per_axis = vec![base; dims];
        let mut cubes = product(base, dims);
        for s in per_axis.iter_mut() {
            let more = cubes / base * (base + 1);
            if more > max_cubes {
                break;
            }
            *s = base + 1;
            cubes = more;
        }
        let ni = max_increments as u64;
        let increments = per_axis
            .iter_mut()
            .map(|s| {
                if ni >= *s {
                    (ni / *s * *s) as usize
                } else if *s <= increments_cap as u64 {
                    *s as usize
                } else {
                    *s = *s / ni * ni;
                    max_increments
                }
            })
            .collect();
        let cubes: u64 = per_axis.iter().product();
        let min_per_cube = if cubes == 1 {
            evaluations
        } else {
            (even / cubes).max(2)
        };
        Strata {
            inverse: per_axis.iter().map(|&s| 1.0 / s as f64).collect(),
            per_axis,
            cubes,
            cube_volume: 1.0 / cubes as f64,
            min_per_cube,
            allocation_budget: (adaptive && cubes > 1)
                .then_some((evaluations - evaluations / 4) as f64),
            increments,
            chunk: chunk_size(evaluations),
        }
    }
}

/// Points per chunk of an iteration of `evaluations` points (see [`CHUNKS`]).
fn chunk_size(evaluations: u64) -> u64 {
    let chunks = (evaluations / MIN_CHUNK).clamp(1, CHUNKS);
    evaluations
        .div_ceil(chunks)
        .min(MAX_CHUNK)
        .max(evaluations.div_ceil(MAX_CHUNKS))
}

/// `base^dims`, saturating.
fn product(base: u64, dims: usize) -> u64 {
    (0..dims).fold(1u64, |p, _| p.saturating_mul(base))
}

/// How many points each hypercube gets in one iteration.
#[derive(Clone, Copy)]
pub(super) struct Allocation<'a> {
    pub(super) min: u64,
    /// Points per unit of `sigma_h^beta` added to `min`; `None` for the uniform allocation.
    pub(super) scale: Option<f64>,
    /// `sigma_h^beta` per hypercube, from the previous iteration.
    pub(super) sigf: &'a [f64],
}

impl Allocation<'_> {
    #[inline]
    pub(super) fn evaluations(&self, cube: u64) -> u64 {
        match self.scale {
            // The float-to-int cast saturates (and sends NaN to 0).
            Some(scale) => self.min + (self.sigf[cube as usize] * scale) as u64,
            None => self.min,
        }
    }
}

/// Where a chunk starts: its first index, the hypercube holding it and the offset within.
#[derive(Clone, Copy)]
pub(super) struct ChunkStart {
    pub(super) index: u64,
    pub(super) cube: u64,
    pub(super) offset: u64,
}

/// Cuts the iteration's index range into chunks of `strata.chunk` points; returns them and the
/// iteration's number of points.
pub(super) fn plan_chunks(strata: &Strata, allocation: &Allocation) -> (Vec<ChunkStart>, u64) {
    let mut chunks = Vec::new();
    let mut total = 0u64;
    let mut boundary = 0u64;
    for cube in 0..strata.cubes {
        let n = allocation.evaluations(cube);
        while boundary < total + n {
            chunks.push(ChunkStart {
                index: boundary,
                cube,
                offset: boundary - total,
            });
            boundary += strata.chunk;
        }
        total += n;
    }
    (chunks, total)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strata_follow_the_vegas_rule() {
        // N = 10^5 in 5 dimensions: at most 12_500 hypercubes; 6^5 = 7776, and 7^3 * 6^2 =
        // 12348 still fits, 7^4 * 6 = 14406 does not. Increments: multiples of the strata.
        let s = Strata::new(5, 100_000, true, 0.75, 1000, 1000);
        assert_eq!(s.per_axis, [7, 7, 7, 6, 6]);
        assert_eq!(s.cubes, 12348);
        assert_eq!(s.min_per_cube, 2);
        assert_eq!(s.allocation_budget, Some(75_000.0));
        assert_eq!(s.increments, [994, 994, 994, 996, 996]);
        // beta = 0: fixed stratification with two points per hypercube.
        let s = Strata::new(2, 1000, true, 0.0, 100, 1000);
        assert_eq!(
            (s.cubes, s.min_per_cube, s.allocation_budget),
            (484, 2, None)
        );
        assert_eq!(s.increments, [88, 88]);
        // High dimension: some axes cut in two, the rest whole.
        let s = Strata::new(20, 1000, true, 0.75, 100, 1000);
        assert_eq!((s.cubes, s.min_per_cube), (64, 3));
        assert_eq!(s.per_axis.iter().filter(|&&a| a == 2).count(), 6);
        // One dimension: 1250 strata exceed the 1000 increments and are cut to 1000.
        let s = Strata::new(1, 10_000, true, 0.75, 1000, 1000);
        assert_eq!((s.cubes, s.min_per_cube, s.increments[0]), (1000, 2, 1000));
        // Off: one hypercube holding every point.
        let s = Strata::new(3, 1000, false, 0.75, 100, 1000);
        assert_eq!(
            (s.cubes, s.min_per_cube, s.allocation_budget),
            (1, 1000, None)
        );
        assert_eq!(s.increments, [100; 3]);
    }

    #[test]
    fn chunks_are_equal_at_least_min_chunk_and_capped() {
        // (points, points per chunk, chunks)
        for (n, chunk, chunks) in [
            (50, 50, 1),
            (4_999, 4_999, 1),
            (10_000, 2_500, 4),
            (50_001, 2_501, 20),
            (1 << 20, 1 << 14, 64),
            (1 << 22, 1 << 16, 64),
            (10_000_000, 1 << 16, 153),
        ] {
            assert_eq!(chunk_size(n), chunk, "{n}");
            assert_eq!(n.div_ceil(chunk_size(n)), chunks, "{n}");
        }
        // Past 2^32 points the chunks grow so that there are never more than MAX_CHUNKS.
        let huge = 1u64 << 40;
        assert_eq!(huge.div_ceil(chunk_size(huge)), MAX_CHUNKS);
    }

    #[test]
    fn allocation_never_exceeds_the_budget() {
        let s = Strata::new(2, 1001, true, 0.75, 100, 1000);
        assert_eq!((s.cubes, s.min_per_cube), (121, 2));
        let sigf: Vec<f64> = (0..s.cubes)
            .map(|h| ((h * 7919) % 13) as f64 + 0.1)
            .collect();
        let sum: f64 = sigf.iter().sum();
        let allocation = Allocation {
            min: s.min_per_cube,
            scale: Some(s.allocation_budget.unwrap() / sum * ALLOCATION_SAFETY),
            sigf: &sigf,
        };
        let (chunks, total) = plan_chunks(&s, &allocation);
        // Each floor loses less than one point.
        assert!((1001 - s.cubes..=1001).contains(&total), "{total}");
        assert_eq!(chunks.len(), 1);
        // All the variance in one hypercube: it gets the 751 allocated points (less the
        // safety margin's rounding down) on top of its two.
        let mut sigf = vec![0.0; s.cubes as usize];
        sigf[17] = 3.0;
        let allocation = Allocation {
            min: s.min_per_cube,
            scale: Some(s.allocation_budget.unwrap() / 3.0 * ALLOCATION_SAFETY),
            sigf: &sigf,
        };
        assert_eq!(allocation.evaluations(17), 752);
        assert_eq!(plan_chunks(&s, &allocation).1, 752 + 120 * 2);
    }
}
