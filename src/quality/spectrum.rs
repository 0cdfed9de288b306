//! Fourier spectra of two-dimensional point sets: the periodogram and its radial average and
//! anisotropy (Ulichney 1987, "Digital Halftoning"; Lagae & Dutré 2008, "A comparison of
//! methods for generating Poisson disk distributions", Computer Graphics Forum 27(1)).
//!
//! The periodogram of `N` points `x_j` on the unit torus at an integer frequency `k` is
//! `P(k) = |sum_j exp(-2 pi i k . x_j)|^2 / N`. It is periodic in each `x_j` (only `x mod 1`
//! matters), `P(0) = N`, and `P(-k) = P(k)`. For independent uniform points
//! `E[P(k)] = 1` at every `k != 0` (white noise); blue-noise sets (jittered, Poisson disk)
//! have `P(k)` well below 1 at low frequencies, which is what makes their integration error
//! small for smooth integrands.
//!
//! # Evaluation
//!
//! Direct summation over the `(2K + 1)^2` frequencies of `[-K, K]^2`, `O(N K^2)`. Only the
//! rows `ky >= 0` are computed (the others follow from `P(-k) = P(k)`). In a row, each point's
//! term starts from `exp(-2 pi i ky y_j)`, evaluated directly with the phase reduced modulo 1,
//! and is carried to `kx = 1, 2, ..., K` (and `-1, ..., -K`) by multiplying with
//! `exp(-2 pi i x_j)` (and its conjugate): one complex multiplication per term instead of a
//! sine and cosine. The rounding error of `K` such steps grows like `K * 2^-53`, below `1e-12`
//! relative for `K <= 1024`. Rows are split across threads; each row is computed by one
//! thread with a fixed order of summation, so the result does not depend on the number of
//! threads, and passes are added in pass order.

use crate::engine::{ChunkJob, Executor, Limits};
use crate::error::{Error, Result};
use crate::points::Points;
use crate::sampler::{PassKind, Sampler};
use crate::threads::available_threads;
use std::f64::consts::TAU;

/// The (mean) periodogram `P(k)` of two-dimensional point sets at the integer frequencies
/// `k = (kx, ky)` in `[-K, K]^2`.
///
/// [`values`](Self::values) is row-major with [`size`](Self::size) `= 2K + 1` values a row:
/// `P(kx, ky)` sits at `(ky + K) * size + (kx + K)`, so the first row is `ky = -K`, the centre
/// `(K, K)` is `k = 0` with `P(0) = N`, and frequency `k` means `k` periods across the unit
/// square.
///
/// ```
/// use mcint::{Points, quality::periodogram};
/// let mut points = Points::new(2, 2)?;
/// points.column_mut(0).copy_from_slice(&[0.0, 0.5]);
/// // Two points half a period apart cancel at odd kx and add up at even kx.
/// let p = periodogram(&points, 2)?;
/// assert_eq!((p.size(), p.values().len()), (5, 25));
/// assert_eq!(p.get(0, 0), Some(2.0));
/// assert!(p.get(1, 0).unwrap().abs() < 1e-15);
/// assert!((p.get(2, -1).unwrap() - 2.0).abs() < 1e-12);
/// assert_eq!(p.get(3, 0), None);
/// # Ok::<(), mcint::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Periodogram {
    max_frequency: usize,
    points: usize,
    passes: usize,
    values: Vec<f64>,
}

