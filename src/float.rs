//! Floating-point constants shared by every layer.

/// The largest `f64` below one, `1 - 2^-53`: the top of the canonical range `[0, 1)`.
/// Samplers clamp coordinates to it so that rounding in `(stratum + jitter) / strata` never
/// produces 1.0, and warps clamp canonical inputs to it so that a table lookup cannot leave
/// the table.
pub(crate) const ONE_BELOW: f64 = 1.0 - f64::EPSILON / 2.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_below_is_the_double_just_below_one() {
        const { assert!(ONE_BELOW < 1.0 && ONE_BELOW + f64::EPSILON / 2.0 == 1.0) };
        assert_eq!(ONE_BELOW, f64::from_bits(1.0f64.to_bits() - 1));
    }
}
