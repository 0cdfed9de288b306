//! The 2-D table (`PiecewiseConstant2d`).

use super::*;

// The 2-D table

/// A 2-D case: the table and its box.
struct Case2d {
    name: &'static str,
    lo: [f64; 2],
    hi: [f64; 2],
    width: usize,
    height: usize,
    values: Vec<f64>,
}

impl Case2d {
    fn pdf(&self) -> PiecewiseConstant2d {
        PiecewiseConstant2d::new(self.lo, self.hi, self.width, self.height, &self.values).unwrap()
    }

    fn sum(&self) -> f64 {
        self.values.iter().sum()
    }

    fn cell_size(&self) -> (f64, f64) {
        (
            (self.hi[0] - self.lo[0]) / self.width as f64,
            (self.hi[1] - self.lo[1]) / self.height as f64,
        )
    }

    /// The centre of cell `(i, j)`.
    fn centre(&self, i: usize, j: usize) -> [f64; 2] {
        let (w, h) = self.cell_size();
        [
            self.lo[0] + (i as f64 + 0.5) * w,
            self.lo[1] + (j as f64 + 0.5) * h,
        ]
    }
}

fn cases_2d() -> Vec<Case2d> {
    // A bright spot on a dim background, 1e4 : 1, like an environment map's sun.
    let spot: Vec<f64> = (0..16 * 16)
        .map(|k| {
            let (i, j) = ((k % 16) as f64 - 11.5, (k / 16) as f64 - 4.5);
            1.0 + 1e4 * (-(i * i + j * j)).exp()
        })
        .collect();
    vec![
        Case2d {
            name: "4x3 with zeros and a zero row",
            lo: [0.0, 0.0],
            hi: [2.0, 1.0],
            width: 4,
            height: 3,
            values: vec![1.0, 0.0, 2.0, 3.0, 0.0, 0.0, 0.0, 0.0, 4.0, 0.0, 0.0, 5.0],
        },
        Case2d {
            name: "16x16 bright spot",
            lo: [-1.0, -2.0],
            hi: [1.0, 2.0],
            width: 16,
            height: 16,
            values: spot,
        },
        Case2d {
            name: "1x1",
            lo: [3.0, 4.0],
            hi: [5.0, 4.5],
            width: 1,
            height: 1,
            values: vec![2.0],
        },
        Case2d {
            name: "5x1 strip",
            lo: [0.0, 0.0],
            hi: [1.0, 1.0],
            width: 5,
            height: 1,
            values: vec![1.0, 2.0, 0.0, 4.0, 8.0],
        },
        Case2d {
            name: "1x6 column, huge box",
            lo: [-1e150, 0.0],
            hi: [1e150, 1e150],
            width: 1,
            height: 6,
            values: vec![1.0, 0.0, 3.0, 1e-3, 1e3, 7.0],
        },
        Case2d {
            name: "3x2 tiny box, extreme values",
            lo: [1e-150, -1e-150],
            hi: [4e-150, 1e-150],
            width: 3,
            height: 2,
            values: vec![1e300, 1e-300, 0.0, 5e299, 1e300, 2e300],
        },
    ]
}

#[test]
fn the_2d_table_integrates_to_one_and_is_the_table() {
    for case in cases_2d() {
        let p = case.pdf();
        assert_eq!((p.dims(), p.canonical_dims()), (2, 2));
        assert_eq!((p.width(), p.height()), (case.width, case.height));
        let (w, h) = case.cell_size();
        let mut total = 0.0;
        for j in 0..case.height {
            for i in 0..case.width {
                let value = case.values[j * case.width + i];
                let probability = value / case.sum();
                let density = p.pdf(&case.centre(i, j));
                // Density times area is the cell's share of the table, to rounding.
                assert!(
                    (density * w * h - probability).abs() <= 1e-14 * probability + 1e-300,
                    "{}: cell ({i}, {j}) density {density}",
                    case.name
                );
                assert!((p.cell_probability(i, j) - probability).abs() <= 1e-14 * probability);
                total += density * w * h;
            }
        }
        assert!((total - 1.0).abs() < 1e-13, "{}: total {total}", case.name);
        // The marginal is the rows' shares; a row of zeros has no conditional.
        for j in 0..case.height {
            let row: f64 = case.values[j * case.width..(j + 1) * case.width]
                .iter()
                .sum();
            let share = p.marginal().cell_probability(j);
            assert!((share - row / case.sum()).abs() <= 1e-14 * share + 1e-300);
            assert_eq!(p.conditional(j).is_none(), row == 0.0, "{}", case.name);
        }
    }
}

