//! Veach's multi-sample MIS estimator: `n_i` samples from each of several techniques per
//! contribution, combined with weights that sum to one.
//!
//! Jarosz's section on multiple importance sampling (after A.25) proposes drawing samples
//! from several pdfs, for example one proportional to `g` and one to `h` when `f = g h`, and
//! combining them (Veach & Guibas 1995; Veach 1997, chapter 9). With `n_i` samples `X_ij` of
//! technique `i` the multi-sample estimator is
//!
//! ```text
//! F = sum_i (1/n_i) sum_j w_i(X_ij) f(X_ij) / p_i(X_ij)
//! ```
//!
//! (Veach 1997, chapter 9: the multi-sample model), unbiased whenever the weights sum to one
//! wherever `f != 0`. Each term is Jarosz's `f/pdf` (A.19) scaled by a weight, so a point is
//! counted by whichever techniques are good at it instead of by all of them.

use super::mis_weighting::{weighted_term, with_densities};
use super::{Estimator, MisHeuristic, MisWeighting};
use crate::error::{Error, Result};
use crate::pdf::Pdf;

/// One sample technique: a pdf and its sample count `n_i`.
struct Technique {
    pdf: Box<dyn Pdf>,
    count: usize,
}

/// The multi-sample MIS estimator: one contribution is one whole group of `sum_i n_i` samples,
/// `sum_i sum_j w_i(X_ij) f(X_ij) / (n_i p_i(X_ij))`.
///
/// The canonical point of a contribution is the concatenation of `n_0` canonical points of
/// technique 0, then `n_1` of technique 1, and so on, so
/// [`canonical_dims`](Estimator::canonical_dims) is `sum_i n_i * canonical_dims_i`. Samples where
/// `f = 0` contribute zero (no pdf is evaluated there). A technique whose pdf is zero or NaN at
/// one of its own samples where `f != 0`, a weight that is NaN, and weights of a user
/// [`MisWeighting`] that do not sum to one within `1e-9` all make the contribution NaN, which
/// the [`Integrator`](crate::Integrator) reports as
/// [`Error::NonFiniteContribution`](crate::Error::NonFiniteContribution) with the count of
/// affected contributions and the first offending canonical point.
///
/// ```
/// use mcint::estimator::{Estimator, MisHeuristic, MultiSampleMis};
/// use mcint::pdf::{Linear, UniformInterval};
/// use mcint::Integrator;
/// // The integral of x^2 + 0.1 over [0, 1) is 1/3 + 0.1.
/// let mis = MultiSampleMis::new(
///     |x: &[f64]| x[0] * x[0] + 0.1,
///     vec![
///         (Box::new(UniformInterval::new(0.0, 1.0)?), 1),
///         (Box::new(Linear::new(0.0, 1.0, 0.0, 1.0)?), 2),
///     ],
///     MisHeuristic::Balance,
/// )?;
/// assert_eq!(mis.canonical_dims(), 3);
/// let e = Integrator::new(mis).samples(20_000).seed(1).run()?;
/// assert!((e.mean - (1.0 / 3.0 + 0.1)).abs() < 5.0 * e.std_error.unwrap());
/// # Ok::<(), mcint::Error>(())
/// ```
pub struct MultiSampleMis<F, W = MisHeuristic> {
    f: F,
    techniques: Vec<Technique>,
    weighting: W,
    dims: usize,
    canonical_dims: usize,
}

