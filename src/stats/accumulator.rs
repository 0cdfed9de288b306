//! Streaming mean and variance with exact merging (Welford 1962; Chan, Golub & LeVeque 1979),
//! and two-pass summaries of whole slices (Chan, Golub & LeVeque 1983).

use super::estimate::{ErrorBasis, Estimate};
use super::rounding::{UNIT_ROUNDOFF, contribution_allowance, gamma};
use super::warning::Warning;
use crate::simd::{Kernel, dispatch};
use crate::stop_reason::StopReason;

/// Interleaved partial sums of [`Accumulator::extend`]: enough independent chains to fill
/// 8 vector lanes of `f64` or hide an addition's latency; fixed, so results do not depend on
/// the machine.
const LANES: usize = 8;

/// Values up to this magnitude (2^480) are accumulated as they are: the squares of their
/// deviations, summed over up to 2^60 values, stay finite. Larger values are accumulated in
/// units of a power of two, [`Accumulator`]'s `scale`, so that values up to `f64::MAX` keep a
/// finite mean and standard error.
pub(crate) const UNSCALED_LIMIT: f64 = f64::from_bits((1023 + 480) << 52); // 2^480, exactly

/// An accumulator whose values so far are all zero takes a first value below this magnitude
/// (2^-480) in units of a power of two near it: the squares of the deviations of values below
/// about `1e-154` underflow, and the standard error with them (values of `1e-200` gave one
/// `1e-14` of the true one).
const SMALL_LIMIT: f64 = f64::from_bits((1023 - 480) << 52); // 2^-480, exactly

/// The smallest units, 2^-960: normal, and values down to the least subnormal are then at
/// least 2^-114 of them.
const SMALLEST_SCALE: f64 = f64::from_bits((1023 - 960) << 52);

/// The factor by which the scale grows, 2^64: a handful of steps covers the exponent range.
const SCALE_STEP: f64 = f64::from_bits((1023 + 64) << 52); // 2^64

/// Count, mean and sum of squared deviations (`M2`) of a stream of values, plus min, max and
/// a count of non-finite values (which are kept out of the moments).
///
/// Welford's update keeps the variance accurate where the naive `E[Y^2] - E[Y]^2` (A.9)
/// cancels; Chan's pairwise formula merges two accumulators, so threads, processes and
/// machines can each accumulate a part of the stream and combine the parts. Values beyond
/// about `1e144` are accumulated in units of a power of two (exactly, so the bits of results
/// that need no scaling are unchanged), so that values up to `f64::MAX` keep a mean within
/// `[min, max]` and a finite standard error; only [`m2`](Self::m2) and
/// [`variance`](Self::variance), which are squares, may then overflow to infinity. Values all
/// below about `1e-145` are accumulated in units near them likewise, so that their standard
/// error does not underflow (their variance, a square, may).
///
/// ```
/// use mcint::stats::Accumulator;
/// let mut left = Accumulator::new();
/// let mut right = Accumulator::new();
/// for y in [1.0, 2.0] { left.push(y); }
/// for y in [3.0, 4.0, f64::NAN] { right.push(y); }
/// left.merge(&right);
/// assert_eq!((left.count(), left.mean(), left.non_finite()), (4, 2.5, 1));
/// assert!((left.variance() - 5.0 / 3.0).abs() < 1e-15);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(into = "AccumulatorState", try_from = "AccumulatorState")
)]
pub struct Accumulator {
    count: u64,
    mean: f64,
    /// `M2` in units of `scale^2`.
    m2: f64,
    min: f64,
    max: f64,
    non_finite: u64,
    /// A bound on the rounding error of `mean` against the exact mean of the finite values
    /// (see [`rounding_error`](Self::rounding_error)).
    rounding: f64,
    /// A power of two, 1 until a value beyond [`UNSCALED_LIMIT`] arrives: deviations and
    /// `m2` are computed in its units.
    scale: f64,
}

impl Default for Accumulator {
    fn default() -> Self {
        Accumulator::new()
    }
}

impl Accumulator {
    /// An empty accumulator.
    ///
    /// ```
    /// assert_eq!(mcint::stats::Accumulator::new().count(), 0);
    /// ```
    pub fn new() -> Self {
        Accumulator {
            count: 0,
            mean: 0.0,
            m2: 0.0,
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
            non_finite: 0,
            rounding: 0.0,
            scale: 1.0,
        }
    }

