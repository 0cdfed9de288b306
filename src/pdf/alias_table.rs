//! Discrete sampling in constant time by the alias method.
//!
//! Walker's alias method (A. J. Walker, "An efficient method for generating discrete random
//! variables with general distributions", *ACM TOMS* 3(3), 1977) splits `n` outcomes'
//! probabilities into `n` equal bins, each holding at most two outcomes: the bin's own and an
//! "alias". A canonical `u` picks a bin from its integer part `floor(u n)` and one of the two
//! outcomes from the fraction. The table is built in `O(n)` with Vose's two-worklist
//! construction (M. D. Vose, "A linear algorithm for generating random numbers with a given
//! distribution", *IEEE TSE* 17(9), 1991), as in pbrt-v4's `AliasTable` (Pharr, Jakob &
//! Humphreys, *Physically Based Rendering*, 4th ed., sec. A.1); the code is our own. This is the
//! discrete counterpart of Jarosz's A.19: a sample `i` drawn with probability `p_i` has the
//! estimator `f(i) / p_i` for a sum `sum_i f(i)`.

use super::piecewise_constant::{check_weights, into_canonical};
use super::{Pdf, debug_assert_len};
use crate::error::Result;
use crate::float::ONE_BELOW;

/// One of the `n` equal bins: the bin's own outcome below `threshold`, `alias` above it.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Bin {
    /// Share of the bin that belongs to its own outcome, in `[0, 1]`.
    threshold: f64,
    alias: usize,
}

/// Samples index `i` with probability `w_i / sum(w)` in `O(1)` by the alias method.
///
/// [`sample`](Self::sample) also returns a remapped canonical coordinate: the fraction of the
/// way `u` was through the part of its bin that chose the index, which is uniform on `[0, 1)`
/// and independent of the index when `u` is uniform, so one `u` can choose a discrete outcome
/// and then drive a further warp (with `log2(n)` fewer bits of resolution).
///
/// Through the [`Pdf`] trait the table is a one-dimensional distribution on the integers
/// `0, ..., n-1`: `sample` writes `x = index as f64`, and `pdf(x)` is the probability of that
/// index (a density with respect to counting measure, so the estimator `f(x) / pdf(x)`
/// estimates the sum `sum_i f(i)`); `pdf` is zero at non-integers and outside the table. The
/// warp is not monotone (a bin's alias can be any index), so there is no inverse and
/// [`invert`](Pdf::invert) keeps the trait's default error, and stratified `u` do not give
/// stratified indices, only balanced bins (each of the `n` bins gets its share of the `u`).
///
/// Weights of zero are never sampled. The sampled frequencies equal the probabilities up to
/// the rounding of the construction, about `n` times `1e-16` absolutely.
///
/// ```
/// use mcint::pdf::AliasTable;
/// let t = AliasTable::new(&[1.0, 0.0, 3.0]).unwrap();
/// assert_eq!(t.len(), 3);
/// assert_eq!(t.probability(2), 0.75);
/// let (i, v) = t.sample(0.4);
/// assert!(i == 0 || i == 2);
/// assert!((0.0..1.0).contains(&v));
/// // Evenly spaced u give the probabilities' counts.
/// let mut counts = [0; 3];
/// for k in 0..1200 {
///     counts[t.sample((k as f64 + 0.5) / 1200.0).0] += 1;
/// }
/// assert_eq!(counts, [300, 0, 900]);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct AliasTable {
    probabilities: Vec<f64>,
    bins: Vec<Bin>,
}