/// The radially averaged power spectrum of a [`Periodogram`] and its anisotropy.
///
/// Annulus `i` (`i = 1 ..= K`) holds the frequencies `k != 0` with `i - 1/2 <= |k| < i + 1/2`
/// (all of them lie in `[-K, K]^2`, so every annulus is complete). For each annulus:
///
/// * `power[i - 1]` is the mean of `P(k)` over it, the radially averaged power spectrum;
/// * `anisotropy[i - 1]` is the sample variance of `P(k)` over it (divided by `count - 1`)
///   over the square of that mean, as defined by Lagae & Dutré (2008). An isotropic process
///   gives only the noise of the periodogram itself: about `1 / M` for the mean of `M`
///   independent periodograms of white noise (`-10 log10 M` in decibels), since `P(k)` is then
///   close to exponentially distributed with variance `1 - 1/N`. Values well above that mark
///   directions that differ, such as the axes of a jittered grid.
///
/// ```
/// use mcint::{quality::mean_periodogram, sampler::Independent};
/// let spectrum = mean_periodogram(&Independent::new(2, 5)?, 256, 8, 16)?.radial_spectrum();
/// assert_eq!(spectrum.frequencies[..3], [1.0, 2.0, 3.0]);
/// assert_eq!(spectrum.counts[..2], [8, 12]); // |k| = 1, sqrt 2; |k| = 2, sqrt 5
/// assert!(spectrum.power.iter().all(|&p| (p - 1.0).abs() < 0.6)); // white noise: about 1
/// # Ok::<(), mcint::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct RadialSpectrum {
    /// The centre `i` of each annulus, in periods across the unit square.
    pub frequencies: Vec<f64>,
    /// Mean `P(k)` over each annulus.
    pub power: Vec<f64>,
    /// Variance of `P(k)` over each annulus divided by the squared mean (0 if the mean is 0).
    pub anisotropy: Vec<f64>,
    /// How many frequencies `k` each annulus holds.
    pub counts: Vec<usize>,
}

impl Periodogram {
    /// The largest `K` accepted: `(2K + 1)^2` values, 34 MB at this limit.
    ///
    /// ```
    /// use mcint::{Points, quality::{periodogram, Periodogram}};
    /// let points = Points::new(2, 1)?;
    /// assert!(periodogram(&points, Periodogram::MAX_FREQUENCY).is_ok());
    /// assert!(periodogram(&points, Periodogram::MAX_FREQUENCY + 1).is_err());
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub const MAX_FREQUENCY: usize = 1024;

    /// The most points in one set (or one pass), `2^24`.
    ///
    /// ```
    /// assert_eq!(mcint::quality::Periodogram::MAX_POINTS, 1 << 24);
    /// ```
    pub const MAX_POINTS: usize = 1 << 24;

    /// The most terms one call may sum, `2^38`: points times passes times the `(K + 1)(2K + 1)`
    /// frequencies computed, minutes of work on one core, so that no call runs for hours.
    ///
    /// ```
    /// use mcint::{quality::{mean_periodogram, Periodogram}, sampler::Independent};
    /// let sampler = Independent::new(2, 0)?;
    /// // 2^20 points at K = 1024 would be 2^41 terms.
    /// let err = mean_periodogram(&sampler, 1 << 20, 1, 1024).unwrap_err();
    /// assert!(err.to_string().contains(&Periodogram::MAX_TERMS.to_string()));
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub const MAX_TERMS: u64 = 1 << 38;

    /// `K`, the largest `|kx|` and `|ky|`.
    ///
    /// ```
    /// let p = mcint::quality::periodogram(&mcint::Points::new(2, 1)?, 3)?;
    /// assert_eq!(p.max_frequency(), 3);
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn max_frequency(&self) -> usize {
        self.max_frequency
    }

    /// `2K + 1`, the number of frequencies along each axis (values per row, and rows).
    ///
    /// ```
    /// let p = mcint::quality::periodogram(&mcint::Points::new(2, 1)?, 3)?;
    /// assert_eq!(p.size(), 7);
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn size(&self) -> usize {
        2 * self.max_frequency + 1
    }

    /// `N`, the number of points of each set.
    ///
    /// ```
    /// let p = mcint::quality::periodogram(&mcint::Points::new(2, 5)?, 3)?;
    /// assert_eq!(p.points(), 5);
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn points(&self) -> usize {
        self.points
    }

