"""An effect must still be there once refitted (issue 33, the loop's misattributions): a candidate
whose gain over the null candidate came from the other parameters' new optimum, not from the
effect, is refused when its refit puts the effect back at its no-effect value.

The record: the third outside simulator (``benchmarks/third_rig.py``, no drillpy code) with a
viscous torque on the bit outside its load cell (18 % of the torque at peak speed) and an exact
load cell. ``sensor_gain`` fitted beside the null candidate read s = 1.046 and lowered the
validation error by 5.6 %; refitted from a fresh law fit, s went to 1.0007, and the loop named a
load-cell error the record does not have (docs/loop.md, "The third simulator")."""
from __future__ import annotations

import pytest

import third_rig  # benchmarks/ (conftest.py): the third outside simulator, no drillpy inside
from conftest import outside_loop
from drillpy.loop.effects.sensor_gain import MARGIN


@pytest.fixture(scope="module")
def viscous_bit(tmp_path_factory):
    return outside_loop(tmp_path_factory.mktemp("refit"), lambda p: third_rig.make_record("bit_viscous", 5, p),
                        ("sensor_gain",))


def test_an_effect_refitted_to_its_no_effect_value_is_not_named(viscous_bit):
    js, ev = viscous_bit
    # the load cell is exact: no load-cell error in the final model, and none added on the way
    assert "sensor_gain" not in js["final_effects"]
    assert all(s["effect"] != "sensor_gain" for s in js["steps"] if s["action"] == "add")
    cands = [c for rnd in ev["rounds"] for c in rnd if c["effect"] == "sensor_gain"]
    assert cands, "sensor_gain was a candidate"
    for c in cands:
        refits = [r for r in c.get("reasons", []) if r.startswith("refitted: torque_scale")]
        if refits:  # passed the guard beside the null candidate, then refitted back to s = 1
            assert "reaches the no-effect value 1" in refits[0]
            assert c["parameters"]["torque_scale"]["value"] > 1.0 + MARGIN  # what the fit beside the null read
