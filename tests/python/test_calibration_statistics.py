"""The WOB above its trend (issue 35, item 2): a summary statistic of what the rig model must produce
itself, and ``calibration.statistics``, the statistics of the distance."""
from __future__ import annotations

import numpy as np
import pytest

from drillpy.calibration.posterior import RigSimulator, calibrate_record, predict_posterior
from drillpy.calibration.priors import prior_spec
from drillpy.calibration.summaries import ALL_NAMES, NAMES, noise_scale, statistics, summaries, wob_above_trend_std
from drillpy.model.config import load_config
from drillpy.records import rigsim
from test_calibration import TRUTH, _config, _truth_record

#: The prototype's jack truth (docs/calibration.md, "What is not done"): the test's truth at 20 rad/s and
#: a damping ratio of 0.02, its jack at 180 N/rad; stick-slip at 2.86 Hz.
JACK_TRUTH = {**TRUTH, "command_rad_s": 20.0, "damping_ratio": 0.02}
WITH = (*NAMES, "wob_above_trend_std")


def test_the_wob_above_its_trend_keeps_the_cycle_and_leaves_out_the_trend():
    dt = 1e-3
    t = np.arange(0.0, 10.0, dt)
    trend = 557.0 + 30.0 * np.sin(2 * np.pi * 0.1 * t)
    cycle = 20.0 * np.sin(2 * np.pi * 2.8 * t)
    # the cycle's standard deviation 20 / sqrt(2) = 14.14 N, the trend's 21.2 N left out
    assert wob_above_trend_std(trend + cycle, dt) == pytest.approx(20.0 / np.sqrt(2.0), rel=0.03)
    assert wob_above_trend_std(trend, dt) < 0.5
    assert np.std(trend + cycle) == pytest.approx(np.hypot(30.0, 20.0) / np.sqrt(2.0), rel=0.03)
    assert np.isnan(wob_above_trend_std(trend[:20], dt))
    # the default statistics are those of before; the new one is asked for by name
    v = 9.0 + 5.0 * np.sin(2 * np.pi * 2.8 * t)
    tq = 2.0 + 0.5 * np.cos(2 * np.pi * 2.8 * t)
    a = statistics(v, tq, v, trend + cycle, dt, 0.5)
    b = statistics(v, tq, v, trend + cycle, dt, 0.5, WITH)
    assert a.size == len(NAMES) == 13 and b.size == 14
    assert np.array_equal(a, b[:13])
    assert b[-1] == pytest.approx(wob_above_trend_std(trend + cycle, dt))


def test_on_a_jack_truth_the_wob_above_its_trend_separates_the_model_with_the_jack_from_the_one_without():
    """At the truth's parameters the calibration's simulator (2.5e-4 s) with the jack is within one noise
    scale of the record (5e-5 s) on the WOB above its trend, without it far off; the WOB's standard
    deviation, which carries the trend the model is given, does not tell them apart (both off)."""
    rec = _truth_record(duration=10.0, truth=JACK_TRUTH)
    thr = rigsim.stick_threshold(rec)
    obs = summaries(rec, thr, 2.0, WITH)
    scale = noise_scale(rec, thr, skip_s=2.0, names=WITH)
    sim = RigSimulator(rec, thr, prior_spec({"families": ["polynomial"], "statistics": list(WITH)}),
                       load_config(preset="thesis-rig")["law"], threads=1)
    z_with = (sim.one("polynomial", JACK_TRUTH) - obs) / scale
    z_without = (sim.one("polynomial", {**JACK_TRUTH, "jack_gain_n_rad": 0.0}) - obs) / scale
    above, total = WITH.index("wob_above_trend_std"), WITH.index("wob_std")
    assert abs(z_with[above]) < 1.0, z_with[above]
    assert z_without[above] < -5.0, z_without[above]
    # the total WOB sd: the model with the jack is off by as much as the one without (the record's trend,
    # the model's input, already holds the jack's slow response)
    assert abs(z_with[total]) > 3.0 and abs(z_without[total]) > 3.0, (z_with[total], z_without[total])


@pytest.mark.parametrize("stats", [[], ["wob_std", "wob_std"], ["wob_rms"], "ss"])
def test_a_bad_statistics_list_is_one_error_naming_the_field(stats):
    with pytest.raises(ValueError, match=r"calibration\.statistics = .*: a non-empty list of distinct statistics"):
        prior_spec({"statistics": stats})


def test_the_chosen_statistics_go_into_the_posterior_and_its_prediction():
    rec = _truth_record(duration=6.0)
    post = calibrate_record(rec, config=_config(statistics=list(WITH)), population=8, max_simulations=40,
                            predictive_draws=4, seed=11, threads=1)
    s = post.summary()
    assert list(s["observed"]) == list(WITH) == list(s["scale"]) == list(s["units"])
    assert s["priors"]["statistics"] == list(WITH) and s["units"]["wob_above_trend_std"] == "N"
    assert set(post.predictive) <= set(WITH) and "wob_above_trend_std" in post.predictive
    pred = predict_posterior(s, rec, draws=4, seed=3, threads=1)["statistics"]
    assert "wob_above_trend_std" in pred
    # a posterior written before the option (no statistics in its priors) predicts the default set
    old = {**s, "priors": {k: v for k, v in s["priors"].items() if k != "statistics"}}
    assert set(predict_posterior(old, rec, draws=4, seed=3, threads=1)["statistics"]) <= set(NAMES)
    assert set(ALL_NAMES) == set(WITH)


def test_posterior_map_without_an_output_folder_prints_the_map(tmp_path):
    """``drillpy posterior-map POSTERIOR --map ... --json`` without ``--out`` (the fuzzer's case with
    ``--chunk 0``: it crashed in the output folder's guard, given None): exit 0 and the map's JSON;
    with ``--chunk 0`` one error naming it."""
    import json

    from test_fuzz import _fixtures, run_cli
    _fixtures(tmp_path)
    argv = ["posterior-map", str(tmp_path / "posterior.json"), "--map", "8:26:2,560:560:1", "--samples", "2", "--json"]
    rc, out, err = run_cli(argv)
    assert rc == 0, err
    m = json.loads(out.strip().splitlines()[-1])
    assert len(m["p_unstable"]) == 1 and len(m["p_unstable"][0]) == 2 and all(0 <= p <= 1 for p in m["p_unstable"][0])
    rc, out, err = run_cli([*argv, "--chunk", "0"])
    assert rc == 2 and "chunk" in err, err
