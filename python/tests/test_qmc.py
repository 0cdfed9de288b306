"""mcint.qmc engines: the Rust samplers' bits, scipy's interface and scipy's own points."""

import subprocess
import warnings

import numpy as np
import pytest
from scipy import stats
from scipy.integrate import qmc_quad
from scipy.stats import qmc

import rust_cli
from genz import genz_families
from mcint import qmc as mq


def rust_points(sampler, d, n, seed, scramble=None):
    """The points the Rust CLI `points` writes (exact little-endian f64), as rows."""
    args = [str(rust_cli.binary("points")), "--sampler", sampler, "--dims", str(d)]
    args += ["--n", str(n), "--seed", str(seed), "--format", "bin"]
    if scramble is not None:
        args += ["--scramble", scramble]
    out = subprocess.run(args, check=True, capture_output=True).stdout
    return np.frombuffer(out, dtype="<f8").reshape(n, d)


@pytest.mark.parametrize(
    "engine, sampler, scramble",
    [
        (lambda: mq.Sobol(5, seed=11), "sobol", None),
        (lambda: mq.Sobol(5, scramble="lms", seed=11), "sobol", "lms"),
        (lambda: mq.Halton(5, seed=11), "halton", None),
        (lambda: mq.Lattice(5, seed=11), "lattice", None),
        (lambda: mq.PMJ02(5, seed=11), "pmj02", None),
        (lambda: mq.Independent(5, seed=11), "independent", None),
        (lambda: mq.LatinHypercube(5, seed=11), "latin", None),
        (lambda: mq.CorrelatedMultiJittered(5, seed=11), "cmj", None),
    ],
)
def test_points_are_the_rust_cli_bits(engine, sampler, scramble):
    got = engine().random(256)
    assert got.shape == (256, 5) and got.dtype == np.float64
    assert np.array_equal(got, rust_points(sampler, 5, 256, 11, scramble))


def test_unscrambled_sobol_is_scipys_bit_for_bit_across_calls():
    ours, theirs = mq.Sobol(7, scramble=False), qmc.Sobol(7, scramble=False)
    for m in (3, 3, 4, 5, 6):
        assert np.array_equal(ours.random_base2(m), theirs.random_base2(m))


def test_unscrambled_halton_is_scipys_to_rounding():
    # scipy sums the radical inverse's digits in another order: the same numbers to a few
    # units in the last place, not the same bits.
    ours = mq.Halton(6, scramble=False).random(2000)
    theirs = qmc.Halton(6, scramble=False).random(2000)
    assert np.max(np.abs(ours - theirs)) <= 4 * np.finfo(float).eps


def test_engines_are_scipy_engines_and_work_with_its_functions():
    engine = mq.Sobol(3, seed=5)
    assert isinstance(engine, qmc.QMCEngine)
    points = engine.random(512)
    assert qmc.discrepancy(points) < qmc.discrepancy(np.random.default_rng(5).random((512, 3)))
    scaled = qmc.scale(points, [-1, 0, 2], [1, 1, 3])
    assert scaled.min() >= -1 and scaled.max() < 3


# Draws of 96 and 32 points: Sobol warns of the balance, as scipy's does.
@pytest.mark.filterwarnings("ignore:The balance properties")
def test_random_continues_reset_restarts_fast_forward_skips():
    whole = mq.Sobol(4, seed=2).random(96)
    engine = mq.Sobol(4, seed=2)
    assert np.array_equal(np.vstack([engine.random(32), engine.random(64)]), whole)
    assert engine.num_generated == 96
    assert np.array_equal(engine.reset().random(96), whole)
    assert np.array_equal(engine.reset().fast_forward(40).random(56), whole[40:])


def test_random_base2_keeps_balance():
    engine = mq.Sobol(2, seed=0)
    assert engine.random_base2(4).shape == (16, 2)
    with pytest.raises(ValueError, match="power of 2"):
        engine.random_base2(3)


