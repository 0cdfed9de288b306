//! The settings of an [`Integrator`] run, shared by scalar and vector estimators.

use super::Integrator;
use crate::engine::run_settings;

/// Configuring: the settings every run shares, scalar or vector.
impl<E> Integrator<E> {
    run_settings! {
        setup: "use mcint::{Integrator, pdf::UniformBox};\n\
                const DIMS: usize = 2;\n\
                let runner = || Integrator::over_box(|x: &[f64]| x[0] * x[1], UniformBox::unit(DIMS).unwrap()).samples(4096);",
        run: ".run().unwrap()";
        sampler, seed, threads, tolerance, non_finite, time_limit, deadline, cancel_token, progress, cluster
    }

    /// Points per replicate (at least 1; a multiple of the pass size for samplers with
    /// fixed passes, at most the pass size for extensible sequences). Defaults to the pass
    /// size for fixed passes and `2^16` otherwise; with a tolerance, the first stage's size.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let e = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).samples(10).run().unwrap();
    /// assert_eq!(e.n, 10);
    /// ```
    pub fn samples(mut self, samples: u64) -> Self {
        self.config.samples = Some(samples);
        self
    }

    /// Number of independent replicates (at least 1; default 1, or 8 in a run to a
    /// tolerance with dependent points).
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let e = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap())
    ///     .samples(10).replicates(3).run().unwrap();
    /// assert_eq!((e.n, e.replicates), (30, 3));
    /// ```
    pub fn replicates(mut self, replicates: u64) -> Self {
        self.config.replicates = Some(replicates);
        self
    }

    /// Names the integrand for checkpoints: a [`PartialRun`](super::PartialRun) of a run with another label is
    /// refused. The integrand itself cannot be compared (only its values at a few probe
    /// points are), so a label such as the family and parameters of a test function guards
    /// against resuming a checkpoint with an integrand that differs elsewhere.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let run = |label: &str| Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap())
    ///     .samples(50_000)
    ///     .label(label);
    /// let part = run("x").run_part(0..1).unwrap();
    /// let err = run("y").finish(&part).unwrap_err();
    /// assert!(err.to_string().contains("label"), "{err}");
    /// ```
    pub fn label(mut self, label: impl Into<String>) -> Self {
        self.config.label = Some(label.into());
        self
    }
}
