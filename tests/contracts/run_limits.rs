//! Time limits, cancellation and budgets: every runner checks its limits before every chunk
//! of work, so it returns within the limit plus one chunk (counted here in evaluations, never
//! in seconds), with what it has and the reason it stopped; budgets beyond 2^52 evaluations
//! need a time limit; a run that reaches the end of its sampler's pass says so.

use crate::common::unit;
use mcint::adaptive::{Miser, TwoStage, Vegas};
use mcint::pdf::UniformBox;
use mcint::sampler::{Pmj02, Scramble, Sobol};
use mcint::stats::{StopReason, Tolerance, Warning};
use mcint::{CancelToken, Error, Estimate, Integrator};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

/// Points of the Integrator's chunks: a run stops within one chunk per thread of a limit.
const CHUNK: u64 = 16_384;

/// An integrand that counts its calls and cancels `token` at call `at`.
fn cancelling(
    token: CancelToken,
    at: u64,
) -> (impl Fn(&[f64]) -> f64 + Send + Sync, &'static AtomicU64) {
    let calls: &'static AtomicU64 = Box::leak(Box::new(AtomicU64::new(0)));
    let f = move |x: &[f64]| {
        if calls.fetch_add(1, Ordering::Relaxed) + 1 == at {
            token.cancel();
        }
        x[0] * x[1]
    };
    (f, calls)
}

fn stopped(e: &Estimate) -> bool {
    e.warnings.iter().any(|w| {
        matches!(
            w,
            Warning::StoppedEarly { .. } | Warning::ToleranceNotMet { .. }
        )
    })
}

#[test]
fn a_cancelled_integrator_returns_the_chunks_it_finished() {
    // One thread: chunks run in order; the 7th, in which call 100 000 falls, is dropped at
    // its next block of 1024 points, and the 6 before it are kept.
    let token = CancelToken::new();
    let (f, calls) = cancelling(token.clone(), 100_000);
    let e = Integrator::over_box(f, unit())
        .samples(100_000_000)
        .threads(1)
        .cancel_token(token)
        .run()
        .unwrap();
    assert_eq!(e.stop, StopReason::Cancelled);
    assert!(stopped(&e), "{:?}", e.warnings);
    assert_eq!(
        calls.load(Ordering::Relaxed),
        100_000u64.div_ceil(1024) * 1024
    );
    assert_eq!(e.n, 6 * CHUNK);
    assert!((e.mean - 0.25).abs() < 5.0 * e.std_error.unwrap());
    // Two threads: each finishes the chunk it is in (at most one window of chunks in all), and
    // only the chunks before the first one not finished count, so that the bits do not depend
    // on the thread count. Which chunks those are depends on scheduling: the other thread may
    // have taken chunks far ahead, so the run may keep none of them.
    let token = CancelToken::new();
    let (f, calls) = cancelling(token.clone(), 100_000);
    let result = Integrator::over_box(f, unit())
        .samples(100_000_000)
        .threads(2)
        .cancel_token(token)
        .run();
    assert!(calls.load(Ordering::Relaxed) <= 100_000 + 2 * 64 * CHUNK);
    match result {
        Ok(e) => {
            assert_eq!(e.stop, StopReason::Cancelled);
            assert!(stopped(&e), "{:?}", e.warnings);
            assert_eq!(e.n % CHUNK, 0);
            assert!(e.n <= 100_000 + 2 * 64 * CHUNK, "{} points", e.n);
            assert!((e.mean - 0.25).abs() < 5.0 * e.std_error.unwrap());
        }
        Err(Error::Interrupted { stop, evaluations }) => {
            assert_eq!((stop, evaluations), (StopReason::Cancelled, 0));
        }
        Err(other) => panic!("expected a cancelled run, got {other}"),
    }
    // Replicates of Sobol' points: only whole replicates count.
    let token = CancelToken::new();
    let (f, _) = cancelling(token.clone(), 5 * (1 << 16) + 10);
    let e = Integrator::over_box(f, unit())
        .sampler(Sobol::new(2, Scramble::Owen, 1).unwrap())
        .samples(1 << 16)
        .replicates(64)
        .threads(1)
        .cancel_token(token)
        .run()
        .unwrap();
    assert_eq!(e.stop, StopReason::Cancelled);
    assert_eq!(e.n % (1 << 16), 0);
    assert!(e.replicates >= 5 && e.replicates < 64, "{}", e.replicates);
}

