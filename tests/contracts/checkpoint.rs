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

/// A run finished from parts counts the evaluations the uninterrupted run counts: each
/// contribution's (MIS with three samples per contribution) and the pilot's (fitted
/// controls). It counted one per contribution and no pilot.
#[test]
fn a_run_from_parts_counts_the_evaluations_of_the_whole() {
    use mcint::estimator::{MisHeuristic, MultiSampleMis};
    use mcint::pdf::{Linear, UniformBox, UniformInterval};
    let mis = || {
        let techniques: Vec<(Box<dyn mcint::pdf::Pdf>, usize)> = vec![
            (Box::new(UniformInterval::new(0.0, 1.0).unwrap()), 1),
            (Box::new(Linear::new(0.0, 1.0, 0.0, 1.0).unwrap()), 2),
        ];
        let estimator =
            MultiSampleMis::new(|x: &[f64]| x[0] * x[0], techniques, MisHeuristic::Balance);
        Integrator::new(estimator.unwrap()).samples(1 << 14).seed(3)
    };
    let whole = mis().run().unwrap();
    let total = mis().total_chunks().unwrap();
    let mut part = mis().run_part(0..1).unwrap();
    mis().resume(&mut part, total).unwrap();
    assert_eq!(mis().finish(&part).unwrap(), whole);
    assert_eq!(whole.evaluations, 3 << 14);

    let controlled = || {
        Integrator::with_controls(|x: &[f64]| x[0].exp(), UniformBox::unit(1).unwrap())
            .control(|x: &[f64]| x[0], 0.5)
            .samples(1 << 14)
            .seed(4)
    };
    let whole = controlled().run().unwrap();
    let total = controlled().total_chunks().unwrap();
    let mut part = controlled().run_part(0..1).unwrap();
    controlled().resume(&mut part, total).unwrap();
    assert_eq!(controlled().finish(&part).unwrap(), whole);
    assert!(whole.evaluations > 1 << 14, "{whole:?}");
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
    assert!(e.contains("seed is the first field that differs"), "{e}");
    let e = independent(1).finish(&part).unwrap_err().to_string();
    assert!(e.contains("missing"), "{e}");
    let mut a = independent(1).run_part(0..2).unwrap();
    let e = a
        .merge(sobol_replicates(1).run_part(0..1).unwrap())
        .unwrap_err()
        .to_string();
    assert!(e.contains("is the first field that differs"), "{e}");
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

/// Finishing, resuming or merging with a part of another run is refused, with the field
/// that differs named: whatever changed, the sampler's randomization, the domain or the
/// integrand.
#[test]
fn a_part_of_another_run_is_refused_naming_what_differs() {
    use mcint::sampler::{Halton, Lattice, OaOffset, OrthogonalArray, Sampler};
    fn over(sampler: impl Sampler + 'static, domain: f64) -> Integrator<impl mcint::Estimator> {
        let dims = sampler.dims();
        Integrator::over_box(
            wavy,
            UniformBox::new(vec![0.0; dims], vec![domain; dims]).unwrap(),
        )
        .sampler(sampler)
        .samples(1 << 15)
        .replicates(4)
    }
    let owen = || Sobol::new(3, Scramble::Owen, 5).unwrap();
    let pairs: Vec<(&str, Integrator<_>, Integrator<_>)> = vec![
        ("probe", over(owen(), 1.0), over(owen(), 2.0)),
        (
            "probe",
            over(owen(), 1.0),
            over(Sobol::new(3, Scramble::Lms, 5).unwrap(), 1.0),
        ),
        (
            "probe",
            over(owen(), 1.0),
            over(Sobol::new(3, Scramble::Xor, 5).unwrap(), 1.0),
        ),
        (
            "probe",
            over(owen(), 1.0),
            over(owen().with_index_shuffle(true), 1.0),
        ),
        (
            "seed",
            over(owen(), 1.0),
            over(Sobol::new(3, Scramble::Owen, 6).unwrap(), 1.0),
        ),
    ];
    for (field, a, b) in &pairs {
        let part = a.run_part(0..2).unwrap();
        for err in [
            b.finish(&part).unwrap_err(),
            b.resume(&mut part.clone(), 1).unwrap_err(),
            b.run_part(2..3).unwrap().merge(part.clone()).unwrap_err(),
        ] {
            assert!(
                err.to_string()
                    .contains(&format!("{field} is the first field")),
                "{err}"
            );
        }
    }
    // Other samplers' randomizations: Halton permutation against Owen scrambling, two
    // generating vectors, two orthogonal-array offsets.
    let halton = |s| Halton::new(3, s, 1).unwrap();
    let a = over(halton(Scramble::Permute), 1.0).run_part(0..1).unwrap();
    assert!(over(halton(Scramble::Owen), 1.0).finish(&a).is_err());
    let lattice = |z: Vec<u64>| Lattice::with_generator(z, 20, Scramble::Shift, 1).unwrap();
    let a = over(lattice(vec![1, 182667, 469891]), 1.0)
        .run_part(0..1)
        .unwrap();
    assert!(
        over(lattice(vec![1, 182667, 302633]), 1.0)
            .finish(&a)
            .is_err()
    );
    let oa = |offset| OrthogonalArray::bose(3, 181, offset, 1).unwrap();
    let bigger = |s| {
        Integrator::over_box(wavy, UniformBox::unit(3).unwrap())
            .sampler(s)
            .replicates(2)
    };
    let a = bigger(oa(OaOffset::Jittered)).run_part(0..1).unwrap();
    let err = bigger(oa(OaOffset::MultiJittered)).finish(&a).unwrap_err();
    assert!(err.to_string().contains("probe"), "{err}");
    // Another integrand, and parts of two integrands merged.
    let other = Integrator::over_box(|x: &[f64]| wavy(x) + 1.0, UniformBox::unit(3).unwrap())
        .samples(200_000)
        .seed(11);
    let part = independent(1).run_part(0..2).unwrap();
    assert!(other.finish(&part).is_err());
    let mut mixed = other.run_part(2..4).unwrap();
    assert!(mixed.merge(part).is_err());
    // The integrand's label, and the non-finite policy.
    let labelled = independent(1).label("wavy v1").run_part(0..1).unwrap();
    let err = independent(1)
        .label("wavy v2")
        .finish(&labelled)
        .unwrap_err();
    assert!(
        err.to_string().contains("label is the first field"),
        "{err}"
    );
    let skip = independent(1).non_finite(mcint::NonFinitePolicy::Skip);
    let err = skip
        .finish(&independent(1).run_part(0..1).unwrap())
        .unwrap_err();
    assert!(
        err.to_string().contains("non_finite is the first field"),
        "{err}"
    );
}

/// One byte of a saved part flipped, 400 times: the part is refused (it does not parse, its
/// checksum fails, or it belongs to another run), or it gives the very same answer; never a
/// different one.
#[test]
fn a_flipped_byte_never_gives_a_different_answer() {
    let integrator = sobol_replicates(1);
    let whole = integrator.run().unwrap();
    let mut part = integrator.run_part(0..3).unwrap();
    part.merge(integrator.run_part(5..6).unwrap()).unwrap();
    let text = serde_json::to_string(&part).unwrap().into_bytes();
    let (mut refused, mut same) = (0, 0);
    for trial in 0..400u64 {
        let mut bytes = text.clone();
        let at = (trial.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 32) as usize % bytes.len();
        bytes[at] ^= 1 << (trial % 8);
        let Ok(mut tampered) = serde_json::from_slice::<PartialRun>(&bytes) else {
            refused += 1;
            continue;
        };
        let finished = (|| {
            while !tampered.is_complete() {
                integrator.resume(&mut tampered, 100)?;
            }
            integrator.finish(&tampered)
        })();
        match finished {
            Ok(e) => {
                assert_eq!(e, whole, "byte {at} flipped gave another answer");
                same += 1;
            }
            Err(_) => refused += 1,
        }
    }
    assert_eq!(refused + same, 400);
    assert!(refused > 300, "{refused} refused, {same} unchanged");
}

/// A part holds one accumulator per replicate and the chunks after its first gap: its saved
/// size does not grow with the chunks done in order (saving every few chunks stays linear).
#[test]
fn a_saved_part_does_not_grow_with_the_chunks_done() {
    let integrator = Integrator::over_box(wavy, UniformBox::unit(3).unwrap())
        .samples(1 << 22)
        .seed(3);
    let size = |chunks| {
        serde_json::to_string(&integrator.run_part(0..chunks).unwrap())
            .unwrap()
            .len()
    };
    let (small, large) = (size(2), size(200));
    assert!(
        large < small + 64,
        "{small} bytes after 2 chunks, {large} after 200"
    );
}

/// A checkpoint written by this version (format 2), checked in: the next version must still
/// read it and finish it to the same bits. Written by
/// `MCINT_WRITE_FIXTURE=1 cargo test --release --test contracts -- checkpoint::a_checked_in`.
#[test]
fn a_checked_in_checkpoint_of_this_format_finishes_to_its_pinned_bits() {
    let integrator = sobol_replicates(1).label("checkpoint fixture: wavy over [0,1)^3");
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/checkpoint_format_2.json"
    );
    if std::env::var_os("MCINT_WRITE_FIXTURE").is_some() {
        let mut part = integrator.run_part(0..3).unwrap();
        part.merge(integrator.run_part(5..6).unwrap()).unwrap();
        std::fs::write(path, serde_json::to_string_pretty(&part).unwrap()).unwrap();
    }
    let mut part: PartialRun =
        serde_json::from_str(&std::fs::read_to_string(path).expect("the fixture")).unwrap();
    assert_eq!((part.chunks_done(), part.next_missing()), (4, Some(3)));
    while !part.is_complete() {
        integrator.resume(&mut part, 100).unwrap();
    }
    let e = integrator.finish(&part).unwrap();
    assert_eq!(e, integrator.run().unwrap());
    assert_eq!(
        (e.mean.to_bits(), e.std_error.map(f64::to_bits)),
        (PINNED_MEAN, Some(PINNED_STD_ERROR)),
        "{:#018x} {:#018x}",
        e.mean.to_bits(),
        e.std_error.unwrap().to_bits()
    );
}

