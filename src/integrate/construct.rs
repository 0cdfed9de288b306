//! The constructors of [`Integrator`]: one per estimator, scalar here (vector ones are in
//! `vector`), each with the integrand and its domain, law or warp.

use super::Integrator;
use crate::engine::RunConfig;
use crate::estimator::{
    BatchUniformEstimator, Estimator, ExpectationEstimator, ImportanceEstimator, UniformEstimator,
    WarpImportanceEstimator,
};
use crate::measure::Measure;
use crate::pdf::{GeometricWarp, Pdf, UniformBox, WarpPoint};
use crate::points::Points;

impl<F: Fn(&[f64]) -> f64 + Send + Sync> Integrator<UniformEstimator<F>> {
    /// Integrates `f` over a box with the uniform estimator (A.14).
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let e = Integrator::over_box(|x: &[f64]| x[0], UniformBox::new(vec![0.0], vec![2.0]).unwrap())
    ///     .samples(10_000)
    ///     .run()
    ///     .unwrap();
    /// assert!((e.mean - 2.0).abs() < 5.0 * e.std_error.unwrap());
    /// ```
    pub fn over_box(f: F, domain: UniformBox) -> Self {
        Integrator::new(UniformEstimator::new(f, domain))
    }
}

impl<F: Fn(&Points, &mut [f64]) + Send + Sync> Integrator<BatchUniformEstimator<F>> {
    /// Integrates a batch integrand over a box with the uniform estimator (A.14): `f(points,
    /// out)` gets a block of up to 1024 domain points (one column per coordinate) and must
    /// write `f(x_i)` to every `out[i]`; see [`BatchUniformEstimator`]. With the same
    /// arithmetic per point, the estimate has the same bits as [`over_box`](Integrator::over_box).
    ///
    /// ```
    /// use mcint::{Integrator, Points, pdf::UniformBox};
    /// // x0 * x1 over [0, 2)^2 is 4, one column pass per coordinate.
    /// let product = |p: &Points, out: &mut [f64]| {
    ///     for (y, (&x0, &x1)) in out.iter_mut().zip(p.column(0).iter().zip(p.column(1))) {
    ///         *y = x0 * x1;
    ///     }
    /// };
    /// let domain = UniformBox::new(vec![0.0; 2], vec![2.0; 2]).unwrap();
    /// let batch = Integrator::over_box_batch(product, domain.clone()).samples(10_000).run().unwrap();
    /// assert!((batch.mean - 4.0).abs() < 5.0 * batch.std_error.unwrap());
    /// let per_point = Integrator::over_box(|x: &[f64]| x[0] * x[1], domain).samples(10_000).run().unwrap();
    /// assert_eq!(batch, per_point);
    /// ```
    pub fn over_box_batch(f: F, domain: UniformBox) -> Self {
        Integrator::new(BatchUniformEstimator::new(f, domain))
    }
}

impl<F: Fn(&[f64]) -> f64 + Send + Sync, P: Pdf> Integrator<ImportanceEstimator<F, P>> {
    /// Integrates `f` over the domain of `pdf`, sampling from `pdf` (A.19).
    ///
    /// ```
    /// use mcint::{Integrator, pdf::Exponential};
    /// // The integral of x e^{-x} over [0, inf) is 1.
    /// let pdf = Exponential::new(1.0, 0.0, f64::INFINITY).unwrap();
    /// let e = Integrator::with_pdf(|x: &[f64]| x[0] * (-x[0]).exp(), pdf).samples(20_000).run().unwrap();
    /// assert!((e.mean - 1.0).abs() < 5.0 * e.std_error.unwrap());
    /// ```
    pub fn with_pdf(f: F, pdf: P) -> Self {
        Integrator::new(ImportanceEstimator::new(f, pdf))
    }
}