impl AliasTable {
    /// The table for `weights`: a non-empty table of finite weights `>= 0` with a positive,
    /// finite sum (the same rules as [`PiecewiseConstant1d`](super::PiecewiseConstant1d)).
    /// Errors name `weights`.
    ///
    /// ```
    /// use mcint::pdf::AliasTable;
    /// assert!(AliasTable::new(&[]).is_err());
    /// assert!(AliasTable::new(&[0.0, 0.0]).is_err());
    /// assert!(AliasTable::new(&[1.0, f64::NAN]).is_err());
    /// assert!(AliasTable::new(&[f64::MAX, f64::MAX]).is_err()); // the sum overflows
    /// ```
    pub fn new(weights: &[f64]) -> Result<Self> {
        let sum = check_weights("weights", weights)?;
        let n = weights.len();
        let probabilities: Vec<f64> = weights.iter().map(|w| w / sum).collect();
        // Each outcome's mass in units of one bin: they add up to n.
        let mut mass: Vec<f64> = probabilities.iter().map(|p| p * n as f64).collect();
        let mut bins = vec![
            Bin {
                threshold: 1.0,
                alias: 0,
            };
            n
        ];
        let (mut light, mut heavy): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| mass[i] < 1.0);
        // Fill each light outcome's bin with mass from a heavy one, which may then turn light.
        while let (Some(&l), Some(&h)) = (light.last(), heavy.last()) {
            light.pop();
            bins[l] = Bin {
                threshold: mass[l],
                alias: h,
            };
            // (mass_h + mass_l) - 1 rather than mass_h - (1 - mass_l): Vose's advice, it
            // loses less to rounding; it is never negative since mass_h >= 1.
            mass[h] = (mass[h] + mass[l]) - 1.0;
            if mass[h] < 1.0 {
                heavy.pop();
                light.push(h);
            }
        }
        // What is left is full bins: exactly so in exact arithmetic, to rounding here.
        for &i in heavy.iter().chain(&light) {
            bins[i] = Bin {
                threshold: 1.0,
                alias: i,
            };
        }
        // Rounding could in principle leave an outcome of zero weight among them (it would
        // need an error of a whole bin); make sure such a bin never returns it.
        let heaviest = (0..n)
            .max_by(|&i, &j| probabilities[i].total_cmp(&probabilities[j]))
            .unwrap_or(0);
        for (i, bin) in bins.iter_mut().enumerate() {
            if weights[i] == 0.0 && bin.threshold > 0.0 {
                *bin = Bin {
                    threshold: 0.0,
                    alias: heaviest,
                };
            }
        }
        Ok(AliasTable {
            probabilities,
            bins,
        })
    }

    /// Number of outcomes `n`.
    ///
    /// ```
    /// assert_eq!(mcint::pdf::AliasTable::new(&[1.0; 5]).unwrap().len(), 5);
    /// ```
    pub fn len(&self) -> usize {
        self.bins.len()
    }

    /// Always false: the constructor rejects empty tables.
    ///
    /// ```
    /// assert!(!mcint::pdf::AliasTable::new(&[1.0]).unwrap().is_empty());
    /// ```
    pub fn is_empty(&self) -> bool {
        self.bins.is_empty()
    }

    /// Probability of index `i`, `w_i / sum(w)` (zero beyond the table).
    ///
    /// ```
    /// let t = mcint::pdf::AliasTable::new(&[1.0, 3.0]).unwrap();
    /// assert_eq!((t.probability(0), t.probability(1), t.probability(2)), (0.25, 0.75, 0.0));
    /// ```
    pub fn probability(&self, i: usize) -> f64 {
        self.probabilities.get(i).copied().unwrap_or(0.0)
    }

    /// Probabilities of all indices.
    ///
    /// ```
    /// let t = mcint::pdf::AliasTable::new(&[2.0, 2.0]).unwrap();
    /// assert_eq!(t.probabilities(), &[0.5, 0.5]);
    /// ```
    pub fn probabilities(&self) -> &[f64] {
        &self.probabilities
    }

    /// Maps a canonical `u` in `[0, 1)` to an index and a remapped canonical coordinate in
    /// `[0, 1)`: bin `floor(u n)`, whose own index is chosen when the fraction `f` of `u`
    /// through the bin is below the bin's threshold `q` (remapped `f / q`), and whose alias
    /// otherwise (remapped `(f - q) / (1 - q)`). `u` outside `[0, 1)` is clamped into it.
    ///
    /// ```
    /// let t = mcint::pdf::AliasTable::new(&[1.0, 1.0]).unwrap();
    /// assert_eq!(t.sample(0.25), (0, 0.5));
    /// assert_eq!(t.sample(0.75), (1, 0.5));
    /// ```
    pub fn sample(&self, u: f64) -> (usize, f64) {
        let n = self.bins.len();
        let scaled = into_canonical(u) * n as f64;
        let bin = (scaled as usize).min(n - 1);
        let fraction = scaled - bin as f64;
        let Bin { threshold, alias } = self.bins[bin];
        if fraction < threshold {
            (bin, (fraction / threshold).min(ONE_BELOW))
        } else {
            let rest = ((fraction - threshold) / (1.0 - threshold)).min(ONE_BELOW);
            (alias, rest)
        }
    }
}

impl Pdf for AliasTable {
    fn canonical_dims(&self) -> usize {
        1
    }

    fn dims(&self) -> usize {
        1
    }

    fn sample(&self, u: &[f64], x: &mut [f64]) {
        debug_assert_len!(self, sample, u, canonical_dims);
        debug_assert_len!(self, sample, x, dims);
        x[0] = AliasTable::sample(self, u[0]).0 as f64;
    }

    /// The probability of index `x[0]` (counting measure); zero unless `x[0]` is one of
    /// `0, ..., n-1`.
    fn pdf(&self, x: &[f64]) -> f64 {
        debug_assert_len!(self, pdf, x, dims);
        let x = x[0];
        if x >= 0.0 && x < self.bins.len() as f64 && x.fract() == 0.0 {
            self.probabilities[x as usize]
        } else {
            0.0
        }
    }
}
