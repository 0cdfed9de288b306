"""Point sets as ``scipy.stats.qmc`` engines.

Each class draws the points of one of mcint's samplers with the methods of a
``scipy.stats.qmc.QMCEngine`` (``random``, ``random_base2``, ``integers``, ``reset``,
``fast_forward``), and subclasses it when scipy is installed, so that an engine can be
passed where scipy takes one::

    >>> import mcint.qmc
    >>> engine = mcint.qmc.Sobol(d=3, seed=7)
    >>> engine.random(4).shape
    (4, 3)

An integer seed gives the same bits as the Rust crate's samplers with that seed.

The sequences (``Sobol``, ``Halton``, ``Lattice``, ``PMJ02``, ``Independent``) continue
where the last call stopped. The point sets of a fixed size (``LatinHypercube``,
``Jittered``, ``MultiJittered``, ...) give, on each call ``random(n)``, a new independent
set of ``n`` points, as scipy's ``LatinHypercube`` does.
"""

import warnings

import numpy as np

from . import _native, _seed

try:
    from scipy.stats import qmc as _scipy_qmc

    _Base = _scipy_qmc.QMCEngine
except ImportError:  # scipy is optional
    _Base = object

__all__ = [
    "Engine",
    "Sobol",
    "Halton",
    "Lattice",
    "PMJ02",
    "Independent",
    "LatinHypercube",
    "Hammersley",
    "Jittered",
    "MultiJittered",
    "CorrelatedMultiJittered",
    "OrthogonalArray",
    "MultiStageNRooks",
    "PoissonDisk",
    "BestCandidate",
    "sampler_names",
    "scramble_names",
]


def sampler_names():
    """The sampler names :class:`Engine` accepts."""
    return list(_native.sampler_names())


def scramble_names():
    """The randomizations :class:`Engine` accepts by name."""
    return list(_native.scramble_names())


