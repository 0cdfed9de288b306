//! Where each integral of the pick-freeze design sits among the outputs of the vector run,
//! and the indices as smooth functions of those integrals.
//!
//! For model output `o`, a block of outputs holds, as means over the same points, with `f`
//! the model's output less a constant (its value at the centre of the cube: without it, the
//! mean of squares of a model far from 0 cancels against its squared mean) and `f0` the mean
//! of that `f`; the other means do not depend on the constant:
//!
//! | position in the block   | integrand                           | its mean                    |
//! |-------------------------|-------------------------------------|-----------------------------|
//! | 0, 1                    | `f(A)`, `f(B)`                      | `f0`                        |
//! | 2, 3                    | `f(A)^2`, `f(B)^2`                  | `V + f0^2`                  |
//! | 4 + j                   | `f(B) (f(AB_j) - f(A))`             | `V_j` (Saltelli et al. 2010)|
//! | 4 + F + j               | `(f(A) - f(AB_j))^2 / 2`            | `V_Tj` (Jansen 1999)        |
//! | 4 + 2F + pair(j, k)     | `f(BA_j) f(AB_k) - f(A) f(B)`       | `V_j + V_k + V_jk`          |
//!
//! for the `F` factors `j` (an input or a group of inputs); the last rows only when second
//! order indices are asked for.

use crate::error::{Error, Result};
use crate::estimator::MAX_OUTPUTS;
use crate::stats::Derived;

/// Outputs of a block before the per-factor ones: the means and mean squares of `f(A)`, `f(B)`.
const MOMENTS: usize = 4;

/// The outputs of the design's vector run for `model_outputs` model outputs and `factors`
/// factors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Layout {
    pub factors: usize,
    pub model_outputs: usize,
    pub second_order: bool,
}

impl Layout {
    /// The layout, or an error when its outputs do not fit in one vector run.
    pub fn new(factors: usize, model_outputs: usize, second_order: bool) -> Result<Layout> {
        let layout = Layout {
            factors,
            model_outputs,
            second_order,
        };
        if model_outputs == 0 {
            return Err(Error::invalid(
                "model outputs",
                0,
                "at least 1 output of the model",
            ));
        }
        let outputs = layout.block().saturating_mul(model_outputs);
        if outputs > MAX_OUTPUTS {
            return Err(Error::invalid(
                "factors",
                format!(
                    "{factors} factors x {model_outputs} model outputs{} ({outputs} integrals)",
                    if second_order {
                        " with second order"
                    } else {
                        ""
                    }
                ),
                format!(
                    "at most {MAX_OUTPUTS} integrals in one run (MAX_OUTPUTS): each model output \
                     needs 4 + 2 F of them, plus F (F - 1) / 2 for second order; group inputs, \
                     or analyse fewer outputs at a time"
                ),
            ));
        }
        Ok(layout)
    }

    /// Outputs per model output.
    pub fn block(self) -> usize {
        let f = self.factors;
        let pairs = if self.second_order {
            f * f.saturating_sub(1) / 2
        } else {
            0
        };
        MOMENTS + 2 * f + pairs
    }

    /// Outputs of the vector run.
    pub fn outputs(self) -> usize {
        self.block() * self.model_outputs
    }

    fn start(self, output: usize) -> usize {
        output * self.block()
    }

    /// The output of `f(A)`; `f(B)`, `f(A)^2`, `f(B)^2` follow it.
    pub fn moments(self, output: usize) -> usize {
        self.start(output)
    }

    /// The output whose mean is the first-order partial variance of factor `j`.
    pub fn first(self, output: usize, j: usize) -> usize {
        self.start(output) + MOMENTS + j
    }

    /// The output whose mean is the total partial variance of factor `j`.
    pub fn total(self, output: usize, j: usize) -> usize {
        self.start(output) + MOMENTS + self.factors + j
    }

