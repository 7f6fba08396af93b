"""The calibration's model discrepancy (issue 35; noisy ABC under model error, Wilkinson 2013):
the option is read and refused when bad, the discrepancy widens the posterior, the ABC stops at
its level, and the same seed gives the same numbers on any thread count."""
from __future__ import annotations

import numpy as np
import pytest
from test_calibration import TINY, _config, _posterior_json, _truth_record

from drillpy.calibration import abcsmc
from drillpy.calibration.posterior import calibrate_record, predict_posterior
from drillpy.calibration.priors import DEFAULT_DISCREPANCY, discrepancy_factor, prior_spec


@pytest.mark.parametrize("value", [-1, -0.5, float("nan"), float("inf"), 101, "2", True, [1.0]])
def test_a_bad_discrepancy_is_one_error_naming_the_field_and_the_value(value):
    with pytest.raises(ValueError, match=r"^calibration\.discrepancy = .+: a number from 0 \(no discrepancy\) to 100"):
        prior_spec({"discrepancy": value})
    with pytest.raises(ValueError, match=r"^--discrepancy = .+: a number from 0"):
        discrepancy_factor(value, "--discrepancy")


def test_the_discrepancy_is_read_from_the_configuration_and_the_argument_overrides_it():
    assert discrepancy_factor(None) == DEFAULT_DISCREPANCY
    assert prior_spec({"discrepancy": 2}).families  # accepted beside the priors
    rec = _truth_record(duration=6.0)
    tiny = {k: v for k, v in TINY.items() if k != "preset"}
    a = calibrate_record(rec, config=_config(discrepancy=2.5), threads=1, **tiny)
    assert a.run["discrepancy"]["factor"] == 2.5
    sd, scale = a.run["discrepancy"]["sd"], a.scale
    assert all(np.isclose(sd[k], 2.5 * scale[k]) for k in scale)  # in units of each statistic's spread
    assert np.isclose(a.run["discrepancy"]["eps_floor"], 2.5)
    b = calibrate_record(rec, config=_config(discrepancy=2.5), discrepancy=0.0, threads=1, **tiny)
    assert b.run["discrepancy"]["factor"] == 0.0 and b.run["discrepancy"]["eps_floor"] == 0.0
    with pytest.raises(ValueError, match=r"^calibration\.discrepancy = -3: a number from 0"):
        calibrate_record(rec, config=_config(discrepancy=-3), **tiny)
    with pytest.raises(ValueError, match=r"^discrepancy = nan: a number from 0"):
        calibrate_record(rec, discrepancy=float("nan"), **TINY)


def _gaussian(discrepancy):
    """The sampler alone: y ~ N(mu, 0.05), mu in [0, 1], observed 0.5, scale 0.05."""
    def sim(m, Z):
        rng = np.random.default_rng(int(1e6 * Z.sum()) % 2 ** 32)
        return (Z[:, 0] + rng.normal(0, 0.05, len(Z)))[:, None]
    r = abcsmc.run(sim, [1], np.array([0.5]), np.array([0.05]), population=300, max_simulations=20000,
                   max_generations=15, seed=4, discrepancy=discrepancy)
    post = r.posterior
    mu = np.array([z[0] for z in post.z])
    mean = float(np.sum(post.weight * mu))
    return r, mean, float(np.sqrt(np.sum(post.weight * (mu - mean) ** 2)))


def test_the_discrepancy_widens_the_posterior_and_the_abc_stops_at_its_level():
    """Under a model error of sd 0.2 the record y = 0.5 says mu = 0.5 +- sqrt(0.05^2 + 0.2^2) = 0.21
    (less at the prior's edges): the posterior is wider than without (whose width is the simulator's
    0.05 and the final tolerance), and eps is held at the discrepancy's level, 0.2 / 0.05 = 4."""
    r0, mean0, sd0 = _gaussian(None)
    r1, mean1, sd1 = _gaussian(np.array([0.2]))
    assert abs(mean0 - 0.5) < 0.05 and abs(mean1 - 0.5) < 0.1
    assert sd0 < 0.08 and sd1 > 0.15 and sd1 > 2 * sd0
    assert r1.stopped == "discrepancy" and r0.stopped != "discrepancy"
    assert r1.populations[-1].eps == pytest.approx(4.0) and min(p.eps for p in r1.populations) >= 4.0
    assert r0.populations[-1].eps < 4.0


def test_a_discrepancy_of_the_wrong_shape_is_refused():
    with pytest.raises(ValueError, match=r"^discrepancy = .*: one non-negative standard deviation per statistic"):
        abcsmc.run(lambda m, Z: Z, [1], np.array([0.5]), np.array([0.1]), population=4, max_simulations=8,
                   discrepancy=np.array([0.1, 0.2]))


def test_same_seed_same_numbers_with_the_discrepancy_whatever_the_threads_and_it_widens_the_predictive():
    rec = _truth_record(duration=6.0)
    a = calibrate_record(rec, threads=1, discrepancy=2.0, **TINY)
    b = calibrate_record(rec, threads=2, discrepancy=2.0, **TINY)
    assert _posterior_json(a) == _posterior_json(b)
    c = calibrate_record(rec, threads=2, discrepancy=0.0, **TINY)
    assert _posterior_json(a) != _posterior_json(c)
    # the proposals are drawn apart from the discrepancy's draws: the prior's population is the same
    # particles, its statistics moved by the discrepancy
    assert a.run["history"][0]["model_probabilities"] == c.run["history"][0]["model_probabilities"]
    # predict applies the posterior's discrepancy: wider intervals than the same particles without it
    s = a.summary()
    with_d = predict_posterior(s, rec, draws=6, seed=3, threads=2)["statistics"]
    s["run"] = {k: v for k, v in s["run"].items() if k != "discrepancy"}
    without = predict_posterior(s, rec, draws=6, seed=3, threads=2)["statistics"]
    width = {k: (v["interval90"][1] - v["interval90"][0], without[k]["interval90"][1] - without[k]["interval90"][0])
             for k, v in with_d.items()}
    assert sum(w > w0 for w, w0 in width.values()) >= len(width) - 2, width  # a bounded statistic may hit its range


def test_on_a_rig_record_the_default_discrepancy_gives_wider_intervals_that_still_cover_the_truth():
    """The record of test_calibration.py's truth (the declared model, another time step, sensor
    noise), 40 particles, 700 simulations: with the default discrepancy the 90 % intervals are wider
    than without (on average over the parameters, and the command's, the best identified) and
    contain the truth."""
    from test_calibration import TRUTH
    rec = _truth_record()
    par = {}
    for d in (0.0, None):
        post = calibrate_record(rec, config=_config(families=["polynomial"]), population=40, max_simulations=700,
                                predictive_draws=4, seed=5, discrepancy=d)
        par[d] = post.parameters["polynomial"]
        for name, value in TRUTH.items():
            lo, hi = par[d][name]["ci90"]
            assert lo <= value <= hi, (d, name, value, lo, hi)
    assert DEFAULT_DISCREPANCY > 0
    ratio = {d: np.mean([p["width_ratio"] for p in par[d].values()]) for d in par}
    assert ratio[None] > ratio[0.0]
    assert par[None]["command_rad_s"]["width_ratio"] > par[0.0]["command_rad_s"]["width_ratio"]
