//! The arithmetic- and geometric-average Asian call under Black-Scholes for the
//! `asian_option` program (the geometric one's closed form is the library's).

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

    /// The exact price of the geometric-average call (the library's closed form,
    /// [`GeometricBrownianMotion::geometric_average_call`]).
    pub fn geometric_price(&self) -> mcint::Result<f64> {
        self.paths(Construction::Standard)?
            .geometric_average_call(self.strike)
    }
}
