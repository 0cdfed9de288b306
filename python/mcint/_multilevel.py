"""``mcint.mlmc``: multilevel Monte Carlo (Giles 2008) of a vectorized model."""

import numbers
import warnings
from collections import namedtuple

import numpy as np

from . import _native, _seed
from ._check import real
from ._integrate import _positive, _whole
from ._result import McintWarning, RunWarning

#: The statistics of one level: ``level``, samples ``n``, ``mean`` and ``variance`` of
#: ``P_l - P_{l-1}``, the ``std_error`` of that mean, the ``cost`` of a sample, the mean and
#: variance of ``P_l`` alone, the ``kurtosis`` of the correction and Giles' consistency
#: ``check`` (``None`` where they cannot be formed).
LevelSummary = namedtuple(
    "LevelSummary",
    ["level", "n", "mean", "variance", "std_error", "cost", "fine_mean", "fine_variance",
     "kurtosis", "check"],
)

# The library's deepest level by default (Multilevel::max_level).
_DEFAULT_MAX_LEVEL = 20
# The deepest level any run or survey may ask for (the library's limit).
_DEEPEST_LEVEL = 60

_PAYOFFS = ("european", "asian", "lookback", "digital", "barrier")


class SdeLevels:
    """The levels of an option price under a stochastic differential equation, built into
    the library: :func:`mlmc` and :func:`mlmc_survey` sample them in Rust, with no call into
    Python (what the command line's ``mlmc`` runs).

    Level ``l`` steps a path on ``M**l`` steps of ``T / M**l`` (``M = refinement``), its
    coarse path on ``M**(l-1)`` steps driven by the sums of ``M`` fine Brownian increments
    (Giles 2008), both built from the canonical point by a Brownian bridge (so multilevel
    QMC pays off). The payoff is discounted by ``exp(-rate * maturity)``: ``european`` and
    ``asian`` (arithmetic average over the steps) calls at ``strike``, ``lookback``
    (floating strike), ``digital`` (pays 1 above ``strike``) and ``barrier`` (a down-and-out
    call knocked out at ``barrier``; the lookback and the barrier sample each step's minimum
    from its Brownian bridge). Build one with :meth:`gbm` or :meth:`heston`.

    Examples
    --------
    >>> import mcint
    >>> call = mcint.SdeLevels.gbm(100.0, 0.05, 0.2, payoff="european", strike=100.0)
    >>> call
    SdeLevels(model='gbm', payoff='european', scheme='milstein', refinement=2, maturity=1.0)
    >>> r = mcint.mlmc(call, 0.01, seed=7)
    >>> abs(r.estimate - 10.450583572185565) < 0.04  # Black-Scholes
    True
    """

    __slots__ = ("_native",)

    def __init__(self, native):
        if not isinstance(native, _native.SdeModel):
            raise TypeError(
                "SdeLevels is built with SdeLevels.gbm(...) or SdeLevels.heston(...)"
            )
        self._native = native

    @classmethod
    def gbm(
        cls,
        s0=100.0,
        rate=0.05,
        sigma=0.2,
        *,
        payoff="european",
        strike=None,
        barrier=None,
        maturity=1.0,
        scheme="milstein",
        refinement=2,
    ):
        """Geometric Brownian motion ``dS = rate S dt + sigma S dW`` from ``s0`` (above 0;
        ``sigma`` at least 0), to ``maturity`` (above 0), under the ``milstein`` (default;
        strong order 1) or ``euler`` scheme.

        ``strike`` (default 100) is taken by every payoff but ``lookback``, and ``barrier``
        (default 85) by ``barrier`` alone; ``refinement``, the factor ``M`` between levels,
        is 2 to 16 (default 2).

        >>> import mcint
        >>> mcint.SdeLevels.gbm(payoff="barrier", barrier=90.0, scheme="euler").scheme
        'euler'
        """
        strike, barrier = _strike_and_barrier(payoff, strike, barrier)
        return cls(_native.SdeModel.gbm(
            real("s0", s0), real("rate", rate), real("sigma", sigma), payoff, strike,
            barrier, real("maturity", maturity), _name("scheme", scheme),
            _refinement(refinement),
        ))

    @classmethod
    def heston(
        cls,
        s0=100.0,
        v0=0.04,
        rate=0.05,
        kappa=2.0,
        theta=0.04,
        xi=0.3,
        rho=-0.7,
        *,
        payoff="european",
        strike=None,
        barrier=None,
        maturity=1.0,
        scheme="euler",
        refinement=2,
    ):
        """Heston's stochastic volatility model, ``dS = rate S dt + sqrt(v) S dW_1``,
        ``dv = kappa (theta - v) dt + xi sqrt(v) dW_2`` with ``corr(dW_1, dW_2) = rho`` (in
        ``[-1, 1]``), from ``(s0, v0)``, stepped with full truncation (``v`` enters the
        coefficients as ``max(v, 0)``). Euler only: its noise does not commute, so Milstein
        would need the Levy areas. The payoff keywords are :meth:`gbm`'s.

        >>> import mcint
        >>> h = mcint.SdeLevels.heston(rho=-0.5, payoff="asian")
        >>> (h.model, h.payoff, h.scheme)
        ('heston', 'asian', 'euler')
        """
        if scheme != "euler":
            raise ValueError(
                f"invalid scheme = {scheme!r}: expected 'euler' (Heston's noise does not "
                "commute, so the library has no Milstein scheme for it)"
            )
        strike, barrier = _strike_and_barrier(payoff, strike, barrier)
        return cls(_native.SdeModel.heston(
            real("s0", s0), real("v0", v0), real("rate", rate), real("kappa", kappa),
            real("theta", theta), real("xi", xi), real("rho", rho), payoff, strike,
            barrier, real("maturity", maturity), scheme, _refinement(refinement),
        ))

    @property
    def model(self):
        """``'gbm'`` or ``'heston'``."""
        return self._native.model

    @property
    def payoff(self):
        """The payoff's name."""
        return self._native.payoff

    @property
    def scheme(self):
        """``'euler'`` or ``'milstein'``."""
        return self._native.scheme

    @property
    def refinement(self):
        """The refinement factor ``M`` between levels."""
        return self._native.refinement

    @property
    def maturity(self):
        """The maturity ``T``."""
        return self._native.maturity

    def __repr__(self):
        return (
            f"SdeLevels(model={self.model!r}, payoff={self.payoff!r}, "
            f"scheme={self.scheme!r}, refinement={self.refinement}, "
            f"maturity={self.maturity!r})"
        )


