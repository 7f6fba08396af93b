"""The rig model's motor torque limit (RigModel.motor_max_torque_nm) and where sample 175's stall comes from:
the model's top speed dips lowest where the record's WOB trend peaks, around the record's one stall
(28.05 s, 1.43 s), and a lower limit deepens that dip (benchmarks/rig_stall.py; docs/records.md, section 4)."""
import dataclasses

import numpy as np
import pytest

import drillpy
from drillpy.records import rigsim
from drillpy.records.cleaning import clean
from drillpy.records.io import read_record

LAW = drillpy.load_config(preset="rgd-rig")["law"]
MODEL = rigsim.RigModel(LAW, 0.036, "rig", 0.25, 0.0186, command_rad_s=17.27, jack_gain_n_rad=181.8,
                        jack_relaxation_s=0.0987, platform_damping=0.75, gj_factor=1.0475, bit_inertia_factor=1.07,
                        coupling_stiffness_nm_rad=41.0)


def test_the_motor_torque_limit_is_the_models_and_its_files():
    assert MODEL.motor_max_torque_nm == rigsim.MOTOR_MAX_TORQUE_NM == 8.0   # the rating, thesis section 5.1
    m = dataclasses.replace(MODEL, motor_max_torque_nm=3.2)
    assert m.motor == (0.25, 0.0186, 3.2)
    assert m.config(17.27, 560.0)["top_drive"]["max_torque_nm"] == 3.2
    assert rigsim.RigModel.from_dict(m.to_dict()).motor_max_torque_nm == 3.2
    for bad in (0.0, -1.0, float("nan")):
        with pytest.raises(ValueError, match="motor_max_torque_nm"):
            dataclasses.replace(MODEL, motor_max_torque_nm=bad)


def test_the_models_top_speed_dips_lowest_at_the_records_stall_and_lower_with_a_lower_limit(testrig_record):
    rec = clean(read_record(testrig_record))[0]
    low = {}
    for lim in (8.0, 3.2):
        sim = rigsim.simulate_model(dataclasses.replace(MODEL, motor_max_torque_nm=lim), rec)
        after = sim.time_s >= 2.0                                  # the start from rest left out
        i = int(np.argmin(np.where(after, sim.top_speed, np.inf)))
        low[lim] = (float(sim.top_speed[i]), float(sim.time_s[i]))
        assert 27.5 <= low[lim][1] <= 30.0                         # the record stalls at 28.05-29.48 s
    assert low[3.2][0] < low[8.0][0] - 1.0                         # the capped motor gives way further


def test_the_static_torques_ageing_is_the_models_and_its_files():
    assert MODEL.static_ageing == 0.0 and "static_ageing" not in MODEL.engine_law   # none by default
    m = dataclasses.replace(MODEL, static_ageing=0.4, static_ageing_s=0.3)
    assert (m.engine_law["static_ageing"], m.engine_law["static_ageing_s"]) == (0.4, 0.3)
    assert m.config(17.27, 560.0)["law"]["static_ageing"] == 0.4
    back = rigsim.RigModel.from_dict(m.to_dict())
    assert (back.static_ageing, back.static_ageing_s) == (0.4, 0.3)
    assert {"motor_max_torque_nm", "static_ageing", "static_ageing_s"} <= set(m.parameters())
    with pytest.raises(ValueError, match="static_ageing = -0.1"):
        dataclasses.replace(MODEL, static_ageing=-0.1)
    with pytest.raises(ValueError, match="static_ageing_s = 0"):
        dataclasses.replace(MODEL, static_ageing_s=0.0)


def test_a_capped_motor_and_an_ageing_static_torque_stall_the_rig_where_the_record_stalls(testrig_record):
    # the motor capped at 3.2 N m: without ageing the bit always breaks free; with it (A 0.4, tau_a 0.3 s) the
    # bit held at the WOB trend's peak holds more than the motor gives, once, where the record stalls
    from drillpy.records import rig_comparison
    rec = clean(read_record(testrig_record))[0]
    thr = rigsim.stick_threshold(rec)
    stalls = {}
    for age in (0.0, 0.4):
        m = dataclasses.replace(MODEL, motor_max_torque_nm=3.2, static_ageing=age, static_ageing_s=0.3)
        stalls[age] = rig_comparison.compare(rec, rigsim.simulate_model(m, rec), thr).simulated["stalls"]
    assert stalls[0.0]["count"] == 0
    assert stalls[0.4]["count"] == 1
    assert 27.5 <= stalls[0.4]["starts_s"][0] <= 30.5 and 0.5 <= stalls[0.4]["durations_s"][0] <= 4.0
