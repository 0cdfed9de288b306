//! [`BrownianMotion`]: paths of `mu t + sigma W(t)` at given times, by the standard
//! (sequential) construction, the Brownian bridge or principal components.

use std::cell::RefCell;

use nalgebra::DMatrix;

use super::normal_map::{check_finite, largest_normal, standard_normal};
use super::principal_components::principal_components;
use super::{Measure, check_factor_dims};
use crate::error::{Error, Result};

/// The most a path may reach in magnitude, half of `f64::MAX`, so that rounding in the sums
/// that build it cannot overflow.
const LARGEST_PATH: f64 = f64::MAX / 2.0;

/// How a Brownian path is built from independent normals `z_0, z_1, ...` (one per canonical
/// coordinate). All three give the same law; they differ in how much of the path's variance
/// the first coordinates carry, and so in how much quasi-Monte Carlo gains (Caflisch, Morokoff
/// & Owen 1997; Glasserman, *Monte Carlo Methods in Financial Engineering*, 3.1).
///
/// ```
/// use mcint::measure::Construction;
/// assert_eq!(Construction::default(), Construction::Standard);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Construction {
    /// Increments in time order: `W(t_i) = W(t_{i-1}) + sqrt(t_i - t_{i-1}) z_i`.
    #[default]
    Standard,
    /// The endpoint first, then midpoints by bisection, each from its two neighbours:
    /// coarse features of the path come from the first coordinates.
    Bridge,
    /// Principal components of the covariance `min(t_i, t_j)`, largest first: the first
    /// coordinates carry the most variance possible.
    Pca,
}

thread_local! {
    static NORMALS: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
}

/// One step of the bridge: `W(t_m) = a W(t_left) + b W(t_right) + c z` (`W(0) = 0` where
/// there is no left neighbour).
#[derive(Debug, Clone, Copy)]
struct BridgeStep {
    m: usize,
    left: Option<usize>,
    right: usize,
    a: f64,
    b: f64,
    c: f64,
}

/// The law of the path `(X(t_1), ..., X(t_n))` of `X(t) = mu t + sigma W(t)`, `W` a standard
/// Brownian motion, at increasing times `0 < t_1 < ... < t_n`: one canonical coordinate per
/// date.
///
/// ```
/// use mcint::{Integrator, measure::{BrownianMotion, Construction}};
/// // E[W(1)^2] = 1 whatever the construction.
/// let times: Vec<f64> = (1..=8).map(|i| i as f64 / 8.0).collect();
/// for construction in [Construction::Standard, Construction::Bridge, Construction::Pca] {
///     let path = BrownianMotion::new(times.clone(), 0.0, 1.0, construction).unwrap();
///     let e = Integrator::expectation(|w: &[f64]| w[7] * w[7], path).samples(100_000).run().unwrap();
///     assert!((e.mean - 1.0).abs() < 5.0 * e.std_error.unwrap());
/// }
/// ```
#[derive(Debug, Clone)]
pub struct BrownianMotion {
    times: Vec<f64>,
    drift: f64,
    diffusion: f64,
    construction: Construction,
    /// `sqrt(t_i - t_{i-1})` (standard construction).
    steps: Vec<f64>,
    /// The bridge's steps after the endpoint.
    bridge: Vec<BridgeStep>,
    /// The principal-component factor, row by row (PCA construction).
    pca: Vec<f64>,
}

impl BrownianMotion {
    /// Paths at `times` (finite, strictly increasing, the first above 0; at most
    /// [`FACTOR_MAX_DIMS`](super::FACTOR_MAX_DIMS) of them for [`Construction::Pca`]) with
    /// `drift` (finite) and `diffusion` (finite, at least 0), built by `construction`. Every
    /// path must stay finite: `|drift| t + diffusion |W(t)|`, with the normals behind `W` as
    /// large as the canonical points allow (about 8.3 in magnitude), must stay below
    /// `f64::MAX / 2`.
    ///
    /// ```
    /// use mcint::measure::{BrownianMotion, Construction};
    /// let err = BrownianMotion::new(vec![0.5, 0.5], 0.0, 1.0, Construction::Bridge).unwrap_err();
    /// assert!(err.to_string().contains("strictly increasing"), "{err}");
    /// assert!(BrownianMotion::new(vec![1.0], 0.0, -1.0, Construction::Standard).is_err());
    /// // drift t overflows at t = 1e308.
    /// let err = BrownianMotion::new(vec![1e308], 10.0, 1.0, Construction::Standard).unwrap_err();
    /// assert!(err.to_string().contains("f64::MAX / 2"), "{err}");
    /// // Without a drift the same date is fine: W(1e308) is about 1e154.
    /// assert!(BrownianMotion::new(vec![1e308], 0.0, 1.0, Construction::Standard).is_ok());
    /// ```
    pub fn new(
        times: Vec<f64>,
        drift: f64,
        diffusion: f64,
        construction: Construction,
    ) -> Result<Self> {
        let path = BrownianMotion::build(times, drift, diffusion, construction)?;
        let reach = path
            .times
            .iter()
            .zip(path.spread())
            .map(|(&t, spread)| drift.abs() * t + diffusion * spread)
            .fold(
                0.0,
                |most: f64, r| if r > most || r.is_nan() { r } else { most },
            );
        if reach.is_nan() || reach > LARGEST_PATH {
            return Err(Error::invalid(
                "drift, diffusion and times",
                format!(
                    "drift {drift:?}, diffusion {diffusion:?}, last date {:?}",
                    path.times[path.times.len() - 1]
                ),
                format!(
                    "paths within f64::MAX / 2 = {LARGEST_PATH:.1e} in magnitude: |drift| t + \
                     diffusion |W(t)|, with normals up to {:.2}, reaches {reach:.3e}",
                    largest_normal()
                ),
            ));
        }
        Ok(path)
    }

