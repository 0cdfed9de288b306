//! The arithmetic- and geometric-average Asian call under Black-Scholes, and the closed-form
//! price of the geometric one (Kemna & Vorst 1990), for the `asian_option` program.

use mcint::measure::{Construction, GeometricBrownianMotion};

/// The contract and the model.
#[derive(Debug, Clone, Copy)]
pub struct Contract {
    pub s0: f64,
    pub strike: f64,
    pub rate: f64,
    pub sigma: f64,
    pub maturity: f64,
    /// Averaging dates, equally spaced: `t_i = i T / dates`.
    pub dates: usize,
}

impl Contract {
    pub fn times(&self) -> Vec<f64> {
        (1..=self.dates)
            .map(|i| i as f64 * self.maturity / self.dates as f64)
            .collect()
    }

    pub fn paths(&self, construction: Construction) -> mcint::Result<GeometricBrownianMotion> {
        GeometricBrownianMotion::new(self.s0, self.rate, self.sigma, self.times(), construction)
    }

    fn discount(&self) -> f64 {
        (-self.rate * self.maturity).exp()
    }

    /// The discounted arithmetic-average payoff of a path of prices.
    pub fn arithmetic(&self, prices: &[f64]) -> f64 {
        let average = prices.iter().sum::<f64>() / prices.len() as f64;
        self.discount() * (average - self.strike).max(0.0)
    }

    /// The discounted geometric-average payoff of a path of prices.
    pub fn geometric(&self, prices: &[f64]) -> f64 {
        let log_average = prices.iter().map(|s| s.ln()).sum::<f64>() / prices.len() as f64;
        self.discount() * (log_average.exp() - self.strike).max(0.0)
    }

    /// The law of the log of the geometric average: normal with mean
    /// `log S0 + (r - sigma^2/2) mean(t)` and standard deviation
    /// `sigma sqrt(sum_ij min(t_i, t_j)) / n`, as `(mean, standard deviation)`.
    pub fn log_geometric_average(&self) -> (f64, f64) {
        let times = self.times();
        let n = times.len() as f64;
        let mean_t = times.iter().sum::<f64>() / n;
        let sum_min: f64 = times
            .iter()
            .map(|&s| times.iter().map(|&t| s.min(t)).sum::<f64>())
            .sum();
        let mu = self.s0.ln() + (self.rate - 0.5 * self.sigma * self.sigma) * mean_t;
        (mu, self.sigma * (sum_min / (n * n)).sqrt())
    }

    /// The exact price of the geometric-average call (a Black-Scholes formula for the
    /// lognormal average of [`log_geometric_average`](Self::log_geometric_average)).
    pub fn geometric_price(&self) -> f64 {
        let (mu, sd) = self.log_geometric_average();
        let variance = sd * sd;
        let d2 = (mu - self.strike.ln()) / sd;
        let d1 = d2 + sd;
        self.discount()
            * ((mu + 0.5 * variance).exp() * normal_cdf(d1) - self.strike * normal_cdf(d2))
    }
}

/// The standard normal cdf, `erfc(-x / sqrt 2) / 2`.
pub fn normal_cdf(x: f64) -> f64 {
    0.5 * libm::erfc(-x / std::f64::consts::SQRT_2)
}
