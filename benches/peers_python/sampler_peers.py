"""Generation throughput, in f64 values (coordinates) per second, of the Python peers of
`cargo bench --bench samplers` and `cargo bench --bench peers`: scipy.stats.qmc (Sobol',
Halton, Latin hypercube), QMCPy (DigitalNetB2, Halton, Lattice, each with every
randomization QMCPy 2.4 accepts) and numpy's PCG64 Generator (the raw-generator baseline,
analogous to the Rust benches' `rand_pcg` fill).

Run on one core:
    OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1 python3 benches/peers_python/sampler_peers.py
(needs: pip install scipy qmcpy numpy; about 19 minutes on the 2-core reference machine,
most of it in QMCPy's Halton at 2^20 points and in the tries of the skipped cases).

Shapes: d = 4 and d = 32 with 2^20 points per call (the `fill_{4,32}d_2^20` groups of
`--bench samplers`; every peer returns one whole (n, d) array, so compare with the `_whole`
rows), and d = 4 with 4096 points per call (the in-cache case: `fill_4d_4096` and the
`--bench peers` groups).

What is timed: one call that returns n points from index 0 of a fresh object, as the Rust
bench fills a fresh pass per iteration. `/fresh` rows include building the object (for the
scrambled generators this draws the scramble: scipy's Sobol' LMS matrices, QMCPy's LMS
matrices, permutations and shifts); a `/gen` row follows with the object built outside the
timer whenever building is at least 10% of the `/fresh` time. Deterministic generators are
rebuilt too (for scipy that is cheap and resets the sequence to index 0). numpy's Generator
is built once and keeps its stream, like the Rust `rand_pcg` baseline; `random(out=...)`
rows write into a preallocated (n, d) array, the others allocate the result.

Each measurement is the best of 5 runs; a run repeats the call until it has taken 0.2 s (so
the 4096-point calls are not timer noise) and every call has a new seed. Before the runs, the
call is tried as a warm-up at n / 256 points (at least 64), then 4 times more up to n; a case
whose n-point call would take more than 20 s (linear extrapolation from the last try) is
skipped and its row says so with the estimate.

Names: scipy's Sobol(scramble=True) is a linear matrix scramble plus a digital shift (LMS+DS,
as scipy documents; `random_base2(m)` is `random(2^m)` with a power-of-2 check); scipy's
Halton(scramble=True) permutes the digits of each base (a random digit permutation per
dimension). QMCPy 2.4 spells randomizations with spaces ('LMS DS') and maps '_' to ' '; its
DigitalNetB2 accepts LMS DS (default), LMS, DS, NUS (alias OWEN), FALSE; its Halton accepts
LMS DP (default, alias LMS PERM), LMS DS, LMS, DP (alias PERM), DS, NUS (alias OWEN), QRNG,
FALSE; its Lattice accepts SHIFT (default) and FALSE.

Output: one line per measurement, `peer  case  d  n  values_per_second` (or `skipped ...`).
"""
import gc
import math
import time
import warnings

import numpy as np
import qmcpy as qp
import scipy
from scipy.stats import qmc

SKIP_SECONDS = 20.0
RUN_SECONDS = 0.2
RUNS = 5
SHAPES = [(4, 1 << 20), (32, 1 << 20), (4, 4096)]


def qmc_cases(d):
    """(peer, case, build(seed), generate(obj, n)) for every QMC peer at dimension d."""
    cases = []
    for scramble in (True, False):
        cases.append(("scipy.Sobol", f"scramble={scramble}",
                      lambda s, sc=scramble: qmc.Sobol(d, scramble=sc, seed=s),
                      lambda o, n: o.random(n)))
    for scramble in (True, False):
        cases.append(("scipy.Halton", f"scramble={scramble}",
                      lambda s, sc=scramble: qmc.Halton(d, scramble=sc, seed=s),
                      lambda o, n: o.random(n)))
    cases.append(("scipy.LatinHypercube", "default", lambda s: qmc.LatinHypercube(d, seed=s),
                  lambda o, n: o.random(n)))
    gen = lambda o, n: o.gen_samples(n, warn=False)  # noqa: E731 (warn: n_min = 0 without DS)
    for r in ["LMS DS", "LMS", "DS", "NUS", "FALSE"]:
        cases.append(("qmcpy.DigitalNetB2", r.replace(" ", "_"),
                      lambda s, r=r: qp.DigitalNetB2(d, seed=s, randomize=r), gen))
    for r in ["LMS DP", "LMS DS", "LMS", "DP", "DS", "NUS", "QRNG", "FALSE"]:
        cases.append(("qmcpy.Halton", r.replace(" ", "_"),
                      lambda s, r=r: qp.Halton(d, seed=s, randomize=r), gen))
    for r in ["SHIFT", "FALSE"]:
        cases.append(("qmcpy.Lattice", r, lambda s, r=r: qp.Lattice(d, seed=s, randomize=r), gen))
    return cases


