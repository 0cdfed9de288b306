//! The peer of `points --sampler sobol --scramble owen --format sum`, as a whole process:
//! `sobol_burley` 0.5's `sample_4d` produces the same number of values (points in 4-dim groups,
//! f32 converted to f64) and the program prints the sum of each coordinate, one line per
//! dimension, accumulated in index order.
//!
//! ```text
//! cargo build --release --example burley_sum
//! target/release/examples/burley_sum DIMS N [SEED]
//! ```
//! `DIMS` is a multiple of 4 up to 256 and `N` at most 65536 (sobol_burley's limits).

use std::io::Write;

fn main() {
    let args: Vec<u32> = std::env::args()
        .skip(1)
        .map(|a| a.parse().expect("usage: burley_sum DIMS N [SEED]"))
        .collect();
    let (dims, n, seed) = match args[..] {
        [dims, n] => (dims, n, 0),
        [dims, n, seed] => (dims, n, seed),
        _ => panic!("usage: burley_sum DIMS N [SEED]"),
    };
    assert!(
        dims % 4 == 0 && dims / 4 <= sobol_burley::NUM_DIMENSION_SETS_4D,
        "DIMS must be a multiple of 4 up to 256"
    );
    assert!(n <= 1 << 16, "N must be at most 65536");
    let mut sums = vec![0.0f64; dims as usize];
    for i in 0..n {
        for (set, sums) in sums.chunks_exact_mut(4).enumerate() {
            let p = sobol_burley::sample_4d(i, set as u32, seed);
            for (sum, v) in sums.iter_mut().zip(p) {
                *sum += f64::from(v);
            }
        }
    }
    let mut out = std::io::stdout().lock();
    for sum in &sums {
        writeln!(out, "{sum:?}").expect("write failed");
    }
}
