//! Strong scaling of a run spread over MPI ranks, and what one exchange between the ranks
//! costs: the figures behind the guide's MPI chapter (`mcint::guide::mpi`).
//!
//! ```text
//! cargo build --release -p mcint-cli --features mpi
//! mpirun -n P target/release/mpi_scaling [--cost-us C] [--points N] [--threads T]
//!     [--method integrator|vegas|vegas-plus]
//! ```
//!
//! Rank 0 prints two kinds of lines:
//! * `exchange`: the time of one `MPI_Allgatherv` in which every rank sends `bytes` (the
//!   collective a spread run makes once per window of chunks), the median of 21;
//! * `run`: a fixed-budget run of `--points` evaluations (default 2^22) of an integrand that
//!   costs about `--cost-us` microseconds (default 1), spread over the ranks, each on
//!   `--threads` threads (default 1): its wall time and evaluations per second. `--method`
//!   (default `integrator`) picks the Integrator's independent points over `[0,1]^2`, or VEGAS
//!   or VEGAS+ over `[0,1]^4` with 5 warm-up and 10 iterations of a fifteenth of the points
//!   each.

use mcint::adaptive::Vegas;
use mcint::mpi::datatype::PartitionMut;
use mcint::mpi::traits::{Communicator, CommunicatorCollectives, Root};
use mcint::{Cluster, Integrator, pdf::UniformBox};
use mcint_cli::args as support;
use mcint_cli::say;
use std::hint::black_box;
use std::time::Instant;
use support::Args;

/// What `--help` says the program does.
const ABOUT: &str = "Strong scaling over MPI ranks and the cost of one exchange between them.";

const SPEC: support::Spec = &[
    (
        "cost-us",
        true,
        "integrand cost in microseconds (default 1)",
    ),
    ("points", true, "points of the run (default 2^22)"),
    ("method", true, "integrator (default), vegas or vegas-plus"),
    support::THREADS,
];

fn main() {
    support::finish(run());
}

/// An integrand of `x` that takes `rounds` rounds of arithmetic (about 4 ns each).
fn busy(x: &[f64], rounds: u64) -> f64 {
    let mut v = x[0];
    for _ in 0..rounds {
        v = (v * 1.000_000_1 + 1e-9).sin().abs();
    }
    v
}

fn run() -> Result<(), String> {
    let args = Args::parse(ABOUT, SPEC)?;
    let cost_us: f64 = args.get("cost-us", "a positive number")?.unwrap_or(1.0);
    let points: u64 = args
        .get("points", "a whole number >= 1")?
        .unwrap_or(1 << 22);
    let threads: usize = args.get("threads", "a whole number >= 1")?.unwrap_or(1);
    let method: String = args
        .get("method", "integrator, vegas or vegas-plus")?
        .unwrap_or_else(|| "integrator".to_string());
    let stratified = match method.as_str() {
        "integrator" => None,
        "vegas" => Some(false),
        "vegas-plus" => Some(true),
        other => {
            return Err(format!(
                "invalid --method = {other}: expected integrator, vegas or vegas-plus"
            ));
        }
    };
    if !(cost_us > 0.0 && cost_us.is_finite()) {
        return Err(format!(
            "invalid --cost-us = {cost_us}: expected a positive number of microseconds"
        ));
    }
    let (_universe, _) = mcint::mpi::initialize_with_threading(mcint::mpi::Threading::Funneled)
        .ok_or("MPI was already initialized")?;
    let cluster = Cluster::world().map_err(support::flag_error)?;
    let world = mcint::mpi::topology::SimpleCommunicator::world();

    // Rank 0 calibrates the integrand's rounds; every rank uses its count.
    let mut rounds = 0u64;
    if cluster.is_root() {
        let trial = 200_000;
        let start = Instant::now();
        black_box(busy(&[0.5], trial));
        let per_round = start.elapsed().as_secs_f64() / trial as f64;
        rounds = ((cost_us * 1e-6 / per_round).round() as u64).max(1);
    }
    world.process_at_rank(0).broadcast_into(&mut rounds);

    for bytes in [64usize, 1 << 10, 16 << 10, 256 << 10, 4 << 20, 16 << 20] {
        let message = vec![1u8; bytes];
        let mut all = vec![0u8; bytes * cluster.size()];
        let counts = vec![bytes as i32; cluster.size()];
        let displacements: Vec<i32> = (0..cluster.size()).map(|r| (r * bytes) as i32).collect();
        let mut times = Vec::new();
        for _ in 0..21 {
            world.barrier();
            let start = Instant::now();
            let mut partition = PartitionMut::new(&mut all[..], &counts[..], &displacements[..]);
            world.all_gather_varcount_into(&message[..], &mut partition);
            times.push(start.elapsed().as_secs_f64());
        }
        times.sort_by(f64::total_cmp);
        if cluster.is_root() {
            say!(
                "exchange ranks={} bytes={bytes} seconds={:.3e}",
                cluster.size(),
                times[times.len() / 2]
            );
        }
    }

    let f = move |x: &[f64]| busy(x, rounds);
    world.barrier();
    let start = Instant::now();
    let estimate = match stratified {
        None => Integrator::over_box(f, UniformBox::unit(2).map_err(support::flag_error)?)
            .samples(points)
            .threads(threads)
            .cluster(cluster)
            .run(),
        Some(stratified) => Vegas::new(f, UniformBox::unit(4).map_err(support::flag_error)?)
            .stratified(stratified)
            .samples((points / 15).max(50))
            .warmup(5)
            .iterations(10)
            .threads(threads)
            .cluster(cluster)
            .run(),
    }
    .map_err(|e| e.message_with_names(&[("samples", "--points"), ("threads", "--threads")]))?;
    let seconds = start.elapsed().as_secs_f64();
    if cluster.is_root() {
        say!(
            "run method={method} ranks={} threads={threads} points={points} cost_us={cost_us} \
             seconds={seconds:.3} evaluations_per_second={:.3e} estimate={}",
            cluster.size(),
            estimate.evaluations as f64 / seconds,
            estimate.mean
        );
    }
    Ok(())
}
