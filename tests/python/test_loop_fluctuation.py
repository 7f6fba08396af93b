"""The long runs' torque fluctuation (``LoopOptions.long_run_fluctuation``, docs/loop.md, "The long run's
torque fluctuation"): the loop's long runs carry the bit-rock torque fluctuation of Eq. (4.1) that the
calibration part shows, measured as the thesis measures it (eta_exp of Eq. 4.2 and its Eq. 4.4 PSD).
Checked on sample 175 (the level the thesis's estimator gives) and on the independent whole-rig truth
(benchmarks/whole_rig.py, no drillpy code), where the loop then names the truth's motor with the truth's
parameters and a steel bar's damping."""
from __future__ import annotations

import json

import numpy as np
import pytest

import drillpy
from _testrig import sample175_cleaned
from drillpy import loop as L
from drillpy.records import rig_fluctuation, rigsim

rig = pytest.importorskip("whole_rig")


def test_the_fluctuation_of_sample_175_is_the_thesis_estimators():
    # eta_exp (Eq. 4.2) of 0-20 s: standard deviation 0.183 (docs/records.md, drillpy analyze's eta_exp);
    # the process built from it has that variance and the Eq. (4.4) shape's slope a < 0 above f0
    rec, _ = sample175_cleaned()
    part = rec.select(0.0, 20.0)
    f = rig_fluctuation.of_record(part, rigsim.stick_threshold(part))
    assert f["std"] == pytest.approx(0.183, abs=0.002)
    assert f["shape"]["a"] < 0 and 0.01 < f["shape"]["f0_hz"] < 2.0
    eta = rig_fluctuation.realization(f, 1e-3, 60.0, seed=0)
    assert np.std(eta) == pytest.approx(0.183, rel=0.1)
    # a record without a stick-slip cycle has no eta_exp to measure: none
    steady = rec.select(0.0, 20.0)
    steady.bit_speed = np.full(len(steady), 9.0)
    assert rig_fluctuation.of_record(steady, rigsim.stick_threshold(steady)) is None


def test_the_option_is_checked_and_a_model_file_carries_the_fluctuation():
    with pytest.raises(ValueError, match="long_run_fluctuation = 'measured'"):
        L.LoopOptions(long_run_fluctuation="measured").validate()
    cfg = drillpy.load_config(preset="thesis-rig")
    fl = {"psd": {"type": "table", "f_hz": [0.0, 10.0], "S": [0.003, 0.003]}, "std": 0.17, "band_hz": [0.0, 10.0]}
    m = L.LoopModel(cfg, dict(cfg["law"]), 9.0, 560.0, fluctuation=fl)
    back = L.LoopModel.from_dict(json.loads(json.dumps(m.to_dict())))
    assert back.fluctuation == fl
    from drillpy.loop.prediction import describe
    assert "torque fluctuation of Eq. (4.1) (std 0.17)" in describe(back)
    d = m.to_dict()
    d.pop("long_run_fluctuation")  # a model file written before the option: deterministic long runs
    assert L.LoopModel.from_dict(d).fluctuation is None


def test_with_the_records_fluctuation_the_loop_names_the_whole_rig_truths_motor(tmp_path):
    # the whole-rig truth: an open-loop motor c_m 0.22 N m s/rad behind a 0.013 kg m^2 rotor, ten lumped
    # segments of the bar with damping 0.02, an exponential Stribeck law with ageing, the jack, the platform
    # and quantized encoders (20 s, seed 5). With deterministic long runs the motor is refused (its long
    # run stops sticking: docs/loop.md); with the record's fluctuation in them it is the first effect named,
    # with the truth's droop and rotor, and the damping re-held on the cycle is a steel bar's
    path = tmp_path / "truth.mat"
    rig.write_mat(rig.simulate({"jack_steps": []}, duration=20.0, seed=5), str(path))
    res = L.run_loop(str(path), drillpy.load_config(preset="thesis-rig"),
                     L.LoopOptions(long_run_fluctuation="record"), log=lambda s: None)
    assert res.baseline.model.fluctuation is not None and 0.02 < res.baseline.model.fluctuation["std"] < 0.5
    added = [s.effect for s in res.steps if s.action == "add"]
    assert added[:1] == ["top_drive_dynamics"]
    p = res.final.model.effects["top_drive_dynamics"]
    assert 1.0 / p["droop_rad_s_per_nm"] == pytest.approx(0.22, rel=0.15)
    assert p["inertia_kg_m2"] == pytest.approx(0.013, rel=0.25)
    assert res.final.model.damping_ratios[0] <= 0.1
    assert res.final.E_test < 0.7 * res.baseline.E_test
    assert res.final.model.to_dict()["long_run_fluctuation"] == res.baseline.model.fluctuation