class Engine(_Base):
    """Any of mcint's samplers by name, as a scipy QMC engine.

    Parameters
    ----------
    name : str
        One of :func:`sampler_names` (``"sobol"``, ``"halton"``, ``"lattice"``, ...).
    d : int
        The dimension.
    scramble : bool or str
        ``True`` for the sampler's default randomization (Owen scrambling for Sobol',
        random digit permutations for Halton, a random shift for lattices), ``False`` for
        none, or a name from :func:`scramble_names`.
    seed : None, int, numpy.random.Generator or SeedSequence
        An integer gives the Rust crate's points for that seed. ``rng`` is a synonym.
    strength : int, optional
        The strength of ``"oa-bush"`` orthogonal arrays.
    """

    def __init__(
        self, name, d, *, scramble=True, seed=None, rng=None, strength=None, optimization=None
    ):
        self._setup(name, d, scramble, seed, rng, strength, optimization)
        self._init_quad = {
            "name": name,
            "d": d,
            "scramble": scramble,
            "strength": strength,
            "optimization": optimization,
        }

    def _setup(self, name, d, scramble, seed, rng, strength, optimization):
        if optimization not in (None, "random-cd", "lloyd"):
            raise ValueError(
                f"invalid optimization = {optimization!r}: expected None, 'random-cd' (swaps "
                "that lower the centered discrepancy) or 'lloyd' (Lloyd relaxation)"
            )
        if seed is not None and rng is not None:
            raise TypeError("give seed or rng, not both")
        seed = rng if rng is not None else seed
        if not _integer(d) or not 1 <= d < 2**64:
            raise ValueError(f"invalid d = {d!r}: expected an integer >= 1 (and below 2**64)")
        if strength is not None and (not _integer(strength) or not 1 <= strength <= 63):
            raise ValueError(
                f"invalid strength = {strength!r}: expected an integer from 1 to 63 "
                "(p**strength points must fit in 64 bits)"
            )
        passes, default_scramble = _native.sampler_info(name)
        if scramble is True:
            scramble_name = None
        elif default_scramble == "none":
            raise ValueError(
                f"invalid scramble = {scramble!r}: the {name} sampler's randomization is built "
                "in; leave scramble at True (scrambles apply to sobol, halton, hammersley and "
                "lattice)"
            )
        elif scramble is False:
            scramble_name = "none"
        elif isinstance(scramble, str) and scramble in scramble_names():
            scramble_name = scramble
        elif isinstance(scramble, str):
            raise ValueError(
                f"invalid scramble = {scramble!r}: expected True, False or one of "
                f"{', '.join(scramble_names())}"
            )
        else:
            raise TypeError(
                f"invalid scramble = {scramble!r}: expected True, False or one of "
                f"{', '.join(scramble_names())}"
            )
        self.d = int(d)
        self._name = name
        self._scramble = scramble_name
        self._strength = strength
        self.rng_seed = seed
        if seed is None:
            self.rng = np.random.default_rng()
            self.seed = _seed.to_int(self.rng)
        else:
            self.seed = _seed.to_int(seed)
            self.rng = _seed.generator(seed)
        # Applied by random() itself (scipy's attribute stays None so nothing applies it twice).
        self.optimization_method = None
        self._optimization = optimization
        self._bits = None
        self.num_generated = 0
        self._fixed = passes == "fixed"
        # Built once for the sequences; the fixed-size sets are built per call, for their n.
        self._points = None
        if not self._fixed:
            self._points = _native.PointSet(name, self.d, 0, scramble_name, self.seed, strength)

    def _point_set(self, n):
        if not self._fixed:
            return self._points
        return _native.PointSet(
            self._name, self.d, n, self._scramble, self.seed, self._strength
        )

    @property
    def name(self):
        """The sampler's name."""
        return self._name

    def random(self, n=1, *, workers=1):
        """``n`` points in ``[0, 1)^d`` as an ``(n, d)`` array.

        ``workers`` is accepted for scipy's signature; the points are generated in Rust.
        """
        start = self.num_generated
        sample = self._random(n, workers=workers)
        if self._bits is not None:
            # As scipy's Sobol(bits=b) with b < 32: integers of b bits over 2**b.
            scale = float(2**self._bits)
            sample = np.floor(sample * scale) / scale
        if self._optimization is not None and len(sample) > 0:
            # A seed per call, from the engine's seed and the call's first index.
            seed = (self.seed * 0x9E3779B97F4A7C15 + start + 1) % 2**64
            sample = _native.optimize(np.ascontiguousarray(sample), self._optimization, seed)
        return sample

    def _random(self, n=1, *, workers=1):
        # scipy's abstract method; here it also advances the engine, as random() does.
        n = _count(n)
        if self._bits is not None and self.num_generated + n > 2**self._bits:
            raise ValueError(
                f"{self.num_generated} + {n} points exceed 2**bits = 2**{self._bits}: draw "
                "fewer, or give more bits (up to 64)"
            )
        if self._fixed:
            if n == 0:
                return np.empty((0, self.d))
            # A new whole set: the next pass of n points after those drawn so far.
            passes = -(-self.num_generated // n)
            sample = self._point_set(n).fill(passes * n, n)
            self.num_generated = (passes + 1) * n
            return sample
        self._check_pass(n)
        sample = self._points.fill(self.num_generated, n)
        self.num_generated += n
        return sample

    def _check_pass(self, n):
        """Refuses to pass the end of a sequence's pass, where its points start over
        (unscrambled: repeated) or join another randomization (no longer a net), as the Rust
        sampler and scipy refuse."""
        kind, most = self._points.passes
        if kind == "extensible" and self.num_generated + n > most:
            raise ValueError(
                f"invalid n = {n}: {self.num_generated} + n points pass the {most} points of "
                f"one pass of the {self._name} sequence"
            )

    def random_base2(self, m):
        """``2**m`` points; the total drawn must stay a power of 2 (balance)."""
        # Bounded before 2**m is formed: Python would compute 2**(10**30) for ever.
        if (
            isinstance(m, (bool, np.bool_))
            or not isinstance(m, (int, np.integer))
            or not 0 <= m <= 62
        ):
            raise ValueError(f"invalid m = {m!r}: expected an integer from 0 to 62")
        n = 2 ** int(m)
        total = self.num_generated + n
        if total & (total - 1):
            raise ValueError(
                f"The balance properties of the points require n to be a power of 2. "
                f"{self.num_generated} points have been previously generated, then: "
                f"n={self.num_generated}+2**{m}={total}. If you still want to do this, "
                f"the function 'random()' can be used."
            )
        return self.random(n)

    def integers(self, l_bounds, u_bounds=None, n=1, *, endpoint=False, workers=1):
        """``n`` integer points in ``[l_bounds, u_bounds)`` (``]`` with ``endpoint``), as
        scipy: the unit points scaled to the bounds and rounded down."""
        if u_bounds is None:
            l_bounds, u_bounds = 0, l_bounds
        lower = np.broadcast_to(np.asarray(l_bounds), (self.d,))
        upper = np.broadcast_to(np.asarray(u_bounds), (self.d,))
        if not (np.issubdtype(lower.dtype, np.integer) and np.issubdtype(upper.dtype, np.integer)):
            raise ValueError("'u_bounds' and 'l_bounds' must be integers or array-like of integers")
        # Past 2**53 the scaled points are not integers f64 can hold, and int64 overflows:
        # refused, as the Rust sampler's integers refuses them.
        if np.any(np.abs(lower) > 2**53) or np.any(np.abs(upper) > 2**53):
            raise ValueError(
                f"invalid bounds = {l_bounds!r}, {u_bounds!r}: expected integers within "
                "+-2**53, which float64 points can reach exactly"
            )
        if endpoint:
            upper = upper + 1
        if np.any(lower >= upper):
            raise ValueError("Bounds are not consistent 'l_bounds' < 'u_bounds'")
        sample = self.random(n)
        return np.floor(lower + sample * (upper - lower)).astype(np.int64)

    def reset(self):
        """Back to the first point, with the same randomization."""
        self.rng = _seed.generator(self.rng_seed)
        self.num_generated = 0
        return self

    def fast_forward(self, n):
        """Skips ``n`` points."""
        n = _count(n)
        if not self._fixed:
            self._check_pass(n)
        if self.num_generated + n >= 2**64:
            raise ValueError(
                f"invalid n = {n}: {self.num_generated} + n points would pass the last index, "
                "2**64 - 1"
            )
        self.num_generated += n
        return self

    def __repr__(self):
        return f"{type(self).__name__}(d={self.d}, seed={self.seed})"


def _integer(value):
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))


