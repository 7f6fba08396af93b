"""The loop's test of whether the recorded WOB is an input or a response of the rotation
(:func:`drillpy.loop.data.wob_response`): on the test rig the jack makes the WOB follow the bit's
angle deficit, and a model fed that WOB would be given the stick-slip cycle it should predict."""
from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from drillpy.loop import LoopModel, LoopOptions, evaluate, run_loop
from drillpy.loop.effects import stripped
from drillpy.loop.data import RESPONSE_R, prepare, wob_response
from drillpy.loop.model import wob_errors
from drillpy.loop.prediction import predict_record
from drillpy.model.config import load_config
from drillpy.records.cleaning import clean
from drillpy.records.io import read_record
from drillpy.loop.synthetic import declared_config, synthetic_record

rig = pytest.importorskip("whole_rig")


def test_the_rig_wob_is_a_response_of_the_rotation(testrig_record):
    r = wob_response(clean(read_record(testrig_record))[0])
    # the jack's WOB rises as the bit falls behind its steady rotation (thesis Figs. 5.6-5.7)
    assert r["response"] and r["correlation"] > 0.7
    assert 80.0 < r["gain_n_rad"] < 200.0          # N per rad of deficit (k_ax d / 2 pi of drill/axial.hpp)
    assert abs(r["lag_s"]) < 0.1


def test_an_independent_jack_gives_a_response_and_a_constant_wob_none(tmp_path):
    on = tmp_path / "jack.mat"
    rig.write_mat(rig.simulate({"jack_steps": []}, duration=24.0, seed=5), str(on))
    assert wob_response(clean(read_record(on))[0])["response"]
    off = tmp_path / "constant.mat"
    rig.write_mat(rig.simulate({}, set(rig.ELEMENTS) - {"axial", "noise", "artifacts"}, duration=24.0, seed=5), str(off))
    r = wob_response(clean(read_record(off))[0])
    assert not r["response"]


@pytest.mark.parametrize("seed", [1, 2])
def test_an_exogenous_wob_is_an_input(seed):
    # the synthetic truths' WOB is a band-limited input that drives the torque (wob_coupling)
    r = wob_response(synthetic_record(("wob_coupling",), seed=seed, duration_s=24.0))
    assert not r["response"] and abs(r["correlation"]) < RESPONSE_R


def test_the_loop_feeds_the_law_the_trend_of_a_response(testrig_record):
    cfg = load_config(preset="thesis-rig")
    rec = read_record(testrig_record)
    auto = prepare(rec, cfg, LoopOptions())
    fed = prepare(rec, cfg, LoopOptions(wob_input="measured"))
    assert auto.wob_response["input"] == "trend" and fed.wob_response["input"] == "measured"
    f = np.fft.rfftfreq(auto.t.size, auto.dt)
    band = (f > 2.0) & (f < 3.5)                     # the stick-slip cycle (2.6-2.9 Hz)
    power = [(np.abs(np.fft.rfft(d.ch["W"] - d.ch["W"].mean())) ** 2)[band].sum() for d in (auto, fed)]
    assert power[0] < 1e-2 * power[1]                # the cycle is gone from the law's WOB
    assert np.allclose(auto.wob_measured, fed.ch["W"])  # the recorded WOB is kept as the restart state
    assert abs(auto.ch["W"].mean() - fed.ch["W"].mean()) < 1.0  # the same operating point [N]


def test_wob_input_is_validated():
    with pytest.raises(ValueError, match="wob_input = 'state'"):
        LoopOptions(wob_input="state").validate()


def _jack_config(base: dict, gain: float = 130.0, tau: float = 0.1) -> dict:
    cfg = json.loads(json.dumps(base))
    cfg["axial"] = {"type": "jack", "gain_n_rad": gain, "relaxation_s": tau}
    return cfg


@pytest.fixture(scope="module")
def jack_record():
    # a noise-free record of the declared model with the jack: its WOB is the axial state
    return synthetic_record({"axial_jack": {"gain_n_rad": 130.0, "relaxation_s": 0.1}}, duration_s=12.0, seed=3,
                            fs_hz=1000.0, noise=0.0, nuisance=False)


