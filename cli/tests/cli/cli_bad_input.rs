//! Generated bad command lines: for every program, 500 argument sets from a seeded
//! generator (valid flags with modest values, mixed with values outside each flag's domain,
//! junk, unknown and repeated flags, stray arguments), each run with stdout read, closed and
//! full (in turn). No run may panic, abort, hang (the guard kills it after 30 s), print more
//! than one error line, name a bad setting by the library's name instead of its flag, or exit
//! with success after printing NaN or an infinity.
//!
//! Values that are valid but large (a study of hours the user asked for) are not bad input
//! and are not generated: size pools hold modest valid values and invalid ones, and the
//! programs that take `--time-limit` always get one (valid, or itself bad). The programs run
//! in a scratch directory, so that a relative path among the values writes nothing elsewhere.
#![cfg(target_os = "linux")]

use crate::common::{self, example};
use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Argument sets per program: 4,500 command lines in all, the CLI tests' largest cost.
const SETS: usize = 500;
/// The time limit of the runs whose `--time-limit` is valid: enough for a stage or two, and
/// short, because the limit ends most of the runs that do work.
const VALID_TIME_LIMIT: &str = "0.1";
/// A run still going after this long is killed and reported as hung.
const HANG: Duration = Duration::from_secs(30);
/// The most stdout read from a run before the pipe is closed (as `head` would).
const READ_AT_MOST: u64 = 1 << 20;

/// Values outside the domain of every flag, or junk, for any flag that is not a path.
const JUNK: &[&str] = &[
    "",
    " ",
    "abc",
    "0x10",
    "1,2",
    ",",
    "-",
    "--json",
    "nan",
    "inf",
    "-inf",
    "1e400",
    "-1e400",
    "18446744073709551616",
    "-0",
    "\u{1F4A5}",
];
/// Junk for a path.
const JUNK_PATHS: &[&str] = &[
    "",
    " ",
    "/dev/zero",
    "/dev/stdout",
    "/dev/null/x",
    "{DIR}",
    "{DIR}/missing/file",
];
/// The flags that name files.
const PATHS: &[&str] = &["out", "input", "cov", "checkpoint"];

/// A flag: its name, and its valid and its invalid (or edge) values; no valid values make a
/// switch.
struct Flag {
    name: &'static str,
    valid: &'static [&'static str],
    invalid: &'static [&'static str],
}

const fn flag(
    name: &'static str,
    valid: &'static [&'static str],
    invalid: &'static [&'static str],
) -> Flag {
    Flag {
        name,
        valid,
        invalid,
    }
}

/// A program: its flags, which of them are required (given most of the time), and whether
/// it takes `--time-limit` (always given, so that no run is unbounded).
struct Program {
    name: &'static str,
    required: &'static [&'static str],
    flags: &'static [Flag],
    timed: bool,
}

const SIZES_BAD: &[&str] = &["0", "-1", "1.5", "1e19", "18446744073709551615"];
const SEEDS: &[&str] = &["0", "1", "42", "18446744073709551615", "1e3"];
const SEEDS_BAD: &[&str] = &["-1", "1.5", "1e-3"];
const THREADS: &[&str] = &["1", "2", "3"];
const THREADS_BAD: &[&str] = &["0", "-2", "1e9", "18446744073709551615"];
const SAMPLERS: &[&str] = &[
    "independent",
    "jittered",
    "latin",
    "sobol",
    "halton",
    "hammersley",
    "lattice",
    "multijitter",
    "cmj",
    "oa-bose",
    "oa-bush",
    "nrooks-multistage",
    "poisson",
    "best-candidate",
    "pmj02",
];
const SCRAMBLES: &[&str] = &["none", "xor", "lms", "owen", "permute", "shift"];
const TOLERANCES: &[&str] = &["1e-2", "1e-3", "0.5"];
const TOLERANCES_BAD: &[&str] = &["0", "-1e-3", "1e-320", "5e-324", "1e308"];
const SWITCH: &[&str] = &[];