impl<P: WarpPoint, R: Into<f64>, F: Fn(P) -> R + Send + Sync, W: GeometricWarp<P>>
    Integrator<WarpImportanceEstimator<F, W, P, R>>
{
    /// Integrates `f` over directions, the points of a triangle or of a disk, handed to it as
    /// a glam vector (`DVec3`, or `DVec2` for the disk; a renderer's `f32` `Vec3` and `Vec2`
    /// too, the sampled point rounded, and `f` may return `f32`), sampling from `warp` (see
    /// [`WarpImportanceEstimator`]): a sphere, a hemisphere or cap about any normal
    /// ([`Warp3::about`](crate::pdf::Warp3::about)), a triangle, a disk.
    ///
    /// ```
    /// use mcint::glam::DVec3;
    /// use mcint::pdf::{UniformHemisphere, Warp3};
    /// use mcint::Integrator;
    /// // The cosine-weighted integral of a constant over the hemisphere about n is pi.
    /// let n = DVec3::new(1.0, -2.0, 0.5);
    /// let f = move |d: DVec3| d.dot(n.normalize()).max(0.0);
    /// let e = Integrator::over_warp(f, UniformHemisphere.about(n)?).samples(100_000).run()?;
    /// assert!((e.mean - std::f64::consts::PI).abs() < 5.0 * e.std_error.unwrap());
    /// // The integral of |p|^2 over the unit disk is pi / 2.
    /// let disk = mcint::pdf::UniformDisk::unit();
    /// let e = Integrator::over_warp(|p: mcint::glam::DVec2| p.length_squared(), disk)
    ///     .samples(100_000)
    ///     .run()?;
    /// assert!((e.mean - std::f64::consts::FRAC_PI_2).abs() < 5.0 * e.std_error.unwrap());
    /// // A renderer's f32 vectors and f32 radiance: the same integral of cos over the hemisphere.
    /// let n32 = mcint::glam::Vec3::new(1.0, -2.0, 0.5).normalize();
    /// let cosine = move |d: mcint::glam::Vec3| d.dot(n32).max(0.0);
    /// let e = Integrator::over_warp(cosine, UniformHemisphere.about(n)?).samples(100_000).run()?;
    /// assert!((e.mean - std::f64::consts::PI).abs() < 5.0 * e.std_error.unwrap());
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn over_warp(f: F, warp: W) -> Self {
        Integrator::new(WarpImportanceEstimator::new(f, warp))
    }
}

impl<F: Fn(&[f64]) -> f64 + Send + Sync, M: Measure> Integrator<ExpectationEstimator<F, M>> {
    /// Integrates `f` against `measure`: `E[f(X)]` under a probability law (a
    /// [`Gaussian`](crate::measure::Gaussian), a [`BrownianMotion`](crate::measure::BrownianMotion)
    /// path, ...), or the integral of `f` over an unbounded box
    /// ([`Lebesgue`](crate::measure::Lebesgue)). Any sampler of the measure's canonical
    /// dimension serves; see [`ExpectationEstimator`].
    ///
    /// ```
    /// use mcint::{Integrator, measure::Gaussian, sampler::{Scramble, Sobol}};
    /// // E[|X|^2] = 3 for a standard normal in 3-D, with scrambled Sobol' points.
    /// let e = Integrator::expectation(|x: &[f64]| x.iter().map(|v| v * v).sum(), Gaussian::standard(3).unwrap())
    ///     .sampler(Sobol::new(3, Scramble::Owen, 1).unwrap())
    ///     .samples(4096)
    ///     .replicates(16)
    ///     .run()
    ///     .unwrap();
    /// assert!((e.mean - 3.0).abs() < 5.0 * e.std_error.unwrap());
    /// ```
    pub fn expectation(f: F, measure: M) -> Self {
        Integrator::new(ExpectationEstimator::new(f, measure))
    }
}

impl<E: Estimator> Integrator<E> {
    /// An integrator for any estimator, with independent points, one replicate, `2^16`
    /// samples and all available threads until told otherwise.
    ///
    /// ```
    /// use mcint::{Integrator, estimator::UniformEstimator, pdf::UniformBox};
    /// let est = UniformEstimator::new(|_: &[f64]| 3.0, UniformBox::unit(1).unwrap());
    /// assert_eq!(Integrator::new(est).run().unwrap().mean, 3.0);
    /// ```
    pub fn new(estimator: E) -> Self {
        Integrator {
            estimator,
            config: RunConfig::default(),
        }
    }
}
