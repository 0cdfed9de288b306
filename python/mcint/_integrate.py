"""``mcint.integrate``: integrals over a box by any method of the library."""

import numbers
import warnings

import numpy as np

from . import _native, _seed
from .measure import spec_of
from ._result import IntegrationResult, McintWarning

METHODS = ("plain", "rqmc", "vegas", "vegas-plus", "miser", "two-stage", "sobol-g")


def integrate(
    f,
    lower,
    upper,
    *,
    method="rqmc",
    rtol=None,
    atol=None,
    n=None,
    replicates=None,
    max_evals=None,
    time_limit=None,
    seed=None,
    threads=None,
    sampler=None,
    scramble=None,
    ratio=None,
):
    """The integral of ``f`` over the box ``[lower, upper)``, with an honest error bar.

    Parameters
    ----------
    f : callable
        Vectorized: takes an ``(n, d)`` float64 array of points (Fortran order: each
        column contiguous) and returns ``n`` values, shape ``(n,)``, or ``n`` rows of ``m``
        outputs, shape ``(n, m)``, all integrated over the same points. It is called once
        at the box's centre to learn ``m`` (not counted in ``evaluations``), then on
        blocks of up to 8192 points (4096 for VEGAS, ``miser`` and ``two-stage``, 1024
        for ``sobol-g``; ``miser`` calls once per exploration or leaf of its tree).
    lower, upper : array_like
        The box's corners (``d`` finite values each, ``lower < upper``).
    method : str
        ``"rqmc"`` (default: Owen-scrambled Sobol' replicates), ``"plain"``, ``"vegas"``,
        ``"vegas-plus"``, ``"miser"``, ``"two-stage"`` or ``"sobol-g"``.
    rtol, atol : float, optional
        Run until the 95% interval's half-width is below ``max(atol, rtol * |mean|)``
        (either alone, or both; ``rtol`` at least 2.2e-16, the float64 epsilon).
    n : int, optional
        Points per replicate (``plain``, ``rqmc``; of the first stage with a tolerance),
        per iteration (VEGAS), per replicate (MISER), in all (``two-stage``) or in the
        first stage (``sobol-g``).
    replicates : int, optional
        Independent randomizations (``plain``, ``rqmc``, ``miser``).
    max_evals : int, optional
        The most evaluations a run to a tolerance may spend.
    time_limit : float, optional
        Seconds; the run stops with the last whole stage when they are up.
    seed : None, int, numpy.random.Generator or SeedSequence
        The same integer seed gives the same bits on any number of ``threads``.
    threads : int, optional
        Threads generating points and combining sums (default: every core). ``f`` itself
        is called under the interpreter's lock, one block at a time. A run started inside
        ``f`` (an integrand that integrates) shares the outer run's threads.
    sampler, scramble : str, optional
        The point set by name (see ``mcint.qmc.sampler_names()``) and its randomization.
    ratio : (int, int), optional
        With several outputs: estimate ``mean[i] / mean[j]`` too, and apply the tolerance
        to it.

    Returns
    -------
    IntegrationResult
        ``mean``, ``std_error``, ``ci(level)``, ``evaluations``, ``converged``,
        ``stop_reason``, ``warnings``, ``covariance``, ``to_dict()``. Its warnings are
        also raised as Python warnings of category ``mcint.McintWarning``.

    Raises
    ------
    ValueError, TypeError
        Bad parameters (the message says what is allowed).
    FloatingPointError
        ``f`` returned NaN or an infinity.
    Exception
        Whatever ``f`` raised, after the run has stopped; ``KeyboardInterrupt`` on Ctrl-C.

    Examples
    --------
    >>> import numpy as np, mcint
    >>> r = mcint.integrate(lambda x: x[:, 0] * x[:, 1], [0, 0], [1, 1], rtol=1e-6, seed=1)
    >>> abs(r.mean - 0.25) < 1e-6
    True
    """
    if not callable(f):
        raise TypeError(f"invalid f = {f!r}: expected a callable taking an (n, d) array")
    if not isinstance(method, str) or method not in METHODS:
        raise ValueError(f"invalid method = {method!r}: expected one of {', '.join(METHODS)}")
    lower = _corner("lower", lower)
    upper = _corner("upper", upper)
    if lower.shape != upper.shape:
        raise ValueError(
            f"lower has {lower.size} values and upper {upper.size}: expected one per dimension"
        )
    centre = (lower + upper) / 2
    return _run(f, lower, upper, centre, None, method, rtol, atol, n, replicates, max_evals,
                time_limit, seed, threads, sampler, scramble, ratio)


