//! Point sets the way scipy.stats.qmc gives them: `random`, `random_base2`, `integers`, rows,
//! and `qmc.scale` with its inverse, bit for bit against scipy 1.17.1
//! (`python tests/data/scipy_style.py` printed the values below).

use mcint::sampler::{Halton, Independent, Jittered, LatinHypercube, Sampler, Sobol};
use mcint::{Points, Scramble};

fn from_bits(bits: &[[u64; 3]]) -> Vec<Vec<f64>> {
    bits.iter()
        .map(|row| row.iter().map(|&b| f64::from_bits(b)).collect())
        .collect()
}

#[test]
fn scale_and_its_inverse_match_scipy_bit_for_bit() {
    let rows = [
        [0.1, 0.7, 0.33],
        [0.999, 0.0, 0.5],
        [0.123456789, 0.987654321, 0.25],
    ];
    let (lower, upper) = ([-1.5, 0.1, 3.0], [2.25, 0.7, 1e6]);
    let points = Points::from_rows(&rows).unwrap();
    let scaled = points.scale(&lower, &upper).unwrap();
    let scipy_scaled = from_bits(&[
        [
            13831117405608214528,
            4602858963157741732,
            4689413003827572900,
        ],
        [
            4612240524131507896,
            4591870180066957722,
            4692333572827119616,
        ],
        [
            13830721255659965622,
            4604413539029182267,
            4687830024739356672,
        ],
    ]);
    assert_eq!(scaled.to_rows(), scipy_scaled);
    let scipy_unscaled = from_bits(&[
        [
            4591870180066957722,
            4604480259023595111,
            4599616371426034975,
        ],
        [4607173411600762667, 0, 4602678819172646912],
        [
            4593560419846153054,
            4607071218809329336,
            4598175219545276416,
        ],
    ]);
    assert_eq!(
        scaled.unscale(&lower, &upper).unwrap().to_rows(),
        scipy_unscaled
    );
}

#[test]
fn random_and_integers_match_scipy() {
    let sobol = Sobol::new(3, Scramble::None, 0).unwrap();
    let scipy_random = from_bits(&[
        [0, 0, 0],
        [
            4602678819172646912,
            4602678819172646912,
            4602678819172646912,
        ],
        [
            4604930618986332160,
            4598175219545276416,
            4598175219545276416,
        ],
        [
            4598175219545276416,
            4604930618986332160,
            4604930618986332160,
        ],
        [
            4600427019358961664,
            4600427019358961664,
            4603804719079489536,
        ],
        [
            4606056518893174784,
            4606056518893174784,
            4593671619917905920,
        ],
        [
            4603804719079489536,
            4593671619917905920,
            4606056518893174784,
        ],
        [
            4593671619917905920,
            4603804719079489536,
            4600427019358961664,
        ],
    ]);
    assert_eq!(sobol.random(8).unwrap().to_rows(), scipy_random);
    assert_eq!(sobol.random_base2(3).unwrap().to_rows(), scipy_random);

    let sobol2 = Sobol::new(2, Scramble::None, 0).unwrap();
    let levels = sobol2.integers(&[0, -5], &[7, 5], 8).unwrap();
    let scipy: Vec<Vec<i64>> = [
        [0, -5],
        [3, 0],
        [5, -3],
        [1, 2],
        [2, -2],
        [6, 3],
        [4, -4],
        [0, 1],
    ]
    .iter()
    .map(|r| r.to_vec())
    .collect();
    assert_eq!(levels.to_rows(), scipy);
    let halton = Halton::new(2, Scramble::None, 0).unwrap();
    let levels = halton.integers(&[1, -100], &[4, 1000], 6).unwrap();
    let scipy: Vec<Vec<i64>> = [[1, -100], [2, 266], [1, 633], [3, 22], [1, 388], [2, 755]]
        .iter()
        .map(|r| r.to_vec())
        .collect();
    assert_eq!(levels.to_rows(), scipy);
}

#[test]
fn random_refuses_sizes_that_break_the_design() {
    let sobol = Sobol::new(2, Scramble::Owen, 3).unwrap();
    assert!(sobol.random(1 << 33).is_err()); // longer than the sequence
    assert!(sobol.random_base2(64).is_err());
    let err = sobol.random_base2(33).unwrap_err().to_string();
    assert!(err.contains("at most 4294967296"), "{err}");
    // A fixed pass is drawn whole.
    let lhs = LatinHypercube::new(3, 100, 0).unwrap();
    assert_eq!(lhs.random(100).unwrap().len(), 100);
    let err = lhs.random(99).unwrap_err().to_string();
    assert!(
        err.contains("expected 100") && err.contains("pass size"),
        "{err}"
    );
    let grid = Jittered::new(2, 3, 0).unwrap();
    assert!(grid.random_base2(3).is_err());
    // Independent points have no net to break.
    assert_eq!(
        Independent::new(2, 0)
            .unwrap()
            .random_base2(5)
            .unwrap()
            .len(),
        32
    );
}

