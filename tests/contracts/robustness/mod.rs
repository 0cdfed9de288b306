//! Robustness: absurd parameters through every public constructor (issue 9, "every bad input
//! gets a clear error").
//!
//! Each property feeds random and extreme values (0, 1, `u64::MAX`, `2^40`, negative, NaN,
//! infinite and subnormal floats, empty and long vectors, mismatched lengths) to a constructor
//! and then either
//! - gets `Ok` and exercises the value a little: sampler points at indices near the start and
//!   the very end of the `u64` index range lie in `[0, 1)`, blocks at the end of the range work
//!   and one point more is an `IndexOutOfRange` error; pdf samples lie in the domain with a
//!   finite density, positive away from the edges of the canonical square; or
//! - gets `Err` whose message is non-empty and, for [`Error::InvalidParameter`], names one of
//!   the parameters the call was given.
//!
//! Where the valid range is simple to state, the property also checks that valid input is
//! accepted, so that "always `Err`" cannot pass. A panic or a hang fails the test. Sizes that
//! are accepted legitimately but are expensive (a Poisson-disk pass of a million points) are
//! only constructed, not generated.

use crate::common::{ONE_BELOW, config};
use mcint::Error;
use proptest::prelude::*;

mod checkpoints;
mod estimators;
mod extremes;
mod integrator;
mod measures;
mod pdfs;
mod samplers;
mod stats_and_testfns;

/// Asserts that an error says something, and that an invalid parameter is one of `params`
/// (matched loosely: the error's name contains one of them, as in `"m * n"` for `"m"`).
fn assert_clear(err: &Error, params: &[&str]) {
    let message = err.to_string();
    assert!(!message.trim().is_empty(), "empty message for {err:?}");
    match err {
        Error::InvalidParameter {
            name,
            value,
            allowed,
        } => {
            assert!(
                !name.is_empty() && !value.is_empty() && !allowed.is_empty(),
                "{err:?}"
            );
            assert!(message.contains(name), "{message}");
            assert!(
                params.iter().any(|p| name.contains(p)),
                "the error names {name:?}, which is none of {params:?}: {message}"
            );
        }
        Error::DimensionMismatch { what, .. } | Error::IndexOutOfRange { what, .. } => {
            assert!(!what.is_empty(), "{err:?}");
        }
        _ => {}
    }
}

/// `Ok` values go to `exercise`, errors to [`assert_clear`].
fn check<T>(result: mcint::Result<T>, params: &[&str], exercise: impl FnOnce(T)) {
    match result {
        Ok(value) => exercise(value),
        Err(err) => assert_clear(&err, params),
    }
}

/// Counts and sizes: small ones, powers of two at the limits of the samplers' tables, and the
/// ends of the `u64` range.
fn count() -> impl Strategy<Value = u64> {
    let special = prop::sample::select(vec![
        0,
        1,
        2,
        3,
        4,
        1 << 14,
        (1 << 14) + 1,
        1 << 20,
        (1 << 20) + 1,
        (1 << 32) - 1,
        1 << 32,
        4_294_967_291, // the largest prime below 2^32
        1 << 40,
        (1 << 40) + 1,
        1 << 53,
        (1 << 53) + 1,
        1 << 63,
        u64::MAX / 2 + 1,
        u64::MAX - 1,
        u64::MAX,
    ]);
    prop_oneof![2 => 0..5u64, 2 => 0..70u64, 2 => special, 1 => any::<u64>()]
}

/// Dimensions: mostly small, sometimes at or past a table's end, sometimes absurd.
fn dims() -> impl Strategy<Value = usize> {
    let special = prop::sample::select(vec![
        9_125,
        9_126,
        10_000,
        10_001,
        21_201,
        21_202,
        u32::MAX as usize,
        u32::MAX as usize + 1,
        1 << 40,
        usize::MAX,
    ]);
    prop_oneof![6 => 0..7usize, 1 => special]
}

/// Floats of every kind: specials, extremes and ordinary values.
fn real() -> impl Strategy<Value = f64> {
    let special = prop::sample::select(vec![
        0.0,
        -0.0,
        0.5,
        1.0,
        -1.0,
        2.0,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::MIN_POSITIVE,
        5e-324,
        -5e-324,
        1e-310,
        f64::EPSILON,
        ONE_BELOW,
        1e-300,
        1e-160,
        1e160,
        1e300,
        f64::MAX,
        f64::MIN,
    ]);
    prop_oneof![2 => special, 2 => -10.0..10.0f64, 1 => any::<f64>()]
}

/// A random canonical coordinate in `[0, 1)`, often at its ends.
fn unit() -> impl Strategy<Value = f64> {
    prop_oneof![
        prop::sample::select(vec![0.0, 5e-324, f64::EPSILON / 2.0, 0.5, ONE_BELOW]),
        0.0..1.0f64,
    ]
}

/// Poisson-disk passes that would take minutes to hours to build are refused up front, from
/// the expected size of their maximal sets, naming the limit.
#[test]
fn poisson_disk_passes_that_would_not_finish_are_refused() {
    use mcint::sampler::PoissonDisk;
    for result in [
        PoissonDisk::new(4, 1 << 20, 0),
        PoissonDisk::new(2, 1 << 20, 0),
        PoissonDisk::with_radius(2, 0.001, 0),
        PoissonDisk::with_radius(3, 0.01, 0),
    ] {
        let err = result.unwrap_err();
        assert!(err.to_string().contains("ten seconds"), "{err}");
    }
    assert!(PoissonDisk::new(4, 4096, 0).is_ok());
}
