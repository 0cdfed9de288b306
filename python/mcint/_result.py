"""The result of ``mcint.integrate``."""

from collections import namedtuple

import numbers

import numpy as np

#: One warning of a run: its kind (``"tolerance-not-met"``, ...), its message, and the
#: output it belongs to in a run of several (``None`` otherwise).
RunWarning = namedtuple("RunWarning", ["kind", "message", "output"])


class McintWarning(UserWarning):
    """The category of the warnings ``mcint.integrate`` raises (a tolerance not met,
    iterations that disagree, non-finite values, ...)."""


class IntegrationResult:
    """What a run estimated and how it ended.

    For an integrand of one output, ``mean`` and ``std_error`` are floats; for several,
    arrays with one entry per output and ``covariance`` their covariance matrix.

    Attributes
    ----------
    mean, std_error :
        The estimate and its standard error (``None``/NaN where the run has none).
    evaluations : int
        Integrand evaluations (points) the run used.
    converged : bool or None
        Whether a run to a tolerance met it (``None`` for a fixed budget).
    stop_reason : str
        ``"budget"``, ``"tolerance met"``, ``"max evaluations"``, ``"time limit"``,
        ``"cancelled"``, ``"sampler exhausted"`` or ``"disagreement"``.
    warnings : list of RunWarning
    covariance : ndarray or None
        The outputs' covariance matrix (vector runs).
    ratio, ratio_std_error :
        The estimate of ``mean[i] / mean[j]`` and its standard error when ``ratio=(i, j)``
        was asked for.
    seed : int
        The library seed the run used (pass it back to repeat the run bit for bit).
    """

    def __init__(self, native, outputs, method, dims, seed):
        self._native = native
        self._report = native.report()
        self._outputs = outputs
        self.method = method
        self.dims = dims
        self.seed = seed
        report = self._report
        self.evaluations = report["evaluations"]
        self.converged = report["converged"]
        self.stop_reason = report["stop"]
        self.iterations = report["iterations"]
        self.warnings = [
            RunWarning(w["kind"], w["message"], w.get("output")) for w in report["warnings"]
        ]
        means = np.array(report["estimates"], dtype=float)
        errors = np.array([np.nan if e is None else e for e in report["std_errors"]], dtype=float)
        covariance = report["covariance"]
        self.covariance = None if covariance is None else np.array(covariance, dtype=float)
        if outputs == 1:
            self.mean = float(means[0])
            self.std_error = None if report["std_errors"][0] is None else float(errors[0])
        else:
            self.mean = means
            self.std_error = errors
        ratio = report.get("ratio")
        self.ratio = None if ratio is None else ratio["estimate"]
        self.ratio_std_error = None if ratio is None else ratio["std_error"]

    def ci(self, level=0.95):
        """The confidence interval at ``level`` (Student-t on the replicates' degrees of
        freedom, or normal): ``(low, high)`` for one output, an ``(m, 2)`` array for
        several; ``None`` (or NaN rows) where the run has no error bar."""
        level = _level(level)
        if self._outputs == 1:
            return self._native.interval(0, level)
        rows = [self._native.interval(k, level) for k in range(self._outputs)]
        return np.array([(np.nan, np.nan) if r is None else r for r in rows], dtype=float)

    def ratio_ci(self, level=0.95):
        """The confidence interval of the ratio at ``level`` (``ratio=(i, j)`` runs)."""
        return self._native.interval(None, _level(level))

    def to_dict(self):
        """The run as the command line's ``integrate --json`` reports it: ``estimate``,
        ``std_error``, ... for one output; ``estimates``, ``std_errors``, ``covariance``,
        ... for several."""
        r = self._report
        common = {
            "method": self.method,
            "dims": self.dims,
            "n": r["n"],
            "replicates": r["replicates"],
            "evaluations": r["evaluations"],
            "converged": r["converged"],
            "stop": r["stop"],
            "iterations": r["iterations"],
            "warnings": [dict(w) for w in r["warnings"]],
            "seed": self.seed,
        }
        if self._outputs == 1:
            return {
                "estimate": r["estimates"][0],
                "std_error": r["std_errors"][0],
                "error_bound": r["error_bounds"][0],
                "rounding_error": r["rounding_errors"][0],
                **common,
            }
        out = {
            "estimates": r["estimates"],
            "std_errors": r["std_errors"],
            "covariance": r["covariance"],
            **common,
        }
        if "ratio" in r:
            out["ratio"] = dict(r["ratio"])
        return out

    def __repr__(self):
        def show(v):
            return "None" if v is None else np.array2string(np.asarray(v), precision=10)

        return (
            f"IntegrationResult(mean={show(self.mean)}, std_error={show(self.std_error)}, "
            f"evaluations={self.evaluations}, converged={self.converged}, "
            f"stop_reason={self.stop_reason!r})"
        )


def _level(level):
    if isinstance(level, (bool, np.bool_)) or not isinstance(level, numbers.Real):
        raise TypeError(f"invalid level = {level!r}: expected a probability in (0, 1)")
    level = float(level)
    if not 0.0 < level < 1.0:
        raise ValueError(f"invalid level = {level}: expected a probability in (0, 1)")
    return level
