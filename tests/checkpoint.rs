//! Checkpoint, resume and merge: a fixed-budget run split into parts at any chunk boundary,
//! saved as JSON between parts, resumed on any number of threads, or computed in disjoint
//! pieces and merged, finishes with the same bits as one uninterrupted run.

use mcint::pdf::UniformBox;
use mcint::sampler::{Scramble, Sobol};
use mcint::stats::{Accumulator, Estimate};
use mcint::{Error, Integrator, PartialRun};
use proptest::prelude::*;

fn wavy(x: &[f64]) -> f64 {
    (7.0 * x[0]).sin() * (3.0 * x[1]).cos() + x[2] * x[2]
}

fn independent(threads: usize) -> Integrator<impl mcint::Estimator> {
    Integrator::over_box(wavy, UniformBox::unit(3).unwrap())
        .samples(200_000)
        .seed(11)
        .threads(threads)
}

fn sobol_replicates(threads: usize) -> Integrator<impl mcint::Estimator> {
    Integrator::over_box(wavy, UniformBox::unit(3).unwrap())
        .sampler(Sobol::new(3, Scramble::Owen, 5).unwrap())
        .samples(1 << 15)
        .replicates(4)
        .threads(threads)
}

/// Saves and reloads a part as JSON, as a checkpoint file would.
fn through_json(part: &PartialRun) -> PartialRun {
    serde_json::from_str(&serde_json::to_string(part).unwrap()).unwrap()
}

#[test]
fn a_run_stopped_saved_and_resumed_gives_the_same_bits() {
    let whole = independent(2).run().unwrap();
    let mut part = independent(1).run_part(0..1).unwrap();
    let mut step = 0;
    while !part.is_complete() {
        part = through_json(&part);
        // Alternate thread counts and step sizes between "sessions".
        independent(1 + step % 3)
            .resume(&mut part, 1 + step as u64 % 4)
            .unwrap();
        step += 1;
    }
    assert!(step >= 3);
    assert_eq!(independent(3).finish(&through_json(&part)).unwrap(), whole);

    let whole = sobol_replicates(2).run().unwrap();
    let mut part = sobol_replicates(1).run_part(0..3).unwrap();
    while !part.is_complete() {
        part = through_json(&part);
        sobol_replicates(2).resume(&mut part, 3).unwrap();
    }
    assert_eq!(sobol_replicates(1).finish(&part).unwrap(), whole);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    /// Parts over any disjoint cover of the chunks, merged in any order, give the same bits.
    #[test]
    fn disjoint_parts_merge_to_the_whole(cuts in proptest::collection::vec(1u64..8, 0..5), reverse: bool) {
        let integrator = sobol_replicates(1);
        let total = integrator.total_chunks().unwrap();
        prop_assert_eq!(total, 8);
        let mut bounds: Vec<u64> = cuts;
        bounds.push(0);
        bounds.push(total);
        bounds.sort_unstable();
        bounds.dedup();
        let mut parts: Vec<PartialRun> = bounds
            .windows(2)
            .map(|w| through_json(&integrator.run_part(w[0]..w[1]).unwrap()))
            .collect();
        if reverse {
            parts.reverse();
        }
        let mut merged = parts.remove(0);
        for p in parts {
            merged.merge(p).unwrap();
        }
        prop_assert_eq!(integrator.finish(&merged).unwrap(), integrator.run().unwrap());
    }
}

#[test]
fn parts_of_another_run_or_incomplete_parts_are_refused() {
    let part = independent(1).run_part(0..2).unwrap();
    let other_seed = independent(1).seed(12);
    let e = other_seed.finish(&part).unwrap_err().to_string();
    assert!(e.contains("same run"), "{e}");
    let e = independent(1).finish(&part).unwrap_err().to_string();
    assert!(e.contains("missing"), "{e}");
    let mut a = independent(1).run_part(0..2).unwrap();
    let e = a
        .merge(sobol_replicates(1).run_part(0..1).unwrap())
        .unwrap_err()
        .to_string();
    assert!(e.contains("same run"), "{e}");
    let e = independent(1).run_part(3..3).unwrap_err().to_string();
    assert!(e.contains("chunk range"), "{e}");
    let tolerance = mcint::stats::Tolerance::absolute(1e-3).unwrap();
    assert!(independent(1).tolerance(tolerance).run_part(0..1).is_err());
    assert!(independent(1).resume(&mut a, 0).is_err());
}

#[test]
fn non_finite_contributions_fail_the_same_way_after_a_checkpoint() {
    let nan_corner = |x: &[f64]| if x[0] > 0.999 { f64::NAN } else { x[0] };
    let integrator = Integrator::over_box(nan_corner, UniformBox::unit(1).unwrap())
        .samples(100_000)
        .seed(2);
    let whole = integrator.run().unwrap_err();
    assert!(matches!(whole, Error::NonFiniteContribution { .. }));
    let mut part = through_json(&integrator.run_part(0..3).unwrap());
    integrator.resume(&mut part, 100).unwrap();
    let resumed = integrator.finish(&through_json(&part)).unwrap_err();
    assert_eq!(resumed.to_string(), whole.to_string());
}

#[test]
fn accumulators_and_estimates_round_trip_through_json() {
    let mut acc = Accumulator::new();
    let empty: Accumulator = serde_json::from_str(&serde_json::to_string(&acc).unwrap()).unwrap();
    assert_eq!(empty, acc);
    acc.extend(&[0.1, 0.7, f64::NAN, 1e-300, 3.0]);
    let back: Accumulator = serde_json::from_str(&serde_json::to_string(&acc).unwrap()).unwrap();
    assert_eq!(back, acc);
    assert_eq!(back.non_finite(), 1);
    let estimate = independent(1).samples(1000).run().unwrap();
    let back: Estimate = serde_json::from_str(&serde_json::to_string(&estimate).unwrap()).unwrap();
    assert_eq!(back, estimate);
    // A tampered accumulator (negative M2) is refused.
    let bad = r#"{"count":2,"mean":1.0,"m2":-1.0,"min":0.0,"max":2.0,"non_finite":0}"#;
    let e = serde_json::from_str::<Accumulator>(bad)
        .unwrap_err()
        .to_string();
    assert!(e.contains("inconsistent accumulator"), "{e}");
}

/// Resuming a part with a gap fills the gap first and stops before chunks it already has.
#[test]
fn resume_fills_gaps_in_order() {
    let integrator = sobol_replicates(1);
    let mut part = integrator.run_part(2..4).unwrap();
    part.merge(integrator.run_part(6..7).unwrap()).unwrap();
    assert_eq!(part.next_missing(), Some(0));
    integrator.resume(&mut part, 100).unwrap();
    assert_eq!((part.chunks_done(), part.next_missing()), (5, Some(4)));
    integrator.resume(&mut part, 100).unwrap();
    assert_eq!(part.next_missing(), Some(7));
    integrator.resume(&mut part, 1).unwrap();
    assert!(part.is_complete() && part.next_missing().is_none());
    assert_eq!(integrator.finish(&part).unwrap(), integrator.run().unwrap());
}