#[test]
fn a_time_limit_stops_every_runner_within_a_chunk() {
    // A limit that has already passed: no chunk starts, and no runner has an estimate.
    let past = Duration::ZERO;
    let errors = [
        Integrator::over_box(|x: &[f64]| x[0], unit())
            .time_limit(past)
            .run(),
        Vegas::new(|x: &[f64]| x[0], unit()).time_limit(past).run(),
        Miser::new(|x: &[f64]| x[0], unit()).time_limit(past).run(),
        TwoStage::new(|x: &[f64]| x[0], unit(), 4)
            .time_limit(past)
            .run(),
        Integrator::over_box(|x: &[f64]| x[0], unit())
            .tolerance(Tolerance::relative(1e-3).unwrap().time_limit(past))
            .run(),
    ];
    for result in errors {
        match result {
            Err(Error::Interrupted { stop, evaluations }) => {
                assert_eq!((stop, evaluations), (StopReason::TimeLimit, 0));
            }
            other => panic!("expected an interrupted run, got {other:?}"),
        }
    }
}

/// The run stopped at its time limit, with at most a quarter of its `budget` spent: an
/// estimate, or (when a busy machine gave it no time before the limit) none.
fn assert_stopped_at_the_limit(run: mcint::Result<Estimate>, budget: u64) {
    let evaluations = match run {
        Ok(e) => {
            assert_eq!(e.stop, StopReason::TimeLimit);
            e.evaluations
        }
        Err(Error::Interrupted { stop, evaluations }) => {
            assert_eq!(stop, StopReason::TimeLimit);
            evaluations
        }
        Err(other) => panic!("{other}"),
    };
    assert!(
        evaluations < budget / 4,
        "{evaluations} of {budget} evaluations"
    );
}

/// A run of a slow integrand (tens of microseconds a call) stops at its 200 ms limit after
/// at most a chunk per thread, where its budget is tens of millions of calls (hours): the
/// count, not the clock, is checked.
#[test]
fn a_slow_integrand_stops_at_the_time_limit() {
    fn slow(x: &[f64]) -> f64 {
        let mut v = x[0];
        for _ in 0..4000 {
            v = std::hint::black_box(v * 0.999_999 + 1e-9);
        }
        v
    }
    let limit = Duration::from_millis(200);
    let budget = 1 << 26;
    let run = Integrator::over_box(slow, unit())
        .samples(budget)
        .threads(2)
        .time_limit(limit)
        .run();
    assert_stopped_at_the_limit(run, budget);
    let run = Vegas::new(slow, unit())
        .samples(1 << 20)
        .warmup(0)
        .iterations(64)
        .threads(2)
        .time_limit(limit)
        .run();
    assert_stopped_at_the_limit(run, 64 << 20);
    let run = Miser::new(slow, unit())
        .samples(1 << 22)
        .tolerance(Tolerance::absolute(1e-12).unwrap())
        .time_limit(limit)
        .threads(2)
        .run();
    assert_stopped_at_the_limit(run, 16 << 22);
}

#[test]
fn a_run_to_a_tolerance_keeps_its_last_whole_stage_when_cancelled() {
    let token = CancelToken::new();
    let (f, _) = cancelling(token.clone(), 8 * 16384 + 5);
    let e = Integrator::over_box(f, unit())
        .sampler(Sobol::new(2, Scramble::Owen, 3).unwrap())
        .tolerance(Tolerance::absolute(1e-15).unwrap())
        .threads(1)
        .cancel_token(token)
        .run()
        .unwrap();
    assert_eq!(e.stop, StopReason::Cancelled);
    assert_eq!(e.converged, Some(false));
    // Stages of 1024, 2048, 4096, 8192, 16384 and 32768 points for each of 8 replicates
    // (131072 evaluations by the fifth); the sixth was cut short.
    assert_eq!((e.iterations, e.n), (5, 8 * 16384));
}

#[test]
fn budgets_beyond_2_52_evaluations_need_a_time_limit() {
    let huge = 1u64 << 53;
    let f = |x: &[f64]| x[0];
    let refused = [
        Integrator::over_box(f, unit())
            .samples(huge)
            .run()
            .unwrap_err(),
        Integrator::over_box(f, unit())
            .tolerance(
                Tolerance::absolute(1e-300)
                    .unwrap()
                    .max_evaluations(u64::MAX)
                    .unwrap(),
            )
            .run()
            .unwrap_err(),
        Miser::new(f, unit())
            .samples(u64::MAX / 16)
            .run()
            .unwrap_err(),
        TwoStage::new(f, unit(), 4)
            .samples(u64::MAX)
            .run()
            .unwrap_err(),
        Vegas::new(f, unit()).samples(huge).run().unwrap_err(),
    ];
    for err in refused {
        assert!(err.to_string().contains("without a time limit"), "{err}");
    }
    // A plan past 2^64 evaluations (2^62 samples x 16 replicates) says so: the saturated
    // product read "18446744073709551615 evaluations", which no setting asked for.
    let err = Miser::new(f, unit()).samples(1 << 62).run().unwrap_err();
    assert!(
        err.to_string()
            .contains("samples x replicates = 2^64 or more evaluations"),
        "{err}"
    );
    // With a time limit the run starts, and stops at it (with an estimate, unless a busy
    // machine gave its threads no time before the limit).
    let run = Integrator::over_box(f, unit())
        .samples(huge)
        .time_limit(Duration::from_millis(200))
        .run();
    assert_stopped_at_the_limit(run, huge);
}

