//! Per-hypercube moments of VEGAS+: running sums within a chunk, exact merges across chunks,
//! and a hypercube's contribution to the estimate, each with a bound on the rounding error of
//! its mean (as [`Accumulator`](crate::Accumulator) keeps one; see `stats::rounding`).

use crate::stats::rounding::{UNIT_ROUNDOFF, contribution_allowance, gamma};

/// Relative roundoff floor of a hypercube's variance (the `EPSILON` of `vegas`).
const ROUNDOFF: f64 = 10.0 * f64::EPSILON;

/// Count, mean and sum of squared deviations, merged exactly (Chan, Golub & LeVeque 1979).
#[cfg_attr(feature = "mpi", derive(serde::Serialize, serde::Deserialize))]
#[derive(Clone, Copy, Default, Debug)]
pub(super) struct Moments {
    pub(super) n: u64,
    pub(super) mean: f64,
    pub(super) m2: f64,
    /// A bound on the rounding error of `mean`.
    pub(super) rounding: f64,
}

impl Moments {
    pub(super) fn merge(&mut self, other: &Moments) {
        if other.n == 0 {
            return;
        }
        if self.n == 0 {
            *self = *other;
            return;
        }
        let (na, nb) = (self.n as f64, other.n as f64);
        let n = na + nb;
        let delta = other.mean - self.mean;
        self.mean += delta * (nb / n);
        self.m2 += other.m2 + delta * delta * (na * nb / n);
        self.n += other.n;
        self.rounding = (na * self.rounding + nb * other.rounding) / n
            + UNIT_ROUNDOFF * (self.mean.abs() + 3.0 * delta.abs() * (nb / n));
    }
}

/// Running sums shifted by the first value, which keep the variance accurate without a
/// division per point.
#[derive(Clone, Copy, Default)]
pub(super) struct ShiftedSums {
    pub(super) n: u64,
    pub(super) shift: f64,
    pub(super) s1: f64,
    pub(super) s2: f64,
}

impl ShiftedSums {
    #[inline]
    pub(super) fn push(&mut self, v: f64) {
        if self.n == 0 {
            self.shift = v;
        }
        let d = v - self.shift;
        self.n += 1;
        self.s1 += d;
        self.s2 += d * d;
    }

    pub(super) fn moments(&self) -> Moments {
        if self.n == 0 {
            return Moments::default();
        }
        let n = self.n as f64;
        let mean = self.shift + self.s1 / n;
        // The n shifted values and their running sum: sum |v - shift| <= sqrt(n s2).
        let rounding = gamma(n + 1.0) * (self.s2 / n).sqrt()
            + UNIT_ROUNDOFF * (self.s1.abs() / n + mean.abs());
        Moments {
            n: self.n,
            mean,
            m2: (self.s2 - self.s1 * self.s1 / n).max(0.0),
            rounding,
        }
    }
}

/// A hypercube's share of an iteration.
#[cfg_attr(feature = "mpi", derive(serde::Serialize, serde::Deserialize))]
#[derive(Clone, Copy, Default, Debug)]
pub(super) struct CubeResult {
    /// Its contribution to the estimate, `V_h mean_h`.
    pub(super) mean: f64,
    /// Its contribution to the variance.
    pub(super) variance: f64,
    /// `V_h^2 s_h^2`, its variance before dividing by its points.
    pub(super) sigma2: f64,
    /// `sigma_h^beta`, for the next allocation.
    pub(super) sigf: f64,
    /// A bound on the rounding error of `mean`, its share of the sum over `cubes` hypercubes
    /// and the allowance for the evaluation of its values included.
    pub(super) rounding: f64,
}

/// One hypercube's share of an iteration of `cubes` hypercubes.
pub(super) fn cube_result(m: &Moments, cube_volume: f64, beta: f64, cubes: u64) -> CubeResult {
    if m.n == 0 {
        return CubeResult::default();
    }
    let n = m.n as f64;
    let s2 = if m.n > 1 { m.m2 / (n - 1.0) } else { 0.0 };
    let v2 = cube_volume * cube_volume;
    let sigma2 = v2 * s2;
    let variance = (sigma2 / n).max(ROUNDOFF * v2 * (m.mean * m.mean + s2) / n);
    let mean = cube_volume * m.mean;
    // mean |J f| <= its root mean square about zero.
    let scale = (m.mean * m.mean + m.m2 / n).sqrt();
    CubeResult {
        mean,
        variance,
        sigma2,
        sigf: sigma2.powf(0.5 * beta),
        rounding: cube_volume * (m.rounding + contribution_allowance(scale))
            + (gamma(cubes as f64) + UNIT_ROUNDOFF) * mean.abs(),
    }
}

