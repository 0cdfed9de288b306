//! Can one Sobol' sequence give Sobol' indices an error bar? The study behind the Walsh-bound
//! entry of `docs/measurements.md` (issue 35): the pick-freeze integrals of Ishigami or a
//! g-function on one LMS-scrambled Sobol' sequence of `2^M` points, each integral's cone-based
//! Walsh bound from [`SobolG`] on the very same points, and two intervals for every index:
//!
//! - `separate`: interval arithmetic on the bounds of the numerator and of the variance;
//! - `linear`: the Walsh bound of the index's linearization
//!   `(n_i - S v_i) / V` (`v_i` the point's contribution to the variance), a second pass over
//!   the same points once `S` and `V` are known.
//!
//! It prints, per index, how many seeds each interval covers and its median half-width over
//! the median actual error, and the quantiles of actual error over the linear bound.
//!
//! ```text
//! cargo run --release --example sensitivity_walsh_study -- MODEL M SEEDS
//! ```
//! `MODEL` is `ishigami` (`a = 7`, `b = 0.1`) or `sobol-g` (weights `0, 1, 4.5`).

use mcint::adaptive::SobolG;
use mcint::pdf::UniformBox;
use mcint::testfns::{Ishigami, SobolGFunction, TestFunction};
use std::f64::consts::PI;
use std::process::ExitCode;

const USAGE: &str =
    "usage: sensitivity_walsh_study ishigami|sobol-g M SEEDS (2^M points, M 8 to 20)";
/// Inputs of both models.
const D: usize = 3;
/// Integrals per point: the means and mean squares of `f(A)`, `f(B)`, then Saltelli's
/// first-order and Jansen's total numerators per input.
const INTEGRALS: usize = 4 + 2 * D;

/// A model on `[0,1)^D`.
type Model = Box<dyn Fn(&[f64]) -> f64 + Sync>;

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [model, m, seeds] = args.as_slice() else {
        return Err(USAGE.into());
    };
    let m: u32 = m.parse().map_err(|_| USAGE)?;
    let seeds: u64 = seeds.parse().map_err(|_| USAGE)?;
    if !(8..=20).contains(&m) || seeds == 0 {
        return Err(USAGE.into());
    }
    let (f, first, total): (Model, Vec<f64>, Vec<f64>) = match model.as_str() {
        "ishigami" => {
            let ishigami = Ishigami::new(7.0, 0.1).map_err(|e| e.to_string())?;
            let exact = ishigami.exact_indices();
            let f = move |u: &[f64]| {
                let x: [f64; D] = std::array::from_fn(|i| PI * (2.0 * u[i] - 1.0));
                ishigami.eval(&x)
            };
            (Box::new(f), exact.first_order, exact.total)
        }
        "sobol-g" => {
            let g = SobolGFunction::new(vec![0.0, 1.0, 4.5]).map_err(|e| e.to_string())?;
            let exact = g.exact_indices();
            (
                Box::new(move |u: &[f64]| g.eval(u)),
                exact.first_order,
                exact.total,
            )
        }
        _ => return Err(USAGE.into()),
    };
    let exact: Vec<f64> = first.into_iter().chain(total).collect();
    let mut covered = [[0u32; 2 * D]; 2];
    let mut widths = vec![[Vec::new(), Vec::new()]; 2 * D];
    let mut errors = vec![Vec::new(); 2 * D];
    let mut ratios = Vec::new();
    for seed in 0..seeds {
        let integral = |g: &(dyn Fn(&[f64]) -> f64 + Sync)| {
            let e = SobolG::new(g, UniformBox::unit(2 * D).map_err(|e| e.to_string())?)
                .samples(1 << m)
                .seed(seed)
                .threads(1)
                .run()
                .map_err(|e| e.to_string())?;
            Ok::<_, String>((e.mean, e.error_bound.unwrap_or(f64::NAN)))
        };
        let pass: Vec<(f64, f64)> = (0..INTEGRALS)
            .map(|k| integral(&|u: &[f64]| design_integrals(&f, u)[k]))
            .collect::<Result<_, _>>()?;
        let (mean, bound): (Vec<f64>, Vec<f64>) = pass.into_iter().unzip();
        let m1 = 0.5 * (mean[0] + mean[1]);
        let variance = 0.5 * (mean[2] + mean[3]) - m1 * m1;
        let e1 = 0.5 * (bound[0] + bound[1]);
        let variance_bound = 0.5 * (bound[2] + bound[3]) + 2.0 * m1.abs() * e1 + e1 * e1;
        for idx in 0..2 * D {
            let k = 4 + idx;
            let index = mean[k] / variance;
            let error = (index - exact[idx]).abs();
            let hi = (mean[k] + bound[k]) / (variance - variance_bound).max(f64::MIN_POSITIVE);
            let lo = (mean[k] - bound[k]) / (variance + variance_bound);
            let (_, linear) = integral(&|u: &[f64]| {
                let v = design_integrals(&f, u);
                let contribution = 0.5 * (v[2] + v[3]) - m1 * (v[0] + v[1]);
                (v[k] - index * contribution) / variance
            })?;
            covered[0][idx] += u32::from(lo <= exact[idx] && exact[idx] <= hi);
            covered[1][idx] += u32::from(error <= linear);
            widths[idx][0].push(0.5 * (hi - lo));
            widths[idx][1].push(linear);
            errors[idx].push(error);
            ratios.push(error / linear);
        }
    }
    println!("{model}, 2^{m} points (x5 model runs), seeds 0..{seeds}");
    for idx in 0..2 * D {
        let kind = if idx < D { "S" } else { "ST" };
        let median_error = median(&mut errors[idx]);
        let rms = (errors[idx].iter().map(|e| e * e).sum::<f64>() / seeds as f64).sqrt();
        println!(
            "{kind}{}: covered separate {}/{seeds}, linear {}/{seeds}; median half-width / \
             median error: separate {:.1}, linear {:.1}; RMS error {rms:.2e}, median {median_error:.2e}",
            idx % D,
            covered[0][idx],
            covered[1][idx],
            median(&mut widths[idx][0]) / median_error,
            median(&mut widths[idx][1]) / median_error,
        );
    }
    ratios.sort_by(f64::total_cmp);
    let quantile = |p: f64| ratios[((ratios.len() as f64 * p) as usize).min(ratios.len() - 1)];
    println!(
        "error / linear bound, every index: 50% {:.3}, 80% {:.3}, 90% {:.3}, 93% {:.3}, 95% {:.3}, 99% {:.3}",
        quantile(0.5),
        quantile(0.8),
        quantile(0.9),
        quantile(0.93),
        quantile(0.95),
        quantile(0.99)
    );
    Ok(())
}

/// The design's integrals at one point `u` of `[0,1)^(2D)`: `A = u[..D]`, `B = u[D..]`.
fn design_integrals(f: &dyn Fn(&[f64]) -> f64, u: &[f64]) -> [f64; INTEGRALS] {
    let (a, b) = u.split_at(D);
    let (fa, fb) = (f(a), f(b));
    let mut out = [0.0; INTEGRALS];
    out[..4].copy_from_slice(&[fa, fb, fa * fa, fb * fb]);
    let mut mixed = [0.0; D];
    for j in 0..D {
        mixed.copy_from_slice(a);
        mixed[j] = b[j];
        let fab = f(&mixed);
        out[4 + j] = fb * (fab - fa);
        out[4 + D + j] = 0.5 * (fa - fab) * (fa - fab);
    }
    out
}

fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}
