"""mcint.integrate: every method, honest intervals, determinism, errors, signals, memory."""

import _thread
import resource
import threading
import time
import warnings

import numpy as np
import pytest
from scipy import stats

import mcint
from genz import genz_families

# The integral of exp(-|x|^2) over [0, 1)^3: (sqrt(pi)/2 erf(1))^3.
GAUSS_3D = (np.sqrt(np.pi) / 2 * 0.8427007929497149) ** 3


def gauss(x):
    return np.exp(-np.sum(x * x, axis=1))


@pytest.mark.parametrize("method", mcint.METHODS)
def test_every_method_lands_within_five_standard_errors(method):
    n = 2000 if method.startswith("vegas") else 4096
    r = mcint.integrate(gauss, [0] * 3, [1] * 3, method=method, n=n, seed=3)
    assert r.stop_reason == "budget" and r.converged is None
    assert r.evaluations >= n
    if method == "sobol-g":  # a deterministic bound from Walsh coefficients, no std error
        assert abs(r.mean - GAUSS_3D) <= r.to_dict()["error_bound"]
    else:
        assert abs(r.mean - GAUSS_3D) <= 5 * r.std_error, r


@pytest.mark.parametrize(
    "method, rtol", [("rqmc", 1e-6), ("plain", 1e-3), ("vegas", 1e-3), ("miser", 1e-2), ("sobol-g", 1e-6)]
)
def test_a_tolerance_is_met_and_said(method, rtol):
    r = mcint.integrate(gauss, [0] * 3, [1] * 3, method=method, rtol=rtol, seed=1)
    assert r.converged is True and r.stop_reason == "tolerance met"
    assert abs(r.mean - GAUSS_3D) <= 5 * rtol * GAUSS_3D


@pytest.mark.parametrize("family", ["gaussian", "product-peak", "oscillatory", "continuous"])
def test_rqmc_intervals_cover_at_the_nominal_rate(family):
    f, exact = genz_families(5)[family]
    seeds, covered = 100, 0
    for seed in range(seeds):
        r = mcint.integrate(lambda x: f(x.T), [0] * 5, [1] * 5, n=256, replicates=8, seed=seed)
        low, high = r.ci(0.95)
        covered += low <= exact <= high
    # Binomial(100, 0.95): mean 95, standard deviation 2.2; 4.5 of them below is 85.
    assert covered >= 85, f"{family}: {covered} of {seeds}"


def test_the_same_seed_gives_the_same_bits_on_any_thread_count():
    runs = [
        mcint.integrate(gauss, [0] * 3, [1] * 3, rtol=1e-5, seed=9, threads=t).to_dict()
        for t in (1, 2, 3, 8)
    ]
    assert all(run == runs[0] for run in runs)
    vegas = [
        mcint.integrate(gauss, [0] * 3, [1] * 3, method="vegas", n=500, seed=9, threads=t).mean
        for t in (1, 3)
    ]
    assert vegas[0] == vegas[1]


@pytest.mark.parametrize("method", ["miser", "two-stage"])
def test_miser_and_two_stage_call_f_on_blocks_with_the_bits_of_any_thread_count(method):
    sizes = []

    def counted(x):
        sizes.append(len(x))
        return gauss(x)

    runs = [
        mcint.integrate(counted, [0] * 3, [1] * 3, method=method, n=50_000, seed=4, threads=t)
        for t in (1, 3)
    ]
    assert runs[0].to_dict() == runs[1].to_dict()
    # MISER: one call per exploration or leaf (each at least 16 d = 48 points); two-stage:
    # blocks of up to 4,096 points gathered across its strata. Per point, it would be
    # 1 call per evaluation.
    calls = len(sizes) // 2 - 1  # one run's calls, less the probe of the output count
    assert max(sizes) <= 4096
    assert calls <= runs[0].evaluations / 48, (calls, runs[0].evaluations)


def test_vector_outputs_covariance_and_ratio():
    def moments(x):
        return np.stack([x[:, 0], x[:, 0] ** 2, x[:, 1] ** 3], axis=1)

    r = mcint.integrate(moments, [0, 0], [1, 1], rtol=1e-5, ratio=(1, 0), seed=4)
    assert r.mean.shape == (3,) and r.std_error.shape == (3,)
    assert np.all(np.abs(r.mean - [1 / 2, 1 / 3, 1 / 4]) <= 5 * r.std_error)
    assert r.covariance.shape == (3, 3)
    assert np.allclose(r.covariance, r.covariance.T)
    assert np.allclose(np.diag(r.covariance), r.std_error**2)
    low, high = r.ratio_ci(0.95)
    assert low <= r.ratio <= high
    assert abs(r.ratio - 2 / 3) <= 5 * r.ratio_std_error
    assert r.ci(0.9).shape == (3, 2)
    keys = {"estimates", "std_errors", "covariance", "ratio", "evaluations", "converged", "stop"}
    assert keys <= set(r.to_dict())