const PROGRAMS: &[Program] = &[
    Program {
        name: "points",
        required: &["sampler", "dims", "n"],
        timed: false,
        flags: &[
            flag("sampler", SAMPLERS, &["sobol2", "Sobol"]),
            flag(
                "dims",
                &["1", "2", "3", "5", "16"],
                &["0", "-3", "100000000000", "21202", "1e19"],
            ),
            flag("n", &["1", "16", "100", "1024"], SIZES_BAD),
            flag("seed", SEEDS, SEEDS_BAD),
            flag(
                "pass",
                &["0", "1", "7"],
                &["-1", "18446744073709551615", "1e19"],
            ),
            flag("scramble", SCRAMBLES, &["owen2"]),
            flag("strength", &["2", "3", "4"], &["0", "1", "40", "-1"]),
            flag("format", &["csv", "bin", "sum", "svg", "png"], &["pdf"]),
            flag("pairs", SWITCH, SWITCH),
            flag(
                "out",
                &["{DIR}/p.svg", "{DIR}/p.png", "{DIR}/p.csv"],
                &["{DIR}", "/dev/full"],
            ),
            flag("measure", &["gaussian"], &["cauchy"]),
            flag(
                "mean",
                &["0,0", "1,2,3", "0.5", "0"],
                &["1e308,1e308", "nan,0"],
            ),
            flag(
                "cov",
                &["{DIR}/cov2.txt", "{DIR}/cov3.txt"],
                &[
                    "{DIR}/nan.csv",
                    "{DIR}/ragged.csv",
                    "{DIR}/empty.csv",
                    "{DIR}/fifo",
                ],
            ),
            flag("factorization", &["cholesky", "pca"], &["svd"]),
        ],
    },
    Program {
        name: "quality",
        required: &["input", "measure"],
        timed: false,
        flags: &[
            flag(
                "input",
                &["{DIR}/points.csv", "{DIR}/points3.csv"],
                &[
                    "{DIR}/nan.csv",
                    "{DIR}/ragged.csv",
                    "{DIR}/empty.csv",
                    "{DIR}/outside.csv",
                    "{DIR}/fifo",
                    "{DIR}/big.csv",
                ],
            ),
            flag(
                "measure",
                &[
                    "l2-star",
                    "centered",
                    "wrap-around",
                    "mixture",
                    "star",
                    "t-value",
                ],
                &["l3"],
            ),
            flag("squared", SWITCH, SWITCH),
        ],
    },
    Program {
        name: "gallery",
        required: &["out", "n", "passes", "frequency"],
        timed: false,
        flags: &[
            flag("out", &["{DIR}/g"], &["/dev/null/x", "{DIR}/points.csv"]),
            flag("n", &["16", "64", "100"], &["0", "65537", "1e7", "-4"]),
            flag("passes", &["1", "2"], &["0", "1025", "1e19"]),
            flag("frequency", &["4", "8"], &["0", "257", "1e19"]),
            flag("format", &["png", "svg"], &["gif"]),
            flag("seed", SEEDS, SEEDS_BAD),
            flag("publication", SWITCH, SWITCH),
        ],
    },
    Program {
        name: "convergence",
        required: &["out", "passes", "max-log2"],
        timed: false,
        flags: &[
            flag("out", &["{DIR}/c"], &["/dev/null/x"]),
            flag(
                "passes",
                &["8", "12"],
                &["0", "1", "2", "3", "1048577", "1e15", "1e19"],
            ),
            flag("max-log2", &["6", "7"], &["0", "5", "25", "4294967296"]),
            flag("seed", SEEDS, SEEDS_BAD),
            flag("format", &["png", "svg"], &["jpg"]),
            flag("publication", SWITCH, SWITCH),
        ],
    },
    Program {
        name: "integrate",
        required: &["integrand", "dims"],
        timed: true,
        flags: &[
            flag(
                "integrand",
                &[
                    "gaussian",
                    "oscillatory",
                    "product-peak",
                    "corner-peak",
                    "continuous",
                    "discontinuous",
                    "keister",
                    "gaussian,oscillatory",
                ],
                &["gauss", "gaussian,", "gaussian,gaussian,nope"],
            ),
            flag(
                "dims",
                &["1", "2", "3", "5"],
                &["0", "-1", "10000000", "1e19"],
            ),
            flag(
                "a",
                &["1,2", "30,30,30", "0"],
                &["-1", "1e308", "nan", "1e400,1"],
            ),
            flag("u", &["0.5", "0.1,0.9", "0,1"], &["-0.5", "2", "nan"]),
            flag("sampler", SAMPLERS, &["sobol3"]),
            flag("scramble", SCRAMBLES, &["rotate"]),
            flag("strength", &["2", "3"], &["0", "99"]),
            flag(
                "n",
                &["1", "64", "1000", "4096"],
                &["0", "-5", "1.5", "1e15", "1e19"],
            ),
            flag(
                "replicates",
                &["1", "2", "16"],
                &["0", "-1", "1e19", "18446744073709551615"],
            ),
            flag("seed", SEEDS, SEEDS_BAD),
            flag("threads", THREADS, THREADS_BAD),
            flag(
                "estimator",
                &["uniform", "importance", "mis", "control"],
                &["cv"],
            ),
            flag(
                "method",
                &[
                    "plain",
                    "rqmc",
                    "vegas",
                    "vegas-plus",
                    "miser",
                    "two-stage",
                    "sobol-g",
                ],
                &["vegas+"],
            ),
            flag("tol-abs", TOLERANCES, TOLERANCES_BAD),
            flag("tol-rel", TOLERANCES, TOLERANCES_BAD),
            flag("max-evals", &["1e5", "1000000"], &["0", "1", "1e19"]),
            flag("ratio", &["0,1", "1,0"], &["0,0", "0,5", "a,b", "-1,0"]),
            flag(
                "checkpoint",
                &["{DIR}/ck{I}.json"],
                &["{DIR}", "{DIR}/fifo", "{DIR}/nan.csv"],
            ),
            flag("save-every", &["1", "4"], &["0", "-1"]),
            flag("stop-after", &["1", "3"], &["0", "1e19"]),
            flag("json", SWITCH, SWITCH),
        ],
    },
    Program {
        name: "sensitivity",
        required: &["function"],
        timed: true,
        flags: &[
            flag("function", &["ishigami", "sobol-g"], &["g"]),
            flag("dims", &["1", "4", "8"], &["0", "127", "1e19"]),
            flag("n", &["16", "256", "1000"], &["0", "1e10", "-1"]),
            flag("replicates", &["2", "4"], &["0", "1", "1e19"]),
            flag("seed", SEEDS, SEEDS_BAD),
            flag("json", SWITCH, SWITCH),
        ],
    },
    Program {
        name: "mlmc",
        required: &[],
        timed: true,
        flags: &[
            flag("model", &["gbm", "heston"], &["cir"]),
            flag(
                "payoff",
                &["european", "asian", "lookback", "digital", "barrier"],
                &["put"],
            ),
            flag("scheme", &["euler", "milstein"], &["rk4"]),
            flag("eps", &["0.5", "0.2", "0.1"], &["0", "-1", "nan", "1e309"]),
            flag("refinement", &["2", "4"], &["1", "17", "1e19"]),
            flag("s0", &["100", "50"], &["0", "-1", "1e309"]),
            flag("sigma", &["0.2", "0.4"], &["-0.2", "nan"]),
            flag("maturity", &["1", "0.5"], &["0", "-1"]),
            flag("rho", &["-0.7", "0.3"], &["2", "-1.5"]),
            flag("min-level", &["1", "3"], &["0", "61"]),
            flag("max-level", &["3", "6"], &["0", "61", "-1"]),
            flag("test-levels", &["2", "3"], &["0", "21"]),
            flag("test-samples", &["100", "1000"], &["1", "-5"]),
            flag("seed", SEEDS, SEEDS_BAD),
            flag("qmc", SWITCH, SWITCH),
            flag("json", SWITCH, SWITCH),
        ],
    },
    Program {
        name: "asian_option",
        required: &[],
        timed: true,
        flags: &[
            flag("dates", &["1", "8", "64"], &["0", "4097", "1e19"]),
            flag("s0", &["100", "1", "1e-3"], &["0", "-1", "1e308", "5e-324"]),
            flag("strike", &["100", "50"], &["0", "-1", "1e308"]),
            flag("rate", &["0.05", "0", "-0.01"], &["1000", "-1000", "1e308"]),
            flag("sigma", &["0.2", "1"], &["0", "-0.2", "1e154", "1e308"]),
            flag("maturity", &["1", "0.25"], &["0", "-1", "1e308"]),
            flag("payoff", &["arithmetic", "geometric"], &["harmonic"]),
            flag("construction", &["standard", "bridge", "pca"], &["svd"]),
            flag(
                "sampler",
                &["sobol", "independent", "lattice", "halton"],
                &["latin"],
            ),
            flag("control", &["geometric", "none"], &["arithmetic"]),
            flag("tol-rel", TOLERANCES, TOLERANCES_BAD),
            flag("max-evals", &["1e5", "1000000"], &["0", "1e19"]),
            flag("n", &["16", "256", "4096"], &["0", "-1", "1e19"]),
            flag("replicates", &["1", "2", "16"], &["0", "1e19"]),
            flag("seed", SEEDS, SEEDS_BAD),
            flag("threads", THREADS, THREADS_BAD),
            flag("json", SWITCH, SWITCH),
            flag("table", SWITCH, SWITCH),
        ],
    },
    Program {
        name: "variance_reduction",
        required: &[],
        timed: true,
        flags: &[
            flag("n", &["4", "100", "4096"], &["0", "3", "5", "-4", "1e19"]),
            flag("seed", SEEDS, SEEDS_BAD),
        ],
    },
];

