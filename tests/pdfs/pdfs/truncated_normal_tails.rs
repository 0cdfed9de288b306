//! Far tails of the truncated normal: samples, densities and inverses stay exact.

use super::*;

// Far tails of the truncated normal

/// Reference truncated-normal cdf and density, computed without any normal cdf: Gauss-Legendre
/// on the Gaussian scaled by its value at the interval end nearest the mean, so nothing
/// underflows even at z = 30.
struct TailReference {
    mean: f64,
    sd: f64,
    /// Standardised interval, with the infinite end cut where the scaled density is e^-60.
    za: f64,
    zb: f64,
    /// The end nearest the mean (the density's largest value in the interval).
    z0: f64,
    total: f64,
}

impl TailReference {
    fn new(mean: f64, sd: f64, a: f64, b: f64) -> Self {
        let (za, zb) = ((a - mean) / sd, (b - mean) / sd);
        let z0 = if za >= 0.0 { za } else { zb };
        // exp(-(z^2 - z0^2)/2) <= exp(-|z0| (|z| - |z0|)): 60 / |z0| beyond z0 leaves e^-60.
        let zb = if zb.is_finite() {
            zb
        } else {
            za + 60.0 / za.abs()
        };
        let za = if za.is_finite() {
            za
        } else {
            zb - 60.0 / zb.abs()
        };
        let mut r = TailReference {
            mean,
            sd,
            za,
            zb,
            z0,
            total: 1.0,
        };
        r.total = r.mass(za, zb);
        r
    }

    fn scaled(&self, z: f64) -> f64 {
        (-0.5 * (z - self.z0) * (z + self.z0)).exp()
    }

    fn mass(&self, from: f64, to: f64) -> f64 {
        integrate(|z| self.scaled(z), from, to, 64)
    }

    fn cdf(&self, x: f64) -> f64 {
        let z = ((x - self.mean) / self.sd).clamp(self.za, self.zb);
        self.mass(self.za, z) / self.total
    }

    fn pdf(&self, x: f64) -> f64 {
        self.scaled((x - self.mean) / self.sd) / (self.sd * self.total)
    }
}

#[test]
fn far_tail_truncated_normals_sample_inside_with_the_right_cdf() {
    // The reference cdf is accurate to ~1e-15; x carries a few ulps of rounding, worth at most
    // pdf(x) * ulp(x) ~ 30 * 3.6e-15 = 1e-13 of probability at z = 30. So 1e-11 is generous
    // and still catches any loss of the tail (a naive 1 - Phi(x) would be off by O(1)).
    for (mean, sd, a, b) in [
        (0.0, 1.0, 8.0, 9.0),
        (0.0, 1.0, -30.0, -29.0),
        (0.0, 1.0, 30.0, INF),
        (0.0, 1.0, -INF, -30.0),
        (1.0, 0.5, 16.0, 17.0),
        (-2.0, 4.0, -150.0, -110.0),
        (0.0, 1.0, 37.0, 37.5),
    ] {
        let p = TruncatedNormal::new(mean, sd, a, b).unwrap();
        let reference = TailReference::new(mean, sd, a, b);
        for i in 0..=1000 {
            let u = (i as f64 / 1000.0).min(ONE_BELOW);
            let x = p.sample_1d(u);
            assert!(a <= x && x <= b, "[{a}, {b}]: sample({u}) = {x} outside");
            let cdf = reference.cdf(x);
            assert!(
                (cdf - u).abs() < 1e-11,
                "N({mean}, {sd}) on [{a}, {b}]: sample({u}) = {x} has cdf {cdf}"
            );
            assert!(
                (p.invert_1d(x) - cdf).abs() < 1e-11,
                "[{a}, {b}]: invert({x}) = {} vs cdf {cdf}",
                p.invert_1d(x)
            );
            // The density, normalised by a mass near 1e-200, keeps full relative precision.
            // (Not at u = 0 with an infinite end: the quantile there is -inf or the end of a
            // root search, where exp(-z^2/2) underflows although the truncated density does
            // not; that far out it is below e^-290 of its peak, so no sample lands there.)
            if i == 0 && !(a.is_finite() && b.is_finite()) {
                continue;
            }
            let density = reference.pdf(x);
            assert!(
                (p.pdf_1d(x) / density - 1.0).abs() < 1e-10,
                "[{a}, {b}]: pdf({x}) = {} vs {density}",
                p.pdf_1d(x)
            );
        }
    }
}