    /// How many sets (sampler passes) were averaged; 1 for [`periodogram`].
    ///
    /// ```
    /// use mcint::{quality::mean_periodogram, sampler::Independent};
    /// let p = mean_periodogram(&Independent::new(2, 0)?, 16, 3, 4)?;
    /// assert_eq!(p.passes(), 3);
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn passes(&self) -> usize {
        self.passes
    }

    /// All `(2K + 1)^2` values, row-major (row `ky + K`, column `kx + K`).
    ///
    /// ```
    /// let p = mcint::quality::periodogram(&mcint::Points::new(2, 4)?, 1)?;
    /// // All four points at the origin: every frequency sees them in phase.
    /// assert!(p.values().iter().all(|&v| (v - 4.0).abs() < 1e-12));
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// `P(kx, ky)`, or `None` outside `[-K, K]^2`.
    ///
    /// ```
    /// let p = mcint::quality::periodogram(&mcint::Points::new(2, 4)?, 1)?;
    /// assert_eq!(p.get(0, 0), Some(4.0));
    /// assert_eq!(p.get(-2, 0), None);
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn get(&self, kx: i64, ky: i64) -> Option<f64> {
        let k = self.max_frequency as i64;
        if kx.abs() > k || ky.abs() > k {
            return None;
        }
        let index = (ky + k) as usize * self.size() + (kx + k) as usize;
        Some(self.values[index])
    }

    /// The radially averaged power spectrum and anisotropy over annuli of width 1 (see
    /// [`RadialSpectrum`]).
    ///
    /// ```
    /// let p = mcint::quality::periodogram(&mcint::Points::new(2, 4)?, 5)?;
    /// let radial = p.radial_spectrum();
    /// assert_eq!(radial.frequencies.len(), 5);
    /// assert!(radial.power.iter().all(|&v| (v - 4.0).abs() < 1e-12));
    /// assert!(radial.anisotropy.iter().all(|&a| a < 1e-20));
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn radial_spectrum(&self) -> RadialSpectrum {
        let k = self.max_frequency as i64;
        let size = self.size();
        let bins = self.max_frequency;
        let mut sums = vec![0.0; bins];
        let mut counts = vec![0usize; bins];
        let mut members: Vec<Vec<f64>> = vec![Vec::new(); bins];
        for ky in -k..=k {
            for kx in -k..=k {
                let Some(bin) = annulus(kx * kx + ky * ky) else {
                    continue;
                };
                if bin > bins {
                    continue;
                }
                let v = self.values[(ky + k) as usize * size + (kx + k) as usize];
                sums[bin - 1] += v;
                counts[bin - 1] += 1;
                members[bin - 1].push(v);
            }
        }
        let power: Vec<f64> = sums
            .iter()
            .zip(&counts)
            .map(|(&s, &c)| s / c as f64)
            .collect();
        let anisotropy = members
            .iter()
            .zip(&power)
            .map(|(values, &mean)| {
                let squares: f64 = values.iter().map(|&v| (v - mean) * (v - mean)).sum();
                let variance = squares / (values.len() - 1) as f64;
                if mean == 0.0 {
                    0.0
                } else {
                    variance / (mean * mean)
                }
            })
            .collect();
        RadialSpectrum {
            frequencies: (1..=bins).map(|i| i as f64).collect(),
            power,
            anisotropy,
            counts,
        }
    }
}

/// The annulus `i = round(|k|)` of a frequency with `|k|^2 = r2`, `None` for `k = 0`.
fn annulus(r2: i64) -> Option<usize> {
    if r2 == 0 {
        return None;
    }
    // i - 1/2 <= |k| < i + 1/2  <=>  i^2 - i < r2 <= i^2 + i for integers.
    let mut i = ((r2 as f64).sqrt() + 0.5) as i64;
    while i * i + i < r2 {
        i += 1;
    }
    while i > 1 && (i - 1) * (i - 1) + (i - 1) >= r2 {
        i -= 1;
    }
    Some(i as usize)
}