/// A seeded generator (SplitMix64): the same argument sets in every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// True with probability `p`.
    fn chance(&mut self, p: f64) -> bool {
        ((self.next() >> 11) as f64) / ((1u64 << 53) as f64) < p
    }

    fn pick<'a>(&mut self, items: &[&'a str]) -> &'a str {
        items[(self.next() % items.len() as u64) as usize]
    }
}

/// How bad one argument set is.
#[derive(Clone, Copy, PartialEq)]
enum Badness {
    /// Valid values only: the valid paths, with odd outputs and combinations.
    None,
    /// One flag with an invalid value or junk: each check alone.
    One,
    /// Any value bad 3 times in 10, and flags repeated, unknown or stray.
    Many,
}

/// A value for `flag`: valid, or (when `bad`) invalid 3 times in 4 and junk otherwise.
fn value(flag: &Flag, rng: &mut Rng, bad: bool) -> &'static str {
    if !bad {
        return rng.pick(flag.valid);
    }
    if !flag.invalid.is_empty() && rng.chance(0.75) {
        rng.pick(flag.invalid)
    } else if PATHS.contains(&flag.name) {
        rng.pick(JUNK_PATHS)
    } else {
        rng.pick(JUNK)
    }
}

/// One argument set for `program`, its `{DIR}` and `{I}` placeholders filled.
fn arguments(program: &Program, rng: &mut Rng, dir: &str, index: usize) -> Vec<String> {
    let badness = match rng.next() % 10 {
        0..4 => Badness::None,
        4..8 => Badness::One,
        _ => Badness::Many,
    };
    // Few optional flags or many: most combinations of many are refused.
    let optional = [0.05, 0.15, 0.3][(rng.next() % 3) as usize];
    let mut args: Vec<String> = Vec::new();
    let mut values = Vec::new();
    for flag in program.flags {
        let required = program.required.contains(&flag.name);
        let given = rng.chance(if required { 0.97 } else { optional });
        // The publication settings are studies of minutes unless their sizes are given.
        let heavy = flag.name == "publication"
            && program
                .required
                .iter()
                .any(|r| !args.contains(&format!("--{r}")));
        if !given || heavy {
            continue;
        }
        args.push(format!("--{}", flag.name));
        if !flag.valid.is_empty() {
            let bad = badness == Badness::Many && rng.chance(0.3);
            values.push((args.len(), flag));
            let text = value(flag, rng, bad);
            args.push(
                text.replace("{DIR}", dir)
                    .replace("{I}", &index.to_string()),
            );
        }
    }
    if badness == Badness::One && !values.is_empty() {
        let (at, flag) = values[(rng.next() % values.len() as u64) as usize];
        let text = value(flag, rng, true);
        args[at] = text
            .replace("{DIR}", dir)
            .replace("{I}", &index.to_string());
    }
    if program.timed {
        args.push("--time-limit".into());
        let bad = badness == Badness::Many && rng.chance(0.3);
        args.push(if bad {
            rng.pick(&["0", "-1", "nan", "soon", ""]).into()
        } else {
            VALID_TIME_LIMIT.into()
        });
    }
    if badness == Badness::Many {
        if rng.chance(0.2) && !args.is_empty() {
            // A flag given twice.
            let at = (rng.next() % args.len() as u64) as usize;
            if args[at].starts_with("--") {
                let repeated: Vec<String> = args[at..].iter().take(2).cloned().collect();
                args.extend(repeated);
            }
        }
        if rng.chance(0.1) {
            args.push("--no-such-flag".into());
        }
        if rng.chance(0.1) {
            args.push("stray".into());
        }
    }
    // Flags in another order mean the same.
    if rng.chance(0.2) && args.len() >= 4 {
        args.rotate_left(2);
    }
    args
}

