//! Optimized designs: random-cd lowers the centered discrepancy of a Latin hypercube and keeps
//! it one; Lloyd relaxation lowers the quantization energy of any point set step by step.

use mcint::Points;
use mcint::quality::{Discrepancy, GeometricCriterion, geometric_discrepancy};
use mcint::sampler::{Independent, LatinHypercube, Lloyd, RandomCd, Sampler, lloyd, random_cd};

/// Each column's values in order: a permutation within columns leaves them unchanged.
fn sorted_columns(points: &Points) -> Vec<Vec<f64>> {
    (0..points.dims())
        .map(|k| {
            let mut column = points.column(k).to_vec();
            column.sort_by(f64::total_cmp);
            column
        })
        .collect()
}

#[test]
fn random_cd_lowers_the_discrepancy_and_keeps_the_latin_hypercube() {
    for seed in 0..8 {
        let original = LatinHypercube::new(5, 100, seed)
            .unwrap()
            .random(100)
            .unwrap();
        let mut points = original.clone();
        let before = Discrepancy::Centered.squared(&points).unwrap();
        let after = random_cd(&mut points, RandomCd::default(), seed).unwrap();
        assert!(after < before, "seed {seed}: {after} >= {before}");
        assert_eq!(after, Discrepancy::Centered.squared(&points).unwrap());
        assert_eq!(sorted_columns(&points), sorted_columns(&original));
        // The same seed gives the same design.
        let mut again = original.clone();
        random_cd(&mut again, RandomCd::default(), seed).unwrap();
        assert_eq!(again, points);
    }
}

#[test]
fn random_cd_leaves_what_it_cannot_improve() {
    let mut line = LatinHypercube::new(1, 16, 0).unwrap().random(16).unwrap();
    let copy = line.clone();
    random_cd(&mut line, RandomCd::default(), 0).unwrap();
    assert_eq!(line, copy);
    let mut points = LatinHypercube::new(2, 16, 0).unwrap().random(16).unwrap();
    let idle = RandomCd {
        max_tries: 10,
        patience: 0,
    };
    assert!(random_cd(&mut points, idle, 0).is_err());
    let mut outside = Points::from_rows(&[[0.5, 1.5], [0.1, 0.2]]).unwrap();
    assert!(random_cd(&mut outside, RandomCd::default(), 0).is_err());
}

#[test]
fn lloyd_lowers_the_energy_every_step_and_spreads_the_points() {
    for (dims, seed) in [(2, 1), (3, 2), (5, 3)] {
        let mut points = Independent::new(dims, seed).unwrap().random(50).unwrap();
        let before = geometric_discrepancy(&points, GeometricCriterion::MinDistance).unwrap();
        let energies = lloyd(&mut points, Lloyd::default()).unwrap();
        assert_eq!(energies.len(), 11);
        assert!(energies.windows(2).all(|w| w[1] <= w[0]), "{energies:?}");
        assert!(energies[10] < energies[0]);
        assert!((0..dims).all(|k| points.column(k).iter().all(|x| (0.0..1.0).contains(x))));
        let after = geometric_discrepancy(&points, GeometricCriterion::MinDistance).unwrap();
        assert!(
            after > before,
            "{dims}-D: minimum distance {before} -> {after}"
        );
    }
    let mut points = Independent::new(2, 0).unwrap().random(8).unwrap();
    let none = Lloyd {
        probes_per_point: 0,
        ..Lloyd::default()
    };
    assert!(lloyd(&mut points, none).is_err());
}
