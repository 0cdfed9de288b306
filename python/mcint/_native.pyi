# Type stubs of the extension module (the public API is in mcint/__init__.py).
from typing import Callable, Optional, Tuple

import numpy as np
import numpy.typing as npt

__version__: str

class PointSet:
    def __init__(
        self,
        kind: str,
        d: int,
        size: int,
        scramble: Optional[str],
        seed: int,
        strength: Optional[int] = None,
    ) -> None: ...
    def fill(self, start: int, n: int) -> npt.NDArray[np.float64]: ...
    @property
    def name(self) -> str: ...
    @property
    def d(self) -> int: ...
    @property
    def randomized(self) -> bool: ...
    @property
    def passes(self) -> Tuple[str, int]: ...

class RunResult:
    def interval(self, output: Optional[int], level: float) -> Optional[Tuple[float, float]]: ...
    def report(self) -> dict: ...

def integrate_box(
    f: Callable[[npt.NDArray[np.float64]], npt.NDArray[np.float64]],
    lower: list,
    upper: list,
    outputs: int,
    method: str,
    *,
    n: Optional[int] = None,
    replicates: Optional[int] = None,
    rtol: Optional[float] = None,
    atol: Optional[float] = None,
    max_evals: Optional[int] = None,
    time_limit: Optional[float] = None,
    seed: int = 0,
    threads: Optional[int] = None,
    sampler: Optional[str] = None,
    scramble: Optional[str] = None,
    ratio: Optional[Tuple[int, int]] = None,
    measure: Optional["MeasureSpec"] = None,
) -> RunResult: ...
def sampler_names() -> list: ...
def scramble_names() -> list: ...
def sampler_info(name: str) -> Tuple[str, str]: ...
def optimize(points: npt.NDArray[np.float64], method: str, seed: int) -> npt.NDArray[np.float64]: ...

class MeasureSpec:
    @staticmethod
    def gaussian(mean: list, covariance: list, factorization: str) -> "MeasureSpec": ...
    @staticmethod
    def lognormal(mean: list, covariance: list, factorization: str) -> "MeasureSpec": ...
    @staticmethod
    def brownian(times: list, drift: float, diffusion: float, how: str) -> "MeasureSpec": ...
    @staticmethod
    def geometric_brownian(
        s0: float, rate: float, sigma: float, times: list, how: str
    ) -> "MeasureSpec": ...
    @staticmethod
    def uniform(lower: list, upper: list) -> "MeasureSpec": ...
    def middle(self) -> list: ...
    @property
    def d(self) -> int: ...
    @property
    def canonical_dims(self) -> int: ...

class SensitivityRun:
    def report(self) -> dict: ...
    def interval(self, kind: str, output: int, j: int, level: float) -> Optional[Tuple[float, float]]: ...

def sobol_indices(
    f: Callable[[npt.NDArray[np.float64]], npt.NDArray[np.float64]],
    measure: MeasureSpec,
    outputs: int,
    *,
    groups: Optional[list] = None,
    second_order: bool = False,
    n: Optional[int] = None,
    replicates: Optional[int] = None,
    rtol: Optional[float] = None,
    atol: Optional[float] = None,
    max_evals: Optional[int] = None,
    time_limit: Optional[float] = None,
    seed: int = 0,
    threads: Optional[int] = None,
) -> SensitivityRun: ...

class MultilevelRun:
    def report(self) -> dict: ...

def mlmc(
    level: Callable[[int, npt.NDArray[np.float64]], npt.NDArray[np.float64]],
    rmse: Optional[float],
    dims: list,
    costs: list,
    refinement: int,
    *,
    survey: Optional[Tuple[int, int]] = None,
    weak_order: Optional[float] = None,
    qmc: bool = False,
    replicates: Optional[int] = None,
    initial_samples: Optional[int] = None,
    min_level: Optional[int] = None,
    max_level: Optional[int] = None,
    max_cost: Optional[float] = None,
    time_limit: Optional[float] = None,
    seed: int = 0,
    threads: Optional[int] = None,
) -> MultilevelRun: ...