    /// Adds one value; NaN and infinities are counted in [`non_finite`](Self::non_finite)
    /// and otherwise ignored.
    ///
    /// ```
    /// let mut acc = mcint::stats::Accumulator::new();
    /// acc.push(f64::INFINITY);
    /// assert_eq!((acc.count(), acc.non_finite()), (0, 1));
    /// ```
    #[inline]
    pub fn push(&mut self, y: f64) {
        if !y.is_finite() {
            self.non_finite += 1;
            return;
        }
        if y.abs() > UNSCALED_LIMIT * self.scale {
            self.rescale(y.abs());
        } else if y != 0.0 && y.abs() < SMALL_LIMIT && self.all_zero_so_far() {
            self.scale = small_scale_for(y.abs()).min(self.scale);
        }
        self.count += 1;
        let k = self.count as f64;
        if self.scale == 1.0 {
            let delta = y - self.mean;
            self.mean += delta / k;
            self.m2 += delta * (y - self.mean);
            self.rounding = self.rounding * (1.0 - 1.0 / k)
                + UNIT_ROUNDOFF * (self.mean.abs() + 2.0 * delta.abs() / k);
        } else {
            // The same update in units of `scale` (exact: a power of two).
            let (y_s, mean_s) = (y / self.scale, self.mean / self.scale);
            let delta = y_s - mean_s;
            let new_mean_s = mean_s + delta / k;
            self.m2 += delta * (y_s - new_mean_s);
            self.mean = new_mean_s * self.scale;
            self.rounding = self.rounding * (1.0 - 1.0 / k)
                + UNIT_ROUNDOFF * self.mean.abs()
                + (UNIT_ROUNDOFF * 2.0 * delta.abs() / k) * self.scale;
        }
        self.min = self.min.min(y);
        self.max = self.max.max(y);
    }

    /// Grows the scale until `magnitude` is within [`UNSCALED_LIMIT`] of it.
    fn rescale(&mut self, magnitude: f64) {
        self.rescale_to(scale_for(magnitude).max(self.scale));
    }

    /// Expresses `m2` in units of `scale` (larger ones, or smaller for an all-zero
    /// accumulator).
    fn rescale_to(&mut self, scale: f64) {
        let ratio = self.scale / scale;
        // Skipped for a zero `m2`: a ratio from small units can square to infinity.
        if self.m2 != 0.0 {
            self.m2 *= ratio * ratio;
        }
        self.scale = scale;
    }

    /// Whether every value so far was zero (or there were none): such an accumulator is exact
    /// in any units.
    fn all_zero_so_far(&self) -> bool {
        self.count == 0 || self.all_zero()
    }

    /// Adds every value of a slice: the same statistics as [`push`](Self::push)ing them one
    /// by one, up to rounding, computed faster.
    ///
    /// The slice's count, minimum, maximum and sum are gathered in eight interleaved
    /// partial results (independent chains that the CPU overlaps and the compiler vectorizes),
    /// then its squared deviations from its own mean in a second pass, with the correction of
    /// Chan, Golub & LeVeque (1983) for the rounding of that mean; the slice's summary is then
    /// merged like [`merge`](Self::merge). The two-pass sums are at least as accurate as
    /// Welford's update, and the order of operations is fixed, so the bits do not depend on the
    /// machine. A slice with values beyond about `1e144`, or all below about `1e-145`, falls
    /// back to pushing value by value.
    ///
    /// ```
    /// let mut acc = mcint::stats::Accumulator::new();
    /// acc.extend(&[1.0, 3.0]);
    /// assert_eq!(acc.mean(), 2.0);
    /// ```
    pub fn extend(&mut self, values: &[f64]) {
        match Accumulator::of_slice(values) {
            Some(summary) => self.merge(&summary),
            None => values.iter().for_each(|&y| self.push(y)),
        }
    }

    /// The statistics of a slice by two passes, or `None` if a sum overflows; compiled for
    /// the widest vector instructions the CPU has (the lanes are explicit, so every
    /// instruction set gives the same bits).
    fn of_slice(values: &[f64]) -> Option<Accumulator> {
        dispatch(SliceSummary(values))
    }