/// Where a run's stdout goes.
#[derive(Clone, Copy, Debug)]
enum Stdout {
    /// A pipe the test reads (at most [`READ_AT_MOST`] bytes, then closes).
    Read,
    /// A pipe closed before the program writes.
    Closed,
    /// `/dev/full`.
    Full,
}

/// The exit status of one run, or what went wrong in it.
fn check(name: &str, args: &[String], mode: Stdout, dir: &Path) -> Result<i32, String> {
    let mut command = Command::new(example(name));
    command
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stderr(Stdio::piped());
    match mode {
        Stdout::Read | Stdout::Closed => command.stdout(Stdio::piped()),
        Stdout::Full => command.stdout(
            std::fs::OpenOptions::new()
                .write(true)
                .open("/dev/full")
                .expect("/dev/full"),
        ),
    };
    let mut child = command.spawn().expect("the program starts");
    let stdout = child.stdout.take();
    let reader = std::thread::spawn(move || {
        let mut seen = Vec::new();
        if let (Stdout::Read, Some(out)) = (mode, stdout) {
            let _ = out.take(READ_AT_MOST).read_to_end(&mut seen);
        }
        seen // the pipe closes here (at once when Closed)
    });
    let mut stderr = child.stderr.take().expect("stderr");
    let errors = std::thread::spawn(move || {
        let mut text = Vec::new();
        let _ = (&mut stderr).take(READ_AT_MOST).read_to_end(&mut text);
        // The rest is drained, so the program never blocks on a full stderr.
        let _ = std::io::copy(&mut stderr, &mut std::io::sink());
        String::from_utf8_lossy(&text).into_owned()
    });
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if started.elapsed() > HANG {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("hung (killed after {} s)", HANG.as_secs()));
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    let seen = reader.join().unwrap_or_default();
    let stderr = errors.join().unwrap_or_default();
    let Some(code) = status.code() else {
        return Err(format!("killed by a signal ({status}): {stderr}"));
    };
    if code == 101 || stderr.contains("panicked") {
        return Err(format!("panicked (status {code}): {stderr}"));
    }
    if code != 0 && code != 2 {
        return Err(format!("status {code}: {stderr}"));
    }
    let error_lines = stderr.lines().filter(|l| !l.starts_with("warning")).count();
    if code == 2 && error_lines != 1 {
        return Err(format!("{error_lines} error lines: {stderr}"));
    }
    // A bad setting is named as the user typed it: a flag, not the library's parameter
    // (`invalid tol_rel = ...`).
    if let Some(named) = stderr.split("error: invalid ").nth(1)
        && let Some((name, _)) = named.split_once(" = ")
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
    {
        return Err(format!("a library parameter named, not its flag: {stderr}"));
    }
    let binary = args.iter().any(|a| a == "bin" || a == "png");
    if code == 0 && !binary {
        let text = String::from_utf8_lossy(&seen);
        let bad = text
            .split(|c: char| !c.is_ascii_alphanumeric())
            .find(|word| ["NaN", "nan", "inf", "Infinity", "infinity"].contains(word));
        if let Some(word) = bad {
            return Err(format!("succeeded printing {word}: {}", tail(&text)));
        }
    }
    Ok(code)
}

