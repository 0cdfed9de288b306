//! The adaptive methods of `integrate --method` (VEGAS, VEGAS+, MISER, two-stage, sobol-g),
//! run from the command line's settings; the library's [`Method`] names them and gives their
//! defaults.

use mcint::adaptive::{Miser, SobolG, TwoStage, Vegas};
use mcint::pdf::UniformBox;
use mcint::sampler::Sampler;
use mcint::stats::Tolerance;
use mcint::testfns::TestFunction;
use mcint::{Estimate, Method};

/// The names `--method` accepts (the library's [`Method`]s).
pub const METHOD_NAMES: &str = "plain, rqmc, vegas, vegas-plus, miser, two-stage or sobol-g";

/// Iterations allowed to a VEGAS run to a tolerance: its evaluation limit stops it first.
pub const VEGAS_ITERATIONS_TO_TOLERANCE: u64 = 1 << 20;

/// Evaluations of a two-stage run when `--n` is not given (pilot included).
const DEFAULT_TWO_STAGE_EVALUATIONS: u64 = 1 << 16;

/// `--method NAME`, with the flag's own message for an unknown name.
pub fn parse_method(name: &str) -> Result<Method, String> {
    name.parse()
        .map_err(|_| format!("unknown --method '{name}': expected {METHOD_NAMES}"))
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
    /// `--time-limit`: the instant the run stops by.
    pub deadline: Option<std::time::Instant>,
    /// `--mpi`: the ranks to spread the run over.
    pub spread: crate::ranks::Spread,
}

impl AdaptiveRun<'_> {
    /// Runs VEGAS, VEGAS+, MISER, two-stage sampling or sobol-g over the unit cube.
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
                if let Some(deadline) = self.deadline {
                    vegas = vegas.deadline(deadline);
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
                if let Some(deadline) = self.deadline {
                    miser = miser.deadline(deadline);
                }
                crate::ranks::spread!(miser, self.spread).run()
            }
            Method::TwoStage => {
                if self.replicates.is_some() || self.tolerance.is_some() {
                    return Err(
                        "--method two-stage takes a fixed budget (--n evaluations), without \
                         --replicates or a tolerance"
                            .into(),
                    );
                }
                let n = self.n.unwrap_or(DEFAULT_TWO_STAGE_EVALUATIONS);
                let strata = TwoStage::<fn(&[f64]) -> f64>::strata_per_axis_for(f.dims(), n);
                let mut two_stage = TwoStage::new(integrand, domain, strata)
                    .sampler(self.sampler)
                    .samples(n)
                    .seed(self.seed)
                    .cancel_token(self.cancel);
                if let Some(t) = self.threads {
                    two_stage = two_stage.threads(t);
                }
                if let Some(deadline) = self.deadline {
                    two_stage = two_stage.deadline(deadline);
                }
                crate::ranks::spread!(two_stage, self.spread).run()
            }
            Method::SobolG => {
                if self.replicates.is_some() {
                    return Err(
                        "--replicates does not apply to --method sobol-g (one sequence, \
                                its error bound from Walsh coefficients)"
                            .into(),
                    );
                }
                // The batch form: Genz families evaluate blocks with vectorized exp and cos.
                let batch = |points: &mcint::Points, out: &mut [f64]| f.eval_batch(points, out);
                let mut sobol_g = SobolG::new_batch(batch, domain)
                    .seed(self.seed)
                    .cancel_token(self.cancel);
                if let Some(n) = self.n {
                    sobol_g = sobol_g.samples(n);
                }
                if let Some(t) = self.threads {
                    sobol_g = sobol_g.threads(t);
                }
                if let Some(t) = self.tolerance {
                    sobol_g = sobol_g.tolerance(t);
                }
                if let Some(deadline) = self.deadline {
                    sobol_g = sobol_g.deadline(deadline);
                }
                crate::ranks::spread!(sobol_g, self.spread).run()
            }
            Method::Plain | Method::Rqmc => {
                return Err(format!("{} is not an adaptive method", self.method.name()));
            }
        };
        result.map_err(|e| e.to_string())
    }
}
