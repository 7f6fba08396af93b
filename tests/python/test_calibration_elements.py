"""Models over the rig's elements in the calibration's comparison (``"FAMILY without ELEMENT"``,
drillpy.calibration.elements; issue 35, item 2)."""
from __future__ import annotations

import numpy as np
import pytest

from drillpy.calibration.elements import ELEMENTS, left_out, parse_model
from drillpy.calibration.posterior import RigSimulator, calibrate_record, predict_posterior
from drillpy.calibration.priors import RIG_CALIBRATED, prior_spec
from drillpy.model.config import load_config
from drillpy.records import rigsim
from test_calibration import TRUTH, _config, _truth_record
from test_calibration_statistics import JACK_TRUTH, WITH

MODELS = ["polynomial", "polynomial without jack", "polynomial without coupling", "polynomial without motor"]


def test_a_model_without_an_element_holds_its_parameter_and_calibrates_the_rest():
    spec = prior_spec({"families": [*MODELS, "tucker_wang without coupling, jack"]})
    names = {m: [p.name for p in ps] for m, ps in spec.families.items()}
    assert names["polynomial without jack"] == [p for p in names["polynomial"] if p != "jack_gain_n_rad"]
    assert names["polynomial without coupling"] == [p for p in names["polynomial"] if p != "coupling_stiffness_nm_rad"]
    assert names["tucker_wang without coupling, jack"][:3] == list(RIG_CALIBRATED[:3])
    assert "jack_gain_n_rad" not in names["tucker_wang without coupling, jack"]
    assert parse_model("tucker_wang without coupling, jack") == ("tucker_wang", ("jack", "coupling"))
    assert left_out("polynomial without jack, coupling") == {"jack_gain_n_rad": 0.0, "coupling_stiffness_nm_rad": None}
    assert set(ELEMENTS) == {"jack", "coupling", "motor"}
    assert left_out("polynomial without motor") == {"motor_slope_nms_rad": None}


@pytest.mark.parametrize("models, match", [
    (["polynomial without platform"], r"\]: model 'polynomial without platform': unknown element 'platform' \(use jack, coupling, motor\)"),
    (["polynomial without jack, jack"], r"an element named twice"),
    (["polynomial without "], r"unknown element ''"),
    (["poly without jack"], r"unknown family 'poly'"),
    (["polynomial without jack", "polynomial without  jack"], r": a model named twice"),
    ([3], r"\]: model 3: a name"),
])
def test_a_bad_model_name_is_one_error_naming_the_field_and_the_value(models, match):
    with pytest.raises(ValueError, match=r"calibration\.families = \[.*" + match):
        prior_spec({"families": models})


def test_the_models_without_an_element_behave_as_the_rig_without_it():
    """On the jack truth's record, at the truth's parameters: the model without the jack is the rig
    model with the jack's gain held at 0, to the bit, and its WOB above the 0.5 Hz trend is gone
    (the trend, its input, alone); without the shaft coupling the rotor turns the bar's top rigidly,
    so the string is stiffer and the stick-slip cycle faster than with a 40 N m/rad coupling in series
    (2.84 -> 3.01 Hz); without the motor the top turns at the command, steadily."""
    rec = _truth_record(duration=8.0, truth=JACK_TRUTH)
    thr = rigsim.stick_threshold(rec)
    sim = RigSimulator(rec, thr, prior_spec({"families": MODELS, "statistics": list(WITH)}),
                       load_config(preset="thesis-rig")["law"], threads=1)
    with_all, no_jack, no_coupling, no_motor = (sim.one(m, JACK_TRUTH) for m in MODELS)
    held = sim.one("polynomial", {**JACK_TRUTH, "jack_gain_n_rad": 0.0})
    assert np.array_equal(no_jack, held)
    above, freq = WITH.index("wob_above_trend_std"), WITH.index("cycle_frequency_hz")
    assert with_all[above] > 30.0 and no_jack[above] < 3.0, (with_all[above], no_jack[above])
    # the bar's G J / L (about 3 N m/rad) in series with 40 N m/rad: sqrt(1 + 3 / 40) = 1.04 for a fixed top
    assert 1.02 * with_all[freq] < no_coupling[freq] < 1.15 * with_all[freq], (no_coupling[freq], with_all[freq])
    # without the motor an ideal drive turns the top at the command; the motor gives way under the
    # torque: its top turns slower on average (by about T / c_m) and swings with the cycle
    mean, sd = WITH.index("top_speed_mean"), WITH.index("top_speed_std")
    assert no_motor[mean] == pytest.approx(JACK_TRUTH["command_rad_s"], rel=1e-6) and no_motor[sd] < 1e-6
    assert with_all[mean] < JACK_TRUTH["command_rad_s"] - 2.0 and with_all[sd] > 0.5, (with_all[mean], with_all[sd])
    model = rigsim.RigModel.from_dict(rigsim.RigModel(**{**_rig_kwargs(), "coupling_stiffness_nm_rad": None}).to_dict())
    assert model.coupling_stiffness_nm_rad is None
    with pytest.raises(ValueError, match=r"coupling_stiffness_nm_rad = -1.0: a positive stiffness, or None"):
        rigsim.RigModel(**{**_rig_kwargs(), "coupling_stiffness_nm_rad": -1.0})


def _rig_kwargs() -> dict:
    """A rig-drive RigModel's arguments at the test truth (the calibration's held values)."""
    from drillpy.calibration.posterior import rig_model
    from drillpy.calibration.priors import FIXED
    m = rig_model(load_config(preset="thesis-rig")["law"], "polynomial", TRUTH, FIXED)
    return {k: getattr(m, k) for k in ("law", "damping_ratio", "drive", "motor_slope_nms_rad", "motor_inertia_kg_m2",
                                       "command_rad_s", "jack_gain_n_rad", "jack_relaxation_s", "platform_damping",
                                       "gj_factor", "bit_inertia_factor", "coupling_stiffness_nm_rad")}


def test_the_models_over_the_elements_go_into_the_posterior_and_its_prediction():
    rec = _truth_record(duration=6.0)
    post = calibrate_record(rec, config=_config(families=MODELS[:2]), population=8, max_simulations=48,
                            predictive_draws=4, seed=11, threads=1)
    s = post.summary()
    assert s["families"] == MODELS[:2]
    assert sum(s["model_probability"].values()) == pytest.approx(1.0)
    assert "no jack" in s["equations"]["polynomial without jack"]
    assert "jack_gain_n_rad" not in s["particles"]["polynomial without jack"]
    assert "jack_gain_n_rad" not in s["parameters"]["polynomial without jack"]
    pred = predict_posterior(s, rec, draws=4, seed=3, threads=1)["statistics"]
    assert all(np.isfinite(v["interval90"]).all() for v in pred.values())
