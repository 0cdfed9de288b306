//! Weighted mixtures of densities, including defensive importance sampling (Hesterberg 1995).
//!
//! A mixture `p(x) = sum_i w_i p_i(x)` is sampled by choosing component `i` with probability
//! `w_i` and then sampling `p_i`. Used as the pdf of Jarosz's importance-sampling estimator
//! (A.19), it is the combined density behind multiple importance sampling with the balance
//! heuristic (Veach & Guibas 1995): one-sample MIS with the balance heuristic is exactly
//! importance sampling from the mixture. With a uniform component of weight `alpha` it is
//! Hesterberg's (1995) *defensive* mixture, whose density never falls below `alpha / volume`, so
//! the weights `f/p` stay bounded even where the proposal misses the integrand.

use super::{Pdf, UniformBox, debug_assert_len};
use crate::error::{Error, Result};
use crate::float::ONE_BELOW;

/// Canonical dimensions whose remapped point fits on the stack when sampling.
const STACK_DIMS: usize = 16;

/// The density `sum_i w_i p_i(x)` of components of the same `dims`, with weights normalised
/// to sum to one.
///
/// Sampling uses `u[0]` twice: the interval of cumulative weights it falls in picks the
/// component, and its position within that interval, rescaled to `[0, 1)`, becomes the
/// component's own `u[0]`; the component's other coordinates are `u[1..]`. The mixture
/// therefore has as many canonical dimensions as its largest component. The rescaling costs
/// precision: a component of weight `w` sees its first coordinate on a grid `1/w` times
/// coarser than `u[0]`'s (`2^-53 / w` for the finest samplers, so a weight of `1e-3` loses
/// about 10 of 53 bits). The map is increasing within each component, so stratification of
/// `u[0]` carries into each component's first coordinate, but the subset of a stratified or
/// low-discrepancy point set that lands in one component is not as evenly spread as the whole
/// set. [`invert`](Pdf::invert) is not available (a point may come from any component).
///
/// ```
/// use mcint::pdf::{Linear, Mixture, Pdf, UniformInterval};
/// let p = Mixture::new(
///     vec![Box::new(UniformInterval::new(0.0, 1.0)?), Box::new(Linear::new(0.0, 1.0, 0.0, 1.0)?)],
///     vec![1.0, 3.0], // normalised to 0.25 and 0.75
/// )?;
/// assert_eq!(p.weights(), &[0.25, 0.75]);
/// assert_eq!(p.pdf(&[0.5]), 0.25 * 1.0 + 0.75 * 1.0);
/// let mut x = [0.0];
/// p.sample(&[0.1], &mut x); // u[0] < 0.25: the uniform component, at 0.1 / 0.25
/// assert!((x[0] - 0.4).abs() < 1e-15);
/// # Ok::<(), mcint::Error>(())
/// ```
pub struct Mixture {
    components: Vec<Box<dyn Pdf>>,
    /// Normalised weights, summing to one.
    weights: Vec<f64>,
    /// `upper[i]`: the end of component `i`'s interval of `u[0]`, the cumulative weight through
    /// `i`; the last component with an interval of positive width ends at exactly 1.
    upper: Vec<f64>,
    /// The last component with an interval of positive width.
    last: usize,
    dims: usize,
    canonical_dims: usize,
}