def _count(n):
    if not _integer(n) or not 0 <= n < 2**64:
        raise ValueError(f"invalid n = {n!r}: expected an integer from 0 to 2**64 - 1")
    return int(n)


def _named(class_name, sampler, doc):
    """An :class:`Engine` subclass for one sampler, built as scipy builds its engines:
    ``Class(d, *, scramble=True, seed=None)``."""

    def __init__(self, d, *, scramble=True, seed=None, rng=None, optimization=None):
        self._setup(sampler, d, scramble, seed, rng, None, optimization)
        self._init_quad = {"d": d, "scramble": scramble, "optimization": optimization}

    return type(class_name, (Engine,), {"__init__": __init__, "__doc__": doc, "__module__": __name__})


class Sobol(Engine):
    """The Sobol' sequence (Joe-Kuo direction numbers, as scipy's); ``scramble=True`` is Owen
    scrambling, ``'lms'`` a linear matrix scramble with a digital shift, ``False`` the plain
    sequence (scipy's ``Sobol(scramble=False)`` bit for bit). mcint's points carry 32 bits
    (``bits=None`` or 32 and more); ``bits`` below 32 rounds them down to ``bits`` bits and
    allows at most ``2**bits`` points, as scipy's."""

    def __init__(self, d, *, scramble=True, bits=None, seed=None, rng=None, optimization=None):
        if bits is not None and (
            isinstance(bits, (bool, np.bool_))
            or not isinstance(bits, (int, np.integer))
            or not 1 <= bits <= 64
        ):
            raise ValueError(f"invalid bits = {bits!r}: expected None or an integer in 1..=64")
        self._setup("sobol", d, scramble, seed, rng, None, optimization)
        self._bits = int(bits) if bits is not None and bits < 32 else None
        self.bits = 32 if bits is None else int(bits)
        self._init_quad = {"d": d, "scramble": scramble, "bits": bits, "optimization": optimization}

    def random(self, n=1, *, workers=1):
        """``n`` points, as :meth:`Engine.random`; like scipy's ``Sobol``, warns (a
        ``UserWarning``) when the points drawn so far stop being a power of 2, whose prefixes
        are the nets that give Sobol' points their balance."""
        sample = super().random(n, workers=workers)
        total = self.num_generated
        if n > 0 and total & (total - 1):
            warnings.warn(
                "The balance properties of Sobol' points require n to be a power of 2.",
                stacklevel=2,
            )
        return sample


