"""``mcint.sobol_indices``: Sobol' sensitivity indices of a vectorized model."""

import numbers

import numpy as np

from . import _native, _seed
from ._integrate import _outputs, _positive, _whole
from ._result import RunWarning
from .measure import spec_of


def sobol_indices(
    f,
    inputs,
    *,
    groups=None,
    second_order=False,
    n=None,
    replicates=None,
    rtol=None,
    atol=None,
    max_evals=None,
    time_limit=None,
    seed=None,
    threads=None,
):
    """Sobol' first-order and total indices (and, with ``second_order``, the second-order
    ones) of the model ``Y = f(X)`` with inputs ``X`` drawn from ``inputs`` (a measure of
    :mod:`mcint.measure`: ``Uniform``, ``Gaussian``, ``Lognormal``, ...), with error bars.

    The library's pick-freeze design (Saltelli et al. 2010 for first order, Jansen 1999 for
    total): ``n`` design points (default 2**16) of ``replicates`` (default 8) independently
    scrambled Sobol' sequences, the error bars from their spread. ``f`` is vectorized: it
    gets an ``(n, d)`` array of inputs (every model run of a block of design points) and
    returns ``(n,)``, or ``(n, m)`` for ``m`` outputs with indices for each. The factors
    are the inputs (the law's canonical coordinates; for a correlated Gaussian, those of its
    Cholesky ordering), or ``groups`` of them (lists of input indices). With ``rtol`` or
    ``atol`` the run grows until every index's 95% half-width is below ``max(atol, rtol *
    |index|)``, or until ``max_evals`` design points (default 2**30). An index whose value
    is 0 (an input without effect) never meets ``rtol`` alone: give ``atol`` with it, or a
    ``max_evals`` you can afford.

    Returns a :class:`SensitivityResult`.

    Examples
    --------
    >>> import numpy as np, mcint
    >>> from mcint.measure import Uniform
    >>> additive = lambda x: x[:, 0] + 2 * x[:, 1]          # variances 1/12 and 4/12
    >>> r = mcint.sobol_indices(additive, Uniform([0, 0], [1, 1]), seed=1)
    >>> np.allclose(r.first_order, [0.2, 0.8], atol=1e-3)
    True
    """
    if not callable(f):
        raise TypeError(f"invalid f = {f!r}: expected a callable taking an (n, d) array")
    spec = spec_of(inputs, "inputs")
    outputs = _outputs(f, np.array(spec.middle()))
    if groups is not None:
        groups = _groups(groups)
    seed_int = _seed.to_int(seed)
    native = _native.sobol_indices(
        f,
        spec,
        outputs,
        groups=groups,
        second_order=bool(second_order),
        n=_whole("n", n, 1),
        replicates=_whole("replicates", replicates, 1),
        rtol=_positive("rtol", rtol),
        atol=_positive("atol", atol),
        max_evals=_whole("max_evals", max_evals, 1),
        time_limit=_positive("time_limit", time_limit),
        seed=seed_int,
        threads=_whole("threads", threads, 1),
    )
    return SensitivityResult(native, outputs, seed_int, bool(second_order))


def _groups(groups):
    """``groups`` as lists of whole input indices; a flat list such as ``[0, 1]`` (or any
    group that is not a list of indices) gets a TypeError that says what is allowed, where
    iterating over it raised a bare ``'int' object is not iterable``."""
    allowed = "a list of lists of input indices, such as [[0, 1], [2]]"
    if not _is_list_like(groups):
        raise TypeError(f"invalid groups = {groups!r}: expected {allowed}")
    checked = []
    for k, group in enumerate(groups):
        if not _is_list_like(group):
            raise TypeError(
                f"invalid groups = {groups!r}: expected {allowed} (group {k} is {group!r})"
            )
        checked.append([_whole("groups", i, 0) for i in group])
    return checked


def _is_list_like(value):
    if isinstance(value, (str, bytes, dict)):
        return False
    try:
        iter(value)
    except TypeError:
        return False
    return True


class SensitivityResult:
    """Sobol' indices with their standard errors.

    For a model of one output, ``first_order``, ``total`` and their ``*_std_error`` are
    arrays with one entry per factor; for ``m`` outputs, ``(m, factors)`` arrays.
    ``second_order`` is a ``(factors, factors)`` array (``(m, factors, factors)``), NaN on
    and below the diagonal (all NaN for one factor), or ``None`` when not asked for. ``variance`` is the output's
    variance. ``points`` design points ran the model ``model_evaluations`` times.
    """

    def __init__(self, native, outputs, seed, second_order=False):
        self._native = native
        self._outputs = outputs
        self.seed = seed
        report = native.report()
        self._report = report
        self.factors = report["factors"]
        self.points = report["points"]
        self.model_evaluations = report["model_evaluations"]
        self.stop_reason = report["stop"]
        self.converged = report["converged"]
        self.warnings = [RunWarning(w["kind"], w["message"], None) for w in report["warnings"]]

        def means(key):
            return np.array([[e[0] for e in o[key]] for o in report["outputs"]], dtype=float)

        def errors(key):
            return np.array(
                [[np.nan if e[1] is None else e[1] for e in o[key]] for o in report["outputs"]],
                dtype=float,
            )

        squeeze = (lambda a: a[0]) if outputs == 1 else (lambda a: a)
        self.first_order = squeeze(means("first_order"))
        self.first_order_std_error = squeeze(errors("first_order"))
        self.total = squeeze(means("total"))
        self.total_std_error = squeeze(errors("total"))
        self.variance = squeeze(np.array([o["variance"][0] for o in report["outputs"]]))
        self.second_order = None
        if second_order:
            count = len(self.factors)
            second = np.full((len(report["outputs"]), count, count), np.nan)
            for k, o in enumerate(report["outputs"]):
                for j, l, (mean, _) in o["second_order"]:
                    second[k, j, l] = mean
            self.second_order = squeeze(second)

    def ci(self, kind="first_order", level=0.95):
        """The confidence intervals of the ``kind`` (``"first_order"``, ``"total"`` or
        ``"second_order"``) indices at ``level``: a ``(factors, 2)`` array (``(m, factors,
        2)``), or for the second order ``(factors, factors, 2)`` (``(m, ...)``) with NaN on
        and below the diagonal; NaN where an index has no error bar."""
        if not isinstance(level, numbers.Real) or not 0 < level < 1:
            raise ValueError(f"invalid level = {level!r}: expected a probability in (0, 1)")
        if kind == "second_order":
            return self._second_order_ci(float(level))
        rows = []
        for o in range(self._outputs):
            row = []
            for j in range(len(self.factors)):
                interval = self._native.interval(kind, o, j, float(level))
                row.append((np.nan, np.nan) if interval is None else interval)
            rows.append(row)
        out = np.array(rows, dtype=float)
        return out[0] if self._outputs == 1 else out

    def _second_order_ci(self, level):
        if self.second_order is None:
            raise ValueError(
                "invalid kind = 'second_order': this run has no second-order indices (ask "
                "for them with second_order=True)"
            )
        count = len(self.factors)
        out = np.full((self._outputs, count, count, 2), np.nan)
        for o, output in enumerate(self._report["outputs"]):
            for pair, (j, l, _) in enumerate(output["second_order"]):
                interval = self._native.interval("second_order", o, pair, level)
                if interval is not None:
                    out[o, j, l] = interval
        return out[0] if self._outputs == 1 else out

    def __repr__(self):
        return (
            f"SensitivityResult(first_order={np.array2string(self.first_order, precision=4)}, "
            f"total={np.array2string(self.total, precision=4)}, points={self.points})"
        )