impl Mixture {
    /// The mixture of `components` (at least one, all with the same [`dims`](Pdf::dims)) with
    /// `weights` (one per component, finite and `>= 0`, with a positive sum), which are
    /// normalised to sum to one. Components of weight zero are never sampled.
    ///
    /// ```
    /// use mcint::pdf::{Mixture, UniformBox, UniformInterval};
    /// let unit = || Box::new(UniformInterval::new(0.0, 1.0).unwrap());
    /// assert!(Mixture::new(vec![unit(), unit()], vec![0.0, 0.0]).is_err());
    /// assert!(Mixture::new(vec![unit(), unit()], vec![1.0, -1.0]).is_err());
    /// assert!(Mixture::new(vec![unit()], vec![1.0, 1.0]).is_err());
    /// let square = Box::new(UniformBox::unit(2).unwrap());
    /// assert!(Mixture::new(vec![unit(), square], vec![1.0, 1.0]).is_err()); // dims differ
    /// ```
    pub fn new(components: Vec<Box<dyn Pdf>>, weights: Vec<f64>) -> Result<Self> {
        let Some(first) = components.first() else {
            return Err(Error::invalid("components", "[]", "at least one pdf"));
        };
        if weights.len() != components.len() {
            return Err(Error::DimensionMismatch {
                what: "weights (one per component)",
                expected: components.len(),
                found: weights.len(),
            });
        }
        let dims = first.dims();
        if let Some(other) = components.iter().find(|c| c.dims() != dims) {
            return Err(Error::DimensionMismatch {
                what: "components (each must have the dims of the first)",
                expected: dims,
                found: other.dims(),
            });
        }
        if let Some((i, w)) = weights
            .iter()
            .enumerate()
            .find(|(_, w)| !(w.is_finite() && **w >= 0.0))
        {
            return Err(Error::invalid(
                "weights",
                format!("{w} (component {i})"),
                "finite weights >= 0 with a positive sum",
            ));
        }
        // Dividing by the largest weight first keeps the sum finite for weights near f64::MAX.
        let largest = weights.iter().fold(0.0f64, |m, &w| m.max(w));
        if largest == 0.0 {
            return Err(Error::invalid(
                "weights",
                format!("{weights:?}"),
                "finite weights >= 0 with a positive sum",
            ));
        }
        let total: f64 = weights.iter().map(|w| w / largest).sum();
        let weights: Vec<f64> = weights.iter().map(|w| w / largest / total).collect();
        let (upper, last) = cumulative_intervals(&weights);
        let canonical_dims = components
            .iter()
            .map(|c| c.canonical_dims())
            .max()
            .unwrap_or(0)
            .max(1);
        Ok(Mixture {
            components,
            weights,
            upper,
            last,
            dims,
            canonical_dims,
        })
    }

    /// Hesterberg's (1995) defensive mixture `alpha * uniform(domain) + (1 - alpha) * proposal`,
    /// for `alpha` in `(0, 1]` and a proposal with the domain's dims.
    ///
    /// Its density is at least `alpha / volume` on the domain, so importance sampling an
    /// integrand `f` over the domain has contributions `f/p <= volume * max|f| / alpha` and,
    /// since `integral f^2 / p <= integral f^2 / (alpha / volume)`, a variance of at most
    /// `sigma_uniform^2 / alpha + (1/alpha - 1) F^2`, however badly the proposal fits `f`
    /// (Hesterberg 1995, Technometrics 37(2):185-194). The proposal's support should lie in the
    /// domain, since every sample of the mixture is a point of the integral.
    ///
    /// ```
    /// use mcint::pdf::{Exponential, Mixture, Pdf, UniformBox};
    /// let proposal = Box::new(Exponential::new(30.0, 0.0, 1.0)?);
    /// let p = Mixture::defensive(proposal, UniformBox::unit(1)?, 0.1)?;
    /// assert!(p.pdf(&[0.99]) >= 0.1); // the proposal alone is about 4e-12 there
    /// assert!(Mixture::defensive(Box::new(Exponential::new(1.0, 0.0, 1.0)?), UniformBox::unit(1)?, 0.0).is_err());
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn defensive(proposal: Box<dyn Pdf>, domain: UniformBox, alpha: f64) -> Result<Self> {
        if !(alpha > 0.0 && alpha <= 1.0) {
            return Err(Error::invalid(
                "alpha",
                alpha,
                "a uniform share in (0, 1] (0 would not be defensive)",
            ));
        }
        if proposal.dims() != domain.dims() {
            return Err(Error::DimensionMismatch {
                what: "proposal (it must have the domain's dims)",
                expected: domain.dims(),
                found: proposal.dims(),
            });
        }
        Mixture::new(vec![Box::new(domain), proposal], vec![alpha, 1.0 - alpha])
    }

    /// The normalised weights, one per component, summing to one.
    ///
    /// ```
    /// use mcint::pdf::{Mixture, UniformInterval};
    /// let unit = || Box::new(UniformInterval::new(0.0, 1.0).unwrap());
    /// assert_eq!(Mixture::new(vec![unit(), unit()], vec![2.0, 6.0]).unwrap().weights(), &[0.25, 0.75]);
    /// ```
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// The components, in the order given.
    ///
    /// ```
    /// use mcint::pdf::{Mixture, Pdf, UniformInterval};
    /// let p = Mixture::new(vec![Box::new(UniformInterval::new(0.0, 2.0).unwrap())], vec![1.0]).unwrap();
    /// assert_eq!(p.components()[0].pdf(&[1.0]), 0.5);
    /// ```
    pub fn components(&self) -> &[Box<dyn Pdf>] {
        &self.components
    }