    /// [`of_slice`](Accumulator::of_slice), inlined into each dispatched build.
    #[inline(always)]
    fn of_slice_inline(values: &[f64]) -> Option<Accumulator> {
        let (chunks, rest) = values.as_chunks::<LANES>();
        // Pass 1: finite count, sum, min and max per lane. Whole arrays of LANES values, then
        // the rest, through functions inlined into each dispatched build: a known length
        // makes each array one vector operation.
        let mut first = FirstPass {
            counts: [0; LANES],
            sums: [0.0; LANES],
            mins: [f64::INFINITY; LANES],
            maxs: [f64::NEG_INFINITY; LANES],
        };
        for lanes in chunks {
            first.add(lanes);
        }
        first.add(rest);
        let FirstPass {
            counts,
            sums,
            mins,
            maxs,
        } = first;
        let count: u64 = counts.iter().sum();
        let non_finite = values.len() as u64 - count;
        if count == 0 {
            return Some(Accumulator {
                non_finite,
                ..Accumulator::new()
            });
        }
        let min = mins.iter().copied().fold(f64::INFINITY, f64::min);
        let max = maxs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let largest = min.abs().max(max.abs());
        if largest > UNSCALED_LIMIT || (largest > 0.0 && largest < SMALL_LIMIT) {
            return None; // values that need a scale are pushed one by one
        }
        let sum: f64 = sums.iter().sum();
        let mean = sum / count as f64;
        // Pass 2: deviations from the slice mean, and their sum, which is zero but for the
        // rounding of `mean`; subtracting its square over `count` corrects for that.
        let mut second = SecondPass {
            mean,
            deviations: [0.0; LANES],
            squares: [0.0; LANES],
        };
        for lanes in chunks {
            second.add(lanes);
        }
        second.add(rest);
        let SecondPass {
            deviations,
            squares,
            ..
        } = second;
        let deviation: f64 = deviations.iter().sum();
        let m2 = squares.iter().sum::<f64>() - deviation * deviation / count as f64;
        // Each value passes through at most ceil(len / LANES) additions in its lane and
        // LANES more joining the lanes; |sum| / count <= the largest magnitude.
        let height = values.len().div_ceil(LANES) + LANES;
        let rounding = gamma(height as f64) * min.abs().max(max.abs()) + UNIT_ROUNDOFF * mean.abs();
        Some(Accumulator {
            count,
            mean,
            m2: m2.max(0.0),
            min,
            max,
            non_finite,
            rounding,
            scale: 1.0,
        })
    }

    /// Combines another accumulator into this one, as if its values had been pushed here.
    ///
    /// ```
    /// use mcint::stats::Accumulator;
    /// let mut a = Accumulator::new();
    /// a.push(1.0);
    /// let mut b = Accumulator::new();
    /// b.push(5.0);
    /// a.merge(&b);
    /// assert_eq!((a.mean(), a.min(), a.max()), (3.0, 1.0, 5.0));
    /// ```
    pub fn merge(&mut self, other: &Accumulator) {
        self.non_finite += other.non_finite;
        if other.count == 0 {
            return;
        }
        if self.count == 0 {
            let non_finite = self.non_finite;
            *self = *other;
            self.non_finite = non_finite;
            return;
        }
        let (na, nb) = (self.count as f64, other.count as f64);
        let n = na + nb;
        // The larger units, unless one side is all zeros, which takes the other's (small) ones.
        let scale = if other.all_zero_so_far() {
            self.scale
        } else if self.all_zero_so_far() {
            other.scale
        } else {
            self.scale.max(other.scale)
        };
        self.rescale_to(scale);
        let other_ratio = other.scale / scale;
        let other_m2 = if other.m2 == 0.0 {
            0.0
        } else {
            other.m2 * (other_ratio * other_ratio)
        };
        // In units of `scale`; with scale 1 these are the plain formulas, bit for bit.
        let (mean_s, other_mean_s) = (self.mean / scale, other.mean / scale);
        let delta = other_mean_s - mean_s;
        self.mean = (mean_s + delta * (nb / n)) * scale;
        self.m2 += other_m2 + delta * delta * (na * nb / n);
        self.rounding = (na * self.rounding + nb * other.rounding) / n
            + UNIT_ROUNDOFF * self.mean.abs()
            + (UNIT_ROUNDOFF * 3.0 * delta.abs() * (nb / n)) * scale;
        self.count += other.count;
        self.min = self.min.min(other.min);
        self.max = self.max.max(other.max);
    }

    /// Number of finite values pushed.
    ///
    /// ```
    /// assert_eq!(mcint::stats::Accumulator::new().count(), 0);
    /// ```
    pub fn count(&self) -> u64 {
        self.count
    }

