"""Sobol' indices at equal model runs: SALib (one scrambled Sobol' sequence, bootstrap
intervals) against mcint's `sensitivity` binary (the library's `mcint::sensitivity`), on

  ishigami   a = 7, b = 0.1, inputs uniform on [-pi, pi]^3
  sobol-g    weights (0, 1, 4.5), inputs uniform on [0, 1]^3

at 40,960 and 327,680 model runs (N = 8192 and 65536 base points, 5 runs each; no second
order). mcint runs its default (8 independent LMS-scrambled sequences of N/8 points) and one
sequence of N points (`--replicates 1`, no error bar). For every index: RMS and median error
against the closed form over the seeds, how many 95% intervals contain the exact value (mcint:
Student-t with 7 degrees of freedom on its standard errors; SALib: its bootstrap `S1_conf`,
`ST_conf`), and the median half-width over the median error. Times are medians per run:
mcint as a whole process, SALib in-process (sample, model, analyze).

Run:  cargo build --release -p mcint-cli
      python3 -m venv /tmp/venv && /tmp/venv/bin/pip install SALib scipy numpy
      /tmp/venv/bin/python benches/peers_python/sensitivity_peers.py [SEEDS]
Output: benches/peers_python/sensitivity_peers.out.txt
"""
import json
import math
import os
import statistics
import subprocess
import sys
import time

import numpy as np
from scipy.stats import t as student_t
from SALib.analyze import sobol as salib_analyze
from SALib.sample import sobol as salib_sample

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SENSITIVITY = os.path.join(ROOT, "target", "release", "sensitivity")
SEEDS = int(sys.argv[1]) if len(sys.argv) > 1 else 100
BASE_POINTS = [8192, 65536]
G_WEIGHTS = [0.0, 1.0, 4.5]


def ishigami(x, a=7.0, b=0.1):
    return np.sin(x[:, 0]) + a * np.sin(x[:, 1]) ** 2 + b * x[:, 2] ** 4 * np.sin(x[:, 0])


def ishigami_exact(a=7.0, b=0.1):
    v1 = 0.5 * (1 + b * math.pi ** 4 / 5) ** 2
    v2 = a ** 2 / 8
    v13 = b ** 2 * math.pi ** 8 * (1 / 18 - 1 / 50)
    v = v1 + v2 + v13
    return np.array([v1 / v, v2 / v, 0.0]), np.array([(v1 + v13) / v, v2 / v, v13 / v])


def g_function(x, weights=G_WEIGHTS):
    return np.prod([(np.abs(4 * x[:, i] - 2) + a) / (1 + a) for i, a in enumerate(weights)], axis=0)


def g_exact(weights=G_WEIGHTS):
    partial = np.array([1 / (3 * (1 + a) ** 2) for a in weights])
    product = np.prod(1 + partial)
    v = product - 1
    return partial / v, partial * product / (1 + partial) / v


MODELS = {
    "ishigami": (ishigami, ishigami_exact(), [[-math.pi, math.pi]] * 3, []),
    "sobol-g": (g_function, g_exact(), [[0.0, 1.0]] * 3,
                ["--weights", ",".join(str(w) for w in G_WEIGHTS)]),
}


def salib_run(model, bounds, n, seed):
    problem = {"num_vars": 3, "names": ["x1", "x2", "x3"], "bounds": bounds}
    start = time.perf_counter()
    x = salib_sample.sample(problem, n, calc_second_order=False, seed=seed)
    si = salib_analyze.analyze(problem, model(x), calc_second_order=False,
                               print_to_console=False, seed=seed)
    elapsed = time.perf_counter() - start
    return si["S1"], si["ST"], si["S1_conf"], si["ST_conf"], elapsed


def mcint_run(name, extra, n, replicates, seed):
    args = [SENSITIVITY, "--function", name, *extra, "--n", str(n // replicates),
            "--replicates", str(replicates), "--seed", str(seed), "--json"]
    start = time.perf_counter()
    out = subprocess.run(args, capture_output=True, text=True, check=True).stdout
    elapsed = time.perf_counter() - start
    report = json.loads(out)
    quantile = student_t.ppf(0.975, replicates - 1) if replicates > 1 else float("nan")

    def column(kind, key):
        return np.array([row[key] if row[key] is not None else float("nan")
                         for row in report[kind]])

    return (column("first_order", "estimate"), column("total", "estimate"),
            quantile * column("first_order", "std_error"),
            quantile * column("total", "std_error"), elapsed)


def summary(label, results, exact_s1, exact_st):
    line = [label]
    for k, exact in ((0, exact_s1), (1, exact_st)):
        errors = np.array([r[k] - exact for r in results])
        half_widths = np.array([r[k + 2] for r in results])
        rms = math.sqrt(np.mean(errors ** 2))
        median_error = np.median(np.abs(errors))
        kind = "S1" if k == 0 else "ST"
        text = f"{kind} rms {rms:.2e} median {median_error:.2e}"
        if not np.isnan(half_widths).all():
            covered = int(np.sum(np.abs(errors) <= half_widths))
            ratio = np.median(half_widths) / median_error
            text += f" covered {covered}/{errors.size} width/error {ratio:.1f}"
        line.append(text)
    line.append(f"time {statistics.median(r[4] for r in results):.3f} s")
    return " | ".join(line)


def main():
    lines = [f"seeds 0..{SEEDS - 1}; model runs = 5 N"]
    for name, (model, (exact_s1, exact_st), bounds, extra) in MODELS.items():
        for n in BASE_POINTS:
            runs = {
                "SALib 1 sequence": [salib_run(model, bounds, n, s) for s in range(SEEDS)],
                "mcint 8 replicates": [mcint_run(name, extra, n, 8, s) for s in range(SEEDS)],
                "mcint 1 sequence": [mcint_run(name, extra, n, 1, s) for s in range(SEEDS)],
            }
            for label, results in runs.items():
                line = summary(f"{name} {5 * n} runs {label}", results, exact_s1, exact_st)
                print(line, flush=True)
                lines.append(line)
    with open(os.path.join(os.path.dirname(os.path.abspath(__file__)),
                           "sensitivity_peers.out.txt"), "w") as out:
        out.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
