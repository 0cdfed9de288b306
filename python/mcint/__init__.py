"""mcint: Monte Carlo and quasi-Monte Carlo integration with honest error bars.

The Python face of the Rust crate ``mcint``:

* :func:`integrate` integrates a vectorized numpy function over a box by any method of
  the library (randomized QMC, plain Monte Carlo, VEGAS, VEGAS+, MISER, two-stage
  stratification, Sobol' with a Walsh-coefficient bound) to a tolerance or a budget.
* :mod:`mcint.qmc` gives the library's point sets as ``scipy.stats.qmc`` engines.
"""

from ._integrate import METHODS, integrate
from ._native import __version__
from ._result import IntegrationResult, McintWarning, RunWarning

__all__ = [
    "integrate",
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