Halton = _named(
    "Halton",
    "halton",
    "The Halton sequence; ``scramble=True`` permutes digits at random, ``'owen'`` Owen-scrambles, "
    "``False`` gives the plain sequence (scipy's ``Halton(scramble=False)``).",
)
Lattice = _named(
    "Lattice",
    "lattice",
    "A rank-1 lattice rule (extensible, radical-inverse order); ``scramble=True`` is a random shift.",
)
PMJ02 = _named("PMJ02", "pmj02", "The progressive multi-jittered (0,2) sequence (2-D strata per pair).")
Independent = _named("Independent", "independent", "Independent uniform points (PCG64).")


class LatinHypercube(Engine):
    """Latin hypercube (N-rooks) sets, as scipy's: each ``random(n)`` a new set of ``n``
    points, one in each ``1/n`` slab of every axis. ``scramble=False`` puts each point at the
    centre of its slab (McKay, Beckman and Conover's midpoint sampling; scipy's centered
    design). ``strength=2`` builds the set from an orthogonal array of strength 2 (Tang 1993,
    Bose's construction, as scipy): ``n = p**2`` for a prime ``p`` and ``d <= p + 1``, and in
    every pair of axes one point in each cell of the ``p x p`` grid as well."""

    def __init__(self, d, *, scramble=True, strength=1, optimization=None, seed=None, rng=None):
        if not _integer(strength) or strength not in (1, 2):
            raise ValueError(
                f"invalid strength = {strength!r}: expected 1 (a Latin hypercube) or 2 (one "
                "built from an orthogonal array of strength 2), as scipy's LatinHypercube"
            )
        if not isinstance(scramble, (bool, np.bool_)):
            raise ValueError(
                f"invalid scramble = {scramble!r}: expected True (each point uniform in its "
                "slab) or False (at the slab's centre); the slabs' order is always random"
            )
        # Strength 2 is the orthogonal array whose offsets make every axis a Latin hypercube.
        sampler, oa_strength = ("latin", None) if strength == 1 else ("oa-bose", 2)
        self._setup(sampler, d, True, seed, rng, oa_strength, optimization)
        self._centered = not scramble
        self._init_quad = {
            "d": d,
            "scramble": scramble,
            "strength": strength,
            "optimization": optimization,
        }

    def _random(self, n=1, *, workers=1):
        sample = super()._random(n, workers=workers)
        if self._centered and len(sample) > 0:
            # Each axis holds one point per slab: a point's rank along an axis is its slab.
            slabs = np.argsort(np.argsort(sample, axis=0, kind="stable"), axis=0, kind="stable")
            sample = (slabs + 0.5) / len(sample)
        return sample

Hammersley = _named("Hammersley", "hammersley", "Hammersley sets of ``n`` points.")
Jittered = _named("Jittered", "jittered", "Stratified (jittered) sets; ``n`` must be ``k**d``.")
MultiJittered = _named("MultiJittered", "multijitter", "Multi-jittered sets of ``n = m * k`` points.")
CorrelatedMultiJittered = _named(
    "CorrelatedMultiJittered", "cmj", "Correlated multi-jittered sets (Kensler) of ``n`` points."
)
MultiStageNRooks = _named(
    "MultiStageNRooks",
    "nrooks-multistage",
    "Multi-stage N-rooks sets of ``n = b**k`` points (``b, k >= 2``: 4, 8, 9, 16, 25, 27, ..., "
    "any dimension), every aligned block of ``b**(k - s)`` points a Latin hypercube at each "
    "stage ``s``.",
)
PoissonDisk = _named("PoissonDisk", "poisson", "Poisson-disk (blue noise) sets of ``n`` points.")
BestCandidate = _named(
    "BestCandidate", "best-candidate", "Mitchell's best-candidate blue-noise sets of ``n`` points."
)


class OrthogonalArray(Engine):
    """Orthogonal arrays with multi-jittered offsets: ``strength=2`` by Bose's construction
    (``n = p**2``, ``p`` prime), higher strengths by Bush's (``n = p**strength``)."""

    def __init__(self, d, *, strength=2, scramble=True, seed=None, rng=None, optimization=None):
        name = "oa-bose" if strength == 2 else "oa-bush"
        self._setup(name, d, scramble, seed, rng, strength, optimization)
        self._init_quad = {
            "d": d,
            "strength": strength,
            "scramble": scramble,
            "optimization": optimization,
        }
