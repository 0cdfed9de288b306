"""``mcint.mlmc``: a multilevel run of a numpy model meets its RMSE target against a closed
form, repeats bit for bit, reports what the command line's ``mlmc --json`` reports, warns
as the library does, and turns every bad input into one clear exception."""

import json
import math
import subprocess

import numpy as np
import pytest
from scipy.special import ndtri

import mcint
import rust_cli

# Geometric Brownian motion S0 = 100, r = 0.05, sigma = 0.2 to T = 1; the discounted
# European call at strike 100 is Black-Scholes' 10.450583572185565.
S0, RATE, SIGMA, STRIKE = 100.0, 0.05, 0.2, 100.0


def black_scholes_call():
    d1 = (math.log(S0 / STRIKE) + RATE + SIGMA**2 / 2) / SIGMA
    d2 = d1 - SIGMA
    phi = lambda x: 0.5 * math.erfc(-x / math.sqrt(2))
    return S0 * phi(d1) - STRIKE * math.exp(-RATE) * phi(d2)


def euler_call(l, u):
    """Level l: Euler on 2**l steps (fine) and 2**(l-1) steps from the same increments."""
    n, steps = u.shape
    h = 1.0 / steps
    dw = math.sqrt(h) * ndtri(u)
    discount = math.exp(-RATE)
    payoff = lambda s: discount * np.maximum(s - STRIKE, 0.0)
    fine = S0 * np.prod(1 + RATE * h + SIGMA * dw, axis=1)
    if l == 0:
        return payoff(fine), np.zeros(n)
    pairs = dw.reshape(n, steps // 2, 2).sum(axis=2)
    coarse = S0 * np.prod(1 + RATE * 2 * h + SIGMA * pairs, axis=1)
    return payoff(fine), payoff(coarse)


def steps(l):
    return 2**l


def test_a_european_call_meets_its_target():
    exact = black_scholes_call()
    assert abs(exact - 10.450583572185565) < 1e-12
    for qmc in (False, True):
        r = mcint.mlmc(euler_call, 0.05, dims=steps, qmc=qmc, seed=3)
        assert r.converged and r.stop_reason == "tolerance met", r
        # The run aims at an RMSE of 0.05 (bias and sampling): 4 of them is far in the tail.
        assert abs(r.estimate - exact) < 4 * 0.05, (qmc, r.estimate)
        assert r.rmse <= 0.05 * (1 + 1e-12)
        assert math.isclose(r.rmse, math.hypot(r.std_error, r.bias), rel_tol=1e-12)
        assert [lv.level for lv in r.levels] == list(range(len(r.levels)))
        assert all(lv.cost == 2.0**lv.level for lv in r.levels)
        assert r.replicates == (32 if qmc else 1)
        # The estimate is the sum of the level means (the telescoping sum).
        assert math.isclose(r.estimate, sum(lv.mean for lv in r.levels), rel_tol=1e-9)


def test_runs_repeat_bit_for_bit_over_threads():
    one = mcint.mlmc(euler_call, 0.1, dims=steps, seed=11, threads=1)
    two = mcint.mlmc(euler_call, 0.1, dims=steps, seed=11, threads=2)
    assert one.to_dict() == two.to_dict()
    other = mcint.mlmc(euler_call, 0.1, dims=steps, seed=12)
    assert other.estimate != one.estimate


def test_the_report_has_the_command_line_keys():
    r = mcint.mlmc(euler_call, 0.1, dims=steps, cost=lambda l: 1.5 * 2**l, seed=1)
    d = r.to_dict()
    for key in ("estimate", "std_error", "bias", "rmse", "eps", "levels", "alpha", "beta",
                "gamma", "refinement", "cost", "standard_mc_cost", "converged", "stop",
                "warnings", "seed"):
        assert key in d, key
    assert set(d["levels"][0]) == {"level", "n", "mean", "variance", "std_error", "cost",
                                   "fine_mean", "fine_variance", "kurtosis", "check"}
    assert d["levels"][2]["cost"] == 6.0
    assert d["eps"] == 0.1 and d["refinement"] == 2
    assert "MultilevelResult(estimate=" in repr(r)


def test_a_capped_level_warns_and_says_why_it_stopped():
    with pytest.warns(mcint.McintWarning, match="bias"):
        r = mcint.mlmc(euler_call, 0.005, dims=steps, max_level=3, seed=2)
    assert (r.stop_reason, r.converged) == ("max level", False)
    assert len(r.levels) == 4
    assert "bias-above-target" in [w.kind for w in r.warnings]
    with pytest.warns(mcint.McintWarning, match="tolerance"):
        r = mcint.mlmc(euler_call, 0.001, dims=steps, max_cost=1e5, seed=2)
    assert r.stop_reason == "max evaluations" and r.cost <= 1e5


def test_a_model_with_a_wrong_coupling_is_flagged():
    # The coarse path of level l scaled by 1.1 does not have the law of level l-1's fine
    # path: Giles' consistency check sees it. Its corrections never shrink, so the run is
    # held to level 5.
    def miscoupled(l, u):
        fine, coarse = euler_call(l, u)
        return fine, 1.1 * coarse

    with pytest.warns(mcint.McintWarning):
        r = mcint.mlmc(miscoupled, 0.05, dims=steps, max_level=5, seed=4)
    assert "inconsistent-levels" in [w.kind for w in r.warnings]


def test_a_coupling_error_stops_the_run():
    # Coarse samples 1.1 times what level l-1's fine ones are: every correction has mean about
    # -1/30, so the bias estimate never falls. Level 1's consistency check passes six
    # standard errors at about 13,000 samples, which the allocation for 0.001 gives it with
    # three or four levels (the library's test of the same levels says how); without the
    # stop the run would add levels to the deepest allowed, 20.
    def miscoupled(l, u):
        fine = u[:, 0] ** 2 + 0.5**l
        coarse = 1.1 * u[:, 0] ** 2 + 0.5 ** (l - 1) if l > 0 else np.zeros(len(u))
        return fine, coarse

    with pytest.warns(mcint.McintWarning) as caught:
        r = mcint.mlmc(miscoupled, 0.001, dims=1, seed=11)
    assert any("consistency check" in str(w.message) for w in caught)
    assert r.stop_reason == "inconsistent levels" and not r.converged, r
    assert len(r.levels) <= 6
    assert "inconsistent-levels" in [w.kind for w in r.warnings]


def test_a_time_limit_longer_than_a_duration_is_no_limit():
    r = mcint.mlmc(euler_call, 0.1, dims=steps, time_limit=1e300, seed=1)
    assert r.converged and r.stop_reason == "tolerance met"


def test_the_model_sees_canonical_blocks():
    seen = []

    def level(l, u):
        seen.append((l, u.shape, u.dtype, float(u.min()), float(u.max())))
        return euler_call(l, u)

    mcint.mlmc(level, 0.2, dims=steps, seed=5, threads=1)
    for l, shape, dtype, low, high in seen:
        assert shape[1] == 2**l and 1 <= shape[0] <= 4096 and dtype == np.float64
        assert 0.0 <= low and high < 1.0


def test_bad_input_is_one_clear_exception():
    with pytest.raises(TypeError, match="level"):
        mcint.mlmc(3, 0.1, dims=1)
    with pytest.raises(ValueError, match="rmse"):
        mcint.mlmc(euler_call, -1.0, dims=steps)
    with pytest.raises(TypeError, match="rmse"):
        mcint.mlmc(euler_call, None, dims=steps)
    with pytest.raises(ValueError, match="dims"):
        mcint.mlmc(euler_call, 0.1, dims=0)
    with pytest.raises(ValueError, match="dims = 'x' at level 0"):
        mcint.mlmc(euler_call, 0.1, dims=lambda l: "x")
    with pytest.raises(ValueError, match="cost"):
        mcint.mlmc(euler_call, 0.1, dims=steps, cost=lambda l: -1.0)
    with pytest.raises(ValueError, match="dims = 1180591620717411303424 at level 0"):
        mcint.mlmc(euler_call, 0.1, dims=2**70)
    # More coordinates than the sampler gives: the model's dims are named, not min_level.
    with pytest.raises(ValueError, match=r"level dims = 1073741824 at level 0: expected 1 to"):
        mcint.mlmc(euler_call, 0.1, dims=2**30)
    # Integers past what the extension takes say what is allowed (no bare OverflowError).
    with pytest.raises(ValueError, match=r"samples = 18446744073709551616: expected a whole "
                       r"number 2 to 2\*\*64 - 1"):
        mcint.mlmc_survey(euler_call, 3, 2**64, dims=steps)
    with pytest.raises(ValueError, match="min_level = 18446744073709551616: expected a whole "
                       "number 1 to 60"):
        mcint.mlmc(euler_call, 0.1, dims=steps, min_level=2**64)
    for refinement in (1, 2**40):
        with pytest.raises(ValueError, match="refinement"):
            mcint.mlmc(euler_call, 0.1, dims=steps, refinement=refinement)
    # Floats that Python and Rust write out in hundreds of digits are shown with exponents.
    with pytest.raises(ValueError, match=r"max_cost = 1e-300: expected"):
        mcint.mlmc(euler_call, 0.1, dims=steps, max_cost=1e-300)
    with pytest.raises(ValueError, match="min_level"):
        mcint.mlmc(euler_call, 0.1, dims=steps, min_level=5, max_level=3)
    with pytest.raises(ValueError, match=r"shapes \(3,\) and"):
        mcint.mlmc(lambda l, u: (np.zeros(3), np.zeros(3)), 0.1, dims=1)
    with pytest.raises(TypeError, match="pair"):
        mcint.mlmc(lambda l, u: 1.0, 0.1, dims=1)
    with pytest.raises(ValueError, match="level 0 has no coarser level"):
        mcint.mlmc(lambda l, u: (u[:, 0], u[:, 0]), 0.1, dims=1)
    with pytest.raises(FloatingPointError, match="level sample"):
        mcint.mlmc(lambda l, u: (np.full(len(u), np.nan), np.zeros(len(u))), 0.1, dims=1)

    class Boom(Exception):
        pass

    def failing(l, u):
        if l == 1:
            raise Boom("the model failed")
        return euler_call(l, u)

    with pytest.raises(Boom, match="the model failed"):
        mcint.mlmc(failing, 0.1, dims=steps)


def test_a_survey_shows_the_euler_rates_and_flags_a_wrong_coupling():
    s = mcint.mlmc_survey(euler_call, 5, 20_000, dims=steps, seed=1)
    assert [lv.level for lv in s.levels] == list(range(6))
    assert all(lv.n == 20_000 for lv in s.levels)
    assert s.target is None and s.converged is False
    # Euler on GBM: V_l ~ h_l (beta 1); the library's own survey test allows 0.3 at this
    # size. (alpha, from means of a few 1e-3 with standard errors near their size on the
    # deep levels, is not checked.)
    assert abs(s.beta - 1) < 0.3, s.beta
    assert all(lv.check < 1 for lv in s.levels[1:])

    def miscoupled(l, u):
        fine, coarse = euler_call(l, u)
        return fine, 1.1 * coarse

    with pytest.warns(mcint.McintWarning, match="law"):
        bad = mcint.mlmc_survey(miscoupled, 3, 20_000, dims=steps, seed=1)
    assert max(lv.check for lv in bad.levels[1:]) > 1
    assert "inconsistent-levels" in [w.kind for w in bad.warnings]


def test_bad_survey_input_is_one_clear_exception():
    for levels in (0, 61, None):
        with pytest.raises((ValueError, TypeError), match="invalid levels"):
            mcint.mlmc_survey(euler_call, levels, 100, dims=steps)
    for samples in (1, None, 2.5):
        with pytest.raises((ValueError, TypeError), match="samples"):
            mcint.mlmc_survey(euler_call, 3, samples, dims=steps)
    # The library's own check names the keyword too (not the `n` of the point sets).
    with pytest.raises(ValueError, match=r"invalid samples = 1099511627777: expected 2 to 2\^40"):
        mcint.mlmc_survey(euler_call, 3, 2**40 + 1, dims=steps)


# The library's own levels (mcint.SdeLevels): sampled in Rust, with the command line's bits.

def command_line_mlmc(*args):
    """`mlmc --json` of the Rust CLI."""
    out = subprocess.run([str(rust_cli.binary("mlmc")), "--json", *args], check=True,
                         capture_output=True)
    return json.loads(out.stdout)


def test_sde_levels_price_a_european_call():
    exact = black_scholes_call()
    for qmc in (False, True):
        r = mcint.mlmc(mcint.SdeLevels.gbm(S0, RATE, SIGMA, strike=STRIKE), 0.01, qmc=qmc,
                       seed=3)
        assert r.converged and r.stop_reason == "tolerance met", r
        # An RMSE target of 0.01: 4 of them is far in the tail.
        assert abs(r.estimate - exact) < 4 * 0.01, (qmc, r.estimate)
        # Milstein takes one step at level 0 and 2**l at level l; a correction pays for
        # its coarse path too (Level::cost in the library).
        assert [lv.cost for lv in r.levels[:3]] == [1.0, 3.0, 6.0]


def test_heston_with_frozen_variance_prices_black_scholes():
    # xi = 0 and v0 = theta: the variance stays SIGMA**2, and the price is Black-Scholes'.
    levels = mcint.SdeLevels.heston(S0, SIGMA**2, RATE, 2.0, SIGMA**2, 0.0, -0.7,
                                    strike=STRIKE)
    r = mcint.mlmc(levels, 0.02, seed=5)
    assert r.converged, r
    assert abs(r.estimate - black_scholes_call()) < 4 * 0.02, r.estimate


@pytest.mark.parametrize(
    "build, flags",
    [
        (lambda: mcint.SdeLevels.gbm(payoff="asian"), ["--payoff", "asian"]),
        (
            lambda: mcint.SdeLevels.heston(payoff="barrier", barrier=90.0, refinement=4),
            ["--model", "heston", "--payoff", "barrier", "--barrier", "90", "--refinement",
             "4"],
        ),
        (lambda: mcint.SdeLevels.gbm(payoff="lookback", scheme="euler"),
         ["--payoff", "lookback", "--scheme", "euler"]),
    ],
)
@pytest.mark.parametrize("qmc", [False, True])
def test_sde_levels_give_the_bits_of_the_command_line(build, flags, qmc):
    r = mcint.mlmc(build(), 0.05, qmc=qmc, seed=7)
    cli = command_line_mlmc(*flags, "--eps", "0.05", "--seed", "7", *(["--qmc"] if qmc else []))
    assert r.estimate == cli["estimate"] and r.std_error == cli["std_error"]
    assert [lv.n for lv in r.levels] == [lv["n"] for lv in cli["levels"]]


def test_sde_levels_take_the_run_settings():
    levels = mcint.SdeLevels.gbm()
    with pytest.warns(mcint.McintWarning, match="tolerance"):
        r = mcint.mlmc(levels, 1e-4, max_cost=1e6, seed=2)
    assert (r.stop_reason, r.converged) == ("max evaluations", False) and r.cost <= 1e6
    one = mcint.mlmc(levels, 0.05, seed=11, threads=1)
    assert one.to_dict() == mcint.mlmc(levels, 0.05, seed=11, threads=2).to_dict()
    s = mcint.mlmc_survey(levels, 6, 20_000, seed=1)
    assert [lv.n for lv in s.levels] == [20_000] * 7
    # Milstein on GBM: V_l ~ h_l**2 (beta 2, Giles 2008); the Euler survey above allows 0.3.
    assert abs(s.beta - 2) < 0.3, s.beta
    assert all(lv.check < 1 for lv in s.levels[1:])


def test_bad_sde_levels_are_one_clear_exception():
    gbm, heston = mcint.SdeLevels.gbm, mcint.SdeLevels.heston
    for call, error, match in [
        (lambda: gbm(s0=-1.0), ValueError, "s0"),
        (lambda: gbm(sigma=float("nan")), ValueError, "sigma"),
        (lambda: gbm(s0="100"), TypeError, "s0"),
        (lambda: gbm(maturity=0.0), ValueError, "maturity"),
        (lambda: gbm(maturity=1e-320), ValueError, "maturity = 1e-320: expected a finite time"),
        (lambda: gbm(rate=-1e300), ValueError, "rate = -1e300 with maturity = 1e0"),
        (lambda: gbm(rate=1e300, maturity=1e10), ValueError, "discount"),
        (lambda: gbm(payoff="put"), ValueError, "'european', 'asian'"),
        (lambda: gbm(scheme="rk4"), ValueError, "'euler' or 'milstein'"),
        (lambda: gbm(scheme=1), TypeError, "scheme"),
        (lambda: gbm(refinement=1), ValueError, "refinement"),
        (lambda: gbm(refinement=17), ValueError, "2 to 16"),
        (lambda: gbm(refinement=2.0), TypeError, "refinement"),
        (lambda: gbm(payoff="lookback", strike=90.0), ValueError, "floating strike"),
        (lambda: gbm(barrier=80.0), ValueError, "payoff='barrier' only"),
        (lambda: gbm(strike=float("inf")), ValueError, "strike"),
        (lambda: heston(rho=2.0), ValueError, "rho"),
        (lambda: heston(scheme="milstein"), ValueError, "'euler'"),
        (lambda: mcint.SdeLevels(None), TypeError, "SdeLevels.gbm"),
        (lambda: mcint.mlmc(gbm(), 0.01, dims=3), TypeError, "dims does not apply"),
        (lambda: mcint.mlmc(gbm(), 0.01, refinement=4), TypeError, "refinement"),
        (lambda: mcint.mlmc(gbm(), 0.0), ValueError, "rmse"),
        (lambda: mcint.mlmc_survey(gbm(), 3, 100, weak_order=1.0), TypeError, "weak_order"),
        (lambda: mcint.mlmc(euler_call, 0.01), TypeError, "invalid dims = None"),
    ]:
        with pytest.raises(error, match=match):
            call()


def test_ctrl_c_stops_a_run_of_sde_levels():
    # No Python code runs during the run: the waiting thread's signal check stops it. To
    # 1e-3 the run costs about 1e9 time steps (minutes) should the interrupt be lost.
    import _thread
    import threading

    timer = threading.Timer(0.2, _thread.interrupt_main)  # as Ctrl-C does
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            mcint.mlmc(mcint.SdeLevels.gbm(), 1e-3, seed=1)
    finally:
        timer.cancel()