    /// [`new`](Self::new) without the bound on the paths (geometric Brownian motion bounds
    /// its prices instead).
    pub(super) fn build(
        times: Vec<f64>,
        drift: f64,
        diffusion: f64,
        construction: Construction,
    ) -> Result<Self> {
        check_times(&times)?;
        check_finite("drift", &[drift])?;
        if !(diffusion.is_finite() && diffusion >= 0.0) {
            return Err(Error::invalid(
                "diffusion",
                diffusion,
                "a finite value >= 0",
            ));
        }
        let mut previous = 0.0;
        let steps = times
            .iter()
            .map(|&t| {
                let step = (t - previous).sqrt();
                previous = t;
                step
            })
            .collect();
        let bridge = if construction == Construction::Bridge {
            bridge_steps(&times)
        } else {
            Vec::new()
        };
        let pca = if construction == Construction::Pca {
            check_factor_dims(
                "times",
                times.len(),
                "dates",
                "; the bridge construction takes O(d)",
            )?;
            pca_factor(&times)?
        } else {
            Vec::new()
        };
        Ok(BrownianMotion {
            times,
            drift,
            diffusion,
            construction,
            steps,
            bridge,
            pca,
        })
    }

    /// The dates.
    ///
    /// ```
    /// use mcint::measure::{BrownianMotion, Construction};
    /// let b = BrownianMotion::new(vec![0.5, 1.0], 0.0, 1.0, Construction::Standard).unwrap();
    /// assert_eq!(b.times(), &[0.5, 1.0]);
    /// ```
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// The linear map `L` from the normals `z` to the standard path `W` (`n x n`, row by
    /// row): `L L'` is the covariance `min(t_i, t_j)` for every construction. An error for
    /// more dates than a dense `n x n` matrix is kept for (the standard and bridge
    /// constructions themselves take any number).
    ///
    /// ```
    /// use mcint::measure::{BrownianMotion, Construction};
    /// let b = BrownianMotion::new(vec![1.0, 2.0], 0.0, 1.0, Construction::Standard).unwrap();
    /// assert_eq!(b.factor().unwrap(), vec![1.0, 0.0, 1.0, 1.0]);
    /// let many: Vec<f64> = (1..=1_000_000).map(|i| i as f64).collect();
    /// let long = BrownianMotion::new(many, 0.0, 1.0, Construction::Bridge).unwrap();
    /// assert!(long.factor().unwrap_err().to_string().contains("at most"));
    /// ```
    pub fn factor(&self) -> Result<Vec<f64>> {
        let n = self.times.len();
        check_factor_dims("times", n, "dates", "; the paths themselves need no factor")?;
        let mut l = vec![0.0; n * n];
        let mut column = vec![0.0; n];
        let mut z = vec![0.0; n];
        for j in 0..n {
            z.fill(0.0);
            z[j] = 1.0;
            self.standard_path(&z, &mut column);
            for i in 0..n {
                l[i * n + j] = column[i];
            }
        }
        Ok(l)
    }

    /// For each date, the largest `|W(t_i)|` any canonical point gives: the normals are at
    /// most [`largest_normal`] in magnitude, so `|W(t_i)|` is at most that times the sum of
    /// the absolute values of row `i` of the factor (or a bound on it, for the bridge).
    pub(super) fn spread(&self) -> Vec<f64> {
        let n = self.times.len();
        let mut sums = vec![0.0; n];
        match self.construction {
            Construction::Standard => {
                let mut total = 0.0;
                for (sum, &step) in sums.iter_mut().zip(&self.steps) {
                    total += step;
                    *sum = total;
                }
            }
            Construction::Bridge => {
                // |W(t_m)| <= a |W(left)| + b |W(right)| + c |z|, with a, b >= 0.
                sums[n - 1] = self.times[n - 1].sqrt();
                for step in &self.bridge {
                    let left = step.left.map_or(0.0, |l| sums[l]);
                    sums[step.m] = step.a * left + step.b * sums[step.right] + step.c;
                }
            }
            Construction::Pca => {
                for (i, sum) in sums.iter_mut().enumerate() {
                    *sum = self.pca[i * n..(i + 1) * n].iter().map(|l| l.abs()).sum();
                }
            }
        }
        let z = largest_normal();
        sums.iter().map(|s| z * s).collect()
    }