/// The periodogram of a two-dimensional point set at the frequencies `[-K, K]^2`,
/// `K = max_frequency`, using all available threads (see [`Periodogram`]).
///
/// Errors: `points.dims() != 2`, an empty set, more than [`Periodogram::MAX_POINTS`] points,
/// a coordinate that is not finite, `max_frequency` outside `1 ..= `
/// [`Periodogram::MAX_FREQUENCY`], or more than [`Periodogram::MAX_TERMS`] terms.
///
/// ```
/// use mcint::{Points, quality::periodogram, sampler::{Jittered, Sampler}};
/// let mut points = Points::new(2, 1024)?;
/// Jittered::new(2, 32, 1)?.fill(0, &mut points)?;
/// let p = periodogram(&points, 8)?;
/// assert_eq!(p.get(0, 0), Some(1024.0));
/// // One point per cell of a 32 x 32 grid: almost no power at low frequencies.
/// assert!(p.get(1, 0).unwrap() < 0.1 && p.get(0, 1).unwrap() < 0.1);
/// # Ok::<(), mcint::Error>(())
/// ```
pub fn periodogram(points: &Points, max_frequency: usize) -> Result<Periodogram> {
    periodogram_with_threads(points, max_frequency, available_threads())
}

/// [`periodogram`] on `threads >= 1` threads; the result is bit-identical for every thread
/// count.
///
/// ```
/// use mcint::{Points, quality::periodogram_with_threads, sampler::{Independent, Sampler}};
/// let mut points = Points::new(2, 100)?;
/// Independent::new(2, 3)?.fill(0, &mut points)?;
/// let one = periodogram_with_threads(&points, 10, 1)?;
/// assert_eq!(one, periodogram_with_threads(&points, 10, 3)?);
/// assert!(periodogram_with_threads(&points, 10, 0).is_err());
/// # Ok::<(), mcint::Error>(())
/// ```
pub fn periodogram_with_threads(
    points: &Points,
    max_frequency: usize,
    threads: usize,
) -> Result<Periodogram> {
    check_sizes(points.len(), 1, max_frequency, threads)?;
    if points.dims() != 2 {
        return Err(Error::DimensionMismatch {
            what: "points of a periodogram",
            expected: 2,
            found: points.dims(),
        });
    }
    let mut half = vec![0.0; (max_frequency + 1) * (2 * max_frequency + 1)];
    add_half_periodogram(points, max_frequency, threads, &mut half)?;
    Ok(mirror(half, max_frequency, points.len(), 1))
}

/// The mean periodogram of `passes` independent passes of `points` points each from a
/// two-dimensional sampler, using all available threads (see [`Periodogram`]).
///
/// Pass `p` is the points the sampler numbers as pass `p`: indices `p * points ..` for
/// independent points, `p * max ..` for an extensible sequence (its first `points <= max`
/// points, a fresh randomization each pass) and `p * size ..` for fixed passes, which must then
/// have exactly `points = size` points. Averaging over passes estimates the expected
/// periodogram, whose noise shrinks like `1 / sqrt(passes)`. An unrandomized sequence repeats
/// the same pass.
///
/// Errors: a sampler not in two dimensions, `passes = 0`, a number of points its passes cannot
/// give, and the limits of [`periodogram`].
///
/// ```
/// use mcint::{quality::mean_periodogram, sampler::{Independent, Jittered}};
/// let white = mean_periodogram(&Independent::new(2, 1)?, 1024, 16, 8)?;
/// let jittered = mean_periodogram(&Jittered::new(2, 32, 1)?, 1024, 16, 8)?;
/// // White noise has power about 1 everywhere, jittered points almost none near k = 0.
/// assert!((white.get(2, 1).unwrap() - 1.0).abs() < 1.0);
/// assert!(jittered.get(2, 1).unwrap() < 0.1);
/// assert!(mean_periodogram(&Jittered::new(2, 32, 1)?, 1000, 16, 8).is_err());
/// # Ok::<(), mcint::Error>(())
/// ```
pub fn mean_periodogram(
    sampler: &dyn Sampler,
    points: usize,
    passes: usize,
    max_frequency: usize,
) -> Result<Periodogram> {
    mean_periodogram_with_threads(sampler, points, passes, max_frequency, available_threads())
}

