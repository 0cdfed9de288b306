//! `SdeModel`: the library's built-in SDE levels (geometric Brownian motion or Heston, a
//! scheme and an option payoff), sampled in Rust, never calling back into Python.

use mcint::multilevel::{Payoff, Scheme, Sde, SdeLevels};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::errors::to_py;

/// The levels of an option's price under an SDE, as `mcint.SdeLevels` holds them: each run
/// builds its [`SdeLevels`] from these (they are cheap to build; the Brownian bridges come
/// when first used).
#[pyclass(module = "mcint._native", frozen)]
pub struct SdeModel {
    sde: Sde,
    scheme: Scheme,
    payoff: Payoff,
    maturity: f64,
    refinement: u32,
    discount: f64,
    model: &'static str,
}

impl SdeModel {
    /// The levels of one run (the settings were checked when the model was built).
    pub fn levels(&self) -> PyResult<SdeLevels> {
        SdeLevels::new(
            self.sde.clone(),
            self.scheme,
            self.payoff.clone(),
            self.maturity,
        )
        .and_then(|l| l.refinement_factor(self.refinement))
        .and_then(|l| l.discount(self.discount))
        .map_err(to_py)
    }

    #[allow(clippy::too_many_arguments, reason = "one keyword each")]
    fn new(
        model: &'static str,
        sde: Sde,
        rate: f64,
        payoff: &str,
        strike: f64,
        barrier: f64,
        maturity: f64,
        scheme: &str,
        refinement: u32,
    ) -> PyResult<Self> {
        let scheme = match scheme {
            "euler" => Scheme::Euler,
            "milstein" => Scheme::Milstein,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "invalid scheme = '{scheme}': expected 'euler' or 'milstein'"
                )));
            }
        };
        let payoff = match payoff {
            "european" => Payoff::european_call(strike),
            "asian" => Payoff::asian_call(strike),
            "lookback" => Ok(Payoff::lookback()),
            "digital" => Payoff::digital_call(strike),
            "barrier" => Payoff::down_and_out_call(strike, barrier),
            _ => {
                return Err(PyValueError::new_err(format!(
                    "invalid payoff = '{payoff}': expected 'european', 'asian', 'lookback', \
                     'digital' or 'barrier'"
                )));
            }
        }
        .map_err(to_py)?;
        let this = SdeModel {
            sde,
            scheme,
            payoff,
            maturity,
            refinement,
            discount: (-rate * maturity).exp(),
            model,
        };
        // Every setting is checked here, where the user gave it, not at the first run; the
        // discount first, in the user's terms.
        if !(this.discount.is_finite() && this.discount > 0.0) {
            return Err(PyValueError::new_err(format!(
                "invalid rate = {rate:e} with maturity = {maturity:e}: expected a discount \
                 factor exp(-rate * maturity) that is finite and above 0"
            )));
        }
        this.levels()?;
        Ok(this)
    }
}

#[pymethods]
impl SdeModel {
    /// Geometric Brownian motion `dS = r S dt + sigma S dW` from `s0`.
    #[staticmethod]
    #[allow(
        clippy::too_many_arguments,
        reason = "the keyword arguments of SdeLevels.gbm"
    )]
    fn gbm(
        s0: f64,
        rate: f64,
        sigma: f64,
        payoff: &str,
        strike: f64,
        barrier: f64,
        maturity: f64,
        scheme: &str,
        refinement: u32,
    ) -> PyResult<Self> {
        let sde = Sde::gbm(s0, rate, sigma).map_err(to_py)?;
        SdeModel::new(
            "gbm", sde, rate, payoff, strike, barrier, maturity, scheme, refinement,
        )
    }

    /// Heston's stochastic volatility model from `(s0, v0)`.
    #[staticmethod]
    #[allow(
        clippy::too_many_arguments,
        reason = "the keyword arguments of SdeLevels.heston"
    )]
    fn heston(
        s0: f64,
        v0: f64,
        rate: f64,
        kappa: f64,
        theta: f64,
        xi: f64,
        rho: f64,
        payoff: &str,
        strike: f64,
        barrier: f64,
        maturity: f64,
        scheme: &str,
        refinement: u32,
    ) -> PyResult<Self> {
        let sde = Sde::heston(s0, v0, rate, kappa, theta, xi, rho).map_err(to_py)?;
        SdeModel::new(
            "heston", sde, rate, payoff, strike, barrier, maturity, scheme, refinement,
        )
    }

    /// `gbm` or `heston`.
    #[getter]
    fn model(&self) -> &'static str {
        self.model
    }

    /// The payoff's name.
    #[getter]
    fn payoff(&self) -> &'static str {
        self.payoff.name()
    }

    /// `euler` or `milstein`.
    #[getter]
    fn scheme(&self) -> &'static str {
        match self.scheme {
            Scheme::Euler => "euler",
            Scheme::Milstein => "milstein",
        }
    }

    /// The refinement factor `M` between levels.
    #[getter]
    fn refinement(&self) -> u32 {
        self.refinement
    }

    /// The maturity `T`.
    #[getter]
    fn maturity(&self) -> f64 {
        self.maturity
    }
}
