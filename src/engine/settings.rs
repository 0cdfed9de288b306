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
        pub fn non_finite(mut self, policy: $crate::non_finite::NonFinitePolicy) -> Self {
            self.config.non_finite = policy;
            self
        }
    };
    (@time_limit $setup:literal $run:literal) => {
        /// The longest the run may take. It is checked before every chunk of work, so the run
        /// returns within the limit plus one chunk's work, with what it has:
        /// [`StopReason::TimeLimit`](crate::stats::StopReason::TimeLimit) on an estimate of the
        /// work done, or [`Error::Interrupted`](crate::Error::Interrupted) if there is none yet.
        /// A time limit also lifts the refusal of budgets above `2^52` evaluations.
        ///
        #[doc = concat!(
            "```\n", $setup, "\n",
            "use std::time::Duration;\n",
            "let e = runner().time_limit(Duration::from_secs(3600))", $run, ";\n",
            "assert_eq!(e.stop, mcint::stats::StopReason::Budget); // finished well within it\n",
            "```"
        )]
        pub fn time_limit(mut self, limit: std::time::Duration) -> Self {
            self.config.time_limit = Some(limit);
            self
        }
    };
    (@deadline $setup:literal $run:literal) => {
        /// The instant by which the run must stop, as for a
        /// [time limit](Self::time_limit) (the earlier of the two applies). For work done in
        /// several calls under one limit, such as a checkpointed run resumed part by part.
        ///
        #[doc = concat!(
            "```\n", $setup, "\n",
            "use std::time::{Duration, Instant};\n",
            "let e = runner().deadline(Instant::now() + Duration::from_secs(3600))", $run, ";\n",
            "assert_eq!(e.stop, mcint::stats::StopReason::Budget); // finished well before it\n",
            "let past = runner().deadline(Instant::now()).run().unwrap_err();\n",
            "assert!(matches!(past, mcint::Error::Interrupted { .. }), \"{past}\");\n",
            "```"
        )]
        pub fn deadline(mut self, deadline: std::time::Instant) -> Self {
            self.config.deadline = Some(deadline);
            self
        }
    };
    (@cancel_token $setup:literal $run:literal) => {
        /// A token that stops the run from another thread (see
        /// [`CancelToken`](crate::CancelToken)): it returns with what it has, as for a time
        /// limit, with [`StopReason::Cancelled`](crate::stats::StopReason::Cancelled).
        ///
        #[doc = concat!(
            "```\n", $setup, "\n",
            "let token = mcint::CancelToken::new();\n",
            "token.cancel(); // before the run: it stops before its first chunk\n",
            "assert!(runner().cancel_token(token).run().is_err());\n",
            "```"
        )]
        pub fn cancel_token(mut self, token: $crate::engine::CancelToken) -> Self {
            self.config.cancel = Some(token);
            self
        }
    };
    (@progress $setup:literal $run:literal) => {
        /// A callback told `(evaluations done, evaluations planned)` as the run goes (the
        /// planned count is 0 when a run to a tolerance cannot know it), on the thread that
        /// called `run`: for progress bars on long runs.
        ///
        #[doc = concat!(
            "```\n", $setup, "\n",
            "use std::sync::{Arc, Mutex};\n",
            "let seen = Arc::new(Mutex::new(Vec::new()));\n",
            "let log = Arc::clone(&seen);\n",
            "let e = runner().progress(move |done, planned| log.lock().unwrap().push((done, planned)))", $run, ";\n",
            "let seen = seen.lock().unwrap();\n",
            "assert!(!seen.is_empty() && seen.windows(2).all(|w| w[0].0 <= w[1].0));\n",
            "assert_eq!(seen.last().unwrap().0, e.evaluations);\n",
            "```"
        )]
        pub fn progress(mut self, progress: impl Fn(u64, u64) + Send + Sync + 'static) -> Self {
            self.config.progress = Some(std::sync::Arc::new(progress));
            self
        }
    };
    (@cluster $setup:literal $run:literal) => {
        /// Spreads the run over the ranks of an MPI job (the `mpi` feature; see
        /// [`Cluster`](crate::Cluster)): call `run` on every rank with the same settings, and
        /// every rank gets the result of a one-process run, bit for bit.
        ///
        #[doc = concat!(
            "```\n", $setup, "\n",
            "let _universe = mcint::mpi::initialize().unwrap();\n",
            "let cluster = mcint::Cluster::world().unwrap();\n",
            "assert_eq!(runner().cluster(cluster)", $run, ", runner()", $run, ");\n",
            "```"
        )]
        #[cfg(feature = "mpi")]
        pub fn cluster(mut self, cluster: $crate::engine::Cluster) -> Self {
            self.config.cluster = Some(cluster);
            self
        }
    };
}

pub(crate) use run_settings;