def test_integers_as_scipy_defines_them():
    engine = mq.Halton(3, seed=9)
    values = engine.integers([0, 5, -3], [4, 6, 3], n=1000)
    assert values.dtype == np.int64 and values.shape == (1000, 3)
    assert values[:, 0].min() == 0 and values[:, 0].max() == 3
    assert np.all(values[:, 1] == 5)
    assert values[:, 2].min() == -3 and values[:, 2].max() == 2
    inclusive = mq.Halton(1, seed=9).integers(2, n=64, endpoint=True)
    assert set(np.unique(inclusive)) == {0, 1, 2}


def test_fixed_size_sets_are_new_independent_sets_per_call():
    engine = mq.LatinHypercube(3, seed=4)
    first, second = engine.random(50), engine.random(50)
    assert not np.array_equal(first, second)
    for sample in (first, second):
        # One point in each of the 50 strata of every axis.
        for axis in range(3):
            assert sorted(np.floor(sample[:, axis] * 50).astype(int)) == list(range(50))
    assert np.array_equal(engine.reset().random(50), first)


def test_seeds_as_numpy_gives_them():
    a = mq.Sobol(2, seed=np.random.default_rng(3)).random(8)
    b = mq.Sobol(2, seed=np.random.default_rng(3)).random(8)
    assert np.array_equal(a, b)
    assert np.array_equal(mq.Sobol(2, rng=17).random(8), mq.Sobol(2, seed=17).random(8))
    assert mq.Sobol(2, seed=np.uint64(2**64 - 1)).seed == 2**64 - 1


@pytest.mark.parametrize(
    "make, error, words",
    [
        (lambda: mq.Sobol(0), ValueError, "d = 0"),
        (lambda: mq.Sobol(2.5), ValueError, "integer >= 1"),
        (lambda: mq.Sobol(2, scramble="scrambled"), ValueError, "owen"),
        (lambda: mq.Sobol(2, scramble=3), TypeError, "True, False"),
        (lambda: mq.Sobol(2, seed=-1), ValueError, "integer >= 0"),
        (lambda: mq.Sobol(2, seed="x"), TypeError, "Generator"),
        (lambda: mq.Sobol(2, seed=1, rng=2), TypeError, "not both"),
        (lambda: mq.Sobol(2, optimization="random_cd"), ValueError, "'random-cd'"),
        (lambda: mq.Sobol(2, bits=0), ValueError, "1..=64"),
        (lambda: mq.Sobol(2, bits=65), ValueError, "1..=64"),
        (lambda: mq.Sobol(2, bits=4).random(17), ValueError, r"2\*\*4"),
        (lambda: mq.Sobol(100_000), ValueError, "invalid d = 100000"),
        (lambda: mq.Engine("sobel", 2), ValueError, "sobol"),
        (lambda: mq.Sobol(2).random(-1), ValueError, "n = -1"),
        # Past a pass a sequence starts over (unscrambled: the same points) or joins another
        # randomization (no longer a net): refused, as the Rust sampler refuses.
        (lambda: mq.PMJ02(2, seed=1).random_base2(17), ValueError, "65536 points of one pass"),
        (lambda: mq.Sobol(2, scramble=False, bits=64).fast_forward(2**32).random(1), ValueError,
         "pass the 4294967296 points"),
        (lambda: mq.Lattice(2).fast_forward(2**20 + 1), ValueError, "lattice sequence"),
        (lambda: mq.Sobol(1).integers(2**63, u_bounds=2**64 - 1, n=4), ValueError, "2\\*\\*53"),
        # Integers past 64 bits say what is allowed (no bare OverflowError from the extension).
        (lambda: mq.Sobol(2**64), ValueError, r"d = 18446744073709551616: expected an integer"),
        (lambda: mq.Sobol(2).random(2**64), ValueError, r"0 to 2\*\*64 - 1"),
        (lambda: mq.Independent(2).fast_forward(2**64 - 5).fast_forward(5), ValueError,
         "last index"),
        (lambda: mq.OrthogonalArray(2, strength=2**64), ValueError, "1 to 63"),
        (lambda: mq.Engine("oa-bush", 2, strength=0), ValueError, "1 to 63"),
        (lambda: mq.Sobol(2).random_base2(-2), ValueError, "m = -2"),
        # Refused before 2**m is formed (which would not finish).
        (lambda: mq.Halton(2).random_base2(10**30), ValueError, "0 to 62"),
        (lambda: mq.Jittered(2, seed=1).random(10), ValueError, "10"),
        (lambda: mq.LatinHypercube(2, scramble="owen"), ValueError, "True .* or False"),
        (lambda: mq.LatinHypercube(2, strength=3), ValueError, "expected 1 .* or 2"),
        (lambda: mq.LatinHypercube(2, strength=True), ValueError, "expected 1 .* or 2"),
        (lambda: mq.LatinHypercube(2, strength=2).random(10), ValueError, "p\\^2 for a prime"),
        (lambda: mq.LatinHypercube(5, strength=2).random(9), ValueError, "p >= 5"),
        (lambda: mq.Halton(2, scramble="owen ish"), ValueError, "expected True, False"),
    ],
)
def test_bad_input_is_a_clear_error(make, error, words):
    with pytest.raises(error, match=words):
        make()