    /// Mean of the finite values (0 when there are none).
    ///
    /// ```
    /// let mut acc = mcint::stats::Accumulator::new();
    /// acc.extend(&[2.0, 4.0]);
    /// assert_eq!(acc.mean(), 3.0);
    /// ```
    pub fn mean(&self) -> f64 {
        self.mean
    }

    /// Sum of squared deviations from the mean, `M2` (infinite when it overflows: values
    /// beyond about `1e154`).
    ///
    /// ```
    /// let mut acc = mcint::stats::Accumulator::new();
    /// acc.extend(&[2.0, 4.0]);
    /// assert_eq!(acc.m2(), 2.0);
    /// ```
    pub fn m2(&self) -> f64 {
        self.m2 * self.scale * self.scale
    }

    /// Unbiased sample variance `M2 / (n - 1)` (NaN with fewer than two values; infinite when
    /// the values are so large that it overflows, beyond about `1e154`).
    ///
    /// ```
    /// let mut acc = mcint::stats::Accumulator::new();
    /// acc.extend(&[2.0, 4.0]);
    /// assert_eq!(acc.variance(), 2.0);
    /// ```
    pub fn variance(&self) -> f64 {
        if self.count < 2 {
            f64::NAN
        } else {
            self.m2 / (self.count - 1) as f64 * self.scale * self.scale
        }
    }

    /// The variance in units of `unit` (a power of two), `variance() / unit^2`, taken from the
    /// scaled sums so that it does not underflow or overflow where that quotient is a normal
    /// number (NaN with fewer than two values). With `unit` 1 it is
    /// [`variance`](Self::variance), bit for bit.
    pub(crate) fn variance_in(&self, unit: f64) -> f64 {
        if self.count < 2 {
            f64::NAN
        } else {
            let ratio = self.scale / unit;
            self.m2 / (self.count - 1) as f64 * ratio * ratio
        }
    }

    /// The sample standard deviation, `sqrt(variance())`, taken in the sums' units so that it
    /// is finite and nonzero whenever the values are and differ (NaN with fewer than two
    /// values); bit for bit `variance().sqrt()` when that neither overflows nor underflows.
    pub(crate) fn std_dev(&self) -> f64 {
        self.variance_in(self.scale).sqrt() * self.scale
    }

    /// Units in which the variances of all of `accumulators` can be compared and summed
    /// ([`variance_in`](Self::variance_in)): those of their largest finite value in
    /// magnitude, a power of two (1 for values from about `1e-145` to `1e144`).
    pub(crate) fn common_unit(accumulators: &[Accumulator]) -> f64 {
        let largest = accumulators
            .iter()
            .filter(|a| a.count > 0)
            .map(|a| a.min.abs().max(a.max.abs()))
            .fold(0.0, f64::max);
        scale_for(largest)
    }

    /// Smallest finite value (`+inf` when empty).
    ///
    /// ```
    /// assert_eq!(mcint::stats::Accumulator::new().min(), f64::INFINITY);
    /// ```
    pub fn min(&self) -> f64 {
        self.min
    }

    /// Largest finite value (`-inf` when empty).
    ///
    /// ```
    /// assert_eq!(mcint::stats::Accumulator::new().max(), f64::NEG_INFINITY);
    /// ```
    pub fn max(&self) -> f64 {
        self.max
    }

    /// Number of NaN or infinite values pushed.
    ///
    /// ```
    /// let mut acc = mcint::stats::Accumulator::new();
    /// acc.push(f64::NAN);
    /// assert_eq!(acc.non_finite(), 1);
    /// ```
    pub fn non_finite(&self) -> u64 {
        self.non_finite
    }

    /// The estimate of the mean of independent values: standard error `sqrt(s^2 / n)` with
    /// `n - 1` degrees of freedom (Jarosz's A.22 with the sample variance for `sigma^2`).
    /// With fewer than two values no standard error is given.
    ///
    /// ```
    /// let mut acc = mcint::stats::Accumulator::new();
    /// acc.extend(&[1.0, 2.0, 3.0, 4.0]);
    /// let e = acc.estimate();
    /// assert_eq!(e.mean, 2.5);
    /// assert!((e.std_error.unwrap() - (5.0f64 / 3.0 / 4.0).sqrt()).abs() < 1e-15);
    /// ```
    pub fn estimate(&self) -> Estimate {
        let honest = self.count >= 2;
        let mut estimate = Estimate {
            mean: self.mean,
            std_error: honest.then(|| self.scaled_std_error()),
            dof: honest.then(|| (self.count - 1) as f64),
            basis: if honest {
                ErrorBasis::PerSample
            } else {
                ErrorBasis::None
            },
            n: self.count,
            evaluations: self.count + self.non_finite,
            replicates: 1,
            non_finite: self.non_finite,
            stop: StopReason::Budget,
            converged: None,
            iterations: 1,
            chi2_dof: None,
            q_value: None,
            rounding_error: self.rounding_error(),
            warnings: Vec::new(),
            error_bound: None,
        };
        if self.all_zero() {
            estimate.warn(Warning::AllZero { count: self.count });
        }
        estimate.finalize();
        estimate
    }

