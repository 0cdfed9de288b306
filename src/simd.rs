//! Run-time dispatch of the crate's hot loops (the samplers' fills, the accumulators' sums,
//! the vectorized math) to wider vector instructions.
//!
//! The kernels are plain Rust loops without loop-carried dependencies. Compiled for the
//! baseline target (SSE2 on x86-64) they vectorize poorly: SSE2 has no 32-bit lane multiply,
//! which the Owen hash needs eight times per value, nor a fast bit reversal. `dispatch` runs a
//! kernel inside a function compiled with `avx2` (or AVX-512 with GFNI, which reverses bits in
//! two instructions) enabled, chosen once per process by CPU detection, so the same loops are
//! inlined there and vectorized with 8 or 16 lanes. The AVX-512 target features need Rust
//! 1.89. The arithmetic is the same Rust code (integer operations, and floating-point
//! operations that the compiler does not reassociate or contract), so every path gives
//! bit-identical values.
//!
//! The only unsafe code of the crate is here: calling a `#[target_feature]` function, which is
//! sound once the CPU is known to have those features.
#![allow(unsafe_code)]

use std::sync::atomic::{AtomicBool, AtomicU8, Ordering};

/// A piece of work to compile once per instruction set. `run` must be `#[inline(always)]`
/// (and so must the helpers it relies on being vectorized), so that it is inlined into, and
/// compiled with the features of, each dispatching wrapper.
pub(crate) trait Kernel {
    /// What the kernel returns.
    type Output;
    /// Does the work.
    fn run(self) -> Self::Output;
}

/// Instruction sets the kernels are compiled for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Level {
    /// Whatever the crate is compiled for (SSE2 on a default x86-64 build).
    Portable = 1,
    /// AVX2: 8 lanes of 32 bits, with a lane multiply (and LZCNT, which every AVX2 CPU
    /// has: a bit scan in one instruction, for the scalar parts of the kernels).
    Avx2 = 2,
    /// AVX-512 (F, VL, BW, DQ) and GFNI: 16 lanes of 32 bits, unsigned conversions to `f64`,
    /// bit reversal by a Galois-field affine transform.
    Avx512 = 3,
}

/// The detected level, 0 until first use.
static DETECTED: AtomicU8 = AtomicU8::new(0);
/// Set by [`force_portable`].
static FORCE_PORTABLE: AtomicBool = AtomicBool::new(false);

/// The best level this CPU supports, detected once.
fn detected() -> Level {
    match DETECTED.load(Ordering::Relaxed) {
        2 => Level::Avx2,
        3 => Level::Avx512,
        1 => Level::Portable,
        _ => {
            let level = detect();
            DETECTED.store(level as u8, Ordering::Relaxed);
            level
        }
    }
}

#[cfg(target_arch = "x86_64")]
fn detect() -> Level {
    if std::arch::is_x86_feature_detected!("avx512f")
        && std::arch::is_x86_feature_detected!("lzcnt")
        && std::arch::is_x86_feature_detected!("avx512vl")
        && std::arch::is_x86_feature_detected!("avx512bw")
        && std::arch::is_x86_feature_detected!("avx512dq")
        && std::arch::is_x86_feature_detected!("gfni")
    {
        Level::Avx512
    } else if std::arch::is_x86_feature_detected!("avx2")
        && std::arch::is_x86_feature_detected!("lzcnt")
    {
        Level::Avx2
    } else {
        Level::Portable
    }
}

#[cfg(not(target_arch = "x86_64"))]
fn detect() -> Level {
    Level::Portable
}

/// The level kernels run at now.
fn level() -> Level {
    if FORCE_PORTABLE.load(Ordering::Relaxed) {
        Level::Portable
    } else {
        detected()
    }
}

/// Makes every later fill use the portable kernels (`true`) or the best ones the CPU supports
/// (`false`, the default). All give bit-identical values; this exists so that tests and
/// benchmarks can compare them. It affects the whole process.
///
/// ```
/// use mcint::Points;
/// use mcint::sampler::{Sampler, Scramble, Sobol, simd};
/// let s = Sobol::new(2, Scramble::Owen, 3).unwrap();
/// let (mut fast, mut portable) = (Points::new(2, 100).unwrap(), Points::new(2, 100).unwrap());
/// s.fill(5, &mut fast).unwrap();
/// simd::force_portable(true);
/// s.fill(5, &mut portable).unwrap();
/// simd::force_portable(false);
/// assert_eq!(fast, portable);
/// ```
pub fn force_portable(on: bool) {
    FORCE_PORTABLE.store(on, Ordering::Relaxed);
}

/// The instruction set the kernels run with now: `"avx512"`, `"avx2"` or `"portable"`.
///
/// ```
/// let name = mcint::sampler::simd::active();
/// assert!(["avx512", "avx2", "portable"].contains(&name));
/// ```
pub fn active() -> &'static str {
    match level() {
        Level::Avx512 => "avx512",
        Level::Avx2 => "avx2",
        Level::Portable => "portable",
    }
}

/// Runs `kernel` compiled for the best instruction set available.
#[inline]
pub(crate) fn dispatch<K: Kernel>(kernel: K) -> K::Output {
    match level() {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `Level::Avx512` is only chosen after `detect` found avx512f, avx512vl,
        // avx512bw, avx512dq, gfni and lzcnt on this CPU.
        Level::Avx512 => unsafe { run_avx512(kernel) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `Level::Avx2` is only chosen after `detect` found avx2 and lzcnt on this CPU.
        Level::Avx2 => unsafe { run_avx2(kernel) },
        _ => kernel.run(),
    }
}

/// `kernel` compiled with AVX2 and LZCNT.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,lzcnt")]
fn run_avx2<K: Kernel>(kernel: K) -> K::Output {
    kernel.run()
}

/// `kernel` compiled with AVX-512, GFNI and LZCNT.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq,gfni,lzcnt")]
fn run_avx512<K: Kernel>(kernel: K) -> K::Output {
    kernel.run()
}