def test_random_cd_lowers_the_discrepancy_and_keeps_a_latin_hypercube():
    n, d = 64, 4
    plain = mq.LatinHypercube(d, seed=3).random(n)
    engine = mq.LatinHypercube(d, seed=3, optimization="random-cd")
    optimized = engine.random(n)
    assert qmc.discrepancy(optimized, method="CD") < qmc.discrepancy(plain, method="CD")
    # One point in each of the n slices of every axis, as before the swaps.
    for column in optimized.T:
        assert sorted(np.floor(column * n).astype(int)) == list(range(n))
    # Reproducible: the same seed gives the same bits, and a second call its own swaps.
    again = mq.LatinHypercube(d, seed=3, optimization="random-cd")
    assert np.array_equal(again.random(n), optimized)
    assert not np.array_equal(engine.random(n), optimized)


def test_lloyd_spreads_the_points():
    def min_distance(x):
        gaps = np.linalg.norm(x[:, None, :] - x[None, :, :], axis=2)
        return gaps[np.triu_indices(len(x), 1)].min()

    plain = mq.Independent(2, seed=5).random(64)
    relaxed = mq.Independent(2, seed=5, optimization="lloyd").random(64)
    assert min_distance(relaxed) > min_distance(plain)
    assert relaxed.min() >= 0 and relaxed.max() <= 1


def test_sobol_bits_as_scipy_defines_them():
    for bits in (10, 30):
        ours = mq.Sobol(3, scramble=False, bits=bits).random(1 << 9)
        theirs = qmc.Sobol(3, scramble=False, bits=bits).random(1 << 9)
        assert np.array_equal(ours, theirs)
    coarse = mq.Sobol(2, bits=6, seed=1).random(64)
    assert np.array_equal(coarse * 64, np.floor(coarse * 64))
    assert mq.Sobol(2, bits=40).bits == 40 and mq.Sobol(2).bits == 32


def test_qmc_quad_rebuilds_engines_with_their_options():
    f, exact = genz_families(5)["gaussian"]
    for qrng in (mq.Sobol(5, seed=2, bits=20), mq.LatinHypercube(5, seed=2, optimization="random-cd")):
        result = qmc_quad(f, [0] * 5, [1] * 5, n_estimates=8, n_points=256, qrng=qrng)
        assert abs(result.integral - exact) <= 5 * result.standard_error


def test_every_named_sampler_has_an_engine():
    for name in mq.sampler_names():
        n = {"jittered": 16, "nrooks-multistage": 16, "oa-bose": 25, "oa-bush": 27}.get(name, 24)
        sample = mq.Engine(name, 2, seed=1).random(n)
        assert sample.shape == (n, 2)
        assert sample.min() >= 0 and sample.max() < 1


