//! Veach's one-sample MIS estimator: each contribution picks one technique at random.
//!
//! Jarosz's multiple importance sampling (after A.25), in the form Veach calls the one-sample
//! model (Veach & Guibas 1995; Veach 1997, chapter 9): technique `i` is chosen with probability
//! `c_i`, a sample `X` is drawn from it, and the contribution is
//!
//! ```text
//! F = w_i(X) f(X) / (c_i p_i(X))
//! ```
//!
//! with weights computed from `q_j = c_j p_j(X)`. It is unbiased whenever the weights sum to one
//! wherever `f != 0`. With the balance heuristic it is exactly Jarosz's A.19 with the mixture
//! density `sum_j c_j p_j` (see [`Mixture`]), and in this model no other weighting has a lower
//! variance: `E[F^2] = sum_i integral w_i^2 f^2 / q_i`, and minimising `sum_i w_i^2 / q_i`
//! subject to `sum_i w_i = 1` gives `w_i = q_i / sum_j q_j`.

use super::mis_weighting::{weighted_term, with_densities};
use super::{Estimator, MisHeuristic, MisWeighting};
use crate::error::{Error, Result};
use crate::pdf::{Mixture, Pdf};

/// How far the selection probabilities may sum from one.
const PROBABILITY_SUM_TOLERANCE: f64 = 1e-12;

/// The one-sample MIS estimator: `w_i(X) f(X) / (c_i p_i(X))` with technique `i` chosen with
/// probability `c_i`.
///
/// The technique is chosen with `u[0]`, whose position within the chosen technique's interval
/// of cumulative probability, rescaled to `[0, 1)`, becomes the technique's own `u[0]` (as in
/// [`Mixture`], including its precision cost: `log2(1/c_i)` bits of the first coordinate), so
/// [`canonical_dims`](Estimator::canonical_dims) is the largest technique's. A technique of
/// probability zero is never chosen. Where `f = 0` the contribution is zero; a pdf that is zero
/// or NaN at its own sample where `f != 0`, NaN weights, and weights of a user
/// [`MisWeighting`] that do not sum to one within `1e-9` make it NaN, which the
/// [`Integrator`](crate::Integrator) reports as
/// [`Error::NonFiniteContribution`](crate::Error::NonFiniteContribution) with the count and the
/// first offending canonical point.
///
/// ```
/// use mcint::estimator::{Estimator, MisHeuristic, OneSampleMis};
/// use mcint::pdf::{Linear, UniformInterval};
/// use mcint::Integrator;
/// let mis = OneSampleMis::new(
///     |x: &[f64]| x[0] * x[0] + 0.1,
///     vec![Box::new(UniformInterval::new(0.0, 1.0)?), Box::new(Linear::new(0.0, 1.0, 0.0, 1.0)?)],
///     vec![0.25, 0.75],
///     MisHeuristic::power(2.0)?,
/// )?;
/// assert_eq!(mis.canonical_dims(), 1);
/// let e = Integrator::new(mis).samples(20_000).seed(2).run()?;
/// assert!((e.mean - (1.0 / 3.0 + 0.1)).abs() < 5.0 * e.std_error.unwrap());
/// # Ok::<(), mcint::Error>(())
/// ```
pub struct OneSampleMis<F, W = MisHeuristic> {
    f: F,
    /// The techniques with their selection probabilities as weights.
    techniques: Mixture,
    weighting: W,
}