    /// The output whose mean is the closed second-order variance of factors `j < k`.
    pub fn pair(self, output: usize, j: usize, k: usize) -> usize {
        debug_assert!(j < k && k < self.factors);
        let before = j * (2 * self.factors - j - 1) / 2;
        self.start(output) + MOMENTS + 2 * self.factors + before + (k - j - 1)
    }

    /// `Var f_o`, from `A` and `B` alike.
    pub fn variance(self, output: usize) -> Derived {
        self.over_variance(output, Vec::new(), false)
    }

    /// `S_j = V_j / V`.
    pub fn first_order(self, output: usize, j: usize) -> Derived {
        self.over_variance(output, vec![(self.first(output, j), 1.0)], true)
    }

    /// `ST_j = V_Tj / V`.
    pub fn total_order(self, output: usize, j: usize) -> Derived {
        self.over_variance(output, vec![(self.total(output, j), 1.0)], true)
    }

    /// `S_jk = (V^c_jk - V_j - V_k) / V`, the second-order index as SALib defines it.
    pub fn second_order(self, output: usize, j: usize, k: usize) -> Derived {
        let terms = vec![
            (self.pair(output, j, k), 1.0),
            (self.first(output, j), -1.0),
            (self.first(output, k), -1.0),
        ];
        self.over_variance(output, terms, true)
    }

    /// `sum c_k I_k / V` when `divide`, else `V` itself; with its gradient.
    fn over_variance(self, output: usize, terms: Vec<(usize, f64)>, divide: bool) -> Derived {
        let m0 = self.moments(output);
        let value_terms = terms.clone();
        let value = move |m: &[f64]| {
            let v = variance(&m[m0..m0 + MOMENTS]);
            if divide {
                numerator(&value_terms, m) / v
            } else {
                v
            }
        };
        let gradient = move |m: &[f64], grad: &mut [f64]| {
            grad.fill(0.0);
            let moments = &m[m0..m0 + MOMENTS];
            variance_gradient(moments, &mut grad[m0..m0 + MOMENTS]);
            if divide {
                let v = variance(moments);
                let num = numerator(&terms, m);
                for g in &mut grad[m0..m0 + MOMENTS] {
                    *g *= -num / (v * v);
                }
                for &(k, c) in &terms {
                    grad[k] += c / v;
                }
            }
        };
        Derived::smooth_with_gradient(value, gradient)
    }
}

fn numerator(terms: &[(usize, f64)], m: &[f64]) -> f64 {
    terms.iter().map(|&(k, c)| c * m[k]).sum()
}

/// `(E f(A)^2 + E f(B)^2)/2 - ((E f(A) + E f(B))/2)^2`.
fn variance(moments: &[f64]) -> f64 {
    let mean = 0.5 * (moments[0] + moments[1]);
    0.5 * (moments[2] + moments[3]) - mean * mean
}

/// The gradient of [`variance`] with respect to the four moments.
fn variance_gradient(moments: &[f64], grad: &mut [f64]) {
    let mean = 0.5 * (moments[0] + moments[1]);
    grad.copy_from_slice(&[-mean, -mean, 0.5, 0.5]);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_integral_has_its_own_output() {
        let layout = Layout::new(4, 2, true).unwrap();
        let mut seen = Vec::new();
        for o in 0..2 {
            seen.extend(o * layout.block()..o * layout.block() + MOMENTS);
            for j in 0..4 {
                seen.push(layout.first(o, j));
                seen.push(layout.total(o, j));
                for k in j + 1..4 {
                    seen.push(layout.pair(o, j, k));
                }
            }
        }
        seen.sort_unstable();
        assert_eq!(seen, (0..layout.outputs()).collect::<Vec<_>>());
    }

    #[test]
    fn too_many_integrals_are_refused_with_the_limit() {
        let err = Layout::new(30, 1, true).unwrap_err().to_string();
        assert!(err.contains("MAX_OUTPUTS"), "{err}");
        assert!(Layout::new(126, 1, false).is_ok());
        assert!(Layout::new(127, 1, false).is_err());
        assert!(Layout::new(3, 0, false).is_err());
    }
}