#[test]
fn narrow_truncated_normals_keep_precision() {
    for width in [1e-6, 1e-9, 1e-12] {
        let p = TruncatedNormal::new(0.0, 1.0, 0.0, width).unwrap();
        // Exact: pdf(0) = phi(0) / (Phi(w) - Phi(0)) = 1 / (w - w^3/6 + O(w^5)).
        let exact = 1.0 / (width - width.powi(3) / 6.0);
        let relative = p.pdf_1d(0.0) / exact - 1.0;
        assert!(
            relative.abs() < 1e-12,
            "width {width}: relative error {relative:e}"
        );
        let total = integrate(|x| p.pdf_1d(x), 0.0, width, 4);
        assert!(
            (total - 1.0).abs() < 1e-12,
            "width {width}: integral {total}"
        );
    }
}

/// A truncated normal's shape on its own interval, for reference: with `t = (x - a) / (b - a)`
/// in `[0, 1]` and `z = (x - mean) / sd`, the density is proportional to
/// `exp(-(z - z0)(z + z0) / 2)`, `z0` the point of the interval nearest the mean, where
/// `z - z0 = (t - t0) w` and `w = (b - a) / sd`. Nothing in it cancels, however narrow the
/// interval, far its tail or large the sd.
struct Shape {
    w: f64,
    t0: f64,
    z0: f64,
    total: f64,
}

/// Quadrature panels on `[0, 1]`: the steepest shape tested falls by about `z0 w` = 500
/// e-folds across it, 8 per panel, which the 12-point rule integrates to far below 1e-15.
const SHAPE_PANELS: usize = 64;

impl Shape {
    fn new(mean: f64, sd: f64, a: f64, b: f64) -> Self {
        let w = (b - a) / sd;
        let (alpha, beta) = ((a - mean) / sd, (b - mean) / sd);
        let (t0, z0) = if alpha >= 0.0 {
            (0.0, alpha)
        } else if beta <= 0.0 {
            (1.0, beta)
        } else {
            ((mean - a) / (b - a), 0.0)
        };
        let mut shape = Shape {
            w,
            t0,
            z0,
            total: 1.0,
        };
        shape.total = shape.integral(1.0);
        shape
    }

    fn scaled(&self, t: f64) -> f64 {
        let d = (t - self.t0) * self.w;
        (-0.5 * d * (2.0 * self.z0 + d)).exp()
    }

    fn integral(&self, t: f64) -> f64 {
        integrate(|s| self.scaled(s), 0.0, t, SHAPE_PANELS)
    }

    fn cdf(&self, t: f64) -> f64 {
        self.integral(t) / self.total
    }
}

/// Truncated normals with the interval placed by what it does to the cdf: tiny compared with
/// an enormous sd (the cdf difference cancels completely), narrow in a far tail, straddling
/// the mean, and ordinary. `(mean, sd, a, b)`; fixed draws, so a run is reproducible.
fn truncated_normal_regimes() -> Vec<(f64, f64, f64, f64)> {
    let mut cases = vec![
        // The two of issue 32: every u gave one end, and invert gave 0.
        (1e-300, 1e308, -2.5e14, -3.3e9),
        (0.0, 1e200, 1.0, 2.0),
        (0.0, 1e3, 0.0, 1.0),
        (0.0, 30.0, 0.0, 1.0),
        (0.0, 1.0, -1e-9, 1e-9),
        (0.0, 1.0, 30.0, 30.0 + 1e-4),
        (0.0, 1.0, 30.0, 30.0 + 1e-3),
        (0.0, 1.0, -30.001, -30.0),
        (5.0, 1.0, 40.0, 40.002),
        (1e6, 1e-3, 1e6 + 0.02, 1e6 + 0.020001),
    ];
    let draws = canonical(7, 600, 0x7e57);
    let mut v = [0.0; 7];
    for i in 0..draws.len() {
        draws.copy_point(i, &mut v);
        let sd = 10f64.powf(-300.0 + 600.0 * v[0]);
        // Widths in sd: from 1e-300, 1e-6 or 0.1 to 10, a third of the draws each.
        let log_w = match (v[6] * 3.0) as usize {
            0 => -300.0 + 301.0 * v[1],
            1 => -6.0 + 7.0 * v[1],
            _ => -1.0 + 2.0 * v[1],
        };
        let w = 10f64.powf(log_w);
        // Where the interval starts, in sd from the mean: central, upper tail, lower tail
        // (placed by its upper end), or within 1e-300..1 of the mean.
        let side = if v[4] < 0.5 { -1.0 } else { 1.0 };
        let alpha = match (v[2] * 4.0) as usize {
            0 => -4.0 + 8.0 * v[3],
            1 => 4.0 + 33.0 * v[3],
            2 => -(4.0 + 33.0 * v[3]) - w,
            _ => side * 10f64.powf(-300.0 + 300.0 * v[3]),
        };
        // The interval's position: at 0, or up to 1e9 widths from it on either side (so that
        // it holds at least 2^20 floats).
        let width = w * sd;
        let a = match (v[4] * 8.0) as usize % 4 {
            0 => 0.0,
            _ => side * width * 10f64.powf(-3.0 + 12.0 * v[5]),
        };
        let b = a + width;
        let mean = a - alpha * sd;
        let floats = (b - a) / (a.abs().max(b.abs()) * f64::EPSILON);
        if mean.is_finite() && b.is_finite() && a < b && floats >= (1u64 << 20) as f64 {
            cases.push((mean, sd, a, b));
        }
    }
    cases
}

