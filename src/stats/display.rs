//! How an [`Estimate`] and a [`VectorEstimate`] print with `{}`: the mean, the half-width and
//! bounds of its 95% interval, and what the run spent.

use std::fmt;

use super::estimate::{ErrorBasis, Estimate};
use super::vector_estimate::VectorEstimate;

/// The level of the interval that `{}` shows.
const LEVEL: f64 = 0.95;

/// `mean ± half-width (95% CI [low, high], n evaluations)`, or `mean (no error bar, n
/// evaluations)` without a standard error; a Walsh-bound estimate shows its guaranteed bound.
/// The formatter's precision (`{:.6}`) applies to the mean and the bounds; the half-width
/// keeps two significant digits.
///
/// ```
/// use mcint::{Integrator, pdf::UniformBox};
/// let e = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap())
///     .samples(1 << 16)
///     .seed(1)
///     .run()
///     .unwrap();
/// let text = format!("{e:.4}"); // such as 0.4991 ± 2.2e-3 (95% CI [0.4969, 0.5013], 65536 evaluations)
/// assert!(text.contains(" ± ") && text.contains("(95% CI [0.4"), "{text}");
/// assert!(text.ends_with(", 65536 evaluations)"), "{text}");
/// // Two replicates of 10 points: mean 2, standard error 1, t_{0.975, 1} = 12.706.
/// let two = mcint::Estimate::from_replicates(&[1.0, 3.0], 10).unwrap();
/// assert_eq!(format!("{two:.2}"), "2.00 ± 1.3e1 (95% CI [-10.71, 14.71], 20 evaluations)");
/// let no_bar = mcint::Estimate::from_replicates(&[0.25], 100).unwrap();
/// assert_eq!(no_bar.to_string(), "0.25 (no error bar, 100 evaluations)");
/// ```
impl fmt::Display for Estimate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        number(f, self.mean)?;
        let Some(half) = self.half_width(LEVEL).ok().flatten() else {
            return write!(f, " (no error bar, {} evaluations)", self.evaluations);
        };
        let interval = if self.basis == ErrorBasis::WalshBound {
            "guaranteed bound"
        } else {
            "95% CI"
        };
        write!(f, " ± {half:.1e} ({interval} [")?;
        number(f, self.mean - half)?;
        write!(f, ", ")?;
        number(f, self.mean + half)?;
        write!(f, "], {} evaluations)", self.evaluations)
    }
}

/// One line per output, `output k: ` and the output's [`Estimate`] as `{}` prints it (with
/// the same precision).
///
/// ```
/// use mcint::{Integrator, pdf::UniformBox};
/// let f = |x: &[f64], out: &mut [f64]| { out[0] = x[0]; out[1] = 2.0 * x[0]; };
/// let run = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap()).samples(1000).run().unwrap();
/// let text = format!("{run:.3}");
/// let lines: Vec<&str> = text.lines().collect();
/// assert_eq!(lines.len(), 2);
/// assert!(lines[0].starts_with("output 0: 0.") && lines[1].starts_with("output 1: "), "{text}");
/// assert!(lines.iter().all(|l| l.contains(" ± ") && l.ends_with(", 1000 evaluations)")), "{text}");
/// ```
impl fmt::Display for VectorEstimate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (k, output) in self.outputs.iter().enumerate() {
            if k > 0 {
                writeln!(f)?;
            }
            write!(f, "output {k}: ")?;
            fmt::Display::fmt(output, f)?;
        }
        Ok(())
    }
}

/// `x` with the formatter's precision, if it has one.
fn number(f: &mut fmt::Formatter<'_>, x: f64) -> fmt::Result {
    match f.precision() {
        Some(digits) => write!(f, "{x:.digits$}"),
        None => write!(f, "{x}"),
    }
}
