"""mcint.expectation over the measures of mcint.measure, against closed forms."""

import numpy as np
import pytest

import mcint
from mcint.measure import BrownianMotion, Gaussian, GeometricBrownianMotion, Lognormal, Uniform

MONTHS = np.arange(1, 13) / 12


@pytest.mark.parametrize("construction", ["standard", "bridge", "pca"])
def test_the_forward_price_under_geometric_brownian_motion(construction):
    paths = GeometricBrownianMotion(100, 0.05, 0.2, MONTHS, construction)
    assert paths.d == 12
    r = mcint.expectation(lambda s: s[:, -1], paths, rtol=1e-6, seed=1)
    assert abs(r.mean - 100 * np.exp(0.05)) <= 5 * r.std_error


def test_gaussian_moments_and_their_covariance():
    g = Gaussian([1.0, 2.0], [[2.0, 0.5], [0.5, 1.0]], factorization="pca")
    r = mcint.expectation(lambda x: np.stack([x[:, 0], x[:, 0] * x[:, 1], x[:, 1] ** 2], axis=1),
                          g, rtol=1e-6, seed=2)
    # E[x0] = 1, E[x0 x1] = 0.5 + 1 * 2, E[x1^2] = 1 + 2^2.
    assert np.all(np.abs(r.mean - [1.0, 2.5, 5.0]) <= 5 * r.std_error)
    assert r.covariance.shape == (3, 3)


def test_lognormal_mean():
    r = mcint.expectation(lambda x: x[:, 0], Lognormal([0.1], [[0.04]]), rtol=1e-6, seed=3)
    assert abs(r.mean - np.exp(0.1 + 0.02)) <= 5 * r.std_error


def test_brownian_covariance_is_min_of_the_dates():
    w = BrownianMotion([0.25, 0.5, 1.0], construction="bridge")
    r = mcint.expectation(lambda x: np.stack([x[:, 0] * x[:, 2], x[:, 1] ** 2], axis=1), w,
                          rtol=1e-5, seed=4)
    assert np.all(np.abs(r.mean - [0.25, 0.5]) <= 5 * r.std_error)


def test_uniform_box_is_the_mean_over_the_box():
    r = mcint.expectation(lambda x: x[:, 0] * x[:, 1], Uniform([0, 1], [2, 3]), rtol=1e-7, seed=5)
    assert abs(r.mean - 1.0 * 2.0) <= 5 * r.std_error


def test_intervals_cover_at_the_nominal_rate():
    paths = GeometricBrownianMotion(100, 0.05, 0.3, MONTHS, "bridge")
    # The geometric average of the monthly prices has a closed form: log of it is normal
    # with mean log 100 + (r - s^2/2) mean(t) and variance s^2 mean_ij min(t_i, t_j).
    t = MONTHS
    mu = np.log(100) + (0.05 - 0.045) * t.mean()
    var = 0.09 * np.minimum.outer(t, t).mean()
    exact = np.exp(mu + var / 2)
    covered = 0
    for seed in range(100):
        r = mcint.expectation(lambda s: np.exp(np.log(s).mean(axis=1)), paths, n=512,
                              replicates=8, seed=seed)
        low, high = r.ci(0.95)
        covered += low <= exact <= high
    # Binomial(100, 0.95): 4.5 standard deviations (2.2 each) below 95 is 85.
    assert covered >= 85, covered


@pytest.mark.parametrize(
    "make, error, words",
    [
        (lambda: Gaussian([0, 0], [[1, 2], [2, 1]], "pca"), ValueError, "eigenvalue"),
        (lambda: Gaussian([0, 0], [[1, 0, 0]]), ValueError, "cov"),
        (lambda: Gaussian([0], [[1]], "lu"), ValueError, "cholesky"),
        # A singular covariance names the keyword value that takes it, not a Rust type.
        (lambda: Gaussian([0, 0], [[1, 1], [1, 1]]), ValueError,
         r"Cholesky factorization \(the pca factorization takes a singular one\)"),
        (lambda: BrownianMotion([0.5, 0.25]), ValueError, "increasing"),
        (lambda: BrownianMotion([1.0], construction="lévy"), ValueError, "bridge"),
        (lambda: GeometricBrownianMotion(-1, 0.05, 0.2, [1.0]), ValueError, "s0"),
        (lambda: Uniform([1], [0]), ValueError, "lo"),
        # Parameters are named as Python spells them, never a bare OverflowError.
        (lambda: Uniform([0, 0], [1]), ValueError, "invalid upper: expected 2 numbers"),
        (lambda: Gaussian([0, 0], [[1, 0.5], [0, 1]]), ValueError, "invalid cov = entries"),
        (lambda: BrownianMotion([1.0], drift=10**400), ValueError, "drift: expected a number"),
        (lambda: BrownianMotion([1.0], drift=None), TypeError, "drift = None"),
        (lambda: BrownianMotion([1.0], diffusion=True), TypeError, "diffusion = True"),
        (lambda: BrownianMotion([10**400]), ValueError, "times: expected numbers within"),
        (lambda: GeometricBrownianMotion(100, 0.05, np.array([0.2]), [1.0]), TypeError, "sigma"),
        # e^800 is past float64: refused when the law is built, not as NaN samples.
        (lambda: Lognormal([800.0]), ValueError, "invalid mean and cov = coordinate 0"),
        # Principal components cannot resolve variances 1e-12 and 1e6 that are correlated.
        (lambda: Gaussian([0, 0], [[1e-12, 5e-4], [5e-4, 1e6]], "pca"), ValueError,
         "use the cholesky factorization"),
        (lambda: mcint.expectation(lambda x: x[:, 0], "gaussian"), TypeError, "measure"),
        (lambda: mcint.expectation(lambda x: x[:, 0], Gaussian([0]), method="vegas"),
         ValueError, "rqmc"),
    ],
)
def test_bad_input_is_a_clear_error(make, error, words):
    with pytest.raises(error, match=words):
        make()
