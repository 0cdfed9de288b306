//! `run_settings!`: the setters of [`RunConfig`](super::RunConfig), written and documented
//! once for every runner.
//!
//! A runner with a field `config: RunConfig` lists the settings it offers:
//!
//! ```ignore
//! impl<F> Vegas<F> {
//!     run_settings! {
//!         setup: "use mcint::{adaptive::Vegas, pdf::UniformBox}; ...",
//!         run: ".run().unwrap()";
//!         sampler, seed, threads, tolerance, non_finite
//!     }
//! }
//! ```
//!
//! `setup` is doctest code defining `DIMS` and `runner`, a closure that returns a fresh
//! runner of the type; `run` is the call that runs it. Each setter's example is built from
//! them, so every runner's page shows its own code.

/// See the [module documentation](self).
macro_rules! run_settings {
    (setup: $setup:literal, run: $run:literal; $($setting:ident),+ $(,)?) => {
        $( $crate::engine::run_settings!(@$setting $setup $run); )+
    };
    (@sampler $setup:literal $run:literal) => {
        /// The source of canonical points (default: independent points); its dimension must
        /// match the run's, and which kinds of passes the method accepts is on its own page. A
        /// seed set with `seed` overrides the sampler's, in whichever order the two are set.
        ///
        #[doc = concat!(
            "```\n", $setup, "\n",
            "use mcint::sampler::{Scramble, Sobol};\n",
            "let sobol = runner().sampler(Sobol::new(DIMS, Scramble::Owen, 1).unwrap())", $run, ";\n",
            "let reseeded = runner().seed(5).sampler(Sobol::new(DIMS, Scramble::Owen, 1).unwrap())", $run, ";\n",
            "assert_eq!(reseeded, runner().sampler(Sobol::new(DIMS, Scramble::Owen, 5).unwrap())", $run, ");\n",
            "assert_ne!(sobol, reseeded);\n",
            "```"
        )]
        pub fn sampler(mut self, sampler: impl $crate::sampler::Sampler + 'static) -> Self {
            self.config.set_sampler(Box::new(sampler));
            self
        }
    };
    (@seed $setup:literal $run:literal) => {
        /// The seed of the sampler's randomization: the same seed gives the same result, bit
        /// for bit.
        ///
        #[doc = concat!(
            "```\n", $setup, "\n",
            "assert_eq!(runner().seed(1)", $run, ", runner().seed(1)", $run, ");\n",
            "assert_ne!(runner().seed(1)", $run, ", runner().seed(2)", $run, ");\n",
            "```"
        )]
        pub fn seed(mut self, seed: u64) -> Self {
            self.config.set_seed(seed);
            self
        }
    };
    (@threads $setup:literal $run:literal) => {
        /// Number of worker threads (at least 1; default: all available). The result does not
        /// depend on it. A run started from inside another run's integrand shares the outer
        /// run's threads.
        ///
        #[doc = concat!(
            "```\n", $setup, "\n",
            "assert_eq!(runner().threads(1)", $run, ", runner().threads(3)", $run, ");\n",
            "```"
        )]
        pub fn threads(mut self, threads: usize) -> Self {
            self.config.threads = Some(threads);
            self
        }
    };
    (@tolerance $setup:literal $run:literal) => {
        /// Runs until the 95% confidence interval meets `tolerance` (absolute and/or relative),
        /// or until its evaluation or time limit, instead of a fixed budget; the method's page
        /// says how it grows the run. [`Estimate::stop`](crate::stats::Estimate::stop),
        /// `converged` and `iterations` say how the run ended, and `evaluations` counts every
        /// evaluation spent.
        ///
        #[doc = concat!(
            "```\n", $setup, "\n",
            "use mcint::stats::{StopReason, Tolerance};\n",
            "let e = runner().tolerance(Tolerance::relative(1e-2).unwrap())", $run, ";\n",
            "assert_eq!((e.stop, e.converged), (StopReason::ToleranceMet, Some(true)));\n",
            "assert!(e.half_width(0.95).unwrap().unwrap() <= 1e-2 * e.mean.abs());\n",
            "```"
        )]
        pub fn tolerance(mut self, tolerance: $crate::stats::Tolerance) -> Self {
            self.config.tolerance = Some(tolerance);
            self
        }
    };
    (@non_finite $setup:literal $run:literal) => {
        /// What to do with NaN or infinite values of the integrand: fail (the default, with
        /// their count and the first point) or skip and count them in
        /// [`Estimate::non_finite`](crate::stats::Estimate::non_finite) (see
        /// [`NonFinitePolicy`](crate::NonFinitePolicy)).
        ///
        #[doc = concat!(
            "```\n", $setup, "\n",
            "use mcint::NonFinitePolicy;\n",
            "let e = runner().non_finite(NonFinitePolicy::Skip)", $run, ";\n",
            "assert_eq!(e.non_finite, 0); // this integrand is finite everywhere\n",
            "```"
        )]
        pub fn non_finite(mut self, policy: $crate::NonFinitePolicy) -> Self {
            self.config.non_finite = policy;
            self
        }
    };
}

pub(crate) use run_settings;
