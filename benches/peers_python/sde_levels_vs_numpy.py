"""`mcint.mlmc` on the library's SDE levels against the same run on a numpy level model.

Euler on GBM (S0 = K = 100, r = 0.05, sigma = 0.2, T = 1), a European call, refinement 2, to
an RMSE of 0.005 on one thread: once with `mcint.SdeLevels.gbm(scheme="euler")`, sampled in
Rust, and once with the numpy model of python/tests/test_mlmc.py (vectorized over each block
of samples; its Euler steps multiply out the path in one `np.prod`). Best of 3 by time; the
per-step figure divides by the fine steps the run took (each level's samples times 2^level).

Run:  /tmp/venv/bin/pip install ./python scipy pytest && /tmp/venv/bin/python benches/peers_python/sde_levels_vs_numpy.py
      (pytest: the test module it imports the model from needs it)
Output: benches/peers_python/sde_levels_vs_numpy.out.txt
"""
import math
import pathlib
import sys
import time

import mcint

# The test suite's numpy model itself, so that the bench measures what the tests check.
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "python" / "tests"))
from test_mlmc import RATE, S0, SIGMA, STRIKE, euler_call  # noqa: E402


def fine_steps(run):
    return sum(level.n * 2**level.level for level in run.levels)


def main():
    sde = mcint.SdeLevels.gbm(S0, RATE, SIGMA, scheme="euler", payoff="european", strike=STRIKE)
    cases = [
        ("numpy model", lambda: mcint.mlmc(euler_call, 0.005, dims=lambda l: 2**l, threads=1, seed=1)),
        ("SdeLevels", lambda: mcint.mlmc(sde, 0.005, threads=1, seed=1)),
    ]
    for name, run in cases:
        best, result = math.inf, None
        for _ in range(3):
            start = time.perf_counter()
            result = run()
            best = min(best, time.perf_counter() - start)
        steps = fine_steps(result)
        print(
            f"{name:<12} seconds {best:6.2f}  fine steps {steps / 1e6:6.1f} M  "
            f"ns per fine step {best * 1e9 / steps:6.1f}  estimate {result.estimate:.5f}"
        )


if __name__ == "__main__":
    main()