    /// `sqrt(s^2 / n)`, computed in units of the scale so that it is finite whenever the
    /// values are (needs two values).
    fn scaled_std_error(&self) -> f64 {
        (self.m2 / (self.count - 1) as f64 / self.count as f64).sqrt() * self.scale
    }

    /// Feeds the state into the checksum of a saved run (checkpoints; the words and their
    /// order are part of the checkpoint format).
    pub(crate) fn feed_checksum(h: &mut crc32fast::Hasher, acc: &Accumulator) {
        for word in [
            acc.count(),
            acc.mean().to_bits(),
            acc.m2().to_bits(),
            acc.min().to_bits(),
            acc.max().to_bits(),
            acc.non_finite(),
            acc.rounding.to_bits(),
        ] {
            h.update(&word.to_le_bytes());
        }
    }

    /// Whether every finite value was exactly zero (and there was at least one).
    pub(crate) fn all_zero(&self) -> bool {
        self.count > 0 && self.min == 0.0 && self.max == 0.0
    }

    /// A bound on the floating-point error of [`mean`](Self::mean): the rounding of the sums
    /// that produced it, tracked operation by operation (Welford updates, two-pass slice sums,
    /// Chan merges), plus an allowance of 64 units in the last place of the values' magnitude
    /// for the evaluation of each value itself. See
    /// [`Estimate::rounding_error`](crate::Estimate::rounding_error).
    ///
    /// ```
    /// let mut acc = mcint::stats::Accumulator::new();
    /// acc.extend(&[0.1; 1000]);
    /// let exact = 0.1; // the mean of equal values
    /// assert!((acc.mean() - exact).abs() <= acc.rounding_error());
    /// assert!(acc.rounding_error() < 1e-12);
    /// ```
    pub fn rounding_error(&self) -> f64 {
        if self.count == 0 {
            return 0.0;
        }
        // mean |y| is at most the largest magnitude, and at most the root mean square.
        let mean_s = self.mean / self.scale;
        let rms = (mean_s * mean_s + self.m2 / self.count as f64).sqrt() * self.scale;
        let scale = self.min.abs().max(self.max.abs()).min(rms);
        self.rounding + contribution_allowance(scale)
    }
}

/// The power of two (1, 2^64, 2^128, ...) in whose units values up to `magnitude` can be
/// squared and summed without overflow: 1 up to [`UNSCALED_LIMIT`]; below [`SMALL_LIMIT`]
/// (and above 0) a power of 2^-64 near `magnitude`, in whose units the squares of values of
/// that size do not underflow.
pub(crate) fn scale_for(magnitude: f64) -> f64 {
    if magnitude > 0.0 && magnitude < SMALL_LIMIT {
        return small_scale_for(magnitude);
    }
    let mut scale = 1.0;
    while magnitude > UNSCALED_LIMIT * scale {
        scale *= SCALE_STEP;
    }
    scale
}

/// The largest power of 2^64 at most `magnitude` (at most 1, at least the normal 2^-960): the
/// units of an accumulator of small values.
fn small_scale_for(magnitude: f64) -> f64 {
    let mut scale = 1.0;
    while magnitude < scale && scale > SMALLEST_SCALE {
        scale /= SCALE_STEP;
    }
    scale
}

/// The serialized form of an [`Accumulator`]: `min` and `max` are absent while it is empty
/// (their infinite starting values have no JSON form).
#[cfg(feature = "serde")]
#[derive(serde::Serialize, serde::Deserialize)]
struct AccumulatorState {
    count: u64,
    mean: f64,
    /// In units of `scale^2`.
    m2: f64,
    min: Option<f64>,
    max: Option<f64>,
    non_finite: u64,
    /// Absent from states written before the bound was kept.
    #[serde(default)]
    rounding: f64,
    /// Written only when it is not 1 (values beyond about 1e144), so states of ordinary runs
    /// keep their form.
    #[serde(default = "unit_scale", skip_serializing_if = "is_unit_scale")]
    scale: f64,
}