def test_the_loop_calibrates_a_declared_jack_and_predicts_its_own_record(jack_record):
    """The jack's WOB is a state restarted from the record (restart_wob) and relaxed towards the
    trend (wob_input): the model with it predicts its own record, the same model without it does not."""
    opt = LoopOptions(rate_hz=1000.0, dt_s=1e-4, max_steps=0, long_run=False, discovery=False, backward=False)
    quiet = dict(log=lambda *a: None)
    with_jack = run_loop(jack_record, _jack_config(declared_config(), 90.0, 0.2), opt, **quiet)
    assert with_jack.data.wob_response["input"] == "trend"   # the record's WOB follows the bit's deficit
    p = with_jack.baseline.model.effects["axial_jack"]
    # calibrated from 90 N/rad and 0.2 s: one stick-slip frequency pins the steady WOB per rad/s of
    # speed deficit, g tau (13 N s/rad), better than g and tau apart (g 175-186, tau 0.065 s)
    assert p["gain_n_rad"] * p["relaxation_s"] == pytest.approx(13.0, rel=0.15)
    without = run_loop(jack_record, declared_config(), opt, **quiet)
    assert with_jack.baseline.E_test < 0.05
    assert without.baseline.E_test > 3 * with_jack.baseline.E_test
    # the horizons report the WOB the law saw: the truth's jack follows the recorded WOB over each
    # horizon (0.065 of the WOB's spread, against 0.012 for E), the calibrated one less closely (0.17: the
    # bit's channels pin g tau, not g and tau apart); without the jack the law's WOB is the trend (1.0)
    truth = with_jack.baseline.model.copy()
    truth.effects = {**truth.effects, "axial_jack": {"gain_n_rad": 130.0, "relaxation_s": 0.1}}
    e_w = {k: float(np.sqrt(np.mean(wob_errors(ev.wob, with_jack.data)))) for k, ev in (
        ("truth", evaluate(truth, with_jack.data)), ("calibrated", with_jack.baseline), ("none", without.baseline))}
    assert e_w["truth"] < 0.1 and e_w["calibrated"] < 0.25 and e_w["none"] > 0.8, e_w
    # drillpy predict reports it for the model with the jack (the same horizons), not for the one without
    pred = {k: predict_record(r.baseline.model, jack_record) for k, r in (("jack", with_jack), ("none", without))}
    assert pred["jack"].wob_horizon_error == pytest.approx(e_w["calibrated"], rel=1e-9)
    assert pred["none"].wob_horizon_error is None
    # the model file carries the intervals and says what it takes from a record
    d = with_jack.baseline.model.to_dict()
    lo, hi = d["intervals"]["axial_jack"]["gain_n_rad"]["ci95"]
    assert lo < p["gain_n_rad"] < hi
    assert d["predictive"] and d["wob_input"] == "trend" and "trend" in d["inputs"]["wob"]


def test_a_model_fed_a_wob_that_responds_to_the_rotation_is_a_diagnosis():
    cfg = stripped(load_config(preset="thesis-rig"))
    fed = LoopModel(cfg, dict(cfg["law"]), 8.5, 557.1, {"wob_coupling": {"gain": 1.0}}, wob_input="measured",
                    wob_is_response=True)
    assert not fed.predictive
    assert LoopModel.from_dict(fed.to_dict()).predictive is False
    for m in (dataclasses.replace(fed, wob_input="trend"), dataclasses.replace(fed, wob_is_response=False),
              dataclasses.replace(fed, effects={})):
        assert m.predictive
    kinematic = dataclasses.replace(fed, effects={"top_drive_dynamics": {"variant": "measured"}})
    assert not kinematic.predictive


def test_a_record_too_short_to_test_the_wob_takes_the_input_the_model_declares(testrig_record):
    # under 10 s (five periods of the 0.5 Hz trend) the response test cannot run; a forced input still holds
    short = read_record(testrig_record).select(30.0, 38.0)
    cfg = load_config(preset="thesis-rig")
    auto = prepare(short, cfg, LoopOptions())
    trend = prepare(short, cfg, LoopOptions(wob_input="trend"))
    assert auto.wob_response is None and auto.wob_measured is None      # untested: the recorded WOB, as before
    assert trend.wob_response["input"] == "trend" and trend.wob_response["correlation"] is None
    f = np.fft.rfftfreq(trend.t.size, trend.dt)
    band = (f > 2.0) & (f < 3.5)                     # the stick-slip cycle
    power = [(np.abs(np.fft.rfft(d.ch["W"] - d.ch["W"].mean())) ** 2)[band].sum() for d in (trend, auto)]
    assert power[0] < 5e-2 * power[1]                # (1.8 %: the zero-phase filter's edges on 8 s)
    assert np.allclose(trend.wob_measured, auto.ch["W"])   # the recorded WOB stays the jack's restart state


def test_the_rig_models_horizons_do_not_depend_on_the_windows_length(testrig_record):
    # the whole-rig model's jack is driven by the slow WOB trend in its long runs; its horizons too, on a
    # window too short for the response test (the recorded WOB would feed it the cycle)
    from drillpy.loop.prediction import rig_horizons
    from drillpy.records import rigsim
    law = load_config(preset="rgd-rig")["law"]
    m = rigsim.RigModel(law, 0.0303, "rig", 0.25, 0.0186, command_rad_s=17.27, jack_gain_n_rad=181.8,
                        jack_relaxation_s=0.0987, platform_damping=0.75, gj_factor=1.0475,
                        bit_inertia_factor=1.07, coupling_stiffness_nm_rad=41.0)
    raw = read_record(testrig_record)
    runs = {}
    for t0, t1 in ((26.0, 40.0), (32.0, 40.0)):
        data, ev = rig_horizons(m, clean(raw.select(t0, t1))[0], 17.27, threads=1)
        assert data.wob_response["input"] == "trend"
        runs[(t0, t1)] = dict(zip(np.round(data.t[data.starts], 2), ev.e_h))
    a, b = runs[(26.0, 40.0)], runs[(32.0, 40.0)]
    common = sorted(set(a) & set(b))[4:]             # away from the short window's first second (its filters' edge)
    assert len(common) >= 20
    ea, eb = (np.sqrt(np.mean([r[t] for t in common])) for r in (a, b))
    assert eb == pytest.approx(ea, rel=0.05)         # the same horizons score alike from either window
