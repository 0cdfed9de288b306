//! The units VEGAS sums each output's values in: a power of two near the values when they are
//! far from 1, so that their squares (in the variances, the covariances and the grid's
//! training data) neither overflow nor underflow. Dividing by a power of two is exact, so a
//! run of `2^k f` is the run of `f` with its results times `2^k`.
//!
//! The units are chosen from the first iteration: its largest `|f_k|` and the domain's volume
//! (the Jacobian of the first, uniform grid) give the magnitude of `J f_k`. When one is
//! beyond [`UNSCALED_EXPONENT`], the iteration is run again, on the same points, in units
//! near it (its evaluations counted); otherwise the units stay 1 and nothing changes.

/// Magnitudes `J f` within `2^±256` (about `1e±77`) are summed as they are: their squares,
/// summed over up to `2^40` points, stay far from overflow, and the variances of the
/// iterations far above the floor that keeps exact iterations from dividing by zero.
const UNSCALED_EXPONENT: i32 = 256;

/// Each output's unit and its inverse (all 1 unless a first iteration called for others).
#[derive(Clone, Debug)]
pub(super) struct Units {
    units: Vec<f64>,
    inverses: Vec<f64>,
}

impl Units {
    /// Units of 1 for `m` outputs.
    pub(super) fn one(m: usize) -> Units {
        Units {
            units: vec![1.0; m],
            inverses: vec![1.0; m],
        }
    }

    /// The units for outputs whose largest finite `|f_k|` over the first iteration is
    /// `largest[k]`, over a domain of volume `volume`; `None` when every one is within
    /// [`UNSCALED_EXPONENT`] (or zero, or never finite).
    pub(super) fn needed(largest: &[f64], volume: f64) -> Option<Units> {
        let exponents: Vec<i32> = largest
            .iter()
            .map(|&value| {
                if value > 0.0 && value.is_finite() {
                    // Logarithms added, not values multiplied: their product may not be a
                    // double. The floor is deterministic; any nearby power of two serves.
                    let exponent = (value.log2() + volume.log2()).floor();
                    exponent.clamp(-1000.0, 1000.0) as i32
                } else {
                    0
                }
            })
            .collect();
        if exponents.iter().all(|e| e.abs() <= UNSCALED_EXPONENT) {
            return None;
        }
        let exponents = exponents
            .iter()
            .map(|&e| if e.abs() <= UNSCALED_EXPONENT { 0 } else { e });
        Some(Units {
            units: exponents.clone().map(|e| 2f64.powi(e)).collect(),
            inverses: exponents.map(|e| 2f64.powi(-e)).collect(),
        })
    }

    /// What each output's values are multiplied by before they are summed.
    pub(super) fn inverses(&self) -> &[f64] {
        &self.inverses
    }

    /// Output `k`'s unit: what its sums are multiplied by to give results.
    pub(super) fn of(&self, k: usize) -> f64 {
        self.units[k]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ordinary magnitudes keep units of 1; far ones get a power of two near `|J f|`, each
    /// output its own, with an exact inverse.
    #[test]
    fn only_far_magnitudes_get_units() {
        assert!(Units::needed(&[1.0, 1e70, 0.0, f64::NAN], 1.0).is_none());
        assert!(Units::needed(&[1e70], 1e10).is_some());
        let units = Units::needed(&[3.0 * 2f64.powi(400), 1.0, 2f64.powi(-700)], 0.5).unwrap();
        assert_eq!(units.of(0), 2f64.powi(400));
        assert_eq!(units.of(1), 1.0);
        assert_eq!(units.of(2), 2f64.powi(-701));
        for k in 0..3 {
            assert_eq!(units.of(k) * units.inverses()[k], 1.0);
        }
        // Values near the largest double over a tiny domain: their product is ordinary.
        assert!(Units::needed(&[1e300], 1e-300).is_none());
    }
}
