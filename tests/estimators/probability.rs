//! The probability identities of Jarosz's section A.1.3 (A.6-A.10), checked exactly on
//! random discrete distributions. These are the facts the estimators' proofs (A.15, A.20,
//! A.21) rest on.

use crate::common::config;
use proptest::prelude::*;

/// A discrete distribution: values with probabilities summing to one.
#[derive(Debug, Clone)]
struct Discrete {
    values: Vec<f64>,
    probs: Vec<f64>,
}

impl Discrete {
    fn mean(&self) -> f64 {
        self.values
            .iter()
            .zip(&self.probs)
            .map(|(v, p)| v * p)
            .sum()
    }

    /// Variance by its definition A.5, `E[(Y - E[Y])^2]`.
    fn variance(&self) -> f64 {
        let m = self.mean();
        self.values
            .iter()
            .zip(&self.probs)
            .map(|(v, p)| (v - m) * (v - m) * p)
            .sum()
    }

    fn map(&self, f: impl Fn(f64) -> f64) -> Discrete {
        Discrete {
            values: self.values.iter().map(|&v| f(v)).collect(),
            probs: self.probs.clone(),
        }
    }
}

fn normalized(weights: Vec<f64>) -> Vec<f64> {
    let total: f64 = weights.iter().sum();
    weights.into_iter().map(|w| w / total).collect()
}

fn discrete() -> impl Strategy<Value = Discrete> {
    (1usize..12).prop_flat_map(|k| {
        (
            prop::collection::vec(-10.0..10.0f64, k),
            prop::collection::vec(0.01..1.0f64, k),
        )
            .prop_map(|(values, weights)| Discrete {
                values,
                probs: normalized(weights),
            })
    })
}

/// A joint distribution of two variables as a table of probabilities.
fn joint() -> impl Strategy<Value = (Vec<f64>, Vec<f64>, Vec<Vec<f64>>)> {
    (1usize..6, 1usize..6).prop_flat_map(|(m, n)| {
        (
            prop::collection::vec(-5.0..5.0f64, m),
            prop::collection::vec(-5.0..5.0f64, n),
            prop::collection::vec(0.01..1.0f64, m * n),
        )
            .prop_map(move |(y1, y2, w)| {
                let w = normalized(w);
                let table = w.chunks(n).map(|row| row.to_vec()).collect();
                (y1, y2, table)
            })
    })
}

/// Relative closeness for quantities computed by different but exact formulas.
fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 1e-12 * scale.max(1.0)
}

proptest! {
    #![proptest_config(config(256, 0x0a06))]

    /// A.6 and A.7: E[aY] = a E[Y], sigma^2[aY] = a^2 sigma^2[Y].
    #[test]
    fn scaling(y in discrete(), a in -20.0..20.0f64) {
        let ay = y.map(|v| a * v);
        prop_assert!(close(ay.mean(), a * y.mean(), 200.0));
        prop_assert!(close(ay.variance(), a * a * y.variance(), 4e4));
    }

    /// A.9: sigma^2[Y] = E[Y^2] - E[Y]^2.
    #[test]
    fn variance_shortcut(y in discrete()) {
        let second = y.map(|v| v * v).mean();
        prop_assert!(close(y.variance(), second - y.mean() * y.mean(), 100.0));
    }

    /// A.8 holds for any joint distribution, dependent or not; A.10 holds when the variables
    /// are independent (the table is the product of its marginals).
    #[test]
    fn sums((y1, y2, table) in joint()) {
        let marginal1: Vec<f64> = table.iter().map(|row| row.iter().sum()).collect();
        let marginal2: Vec<f64> = (0..y2.len()).map(|j| table.iter().map(|row| row[j]).sum()).collect();
        let d1 = Discrete { values: y1.clone(), probs: marginal1.clone() };
        let d2 = Discrete { values: y2.clone(), probs: marginal2.clone() };
        let sum_of = |table: &Vec<Vec<f64>>| {
            let mut values = Vec::new();
            let mut probs = Vec::new();
            for (i, row) in table.iter().enumerate() {
                for (j, &p) in row.iter().enumerate() {
                    values.push(y1[i] + y2[j]);
                    probs.push(p);
                }
            }
            Discrete { values, probs }
        };
        prop_assert!(close(sum_of(&table).mean(), d1.mean() + d2.mean(), 10.0));

        let independent: Vec<Vec<f64>> =
            marginal1.iter().map(|p| marginal2.iter().map(|q| p * q).collect()).collect();
        prop_assert!(close(sum_of(&independent).variance(), d1.variance() + d2.variance(), 100.0));
    }
}

/// A.10's footnote: being uncorrelated suffices. Y1 uniform on {-1, 0, 1} and Y2 = Y1^2 are
/// dependent but uncorrelated, and the variance of the sum is the sum of the variances; for
/// the correlated pair (Y1, Y1) it is not (the identity is not vacuous).
#[test]
fn uncorrelated_suffices_for_a10() {
    let y1 = Discrete {
        values: vec![-1.0, 0.0, 1.0],
        probs: vec![1.0 / 3.0; 3],
    };
    let y2 = y1.map(|v| v * v);
    let sum = y1.map(|v| v + v * v);
    assert!(close(sum.variance(), y1.variance() + y2.variance(), 1.0));
    let doubled = y1.map(|v| 2.0 * v);
    assert!(!close(doubled.variance(), 2.0 * y1.variance(), 1.0));
}