#[cfg(feature = "serde")]
fn unit_scale() -> f64 {
    1.0
}

#[cfg(feature = "serde")]
fn is_unit_scale(scale: &f64) -> bool {
    *scale == 1.0
}

#[cfg(feature = "serde")]
impl From<Accumulator> for AccumulatorState {
    fn from(a: Accumulator) -> Self {
        let seen = a.count > 0;
        AccumulatorState {
            count: a.count,
            mean: a.mean,
            m2: a.m2,
            min: seen.then_some(a.min),
            max: seen.then_some(a.max),
            non_finite: a.non_finite,
            rounding: a.rounding,
            scale: a.scale,
        }
    }
}

#[cfg(feature = "serde")]
impl TryFrom<AccumulatorState> for Accumulator {
    type Error = String;

    fn try_from(s: AccumulatorState) -> std::result::Result<Self, String> {
        let rounding_ok = s.rounding.is_finite() && s.rounding >= 0.0;
        // A (normal) power of two: the only scales an accumulator takes.
        let scale_ok = s.scale.is_finite() && s.scale > 0.0 && s.scale.to_bits() << 12 == 0;
        let consistent = rounding_ok
            && scale_ok
            && match (s.count, s.min, s.max) {
                (0, None, None) => s.mean == 0.0 && s.m2 == 0.0,
                (_, Some(lo), Some(hi)) => {
                    s.count > 0 && lo <= hi && s.mean.is_finite() && s.m2.is_finite() && s.m2 >= 0.0
                }
                _ => false,
            };
        if !consistent {
            return Err(format!(
                "inconsistent accumulator: count {}, mean {}, m2 {}, min {:?}, max {:?}, \
                 scale {}",
                s.count, s.mean, s.m2, s.min, s.max, s.scale
            ));
        }
        Ok(Accumulator {
            count: s.count,
            mean: s.mean,
            m2: s.m2,
            min: s.min.unwrap_or(f64::INFINITY),
            max: s.max.unwrap_or(f64::NEG_INFINITY),
            non_finite: s.non_finite,
            rounding: s.rounding,
            scale: s.scale,
        })
    }
}

/// Pass 1 of [`Accumulator::of_slice`]: per lane, the finite count, sum, min and max.
struct FirstPass {
    counts: [u64; LANES],
    sums: [f64; LANES],
    mins: [f64; LANES],
    maxs: [f64; LANES],
}

impl FirstPass {
    /// Adds up to `LANES` values, value `j` to lane `j`; non-finite values are masked out
    /// (a select, not a branch, so the loop vectorizes).
    #[inline(always)]
    fn add(&mut self, lanes: &[f64]) {
        for (lane, &y) in lanes.iter().enumerate() {
            let finite = y.is_finite();
            self.counts[lane] += u64::from(finite);
            self.sums[lane] += if finite { y } else { 0.0 };
            self.mins[lane] = self.mins[lane].min(if finite { y } else { f64::INFINITY });
            self.maxs[lane] = self.maxs[lane].max(if finite { y } else { f64::NEG_INFINITY });
        }
    }
}

/// Pass 2 of [`Accumulator::of_slice`]: per lane, the sums of deviations from `mean` and of
/// their squares.
struct SecondPass {
    mean: f64,
    deviations: [f64; LANES],
    squares: [f64; LANES],
}

impl SecondPass {
    /// Adds up to `LANES` values, value `j` to lane `j`.
    #[inline(always)]
    fn add(&mut self, lanes: &[f64]) {
        for (lane, &y) in lanes.iter().enumerate() {
            let d = if y.is_finite() { y - self.mean } else { 0.0 };
            self.deviations[lane] += d;
            self.squares[lane] += d * d;
        }
    }
}

/// [`Accumulator::of_slice`] as a kernel for the run-time dispatch.
struct SliceSummary<'a>(&'a [f64]);

impl Kernel for SliceSummary<'_> {
    type Output = Option<Accumulator>;
    #[inline(always)]
    fn run(self) -> Option<Accumulator> {
        Accumulator::of_slice_inline(self.0)
    }
}
