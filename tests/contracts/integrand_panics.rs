//! An integrand that panics ends the run with `Error::IntegrandPanicked`, carrying the panic
//! message and where the chunk of work that panicked starts, on any number of threads and in
//! every method; nothing unwinds into the caller.

use crate::common::unit;
use mcint::adaptive::{Miser, TwoStage, Vegas};
use mcint::{Error, Integrator};

/// Panics at the points whose first coordinate is above 0.75 (with its value in the message).
fn fragile(x: &[f64]) -> f64 {
    assert!(x[0] <= 0.75, "integrand broke at x0 = {:.3}", x[0]);
    x[0]
}

fn assert_panicked(result: mcint::Result<mcint::Estimate>, method: &str) {
    match result {
        Err(Error::IntegrandPanicked { message, .. }) => {
            assert!(
                message.starts_with("integrand broke at x0 = "),
                "{method}: {message}"
            )
        }
        other => panic!("{method}: expected IntegrandPanicked, got {other:?}"),
    }
}

#[test]
fn the_integrator_reports_the_panic_and_the_chunk_it_came_from() {
    for threads in [1, 2, 3] {
        let err = Integrator::over_box(fragile, unit())
            .samples(100_000)
            .replicates(2)
            .threads(threads)
            .run()
            .unwrap_err();
        // Every chunk meets a point above 0.75; the first chunk in order is reported.
        assert!(
            matches!(
                err,
                Error::IntegrandPanicked {
                    replicate: 0,
                    first_index: 0,
                    ..
                }
            ),
            "{threads} threads: {err:?}"
        );
        assert!(err.to_string().contains("sample 0 of replicate 0"), "{err}");
    }
}

#[test]
fn every_method_reports_the_panic() {
    assert_panicked(Integrator::over_box(fragile, unit()).run(), "plain");
    assert_panicked(Vegas::new(fragile, unit()).threads(2).run(), "vegas");
    assert_panicked(Miser::new(fragile, unit()).threads(2).run(), "miser");
    assert_panicked(
        TwoStage::new(fragile, unit(), 4).threads(2).run(),
        "two-stage",
    );
    let controls = Integrator::with_controls(fragile, unit())
        .control(|x: &[f64]| x[1], 0.5)
        .threads(2)
        .run();
    assert_panicked(controls, "control variates");
}
