"""Time to |error| <= 1e-5 on the 5-D Genz Gaussian and oscillatory families for the Python
peers of `cargo bench --bench adaptive`: the vegas package (default parameters, 1e5
evaluations per iteration, after a discarded training run), scipy's qmc_quad (16 replicates of
Owen-scrambled Sobol') and QMCPy's CubQMCSobolG.

Run on one core:  OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python3 benches/peers_python/adaptive_peers.py
(needs: pip install vegas scipy qmcpy numpy). Each line: peer, family, evaluations, seconds,
|error|, the best of 5 runs by time.
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


def exact(family):
    if family == "gaussian":
        from scipy.special import erf
        return float(np.prod(math.sqrt(math.pi) / (2 * A) * (erf(A * (1 - U)) - erf(-A * U))))
    # Re of exp(i 2 pi u1) prod (exp(i a) - 1) / (i a)
    z = np.exp(2j * math.pi * U[0]) * np.prod((np.exp(1j * A) - 1) / (1j * A))
    return float(z.real)


FUNCTIONS = {"gaussian": gaussian, "oscillatory": oscillatory}


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
    while True:
        # qmc_quad passes points as an array of shape (d, n).
        res = qmc_quad(lambda x: f(x.T), np.zeros(D), np.ones(D), n_estimates=16, n_points=n,
                       qrng=qmc.Sobol(D, scramble=True, seed=1))
        # qmc_quad's standard_error is that of the mean of the 16 estimates.
        if 2.13 * res.standard_error <= target or n >= 1 << 20:
            return res.integral, 16 * n
        n *= 2


def run_qmcpy(f, target):
    import qmcpy as qp

    integrand = qp.CustomFun(qp.Uniform(qp.DigitalNetB2(D, seed=7)), g=f)
    solution, data = qp.CubQMCSobolG(integrand, abs_tol=target).integrate()
    return float(np.asarray(solution).ravel()[0]), int(np.asarray(data.n_total).ravel()[0])


def main():
    for name, runner in [("vegas", run_vegas), ("scipy_qmc_quad", run_qmc_quad),
                         ("qmcpy_CubQMCSobolG", run_qmcpy)]:
        for family, f in FUNCTIONS.items():
            best = None
            for _ in range(5):
                start = time.perf_counter()
                mean, evaluations = runner(f, 1e-5)
                seconds = time.perf_counter() - start
                if best is None or seconds < best[1]:
                    best = (evaluations, seconds, abs(mean - exact(family)))
            print(f"{name} {family} evaluations={best[0]} seconds={best[1]:.3f} error={best[2]:.2e}")


if __name__ == "__main__":
    main()
