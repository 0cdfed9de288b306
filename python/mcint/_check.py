"""Checks of scalar arguments shared by the modules: the error names the argument and what
it takes, where Python or numpy would raise a bare OverflowError or a message without it."""

import numbers

import numpy as np


def real(name, value):
    """``value`` as a float, or a TypeError / ValueError naming ``name``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"invalid {name} = {value!r}: expected a number")
    try:
        return float(value)
    except OverflowError:
        raise ValueError(
            f"invalid {name}: expected a number within float64 (magnitude below about "
            f"1.8e308), got an integer of {len(str(abs(value)))} digits"
        ) from None