/// [`mean_periodogram`] on `threads >= 1` threads; the result is bit-identical for every
/// thread count.
///
/// ```
/// use mcint::{quality::mean_periodogram_with_threads, sampler::{Scramble, Sobol}};
/// let sobol = Sobol::new(2, Scramble::Owen, 9)?;
/// let one = mean_periodogram_with_threads(&sobol, 256, 4, 12, 1)?;
/// assert_eq!(one, mean_periodogram_with_threads(&sobol, 256, 4, 12, 2)?);
/// # Ok::<(), mcint::Error>(())
/// ```
pub fn mean_periodogram_with_threads(
    sampler: &dyn Sampler,
    points: usize,
    passes: usize,
    max_frequency: usize,
    threads: usize,
) -> Result<Periodogram> {
    if sampler.dims() != 2 {
        return Err(Error::DimensionMismatch {
            what: "sampler of a periodogram",
            expected: 2,
            found: sampler.dims(),
        });
    }
    if passes == 0 {
        return Err(Error::invalid("passes", 0, "at least 1"));
    }
    check_sizes(points, passes, max_frequency, threads)?;
    let n = points as u64;
    let stride = match sampler.passes() {
        PassKind::Independent => n,
        PassKind::Extensible { max } => {
            if n > max {
                return Err(Error::invalid(
                    "points",
                    points,
                    format!(
                        "at most {max}, the points in one pass of the {} sampler",
                        sampler.name()
                    ),
                ));
            }
            max
        }
        PassKind::Fixed { size } => {
            if n != size {
                return Err(Error::invalid(
                    "points",
                    points,
                    format!(
                        "the {} sampler's pass size {size} (a part or several of its fixed \
                         passes is not one of its point sets)",
                        sampler.name()
                    ),
                ));
            }
            size
        }
    };
    (passes as u64 - 1)
        .checked_mul(stride)
        .and_then(|start| start.checked_add(n))
        .ok_or(Error::IndexOutOfRange {
            what: "sample index of the last pass",
            limit: u64::MAX,
        })?;
    let mut block = Points::new(2, points)?;
    let mut half = vec![0.0; (max_frequency + 1) * (2 * max_frequency + 1)];
    for pass in 0..passes as u64 {
        sampler.fill(pass * stride, &mut block)?;
        add_half_periodogram(&block, max_frequency, threads, &mut half)?;
    }
    let scale = 1.0 / passes as f64;
    half.iter_mut().for_each(|v| *v *= scale);
    Ok(mirror(half, max_frequency, points, passes))
}

/// Validates the sizes shared by every entry point.
fn check_sizes(points: usize, passes: usize, max_frequency: usize, threads: usize) -> Result<()> {
    if threads == 0 {
        return Err(Error::invalid("threads", 0, "at least 1"));
    }
    if max_frequency == 0 || max_frequency > Periodogram::MAX_FREQUENCY {
        return Err(Error::invalid(
            "max_frequency",
            max_frequency,
            format!("K in 1..={}", Periodogram::MAX_FREQUENCY),
        ));
    }
    if points == 0 {
        return Err(Error::invalid("points", 0, "at least 1 point"));
    }
    if points > Periodogram::MAX_POINTS {
        return Err(Error::invalid(
            "points",
            points,
            format!("at most {} points per set", Periodogram::MAX_POINTS),
        ));
    }
    let frequencies = ((max_frequency + 1) * (2 * max_frequency + 1)) as u64;
    let terms = (points as u64)
        .checked_mul(passes as u64)
        .and_then(|t| t.checked_mul(frequencies));
    match terms {
        Some(t) if t <= Periodogram::MAX_TERMS => Ok(()),
        _ => Err(Error::invalid(
            "points * passes * (K + 1) * (2K + 1)",
            format!("{points} * {passes} * {frequencies}"),
            format!("at most {} terms", Periodogram::MAX_TERMS),
        )),
    }
}