/// The last lines of a long output.
fn tail(text: &str) -> String {
    let lines: Vec<&str> = text.lines().collect();
    lines[lines.len().saturating_sub(6)..].join("\n")
}

/// The files the argument sets name.
fn prepare(dir: &Path) {
    std::fs::create_dir_all(dir).unwrap();
    let write = |name: &str, text: &str| std::fs::write(dir.join(name), text).unwrap();
    let points: String = (0..64)
        .map(|i| {
            format!(
                "{},{}\n",
                (i as f64 + 0.5) / 64.0,
                ((i * 37) % 64) as f64 / 64.0
            )
        })
        .collect();
    write("points.csv", &points);
    write("points3.csv", "0.1,0.2,0.3\n0.5,0.5,0.5\n0.9,0.1,0.7\n");
    write("nan.csv", "0.1,NaN\n0.5,0.5\n");
    write("ragged.csv", "0.1,0.2\n0.5\n");
    write("empty.csv", "");
    write("outside.csv", "0.1,1.5\n");
    write("cov2.txt", "1 0\n0 1\n");
    write("cov3.txt", "2,1,0\n1,2,1\n0,1,2\n");
    std::fs::File::create(dir.join("big.csv"))
        .unwrap()
        .set_len((64 << 20) + 1)
        .unwrap();
    let _ = Command::new("mkfifo").arg(dir.join("fifo")).status();
}