def _name(name, value):
    if not isinstance(value, str):
        raise TypeError(f"invalid {name} = {value!r}: expected a name (a string)")
    return value


def _refinement(value):
    value = _whole("refinement", value, 2, 16)
    if value is None:
        raise TypeError("invalid refinement = None: expected a whole number 2 to 16")
    return value


def _strike_and_barrier(payoff, strike, barrier):
    """The strike and barrier the payoff takes (their defaults when not given); a keyword
    the payoff would ignore is refused, so that no run prices another option than the one
    described."""
    if payoff not in _PAYOFFS:
        raise ValueError(
            f"invalid payoff = {payoff!r}: expected 'european', 'asian', 'lookback', "
            "'digital' or 'barrier'"
        )
    if payoff == "lookback" and strike is not None:
        raise ValueError("strike does not apply to payoff='lookback' (a floating strike)")
    if payoff != "barrier" and barrier is not None:
        raise ValueError(f"barrier applies to payoff='barrier' only, not {payoff!r}")
    strike = 100.0 if strike is None else real("strike", strike)
    barrier = 85.0 if barrier is None else real("barrier", barrier)
    return strike, barrier


def mlmc(
    level,
    rmse,
    *,
    dims=None,
    cost=None,
    refinement=None,
    weak_order=None,
    qmc=False,
    replicates=None,
    initial_samples=None,
    min_level=None,
    max_level=None,
    max_cost=None,
    time_limit=None,
    seed=None,
    threads=None,
):
    """The expectation of a model's finest approximation by multilevel Monte Carlo (Giles
    2008; multilevel QMC with ``qmc=True``, Giles and Waterhouse 2009), to a root-mean-square
    error ``rmse``: levels are added until the estimated bias is small, and samples are
    spread over the levels to minimize the cost.

    Parameters
    ----------
    level : callable or SdeLevels
        ``level(l, u)`` gives the samples of level ``l`` from ``u``, an ``(n, dims(l))``
        float64 array of canonical points in ``[0, 1)`` (independent uniforms, or a
        scrambled Sobol' sequence with ``qmc``; map them to normals with, say,
        ``scipy.special.ndtri``): a pair ``(fine, coarse)`` of ``(n,)`` arrays, ``P_l`` and
        ``P_{l-1}`` of each sample computed from the same coordinates (at level 0, the
        coarse values are 0). It is called on blocks of up to 4096 samples. Or an
        :class:`SdeLevels`, the library's own option-pricing levels, sampled in Rust
        (``dims``, ``cost``, ``refinement`` and ``weak_order`` are then its own).
    rmse : float
        The target root-mean-square error (above 0).
    dims : int or callable
        The coordinates one sample of level ``l`` takes: a number for every level, or
        ``dims(l)`` (required with a callable ``level``). Put the ones that matter most
        first (a Brownian bridge does that).
    cost : callable, optional
        ``cost(l)``, the cost of one sample of level ``l`` in any fixed unit (default
        ``refinement ** l``, time steps of a path refined by ``refinement`` per level).
    refinement : int
        The refinement factor ``M`` between levels (default 2).
    weak_order : float, optional
        The known weak order ``alpha`` of the scheme (estimated from the levels otherwise).
    qmc : bool
        Multilevel QMC: each level's samples are ``replicates`` scrambled Sobol' sequences.
    replicates, initial_samples, min_level, max_level, max_cost :
        The run's settings (defaults: 32 randomizations per level with ``qmc``; 1000
        initial samples of levels ``0..=min_level``, 8 per randomization with ``qmc``;
        levels 0 to 2 at least and 20 at most; a cost limit of 1e12).
    time_limit : float, optional
        Seconds after which the run stops with what it has (the result says so).
    seed, threads :
        The seed (an integer, a ``numpy.random.Generator`` or ``SeedSequence``; fresh
        entropy when ``None``) and the worker threads (the result does not depend on them).

    Returns a :class:`MultilevelResult`; each of its warnings (a tolerance not met, a bias
    above its target at the deepest level, heavy-tailed or inconsistent levels) is also
    raised as a :class:`McintWarning`.

    Examples
    --------
    A toy model whose level ``l`` adds a bias of ``2**-l`` to ``E[U^2] = 1/3``:

    >>> import numpy as np, mcint
    >>> def level(l, u):
    ...     p = lambda k: u[:, 0] ** 2 + 0.5 ** k
    ...     return p(l), (p(l - 1) if l > 0 else np.zeros(len(u)))
    >>> r = mcint.mlmc(level, 1e-3, dims=1, seed=1)
    >>> abs(r.estimate - 1 / 3) < 4e-3, r.converged
    (True, True)
    """
    rmse = _positive("rmse", rmse)
    if rmse is None:
        raise TypeError("invalid rmse = None: expected a number above 0")
    result = _run(
        level, rmse, None, dims, cost, refinement, weak_order, qmc, replicates,
        initial_samples, min_level, _whole("max_level", max_level, 1, _DEEPEST_LEVEL), max_cost,
        time_limit, seed, threads,
    )
    for w in result.warnings:
        warnings.warn(w.message, McintWarning, stacklevel=2)
    return result


