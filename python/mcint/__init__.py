"""mcint: Monte Carlo and quasi-Monte Carlo integration with honest error bars.

The Python face of the Rust crate ``mcint``:

* :func:`integrate` integrates a vectorized numpy function over a box by any method of
  the library (randomized QMC, plain Monte Carlo, VEGAS, VEGAS+, MISER, two-stage
  stratification, Sobol' with a Walsh-coefficient bound) to a tolerance or a budget.
* :func:`expectation` averages a function over a measure of :mod:`mcint.measure`
  (Gaussian, lognormal, Brownian paths, geometric Brownian motion).
* :func:`sobol_indices` gives Sobol' sensitivity indices of a model with error bars.
* :func:`mlmc` estimates the expectation of a model's finest level by multilevel Monte
  Carlo (or QMC) to a root-mean-square error; :func:`mlmc_survey` is Giles' survey of its
  levels; :class:`SdeLevels` are the library's own option-pricing levels (geometric
  Brownian motion or Heston), sampled in Rust.
* :mod:`mcint.qmc` gives the library's point sets as ``scipy.stats.qmc`` engines.
"""

from . import measure
from ._integrate import METHODS, expectation, integrate
from ._multilevel import LevelSummary, MultilevelResult, SdeLevels, mlmc, mlmc_survey
from ._native import __version__
from ._result import IntegrationResult, McintWarning, RunWarning
from ._sensitivity import SensitivityResult, sobol_indices

__all__ = [
    "integrate",
    "expectation",
    "sobol_indices",
    "SensitivityResult",
    "mlmc",
    "mlmc_survey",
    "SdeLevels",
    "MultilevelResult",
    "LevelSummary",
    "measure",
    "qmc",
    "IntegrationResult",
    "McintWarning",
    "RunWarning",
    "METHODS",
    "__version__",
]


def __getattr__(name):
    # mcint.qmc imports scipy (its engines subclass scipy's): only when asked for.
    if name == "qmc":
        import importlib

        return importlib.import_module(".qmc", __name__)
    raise AttributeError(f"module 'mcint' has no attribute {name!r}")