    /// The path at its dates from one standard normal per date, as [`Measure::map`] gives it
    /// from their canonical coordinates: for callers that draw many paths and keep the
    /// normals in their own buffer.
    pub(crate) fn map_normals(&self, z: &[f64], x: &mut [f64]) {
        self.standard_path(z, x);
        for (x, &t) in x.iter_mut().zip(&self.times) {
            *x = self.drift * t + self.diffusion * *x;
        }
    }

    /// The standard Brownian path `W(t_i)` from the normals `z`.
    fn standard_path(&self, z: &[f64], w: &mut [f64]) {
        let n = self.times.len();
        match self.construction {
            Construction::Standard => {
                let mut level = 0.0;
                for ((slot, &step), &z) in w.iter_mut().zip(&self.steps).zip(z) {
                    level += step * z;
                    *slot = level;
                }
            }
            Construction::Bridge => {
                w[n - 1] = self.times[n - 1].sqrt() * z[0];
                for (step, &z) in self.bridge.iter().zip(&z[1..]) {
                    let left = step.left.map_or(0.0, |l| w[l]);
                    w[step.m] = step.a * left + step.b * w[step.right] + step.c * z;
                }
            }
            Construction::Pca => {
                for (i, slot) in w.iter_mut().enumerate().take(n) {
                    let row = &self.pca[i * n..(i + 1) * n];
                    *slot = row.iter().zip(z).map(|(l, z)| l * z).sum();
                }
            }
        }
    }
}

impl Measure for BrownianMotion {
    fn canonical_dims(&self) -> usize {
        self.times.len()
    }

    fn dims(&self) -> usize {
        self.times.len()
    }

    fn map(&self, u: &[f64], x: &mut [f64]) -> f64 {
        let n = self.times.len();
        NORMALS.with_borrow_mut(|z| {
            z.clear();
            z.extend(u[..n].iter().map(|&v| standard_normal(v)));
            self.map_normals(z, &mut x[..n]);
        });
        1.0
    }
}

/// Checks that `times` are finite, strictly increasing and above 0.
pub(super) fn check_times(times: &[f64]) -> Result<()> {
    if times.is_empty() {
        return Err(Error::invalid("times", "[]", "at least one date"));
    }
    check_finite("times", times)?;
    if times[0] <= 0.0 {
        return Err(Error::invalid(
            "times",
            format!("first date {}", times[0]),
            "dates above 0 (W(0) = 0 is known)",
        ));
    }
    if let Some(i) = times.windows(2).position(|w| w[1] <= w[0]) {
        return Err(Error::invalid(
            "times",
            format!("{} then {} at index {}", times[i], times[i + 1], i + 1),
            "strictly increasing dates",
        ));
    }
    Ok(())
}

/// The bridge's steps after the endpoint, breadth first: every level of bisection before
/// the next, so the first normals fix the coarsest features.
fn bridge_steps(times: &[f64]) -> Vec<BridgeStep> {
    let n = times.len();
    let mut steps = Vec::with_capacity(n.saturating_sub(1));
    let mut queue = std::collections::VecDeque::from([(None, n - 1)]);
    while let Some((left, right)) = queue.pop_front() {
        let first = left.map_or(0, |l: usize| l + 1);
        if first >= right {
            continue;
        }
        let m = (first + right - 1) / 2;
        let t_left = left.map_or(0.0, |l| times[l]);
        let (t_m, t_right) = (times[m], times[right]);
        let span = t_right - t_left;
        let (near, far) = (t_m - t_left, t_right - t_m);
        // The variance near far / span; for dates beyond about 1e154 (or below 1e-154) the
        // product overflows (underflows), and near / span * far, with near / span <= 1, not.
        let variance = match near * far {
            product if product.is_normal() => product / span,
            _ => near / span * far,
        };
        steps.push(BridgeStep {
            m,
            left,
            right,
            a: far / span,
            b: near / span,
            c: variance.sqrt(),
        });
        queue.push_back((left, m));
        queue.push_back((Some(m), right));
    }
    steps
}

/// `V sqrt(Lambda)` of the covariance `min(t_i, t_j)`, eigenvalues in decreasing order.
fn pca_factor(times: &[f64]) -> Result<Vec<f64>> {
    let n = times.len();
    let covariance = DMatrix::from_fn(n, n, |i, j| times[i].min(times[j]));
    principal_components(
        &covariance,
        "times",
        "use the standard or bridge construction",
    )
}