/// pmj02 passes of 2^10 points: a tolerance out of reach runs to the end of the pass and says
/// the sampler ran out, rather than blaming the evaluation limit.
#[test]
fn a_run_that_exhausts_its_sampler_says_so() {
    let e = Integrator::over_box(|x: &[f64]| (9.0 * x[0]).sin(), unit())
        .sampler(Pmj02::with_max_points(2, 10, 1).unwrap())
        .samples(64)
        .tolerance(Tolerance::absolute(1e-12).unwrap())
        .run()
        .unwrap();
    assert_eq!(e.stop, StopReason::SamplerExhausted);
    assert_eq!(e.n, 8 * 1024);
    assert!(
        e.warnings.contains(&Warning::ToleranceNotMet {
            stop: StopReason::SamplerExhausted
        }),
        "{:?}",
        e.warnings
    );
}

/// Progress comes after every chunk of work (every replicate for MISER, every group of chunks
/// for VEGAS), not only between stages or iterations, and ends at the evaluations the
/// estimate counts.
#[test]
fn progress_is_reported_after_every_chunk() {
    use std::sync::{Arc, Mutex};
    type Log = Arc<Mutex<Vec<(u64, u64)>>>;
    let logger = || {
        let log: Log = Arc::default();
        let sink = Arc::clone(&log);
        (log, move |done, planned| {
            sink.lock().unwrap().push((done, planned))
        })
    };
    let check = |log: Log, e: Estimate, at_least: usize, method: &str| {
        let seen = log.lock().unwrap();
        assert!(seen.len() >= at_least, "{method}: {} reports", seen.len());
        assert!(seen.windows(2).all(|w| w[0].0 <= w[1].0), "{method}");
        assert_eq!(seen.last().unwrap().0, e.evaluations, "{method}");
    };
    let f = |x: &[f64]| x[0] * x[1];
    // 2^20 points: 64 chunks of 16384.
    let (log, progress) = logger();
    let e = Integrator::over_box(f, unit())
        .samples(1 << 20)
        .progress(progress)
        .run()
        .unwrap();
    check(log, e, 64, "integrator");
    // 5 iterations (warm-up included) of 2^16 points: 26 chunks of 2521 each, folded in 4
    // groups of at most 8.
    let (log, progress) = logger();
    let e = Vegas::new(f, unit())
        .samples(1 << 16)
        .iterations(4)
        .progress(progress)
        .run()
        .unwrap();
    check(log, e, 5 * 4, "vegas");
    // One stage of 16 replicates.
    let (log, progress) = logger();
    let e = Miser::new(f, unit())
        .samples(4096)
        .progress(progress)
        .run()
        .unwrap();
    check(log, e, 16, "miser");
    // 32 x 32 strata: a pilot of 8192 evaluations in one chunk, then 16 chunks of at most
    // 2^16 evaluations.
    let (log, progress) = logger();
    let e = TwoStage::new(f, unit(), 32)
        .samples(1 << 20)
        .progress(progress)
        .run()
        .unwrap();
    check(log, e, 1 + 16, "two-stage");
}

