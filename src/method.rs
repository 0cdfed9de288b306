//! [`Method`]: the integration methods by the names users pick them (`integrate --method`),
//! with the sampler and replicate defaults each starts from.

use crate::error::{Error, Result};
use crate::sampler::{PassKind, Sampler, SamplerKind};

/// An integration method: the [`Integrator`](crate::Integrator) with plain or randomized
/// quasi-Monte Carlo points, or one of the adaptive runners of [`adaptive`](crate::adaptive).
///
/// ```
/// use mcint::{Method, SamplerKind};
/// let method: Method = "rqmc".parse()?;
/// assert_eq!(method.default_sampler(), SamplerKind::Sobol);
/// assert!(!method.is_adaptive());
/// assert_eq!("vegas-plus".parse::<Method>()?, Method::VegasPlus);
/// assert!("monte".parse::<Method>().unwrap_err().to_string().contains("two-stage"));
/// # Ok::<(), mcint::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Method {
    /// The Integrator with the sampler as given (default independent points).
    Plain,
    /// Randomized quasi-Monte Carlo: Owen-scrambled Sobol' points by default, in independent
    /// replicates whose spread is the error bar.
    Rqmc,
    /// VEGAS ([`Vegas`](crate::adaptive::Vegas) without stratification).
    Vegas,
    /// VEGAS+ ([`Vegas`](crate::adaptive::Vegas) with adaptive stratification).
    VegasPlus,
    /// MISER ([`Miser`](crate::adaptive::Miser)).
    Miser,
    /// Two-stage stratified sampling ([`TwoStage`](crate::adaptive::TwoStage)).
    TwoStage,
    /// One LMS-scrambled Sobol' sequence doubled until a bound from its Walsh coefficients
    /// meets the tolerance ([`SobolG`](crate::adaptive::SobolG), QMCPy's `CubQMCSobolG`).
    SobolG,
}

impl Method {
    /// Every method, in the order of the names above.
    ///
    /// ```
    /// assert_eq!(mcint::Method::ALL.len(), 7);
    /// ```
    pub const ALL: [Method; 7] = [
        Method::Plain,
        Method::Rqmc,
        Method::Vegas,
        Method::VegasPlus,
        Method::Miser,
        Method::TwoStage,
        Method::SobolG,
    ];

    /// The method's name: `plain`, `rqmc`, `vegas`, `vegas-plus`, `miser`, `two-stage` or
    /// `sobol-g`.
    ///
    /// ```
    /// assert_eq!(mcint::Method::VegasPlus.name(), "vegas-plus");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            Method::Plain => "plain",
            Method::Rqmc => "rqmc",
            Method::Vegas => "vegas",
            Method::VegasPlus => "vegas-plus",
            Method::Miser => "miser",
            Method::TwoStage => "two-stage",
            Method::SobolG => "sobol-g",
        }
    }

    /// The sampler a run of this method uses when none is chosen: Sobol' for RQMC
    /// (Owen-scrambled, its default scramble) and for `sobol-g` (which scrambles its own
    /// sequence, LMS and a digital shift), independent points otherwise.
    ///
    /// ```
    /// use mcint::{Method, SamplerKind};
    /// assert_eq!(Method::Miser.default_sampler(), SamplerKind::Independent);
    /// ```
    pub fn default_sampler(self) -> SamplerKind {
        match self {
            Method::Rqmc | Method::SobolG => SamplerKind::Sobol,
            _ => SamplerKind::Independent,
        }
    }

    /// Whether the method adapts to the integrand as it runs (VEGAS, VEGAS+, MISER, two-stage,
    /// and `sobol-g`, which adapts its number of points).
    ///
    /// ```
    /// assert!(mcint::Method::TwoStage.is_adaptive());
    /// ```
    pub fn is_adaptive(self) -> bool {
        !matches!(self, Method::Plain | Method::Rqmc)
    }

    /// Replicates of a fixed-budget Integrator run (plain or RQMC) with `sampler` when none
    /// are chosen: 1 for independent points, whose per-sample variance is honest, or for an
    /// unrandomized sampler (whose passes repeat each other); 16 for a randomized sampler of
    /// dependent points, whose error bar is the spread of independent replicates (MISER's
    /// default too). A run to a tolerance given no replicates starts with 8 and adds more
    /// when that is cheaper than doubling their points.
    ///
    /// ```
    /// use mcint::{Method, Scramble};
    /// use mcint::sampler::{Independent, Sobol};
    /// assert_eq!(Method::Rqmc.default_replicates(&Sobol::new(2, Scramble::Owen, 0)?), 16);
    /// assert_eq!(Method::Rqmc.default_replicates(&Sobol::new(2, Scramble::None, 0)?), 1);
    /// assert_eq!(Method::Plain.default_replicates(&Independent::new(2, 0)?), 1);
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn default_replicates(self, sampler: &dyn Sampler) -> u64 {
        let independent = sampler.passes() == PassKind::Independent;
        match self {
            Method::Miser => crate::engine::DEFAULT_REPLICATES,
            _ if independent || !sampler.is_randomized() => 1,
            _ => crate::engine::DEFAULT_REPLICATES,
        }
    }
}

impl std::fmt::Display for Method {
    /// The method's [`name`](Method::name).
    ///
    /// ```
    /// assert_eq!(mcint::Method::Rqmc.to_string(), "rqmc");
    /// ```
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Method {
    type Err = Error;

    /// A method by its [`name`](Method::name).
    ///
    /// ```
    /// assert!("miser".parse::<mcint::Method>().is_ok());
    /// ```
    fn from_str(name: &str) -> Result<Method> {
        Method::ALL
            .into_iter()
            .find(|m| m.name() == name)
            .ok_or_else(|| {
                Error::invalid(
                    "method",
                    name,
                    "one of plain, rqmc, vegas, vegas-plus, miser, two-stage, sobol-g",
                )
            })
    }
}
