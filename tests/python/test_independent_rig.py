"""The outside simulator of the loop's independent check (benchmarks/independent_rig.py): it shares
no code with drillpy, its rig has the thesis's first mode, its clean record stick-slips like the test
rig, and its effects leave the marks they should (an acquisition filter's delay, a break-away
torque's longer sticks)."""
from __future__ import annotations

import ast
import math

import numpy as np
import pytest

from conftest import REPO

rig = pytest.importorskip("independent_rig")

SHORT = {"duration_s": 8.0, "settle_s": 3.0}


def test_it_imports_no_drillpy_code():
    tree = ast.parse((REPO / "benchmarks" / "independent_rig.py").read_text())
    names = {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    names |= {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.module}
    assert not any(x.split(".")[0] == "drillpy" for x in names)


def test_clean_rig_has_the_thesis_mode_and_stick_slips():
    res = rig.simulate({}, seed=1, **SHORT)
    assert res["modes_hz"][0] == pytest.approx(math.sqrt(3.08 / 9.33e-3) / (2 * math.pi), rel=0.01)  # 2.89 Hz
    m = rig.metrics(res["clean"]["bit_speed"], res["clean"]["top_speed"])
    assert 0.9 < m["ss"] < 1.5 and 0.05 < m["stick_fraction"] < 0.3 and 2.0 < m["spectral_peak_hz"] < 3.3


def test_effects_leave_their_marks():
    clean = rig.simulate({}, seed=2, **SHORT)
    lag = rig.simulate(rig.effect_params(["sensor_lag"]), seed=2, **SHORT)
    v0, v1 = clean["clean"]["bit_speed"], lag["bit_speed"]
    x0, x1 = v0 - v0.mean(), v1 - v1.mean()
    shifts = np.arange(0, 40)
    lag_s = shifts[np.argmax([x0[: x0.size - k] @ x1[k:] for k in shifts])] / rig.FS_HZ
    assert lag_s == pytest.approx(math.sqrt(2) / (2 * math.pi * 10.0), abs=0.004)  # 22.5 ms at 10 Hz
    stuck = rig.simulate(rig.effect_params(["static_friction"]), seed=2, **SHORT)
    m0 = rig.metrics(v0, clean["clean"]["top_speed"])
    m1 = rig.metrics(stuck["clean"]["bit_speed"], stuck["clean"]["top_speed"])
    assert m1["stick_fraction"] > 1.5 * m0["stick_fraction"]