    /// Samples like [`sample`](Pdf::sample) and returns the index of the component that
    /// produced `x` (which one-sample MIS needs).
    ///
    /// # Panics
    ///
    /// As [`Pdf::sample`]: `u.len()` must equal [`canonical_dims`](Pdf::canonical_dims) and
    /// `x.len()` must equal [`dims`](Pdf::dims) (checked with debug assertions; in release a
    /// slice that is too short panics, one that is too long gives unspecified results).
    ///
    /// ```
    /// use mcint::pdf::{Mixture, UniformInterval};
    /// let p = Mixture::new(
    ///     vec![Box::new(UniformInterval::new(0.0, 1.0).unwrap()), Box::new(UniformInterval::new(5.0, 6.0).unwrap())],
    ///     vec![1.0, 1.0],
    /// )
    /// .unwrap();
    /// let mut x = [0.0];
    /// assert_eq!(p.sample_with_component(&[0.75], &mut x), 1);
    /// assert_eq!(x, [5.5]);
    /// ```
    pub fn sample_with_component(&self, u: &[f64], x: &mut [f64]) -> usize {
        debug_assert_len!(self, sample_with_component, u, canonical_dims);
        debug_assert_len!(self, sample_with_component, x, dims);
        // Slicing to the full lengths makes a too-short slice panic in release builds too,
        // whichever component is chosen (a component may take fewer coordinates of u).
        let u = &u[..self.canonical_dims];
        let x = &mut x[..self.dims];
        let (index, first) = self.select(u[0]);
        let component = &self.components[index];
        let dims = component.canonical_dims();
        if dims == 0 {
            component.sample(&[], x);
        } else if dims <= STACK_DIMS {
            let mut remapped = [0.0; STACK_DIMS];
            remapped[0] = first;
            remapped[1..dims].copy_from_slice(&u[1..dims]);
            component.sample(&remapped[..dims], x);
        } else {
            let mut remapped = u[..dims].to_vec();
            remapped[0] = first;
            component.sample(&remapped, x);
        }
        index
    }

    /// The component whose interval of cumulative weight holds `u0`, and `u0`'s position in
    /// that interval rescaled to `[0, 1)`.
    fn select(&self, u0: f64) -> (usize, f64) {
        // The first interval ending above u0; empty intervals (weight zero) never qualify.
        let index = self.upper.partition_point(|&end| end <= u0).min(self.last);
        let start = if index == 0 {
            0.0
        } else {
            self.upper[index - 1]
        };
        let t = (u0 - start) / (self.upper[index] - start);
        (index, t.clamp(0.0, ONE_BELOW))
    }
}

/// Interval ends `upper[i] = w_0 + ... + w_i` (non-decreasing, at most one) and the last
/// component with an interval of positive width, whose end is set to exactly one so that every
/// `u0` in `[0, 1)` selects a component of positive weight.
fn cumulative_intervals(weights: &[f64]) -> (Vec<f64>, usize) {
    let mut upper = Vec::with_capacity(weights.len());
    let mut sum = 0.0f64;
    for &w in weights {
        sum = (sum + w).min(1.0);
        upper.push(sum);
    }
    let mut last = 0;
    let mut start = 0.0;
    for (i, &end) in upper.iter().enumerate() {
        if end > start {
            last = i;
        }
        start = end;
    }
    for end in &mut upper[last..] {
        *end = 1.0;
    }
    (upper, last)
}

impl std::fmt::Debug for Mixture {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Mixture")
            .field("weights", &self.weights)
            .field("dims", &self.dims)
            .field("canonical_dims", &self.canonical_dims)
            .finish()
    }
}

impl Pdf for Mixture {
    fn canonical_dims(&self) -> usize {
        self.canonical_dims
    }

    fn dims(&self) -> usize {
        self.dims
    }

    fn sample(&self, u: &[f64], x: &mut [f64]) {
        debug_assert_len!(self, sample, u, canonical_dims);
        debug_assert_len!(self, sample, x, dims);
        self.sample_with_component(u, x);
    }

    fn pdf(&self, x: &[f64]) -> f64 {
        debug_assert_len!(self, pdf, x, dims);
        // Sliced so a too-short x panics here, not only if some component indexes it.
        let x = &x[..self.dims];
        // Components of weight zero are skipped, so their value (even NaN) cannot leak in.
        self.components
            .iter()
            .zip(&self.weights)
            .filter(|(_, w)| **w > 0.0)
            .map(|(c, w)| w * c.pdf(x))
            .sum()
    }
}