/// Position of the pair `(j, k)`, `j < k`, among the outputs' cross products.
#[inline]
pub(super) fn pair(j: usize, k: usize) -> usize {
    k * (k - 1) / 2 + j
}

/// The shifted sums of every output of one hypercube's points, with the sums of the products
/// of each pair of outputs (none for a single output, whose arithmetic is the scalar one).
#[derive(Clone, Default)]
pub(super) struct CubeSums {
    pub(super) outputs: Vec<ShiftedSums>,
    cross: Vec<f64>,
}

impl CubeSums {
    pub(super) fn new(m: usize) -> CubeSums {
        CubeSums {
            outputs: vec![ShiftedSums::default(); m],
            cross: vec![0.0; m * (m - 1) / 2],
        }
    }

    #[inline(always)]
    pub(super) fn clear(&mut self) {
        self.outputs.fill(ShiftedSums::default());
        self.cross.fill(0.0);
    }

    /// Adds one point's values `J f_k` (all finite).
    #[inline]
    pub(super) fn push(&mut self, values: &[f64]) {
        for (sums, &v) in self.outputs.iter_mut().zip(values) {
            sums.push(v);
        }
        for k in 1..values.len() {
            let dk = values[k] - self.outputs[k].shift;
            let row = &mut self.cross[pair(0, k)..pair(0, k) + k];
            for ((c, &v), sums) in row.iter_mut().zip(&values[..k]).zip(&self.outputs) {
                *c += (v - sums.shift) * dk;
            }
        }
    }

    pub(super) fn moments(&self) -> CubeMoments {
        let mut moments = CubeMoments::empty(self.outputs.len());
        self.moments_into(&mut moments);
        moments
    }

    /// [`moments`](Self::moments) into `out` (of the same number of outputs), without
    /// allocating: a hypercube closes every few points.
    #[inline(always)]
    pub(super) fn moments_into(&self, out: &mut CubeMoments) {
        if let ([moments], [sums]) = (&mut out.outputs[..], &self.outputs[..]) {
            // One output: no pairs (the common case, kept as lean as the scalar code).
            *moments = sums.moments();
            return;
        }
        for (moments, sums) in out.outputs.iter_mut().zip(&self.outputs) {
            *moments = sums.moments();
        }
        let n = self.outputs.first().map_or(0, |s| s.n) as f64;
        for k in 1..self.outputs.len() {
            for j in 0..k {
                let (a, b) = (&self.outputs[j], &self.outputs[k]);
                out.cross[pair(j, k)] = if n > 0.0 {
                    self.cross[pair(j, k)] - a.s1 * b.s1 / n
                } else {
                    0.0
                };
            }
        }
    }
}

/// Every output's [`Moments`] of one hypercube's points, with the co-moments
/// `sum (v_j - mean_j)(v_k - mean_k)` of each pair.
#[cfg_attr(feature = "mpi", derive(serde::Serialize, serde::Deserialize))]
#[derive(Clone, Default, Debug)]
pub(super) struct CubeMoments {
    pub(super) outputs: Vec<Moments>,
    pub(super) cross: Vec<f64>,
}

impl CubeMoments {
    pub(super) fn empty(m: usize) -> CubeMoments {
        CubeMoments {
            outputs: vec![Moments::default(); m],
            cross: vec![0.0; m * (m - 1) / 2],
        }
    }

    fn count(&self) -> u64 {
        self.outputs.first().map_or(0, |m| m.n)
    }

    /// Back to no points, keeping the buffers.
    pub(super) fn clear(&mut self) {
        self.outputs.fill(Moments::default());
        self.cross.fill(0.0);
    }