/// Adds `P(k)` for the rows `ky = 0 ..= K` of one point set to `half` (row `ky`, column
/// `kx + K`).
fn add_half_periodogram(
    points: &Points,
    max_frequency: usize,
    threads: usize,
    half: &mut [f64],
) -> Result<()> {
    let executor = Executor::new(Some(threads))?;
    let (xs, ys) = (points.column(0), points.column(1));
    for (dim, column) in [xs, ys].into_iter().enumerate() {
        if let Some(i) = column.iter().position(|v| !v.is_finite()) {
            return Err(Error::invalid(
                "points",
                format!("coordinate {} of point {i} in dimension {dim}", column[i]),
                "finite coordinates",
            ));
        }
    }
    // exp(-2 pi i x) of each point: the step from kx to kx + 1.
    let (step_re, step_im): (Vec<f64>, Vec<f64>) = xs
        .iter()
        .map(|&x| {
            let (s, c) = libm::sincos(TAU * (x - x.floor()));
            (c, -s)
        })
        .unzip();
    let back_im: Vec<f64> = step_im.iter().map(|&s| -s).collect();
    let row_len = 2 * max_frequency + 1;
    let rows = max_frequency + 1;
    let steps = Steps {
        ys,
        re: &step_re,
        im: &step_im,
        back_im: &back_im,
        max_frequency,
        norm: 1.0 / points.len() as f64,
    };
    // Each row is the same computation whichever thread does it, and rows are added in order.
    executor.run(
        &steps,
        0..rows as u64,
        rows as u64,
        &Limits::default(),
        |ky, row| {
            let ky = ky as usize;
            for (sum, v) in half[ky * row_len..(ky + 1) * row_len].iter_mut().zip(row) {
                *sum += v;
            }
            Ok(())
        },
    )?;
    Ok(())
}

impl ChunkJob for Steps<'_> {
    type Scratch = Scratch;
    type Output = Vec<f64>;

    fn scratch(&self) -> Result<Scratch> {
        Ok(Scratch::new(self.ys.len()))
    }

    fn run(&self, scratch: &mut Scratch, ky: u64, _: &Limits) -> Result<Option<Vec<f64>>> {
        let mut row = vec![0.0; 2 * self.max_frequency + 1];
        self.row(ky as usize, scratch, &mut row);
        Ok(Some(row))
    }

    fn origin(&self, ky: u64) -> (u64, u64) {
        (0, ky)
    }
}

/// The per-point data every row needs.
struct Steps<'a> {
    ys: &'a [f64],
    re: &'a [f64],
    im: &'a [f64],
    back_im: &'a [f64],
    max_frequency: usize,
    norm: f64,
}

/// Each point's current term `exp(-2 pi i k . x_j)`, and its value at `kx = 0`.
struct Scratch {
    re: Vec<f64>,
    im: Vec<f64>,
    base_re: Vec<f64>,
    base_im: Vec<f64>,
}

impl Scratch {
    fn new(len: usize) -> Self {
        Scratch {
            re: vec![0.0; len],
            im: vec![0.0; len],
            base_re: vec![0.0; len],
            base_im: vec![0.0; len],
        }
    }

    fn restart(&mut self) {
        self.re.copy_from_slice(&self.base_re);
        self.im.copy_from_slice(&self.base_im);
    }
}