@pytest.mark.parametrize("family", ["gaussian", "product-peak", "oscillatory", "continuous"])
def test_qmc_quad_with_an_mcint_engine_covers_at_the_nominal_rate(family):
    f, exact = genz_families(5)[family]
    seeds = 100
    t = stats.t.ppf(0.975, df=7)  # qmc_quad: 8 independent randomizations
    covered = 0
    for seed in range(seeds):
        result = qmc_quad(f, [0] * 5, [1] * 5, n_estimates=8, n_points=256, qrng=mq.Sobol(5, seed=seed))
        covered += abs(result.integral - exact) <= t * result.standard_error
    # 95% nominal over 100 seeds: the binomial mean 95, standard deviation 2.2; 4.5 of them
    # below the mean is 85.
    assert covered >= 85, f"{family}: {covered} of {seeds} intervals cover"


def test_sobol_warns_as_scipy_when_the_points_stop_being_a_power_of_2():
    for engine in (qmc.Sobol(2, seed=1), mq.Sobol(2, seed=1)):
        with pytest.warns(UserWarning, match="balance properties"):
            engine.random(10)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        engine = mq.Sobol(2, seed=1)
        engine.random(8)
        engine.random(8)
        engine.random_base2(4)


def _slabs(points):
    """Each point's slab along each axis, as integers."""
    return np.floor(points * len(points)).astype(int)


@pytest.mark.parametrize("make", [mq.LatinHypercube, qmc.LatinHypercube])
def test_centered_latin_hypercubes_put_one_point_at_each_slab_centre(make):
    # scipy's LatinHypercube(scramble=False) and ours: every axis is a permutation of the
    # centres (k + 1/2) / n, and each call a new permutation.
    engine = make(4, scramble=False, seed=5) if make is mq.LatinHypercube else make(
        4, scramble=False, rng=5
    )
    first, second = engine.random(50), engine.random(50)
    centres = (np.arange(50) + 0.5) / 50
    for sample in (first, second):
        for column in sample.T:
            assert np.array_equal(np.sort(column), centres)
    assert not np.array_equal(first, second)


@pytest.mark.parametrize("scramble", [True, False])
@pytest.mark.parametrize("p, d", [(3, 2), (3, 4), (5, 6), (7, 3)])
def test_strength_2_latin_hypercubes_are_orthogonal_arrays_as_scipys(p, d, scramble):
    n = p * p
    ours = mq.LatinHypercube(d, strength=2, scramble=scramble, seed=7).random(n)
    theirs = qmc.LatinHypercube(d, strength=2, scramble=scramble, rng=7).random(n)
    for sample in (ours, theirs):
        # A Latin hypercube: one point per 1/n slab of each axis ...
        for column in _slabs(sample).T:
            assert np.array_equal(np.sort(column), np.arange(n))
        # ... and one point per cell of the p x p grid of every pair of axes.
        cells = np.floor(sample * p).astype(int)
        for i in range(d):
            for j in range(i + 1, d):
                assert len(set(zip(cells[:, i], cells[:, j]))) == n
        if not scramble:
            assert np.allclose(sample * n % 1.0, 0.5)


def test_strength_2_latin_hypercubes_are_the_rust_orthogonal_array_bits():
    got = mq.LatinHypercube(5, strength=2, seed=11).random(49)
    assert np.array_equal(got, rust_points("oa-bose", 5, 49, 11))


def test_seeds_past_64_bits_go_through_a_seed_sequence_as_numpys():
    # scipy's engines take them (numpy's SeedSequence does); they were refused.
    big = 2**70
    first = mq.Sobol(3, seed=big).random(8)
    assert np.array_equal(first, mq.Sobol(3, seed=big).random(8))
    assert not np.array_equal(first, mq.Sobol(3, seed=big + 1).random(8))
    mapped = int(np.random.SeedSequence(big).generate_state(1, np.uint64)[0])
    assert np.array_equal(first, mq.Sobol(3, seed=mapped).random(8))
    with pytest.raises(ValueError, match="integer >= 0"):
        mq.Sobol(3, seed=-1)