def mlmc_survey(
    level,
    levels,
    samples,
    *,
    dims=None,
    cost=None,
    refinement=None,
    weak_order=None,
    qmc=False,
    replicates=None,
    time_limit=None,
    seed=None,
    threads=None,
):
    """Giles' ``mlmc_test`` survey of a model before a run: ``samples`` samples (per
    randomization with ``qmc``) of every level ``0..=levels``, with each level's mean,
    variance, cost, kurtosis and consistency check, and the fitted rates ``alpha``,
    ``beta`` and ``gamma`` (:func:`mlmc` takes the same ``level``, ``dims``, ``cost``,
    ``refinement``, ``weak_order``, ``qmc``, ``replicates``, ``time_limit``, ``seed`` and
    ``threads``).

    Returns a :class:`MultilevelResult` whose ``target`` is ``None``; the heavy-tailed and
    inconsistent-level warnings are raised as :class:`McintWarning`, as :func:`mlmc` does.
    Check that ``check`` stays below 1 (the coarse path of level ``l`` has the law of the
    fine path of level ``l - 1``) and that ``beta`` is what the scheme promises before
    trusting a run.

    Examples
    --------
    >>> import numpy as np, mcint
    >>> def level(l, u):
    ...     p = lambda k: u[:, 0] ** 2 + 0.5 ** k
    ...     return p(l), (p(l - 1) if l > 0 else np.zeros(len(u)))
    >>> s = mcint.mlmc_survey(level, 4, 1000, dims=1, seed=1)
    >>> len(s.levels), round(s.alpha, 6)  # the corrections' means halve: alpha = 1
    (5, 1.0)
    """
    levels = _whole("levels", levels, 1, _DEEPEST_LEVEL)
    if levels is None:
        raise TypeError(f"invalid levels = None: expected a whole number 1 to {_DEEPEST_LEVEL}")
    samples = _whole("samples", samples, 2)
    if samples is None:
        raise TypeError("invalid samples = None: expected a whole number >= 2")
    result = _run(
        level, None, (levels, samples), dims, cost, refinement, weak_order, qmc, replicates,
        None, 1, levels, None, time_limit, seed, threads,
    )
    for w in result.warnings:
        warnings.warn(w.message, McintWarning, stacklevel=2)
    return result


