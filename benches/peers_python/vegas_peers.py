"""Evaluations and time to the same relative error: Lepage's `vegas` (6.4.1) against mcint's
`vegas-plus` and `vegas` on sharp Genz peaks and a two-peak integrand:

  gaussian     4-D, a = 20, 25, 30, 35, u = 0.3, 0.6, 0.7, 0.2
  product-peak 6-D, a = 20, 24, 28, 32, 36, 40, u = 0.3, 0.6, 0.7, 0.2, 0.4, 0.7
  two-peak     8-D, two Genz Gaussians with a_i = 10, at u = 0.3, 0.6, 0.7, 0.2, 0.4, 0.7,
               0.3, 0.8 and at 1 - u

to a 1-sigma relative error of 1e-4 (1e-3 for the two peaks; mcint: `--tol-rel` 1.96 times
that, its 95% half-width). The peer trains its grid with 10 iterations (discarded, counted),
then adds iterations of the same size until the combined 1-sigma error is below the target;
it runs at 10^4, 10^5 and 10^6 evaluations per iteration, and the table keeps each size, so
the best one is visible. Every evaluation counts, training included. Medians over seeds 1-5
(`vegas` seeds numpy's and its own generator with `ran_array_generator`). mcint runs as the
`integrate` binary, or, for the two peaks (which `integrate` does not offer), through its
Python package with the same numpy integrand as the peer.

Run:  python3 -m venv /tmp/venv && /tmp/venv/bin/pip install vegas==6.4.1 numpy ./python
      cargo build --release -p mcint-cli
      OMP_NUM_THREADS=1 /tmp/venv/bin/python benches/peers_python/vegas_peers.py
Output: benches/peers_python/vegas_peers.out.txt (one line per peer, case and setting:
median evaluations, median seconds, median |error| / exact, and median |error| over the
target, the error in units of the 1-sigma error the runs stopped at).
"""
import json
import math
import os
import statistics
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
INTEGRATE = os.path.join(ROOT, "target", "release", "integrate")
RELATIVE = 1e-4
SEEDS = range(1, 6)
CASES = {
    "gaussian": ([20.0, 25.0, 30.0, 35.0], [0.3, 0.6, 0.7, 0.2]),
    "product-peak": ([20.0, 24.0, 28.0, 32.0, 36.0, 40.0], [0.3, 0.6, 0.7, 0.2, 0.4, 0.7]),
    "two-peak": ([10.0] * 8, [0.3, 0.6, 0.7, 0.2, 0.4, 0.7, 0.3, 0.8]),
}
# The two peaks take about a hundred times the evaluations of the others to the same error.
TARGETS = {"gaussian": RELATIVE, "product-peak": RELATIVE, "two-peak": 10 * RELATIVE}


def integrand(family, a, u):
    a, u = np.array(a), np.array(u)
    if family == "gaussian":
        return lambda x: np.exp(-np.sum((a * (x - u)) ** 2, axis=-1))
    if family == "two-peak":
        return lambda x: (np.exp(-np.sum((a * (x - u)) ** 2, axis=-1))
                          + np.exp(-np.sum((a * (x - 1 + u)) ** 2, axis=-1)))
    return lambda x: np.prod(1.0 / (a ** -2.0 + (x - u) ** 2), axis=-1)


def exact(family, a, u):
    a, u = np.array(a), np.array(u)
    if family == "gaussian":
        from math import erf
        return float(np.prod([math.sqrt(math.pi) / (2 * ai) * (erf(ai * (1 - ui)) + erf(ai * ui))
                              for ai, ui in zip(a, u)]))
    if family == "two-peak":
        # Each peak's box integral is symmetric under u -> 1 - u: twice one Gaussian's.
        return 2 * exact("gaussian", a, u)
    return float(np.prod(a * (np.arctan(a * (1 - u)) + np.arctan(a * u))))


def run_vegas(family, a, u, neval, seed, target=RELATIVE):
    import vegas
    f = integrand(family, a, u)

    @vegas.lbatchintegrand
    def g(x):
        return f(x)

    np.random.seed(seed)
    gen = np.random.default_rng(seed)
    vegas.ran_array_generator = gen.random
    start = time.perf_counter()
    integ = vegas.Integrator(len(a) * [[0, 1]])
    training = integ(g, nitn=10, neval=neval)
    evaluations = training.sum_neval
    results = []
    while True:
        r = integ(g, nitn=1, neval=neval)
        results.append(r)
        evaluations += r.sum_neval
        w = sum(1 / x.sdev ** 2 for x in results)
        mean = sum(x.mean / x.sdev ** 2 for x in results) / w
        if 1 / math.sqrt(w) <= target * abs(mean):
            return mean, evaluations, time.perf_counter() - start


def run_mcint(family, a, u, method, seed, target=RELATIVE):
    if family == "two-peak":
        import mcint
        start = time.perf_counter()
        r = mcint.integrate(integrand(family, a, u), [0] * len(a), [1] * len(a), method=method,
                            rtol=1.96 * target, seed=seed, threads=1)
        return r.mean, r.evaluations, time.perf_counter() - start
    out = subprocess.run(
        [INTEGRATE, "--integrand", family, "--dims", str(len(a)),
         "--a", ",".join(map(str, a)), "--u", ",".join(map(str, u)), "--method", method,
         "--tol-rel", str(1.96 * target), "--seed", str(seed), "--threads", "1", "--json"],
        check=True, capture_output=True, text=True).stdout
    r = json.loads(out)
    return r["estimate"], r["evaluations"], r["seconds"]


def main():
    import vegas
    lines = [f"# vegas {vegas.__version__}, numpy {np.__version__}; 1-sigma relative errors "
             f"{TARGETS}; medians over seeds {SEEDS.start}-{SEEDS.stop - 1}; one thread"]
    for family, (a, u) in CASES.items():
        truth = exact(family, a, u)
        target = TARGETS[family]
        runs = [(f"mcint {m}", lambda s, m=m: run_mcint(family, a, u, m, s, target))
                for m in ("vegas-plus", "vegas")]
        for neval in (10**4, 10**5, 10**6):
            runs.append((f"vegas neval={neval}",
                         lambda s, n=neval: run_vegas(family, a, u, n, s, target)))
        for name, run in runs:
            results = [run(seed) for seed in SEEDS]
            evaluations = statistics.median(r[1] for r in results)
            seconds = statistics.median(r[2] for r in results)
            error = statistics.median(abs(r[0] - truth) / truth for r in results)
            line = (f"{family:13} {len(a)}-D  {name:22} evaluations {evaluations:>12,.0f}  "
                    f"seconds {seconds:8.3f}  |error|/exact {error:.1e}  "
                    f"in sigmas {error / target:6.1f}")
            print(line, flush=True)
            lines.append(line)
    with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "vegas_peers.out.txt"),
              "w") as out:
        out.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    sys.exit(main())
