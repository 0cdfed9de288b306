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
use std::process::ExitCode;

const USAGE: &str =
    "usage: burley_sum DIMS N [SEED] (DIMS a multiple of 4 up to 256, N at most 65536)";

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), String> {
    let args = std::env::args()
        .skip(1)
        .map(|a| {
            a.parse::<u32>()
                .map_err(|_| format!("'{a}' is not a whole number; {USAGE}"))
        })
        .collect::<Result<Vec<u32>, String>>()?;
    let (dims, n, seed) = match args[..] {
        [dims, n] => (dims, n, 0),
        [dims, n, seed] => (dims, n, seed),
        _ => return Err(USAGE.to_string()),
    };
    if dims == 0 || dims % 4 != 0 || dims / 4 > sobol_burley::NUM_DIMENSION_SETS_4D {
        return Err(format!("DIMS = {dims}: {USAGE}"));
    }
    if n > 1 << 16 {
        return Err(format!("N = {n}: {USAGE}"));
    }
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
        match writeln!(out, "{sum:?}") {
            Ok(()) => {}
            // A reader that stopped early (`| head`) is not an error.
            Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => return Ok(()),
            Err(e) => return Err(format!("writing the sums: {e}")),
        }
    }
    Ok(())
}