#[test]
fn generated_bad_command_lines_never_panic_hang_or_print_nan() {
    let dir = common::scratch_dir("bad-input");
    prepare(&dir);
    let dir_text = dir.to_str().unwrap().to_string();
    let modes = [Stdout::Read, Stdout::Closed, Stdout::Full];
    let mut cases: Vec<(&str, Vec<String>, Stdout)> = Vec::new();
    for (p, program) in PROGRAMS.iter().enumerate() {
        let mut rng = Rng(0x6d63_696e_7400 + p as u64);
        for i in 0..SETS {
            let args = arguments(program, &mut rng, &dir_text, i);
            cases.push((program.name, args, modes[i % modes.len()]));
        }
    }
    let next = Mutex::new(0usize);
    let failures = Mutex::new(Vec::new());
    // Per program: runs that succeeded and runs refused with an error.
    let outcomes = Mutex::new(vec![(0usize, 0usize); PROGRAMS.len()]);
    let workers = std::thread::available_parallelism()
        .map_or(2, |n| n.get())
        .clamp(2, 4);
    std::thread::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|| {
                loop {
                    let i = {
                        let mut next = next.lock().unwrap();
                        *next += 1;
                        *next - 1
                    };
                    let Some((name, args, mode)) = cases.get(i) else {
                        break;
                    };
                    let program = i / SETS;
                    match check(name, args, *mode, &dir) {
                        Ok(0) => outcomes.lock().unwrap()[program].0 += 1,
                        Ok(_) => outcomes.lock().unwrap()[program].1 += 1,
                        Err(problem) => failures
                            .lock()
                            .unwrap()
                            .push(format!("{name} {args:?} (stdout {mode:?}): {problem}")),
                    }
                }
            });
        }
    });
    let _ = std::fs::remove_dir_all(&dir);
    let failures = failures.into_inner().unwrap();
    // The generator reaches both sides: runs that do their work, and runs refused.
    for (program, (done, refused)) in PROGRAMS.iter().zip(outcomes.into_inner().unwrap()) {
        println!("{}: {done} succeeded, {refused} refused", program.name);
        assert!(
            done >= SETS / 20 && refused >= SETS / 20,
            "{}: {done} runs succeeded and {refused} were refused, of {SETS}",
            program.name
        );
    }
    assert!(
        failures.is_empty(),
        "{} of {} runs went wrong; the first ones:\n{}",
        failures.len(),
        cases.len(),
        failures[..failures.len().min(25)].join("\n")
    );
}