#[test]
fn truncated_normals_sample_and_invert_exactly_in_every_regime() {
    // u on a stratified grid: sample(u_i) is the u_i quantile, so the fraction of samples
    // at or below any x is the cdf there to within 1/(2N), plus the samples whose u is
    // within the round-trip error of the cdf.
    const N: usize = 1000;
    let (mut tested, mut refused) = (0, 0);
    for (mean, sd, a, b) in truncated_normal_regimes() {
        let name = format!("N({mean:e}, {sd:e}) on [{a:e}, {b:e}]");
        let Ok(p) = TruncatedNormal::new(mean, sd, a, b) else {
            refused += 1;
            continue;
        };
        tested += 1;
        let shape = Shape::new(mean, sd, a, b);
        let t_of = |x: f64| ((x - a) / (b - a)).clamp(0.0, 1.0);
        let xs: Vec<f64> = (0..N)
            .map(|i| p.sample_1d((i as f64 + 0.5) / N as f64))
            .collect();
        let mut previous = a;
        for (i, &x) in xs.iter().enumerate() {
            let u = (i as f64 + 0.5) / N as f64;
            assert!(
                previous <= x && x <= b,
                "{name}: sample({u}) = {x:e} after {previous:e}"
            );
            previous = x;
            // The round trip: x is a float of relative precision EPSILON, and its position
            // relative to the mean carries the quantile's relative error (7e-16); both move u
            // by the density times that much x. The cdf arithmetic adds a few ulps of u,
            // magnified by at most 1/0.03 where the interval's probability is a difference of
            // tail probabilities.
            let density = p.pdf_1d(x);
            let tolerance = 1e-12 + 8.0 * density * f64::EPSILON * (x.abs() + (x - mean).abs());
            let back = p.invert_1d(x);
            assert!(
                (back - u).abs() <= tolerance,
                "{name}: invert(sample({u}) = {x:e}) = {back}"
            );
            // The density against the shape: exp(-z^2 / 2) carries a relative error of about
            // EPSILON z^2, the normalisation a few ulps.
            let z = (x - mean) / sd;
            let reference = shape.scaled(t_of(x)) / (shape.total * (b - a));
            assert!(
                (density / reference - 1.0).abs() <= 1e-12 + 4.0 * f64::EPSILON * z * z,
                "{name}: pdf({x:e}) = {density:e}, shape says {reference:e}"
            );
        }
        assert!(xs[0] < xs[N - 1], "{name}: every sample is {:e}", xs[0]);
        for j in 1..8 {
            let x = a + (b - a) * j as f64 / 8.0;
            let below = xs.partition_point(|&s| s <= x) as f64 / N as f64;
            let cdf = shape.cdf(t_of(x));
            assert!(
                (below - cdf).abs() <= 1.0 / N as f64 + 1e-9,
                "{name}: {below} of the samples are <= {x:e}, where the cdf is {cdf}"
            );
        }
    }
    // Only intervals without probability in f64 (far tails) are refused.
    assert!(tested >= 300, "{tested} tested, {refused} refused");
}

#[test]
fn truncated_normals_are_scale_invariant() {
    // N(0, s) on [20 s, 21 s] is N(0, 1) on [20, 21] in units of s: samples times s, density
    // over s. At s = 1e-230 the normalisation sd * mass is 2.8e-319, a subnormal with five
    // significant digits, which the density must not divide by. The tolerance allows the
    // rounding of x * s, magnified by z^2 = 441 in exp(-z^2 / 2).
    let unit = TruncatedNormal::new(0.0, 1.0, 20.0, 21.0).unwrap();
    for scale in [1e-230, 1e-200, 1e200] {
        let p = TruncatedNormal::new(0.0, scale, 20.0 * scale, 21.0 * scale).unwrap();
        for u in [0.0, 0.1, 0.5, 0.9, ONE_BELOW] {
            let x = unit.sample_1d(u);
            let sample = p.sample_1d(u) / scale;
            assert!(
                (sample / x - 1.0).abs() < 1e-14,
                "s = {scale:e}: {sample} vs {x}"
            );
            let density = p.pdf_1d(x * scale) * scale;
            assert!(
                (density / unit.pdf_1d(x) - 1.0).abs() < 1e-12,
                "s = {scale:e}: pdf {density} vs {}",
                unit.pdf_1d(x)
            );
        }
    }
}
