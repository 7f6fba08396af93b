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