impl<F: Fn(&[f64]) -> f64 + Send + Sync, W: MisWeighting> MultiSampleMis<F, W> {
    /// Combines `techniques`, each a pdf and its sample count `n_i >= 1`, with `weighting` (a
    /// [`MisHeuristic`] or any [`MisWeighting`]).
    ///
    /// Errors name the field: `techniques` (none given, or pdfs with different `dims`),
    /// `n_i` (a count of zero, or counts whose canonical dimension overflows), and the
    /// weighting's own parameters (`beta`, `alpha`).
    ///
    /// ```
    /// use mcint::estimator::{MisHeuristic, MultiSampleMis};
    /// use mcint::pdf::{Pdf, UniformBox, UniformInterval};
    /// let f = |x: &[f64]| x[0];
    /// let unit = || -> Box<dyn Pdf> { Box::new(UniformInterval::new(0.0, 1.0).unwrap()) };
    /// let zero = MultiSampleMis::new(f, vec![(unit(), 0)], MisHeuristic::Balance);
    /// assert!(zero.err().unwrap().to_string().contains("n_i"));
    /// let mixed = MultiSampleMis::new(f, vec![(unit(), 1), (Box::new(UniformBox::unit(2).unwrap()), 1)], MisHeuristic::Balance);
    /// assert!(mixed.is_err());
    /// assert!(MultiSampleMis::new(f, vec![(unit(), 1)], MisHeuristic::Power { beta: f64::NAN }).is_err());
    /// ```
    pub fn new(f: F, techniques: Vec<(Box<dyn Pdf>, usize)>, weighting: W) -> Result<Self> {
        weighting.check()?;
        let Some((first, _)) = techniques.first() else {
            return Err(Error::invalid(
                "techniques",
                "[]",
                "at least one (pdf, n_i) technique",
            ));
        };
        let dims = first.dims();
        if let Some((other, _)) = techniques.iter().find(|(p, _)| p.dims() != dims) {
            return Err(Error::DimensionMismatch {
                what: "techniques (each pdf must have the dims of the first)",
                expected: dims,
                found: other.dims(),
            });
        }
        let mut canonical_dims = 0usize;
        // The total count too (`samples_per_contribution`): a pdf that consumes no canonical
        // coordinates leaves the dimension unchanged however large its count.
        let mut total_count = 0usize;
        for (i, (pdf, count)) in techniques.iter().enumerate() {
            if *count == 0 {
                return Err(Error::invalid(
                    "n_i",
                    format!("0 (technique {i})"),
                    "at least one sample per technique",
                ));
            }
            let overflow = || {
                Error::invalid(
                    "n_i",
                    format!("{count} (technique {i})"),
                    "counts whose total and total canonical dimension fit in usize",
                )
            };
            canonical_dims = count
                .checked_mul(pdf.canonical_dims())
                .and_then(|d| d.checked_add(canonical_dims))
                .ok_or_else(overflow)?;
            total_count = total_count.checked_add(*count).ok_or_else(overflow)?;
        }
        let techniques = techniques
            .into_iter()
            .map(|(pdf, count)| Technique { pdf, count })
            .collect();
        Ok(MultiSampleMis {
            f,
            techniques,
            weighting,
            dims,
            canonical_dims,
        })
    }

    /// The number of samples `sum_i n_i` behind one contribution (for comparing variances per
    /// sample with single-technique estimators).
    ///
    /// ```
    /// use mcint::estimator::{MisHeuristic, MultiSampleMis};
    /// use mcint::pdf::UniformInterval;
    /// let unit = || Box::new(UniformInterval::new(0.0, 1.0).unwrap());
    /// let mis = MultiSampleMis::new(|x: &[f64]| x[0], vec![(unit(), 2), (unit(), 3)], MisHeuristic::Balance).unwrap();
    /// assert_eq!(mis.samples_per_contribution(), 5);
    /// ```
    pub fn samples_per_contribution(&self) -> usize {
        self.techniques.iter().map(|t| t.count).sum()
    }
}

impl<F, W> std::fmt::Debug for MultiSampleMis<F, W> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let counts: Vec<usize> = self.techniques.iter().map(|t| t.count).collect();
        f.debug_struct("MultiSampleMis")
            .field("sample_counts", &counts)
            .field("dims", &self.dims)
            .field("canonical_dims", &self.canonical_dims)
            .finish_non_exhaustive()
    }
}

impl<F: Fn(&[f64]) -> f64 + Send + Sync, W: MisWeighting> Estimator for MultiSampleMis<F, W> {
    fn canonical_dims(&self) -> usize {
        self.canonical_dims
    }

    fn evaluations_per_contribution(&self) -> u64 {
        self.samples_per_contribution() as u64
    }

    fn domain_dims(&self) -> usize {
        self.dims
    }

    fn contribution(&self, u: &[f64], x: &mut [f64]) -> f64 {
        with_densities(self.techniques.len(), |densities| {
            let mut total = 0.0;
            let mut offset = 0;
            for (i, technique) in self.techniques.iter().enumerate() {
                let width = technique.pdf.canonical_dims();
                for _ in 0..technique.count {
                    technique.pdf.sample(&u[offset..offset + width], x);
                    offset += width;
                    let value = (self.f)(x);
                    if value == 0.0 {
                        // Zero integrand contributes zero whatever the pdfs say (no 0/0).
                        continue;
                    }
                    for (q, t) in densities.iter_mut().zip(&self.techniques) {
                        *q = t.count as f64 * t.pdf.pdf(x);
                    }
                    total += weighted_term(&self.weighting, i, x, densities, value);
                }
            }
            total
        })
    }
}
