//! Runs spread over MPI ranks give the bits of a one-process run.
//!
//! `cargo test --release -p mcint-cli --features mpi --test mpi` builds this file as a program that
//! launches itself under `mpirun` (Open MPI, oversubscribed, allowed to run as root) with 1, 2,
//! 3 and 4 ranks. Each rank runs every case twice, spread over the ranks and alone, and
//! compares every bit; then a checkpoint saved by 3 ranks is resumed by 2. A rank records a
//! failed comparison and goes on (leaving early would strand the others in a collective), and
//! exits non-zero at the end, which fails `mpirun` and this test. Last, the `integrate` and
//! `sensitivity` and `mlmc` programs (built with this test, `cargo test -p mcint-cli --features
//! mpi`) run with `--mpi` on 2 and 3 ranks print the one-process result.
//!
//! Set `MPIRUN` to use another launcher.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::sync::atomic::{AtomicU64, Ordering};

use mcint::adaptive::{Miser, SobolG, TwoStage, Vegas};
use mcint::mpi::traits::{Communicator, CommunicatorCollectives, Root};
use mcint::pdf::UniformBox;
use mcint::sampler::{Jittered, Scramble, Sobol};
use mcint::stats::{Derived, StopReason, Tolerance};
use mcint::{CancelToken, Cluster, Error, Integrator, NonFinitePolicy, PartialRun};

/// Set in the environment of the ranks: which part of the test to run.
const ROLE: &str = "MCINT_MPI_ROLE";
/// The checkpoint file the checkpoint roles share.
const CHECKPOINT: &str = "MCINT_MPI_CHECKPOINT";

fn main() -> ExitCode {
    match std::env::var(ROLE).as_deref() {
        Ok(role) => rank_main(role),
        Err(_) => launch(),
    }
}