#[test]
fn the_2d_table_samples_follow_the_density() {
    // 2x2 bins in every cell, expected counts from the pdf at the bins' Gauss points (it is
    // constant on them, so a 2-point tensor rule integrates it exactly).
    const SAMPLES: usize = 400_000;
    for (c, case) in cases_2d().iter().enumerate() {
        let p = case.pdf();
        let (bx, by) = (2 * case.width, 2 * case.height);
        let (w, h) = (
            (case.hi[0] - case.lo[0]) / bx as f64,
            (case.hi[1] - case.lo[1]) / by as f64,
        );
        let g = 0.5 / 3f64.sqrt();
        let mut expected = vec![0.0; bx * by];
        for j in 0..by {
            for i in 0..bx {
                let mut integral = 0.0;
                for (sx, sy) in [(-g, -g), (-g, g), (g, -g), (g, g)] {
                    let x = case.lo[0] + (i as f64 + 0.5 + sx) * w;
                    let y = case.lo[1] + (j as f64 + 0.5 + sy) * h;
                    integral += 0.25 * p.pdf(&[x, y]) * w * h;
                }
                expected[j * bx + i] = SAMPLES as f64 * integral;
            }
        }
        let total = expected.iter().sum::<f64>() / SAMPLES as f64;
        assert!(
            (total - 1.0).abs() < 1e-12,
            "{}: bins hold {total}",
            case.name
        );

        let u = canonical(2, SAMPLES, 600 + c as u64);
        let mut observed = vec![0u64; bx * by];
        let (mut uu, mut x) = ([0.0; 2], [0.0; 2]);
        for k in 0..SAMPLES {
            u.copy_point(k, &mut uu);
            p.sample(&uu, &mut x);
            let bin = |d: usize, n: usize| {
                let t = (x[d] - case.lo[d]) / (case.hi[d] - case.lo[d]) * n as f64;
                assert!(
                    x[d] >= case.lo[d] && x[d] < case.hi[d],
                    "{}: sample {x:?} outside",
                    case.name
                );
                (t as usize).min(n - 1)
            };
            let (i, j) = (bin(0, bx), bin(1, by));
            observed[j * bx + i] += 1;
            assert!(
                p.pdf(&x) > 0.0,
                "{}: sample {x:?} has zero density",
                case.name
            );
        }
        assert_fits(case.name, &observed, &expected);
    }
}

