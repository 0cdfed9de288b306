//! A small globally adaptive Gauss-Kronrod (G7/K15) quadrature for smooth 1-D integrals.
//!
//! Used where a value reduces to a one-dimensional integral without a cancellation-free
//! closed form: the Genz (1984) corner-peak integral (see `testfns/genz.rs`) and the mass of
//! narrow truncated-normal intervals (see `pdf/truncated_normal.rs`). It is deliberately
//! minimal: a finite interval, a smooth integrand, and a tolerance near machine precision.

/// Abscissae of the 15-point Kronrod rule on `[-1, 1]`, largest first; the odd positions
/// (1, 3, 5) and the centre (7) are the nodes of the embedded 7-point Gauss rule.
const KRONROD_NODES: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];

/// Weights of the 15-point Kronrod rule, matching [`KRONROD_NODES`].
const KRONROD_WEIGHTS: [f64; 8] = [
    0.022_935_322_010_529_225,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_18,
    0.140_653_259_715_525_92,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_727_83,
];

/// Weights of the 7-point Gauss rule at `KRONROD_NODES[1]`, `[3]`, `[5]` and `[7]` (the centre).
const GAUSS_WEIGHTS: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// The result of [`gauss_kronrod`]: the integral and an (intentionally pessimistic) bound on
/// its error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Estimate {
    /// The Kronrod estimate of the integral.
    pub value: f64,
    /// The sum over subintervals of `|K15 - G7|`. This is roughly the error of the Gauss
    /// rule, so the Kronrod value is usually far more accurate than this bound says.
    pub error: f64,
}

/// One subinterval with its K15 value and `|K15 - G7|`.
#[derive(Debug, Clone, Copy)]
struct Panel {
    lo: f64,
    hi: f64,
    value: f64,
    error: f64,
}

/// Applies the G7/K15 pair on `[lo, hi]`.
fn panel<F: FnMut(f64) -> f64>(f: &mut F, lo: f64, hi: f64) -> Panel {
    let centre = 0.5 * (lo + hi);
    let half = 0.5 * (hi - lo);
    let f0 = f(centre);
    let mut kronrod = KRONROD_WEIGHTS[7] * f0;
    let mut gauss = GAUSS_WEIGHTS[3] * f0;
    for j in 0..7 {
        let dx = half * KRONROD_NODES[j];
        let pair = f(centre - dx) + f(centre + dx);
        kronrod += KRONROD_WEIGHTS[j] * pair;
        // The Gauss nodes are the odd-indexed Kronrod nodes.
        if j % 2 == 1 {
            gauss += GAUSS_WEIGHTS[j / 2] * pair;
        }
    }
    Panel {
        lo,
        hi,
        value: kronrod * half,
        error: ((kronrod - gauss) * half).abs(),
    }
}

/// Integrates `f` over `[breaks[0], breaks[last]]` by globally adaptive bisection.
///
/// `breaks` must be increasing; each gap starts as one panel, so points where `f` changes
/// character (a peak, a change of scale) should be listed. The panel with the largest
/// `|K15 - G7|` is then halved until the summed difference is at most
/// `max(abs_tol, rel_tol * |integral|)`, until `max_panels` panels are in use, or until the
/// worst panel can no longer be halved in floating point. The integrand is never evaluated
/// at a breakpoint. `f` may return `0.0` where it underflows; it should not return NaN.
/// Fewer than two breakpoints give an integral of zero.
pub(crate) fn gauss_kronrod<F: FnMut(f64) -> f64>(
    mut f: F,
    breaks: &[f64],
    rel_tol: f64,
    abs_tol: f64,
    max_panels: usize,
) -> Estimate {
    let mut panels: Vec<Panel> = breaks
        .windows(2)
        .map(|w| (w[0], w[1]))
        .filter(|(lo, hi)| lo < hi)
        .map(|(lo, hi)| panel(&mut f, lo, hi))
        .collect();
    loop {
        // Summing afresh each pass avoids drift from repeated subtraction; n stays small.
        let value: f64 = panels.iter().map(|p| p.value).sum();
        let error: f64 = panels.iter().map(|p| p.error).sum();
        let done = error <= abs_tol.max(rel_tol * value.abs()) || panels.len() >= max_panels;
        let worst = panels
            .iter()
            .enumerate()
            .max_by(|x, y| x.1.error.total_cmp(&y.1.error))
            .map(|(i, p)| (i, *p));
        let Some((index, worst)) = worst.filter(|_| !done) else {
            return Estimate { value, error };
        };
        let mid = 0.5 * (worst.lo + worst.hi);
        if !(worst.lo < mid && mid < worst.hi) {
            // Floating point cannot split further: this is as good as it gets.
            return Estimate { value, error };
        }
        panels[index] = panel(&mut f, worst.lo, mid);
        panels.push(panel(&mut f, mid, worst.hi));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The constants must make K15 exact for degree <= 22 and G7 exact for degree <= 13;
    /// a wrong digit anywhere would show up here.
    #[test]
    fn rules_are_exact_on_monomials() {
        for k in 0..=22_i32 {
            let exact = if k % 2 == 0 {
                2.0 / f64::from(k + 1)
            } else {
                0.0
            };
            let mut kr = KRONROD_WEIGHTS[7] * 0f64.powi(k);
            let mut ga = GAUSS_WEIGHTS[3] * 0f64.powi(k);
            for j in 0..7 {
                let x = KRONROD_NODES[j];
                let pair = x.powi(k) + (-x).powi(k);
                kr += KRONROD_WEIGHTS[j] * pair;
                if j % 2 == 1 {
                    ga += GAUSS_WEIGHTS[j / 2] * pair;
                }
            }
            assert!(
                (kr - exact).abs() < 4e-16,
                "K15 degree {k}: {kr} vs {exact}"
            );
            if k <= 13 {
                assert!((ga - exact).abs() < 4e-16, "G7 degree {k}: {ga} vs {exact}");
            }
        }
    }

    #[test]
    fn adaptive_handles_a_sharp_peak() {
        // ∫_0^1 1/(1e-6 + (x - 0.3)^2) dx = 1e3 (atan(700) + atan(300)).
        let est = gauss_kronrod(
            |x| 1.0 / (1e-6 + (x - 0.3) * (x - 0.3)),
            &[0.0, 1.0],
            1e-14,
            0.0,
            500,
        );
        let exact = 1e3 * (700f64.atan() + 300f64.atan());
        assert!(
            (est.value - exact).abs() <= 1e-13 * exact,
            "{} vs {exact}",
            est.value
        );
    }

    #[test]
    fn breakpoints_resolve_a_kink() {
        let est = gauss_kronrod(|x| (x - 0.3).abs(), &[0.0, 0.3, 1.0], 1e-15, 0.0, 10);
        assert!((est.value - 0.29).abs() < 1e-15 && est.error < 1e-15);
        assert_eq!(gauss_kronrod(|x| x, &[1.0], 0.0, 0.0, 10).value, 0.0);
    }

    #[test]
    fn stops_on_panel_budget() {
        let est = gauss_kronrod(|x| x.sqrt(), &[0.0, 1.0], 0.0, 0.0, 40);
        assert!((est.value - 2.0 / 3.0).abs() < 1e-8);
        assert!(est.error > 0.0);
    }
}
