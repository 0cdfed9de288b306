"""mcint's Python package against the Python peers, all from one Python process, with the
same numpy integrands:

1. Time to a 95% half-width of 1e-5 on the four 5-D Genz families of adaptive_peers.py:
   `mcint.integrate(f, ..., method="rqmc", atol=1e-5)` against scipy's `qmc_quad` (16
   scrambled Sobol' replicates, doubling) and QMCPy's `CubQMCSobolG(abs_tol=1e-5)`, with
   adaptive_peers.py's protocols; best of 5 by time, as there.
2. Time to a 1-sigma relative error of 1e-4 on the 4-D Gaussian peak of vegas_peers.py:
   `mcint.integrate(f, ..., method="vegas-plus", rtol=1.96e-4)` (its 95% half-width) against
   `vegas` 6.4.1 with a batched integrand (10 training iterations counted, then iterations
   until the combined error is below the target; its best of neval = 1e4, 1e5); medians over
   seeds 1-5, as there.

mcint runs on one thread (the peers use one core), and again with its default, every core
(the integrand is called one block at a time, but numpy releases the interpreter's lock in
its loops, and points are generated and summed on the other cores meanwhile); each line gives
its time over both: "x mcint time" against the one-thread run, "x default" against the
default run.

Run:  python3 -m venv /tmp/venv && /tmp/venv/bin/pip install ./python scipy qmcpy vegas==6.4.1
      OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 /tmp/venv/bin/python benches/peers_python/python_package_peers.py
Output: benches/peers_python/python_package_peers.out.txt
"""
import os
import statistics
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import adaptive_peers  # noqa: E402
import vegas_peers  # noqa: E402

import mcint  # noqa: E402


def best_of(repeats, run):
    """The fastest of `repeats` runs: (estimate, evaluations, seconds)."""
    best = None
    for _ in range(repeats):
        start = time.perf_counter()
        mean, evaluations = run()
        seconds = time.perf_counter() - start
        if best is None or seconds < best[2]:
            best = (mean, evaluations, seconds)
    return best


def genz(lines, repeats):
    d = adaptive_peers.D
    for family, f in adaptive_peers.FUNCTIONS.items():
        truth = adaptive_peers.exact(family)

        def ours(threads):
            r = mcint.integrate(f, [0] * d, [1] * d, atol=1e-5, seed=1, threads=threads)
            return r.mean, r.evaluations

        runs = {
            "mcint rqmc": best_of(repeats, lambda: ours(1)),
            "mcint rqmc, all cores": best_of(repeats, lambda: ours(None)),
            "scipy qmc_quad": best_of(repeats, lambda: adaptive_peers.run_qmc_quad(f, 1e-5)),
            "qmcpy CubQMCSobolG": best_of(repeats, lambda: adaptive_peers.run_qmcpy(f, 1e-5)),
        }
        mine = runs["mcint rqmc"][2]
        default = runs["mcint rqmc, all cores"][2]
        for name, (mean, evaluations, seconds) in runs.items():
            line = (f"{family:13} 5-D  {name:27} evaluations {evaluations:>11,}  seconds "
                    f"{seconds:8.4f}  |error| {abs(mean - truth):.1e}  x mcint time "
                    f"{seconds / mine:6.1f}  x default {seconds / default:6.1f}")
            print(line, flush=True)
            lines.append(line)


def vegas_peak(lines):
    family = "gaussian"
    a, u = vegas_peers.CASES[family]
    truth = vegas_peers.exact(family, a, u)
    f = vegas_peers.integrand(family, a, u)
    target = vegas_peers.RELATIVE

    def ours(seed, threads=1):
        start = time.perf_counter()
        r = mcint.integrate(f, [0] * len(a), [1] * len(a), method="vegas-plus",
                            rtol=1.96 * target, seed=seed, threads=threads)
        return r.mean, r.evaluations, time.perf_counter() - start

    runs = [("mcint vegas-plus", ours),
            ("mcint vegas-plus, all cores", lambda s: ours(s, None))]
    for neval in (10**4, 10**5):
        runs.append((f"vegas neval={neval}",
                     lambda s, n=neval: vegas_peers.run_vegas(family, a, u, n, s)))
    medians = {}
    for name, run in runs:
        results = [run(seed) for seed in range(1, 6)]
        medians[name] = (statistics.median(abs(r[0] - truth) / truth for r in results),
                         statistics.median(r[1] for r in results),
                         statistics.median(r[2] for r in results))
    mine = medians["mcint vegas-plus"][2]
    default = medians["mcint vegas-plus, all cores"][2]
    for name, (error, evaluations, seconds) in medians.items():
        line = (f"{family:13} {len(a)}-D  {name:27} evaluations {evaluations:>11,.0f}  seconds "
                f"{seconds:8.4f}  |error|/exact {error:.1e}  x mcint time {seconds / mine:6.1f}  "
                f"x default {seconds / default:6.1f}")
        print(line, flush=True)
        lines.append(line)


def main():
    import qmcpy
    import scipy
    import vegas

    repeats = 1 if "--quick" in sys.argv else 5
    lines = [f"# mcint {mcint.__version__} (Python), scipy {scipy.__version__}, qmcpy "
             f"{qmcpy.__version__}, vegas {vegas.__version__}, numpy {np.__version__}; "
             f"{os.cpu_count()} cores; {time.strftime('%Y-%m-%d')}"]
    genz(lines, repeats)
    vegas_peak(lines)
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "python_package_peers.out.txt")
    with open(path, "w") as out:
        out.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
