"""``sensor_gain`` (issue 29, item 5): a torque load cell that reads 1.15 x the true torque plus
0.15 N m, on records of an outside simulator (``benchmarks/independent_rig.py``, no drillpy inside;
the load cell applied to its recorded torque outside it, ``loop_independent.torque_channel``). The
torque's scale is pinned by the dynamics: the disk's known inertia relates it to the bit encoder's
acceleration (docs/loop.md, ``sensor_gain``)."""
from __future__ import annotations

import numpy as np
import pytest

import independent_rig as rig  # benchmarks/ (conftest.py): the outside simulator
from loop_independent import GAIN, torque_channel

import drillpy
from drillpy.loop import LoopOptions, run_loop
from drillpy.loop.data import prepare
from drillpy.loop.effects import CATALOGUE, stripped
from drillpy.loop.effects.sensor_gain import MARGIN, encoder_torque
from drillpy.loop.model import LoopModel

SEED = 19          # loop_independent.py's sensor_gain case
DURATION_S = 20.0  # a short record: 10 calibration and 10 validation seconds
#: the loop's candidates: the gain and the stiffness, the catalogue's other reading of a torque that
#: does not balance the encoders' twist (the others are tested on the same simulator elsewhere)
OPTIONS = dict(rate_hz=250.0, effects=("sensor_gain", "string_stiffness"))


def _write(sim: dict, path, note: str):
    rig.write_csv(sim, str(path), [f"independent_rig.py seed {SEED}, {DURATION_S:g} s: {note}"])
    return path


@pytest.fixture(scope="module")
def records(tmp_path_factory):
    """The same simulation recorded through a correct load cell and through the miscalibrated one."""
    folder = tmp_path_factory.mktemp("gain")
    sim = rig.simulate({}, seed=SEED, duration_s=DURATION_S)
    clean = _write(sim, folder / "clean.csv", "clean")
    gain = _write(torque_channel(dict(sim), **GAIN), folder / "gain.csv", f"torque read as {GAIN}")
    return clean, gain


@pytest.fixture(scope="module")
def soft(tmp_path_factory):
    """The same seed with a bar 15 % softer (GJ x 0.85) and a correct load cell."""
    sim = rig.simulate(rig.effect_params(["string_stiffness"]), seed=SEED, duration_s=DURATION_S)
    return _write(sim, tmp_path_factory.mktemp("soft") / "soft.csv", "GJ x 0.85")


def _loop(path):
    lines: list = []
    res = run_loop(path, drillpy.load_config(preset="thesis-rig"), LoopOptions(**OPTIONS), log=lines.append)
    return res, "\n".join(lines)


def _data_model(path):
    cfg = drillpy.load_config(preset="thesis-rig")
    data = prepare(str(path), cfg, LoopOptions(**OPTIONS))
    base = stripped(cfg)
    return data, LoopModel(base, dict(base["law"]), float(np.mean(data.ch["top"])), 557.1)


def test_the_encoders_measure_the_torque_scale_and_tell_it_from_a_stiffness_mismatch(records, soft):
    """Eq. (SG.1) on the calibration part: s from the inertial term, the stiffness ratio from the
    twist term. A gain scales both; a 15 % softer bar scales the twist term only, and is not
    proposed as a gain."""
    clean, gain = (encoder_torque(*_data_model(p)[::-1]) for p in records)
    assert abs(clean["scale"] - 1.0) < MARGIN and abs(clean["gj_ratio"] - 1.0) < 0.03
    assert abs(gain["scale"] - GAIN["torque_scale"]) < 0.02
    assert gain["scale_ci95"][0] > 1.0 + MARGIN  # significant
    assert abs(gain["gj_ratio"] - 1.0) < 0.03      # the stiffness is the declared one
    data, model = _data_model(soft)
    m = encoder_torque(model, data)
    assert abs(m["scale"] - 1.0) < MARGIN and abs(m["gj_ratio"] - 0.85) < 0.03
    assert not CATALOGUE["sensor_gain"].direct(model, data)["significant"]


def test_the_loop_names_the_gain_and_recovers_the_scale(records):
    res, log = _loop(records[1])
    added = [s.effect for s in res.steps if s.action == "add"]
    assert added and added[0] == "sensor_gain", log
    step = next(s for s in res.steps if s.effect == "sensor_gain")
    assert step.error_after <= 0.95 * step.error_before  # the step gate
    p = res.final.model.effects["sensor_gain"]
    assert abs(p["torque_scale"] - GAIN["torque_scale"]) < 0.05
    lo, hi = step.evidence.parameters["torque_scale"]["ci95"]
    assert lo <= p["torque_scale"] <= hi and hi - lo < 0.05
    assert abs(p["torque_offset_nm"]) <= 0.5  # reported, not identified by the dynamics


def test_a_clean_record_does_not_name_the_gain(records):
    res, log = _loop(records[0])
    assert "sensor_gain" not in res.final.model.effects, log
    assert all(s.effect != "sensor_gain" for s in res.steps if s.action == "add")


def test_a_softer_bar_is_named_string_stiffness_not_a_gain(soft):
    """The confounded pair: a torque that does not balance the encoders' twist. The inertial term
    says the load cell is right, the twist term that the bar is soft."""
    res, log = _loop(soft)
    added = [s.effect for s in res.steps if s.action == "add"]
    assert added == ["string_stiffness"], log
    assert abs(res.final.model.effects["string_stiffness"]["gj_factor"] - 0.85) < 0.02