impl Steps<'_> {
    /// `P(kx, ky)` for `kx = -K ..= K` into `row`.
    fn row(&self, ky: usize, scratch: &mut Scratch, row: &mut [f64]) {
        let k = self.max_frequency;
        let ky = ky as f64;
        for ((re, im), &y) in scratch
            .base_re
            .iter_mut()
            .zip(scratch.base_im.iter_mut())
            .zip(self.ys)
        {
            // Reduced modulo 1 first, so the sine and cosine see an argument below 2 pi.
            let phase = ky * y;
            let (sin, cos) = libm::sincos(TAU * (phase - phase.floor()));
            (*re, *im) = (cos, -sin);
        }
        scratch.restart();
        for kx in 0..=k {
            let (sr, si) = sum_and_step(&mut scratch.re, &mut scratch.im, self.re, self.im);
            row[k + kx] = (sr * sr + si * si) * self.norm;
        }
        scratch.restart();
        // Step once before summing: the first term wanted is kx = -1.
        sum_and_step(&mut scratch.re, &mut scratch.im, self.re, self.back_im);
        for kx in 1..=k {
            let (sr, si) = sum_and_step(&mut scratch.re, &mut scratch.im, self.re, self.back_im);
            row[k - kx] = (sr * sr + si * si) * self.norm;
        }
    }
}

/// Returns the sum of the terms `z_j` and multiplies each by its step `w_j`. Four partial sums
/// let the compiler keep several lanes in flight; their order is fixed.
fn sum_and_step(re: &mut [f64], im: &mut [f64], step_re: &[f64], step_im: &[f64]) -> (f64, f64) {
    const LANES: usize = 4;
    let mut sum_re = [0.0; LANES];
    let mut sum_im = [0.0; LANES];
    let full = re.len() / LANES * LANES;
    let (re_head, re_tail) = re.split_at_mut(full);
    let (im_head, im_tail) = im.split_at_mut(full);
    for (((zr, zi), wr), wi) in re_head
        .chunks_exact_mut(LANES)
        .zip(im_head.chunks_exact_mut(LANES))
        .zip(step_re.chunks_exact(LANES))
        .zip(step_im.chunks_exact(LANES))
    {
        for lane in 0..LANES {
            let (a, b) = (zr[lane], zi[lane]);
            sum_re[lane] += a;
            sum_im[lane] += b;
            zr[lane] = a * wr[lane] - b * wi[lane];
            zi[lane] = a * wi[lane] + b * wr[lane];
        }
    }
    let mut tail_re = 0.0;
    let mut tail_im = 0.0;
    for (((zr, zi), &wr), &wi) in re_tail
        .iter_mut()
        .zip(im_tail.iter_mut())
        .zip(&step_re[full..])
        .zip(&step_im[full..])
    {
        let (a, b) = (*zr, *zi);
        tail_re += a;
        tail_im += b;
        *zr = a * wr - b * wi;
        *zi = a * wi + b * wr;
    }
    (
        (sum_re[0] + sum_re[1]) + (sum_re[2] + sum_re[3]) + tail_re,
        (sum_im[0] + sum_im[1]) + (sum_im[2] + sum_im[3]) + tail_im,
    )
}

/// The full periodogram from its rows `ky >= 0`, using `P(-k) = P(k)`.
fn mirror(half: Vec<f64>, max_frequency: usize, points: usize, passes: usize) -> Periodogram {
    let size = 2 * max_frequency + 1;
    let mut values = vec![0.0; size * size];
    let centre = max_frequency * size;
    // Row 0 as computed on its right half, mirrored exactly onto its left half.
    values[centre..centre + size].copy_from_slice(&half[..size]);
    for kx in 1..=max_frequency {
        values[centre + max_frequency - kx] = values[centre + max_frequency + kx];
    }
    for ky in 1..=max_frequency {
        let row = &half[ky * size..(ky + 1) * size];
        values[(max_frequency + ky) * size..(max_frequency + ky + 1) * size].copy_from_slice(row);
        // Row -ky is row ky reversed (kx -> -kx).
        let mirrored = &mut values[(max_frequency - ky) * size..(max_frequency - ky + 1) * size];
        for (slot, &v) in mirrored.iter_mut().zip(row.iter().rev()) {
            *slot = v;
        }
    }
    Periodogram {
        max_frequency,
        points,
        passes,
        values,
    }
}
