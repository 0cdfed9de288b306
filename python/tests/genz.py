"""Four Genz families on the unit cube with their exact integrals (closed forms), shared
by the tests. Each function takes points as scipy's qmc_quad passes them: shape (d, n)."""

from math import erf, pi, sqrt

import numpy as np


def genz_families(d):
    """Four Genz families on [0, 1)^d with their exact integrals (closed forms)."""
    a = 1.0 + 0.5 * np.arange(d)
    u = 0.2 + 0.6 * np.arange(d) / (d - 1)

    def gaussian(x):
        return np.exp(-np.sum((a * (np.atleast_2d(x.T) - u)) ** 2, axis=1))

    gaussian_exact = np.prod(
        [sqrt(pi) / (2 * ai) * (erf(ai * (1 - ui)) + erf(ai * ui)) for ai, ui in zip(a, u)]
    )

    def product_peak(x):
        return np.prod(1.0 / (a**-2 + (np.atleast_2d(x.T) - u) ** 2), axis=1)

    peak_exact = np.prod([ai * (np.arctan(ai * (1 - ui)) + np.arctan(ai * ui)) for ai, ui in zip(a, u)])

    def oscillatory(x):
        return np.cos(2 * pi * u[0] + np.sum(a * np.atleast_2d(x.T), axis=1))

    # The real part of e^{i 2 pi u_0} prod (e^{i a_k} - 1) / (i a_k).
    z = np.exp(2j * pi * u[0]) * np.prod([(np.exp(1j * ai) - 1) / (1j * ai) for ai in a])
    oscillatory_exact = z.real

    def continuous(x):
        return np.exp(-np.sum(a * np.abs(np.atleast_2d(x.T) - u), axis=1))

    continuous_exact = np.prod(
        [(2 - np.exp(-ai * ui) - np.exp(-ai * (1 - ui))) / ai for ai, ui in zip(a, u)]
    )
    return {
        "gaussian": (gaussian, gaussian_exact),
        "product-peak": (product_peak, peak_exact),
        "oscillatory": (oscillatory, oscillatory_exact),
        "continuous": (continuous, continuous_exact),
    }