proptest! {
    #![proptest_config(config(400, 20240605))]

    #[test]
    fn the_2d_table_inverts_its_samples(
        width in 1usize..8,
        height in 1usize..8,
        raw in prop::collection::vec(weight(), 64),
        box_lo in prop::array::uniform2(-1e3..1e3f64),
        log_size in prop::array::uniform2(-3.0..3.0f64),
        u in prop::array::uniform2(canonical_u()),
    ) {
        let mut values = raw[..width * height].to_vec();
        if values.iter().all(|&v| v == 0.0) {
            values[0] = 1.0;
        }
        let hi = [box_lo[0] + 10f64.powf(log_size[0]), box_lo[1] + 10f64.powf(log_size[1])];
        let p = PiecewiseConstant2d::new(box_lo, hi, width, height, &values).unwrap();
        let (mut x, mut back) = ([0.0; 2], [0.0; 2]);
        p.sample(&u, &mut x);
        p.invert(&x, &mut back).unwrap();
        // Each coordinate is a 1-D warp (marginal, then the row's conditional), so each round
        // trip has the 1-D tolerance with that warp's density.
        let row = p.marginal().cell_at(x[1]).unwrap();
        let conditional = p.conditional(row).unwrap();
        let densities = [conditional.pdf_1d(x[0]), p.marginal().pdf_1d(x[1])];
        for d in 0..2 {
            let tolerance = round_trip_tolerance(densities[d], x[d]);
            prop_assert!(
                (back[d] - u[d]).abs() <= tolerance,
                "dim {}: {:?} -> {:?} -> {:?}",
                d,
                u,
                x,
                back
            );
        }
        // Samples land only in cells of positive value, and the density is the product.
        let column = conditional.cell_at(x[0]).unwrap();
        prop_assert!(values[row * width + column] > 0.0);
        prop_assert_eq!(p.pdf(&x), densities[0] * densities[1]);
    }
}

#[test]
fn the_2d_table_keeps_stratification() {
    // N x N jittered u: u[1]'s stratum j must be the marginal cdf stratum of y, and u[0]'s
    // stratum i the stratum of x under the conditional cdf of y's row, both by the reference
    // cdfs written here. So each of the N^2 (marginal, conditional) equal-probability cells
    // holds exactly one sample.
    const N: usize = 40;
    for (c, case) in cases_2d().iter().enumerate() {
        let p = case.pdf();
        let row_sums: Vec<f64> = case
            .values
            .chunks_exact(case.width)
            .map(|r| r.iter().sum())
            .collect();
        let jitter = canonical(2, N * N, 700 + c as u64);
        let mut counts = vec![0u32; N * N];
        let (mut xi, mut x) = ([0.0; 2], [0.0; 2]);
        for k in 0..N * N {
            jitter.copy_point(k, &mut xi);
            let (i, j) = (k % N, k / N);
            let u = [(i as f64 + xi[0]) / N as f64, (j as f64 + xi[1]) / N as f64];
            p.sample(&u, &mut x);
            let fy = reference_table_cdf(case.lo[1], case.hi[1], &row_sums, x[1]);
            let row = (((x[1] - case.lo[1]) / (case.hi[1] - case.lo[1]) * case.height as f64)
                as usize)
                .min(case.height - 1);
            let cells = &case.values[row * case.width..(row + 1) * case.width];
            let fx = reference_table_cdf(case.lo[0], case.hi[0], cells, x[0]);
            let (si, sj) = ((fx * N as f64) as usize, (fy * N as f64) as usize);
            assert_eq!((si, sj), (i, j), "{}: u = {u:?}, x = {x:?}", case.name);
            counts[sj * N + si] += 1;
        }
        assert!(counts.iter().all(|&k| k == 1), "{}", case.name);
    }
}

#[test]
fn the_2d_density_vanishes_outside_and_in_zero_cells() {
    let case = &cases_2d()[0];
    let p = case.pdf();
    for x in [
        [-0.1, 0.5],
        [2.0, 0.5],
        [1.0, -1e-300],
        [1.0, 1.0],
        [NAN, 0.5],
        [1.0, NAN],
        [INF, 0.5],
        [1.0, -INF],
    ] {
        assert_eq!(p.pdf(&x), 0.0, "pdf({x:?})");
    }
    for j in 0..case.height {
        for i in 0..case.width {
            if case.values[j * case.width + i] == 0.0 {
                assert_eq!(p.pdf(&case.centre(i, j)), 0.0, "cell ({i}, {j})");
            }
        }
    }
    // invert clamps points outside the box to the cdf's ends.
    let mut u = [0.5; 2];
    p.invert(&[-5.0, -5.0], &mut u).unwrap();
    assert_eq!(u, [0.0, 0.0]);
    p.invert(&[5.0, 5.0], &mut u).unwrap();
    assert_eq!(u, [1.0, 1.0]);
}
