//! Writing reports: to stdout through [`say!`](crate::say), so that a reader that closes the pipe
//! (`| head -1`) ends the program quietly with success, and any other write error (a full
//! disk, `> /dev/full`) is one line on stderr and exit status 2, never a panic; warnings go to
//! stderr through [`note!`](crate::note), which drops what it cannot write (there is no other place left
//! to report it).

use std::io::Write;

/// `println!` to stdout, ending the program on a write error (see the module).
#[macro_export]
macro_rules! say {
    () => {
        $crate::output::line(format_args!(""))
    };
    ($($arg:tt)*) => {
        $crate::output::line(format_args!($($arg)*))
    };
}

/// `eprintln!` that never panics: a message stderr cannot take is dropped.
#[macro_export]
macro_rules! note {
    ($($arg:tt)*) => {
        $crate::output::note_line(format_args!($($arg)*))
    };
}

/// `x` with `digits` decimals (as `{}` when `None`), in exponent form outside `1e-4..1e15`
/// so that a price of `1e200` is not two hundred digits.
pub fn decimals(x: f64, digits: Option<usize>) -> String {
    let plain = x == 0.0 || !x.is_finite() || (1e-4..1e15).contains(&x.abs());
    match (plain, digits) {
        (true, Some(d)) => format!("{x:.d$}"),
        (true, None) => format!("{x}"),
        (false, Some(d)) => format!("{x:.d$e}"),
        (false, None) => format!("{x:e}"),
    }
}

/// Writes `args` and a newline to stdout (see [`say!`](crate::say)).
pub fn line(args: std::fmt::Arguments) {
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_fmt(args).and_then(|()| out.write_all(b"\n")) {
        exit_on_write_error(e);
    }
}

/// Writes `args` and a newline to stderr, ignoring a failure.
pub fn note_line(args: std::fmt::Arguments) {
    let mut err = std::io::stderr().lock();
    let _ = err.write_fmt(args).and_then(|()| err.write_all(b"\n"));
}

/// Flushes stdout, ending the program on a write error: every program calls it last, so that
/// output still buffered cannot fail unseen at exit.
pub fn flush() {
    if let Err(e) = std::io::stdout().lock().flush() {
        exit_on_write_error(e);
    }
}

/// Ends the program after a failed write to stdout or to an output file: quietly with
/// success for a closed pipe, else with one line naming the error and status 2.
pub fn exit_on_write_error(e: std::io::Error) -> ! {
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        std::process::exit(0);
    }
    fail(format!("cannot write the output: {e}"))
}

/// Prints `error: message` on one line and exits with status 2. Under `mpirun` only rank 0
/// prints: every rank runs the same command line, so would print the same error. The other
/// ranks wait (up to 30 s) before they exit: `mpirun` ends the whole job when
/// the first process fails, and a rank that failed first could take rank 0 down before its
/// line was out (seen in CI with waits of 0 and, on a loaded machine, 5 s); rank 0's own exit
/// ends their wait, so it lasts only as long as rank 0 takes to fail.
pub fn fail(message: impl std::fmt::Display) -> ! {
    if launched_rank().is_none_or(|rank| rank == 0) {
        note_line(format_args!("error: {message}"));
    } else {
        std::thread::sleep(QUIET_RANK_WAIT);
    }
    std::process::exit(2)
}

/// How long a rank other than 0 waits before it exits on an error (see [`fail`]).
const QUIET_RANK_WAIT: std::time::Duration = std::time::Duration::from_secs(30);

/// This process's rank in the job `mpirun` launched it in (from the launcher's environment:
/// Open MPI, PMIx, MPICH), known before MPI is initialized, if any.
pub fn launched_rank() -> Option<u64> {
    ["OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"]
        .iter()
        .find_map(|name| std::env::var(name).ok()?.parse().ok())
}
