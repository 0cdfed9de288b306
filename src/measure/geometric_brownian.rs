//! [`GeometricBrownianMotion`]: asset prices `S(t) = S0 exp((r - sigma^2/2) t + sigma W(t))`.

use super::Measure;
use super::brownian::{BrownianMotion, Construction};
use super::normal_map::largest_normal;
use crate::error::{Error, Result};
use crate::special::normal_cdf;

/// The largest log-price a path may reach: below `ln(f64::MAX / 2) = 709.08`, so that prices
/// stay finite with room for rounding.
pub(super) const LARGEST_LOG_PRICE: f64 = 709.0;

/// The law of `(S(t_1), ..., S(t_n))` for geometric Brownian motion
/// `S(t) = S0 exp((r - sigma^2 / 2) t + sigma W(t))`, the Black-Scholes model of an asset under
/// the risk-neutral measure with rate `r`: one canonical coordinate per date, the path built
/// by any [`Construction`].
///
/// ```
/// use mcint::{Integrator, measure::{Construction, GeometricBrownianMotion}};
/// // Under the risk-neutral measure the discounted price is a martingale: E[S(T)] = S0 e^{rT}.
/// let gbm = GeometricBrownianMotion::new(100.0, 0.05, 0.2, vec![0.5, 1.0], Construction::Bridge).unwrap();
/// let e = Integrator::expectation(|s: &[f64]| s[1], gbm).samples(200_000).run().unwrap();
/// assert!((e.mean - 100.0 * 0.05f64.exp()).abs() < 5.0 * e.std_error.unwrap());
/// ```
#[derive(Debug, Clone)]
pub struct GeometricBrownianMotion {
    s0: f64,
    rate: f64,
    sigma: f64,
    path: BrownianMotion,
}

impl GeometricBrownianMotion {
    /// Prices from `s0` (finite, `> 0`) with rate `rate` (finite) and volatility `sigma`
    /// (finite, `>= 0`, with a finite square) at `times` (strictly increasing, above 0).
    /// Every price must stay finite: `ln s0 + (rate - sigma^2 / 2) t + sigma W(t)`, with the
    /// normals behind `W` as large as the canonical points allow (about 8.3), must stay below
    /// 709 (`ln(f64::MAX / 2)` is 709.08).
    ///
    /// ```
    /// use mcint::measure::{Construction, GeometricBrownianMotion};
    /// assert!(GeometricBrownianMotion::new(0.0, 0.05, 0.2, vec![1.0], Construction::Pca).is_err());
    /// assert!(GeometricBrownianMotion::new(100.0, f64::NAN, 0.2, vec![1.0], Construction::Pca).is_err());
    /// // e^1000 overflows.
    /// let err = GeometricBrownianMotion::new(100.0, 1000.0, 0.2, vec![1.0], Construction::Standard)
    ///     .unwrap_err();
    /// assert!(err.to_string().contains("709"), "{err}");
    /// ```
    pub fn new(
        s0: f64,
        rate: f64,
        sigma: f64,
        times: Vec<f64>,
        construction: Construction,
    ) -> Result<Self> {
        if !(s0.is_finite() && s0 > 0.0) {
            return Err(Error::invalid("s0", s0, "a finite price > 0"));
        }
        if !(sigma.is_finite() && sigma >= 0.0) {
            return Err(Error::invalid("sigma", sigma, "a finite volatility >= 0"));
        }
        if !rate.is_finite() {
            return Err(Error::invalid("rate", rate, "a finite rate"));
        }
        let drift = rate - 0.5 * sigma * sigma;
        if !drift.is_finite() {
            return Err(Error::invalid(
                "sigma",
                format!("{sigma:?}"),
                "a volatility whose square is finite (below 1.3e154)",
            ));
        }
        let path = BrownianMotion::build(times, drift, sigma, construction)?;
        // The largest log-price any canonical point gives, NaN if drift t and sigma W
        // overflow with opposite signs.
        let top = path
            .times()
            .iter()
            .zip(path.spread())
            .map(|(&t, spread)| s0.ln() + drift * t + sigma * spread)
            .fold(f64::NEG_INFINITY, |most, r| {
                if r > most || r.is_nan() { r } else { most }
            });
        if top.is_nan() || top > LARGEST_LOG_PRICE {
            let times = path.times();
            return Err(Error::invalid(
                "s0, rate, sigma and times",
                format!(
                    "s0 {s0:?}, rate {rate:?}, sigma {sigma:?}, last date {:?}",
                    times[times.len() - 1]
                ),
                format!(
                    "prices below f64::MAX / 2: ln s0 + (rate - sigma^2 / 2) t + sigma W(t), \
                     with normals up to {:.2}, at most {LARGEST_LOG_PRICE} (it reaches {top:.4e})",
                    largest_normal()
                ),
            ));
        }
        Ok(GeometricBrownianMotion {
            s0,
            rate,
            sigma,
            path,
        })
    }

