//! The integration methods of `integrate --method`: the `Integrator` with plain or
//! randomized quasi-Monte Carlo points, and the adaptive VEGAS, VEGAS+ and MISER.

use mcint::Estimate;
use mcint::adaptive::{Miser, Vegas};
use mcint::pdf::UniformBox;
use mcint::sampler::Sampler;
use mcint::stats::Tolerance;
use mcint::testfns::TestFunction;

/// The integration methods `--method` accepts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    Plain,
    Rqmc,
    Vegas,
    VegasPlus,
    Miser,
}

pub const METHOD_NAMES: &str = "plain, rqmc, vegas, vegas-plus or miser";

/// Iterations allowed to a VEGAS run to a tolerance: its evaluation limit stops it first.
pub const VEGAS_ITERATIONS_TO_TOLERANCE: u64 = 1 << 20;

impl Method {
    pub fn name(self) -> &'static str {
        match self {
            Method::Plain => "plain",
            Method::Rqmc => "rqmc",
            Method::Vegas => "vegas",
            Method::VegasPlus => "vegas-plus",
            Method::Miser => "miser",
        }
    }

    /// The sampler used when `--sampler` is not given.
    pub fn default_sampler(self) -> &'static str {
        match self {
            Method::Rqmc => "sobol",
            _ => "independent",
        }
    }

    /// Whether the method is one of the adaptive integrators (VEGAS, VEGAS+, MISER).
    pub fn is_adaptive(self) -> bool {
        matches!(self, Method::Vegas | Method::VegasPlus | Method::Miser)
    }
}

impl std::str::FromStr for Method {
    type Err = String;

    fn from_str(name: &str) -> Result<Method, String> {
        match name {
            "plain" => Ok(Method::Plain),
            "rqmc" => Ok(Method::Rqmc),
            "vegas" => Ok(Method::Vegas),
            "vegas-plus" => Ok(Method::VegasPlus),
            "miser" => Ok(Method::Miser),
            _ => Err(format!(
                "unknown --method '{name}': expected {METHOD_NAMES}"
            )),
        }
    }
}

/// What an adaptive run needs from the command line.
pub struct AdaptiveRun<'a> {
    pub method: Method,
    pub f: &'a dyn TestFunction,
    pub sampler: Box<dyn Sampler>,
    /// `--n`: evaluations per iteration (VEGAS) or per replicate (MISER; with a tolerance, of
    /// the first stage).
    pub n: Option<u64>,
    /// `--replicates` (MISER only).
    pub replicates: Option<u64>,
    pub tolerance: Option<Tolerance>,
    pub seed: u64,
    pub threads: Option<usize>,
    /// Stops the run early (SIGINT or SIGTERM).
    pub cancel: mcint::CancelToken,
    /// `--mpi`: the ranks to spread the run over.
    pub spread: crate::ranks::Spread,
}

impl AdaptiveRun<'_> {
    /// Runs VEGAS, VEGAS+ or MISER over the unit cube.
    pub fn run(self) -> Result<Estimate, String> {
        let f = self.f;
        let integrand = |x: &[f64]| f.eval(x);
        let domain = UniformBox::unit(f.dims()).map_err(|e| e.to_string())?;
        let result = match self.method {
            Method::Vegas | Method::VegasPlus => {
                if self.replicates.is_some() {
                    return Err(format!(
                        "--replicates does not apply to --method {} (its error bar combines \
                         iterations)",
                        self.method.name()
                    ));
                }
                let mut vegas = Vegas::new(integrand, domain)
                    .sampler(self.sampler)
                    .stratified(self.method == Method::VegasPlus)
                    .seed(self.seed)
                    .cancel_token(self.cancel);
                if let Some(n) = self.n {
                    vegas = vegas.samples(n);
                }
                if let Some(t) = self.threads {
                    vegas = vegas.threads(t);
                }
                if let Some(t) = self.tolerance {
                    vegas = vegas.tolerance(t).iterations(VEGAS_ITERATIONS_TO_TOLERANCE);
                }
                crate::ranks::spread!(vegas, self.spread).run()
            }
            Method::Miser => {
                let mut miser = Miser::new(integrand, domain)
                    .sampler(self.sampler)
                    .seed(self.seed)
                    .cancel_token(self.cancel);
                if let Some(n) = self.n {
                    miser = miser.samples(n);
                }
                if let Some(r) = self.replicates {
                    miser = miser.replicates(r);
                }
                if let Some(t) = self.threads {
                    miser = miser.threads(t);
                }
                if let Some(t) = self.tolerance {
                    miser = miser.tolerance(t);
                }
                crate::ranks::spread!(miser, self.spread).run()
            }
            Method::Plain | Method::Rqmc => {
                return Err(format!("{} is not an adaptive method", self.method.name()));
            }
        };
        result.map_err(|e| e.to_string())
    }
}