const PINNED_MEAN: u64 = 0x3fd5_7071_ab87_d791;
const PINNED_STD_ERROR: u64 = 0x3ea3_63ef_895f_490c;

/// The reader checks a part's state against its plan (counts per replicate and chunk, chunk
/// order, first non-finite value); every part a run leaves passes, whatever its shape: vector
/// outputs with their covariance, skipped non-finite values, gaps, complete parts.
#[test]
fn honest_parts_of_every_shape_read_back_and_finish() {
    let f = |x: &[f64], out: &mut [f64]| {
        out[0] = x[0];
        out[1] = if x[1] > 0.9 { f64::NAN } else { x[1] };
    };
    let vector = Integrator::over_box_vector(2, f, UniformBox::unit(2).unwrap())
        .samples(70_000)
        .non_finite(mcint::NonFinitePolicy::Skip)
        .seed(5);
    let whole = vector.run().unwrap();
    let mut part = through_json(&vector.run_part(1..2).unwrap());
    part.merge(through_json(&vector.run_part(3..5).unwrap()))
        .unwrap();
    while !part.is_complete() {
        part = through_json(&part);
        vector.resume(&mut part, 1).unwrap();
    }
    assert_eq!(vector.finish(&through_json(&part)).unwrap(), whole);

    let scalar = sobol_replicates(1).non_finite(mcint::NonFinitePolicy::Skip);
    let mut part = through_json(&scalar.run_part(6..8).unwrap());
    part.merge(through_json(&scalar.run_part(0..3).unwrap()))
        .unwrap();
    scalar.resume(&mut through_json(&part), 2).unwrap();
    scalar.resume(&mut part, 100).unwrap();
    assert_eq!(
        scalar.finish(&through_json(&part)).unwrap(),
        scalar.run().unwrap()
    );
}

/// A covariance accumulator whose co-moment triangle does not match its means is refused
/// when read (a checkpoint with a short triangle panicked in its checksum); an honest one
/// reads back unchanged.
#[test]
fn covariance_accumulators_of_the_wrong_shape_are_refused() {
    use mcint::stats::CovarianceAccumulator;
    let mut acc = CovarianceAccumulator::new(2).unwrap();
    acc.push(&[1.0, 2.0]).unwrap();
    acc.push(&[3.0, 1.0]).unwrap();
    let text = serde_json::to_string(&acc).unwrap();
    assert_eq!(
        serde_json::from_str::<CovarianceAccumulator>(&text).unwrap(),
        acc
    );
    for bad in [
        r#"{"count":2,"means":[2.0,1.5],"comoments":[2.0,-1.0],"non_finite":0}"#,
        r#"{"count":2,"means":[],"comoments":[],"non_finite":0}"#,
        r#"{"count":2,"means":[2.0],"comoments":[2.0,-1.0,0.5],"non_finite":0}"#,
    ] {
        let e = serde_json::from_str::<CovarianceAccumulator>(bad).unwrap_err();
        assert!(e.to_string().contains("co-moments"), "{e}");
    }
}