    /// The dates.
    ///
    /// ```
    /// use mcint::measure::{Construction, GeometricBrownianMotion};
    /// let g = GeometricBrownianMotion::new(1.0, 0.0, 0.1, vec![0.25, 1.0], Construction::Standard).unwrap();
    /// assert_eq!(g.times(), &[0.25, 1.0]);
    /// ```
    pub fn times(&self) -> &[f64] {
        self.path.times()
    }

    /// The exact price `E[e^{-r T} max(G - K, 0)]` of a call on the geometric average
    /// `G = (S(t_1) ... S(t_n))^(1/n)` of the prices at the dates, paid at the last date `T`,
    /// for a strike `K` (finite, `> 0`): `ln G` is normal with mean
    /// `ln S0 + (r - sigma^2/2) mean(t)` and variance `sigma^2 sum_ij min(t_i, t_j) / n^2`, which
    /// gives a Black-Scholes formula (Kemna & Vorst 1990). It is the classic control variate of
    /// the arithmetic-average Asian call (see
    /// [`Integrator::expectation_with_controls`](crate::Integrator::expectation_with_controls)).
    ///
    /// ```
    /// use mcint::measure::{Construction, GeometricBrownianMotion};
    /// // One date: the European call of Black-Scholes.
    /// let one = GeometricBrownianMotion::new(100.0, 0.05, 0.2, vec![1.0], Construction::Standard)?;
    /// assert!((one.geometric_average_call(100.0)? - 10.450583572185565).abs() < 1e-12);
    /// assert!(one.geometric_average_call(0.0).is_err());
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn geometric_average_call(&self, strike: f64) -> Result<f64> {
        if !(strike.is_finite() && strike > 0.0) {
            return Err(Error::invalid("strike", strike, "a finite strike > 0"));
        }
        let times = self.path.times();
        let n = times.len() as f64;
        let mean_t = times.iter().sum::<f64>() / n;
        let sum_min: f64 = times
            .iter()
            .map(|&s| times.iter().map(|&t| s.min(t)).sum::<f64>())
            .sum();
        let mu = self.s0.ln() + (self.rate - 0.5 * self.sigma * self.sigma) * mean_t;
        let sd = self.sigma * (sum_min / (n * n)).sqrt();
        let discount = (-self.rate * times[times.len() - 1]).exp();
        if sd == 0.0 {
            // A certain average: the payoff itself.
            return Ok(discount * (mu.exp() - strike).max(0.0));
        }
        let d2 = (mu - strike.ln()) / sd;
        let d1 = d2 + sd;
        Ok(discount * ((mu + 0.5 * sd * sd).exp() * normal_cdf(d1) - strike * normal_cdf(d2)))
    }
}

impl Measure for GeometricBrownianMotion {
    fn canonical_dims(&self) -> usize {
        self.path.canonical_dims()
    }

    fn dims(&self) -> usize {
        self.path.dims()
    }

    fn map(&self, u: &[f64], x: &mut [f64]) -> f64 {
        let weight = self.path.map(u, x);
        for v in x.iter_mut().take(self.path.dims()) {
            *v = self.s0 * v.exp();
        }
        weight
    }
}