def test_result_dict_has_the_cli_json_keys():
    d = mcint.integrate(gauss, [0] * 3, [1] * 3, n=1024, seed=0).to_dict()
    for key in ("estimate", "std_error", "error_bound", "n", "replicates", "evaluations",
                "converged", "stop", "iterations", "rounding_error", "warnings", "method", "dims"):
        assert key in d, key
    assert d["method"] == "rqmc" and d["dims"] == 3 and d["stop"] == "budget"


def test_an_unmet_tolerance_warns_and_says_so():
    with pytest.warns(mcint.McintWarning, match="tolerance"):
        r = mcint.integrate(gauss, [0] * 3, [1] * 3, atol=1e-12, max_evals=1 << 14, seed=1)
    assert r.converged is False and r.stop_reason == "max evaluations"
    assert any(w.kind == "tolerance-not-met" for w in r.warnings)


def test_an_exception_in_f_propagates_as_itself_after_the_run_stops():
    calls = []

    def broken(x):
        calls.append(len(x))
        if len(calls) > 3:
            raise ZeroDivisionError("boom")
        return gauss(x)

    with pytest.raises(ZeroDivisionError, match="boom"):
        mcint.integrate(broken, [0] * 3, [1] * 3, n=1 << 20, replicates=8, threads=2, seed=0)
    # Stopped within a chunk: far fewer calls than the 8 M points would take.
    assert len(calls) < 200


def test_keyboard_interrupt_cancels_the_run():
    calls = []

    def interrupted(x):
        calls.append(len(x))
        if len(calls) == 5:
            _thread.interrupt_main()  # as Ctrl-C does
        return gauss(x)

    with pytest.raises(KeyboardInterrupt):
        mcint.integrate(interrupted, [0] * 3, [1] * 3, n=1 << 22, replicates=16, seed=0)
    assert len(calls) < 2000  # of 65,536 blocks


def test_the_lock_is_released_while_the_run_goes_on():
    # A Python thread keeps running while mcint integrates on the main thread: it ticks
    # between the integrand's calls, not only before and after the run.
    ticks, calls = [], []
    stop = threading.Event()

    def ticker():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            stop.wait(0.001)

    def timed(x):
        calls.append(time.perf_counter())
        return gauss(x)

    thread = threading.Thread(target=ticker)
    thread.start()
    try:
        mcint.integrate(timed, [0] * 3, [1] * 3, n=1 << 18, replicates=8, seed=0, threads=1)
    finally:
        stop.set()
        thread.join()
    during = [t for t in ticks if calls[1] < t < calls[-1]]  # calls[0] is the shape probe
    assert len(during) > 1, (len(ticks), len(calls))