/// The launcher: every case on 1-4 ranks, then a checkpoint moved from 3 ranks to 2.
fn launch() -> ExitCode {
    let mut failed = Vec::new();
    for ranks in 1..=4 {
        if !mpirun(ranks, "cases", None) {
            failed.push(format!("cases on {ranks} ranks"));
        }
    }
    let dir = std::env::temp_dir().join(format!("mcint-mpi-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let file = dir.join("checkpoint.json");
    if !(mpirun(3, "checkpoint-save", Some(&file)) && mpirun(2, "checkpoint-resume", Some(&file))) {
        failed.push("a checkpoint saved on 3 ranks, resumed on 2".to_string());
    }
    let _ = std::fs::remove_dir_all(&dir);
    for ranks in [2, 3] {
        if let Err(e) = cli_matches_one_process(ranks) {
            eprintln!("mpi: {e}");
            failed.push(format!(
                "integrate, sensitivity and mlmc --mpi on {ranks} ranks"
            ));
        }
    }
    if let Err(e) = one_error_line_from_the_job() {
        eprintln!("mpi: {e}");
        failed.push("an argument error on 3 ranks".to_string());
    }
    if failed.is_empty() {
        println!(
            "mpi: every case matched the one-process run on 1, 2, 3 and 4 ranks, and so did \
             integrate, sensitivity and mlmc --mpi on 2 and 3"
        );
        ExitCode::SUCCESS
    } else {
        eprintln!("mpi: FAILED: {}", failed.join("; "));
        ExitCode::FAILURE
    }
}

/// `mpirun -n ranks integrate --mpi ...` prints one JSON result, the one-process result with
/// `ranks` set, for a run to a tolerance and for VEGAS+; so do `sensitivity --mpi` for
/// second-order indices to a tolerance and `mlmc --mpi` for a lookback by multilevel QMC.
fn cli_matches_one_process(ranks: usize) -> Result<(), String> {
    let launcher = std::env::var("MPIRUN").unwrap_or_else(|_| "mpirun".to_string());
    let runs: [(&str, &[&str]); 4] = [
        (
            "integrate",
            &[
                "--integrand",
                "oscillatory",
                "--dims",
                "5",
                "--method",
                "rqmc",
                "--tol-abs",
                "1e-6",
            ],
        ),
        (
            "integrate",
            &[
                "--integrand",
                "gaussian,continuous",
                "--ratio",
                "1,0",
                "--dims",
                "4",
                "--method",
                "vegas-plus",
                "--n",
                "20000",
            ],
        ),
        (
            "sensitivity",
            &[
                "--function",
                "sobol-g",
                "--weights",
                "0,1,4.5",
                "--second-order",
                "--tol-abs",
                "2e-3",
            ],
        ),
        ("mlmc", &["--payoff", "lookback", "--eps", "0.02", "--qmc"]),
    ];
    for (program, flags) in runs {
        let integrate = common::example(program);
        let alone = Command::new(&integrate)
            .args(flags)
            .args(["--json", "--threads", "1"])
            .output()
            .map_err(|e| {
                format!(
                    "cannot run {} ({e}): build it with cargo build --release -p mcint-cli --features mpi",
                    integrate.display()
                )
            })?;
        let spread = Command::new(&launcher)
            .args(["--oversubscribe", "-n", &ranks.to_string()])
            .arg(&integrate)
            .args(flags)
            .args(["--json", "--threads", "1", "--mpi"])
            .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
            .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
            .output()
            .map_err(|e| format!("cannot start {launcher}: {e}"))?;
        let text = String::from_utf8_lossy(&spread.stdout);
        if !spread.status.success() || text.lines().count() != 1 {
            return Err(format!(
                "{flags:?} on {ranks} ranks: expected one JSON line from rank 0, got {text:?} ({})",
                String::from_utf8_lossy(&spread.stderr)
            ));
        }
        let parse = |bytes: &[u8]| -> serde_json::Value {
            serde_json::from_slice(bytes).unwrap_or(serde_json::Value::Null)
        };
        let (mut alone, mut spread) = (parse(&alone.stdout), parse(&spread.stdout));
        if spread["ranks"] != ranks || alone["ranks"] != 1 {
            return Err(format!(
                "{flags:?}: ranks {} and {}",
                spread["ranks"], alone["ranks"]
            ));
        }
        for json in [&mut alone, &mut spread] {
            if let Some(fields) = json.as_object_mut() {
                fields.remove("ranks");
                fields.remove("seconds");
            }
        }
        if alone != spread || alone.is_null() {
            return Err(format!(
                "{flags:?} on {ranks} ranks: {spread} differs from {alone}"
            ));
        }
    }
    Ok(())
}

/// `mpirun -n 3 integrate --mpi` with a bad argument: one error line (from rank 0), where
/// every rank printed it.
fn one_error_line_from_the_job() -> Result<(), String> {
    let launcher = std::env::var("MPIRUN").unwrap_or_else(|_| "mpirun".to_string());
    let out = Command::new(&launcher)
        .args(["--oversubscribe", "-n", "3"])
        .arg(common::example("integrate"))
        .args(["--integrand", "nope", "--dims", "2", "--mpi"])
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .output()
        .map_err(|e| format!("cannot start {launcher}: {e}"))?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    let errors = stderr.lines().filter(|l| l.starts_with("error: ")).count();
    if out.status.success() || errors != 1 {
        return Err(format!(
            "a bad argument on 3 ranks: expected one error line and a failure, got {errors}: \
             {stderr}"
        ));
    }
    Ok(())
}

/// Runs this program on `ranks` ranks in `role`; whether every rank succeeded.
fn mpirun(ranks: usize, role: &str, checkpoint: Option<&Path>) -> bool {
    let launcher = std::env::var("MPIRUN").unwrap_or_else(|_| "mpirun".to_string());
    let exe = std::env::current_exe().expect("the test's own path");
    let mut command = Command::new(&launcher);
    command
        .args(["--oversubscribe", "-n", &ranks.to_string()])
        .arg(&exe)
        .env(ROLE, role)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1");
    if let Some(file) = checkpoint {
        command.env(CHECKPOINT, file);
    }
    println!("mpi: {launcher} -n {ranks} ({role})");
    match command.status() {
        Ok(status) => status.success(),
        Err(e) => {
            eprintln!("mpi: cannot start {launcher} ({e}); install Open MPI (openmpi-bin)");
            false
        }
    }
}

/// Failed comparisons of one rank.
struct Checks {
    rank: usize,
    failures: Vec<String>,
}

impl Checks {
    fn check(&mut self, case: &str, ok: bool, detail: impl FnOnce() -> String) {
        if !ok {
            let message = format!("rank {}: {case}: {}", self.rank, detail());
            eprintln!("{message}");
            self.failures.push(message);
        }
    }

    /// Records whether `spread` and `alone` are equal, bit for bit.
    fn same<T: PartialEq + std::fmt::Debug>(&mut self, case: &str, spread: T, alone: T) {
        let ok = spread == alone;
        self.check(case, ok, || {
            format!("spread over the ranks {spread:?}\n  alone {alone:?}")
        });
    }
}

fn rank_main(role: &str) -> ExitCode {
    let (_universe, _) = mcint::mpi::initialize_with_threading(mcint::mpi::Threading::Funneled)
        .expect("MPI initializes once");
    let cluster = Cluster::world().expect("MPI is running");
    let mut checks = Checks {
        rank: cluster.rank(),
        failures: Vec::new(),
    };
    let checkpoint = std::env::var_os(CHECKPOINT).map(PathBuf::from);
    match (role, checkpoint) {
        ("cases", _) => cases(cluster, &mut checks),
        ("checkpoint-save", Some(file)) => checkpoint_save(cluster, &file, &mut checks),
        ("checkpoint-resume", Some(file)) => checkpoint_resume(cluster, &file, &mut checks),
        _ => checks.check(role, false, || "unknown role".to_string()),
    }
    if checks.failures.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

fn unit(dims: usize) -> UniformBox {
    UniformBox::unit(dims).unwrap()
}

/// A smooth 4-D integrand (the Genz Gaussian family's shape).
fn gaussian(x: &[f64]) -> f64 {
    let r2: f64 = x.iter().map(|&v| (v - 0.4) * (v - 0.4)).sum();
    (-4.0 * r2).exp()
}

fn cases(cluster: Cluster, checks: &mut Checks) {
    // Threads per rank do not matter either: one rank count runs with 2.
    let threads = if cluster.size() == 3 { 2 } else { 1 };
    let sobol = |seed| Sobol::new(4, Scramble::Owen, seed).unwrap();

    let plain = || {
        Integrator::over_box(gaussian, unit(4))
            .samples(300_000)
            .seed(11)
            .threads(threads)
    };
    checks.same("plain", plain().cluster(cluster).run(), plain().run());
    shares_the_work(cluster, checks);

    let rqmc = || {
        Integrator::over_box(gaussian, unit(4))
            .sampler(sobol(5))
            .samples(1 << 15)
            .replicates(8)
            .threads(threads)
    };
    checks.same("rqmc", rqmc().cluster(cluster).run(), rqmc().run());

    let stratified = || {
        Integrator::over_box(gaussian, unit(4))
            .sampler(Jittered::new(4, 8, 3).unwrap())
            .samples(4096 * 8)
            .replicates(4)
            .threads(threads)
    };
    checks.same(
        "stratified",
        stratified().cluster(cluster).run(),
        stratified().run(),
    );

    // A run of one chunk: every rank but one gets nothing to do.
    let tiny = || {
        Integrator::over_box(gaussian, unit(4))
            .samples(1000)
            .seed(2)
    };
    checks.same("one chunk", tiny().cluster(cluster).run(), tiny().run());

    let tolerance = Tolerance::absolute(2e-5).unwrap();
    let rqmc_tol = || {
        Integrator::over_box(gaussian, unit(4))
            .sampler(sobol(9))
            .tolerance(tolerance)
            .threads(threads)
    };
    let spread = rqmc_tol().cluster(cluster).run();
    checks.check(
        "rqmc to a tolerance",
        spread
            .as_ref()
            .is_ok_and(|e| e.stop == StopReason::ToleranceMet),
        || format!("did not meet its tolerance: {spread:?}"),
    );
    checks.same("rqmc to a tolerance", spread, rqmc_tol().run());

    let plain_tol = || {
        Integrator::over_box(gaussian, unit(4))
            .seed(4)
            .tolerance(Tolerance::absolute(1e-3).unwrap())
            .threads(threads)
    };
    checks.same(
        "plain to a tolerance",
        plain_tol().cluster(cluster).run(),
        plain_tol().run(),
    );

    let vector = || {
        let f = |x: &[f64], out: &mut [f64]| {
            out[0] = gaussian(x);
            out[1] = x[0] * gaussian(x);
        };
        Integrator::over_box_vector(2, f, unit(4))
            .sampler(sobol(13))
            .samples(1 << 14)
            .replicates(8)
            .derived_tolerance(Derived::ratio(1, 0), Tolerance::absolute(1e-4).unwrap())
            .threads(threads)
    };
    checks.same(
        "vector, a ratio to a tolerance",
        vector().cluster(cluster).run(),
        vector().run(),
    );

    for plus in [false, true] {
        let vegas = || {
            Vegas::new(gaussian, unit(4))
                .samples(20_000)
                .iterations(5)
                .stratified(plus)
                .seed(21)
                .threads(threads)
        };
        let name = if plus { "VEGAS+" } else { "VEGAS" };
        checks.same(name, vegas().cluster(cluster).run(), vegas().run());
        let to_tolerance = || vegas().tolerance(Tolerance::relative(1e-3).unwrap());
        checks.same(
            &format!("{name} to a tolerance"),
            to_tolerance().cluster(cluster).run(),
            to_tolerance().run(),
        );
    }

    let miser = || {
        Miser::new(gaussian, unit(4))
            .samples(20_000)
            .seed(8)
            .tolerance(Tolerance::absolute(1e-4).unwrap())
            .threads(threads)
    };
    checks.same(
        "MISER to a tolerance",
        miser().cluster(cluster).run(),
        miser().run(),
    );

    let two_stage = || {
        TwoStage::new(gaussian, unit(4), 3)
            .samples(50_000)
            .seed(6)
            .threads(threads)
    };
    checks.same(
        "two-stage",
        two_stage().cluster(cluster).run(),
        two_stage().run(),
    );

    let sobol_g = || {
        SobolG::new(gaussian, unit(4))
            .tolerance(Tolerance::absolute(1e-6).unwrap())
            .seed(9)
            .threads(threads)
    };
    checks.same(
        "sobol-g to a tolerance",
        sobol_g().cluster(cluster).run(),
        sobol_g().run(),
    );

    failures_on_one_rank(cluster, checks);
}

/// Each rank evaluates its share of the points only, and the shares add up to the run.
fn shares_the_work(cluster: Cluster, checks: &mut Checks) {
    let evaluations = AtomicU64::new(0);
    let counted = |x: &[f64]| {
        evaluations.fetch_add(1, Ordering::Relaxed);
        x[0]
    };
    let total = 20 * 16384;
    let run = Integrator::over_box(counted, unit(1))
        .samples(total)
        .cluster(cluster)
        .run();
    checks.check("shared work", run.is_ok(), || format!("{run:?}"));
    let mine = evaluations.load(Ordering::Relaxed);
    let mut all = vec![0u64; cluster.size()];
    mcint::mpi::topology::SimpleCommunicator::world().all_gather_into(&mine, &mut all[..]);
    let most = total.div_ceil(16384).div_ceil(cluster.size() as u64) * 16384;
    checks.check(
        "shared work",
        all.iter().sum::<u64>() == total && all.iter().all(|&n| n <= most),
        || format!("evaluations per rank {all:?}: each at most {most}, {total} in all"),
    );
}

/// An integrand that fails on the last rank only ends the run on every rank with its error.
fn failures_on_one_rank(cluster: Cluster, checks: &mut Checks) {
    // The panics below are meant: keep them off the output.
    std::panic::set_hook(Box::new(|_| {}));
    let last = cluster.size() - 1;
    let panics = |x: &[f64]| {
        assert!(cluster.rank() != last, "rank {last} cannot evaluate this");
        x[0]
    };
    let spread = Integrator::over_box(panics, unit(2))
        .samples(1 << 18)
        .cluster(cluster)
        .run();
    let expected = format!("rank {last} cannot evaluate this");
    checks.check(
        "a panic on one rank",
        matches!(&spread, Err(Error::IntegrandPanicked { message, .. }) if *message == expected),
        || format!("every rank should report the panic: {spread:?}"),
    );

    let nan = |x: &[f64]| {
        if cluster.rank() == last {
            f64::NAN
        } else {
            x[0]
        }
    };
    let spread = Integrator::over_box(nan, unit(2))
        .samples(1 << 18)
        .cluster(cluster)
        .run();
    checks.check(
        "a NaN on one rank",
        matches!(spread, Err(Error::NonFiniteContribution { .. })),
        || format!("every rank should report the NaN: {spread:?}"),
    );
    let skipped = Integrator::over_box(nan, unit(2))
        .samples(1 << 18)
        .non_finite(NonFinitePolicy::Skip)
        .cluster(cluster)
        .run();
    // Every rank has the same estimate: all ranks' result is rank 0's, gathered.
    same_everywhere(
        cluster,
        "NaN skipped on one rank",
        &format!("{skipped:?}"),
        checks,
    );

    // 100,000 points an iteration: 40 chunks in 5 groups, at least one for every rank of 4.
    let vegas = Vegas::new(panics, unit(2))
        .samples(100_000)
        .cluster(cluster)
        .run();
    checks.check(
        "a panic on one rank under VEGAS",
        matches!(&vegas, Err(Error::IntegrandPanicked { .. })),
        || format!("every rank should report the panic: {vegas:?}"),
    );

    // A flag raised on one rank is seen by every rank (what integrate --mpi --checkpoint
    // asks before stopping between steps).
    let seen = cluster.any(cluster.rank() == last);
    checks.check("a flag on one rank", matches!(seen, Ok(true)), || {
        format!("{seen:?}")
    });
    let none = cluster.any(false);
    checks.check("no flag on any rank", matches!(none, Ok(false)), || {
        format!("{none:?}")
    });

    // A run cancelled on one rank stops on every rank.
    let token = CancelToken::new();
    if cluster.rank() == last {
        token.cancel();
    }
    let cancelled = Integrator::over_box(gaussian, unit(4))
        .samples(1 << 20)
        .cancel_token(token)
        .cluster(cluster)
        .run();
    checks.check(
        "cancelled on one rank",
        matches!(
            cancelled,
            Err(Error::Interrupted {
                stop: StopReason::Cancelled,
                ..
            })
        ),
        || format!("every rank should stop: {cancelled:?}"),
    );
    let _ = std::panic::take_hook();
}

/// Records whether `text` is the same on every rank.
fn same_everywhere(cluster: Cluster, case: &str, text: &str, checks: &mut Checks) {
    let world = mcint::mpi::topology::SimpleCommunicator::world();
    let len = text.len() as i32;
    let mut lens = vec![0i32; cluster.size()];
    world.all_gather_into(&len, &mut lens[..]);
    let ok = lens.iter().all(|&l| l == len);
    let mut root = text.as_bytes().to_vec();
    world.process_at_rank(0).broadcast_into(&mut root[..]);
    checks.check(case, ok && root == text.as_bytes(), || {
        format!("differs from rank 0's: {text}")
    });
}

/// The run the checkpoint roles share: 80 chunks of RQMC.
fn checkpointed(cluster: Cluster) -> Integrator<impl mcint::Estimator> {
    Integrator::over_box(gaussian, unit(4))
        .sampler(Sobol::new(4, Scramble::Owen, 17).unwrap())
        .samples(1 << 18)
        .replicates(5)
        .label("mpi checkpoint test")
        .cluster(cluster)
}

/// 3 ranks run the first 30 chunks; rank 0 saves the part.
fn checkpoint_save(cluster: Cluster, file: &Path, checks: &mut Checks) {
    let part = checkpointed(cluster).run_part(0..30);
    checks.check("run_part", part.is_ok(), || format!("{part:?}"));
    if let (Ok(part), true) = (part, cluster.is_root()) {
        let saved = serde_json::to_string(&part).expect("a part serializes");
        std::fs::write(file, saved).expect("the checkpoint is written");
    }
}

/// 2 ranks resume the part saved by 3 and finish with the bits of one uninterrupted run.
fn checkpoint_resume(cluster: Cluster, file: &Path, checks: &mut Checks) {
    let text = std::fs::read_to_string(file).expect("rank 0 of the last job saved it");
    let mut part: PartialRun = serde_json::from_str(&text).expect("the checkpoint reads back");
    let run = checkpointed(cluster);
    while !part.is_complete() {
        if let Err(e) = run.resume(&mut part, 7) {
            checks.check("resume", false, || e.to_string());
            return;
        }
    }
    let alone = Integrator::over_box(gaussian, unit(4))
        .sampler(Sobol::new(4, Scramble::Owen, 17).unwrap())
        .samples(1 << 18)
        .replicates(5)
        .run();
    checks.same(
        "checkpoint from 3 ranks resumed on 2",
        run.finish(&part),
        alone,
    );
}