def one_call(build, generate, n, seed):
    """Seconds to build the object and to generate n points, and the output shape."""
    gc.collect()  # so freeing the previous call's objects is not charged to this one
    t0 = time.perf_counter()
    obj = build(seed)
    t1 = time.perf_counter()
    x = generate(obj, n)
    t2 = time.perf_counter()
    shape = x.shape
    del x, obj
    return t1 - t0, t2 - t1, shape


def probe(build, generate, d, n):
    """Warm up at growing sizes; the extrapolated seconds of one n-point call, and the size
    the estimate came from."""
    m = max(n >> 8, 64)
    seed = 1000
    while True:
        b, g, shape = one_call(build, generate, m, seed)
        seed += 1
        assert shape == (m, d), shape
        estimate = (b + g) * n / m
        if m == n or estimate > SKIP_SECONDS or (b + g) * 4 > SKIP_SECONDS:
            return estimate, m
        m = min(4 * m, n)


def measure_qmc(peer, case, build, generate, d, n):
    estimate, m = probe(build, generate, d, n)
    if estimate > SKIP_SECONDS:
        print(f"{peer}  {case}/fresh  {d}  {n}  skipped: ~{estimate:.0f} s per call "
              f"(> {SKIP_SECONDS:.0f} s, extrapolated from {m} points)", flush=True)
        return
    calls = max(1, math.ceil(RUN_SECONDS / max(estimate, 1e-9)))
    best_fresh = best_gen = math.inf
    seed = 0
    for _ in range(RUNS):
        fresh = gen = 0.0
        for _ in range(calls):
            b, g, _ = one_call(build, generate, n, seed)
            seed += 1
            fresh += b + g
            gen += g
        best_fresh = min(best_fresh, fresh / calls)
        best_gen = min(best_gen, gen / calls)
    print(f"{peer}  {case}/fresh  {d}  {n}  {d * n / best_fresh:.3e}", flush=True)
    if best_fresh >= 1.1 * best_gen:
        print(f"{peer}  {case}/gen  {d}  {n}  {d * n / best_gen:.3e}", flush=True)


def measure_numpy(d, n):
    rng = np.random.Generator(np.random.PCG64(0xCAFEF00D))
    out = np.empty((n, d))
    for case, call in [("random((n,d))", lambda: rng.random((n, d))),
                       ("random((d,n))", lambda: rng.random((d, n))),
                       ("random(out=(n,d))", lambda: rng.random(out=out))]:
        call()  # warm-up
        t0 = time.perf_counter()
        call()
        calls = max(1, math.ceil(RUN_SECONDS / (time.perf_counter() - t0)))
        best = math.inf
        for _ in range(RUNS):
            gc.collect()
            t0 = time.perf_counter()
            for _ in range(calls):
                call()
            best = min(best, (time.perf_counter() - t0) / calls)
        print(f"numpy.PCG64  {case}  {d}  {n}  {d * n / best:.3e}", flush=True)


def main():
    warnings.simplefilter("ignore")
    start = time.perf_counter()
    print(f"# python sampler peers: scipy {scipy.__version__}, qmcpy {qp.__version__}, "
          f"numpy {np.__version__}")
    print("# peer  case  d  n  values_per_second")
    for d, n in SHAPES:
        measure_numpy(d, n)
        for peer, case, build, generate in qmc_cases(d):
            measure_qmc(peer, case, build, generate, d, n)
    print(f"# total run time: {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