/// A stopped TwoStage keeps its pilot, a whole stage and an unbiased stratified estimate of
/// its own (it returned `Err(Interrupted)`); a stratum of any size is sampled in chunks, so a
/// cancellation inside one huge stratum stops the run within one chunk of calls (a run of one
/// stratum and 2^40 points ignored it, and its time limit, until its end).
#[test]
fn a_stopped_two_stage_run_keeps_its_pilot_and_stops_within_a_chunk() {
    // 16 strata x 8 pilot points; the main stage is cancelled 1000 calls in.
    let token = CancelToken::new();
    let (f, calls) = cancelling(token.clone(), 16 * 8 + 1000);
    let e = TwoStage::new(f, unit(), 4)
        .samples(1 << 40)
        .time_limit(Duration::from_secs(3600))
        .threads(1)
        .cancel_token(token)
        .run()
        .unwrap();
    assert_eq!(
        (e.stop, e.iterations, e.n),
        (StopReason::Cancelled, 1, 16 * 8)
    );
    assert!(stopped(&e), "{:?}", e.warnings);
    assert!((e.mean - 0.25).abs() < 5.0 * e.std_error.unwrap());
    // Chunks of at most 2^16 evaluations in 2 dimensions (and the pilot's two strata
    // pieces at most beyond them).
    let spent = calls.load(Ordering::Relaxed);
    assert!(spent <= 16 * 8 + 1000 + 3 * (1 << 16), "{spent} calls");
    assert_eq!(e.evaluations, spent);

    // One stratum: the main stage is a single batch of 2^40 - 2 points.
    let token = CancelToken::new();
    let (f, calls) = cancelling(token.clone(), 100_000);
    let e = TwoStage::new(f, unit(), 1)
        .pilot(2)
        .samples(1 << 40)
        .time_limit(Duration::from_secs(3600))
        .threads(2)
        .cancel_token(token)
        .run()
        .unwrap();
    assert_eq!((e.stop, e.n), (StopReason::Cancelled, 2));
    let spent = calls.load(Ordering::Relaxed);
    assert!(spent <= 100_000 + 2 * 256 * (1 << 16), "{spent} calls");

    // Cancelled in the pilot (of 128 x 128 strata x 8 points, two chunks): no whole
    // stage, no estimate.
    let token = CancelToken::new();
    let (f, _) = cancelling(token.clone(), 10);
    let err = TwoStage::new(f, unit(), 128)
        .threads(1)
        .cancel_token(token)
        .run()
        .unwrap_err();
    assert_eq!(
        err,
        Error::Interrupted {
            stop: StopReason::Cancelled,
            evaluations: 1 << 16
        }
    );
}

/// The strata per axis a budget affords are computed, not searched one at a time: a
/// budget of 10^14 evaluations in one dimension took minutes (and then failed, as more
/// strata than the run may keep); now it plans the most strata the helper allows.
#[test]
fn strata_per_axis_for_any_budget_is_immediate() {
    use mcint::adaptive::strata_per_axis_for;
    assert_eq!(strata_per_axis_for(1, 100_000_000_000_000), 1 << 20);
    assert_eq!(strata_per_axis_for(1, u64::MAX), 1 << 20);
    assert_eq!(strata_per_axis_for(2, u64::MAX), 1 << 10);
    assert_eq!(strata_per_axis_for(5, 32 * 3u64.pow(5)), 3);
    assert_eq!(strata_per_axis_for(5, 32 * 3u64.pow(5) - 1), 2);
    assert_eq!(strata_per_axis_for(10_000, u64::MAX), 1);
    assert_eq!(strata_per_axis_for(3, 0), 1);
}

/// A time limit past the last instant the clock can represent is no limit (it panicked on
/// `Instant + Duration` overflow in every runner).
#[test]
fn a_limit_of_duration_max_is_no_limit() {
    use mcint::adaptive::SobolG;
    let f = |x: &[f64]| x[0] * x[1];
    for limit in [Duration::MAX, Duration::from_secs(u64::MAX)] {
        let runs = [
            Integrator::over_box(f, unit()).time_limit(limit).run(),
            Integrator::over_box(f, unit())
                .tolerance(Tolerance::absolute(1e-3).unwrap().time_limit(limit))
                .run(),
            Vegas::new(f, unit()).time_limit(limit).run(),
            Miser::new(f, unit()).time_limit(limit).run(),
            TwoStage::new(f, unit(), 4).time_limit(limit).run(),
            SobolG::new(f, unit()).time_limit(limit).run(),
        ];
        for run in runs {
            let e = run.unwrap();
            assert_ne!(e.stop, StopReason::TimeLimit);
            assert!((e.mean - 0.25).abs() < 5.0 * e.std_error.or(e.error_bound).unwrap());
        }
        let vector = Integrator::over_box_vector(
            2,
            |x: &[f64], out: &mut [f64]| out.copy_from_slice(x),
            unit(),
        )
        .time_limit(limit)
        .run()
        .unwrap();
        assert_eq!(vector.outputs.len(), 2);
    }
}

