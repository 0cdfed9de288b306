//! [`Level`]: what a multilevel run needs of a model.

use crate::Points;

/// A model seen level by level: level `l` approximates the quantity of interest with a time
/// step (or mesh) refined by the factor [`refinement`](Self::refinement) per level, and one
/// sample of it gives the fine approximation `P_l` and the coarse one `P_{l-1}` from the same
/// randomness, so that `P_l - P_{l-1}` is small when the approximations converge.
///
/// A sample is driven by one canonical point `u` in `[0,1)^dims(l)` (independent points for
/// multilevel Monte Carlo, a scrambled Sobol' sequence for multilevel QMC): put the
/// coordinates that matter most first (a Brownian bridge does that for paths).
///
/// ```
/// use mcint::multilevel::{Level, Multilevel};
/// // E[U^2] with "level l" adding a bias of 2^-l: P_l = u^2 + 2^-l.
/// struct Biased;
/// impl Level for Biased {
///     fn dims(&self, _: usize) -> usize { 1 }
///     fn cost(&self, level: usize) -> f64 { (1u64 << level) as f64 }
///     fn sample(&self, level: usize, u: &[f64], _: &mut Vec<f64>) -> (f64, f64) {
///         let p = |l: usize| u[0] * u[0] + 0.5f64.powi(l as i32);
///         (p(level), if level == 0 { 0.0 } else { p(level - 1) })
///     }
/// }
/// let run = Multilevel::new(Biased).rmse(1e-3).seed(1).run().unwrap();
/// assert!((run.estimate - 1.0 / 3.0).abs() < 3e-3, "{run}");
/// ```
pub trait Level: Send + Sync {
    /// The refinement factor `M` between levels (the time step of level `l` is `h_0 M^-l`):
    /// the base of the decay rates `alpha`, `beta` and `gamma`. Default 2.
    ///
    /// ```
    /// use mcint::multilevel::{Level, Payoff, Scheme, Sde, SdeLevels};
    /// let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// let levels = SdeLevels::new(gbm, Scheme::Milstein, Payoff::european_call(100.0).unwrap(), 1.0)
    ///     .unwrap();
    /// assert_eq!(levels.refinement(), 2);
    /// ```
    fn refinement(&self) -> u32 {
        2
    }

    /// The canonical coordinates one sample of level `level` takes.
    ///
    /// ```
    /// use mcint::multilevel::{Level, Payoff, Scheme, Sde, SdeLevels};
    /// let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// let levels = SdeLevels::new(gbm, Scheme::Euler, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
    /// assert_eq!(levels.dims(3), 8); // 2^3 time steps, one normal each
    /// ```
    fn dims(&self, level: usize) -> usize;

    /// The cost of one sample of level `level`, in any fixed unit (time steps of the fine and
    /// coarse paths, for an SDE): the optimal allocation weighs samples by it, and the run
    /// reports costs in it.
    ///
    /// ```
    /// use mcint::multilevel::{Level, Payoff, Scheme, Sde, SdeLevels};
    /// let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// let levels = SdeLevels::new(gbm, Scheme::Euler, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
    /// assert_eq!((levels.cost(0), levels.cost(3)), (1.0, 12.0)); // 8 fine + 4 coarse steps
    /// ```
    fn cost(&self, level: usize) -> f64;

    /// The cost of `P_l` alone, what standard Monte Carlo on level `level` pays per sample
    /// (default: [`cost`](Self::cost)).
    ///
    /// ```
    /// use mcint::multilevel::{Level, Payoff, Scheme, Sde, SdeLevels};
    /// let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// let levels = SdeLevels::new(gbm, Scheme::Euler, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
    /// assert_eq!(levels.fine_cost(3), 8.0);
    /// ```
    fn fine_cost(&self, level: usize) -> f64 {
        self.cost(level)
    }

    /// The known weak rate `alpha` of `|E[P_l - P_{l-1}]| ~ M^(-alpha l)`, if the model knows
    /// it (default: none). The bias extrapolation then takes the smaller of it and the fitted
    /// rate: the first levels often fall faster than the asymptotic rate, and a fit to them
    /// alone underestimates the bias.
    ///
    /// ```
    /// use mcint::multilevel::{Level, Payoff, Scheme, Sde, SdeLevels};
    /// let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// let levels = SdeLevels::new(gbm, Scheme::Euler, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
    /// assert_eq!(levels.weak_order(), Some(1.0));
    /// ```
    fn weak_order(&self) -> Option<f64> {
        None
    }

    /// One sample of level `level` from the canonical point `u`: `(P_l, P_{l-1})`, with
    /// `P_{-1} = 0` at level 0. `scratch` is a buffer the run keeps for each thread, for the
    /// model's own use.
    ///
    /// ```
    /// use mcint::multilevel::{Level, Payoff, Scheme, Sde, SdeLevels};
    /// let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// let levels = SdeLevels::new(gbm, Scheme::Euler, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
    /// let (fine, coarse) = levels.sample(2, &[0.9, 0.8, 0.7, 0.6], &mut Vec::new());
    /// assert!(fine > 0.0 && coarse > 0.0); // W(1) = 1.28: both paths end in the money
    /// assert_eq!(levels.sample(0, &[0.1], &mut Vec::new()).1, 0.0);
    /// ```
    fn sample(&self, level: usize, u: &[f64], scratch: &mut Vec<f64>) -> (f64, f64);

    /// The samples of level `level` from a block of canonical points, one sample per point:
    /// `(fine[i], coarse[i])` is [`sample`](Self::sample) of point `i`. A run draws its
    /// samples through this, a block at a time; the default calls `sample` point by point.
    /// Override it where one call per block is cheaper (a model in another language, or
    /// vectorized over the block); `fine` and `coarse` hold `points.len()` values.
    ///
    /// ```
    /// use mcint::Points;
    /// use mcint::multilevel::{Level, Payoff, Scheme, Sde, SdeLevels};
    /// let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// let levels = SdeLevels::new(gbm, Scheme::Euler, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
    /// let points = Points::from_rows(&[vec![0.9, 0.8], vec![0.1, 0.3]]).unwrap();
    /// let (mut fine, mut coarse) = ([0.0; 2], [0.0; 2]);
    /// levels.sample_block(1, &points, &mut fine, &mut coarse, &mut Vec::new());
    /// assert_eq!((fine[1], coarse[1]), levels.sample(1, &[0.1, 0.3], &mut Vec::new()));
    /// ```
    fn sample_block(
        &self,
        level: usize,
        points: &Points,
        fine: &mut [f64],
        coarse: &mut [f64],
        scratch: &mut Vec<f64>,
    ) {
        let mut u = vec![0.0; points.dims()];
        for (i, (fine, coarse)) in fine.iter_mut().zip(coarse).enumerate().take(points.len()) {
            points.copy_point(i, &mut u);
            (*fine, *coarse) = self.sample(level, &u, scratch);
        }
    }
}
