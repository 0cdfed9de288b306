"""Which point set makes pick-freeze Sobol' indices accurate? Ishigami (a = 7, b = 0.1), first
order (Saltelli 2010) and total (Jansen 1999) indices, the same numpy estimator for every
point set, RMS error over seeds against the closed form:

  SALib 1.x `sobol.sample`/`sobol.analyze` (scipy's Sobol', LMS + digital shift, one sequence);
  mcint's Sobol' from the `points` binary, Owen-scrambled or LMS + shift, one sequence of N
  points or R independent scrambles of N/R points (pooled, as a replicate run pools them).

Run:  cargo build --release -p mcint-cli
      python3 -m venv /tmp/venv && /tmp/venv/bin/pip install SALib scipy numpy
      /tmp/venv/bin/python benches/peers_python/sensitivity_points.py N SEEDS
N points give N (d + 2) = 5 N model runs (N = 8192: 40,960 runs; N = 65536: 327,680).
"""
import math
import os
import subprocess
import sys

import numpy as np
from SALib.analyze import sobol as salib_analyze
from SALib.sample import sobol as salib_sample

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
POINTS = os.path.join(ROOT, "target", "release", "points")
A, B, D = 7.0, 0.1, 3


def ishigami(x):
    return np.sin(x[:, 0]) + A * np.sin(x[:, 1]) ** 2 + B * x[:, 2] ** 4 * np.sin(x[:, 0])


V = A ** 2 / 8 + B * math.pi ** 4 / 5 + B ** 2 * math.pi ** 8 / 18 + 0.5
V1 = 0.5 * (1 + B * math.pi ** 4 / 5) ** 2
V2 = A ** 2 / 8
V13 = B ** 2 * math.pi ** 8 * (1 / 18 - 1 / 50)
S1 = np.array([V1 / V, V2 / V, 0.0])
ST = np.array([(V1 + V13) / V, V2 / V, V13 / V])
PROBLEM = {"num_vars": D, "names": ["x1", "x2", "x3"], "bounds": [[-math.pi, math.pi]] * D}


def indices(fa, fb, fab):
    v = np.var(np.r_[fa, fb])
    s1 = np.mean(fb[:, None] * (fab - fa[:, None]), axis=0) / v
    st = 0.5 * np.mean((fa[:, None] - fab) ** 2, axis=0) / v
    return s1, st


def model_runs(u):
    a = -math.pi + 2 * math.pi * u[:, :D]
    b = -math.pi + 2 * math.pi * u[:, D:]
    fab = np.stack([ishigami(np.where(np.arange(D) == i, b, a)) for i in range(D)], axis=1)
    return ishigami(a), ishigami(b), fab


def mcint_points(n, seed, scramble, pass_index=0):
    out = subprocess.run(
        [POINTS, "--sampler", "sobol", "--scramble", scramble, "--dims", str(2 * D), "--n",
         str(n), "--seed", str(seed), "--pass", str(pass_index)],
        capture_output=True, text=True, check=True).stdout
    return np.loadtxt(out.splitlines(), delimiter=",")


def salib(n, seed):
    x = salib_sample.sample(PROBLEM, n, calc_second_order=False, seed=seed)
    si = salib_analyze.analyze(PROBLEM, ishigami(x), calc_second_order=False,
                               print_to_console=False, seed=seed)
    return si["S1"], si["ST"]


def mcint(n, seed, scramble, replicates):
    parts = [model_runs(mcint_points(n // replicates, seed, scramble, p))
             for p in range(replicates)]
    return indices(*(np.concatenate(column) for column in zip(*parts)))


def rms(results):
    e1 = np.array([r[0] - S1 for r in results])
    et = np.array([r[1] - ST for r in results])
    return math.sqrt(np.mean(e1 ** 2)), math.sqrt(np.mean(et ** 2))


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 8192
    seeds = range(1, (int(sys.argv[2]) if len(sys.argv) > 2 else 20) + 1)
    cases = [("SALib (scipy LMS + shift, 1 sequence)", lambda s: salib(n, s))]
    for scramble in ("lms", "owen"):
        for replicates in (1, 2, 16):
            cases.append((f"mcint {scramble}, {replicates} x {n // replicates}",
                          lambda s, c=scramble, r=replicates: mcint(n, s, c, r)))
    for name, run in cases:
        s1, st = rms([run(seed) for seed in seeds])
        print(f"N={n} ({5 * n} runs), {len(seeds)} seeds  {name:40s} RMS S1 {s1:.2e}  ST {st:.2e}",
              flush=True)


if __name__ == "__main__":
    main()