def expectation(
    f,
    measure,
    *,
    method="rqmc",
    rtol=None,
    atol=None,
    n=None,
    replicates=None,
    max_evals=None,
    time_limit=None,
    seed=None,
    threads=None,
    sampler=None,
    scramble=None,
    ratio=None,
):
    """The expectation of ``f(X)`` for ``X`` drawn from ``measure`` (see
    :mod:`mcint.measure`): a Gaussian, a lognormal, Brownian paths on given dates, geometric
    Brownian motion, a uniform box.

    ``f`` is vectorized as in :func:`integrate`: it gets an ``(n, measure.d)`` array of the
    measure's points and returns ``(n,)`` or ``(n, m)``. The points come from uniform
    (quasi-random) points mapped through the measure, so ``method`` is ``"rqmc"`` (default)
    or ``"plain"``; the other arguments and the result are those of :func:`integrate`.

    Examples
    --------
    >>> import numpy as np, mcint
    >>> from mcint.measure import GeometricBrownianMotion
    >>> paths = GeometricBrownianMotion(100, 0.05, 0.2, np.arange(1, 13) / 12, "bridge")
    >>> r = mcint.expectation(lambda s: s[:, -1], paths, rtol=1e-6, seed=1)  # E[S(1)]
    >>> bool(abs(r.mean - 100 * np.exp(0.05)) < 5 * r.std_error)
    True
    """
    if not callable(f):
        raise TypeError(f"invalid f = {f!r}: expected a callable taking an (n, d) array")
    spec = spec_of(measure, "measure")
    if method not in ("rqmc", "plain"):
        raise ValueError(
            f"invalid method = {method!r}: an expectation over a measure takes 'rqmc' or 'plain'"
        )
    cube = np.zeros(spec.canonical_dims)
    return _run(f, cube, cube + 1, np.array(spec.middle()), spec, method, rtol, atol, n,
                replicates, max_evals, time_limit, seed, threads, sampler, scramble, ratio)


def _run(f, lower, upper, probe, spec, method, rtol, atol, n, replicates, max_evals,
         time_limit, seed, threads, sampler, scramble, ratio):
    outputs = _outputs(f, probe)
    seed_int = _seed.to_int(seed)
    if ratio is not None:
        if outputs < 2:
            raise ValueError("ratio needs an integrand of at least 2 outputs, shape (n, m)")
        if isinstance(ratio, (str, bytes)) or not isinstance(ratio, (tuple, list, np.ndarray)):
            raise TypeError(f"invalid ratio = {ratio!r}: expected two output indices (i, j)")
        ratio = tuple(_whole("ratio", i, 0) for i in ratio)
        if len(ratio) != 2:
            raise ValueError(f"invalid ratio = {ratio!r}: expected two output indices (i, j)")

    native = _native.integrate_box(
        f,
        lower.tolist(),
        upper.tolist(),
        outputs,
        method,
        n=_whole("n", n, 1),
        replicates=_whole("replicates", replicates, 1),
        rtol=_positive("rtol", rtol),
        atol=_positive("atol", atol),
        max_evals=_whole("max_evals", max_evals, 1),
        time_limit=_positive("time_limit", time_limit),
        seed=seed_int,
        threads=_whole("threads", threads, 1),
        sampler=sampler,
        scramble=scramble,
        ratio=ratio,
        measure=spec,
    )
    dims = lower.size if spec is None else spec.d
    result = IntegrationResult(native, outputs, method, dims, seed_int)
    for w in result.warnings:
        where = "" if w.output is None else f"output {w.output}: "
        warnings.warn(f"{where}{w.message}", McintWarning, stacklevel=3)
    return result


def _corner(name, values):
    try:
        array = np.asarray(values, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise TypeError(f"invalid {name} = {values!r}: expected numbers, one per dimension") from None
    if array.size == 0:
        raise ValueError(f"invalid {name}: expected at least one dimension")
    return array


def _outputs(f, point):
    """The number of outputs of ``f``, from one call at ``point``."""
    y = _real_values(f(np.asfortranarray(point.reshape(1, -1))))
    if y.shape in ((1,), (1, 1)):
        return 1
    if y.ndim == 2 and y.shape[0] == 1 and y.shape[1] >= 1:
        return y.shape[1]
    raise ValueError(
        f"the integrand returned shape {y.shape} for 1 point: expected (1,) for one output "
        "or (1, m) for m outputs (it must be vectorized over the rows of an (n, d) array)"
    )


def _real_values(y):
    """What ``f`` returned, as float64: complex values are refused (numpy would drop their
    imaginary parts with a warning), and so is what is not numbers."""
    if np.iscomplexobj(y):
        raise TypeError(
            "the integrand returned complex values: expected real numbers (integrate the real "
            "and imaginary parts as two outputs, shape (n, 2))"
        )
    try:
        return np.asarray(y, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(
            f"the integrand returned {type(y).__name__} {y!r:.60}: expected an array of real "
            "numbers, shape (n,) or (n, m)"
        ) from None


def _whole(name, value, least, most=2**64 - 1):
    if value is None:
        return None
    shown = "2**64 - 1" if most == 2**64 - 1 else most
    allowed = f"a whole number {least} to {shown}"
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"invalid {name} = {value!r}: expected {allowed}")
    # Checked here, or past 2**64 the extension raises a bare OverflowError.
    if not least <= value <= most:
        raise ValueError(f"invalid {name} = {value}: expected {allowed}")
    return int(value)


def _positive(name, value):
    if value is None:
        return None
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"invalid {name} = {value!r}: expected a number above 0")
    if not (np.isfinite(value) and value > 0):
        raise ValueError(f"invalid {name} = {value}: expected a finite number above 0")
    return float(value)
