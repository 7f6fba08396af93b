"""Rival explanations (:mod:`drillpy.loop.rivals`, issue 29): a candidate the chosen effect does not
beat by the guard's own test is a rival, tested jointly; one that adds nothing beside the chosen
effect makes the pair confusable, reported with both names."""
from __future__ import annotations

import pytest

from drillpy.loop import Evidence, LoopOptions
from drillpy.loop.data import prepare
from drillpy.loop.fitting import calibrate, fit_candidate
from drillpy.loop.model import evaluate
from drillpy.loop.rivals import confusable_note, distinct, rivals
from drillpy.loop.synthetic import declared_config, synthetic_record

MOTOR = "top_drive_dynamics"


@pytest.fixture(scope="module")
def motor_case():
    """A truth whose top drive gives way (the declared model's ideal drive does not): the baseline
    calibrated, and the motor candidate fitted from it."""
    opt = LoopOptions(rate_hz=250.0)
    data = prepare(synthetic_record((MOTOR,), seed=13, duration_s=16.0), declared_config(), opt)
    base, _ = calibrate(declared_config(), data, opt)
    motor, _ = fit_candidate(base, data, MOTOR, opt)
    return opt, data, evaluate(base, data, 1), evaluate(motor, data, 1)


def test_a_candidate_is_no_rival_of_itself_and_the_truth_beats_the_baseline(motor_case):
    opt, data, base, motor = motor_case
    same = distinct(motor, motor, data, opt)
    assert same["gain"] == 0.0 and not same["distinct"]      # identical predictions: no evidence either way
    better = distinct(motor, base, data, opt)
    assert better["distinct"] and better["gain"] > 0.3 and better["p_value"] < 1e-6


def test_an_equal_candidate_that_adds_nothing_beside_the_chosen_one_is_confusable(motor_case):
    """A second name with the very predictions of the motor (here the sensor_lag slot given the
    motor's evaluation) is not beaten by the guard's test; fitted on top of the motor model it adds
    nothing (the truth has no filter), so the pair is reported as confusable, both names in the note."""
    opt, data, base, motor = motor_case
    results = [(MOTOR, motor, Evidence(accepted=True)), ("sensor_lag", motor, Evidence(accepted=True)),
               ("string_friction", base, Evidence(accepted=True))]   # beaten by the motor: no rival
    lines = []
    rv = rivals(MOTOR, results, motor, data, opt, 1, log=lines.append)
    assert [r["effect"] for r in rv] == ["sensor_lag"]
    r = rv[0]
    assert r["verdict"] == "confusable" and not r["joint"]["present"]
    note = confusable_note(MOTOR, rv)
    assert note.startswith(f"confusable: {MOTOR} or sensor_lag") and "cannot tell them apart" in note
    assert any("rival sensor_lag" in s for s in lines)


def test_a_rival_present_beside_the_chosen_effect_is_no_confusion(motor_case):
    """The other way round: the chosen model is the baseline (no motor) and the motor has the
    baseline's own evaluation in the round; fitted on top, it is present (the truth has it)."""
    opt, data, base, _ = motor_case
    results = [("sensor_lag", base, Evidence(accepted=True)), (MOTOR, base, Evidence(accepted=True))]
    rv = rivals("sensor_lag", results, base, data, opt, 1, log=lambda s: None)
    assert len(rv) == 1 and rv[0]["verdict"] == "both" and rv[0]["joint"]["gain"] > 0.3
    assert confusable_note("sensor_lag", rv) is None
