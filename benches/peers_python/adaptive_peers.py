"""Time to a 95% half-width of 1e-5 on the 5-D Genz Gaussian, oscillatory, product-peak and
continuous families (customary parameters) for the Python peers of `cargo bench --bench
adaptive`: scipy's qmc_quad (16 replicates of scrambled Sobol', doubling until t * SE <= 1e-5;
evaluations counted over every call, as each starts afresh),
QMCPy's CubQMCSobolG(abs_tol=1e-5) and, on the Gaussian, the vegas package (1e5 evaluations
per iteration after a discarded training run). Each run is timed inside this process around
the integration alone.

Run on one core:  OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python3 benches/peers_python/adaptive_peers.py
(needs: pip install vegas scipy qmcpy numpy). Each line: peer, family, evaluations, seconds,
|error|, the best of 5 runs by time. `--quick` runs each case once.
"""
import math
import time

import numpy as np

D = 5
A = 1.0 + 0.5 * np.arange(D)
U = 0.2 + 0.6 * np.arange(D) / (D - 1)


def gaussian(x):
    return np.exp(-np.sum((A * (x - U)) ** 2, axis=-1))


def oscillatory(x):
    return np.cos(2 * math.pi * U[0] + x @ A)


def product_peak(x):
    return np.prod(1.0 / (A ** -2.0 + (x - U) ** 2), axis=-1)


def continuous(x):
    return np.exp(-np.sum(A * np.abs(x - U), axis=-1))


def exact(family):
    if family == "gaussian":
        from scipy.special import erf
        return float(np.prod(math.sqrt(math.pi) / (2 * A) * (erf(A * (1 - U)) - erf(-A * U))))
    if family == "product-peak":
        return float(np.prod(A * (np.arctan(A * (1 - U)) + np.arctan(A * U))))
    if family == "continuous":
        return float(np.prod((2 - np.exp(-A * U) - np.exp(-A * (1 - U))) / A))
    # Re of exp(i 2 pi u1) prod (exp(i a) - 1) / (i a)
    z = np.exp(2j * math.pi * U[0]) * np.prod((np.exp(1j * A) - 1) / (1j * A))
    return float(z.real)


FUNCTIONS = {"gaussian": gaussian, "oscillatory": oscillatory, "product-peak": product_peak,
             "continuous": continuous}


def run_vegas(f, target):
    import vegas

    @vegas.lbatchintegrand
    def g(x):
        return f(x)

    integ = vegas.Integrator(D * [[0, 1]])
    integ(g, nitn=10, neval=100_000)  # training, discarded
    evaluations = 0
    # Keep adding iterations until the reported 95% half-width is below the target.
    results = []
    while True:
        r = integ(g, nitn=1, neval=100_000)
        results.append(r)
        evaluations += r.sum_neval
        w = sum(1 / x.sdev ** 2 for x in results)
        mean = sum(x.mean / x.sdev ** 2 for x in results) / w
        if 1.96 / math.sqrt(w) <= target:
            return mean, evaluations


def run_qmc_quad(f, target):
    from scipy.integrate import qmc_quad
    from scipy.stats import qmc

    n = 1 << 10
    spent = 0  # every call starts afresh: the evaluations of all of them
    while True:
        # qmc_quad passes points as an array of shape (d, n).
        res = qmc_quad(lambda x: f(x.T), np.zeros(D), np.ones(D), n_estimates=16, n_points=n,
                       qrng=qmc.Sobol(D, scramble=True, seed=1))
        spent += 16 * n
        # qmc_quad's standard_error is that of the mean of the 16 estimates.
        if 2.13 * res.standard_error <= target or n >= 1 << 21:
            return res.integral, spent
        n *= 2


def run_qmcpy(f, target):
    import qmcpy as qp

    integrand = qp.CustomFun(qp.Uniform(qp.DigitalNetB2(D, seed=7)), g=f)
    solution, data = qp.CubQMCSobolG(integrand, abs_tol=target).integrate()
    return float(np.asarray(solution).ravel()[0]), int(np.asarray(data.n_total).ravel()[0])


def main():
    import sys
    repeats = 1 if "--quick" in sys.argv else 5
    for name, runner in [("scipy_qmc_quad", run_qmc_quad), ("qmcpy_CubQMCSobolG", run_qmcpy),
                         ("vegas", run_vegas)]:
        for family, f in FUNCTIONS.items():
            if name == "vegas" and family != "gaussian":
                continue  # hours on the others (84 s per run on the oscillatory family)
            best = None
            for _ in range(repeats):
                start = time.perf_counter()
                mean, evaluations = runner(f, 1e-5)
                seconds = time.perf_counter() - start
                if best is None or seconds < best[1]:
                    best = (evaluations, seconds, abs(mean - exact(family)))
            print(f"{name} {family} evaluations={best[0]} seconds={best[1]:.4f} error={best[2]:.2e}",
                  flush=True)


if __name__ == "__main__":
    main()
