"""The loop's step rule (drillpy.loop.time_step, issue 33): the steps it tries divide the analysis
interval, the difference it measures bounds the change of E on either part (the triangle
inequality of E's RMS norm), and the loop predicts at a coarser step only where the declared
model's and the calibrated baseline's predictions stay within the tolerance."""
from __future__ import annotations

import math

import pytest

from drillpy import loop as L
from drillpy.loop import time_step as TS
from drillpy.loop.model import evaluate
from drillpy.loop.synthetic import declared_config, synthetic_record

RATE_HZ = 250.0


def test_the_steps_tried_divide_the_analysis_interval_and_are_at_least_twice_the_declared():
    assert TS.candidate_steps(1e-3, 1e-4) == pytest.approx([2e-4, 2.5e-4, 5e-4, 1e-3])
    steps = TS.candidate_steps(4e-3, 1e-4)
    assert steps == sorted(steps) and steps[-1] == pytest.approx(4e-3)
    for h in steps:
        assert 4e-3 / h == pytest.approx(round(4e-3 / h)) and h >= 2e-4 * (1 - 1e-12)
    assert TS.candidate_steps(1e-3, 6e-4) == []  # no divisor of 1 ms is twice 0.6 ms


@pytest.fixture(scope="module")
def baseline():
    rec = synthetic_record({"top_drive_dynamics": {}}, duration_s=12.0, seed=7, fs_hz=RATE_HZ)
    res = L.run_loop(rec, declared_config(), L.LoopOptions(rate_hz=RATE_HZ, dt_s=1e-4, max_steps=0, long_run=False,
                                                           discovery=False), log=lambda *a: None)
    return res


def test_the_difference_is_zero_at_the_own_step_and_bounds_the_change_of_e_on_both_parts(baseline):
    m, data = baseline.baseline.model, baseline.data
    assert TS.step_difference(m, data, m.cfg["simulation"]["dt_s"]) == 0.0
    e0 = evaluate(m, data)
    for h in (2e-4, 5e-4, 1e-3):
        d = TS.step_difference(m, data, h)
        e = evaluate(TS.at_step(m, h), data)
        assert 0.0 < d < math.inf
        assert abs(e.E_train - e0.E_train) <= d * (1 + 1e-9)
        assert abs(e.E_test - e0.E_test) <= d * (1 + 1e-9)


def test_the_loop_takes_the_coarsest_step_within_the_tolerance_and_confirms_it(baseline):
    """On this record the declared model's differences are about 0.013, 0.026, 0.070 and 0.10 at 2,
    2.5, 4 and 5 times the declared step: a tolerance of 0.09 takes the fourth step's predecessor."""
    rec = synthetic_record({"top_drive_dynamics": {}}, duration_s=12.0, seed=7, fs_hz=RATE_HZ)
    cfg, tol = declared_config(), 0.09
    res = L.run_loop(rec, cfg, L.LoopOptions(rate_hz=RATE_HZ, step_tolerance=tol, max_steps=0, long_run=False,
                                             discovery=False), log=lambda *a: None)
    ts = res.time_step
    assert ts["declared_s"] == pytest.approx(1e-4)
    diffs = [x["difference"] for x in ts["tried"]]
    assert diffs == sorted(diffs)  # a first-order scheme: the coarser, the further
    assert diffs[-1] > tol >= diffs[-2]  # tried up to the first beyond the tolerance
    assert ts["used_s"] == pytest.approx(ts["tried"][-2]["dt_s"]) and ts["used_s"] >= 2e-4
    assert ts["baseline_difference"] <= tol and ts["final_difference"] <= tol
    assert res.baseline.model.cfg["simulation"]["dt_s"] == pytest.approx(ts["used_s"])
    assert res.loop_json()["time_step"] == ts
    off = L.run_loop(rec, cfg, L.LoopOptions(rate_hz=RATE_HZ, step_tolerance=0.0, max_steps=0, long_run=False,
                                             discovery=False), log=lambda *a: None)
    assert off.time_step == {} and off.baseline.model.cfg["simulation"]["dt_s"] == pytest.approx(1e-4)


def test_a_baseline_beyond_the_tolerance_sends_the_loop_back_to_the_declared_step(baseline):
    from drillpy.loop.run import _step_holds
    m = TS.at_step(baseline.baseline.model, 5e-4)
    d = TS.step_difference(baseline.baseline.model, baseline.data, 5e-4)
    for tol, holds in ((2 * d, True), (0.5 * d, False)):
        step = {"declared_s": 1e-4, "used_s": 5e-4}
        ok = _step_holds(step, m, baseline.data, L.LoopOptions(step_tolerance=tol), lambda *a: None)
        assert ok is holds and step["baseline_difference"] == pytest.approx(d, rel=1e-12)
        assert step["used_s"] == (5e-4 if holds else 1e-4)


def test_a_bad_tolerance_is_named():
    with pytest.raises(ValueError, match="step_tolerance"):
        L.LoopOptions(step_tolerance=-0.1).validate()
