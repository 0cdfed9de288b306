"""Measures to take expectations over: ``mcint.expectation(f, measure)`` averages ``f`` over
points drawn from them by (randomized quasi-) Monte Carlo, the points built from canonical
uniform points by inverse cdfs and factorizations, so that QMC points stay QMC points."""

import numpy as np

from . import _native
from ._check import real

__all__ = ["Gaussian", "Lognormal", "BrownianMotion", "GeometricBrownianMotion", "Uniform"]


def _floats(name, values, ndim):
    try:
        array = np.asarray(values, dtype=np.float64)
    except OverflowError:
        raise ValueError(
            f"invalid {name}: expected numbers within float64 (magnitude below about 1.8e308)"
        ) from None
    except (TypeError, ValueError):
        raise TypeError(f"invalid {name} = {values!r}: expected numbers") from None
    if array.ndim != ndim:
        raise ValueError(f"invalid {name}: expected {ndim}-dimensional numbers, got shape {array.shape}")
    return array


def spec_of(measure, name):
    """The native measure of ``measure``, or a TypeError naming the argument ``name``."""
    spec = getattr(measure, "_spec", None)
    if not isinstance(spec, _native.MeasureSpec):
        raise TypeError(
            f"invalid {name} = {measure!r}: expected a measure of mcint.measure (Gaussian, "
            "Lognormal, BrownianMotion, GeometricBrownianMotion, Uniform)"
        )
    return spec


class _Measure:
    _spec = None

    @property
    def d(self):
        """The dimension of the measure's points."""
        return self._spec.d

    @property
    def canonical_dims(self):
        """Uniform coordinates one point takes."""
        return self._spec.canonical_dims

    def __repr__(self):
        return f"{type(self).__name__}(d={self.d})"


class Gaussian(_Measure):
    """The normal law with ``mean`` and covariance ``cov`` (default the identity), its
    points ``mean + L z`` with ``L`` the Cholesky factor (``factorization="cholesky"``) or the
    principal components (``"pca"``: the first coordinates carry the most variance, which
    suits QMC; accepts a singular ``cov``)."""

    _kind = "gaussian"

    def __init__(self, mean, cov=None, factorization="cholesky"):
        mean = _floats("mean", mean, 1)
        cov = np.eye(mean.size) if cov is None else _floats("cov", cov, 2)
        if cov.shape != (mean.size, mean.size):
            raise ValueError(f"invalid cov: expected shape {(mean.size, mean.size)}, got {cov.shape}")
        build = getattr(_native.MeasureSpec, self._kind)
        self._spec = build(mean.tolist(), cov.reshape(-1).tolist(), factorization)


class Lognormal(Gaussian):
    """``exp`` of the normal law with ``mean`` and ``cov``, coordinate by coordinate."""

    _kind = "lognormal"


class BrownianMotion(_Measure):
    """``drift t + diffusion W(t)`` on the dates ``times`` (increasing, above 0), built by
    ``construction`` ``"standard"`` (increments in time order), ``"bridge"`` (the endpoint
    first, then midpoints) or ``"pca"`` (principal components first)."""

    def __init__(self, times, drift=0.0, diffusion=1.0, construction="standard"):
        times = _floats("times", times, 1)
        self._spec = _native.MeasureSpec.brownian(
            times.tolist(), real("drift", drift), real("diffusion", diffusion), construction
        )


class GeometricBrownianMotion(_Measure):
    """Prices ``S(t) = s0 exp((rate - sigma^2 / 2) t + sigma W(t))`` on the dates ``times``."""

    def __init__(self, s0, rate, sigma, times, construction="standard"):
        times = _floats("times", times, 1)
        self._spec = _native.MeasureSpec.geometric_brownian(
            real("s0", s0), real("rate", rate), real("sigma", sigma), times.tolist(), construction
        )


class Uniform(_Measure):
    """The uniform law on the box ``[lower, upper)``."""

    def __init__(self, lower, upper):
        lower, upper = _floats("lower", lower, 1), _floats("upper", upper, 1)
        if lower.size != upper.size:
            raise ValueError(
                f"invalid upper: expected {lower.size} numbers, one per number of lower, "
                f"got {upper.size}"
            )
        self._spec = _native.MeasureSpec.uniform(lower.tolist(), upper.tolist())