/// Limits are checked between blocks of work inside a chunk, and a chunk stopped midway is
/// dropped (its work is redone on resumption, so the bits do not change): in 10,000
/// dimensions, where one chunk is seconds of work, every runner stops within a block of
/// calls of a cancellation (VEGAS's blocks hold 2^16 coordinates, 6 points here), counted
/// here in calls, never in seconds.
#[test]
fn every_runner_stops_within_a_block_in_high_dimension() {
    use mcint::adaptive::SobolG;
    let dims = 10_000;
    let cube = || UniformBox::unit(dims).unwrap();
    let at = 20;
    let check = |name: &str, run: mcint::Result<Estimate>, calls: &AtomicU64, most: u64| {
        match run {
            Err(Error::Interrupted { stop, evaluations }) => {
                assert_eq!(stop, StopReason::Cancelled, "{name}");
                assert!(evaluations <= at + most, "{name}: {evaluations}");
            }
            other => panic!("{name}: expected an interrupted run, got {other:?}"),
        }
        let spent = calls.load(Ordering::Relaxed);
        assert!(spent <= at + most, "{name}: {spent} calls");
    };
    let (token, f, calls) = high(at);
    let run = Integrator::over_box(f, cube())
        .threads(1)
        .cancel_token(token)
        .run();
    check("integrator", run, calls, 1024);
    let (token, f, calls) = high(at);
    let run = Vegas::new(f, cube()).threads(1).cancel_token(token).run();
    check("vegas", run, calls, 6);
    let (token, f, calls) = high(at);
    let run = Vegas::new(f, cube())
        .stratified(true)
        .threads(1)
        .cancel_token(token)
        .run();
    check("vegas+", run, calls, 6);
    let (token, f, calls) = high(at);
    let run = Miser::new(f, cube()).threads(1).cancel_token(token).run();
    check("miser", run, calls, 256);
    // Chunks of 2^22 coordinates: 419 points.
    let (token, f, calls) = high(at);
    let run = TwoStage::new(f, cube(), 1)
        .pilot(1000)
        .threads(1)
        .cancel_token(token)
        .run();
    check("two-stage", run, calls, 419);
    // Chunks of 4096 points, each one batch call.
    let (token, f, calls) = high(at);
    let run = SobolG::new(f, cube())
        .samples(1 << 16)
        .threads(1)
        .cancel_token(token)
        .run();
    check("sobol-g", run, calls, 4096);
}

/// A token, an integrand of 10,000 dimensions that cancels it at call `at`, and its calls.
fn high(
    at: u64,
) -> (
    CancelToken,
    impl Fn(&[f64]) -> f64 + Send + Sync,
    &'static AtomicU64,
) {
    let token = CancelToken::new();
    let (f, calls) = cancelling(token.clone(), at);
    (token, move |x: &[f64]| f(&x[..2]), calls)
}

/// The same unreachable tolerance stops every runner that takes one the same way: on the
/// evaluation limit, not converged, with the tolerance-not-met warning (SobolG gave no
/// warning, and VEGAS named its iteration cap the budget).
#[test]
fn an_unreachable_tolerance_ends_every_runner_the_same_way() {
    use mcint::adaptive::SobolG;
    let f = |x: &[f64]| (9.0 * x[0]).sin() * x[1];
    let unreachable = || {
        Tolerance::absolute(1e-9)
            .unwrap()
            .max_evaluations(1 << 14)
            .unwrap()
    };
    let runs: [(&str, mcint::Result<Estimate>); 6] = [
        (
            "integrator, independent points",
            Integrator::over_box(f, unit())
                .samples(1024)
                .tolerance(unreachable())
                .run(),
        ),
        (
            "integrator, rqmc",
            Integrator::over_box(f, unit())
                .sampler(Sobol::new(2, Scramble::Owen, 1).unwrap())
                .samples(256)
                .tolerance(unreachable())
                .run(),
        ),
        (
            "vegas",
            Vegas::new(f, unit())
                .samples(1000)
                .warmup(1)
                .iterations(1 << 20)
                .tolerance(unreachable())
                .run(),
        ),
        (
            "vegas, its most iterations",
            Vegas::new(f, unit())
                .samples(1000)
                .warmup(1)
                .iterations(3)
                .tolerance(unreachable())
                .run(),
        ),
        (
            "miser",
            Miser::new(f, unit())
                .samples(256)
                .tolerance(unreachable())
                .run(),
        ),
        (
            "sobol-g",
            SobolG::new(f, unit())
                .samples(1024)
                .tolerance(unreachable())
                .run(),
        ),
    ];
    for (name, run) in runs {
        let e = run.unwrap_or_else(|err| panic!("{name}: {err}"));
        assert_eq!(
            (e.stop, e.converged),
            (StopReason::MaxEvaluations, Some(false)),
            "{name}"
        );
        assert!(
            e.warnings.contains(&Warning::ToleranceNotMet {
                stop: StopReason::MaxEvaluations
            }),
            "{name}: {:?}",
            e.warnings
        );
        assert!(e.evaluations <= 1 << 14, "{name}: {}", e.evaluations);
    }
}
