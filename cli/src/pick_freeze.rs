//! First-order and total Sobol' indices as smooth functions of the integrals of one vector
//! integrand: the pick-freeze (radial) design of Saltelli et al. (2010), "Variance based
//! sensitivity analysis of model output. Design and estimator for the total sensitivity
//! index", Comput. Phys. Commun. 181, 259-270.
//!
//! One point `u` of `[0,1)^{2d}` gives two independent inputs `A = u[0..d]` and
//! `B = u[d..2d]`, and for each input `i` the mixed point `AB_i`: `A` with coordinate `i`
//! taken from `B`. Per point the model runs `d + 2` times (`f(A)`, `f(B)`, every `f(AB_i)`),
//! and the integrand returns, as means over the same points:
//!
//! | output        | integrand                   | its mean                                  |
//! |---------------|-----------------------------|-------------------------------------------|
//! | 0, 1          | `f(A)`, `f(B)`              | `f0`                                      |
//! | 2, 3          | `f(A)^2`, `f(B)^2`          | `V + f0^2`                                |
//! | 4 + i         | `f(B) (f(AB_i) - f(A))`     | `V_i`, first-order (Saltelli et al. 2010) |
//! | 4 + d + i     | `(f(A) - f(AB_i))^2 / 2`    | `V_Ti`, total (Jansen 1999)               |
//!
//! Both are the estimators Saltelli et al. (2010) recommend; M. J. W. Jansen, "Analysis of
//! variance designs for model output", Comput. Phys. Commun. 117 (1999), 35-43.
//!
//! `f(B)` and `f(AB_i)` share only `x_i`, so `E[f(B) f(AB_i)] = E[E[Y|x_i]^2] = V_i + f0^2`,
//! while `f(B)` and `f(A)` are independent; `f(A)` and `f(AB_i)` share all but `x_i`, so half
//! their mean squared difference is `E[Var(Y|x_~i)]`, the total partial variance `V_Ti`.
//! Both numerators are unbiased; `S_i = V_i / V` and `ST_i = V_Ti / V` are ratios of means, so
//! the delta method gives their standard errors from the covariance of the outputs.

use mcint::estimator::MAX_OUTPUTS;
use mcint::stats::Derived;

/// Outputs before the per-input ones: the means and mean squares of `f(A)` and `f(B)`.
const MOMENTS: usize = 4;

/// The most inputs whose `4 + 2d` outputs fit in one vector run.
pub const MAX_INPUTS: usize = (MAX_OUTPUTS - MOMENTS) / 2;

/// The design for a model of `inputs` inputs.
#[derive(Clone, Copy)]
pub struct PickFreeze {
    pub inputs: usize,
}

impl PickFreeze {
    /// Dimensions of the canonical points: `A` and `B` side by side.
    pub fn point_dims(self) -> usize {
        2 * self.inputs
    }

    /// Outputs of the vector integrand.
    pub fn outputs(self) -> usize {
        MOMENTS + 2 * self.inputs
    }

    /// Model evaluations per point.
    pub fn model_runs_per_point(self) -> u64 {
        self.inputs as u64 + 2
    }

    /// The vector integrand over `[0,1)^{2d}` of a model `f` on `[0,1)^d` (the table above).
    pub fn integrand(
        self,
        f: impl Fn(&[f64]) -> f64 + Send + Sync,
    ) -> impl Fn(&[f64], &mut [f64]) + Send + Sync {
        let d = self.inputs;
        move |u: &[f64], out: &mut [f64]| {
            let (a, b) = u.split_at(d);
            let (fa, fb) = (f(a), f(b));
            out[..MOMENTS].copy_from_slice(&[fa, fb, fa * fa, fb * fb]);
            let mut ab = a.to_vec();
            for i in 0..d {
                ab[i] = b[i];
                let fab = f(&ab);
                ab[i] = a[i];
                out[MOMENTS + i] = fb * (fab - fa);
                out[MOMENTS + d + i] = 0.5 * (fa - fab) * (fa - fab);
            }
        }
    }

    /// `V = Var f`, from `A` and `B` alike: `(E f(A)^2 + E f(B)^2)/2 - ((E f(A) + E f(B))/2)^2`.
    pub fn variance(self) -> Derived {
        Derived::smooth_with_gradient(variance, |m: &[f64], grad: &mut [f64]| {
            grad.fill(0.0);
            variance_gradient(m, grad);
        })
    }

    /// The first-order index `S_i = V_i / V`.
    pub fn first_order(self, i: usize) -> Derived {
        over_variance(MOMENTS + i)
    }

    /// The total index `ST_i = V_Ti / V`.
    pub fn total(self, i: usize) -> Derived {
        over_variance(MOMENTS + self.inputs + i)
    }
}

fn variance(m: &[f64]) -> f64 {
    let mean = 0.5 * (m[0] + m[1]);
    0.5 * (m[2] + m[3]) - mean * mean
}

/// Adds the gradient of [`variance`] to `grad[0..4]`.
fn variance_gradient(m: &[f64], grad: &mut [f64]) {
    let mean = 0.5 * (m[0] + m[1]);
    grad[0] -= mean;
    grad[1] -= mean;
    grad[2] += 0.5;
    grad[3] += 0.5;
}

/// `m[k] / V`, with the quotient rule for its gradient.
fn over_variance(k: usize) -> Derived {
    Derived::smooth_with_gradient(
        move |m: &[f64]| m[k] / variance(m),
        move |m: &[f64], grad: &mut [f64]| {
            let v = variance(m);
            grad.fill(0.0);
            variance_gradient(m, grad);
            for g in &mut grad[..MOMENTS] {
                *g *= -m[k] / (v * v);
            }
            grad[k] = 1.0 / v;
        },
    )
}