# numpy's divide-by-zero warning is raised on the thread that calls f.
@pytest.mark.filterwarnings("ignore::RuntimeWarning")
def test_non_finite_values_are_a_floating_point_error():
    with pytest.raises(FloatingPointError, match="non-finite"):
        mcint.integrate(lambda x: 1 / (x[:, 0] - x[:, 0]), [0], [1], n=64, seed=0)


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        (dict(method="simpson"), ValueError, "rqmc"),
        (dict(lower=[0, 0], upper=[1]), ValueError, "one per dimension"),
        (dict(lower=[1, 0], upper=[0, 1]), ValueError, "lo < hi"),
        (dict(lower=[0, 0], upper=[1, np.inf]), ValueError, "finite"),
        (dict(rtol=-1.0), ValueError, "rtol"),
        (
            dict(rtol=1e-20),
            ValueError,
            "rtol = 1e-20: expected a relative tolerance of at least 2.2e-16",
        ),
        (dict(atol=np.nan), ValueError, "atol"),
        (dict(rtol="small"), TypeError, "number"),
        (dict(n=0), ValueError, "n = 0"),
        (dict(method="vegas", n=3), ValueError, "invalid n = 3: expected at least 50"),
        (dict(n=1.5), TypeError, "whole number"),
        # Past 2**64 the extension would raise a bare OverflowError.
        (
            dict(n=2**64),
            ValueError,
            r"invalid n = 18446744073709551616: expected a whole number 1 to 2\*\*64 - 1",
        ),
        (dict(rtol=1e-3, max_evals=2**70), ValueError, "max_evals"),
        (dict(threads=0), ValueError, "threads"),
        (dict(max_evals=1000), ValueError, "rtol or atol"),
        (dict(time_limit=-1.0), ValueError, "time_limit"),
        (dict(seed=-3), ValueError, "seed"),
        (dict(ratio=(0, 1)), ValueError, "2 outputs"),
        (dict(method="rqmc", sampler="independent"), ValueError, "randomized"),
        (dict(sampler="sobel"), ValueError, "sobol"),
        (dict(method="vegas", replicates=4), ValueError, "replicates"),
        (dict(method="two-stage", rtol=1e-3), ValueError, "fixed budget"),
        (dict(method="sobol-g", sampler="halton"), ValueError, "own"),
        (dict(f=lambda x: x.ravel()), ValueError, "shape"),
        (dict(f=lambda x: x.sum()), ValueError, "shape"),
        (dict(f=3), TypeError, "callable"),
        # numpy dropped the imaginary parts, with a ComplexWarning only.
        (dict(f=lambda x: x[:, 0] + 1j), TypeError, "complex values"),
        (dict(f=lambda x: (v for v in x[:, 0])), TypeError, "returned generator"),
        (dict(f=lambda x: x, ratio=5), TypeError, r"ratio = 5: expected two output indices"),
    ],
)
def test_bad_input_is_a_clear_error(kwargs, error, words):
    args = dict(f=gauss, lower=[0, 0], upper=[1, 1], n=64, seed=0)
    args.update(kwargs)
    with pytest.raises(error, match=words):
        mcint.integrate(**args)


def test_a_wrong_shape_later_on_is_an_error_too():
    def sometimes(x):
        return gauss(x) if len(x) == 1 else gauss(x)[:-1]

    with pytest.raises(ValueError, match="shape"):
        mcint.integrate(sometimes, [0] * 3, [1] * 3, n=4096, seed=0)

    def complex_later(x):
        return gauss(x) if len(x) == 1 else gauss(x) + 0j

    with pytest.raises(TypeError, match="complex values"):
        mcint.integrate(complex_later, [0] * 3, [1] * 3, n=4096, seed=0)


def test_no_memory_growth_over_ten_thousand_calls():
    def run():
        mcint.integrate(gauss, [0] * 3, [1] * 3, n=32, replicates=8, seed=1, threads=1)

    for _ in range(500):  # allocator pools reach their steady size
        run()
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    for _ in range(10_000):
        run()
    grown_kib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before
    # A leak of even 1 KiB a call would be 10 MB.
    assert grown_kib < 4096, f"peak memory grew by {grown_kib} KiB"


def test_intervals_use_the_replicates_degrees_of_freedom():
    with pytest.warns(mcint.McintWarning, match="only 4 replicates"):
        r = mcint.integrate(gauss, [0] * 3, [1] * 3, n=256, replicates=4, seed=2)
    low, high = r.ci(0.95)
    t = stats.t.ppf(0.975, df=3)
    assert (high - low) / 2 == pytest.approx(t * r.std_error, rel=1e-12)
    with pytest.raises(ValueError, match="level"):
        r.ci(1.5)
    # Not a number: said so (it was "could not convert string to float").
    for level in ("abc", np.array([0.9, 0.95]), True):
        with pytest.raises(TypeError, match="expected a probability"):
            r.ci(level)


NESTED = """
import mcint
def inner_mean():
    return mcint.integrate(lambda y: y[:, 0], [0], [1], n=1024, replicates=8, seed=1).mean
def outer(x):
    return x[:, 0] * inner_mean()
r = mcint.integrate(outer, [0], [1], n=1024, replicates=8, seed=2, threads={threads})
print(r.mean, r.std_error, inner_mean())
"""


@pytest.mark.parametrize("threads", [1, 2, 4])
def test_an_integrand_that_integrates_runs_on_the_outer_runs_threads(threads):
    # The inner run once waited for pool threads that were all inside the outer run's
    # integrand, waiting for it: a deadlock (Ctrl-C did not end it). The timeout only keeps
    # a regression from hanging the suite.
    import subprocess
    import sys

    out = subprocess.run(
        [sys.executable, "-c", NESTED.format(threads=threads)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert out.returncode == 0, out.stderr
    mean, std_error, inner = map(float, out.stdout.split())
    # The integral of x c over [0, 1] is c / 2, with c the inner run's mean (the same run
    # every time: its seed is fixed).
    assert abs(mean - inner / 2) <= 5 * std_error, out.stdout