impl<F: Fn(&[f64]) -> f64 + Send + Sync, W: MisWeighting> OneSampleMis<F, W> {
    /// Combines `techniques` (at least one, all with the same `dims`), chosen with
    /// `probabilities` `c_i` (one per technique, finite, `>= 0`, summing to one within
    /// `1e-12`), with `weighting` (a [`MisHeuristic`] or any [`MisWeighting`]).
    ///
    /// Probabilities that do not sum to one are an error, never silently renormalised: they
    /// are part of the estimator (`c_i` divides each contribution), so a wrong sum is a
    /// mistake to fix. (Within the tolerance the remainder is rounding, which is divided out
    /// so that the selection probabilities are exactly the ones in the denominators.)
    ///
    /// ```
    /// use mcint::estimator::{MisHeuristic, OneSampleMis};
    /// use mcint::pdf::{Pdf, UniformInterval};
    /// let unit = || -> Box<dyn Pdf> { Box::new(UniformInterval::new(0.0, 1.0).unwrap()) };
    /// let err = OneSampleMis::new(|x: &[f64]| x[0], vec![unit(), unit()], vec![0.5, 0.6], MisHeuristic::Balance)
    ///     .err()
    ///     .unwrap();
    /// assert!(err.to_string().contains("probabilities") && err.to_string().contains("sum to 1.1"));
    /// ```
    pub fn new(
        f: F,
        techniques: Vec<Box<dyn Pdf>>,
        probabilities: Vec<f64>,
        weighting: W,
    ) -> Result<Self> {
        weighting.check()?;
        if techniques.is_empty() {
            return Err(Error::invalid("techniques", "[]", "at least one pdf"));
        }
        if probabilities.len() != techniques.len() {
            return Err(Error::DimensionMismatch {
                what: "probabilities (one per technique)",
                expected: techniques.len(),
                found: probabilities.len(),
            });
        }
        let dims = techniques[0].dims();
        if let Some(other) = techniques.iter().find(|p| p.dims() != dims) {
            return Err(Error::DimensionMismatch {
                what: "techniques (each pdf must have the dims of the first)",
                expected: dims,
                found: other.dims(),
            });
        }
        if let Some((i, c)) = probabilities
            .iter()
            .enumerate()
            .find(|(_, c)| !(c.is_finite() && **c >= 0.0))
        {
            return Err(Error::invalid(
                "probabilities",
                format!("{c} (technique {i})"),
                "finite probabilities >= 0 that sum to one",
            ));
        }
        let sum: f64 = probabilities.iter().sum();
        let sums_to_one = (sum - 1.0).abs() <= PROBABILITY_SUM_TOLERANCE;
        if !sums_to_one {
            return Err(Error::invalid(
                "probabilities",
                format!("{probabilities:?}, which sum to {sum}"),
                format!(
                    "selection probabilities that sum to one within {PROBABILITY_SUM_TOLERANCE:e} \
                     (they are not renormalised)"
                ),
            ));
        }
        let techniques = Mixture::new(techniques, probabilities)?;
        Ok(OneSampleMis {
            f,
            techniques,
            weighting,
        })
    }

    /// The selection probabilities `c_i`.
    ///
    /// ```
    /// use mcint::estimator::{MisHeuristic, OneSampleMis};
    /// use mcint::pdf::UniformInterval;
    /// let unit = || Box::new(UniformInterval::new(0.0, 1.0).unwrap()) as Box<dyn mcint::Pdf>;
    /// let mis = OneSampleMis::new(|x: &[f64]| x[0], vec![unit(), unit()], vec![0.5, 0.5], MisHeuristic::Balance).unwrap();
    /// assert_eq!(mis.probabilities(), &[0.5, 0.5]);
    /// ```
    pub fn probabilities(&self) -> &[f64] {
        self.techniques.weights()
    }
}

impl<F, W> std::fmt::Debug for OneSampleMis<F, W> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("OneSampleMis")
            .field("probabilities", &self.techniques.weights())
            .field("dims", &self.techniques.dims())
            .finish_non_exhaustive()
    }
}

impl<F: Fn(&[f64]) -> f64 + Send + Sync, W: MisWeighting> Estimator for OneSampleMis<F, W> {
    fn canonical_dims(&self) -> usize {
        self.techniques.canonical_dims()
    }

    fn domain_dims(&self) -> usize {
        self.techniques.dims()
    }

    fn contribution(&self, u: &[f64], x: &mut [f64]) -> f64 {
        let chosen = self.techniques.sample_with_component(u, x);
        let value = (self.f)(x);
        if value == 0.0 {
            // Zero integrand contributes zero whatever the pdfs say (no 0/0).
            return 0.0;
        }
        let pdfs = self.techniques.components();
        let probabilities = self.techniques.weights();
        with_densities(pdfs.len(), |densities| {
            for ((q, pdf), &c) in densities.iter_mut().zip(pdfs).zip(probabilities) {
                // A technique that is never chosen has q = 0 whatever its pdf says.
                *q = if c > 0.0 { c * pdf.pdf(x) } else { 0.0 };
            }
            weighted_term(&self.weighting, chosen, x, densities, value)
        })
    }
}