def _run(level, rmse, survey, dims, cost, refinement, weak_order, qmc, replicates,
         initial_samples, min_level, deepest, max_cost, time_limit, seed, threads):
    """Checks the settings shared by a run and a survey and calls the extension."""
    settings = dict(
        survey=survey,
        qmc=bool(qmc),
        replicates=_whole("replicates", replicates, 1),
        initial_samples=_whole("initial_samples", initial_samples, 1),
        min_level=_whole("min_level", min_level, 1, _DEEPEST_LEVEL),
        max_level=deepest,
        max_cost=_positive("max_cost", max_cost),
        time_limit=_positive("time_limit", time_limit),
        threads=_whole("threads", threads, 1),
    )
    if isinstance(level, SdeLevels):
        given = [name for name, value in (("dims", dims), ("cost", cost),
                 ("refinement", refinement), ("weak_order", weak_order)) if value is not None]
        if given:
            raise TypeError(
                f"{given[0]} does not apply to SdeLevels, which has its own dims, cost, "
                "refinement and weak_order (set the refinement with SdeLevels.gbm or .heston)"
            )
        seed_int = _seed.to_int(seed)
        native = _native.mlmc_sde(level._native, rmse, seed=seed_int, **settings)
        return MultilevelResult(native, seed_int)
    if not callable(level):
        raise TypeError(
            f"invalid level = {level!r}: expected a callable level(l, u) or an SdeLevels"
        )
    if dims is None:
        raise TypeError(
            "invalid dims = None: expected the coordinates of a sample of each level (an "
            "int, or a callable dims(l)), which a callable level needs"
        )
    refinement = _whole("refinement", 2 if refinement is None else refinement, 2, 2**16)
    # Every level the run may sample, and level 2 (a checkpoint's fingerprint reads 0..2).
    levels = range(max(_DEFAULT_MAX_LEVEL if deepest is None else deepest, 2) + 1)
    dims_table = [_level_dims(dims, l) for l in levels]
    cost_table = [_level_cost(cost, refinement, l) for l in levels]
    if weak_order is not None:
        weak_order = _positive("weak_order", weak_order)
    seed_int = _seed.to_int(seed)
    native = _native.mlmc(
        _blocks(level),
        rmse,
        dims_table,
        cost_table,
        refinement,
        weak_order=weak_order,
        seed=seed_int,
        **settings,
    )
    return MultilevelResult(native, seed_int)