#[test]
fn integers_refuse_empty_and_huge_ranges() {
    let sobol = Sobol::new(2, Scramble::Owen, 0).unwrap();
    assert!(sobol.integers(&[0, 0], &[1, 0], 4).is_err());
    assert!(sobol.integers(&[0], &[1], 4).is_err());
    assert!(sobol.integers(&[0, i64::MIN], &[1, 0], 4).is_err());
    let wide = sobol
        .integers(&[0, -(1 << 53)], &[1, 1 << 53], 1024)
        .unwrap();
    assert!(wide.column(0).iter().all(|&k| k == 0));
    assert!(
        wide.column(1)
            .iter()
            .all(|&k| (-(1 << 53)..1 << 53).contains(&k))
    );
}

#[test]
fn rows_round_trip_and_refuse_ragged_input() {
    let sobol = Sobol::new(5, Scramble::Owen, 2).unwrap();
    let points = sobol.random(64).unwrap();
    let rows = points.to_rows();
    assert_eq!(rows.len(), 64);
    assert_eq!(Points::from_rows(&rows).unwrap(), points);
    for (i, row) in points.rows().enumerate() {
        assert_eq!(Some(row), points.row(i));
    }
    assert!(Points::from_rows(&[vec![0.5; 5], vec![0.5; 4]]).is_err());
    assert!(points.scale(&[0.0; 5], &[f64::INFINITY; 5]).is_err());
    assert!(points.scale(&[0.0; 4], &[1.0; 4]).is_err());
}

#[test]
fn geometric_discrepancy_matches_scipy() {
    use mcint::quality::{GeometricCriterion, geometric_discrepancy};
    let sobol = Sobol::new(3, Scramble::None, 0)
        .unwrap()
        .random(64)
        .unwrap();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-15 * b;
    let min = geometric_discrepancy(&sobol, GeometricCriterion::MinDistance).unwrap();
    assert!(close(min, 0.10364452469860624), "{min}");
    let mst = geometric_discrepancy(&sobol, GeometricCriterion::MinimumSpanningTree).unwrap();
    assert!(close(mst, 0.2101623405823559), "{mst}");
    // A duplicated point: scipy leaves its zero-length edge out of both measures.
    let mut rows = Halton::new(2, Scramble::None, 0)
        .unwrap()
        .random(30)
        .unwrap()
        .to_rows();
    rows.push(rows[7].clone());
    let dup = Points::from_rows(&rows).unwrap();
    let min = geometric_discrepancy(&dup, GeometricCriterion::MinDistance).unwrap();
    assert!(close(min, 0.09694702502451269), "{min}");
    let mst = geometric_discrepancy(&dup, GeometricCriterion::MinimumSpanningTree).unwrap();
    assert!(close(mst, 0.16011377931067597), "{mst}");
    let same = Points::from_rows(&[[0.5, 0.5], [0.5, 0.5]]).unwrap();
    assert!(geometric_discrepancy(&same, GeometricCriterion::MinDistance).is_err());
}

#[test]
fn update_discrepancy_is_the_discrepancy_of_the_larger_set() {
    use mcint::quality::{Discrepancy, update_discrepancy};
    // Grow a 5-D set one point at a time from one point to 200; every update is the fresh
    // CD^2 of the set so far, to the rounding of recovering the pair sum (a few eps (13/12)^d
    // per update, summed over the updates).
    let all = Independent::new(5, 3)
        .unwrap()
        .random(200)
        .unwrap()
        .to_rows();
    let mut cd2 = Discrepancy::Centered
        .squared(&Points::from_rows(&all[..1]).unwrap())
        .unwrap();
    let scale = (13.0f64 / 12.0).powi(5);
    for n in 1..all.len() {
        let set = Points::from_rows(&all[..n]).unwrap();
        cd2 = update_discrepancy(&all[n], &set, cd2).unwrap();
        let fresh = Discrepancy::Centered
            .squared(&Points::from_rows(&all[..=n]).unwrap())
            .unwrap();
        let bound = 16.0 * n as f64 * f64::EPSILON * scale;
        assert!((cd2 - fresh).abs() <= bound, "{n}: {cd2} vs {fresh}");
    }
    let set = Points::from_rows(&all[..3]).unwrap();
    assert!(update_discrepancy(&[0.5; 4], &set, 0.1).is_err());
    assert!(update_discrepancy(&[0.5; 5], &set, f64::NAN).is_err());
}
