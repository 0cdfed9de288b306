"""mcint.sobol_indices against the Ishigami function's closed-form indices."""

import numpy as np
import pytest

import mcint
from mcint.measure import Gaussian, Uniform

A, B = 7.0, 0.1
CUBE = Uniform([-np.pi] * 3, [np.pi] * 3)


def ishigami(x):
    return np.sin(x[:, 0]) + A * np.sin(x[:, 1]) ** 2 + B * x[:, 2] ** 4 * np.sin(x[:, 0])


def ishigami_exact():
    """Sobol' and Levitan (1999): the variance and its parts for inputs uniform on [-pi, pi]."""
    v1 = 0.5 * (1 + B * np.pi**4 / 5) ** 2
    v2 = A**2 / 8
    v13 = B**2 * np.pi**8 * (1 / 18 - 1 / 50)
    v = v1 + v2 + v13
    first = np.array([v1, v2, 0.0]) / v
    total = np.array([v1 + v13, v2, v13]) / v
    return first, total, v13 / v


def test_indices_and_second_order_match_the_closed_form():
    first, total, s13 = ishigami_exact()
    r = mcint.sobol_indices(ishigami, CUBE, second_order=True, seed=3)
    assert np.all(np.abs(r.first_order - first) <= 5 * r.first_order_std_error)
    assert np.all(np.abs(r.total - total) <= 5 * r.total_std_error)
    assert abs(r.second_order[0, 2] - s13) < 0.02
    ci = r.ci("second_order")
    assert ci.shape == (3, 3, 2) and np.all(np.isnan(ci[2, 0])) and np.all(np.isnan(ci[1, 1]))
    assert ci[0, 2, 0] <= r.second_order[0, 2] <= ci[0, 2, 1]
    # One factor has no pair: an array of NaN, not None (which means "not asked for").
    one = mcint.sobol_indices(lambda x: x[:, 0] ** 2, Uniform([0], [1]), second_order=True, seed=1)
    assert one.second_order.shape == (1, 1) and np.isnan(one.second_order[0, 0])
    with pytest.raises(ValueError, match="second_order=True"):
        mcint.sobol_indices(ishigami, CUBE, n=1 << 10, seed=3).ci("second_order")
    assert r.model_evaluations == r.points * 8  # A, B, three AB_j, three BA_j


def test_intervals_cover_at_the_nominal_rate():
    first, total, _ = ishigami_exact()
    seeds = 50
    covered = np.zeros((2, 3), dtype=int)
    for seed in range(seeds):
        r = mcint.sobol_indices(ishigami, CUBE, n=1 << 12, seed=seed)
        for row, (ci, exact) in enumerate([(r.ci("first_order"), first), (r.ci("total"), total)]):
            covered[row] += (ci[:, 0] <= exact) & (exact <= ci[:, 1])
    # Binomial(50, 0.95) per index: mean 47.5, standard deviation 1.54; 4.5 of them below
    # is 40.6.
    assert covered.min() >= 41, covered


def test_several_outputs_groups_and_a_gaussian_law():
    def two(x):
        return np.stack([x[:, 0] + 2 * x[:, 1], x[:, 2]], axis=1)

    law = Gaussian([0.0, 0.0, 0.0], np.diag([1.0, 1.0, 1.0]))
    r = mcint.sobol_indices(two, law, groups=[[0, 1], [2]], seed=1)
    assert r.first_order.shape == (2, 2)
    # Output 0 depends on the group {0, 1} alone, output 1 on input 2 alone.
    assert np.allclose(r.first_order, [[1, 0], [0, 1]], atol=1e-3)
    assert np.allclose(r.variance, [5.0, 1.0], rtol=1e-2)


def test_an_exception_in_the_model_propagates():
    def broken(x):
        if len(x) > 1:
            raise RuntimeError("model failed")
        return x[:, 0]

    with pytest.raises(RuntimeError, match="model failed"):
        mcint.sobol_indices(broken, CUBE, seed=0)


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        (dict(inputs="cube"), TypeError, "measure"),
        (dict(groups=[[0], [7]]), ValueError, "group"),
        # A flat list raised a bare "'int' object is not iterable".
        (dict(groups=[0, 1]), TypeError, r"invalid groups = \[0, 1\]: expected a list of lists"),
        (dict(groups=3), TypeError, "invalid groups = 3: expected a list of lists"),
        (dict(groups=[[0], "ab"]), TypeError, "group 1 is 'ab'"),
        (dict(n=1001), ValueError, "invalid n = 1001: expected a positive multiple"),
        (dict(n=None, replicates=3), ValueError, r"invalid n = 65536 \(the default\)"),
        (dict(replicates=0), ValueError, "replicates"),
        (
            dict(replicates=2**64),
            ValueError,
            r"replicates = 18446744073709551616: expected a whole number 1 to 2\*\*64 - 1",
        ),
        (dict(groups=[[0, 2**64]]), ValueError, r"groups = 18446744073709551616"),
        (dict(rtol=0.0), ValueError, "rtol"),
        (dict(rtol=1e-20), ValueError, "rtol = 1e-20"),
        (dict(max_evals=1 << 14), ValueError, "rtol or atol"),
        (dict(atol=1e-3, max_evals=0), ValueError, "max_evals"),
        (dict(f=lambda x: np.ones(len(x))), ValueError, "variance"),
        (dict(f=lambda x: x.ravel()), ValueError, "shape"),
    ],
)
def test_bad_input_is_a_clear_error(kwargs, error, words):
    args = dict(f=ishigami, inputs=CUBE, n=1 << 10, seed=0)
    args.update(kwargs)
    with pytest.raises(error, match=words):
        mcint.sobol_indices(**args)


def test_an_unreachable_tolerance_stops_at_max_evals():
    r = mcint.sobol_indices(ishigami, CUBE, n=1 << 10, atol=1e-9, max_evals=1 << 14, seed=0)
    assert r.converged is False
    assert r.stop_reason == "max evaluations"
    assert 1 << 10 <= r.points <= 1 << 14
    assert r.model_evaluations == 5 * r.points
    assert any(w.kind == "tolerance-not-met" for w in r.warnings)


def test_a_non_finite_model_value_is_named_at_the_models_input():
    # The library's error named a design integral ("output 1") and a point of twice the
    # inputs' dimension; the message now gives the model's own input and run.
    import re

    def model(x):
        return np.where(x[:, 0] > 0.999, np.nan, x[:, 0] + x[:, 1])

    with pytest.raises(FloatingPointError, match=r"the model returned NaN at x = \[") as caught:
        mcint.sobol_indices(model, Uniform([0, 0], [1, 1]), n=1024, seed=1)
    text = str(caught.value)
    assert re.search(r"run (A|B|AB_0|AB_1) of design point \d+ of replicate \d+", text), text
    x = [float(v) for v in re.search(r"x = \[([^\]]*)\]", text).group(1).split(",")]
    assert len(x) == 2 and np.isnan(model(np.array([x])))[0], text
