//! Per-hypercube moments of VEGAS+: running sums within a chunk, exact merges across chunks,
//! and a hypercube's contribution to the estimate, each with a bound on the rounding error of
//! its mean (as [`Accumulator`](crate::Accumulator) keeps one; see `stats::rounding`).

use crate::stats::rounding::{UNIT_ROUNDOFF, contribution_allowance, gamma};

/// Relative roundoff floor of a hypercube's variance (the `EPSILON` of `vegas`).
const ROUNDOFF: f64 = 10.0 * f64::EPSILON;

/// Count, mean and sum of squared deviations, merged exactly (Chan, Golub & LeVeque 1979).
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
#[derive(Clone, Copy, Default, Debug)]
pub(super) struct CubeResult {
    /// Its contribution to the estimate, `V_h mean_h`.
    pub(super) mean: f64,
    /// Its contribution to the variance.
    pub(super) variance: f64,
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
        sigf: sigma2.powf(0.5 * beta),
        rounding: cube_volume * (m.rounding + contribution_allowance(scale))
            + (gamma(cubes as f64) + UNIT_ROUNDOFF) * mean.abs(),
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
