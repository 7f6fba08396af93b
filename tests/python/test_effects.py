"""The catalogue of the loop: the six named effects, each with parameters, a model change, a
signature and a reading; which of them a declared configuration already has."""
from __future__ import annotations

import copy

from drillpy.config import load_config, normalize
from drillpy.effects import CATALOGUE, NAMES, declared_effects


def test_catalogue_has_the_six_named_effects_with_their_descriptions():
    assert NAMES == ("bit_hysteresis", "wob_coupling", "top_drive_dynamics", "sensor_lag", "torque_fluctuation",
                     "viscous_damping")
    for name in NAMES:
        e = CATALOGUE[name]
        assert e.name == name and e.level in ("law", "dynamic")
        assert e.parameters and e.change and e.signature and e.reading
    assert CATALOGUE["wob_coupling"].needs == ("wob",)
    assert CATALOGUE["top_drive_dynamics"].needs == ("top_speed",)


def test_declared_effects_are_read_off_the_configuration():
    rig = load_config(preset="thesis-rig")
    assert set(declared_effects(rig)) == {"bit_hysteresis"}  # Eq. (5.3) with beta1 = 0.086
    assert declared_effects(rig)["bit_hysteresis"]["beta1"] == rig["law"]["beta1"]
    c = copy.deepcopy(rig)
    c["law"]["beta1"] = 0.0
    c["top_drive"] = {"type": "motor", "slope_nms_rad": 0.5, "inertia_kg_m2": 0.02}
    c["sensors"] = {"lowpass_hz": 10.0}
    c["operation"]["bit_viscous_nms"] = 0.01
    d = declared_effects(normalize(c))
    assert set(d) == {"top_drive_dynamics", "sensor_lag", "viscous_damping"}
    assert d["top_drive_dynamics"]["droop_rad_s_per_nm"] == 2.0
    assert d["sensor_lag"]["lowpass_hz"] == 10.0
