"""Seeds as numpy users give them, as the 64-bit integer seeds of the Rust library."""

import numbers

import numpy as np

_SEED_HELP = (
    "expected None, an integer >= 0, a numpy.random.Generator, or a numpy.random.SeedSequence"
)


def to_int(seed):
    """The library seed for ``seed``.

    An integer below 2**64 is used as it is, so ``seed=7`` gives the same points as the Rust
    crate's ``seed(7)`` (a larger one goes through a ``SeedSequence``, as numpy's); a ``Generator`` gives one draw from it (so the spawned generators
    ``scipy.integrate.qmc_quad`` passes give independent randomizations); ``None`` draws
    fresh entropy from the operating system.
    """
    if seed is None:
        return int(np.random.SeedSequence().generate_state(1, np.uint64)[0])
    if isinstance(seed, (bool, np.bool_)):
        raise TypeError(f"invalid seed = {seed!r}: {_SEED_HELP}")
    if isinstance(seed, numbers.Integral):
        value = int(seed)
        if value < 0:
            raise ValueError(f"invalid seed = {value}: {_SEED_HELP}")
        if value >= 2**64:
            # As numpy takes one (scipy's engines accept it): through a SeedSequence.
            return int(np.random.SeedSequence(value).generate_state(1, np.uint64)[0])
        return value
    if isinstance(seed, np.random.Generator):
        return int(seed.integers(0, 2**64, dtype=np.uint64))
    if isinstance(seed, np.random.SeedSequence):
        return int(seed.generate_state(1, np.uint64)[0])
    raise TypeError(f"invalid seed = {seed!r}: {_SEED_HELP}")


def generator(seed):
    """A numpy ``Generator`` standing for ``seed`` (what scipy's engines keep as ``rng``)."""
    if isinstance(seed, np.random.Generator):
        return seed
    return np.random.default_rng(seed)