def _level_dims(dims, l):
    value = dims(l) if callable(dims) else dims
    whole = isinstance(value, numbers.Integral) and not isinstance(value, (bool, np.bool_))
    if not whole or not 1 <= value < 2**63:
        raise ValueError(
            f"invalid dims = {value!r} at level {l}: expected a whole number >= 1 of "
            "coordinates per sample (an int, or a callable dims(l) giving one)"
        )
    return int(value)


def _level_cost(cost, refinement, l):
    if cost is None:
        return float(refinement) ** l
    value = cost(l)
    if (
        isinstance(value, (bool, np.bool_))
        or not isinstance(value, numbers.Real)
        or not (np.isfinite(value) and value > 0)
    ):
        raise ValueError(
            f"invalid cost = {value!r} at level {l}: expected a finite number above 0 "
            "(the cost of one sample of the level)"
        )
    return float(value)


def _blocks(level):
    """``level`` as the extension calls it: ``(n, 2)`` columns of fine and coarse values,
    after checking the pair the user's function returned."""

    def call(l, u):
        pair = level(l, u)
        try:
            fine, coarse = pair
        except (TypeError, ValueError):
            raise TypeError(
                f"level({l}, u) returned {type(pair).__name__}: expected a pair (fine, "
                "coarse) of arrays with one value per row of u"
            ) from None
        n = u.shape[0]
        fine = np.asarray(fine, dtype=np.float64)
        coarse = np.asarray(coarse, dtype=np.float64)
        if fine.shape != (n,) or coarse.shape != (n,):
            raise ValueError(
                f"level({l}, u) returned shapes {fine.shape} and {coarse.shape} for {n} "
                f"samples: expected ({n},) each"
            )
        if l == 0 and np.any(coarse != 0):
            raise ValueError(
                "level(0, u) returned nonzero coarse values: level 0 has no coarser level, "
                "so its coarse values must be 0 (P_-1 = 0)"
            )
        return np.column_stack((fine, coarse))

    return call


class MultilevelResult:
    """What a multilevel run estimated and how it ended.

    Attributes
    ----------
    estimate, std_error, bias, rmse :
        The estimate, its standard error (sampling alone), the estimated bias of the
        deepest level, and ``sqrt(std_error**2 + bias**2)``.
    target : float or None
        The RMSE asked for (``None`` for a survey).
    levels : list of LevelSummary
    alpha, beta, gamma : float
        The fitted decay rates of the mean, the variance and the cost of the corrections.
    refinement : int
    cost, standard_mc_cost : float
        The run's cost, and what plain Monte Carlo on the deepest level would have paid for
        the same error.
    replicates : int
    converged : bool
        Whether the target was met.
    stop_reason : str
        ``"tolerance met"``, ``"max level"``, ``"inconsistent levels"`` (a coupling error
        in the model: no more levels are added), ``"max evaluations"`` (the cost limit),
        ``"time limit"`` or ``"cancelled"``.
    warnings : list of RunWarning
    seed : int
        The library seed (pass it back to repeat the run bit for bit).
    """

    def __init__(self, native, seed):
        report = native.report()
        self._report = report
        self.seed = seed
        for key in ("estimate", "std_error", "bias", "rmse", "target", "alpha", "beta",
                    "gamma", "refinement", "cost", "standard_mc_cost", "replicates",
                    "converged"):
            setattr(self, key, report[key])
        self.stop_reason = report["stop"]
        self.levels = [LevelSummary(**level) for level in report["levels"]]
        self.warnings = [RunWarning(w["kind"], w["message"], None) for w in report["warnings"]]

    def to_dict(self):
        """The run with the keys of the command line's ``mlmc --json``."""
        out = {k: v for k, v in self._report.items() if k not in ("stop", "target", "levels")}
        out["eps"] = self._report["target"]
        out["levels"] = [dict(level) for level in self._report["levels"]]
        out["stop"] = self._report["stop"]
        out["seed"] = self.seed
        return out

    def __repr__(self):
        return (
            f"MultilevelResult(estimate={self.estimate!r}, rmse={self.rmse!r}, "
            f"levels={len(self.levels)}, cost={self.cost!r}, converged={self.converged}, "
            f"stop_reason={self.stop_reason!r})"
        )