    /// Chan's merge of every output and pair.
    pub(super) fn merge(&mut self, other: &CubeMoments) {
        if other.count() == 0 {
            return;
        }
        if self.count() == 0 {
            self.clone_from(other);
            return;
        }
        let (na, nb) = (self.count() as f64, other.count() as f64);
        let weight = na * nb / (na + nb);
        for k in 1..self.outputs.len() {
            let dk = other.outputs[k].mean - self.outputs[k].mean;
            for j in 0..k {
                let dj = other.outputs[j].mean - self.outputs[j].mean;
                self.cross[pair(j, k)] += other.cross[pair(j, k)] + dj * dk * weight;
            }
        }
        for (m, o) in self.outputs.iter_mut().zip(&other.outputs) {
            m.merge(o);
        }
    }
}

/// Hypercubes' shares of an iteration, summed: per output the `mean`, `variance` and
/// `rounding` of [`CubeResult`], and per pair of outputs the covariance, each hypercube
/// adding `V_h^2 c_jk / n_h`.
#[cfg_attr(feature = "mpi", derive(serde::Serialize, serde::Deserialize))]
#[derive(Debug, Clone)]
pub(super) struct CubeTotals {
    pub(super) outputs: Vec<CubeResult>,
    pub(super) covariance: Vec<f64>,
}

impl CubeTotals {
    /// Nothing yet, for `m` outputs.
    pub(super) fn zero(m: usize) -> CubeTotals {
        CubeTotals {
            outputs: vec![CubeResult::default(); m],
            covariance: vec![0.0; m * (m - 1) / 2],
        }
    }

    /// Back to nothing, keeping the buffers.
    pub(super) fn clear(&mut self) {
        self.outputs.fill(CubeResult::default());
        self.covariance.fill(0.0);
    }

    /// Adds other sums of hypercubes.
    pub(super) fn add(&mut self, other: &CubeTotals) {
        for (total, cube) in self.outputs.iter_mut().zip(&other.outputs) {
            total.mean += cube.mean;
            total.variance += cube.variance;
            total.rounding += cube.rounding;
        }
        for (total, c) in self.covariance.iter_mut().zip(&other.covariance) {
            *total += c;
        }
    }

    /// Adds the hypercube with moments `m` and returns its `sigma_h^beta` for the next
    /// allocation: the scalar one for a single output, and `(sum_k w_k sigma_hk^2)^(beta/2)`
    /// for several, `w_k` scaling each output to a comparable size. Allocates nothing: it
    /// runs once per hypercube.
    #[inline(always)]
    pub(super) fn add_cube(
        &mut self,
        m: &CubeMoments,
        cube_volume: f64,
        beta: f64,
        cubes: u64,
        weights: &[f64],
    ) -> f64 {
        if let ([total], [moments]) = (&mut self.outputs[..], &m.outputs[..]) {
            // One output: no pairs and no weights (the scalar arithmetic, as lean as it was).
            let cube = cube_result(moments, cube_volume, beta, cubes);
            total.mean += cube.mean;
            total.variance += cube.variance;
            total.rounding += cube.rounding;
            return cube.sigf;
        }
        let mut weighted = 0.0;
        for ((total, moments), w) in self.outputs.iter_mut().zip(&m.outputs).zip(weights) {
            let cube = cube_result(moments, cube_volume, beta, cubes);
            total.mean += cube.mean;
            total.variance += cube.variance;
            total.rounding += cube.rounding;
            weighted += w * cube.sigma2;
        }
        let n = m.count() as f64;
        let v2 = cube_volume * cube_volume;
        for (total, &c) in self.covariance.iter_mut().zip(&m.cross) {
            *total += if n > 1.0 {
                v2 * (c / (n - 1.0)) / n
            } else {
                0.0
            };
        }
        weighted.powf(0.5 * beta)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shifted_sums_and_merges_agree_with_two_pass_moments() {
        let values: Vec<f64> = (0..100).map(|i| 1e6 + ((i * 37) % 11) as f64).collect();
        let mean = values.iter().sum::<f64>() / 100.0;
        let m2: f64 = values.iter().map(|v| (v - mean) * (v - mean)).sum();
        let mut left = ShiftedSums::default();
        let mut right = ShiftedSums::default();
        values[..30].iter().for_each(|&v| left.push(v));
        values[30..].iter().for_each(|&v| right.push(v));
        let mut merged = left.moments();
        merged.merge(&right.moments());
        assert_eq!(merged.n, 100);
        assert!((merged.mean - mean).abs() < 1e-9);
        assert!((merged.m2 - m2).abs() < 1e-9 * m2);
    }
}
