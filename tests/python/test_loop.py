"""drillpy loop on records its declared model did not generate: the fast validation cases (truth
away from the declared model, effects named, clean records untouched, an effect outside the
catalogue never misnamed), a declared effect the record lacks calibrated away, the trivial
predictors, the outputs (interface keys, the metric recomputed, model.json applied to another
record), the recursive estimate of the fluctuation, the guard, sample 175, and bad input."""
from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest

from conftest import run_cli
from _testrig import sample175_path
from loop_validation import CASES, DURATION_S, LOOP_DT_S, RATE_HZ, run_case

from drillpy import loop as L
from drillpy.model.config import load_config
from drillpy.loop.effects import torque_fluctuation as TF
from drillpy.loop.model import law_torque, state_channels
from drillpy.loop.run import analysis_config
from drillpy.records.io import Record, write_csv
from drillpy.loop.synthetic import declared_config, synthetic_record

LOOP_KEYS = {"metric", "decision", "warnings", "baseline_error", "steps", "final_error", "parameters", "declared", "removed", "final_effects",
             "confusable", "unexplained_fraction", "discovered_terms", "adequacy", "baseline_long_run", "provenance",
             "wob_input", "channel_timing", "time_step"}
STEP_KEYS = {"action", "effect", "error_before", "error_after", "evidence", "long_run"}


@pytest.mark.parametrize("case", [c for c in CASES if c.fast], ids=lambda c: f"{c.kind}-{c.label}-seed{c.seed}")
def test_validation_case_passes(case):
    """The fast subset of benchmarks/loop_validation.py (the table of docs/loop.md): truths away from
    the declared model; clean: nothing added; single: named first with E after <= 0.6 E before; two:
    both found; outside the catalogue: nothing misnamed. "E before" is the calibrated declared model's
    (the baseline), whatever the path: case 18 recalibrates the GJ first or not as the rounding goes
    (a 1 % better calibration error decides it). On OpenBLAS's Sandybridge kernel with one thread:
    E 0.0963, recalibrated 0.0897, static_friction 0.0542 (0.604 x the step's own "before", 0.563 x
    the baseline); SkylakeX with two: 0.1040, 0.0996, 0.0522 (0.524 x, 0.502 x)."""
    r = run_case(case)
    assert r["ok"], {k: r[k] for k in ("found", "removed", "baseline", "first_after", "final", "params")}
    assert r["truth"]["modes"] == 3 and r["truth"]["damping_ratio"] != 0.05  # not the declared model


def test_a_declared_effect_the_record_lacks_is_calibrated_away_and_never_costs_a_step():
    """A declared hysteretic law (beta1 = 0.15) on a record of a reversible truth: the calibration
    takes beta1 to about zero (0.0056), nothing is added, and the backward step removes the effect
    only if its removal does not raise E (no step raises E, issue 29; on this record the near-zero
    hysteresis still absorbs 2.6 % of the truth's nuisance, so it is kept, not defended)."""
    rec = synthetic_record((), duration_s=DURATION_S, seed=5, fs_hz=RATE_HZ)
    cfg = declared_config()
    cfg["law"]["beta1"], cfg["law"]["beta2"] = 0.15, 0.005
    res = L.run_loop(rec, cfg, L.LoopOptions(rate_hz=RATE_HZ, dt_s=LOOP_DT_S), log=lambda *a: None)
    assert res.declared == ["bit_hysteresis"]
    assert res.baseline.model.effects["bit_hysteresis"]["beta1"] < 0.03  # the record lacks it: calibrated away
    assert not [s for s in res.steps if s.action == "add"]
    for s in res.steps:
        assert s.action == "remove" and s.effect == "bit_hysteresis" and s.error_after <= s.error_before
    if "bit_hysteresis" in res.final.model.effects:
        assert res.final.model.effects["bit_hysteresis"]["beta1"] < 0.03


def test_trivial_predictors_are_what_they_say():
    """The mean predictor's E and the hold-last predictor's E recomputed by hand."""
    rec = synthetic_record((), duration_s=8.0, seed=2, fs_hz=RATE_HZ)
    cfg = analysis_config(declared_config(), 1.0 / RATE_HZ, LOOP_DT_S)
    data = L.prepare(rec, cfg, L.LoopOptions(rate_hz=RATE_HZ))
    triv = L.trivial_predictors(data)
    te = data.is_test
    hs = data.horizon_samples[te]
    tr = data.valid & (data.t < data.t_split)
    sv, sT, top = data.sigma_v, data.sigma_T, data.top_meas
    assert data.top_ok.all()  # a synthetic top-speed channel has no artifact
    e_mean = math.sqrt((np.mean((data.v_meas[hs] - data.v_meas[tr].mean()) ** 2) / sv ** 2
                        + np.mean((data.T_meas[hs] - data.T_meas[tr].mean()) ** 2) / sT ** 2
                        + np.mean((top[hs] - top[tr].mean()) ** 2) / sv ** 2) / 3)
    assert triv["mean"] == pytest.approx(e_mean, rel=1e-9)
    s0 = data.starts[te]
    e_hold = math.sqrt((np.mean((data.v_meas[hs] - data.ch["v"][s0][:, None]) ** 2) / sv ** 2
                        + np.mean((data.T_meas[hs] - data.ch["T"][s0][:, None]) ** 2) / sT ** 2
                        + np.mean((top[hs] - data.ch["top"][s0][:, None]) ** 2) / sv ** 2) / 3)
    assert triv["hold_last"] == pytest.approx(e_hold, rel=1e-9)
    # two channels at their own spread and a steady top: sqrt(2/3), give or take the parts' difference
    assert 0.6 < triv["mean"] < 1.2


@pytest.mark.parametrize("scheme,dt", [("modified_euler", 1e-4), ("exact_modal", 1e-3)])
def test_noise_free_declared_model_predicts_its_own_record(scheme, dt):
    """Restarted from the states read off a noise-free record of the declared model itself, the
    calibrated model predicts the record: E below 0.05 (the channel spreads are 1); on the exact
    modal scheme at a step ten times the record's generator's too (issue 33), the scheme named in
    the engine configuration the loop used."""
    rec = synthetic_record((), duration_s=8.0, seed=3, fs_hz=RATE_HZ, noise=0.0, nuisance=False)
    res = L.run_loop(rec, declared_config(), L.LoopOptions(rate_hz=RATE_HZ, dt_s=dt, scheme=scheme, max_steps=0,
                                                           long_run=False, discovery=False), log=lambda *a: None)
    assert res.baseline.model.cfg["simulation"]["scheme"] == scheme
    assert res.baseline.E_test < 0.05
    assert res.baseline.channel_rmse["bit_speed_rad_s"] < 0.05 * res.data.sigma_v


@pytest.fixture(scope="module")
def two_effect_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("loop")
    rec = synthetic_record({"top_drive_dynamics": {}, "wob_coupling": {}}, duration_s=2 * DURATION_S, seed=4,
                           fs_hz=RATE_HZ)
    path = write_csv(rec.select(0.0, DURATION_S), out / "record.csv")
    write_csv(rec.select(DURATION_S, 2 * DURATION_S), out / "later.csv")  # for drillpy predict
    cfg = out / "declared.json"
    cfg.write_text(json.dumps(declared_config()))
    p = run_cli("loop", str(path), "--config", str(cfg), "--out", str(out / "res"), "--rate", str(RATE_HZ),
                "--dt", str(LOOP_DT_S))
    assert p.returncode == 0, p.stderr
    return out / "res"


def _predictions(path):
    with open(path) as fh:
        rows = list(csv.reader(line for line in fh if not line.startswith("#")))  # the provenance line
    head = rows[0]
    data = np.array([[float(x) if x else np.nan for x in r] for r in rows[1:]])
    return head, data


def test_outputs_have_the_interface_keys_and_the_metric_is_what_it_says(two_effect_run):
    out = two_effect_run
    js = json.loads((out / "loop.json").read_text())
    assert set(js) == LOOP_KEYS
    added = [s["effect"] for s in js["steps"] if s["action"] == "add"]
    assert set(added) >= {"top_drive_dynamics", "wob_coupling"}
    for s in js["steps"]:
        assert set(s) == STEP_KEYS
        # every step lowers E on the data that decide it, the validation part (issue 29): an addition by the
        # guard's margin, a recalibration (proposed by the calibration part) by any amount
        if s["action"] == "recalibrate":  # proposed by the calibration part (string_stiffness inside the GJ tolerance)
            e = s["evidence"]
            assert e["calibration_error_after"] < 0.99 * e["calibration_error_before"]
            assert abs(e["gj_factor"] - 1.0) <= 0.03 and s["effect"] == "string_stiffness"
            assert s["error_after"] < s["error_before"]
        elif s["action"] == "remove":  # a removal never raises it
            assert s["error_after"] <= s["error_before"]
        else:
            assert s["error_after"] <= 0.95 * s["error_before"]
        lr = s["long_run"]
        assert set(lr) >= {"measured", "before", "after"} and lr["after"]["stick_fraction"] is not None
    assert "validation part" in js["decision"]["decided_on"] and "validation part" in js["decision"]["final_error_on"]
    assert "calibration part" in js["decision"]["fitted_on"]
    assert js["steps"][0]["error_before"] == js["baseline_error"]
    assert js["steps"][-1]["error_after"] == js["final_error"]
    assert set(js["final_effects"]) == set(js["parameters"]["effects"]) >= {"top_drive_dynamics", "wob_coupling"}
    assert js["declared"] == [] and js["removed"] == []
    assert 0.0 <= js["unexplained_fraction"] <= 1.0
    assert js["adequacy"]["adequate"] and js["adequacy"]["baseline_error"] < js["adequacy"]["hold_last_predictor_error"]
    head, d = _predictions(out / "predictions.csv")
    assert head == ["time_s", "bit_speed_rad_s", "torque_on_bit_Nm", "top_speed_rad_s", "top_speed_measured",
                    "baseline_bit_speed_rad_s", "baseline_torque_on_bit_Nm", "baseline_top_speed_rad_s",
                    "final_bit_speed_rad_s", "final_torque_on_bit_Nm", "final_top_speed_rad_s", "validation", "horizon"]
    ev = json.loads((out / "evidence.json").read_text())
    sv, sT = ev["record"]["sd_bit_speed_rad_s"], ev["record"]["sd_torque_nm"]
    # E recomputed from predictions.csv: the validation rows, three channels normalized (the top by sd_v)
    val = d[:, 11] == 1
    for c0, key in ((5, "baseline_error"), (8, "final_error")):
        top = np.where(d[val, 4] == 1, d[val, c0 + 2] - d[val, 3], 0.0)
        e2 = (np.mean((d[val, c0] - d[val, 1]) ** 2) / sv ** 2 + np.mean((d[val, c0 + 1] - d[val, 2]) ** 2) / sT ** 2
              + np.mean(top ** 2) / sv ** 2) / 3
        assert math.sqrt(e2) == pytest.approx(js[key], rel=1e-9)
    # calibration rows all precede the validation rows
    assert np.max(d[d[:, 11] == 0, 0]) < np.min(d[val, 0])
    assert "validation part" in js["metric"] and "restarted every 0.25 s" in js["metric"]
    report = (out / "report.md").read_text()
    for section in ("## Metrics", "## Result", "### Physical reading", "## Evidence per round", "## Figures"):
        assert section in report
    for fig in ("residual_signature.png", "overlay.png", "loops.png", "errors.png"):
        assert (out / fig).stat().st_size > 10_000
    model = json.loads((out / "model.json").read_text())
    assert model["format"] == "drillpy.loop_model" and model["config"]["top_drive"]["type"] == "motor"
    assert json.loads((out / "config.json").read_text())["top_drive"]["type"] == "motor"


def test_a_loop_model_predicts_another_record_without_refitting(two_effect_run):
    """model.json of the loop applied by drillpy predict to the next 12 s of the same run (never seen
    by the loop): the short-horizon error stays near the loop's own final error, and the long run
    reproduces the cycle frequency."""
    path = two_effect_run.parent / "later.csv"
    p = run_cli("predict", str(two_effect_run / "model.json"), str(path), "--json")
    assert p.returncode == 0, p.stderr
    s = json.loads(p.stdout)
    js = json.loads((two_effect_run / "loop.json").read_text())
    assert s["short_horizon_error"] < 2.0 * js["final_error"] + 0.05
    lr = s["long_run"]
    assert abs(lr["cycle_frequency_hz"]["relative_error"]) < 0.15


def test_eta_estimate_recovers_a_line_and_the_forecast_starts_from_it():
    """The recursive weighted least squares gives the level and slope of a straight eta exactly,
    and the forecast starts at the level with the slope (d/ds of the free response at 0)."""
    rec = synthetic_record((), duration_s=4.0, seed=1, fs_hz=RATE_HZ, noise=0.0)
    cfg = analysis_config(declared_config(), 1.0 / RATE_HZ)
    data = L.prepare(rec, cfg, L.LoopOptions(rate_hz=RATE_HZ))
    p = {"tau_s": 0.7, "memory_s": 0.2}
    m = L.LoopModel(cfg, dict(cfg["law"]), cfg["operation"]["top_speed_rad_s"], cfg["operation"]["wob_n"],
                    {"torque_fluctuation": p})
    chs = state_channels(m, data)
    eta = 0.1 + 0.05 * data.t  # a torque 10 % above the law, rising by 5 % per second
    chs["T"] = law_torque(m, chs) * (1.0 + eta)
    level, slope = TF.estimate(p, m, data, chs)
    slip = np.flatnonzero(data.valid & (chs["v"] > data.stick_threshold))
    k = slip[slip > 50][::7]
    assert np.allclose(level[k], eta[k], atol=1e-9)
    assert np.allclose(slope[k], 0.05, atol=1e-7)
    lead = np.array([0.0, 1e-6])
    f = TF.forecast(p, level[k], slope[k], lead)
    assert np.allclose(f[:, 0], level[k])
    assert np.allclose((f[:, 1] - f[:, 0]) / 1e-6, slope[k], atol=1e-5)


def test_guard_refuses_a_candidate_that_changes_nothing():
    rec = synthetic_record((), duration_s=8.0, seed=2, fs_hz=RATE_HZ)
    opt = L.LoopOptions(rate_hz=RATE_HZ, dt_s=LOOP_DT_S)
    cfg = analysis_config(declared_config(), 1.0 / RATE_HZ, LOOP_DT_S)
    data = L.prepare(rec, cfg, opt)
    base = L.evaluate(L.calibrate(cfg, data, opt)[0], data)
    e = L.evidence(base, base, data, 6, opt)
    assert e.relative_gain == 0.0 and e.explained_fraction == 0.0
    assert not e.accepted and len(e.reasons) == 3
    assert e.level == pytest.approx(opt.alpha / 6)


def test_the_step_gate_asks_every_step_to_lower_the_validation_error():
    """The gate every added or recalibrated step passes on the validation part (issue 29): an addition
    lowers E by min_gain (5 %), a recalibration (margin 0) by any amount; a step that raises E, or
    leaves it equal, or cannot be scored, is refused with the numbers in the reason."""
    from drillpy.loop.run import step_gate
    assert step_gate(0.100, 0.094, 0.05) is None
    assert step_gate(0.100, 0.0564 / 0.0556 * 0.100, 0.0) is not None  # the recalibration of docs/loop.md
    assert "0.1380 -> 0.1410" in step_gate(0.138, 0.141, 0.05)  # validation case 51's direct static friction
    assert step_gate(0.100, 0.096, 0.05) is not None  # lower, but by less than the margin
    assert step_gate(0.100, 0.0999, 0.0) is None and step_gate(0.100, 0.100, 0.0) is not None
    assert step_gate(0.100, float("nan"), 0.0) is not None


def _lr(ss, stick, measured=(1.216, 0.114)):
    meas, mod = {"ss": measured[0], "stick_fraction": measured[1]}, {"ss": ss, "stick_fraction": stick}
    return {"measured": meas, "model": mod, "relative_error": {k: mod[k] / meas[k] - 1.0 if meas[k] else None for k in mod},
            "stick_slips": {"measured": measured[1] >= 0.01, "model": stick >= 0.01}}


def test_a_final_model_off_the_record_cycle_is_said_to_be_unexplained():
    """The third simulator's out-of-catalogue compliance (benchmarks/third_rig.py, case 1): the final
    model sticks 0.07 of the time against the record's 0.25; the loop's notes must say the catalogue
    does not explain the record. Sample 175's final model (SS 1.033, stick 0.103 against 1.213, 0.082)
    meets the cycle within the bounds; a record that does not stick-slip constrains nothing."""
    from drillpy.loop.longrun import missed_cycle
    note = missed_cycle(_lr(1.10, 0.07, measured=(1.20, 0.25)))
    assert "stick fraction 0.070 against the record's 0.250" in note and "does not explain" in note
    assert "SS 0.800" in missed_cycle(_lr(0.80, 0.2, measured=(1.20, 0.25)))
    assert missed_cycle(_lr(1.033, 0.103, measured=(1.213, 0.082))) is None
    assert missed_cycle(_lr(0.2, 0.0, (0.2, 0.0))) is None
    assert missed_cycle({"error": "diverged"}) is None


def test_long_run_check_rejects_a_step_that_breaks_the_measured_cycle():
    """A model that stops sticking while the record sticks, or cannot be simulated, is rejected; so is
    a step whose stick phases vanish is named, taking the stick fraction below a third of the record's
    from above it (like sample 175's motor on the scalar path: 0.111 -> 0.016 against 0.114); a step that keeps the
    stick passes, as does one from a model already below that third; a record without stick-slip
    constrains nothing. The long-run error sums the relative SS and stick-fraction errors."""
    from drillpy.loop.longrun import cycle_damage, cycle_miss, stick_collapse
    assert cycle_miss(_lr(1.187, 0.133)) == pytest.approx(0.0236 + 0.1667, abs=1e-3)
    assert "no longer stick-slips" in cycle_damage(_lr(1.1, 0.1), _lr(1.1, 0.0))
    assert "cannot be simulated" in cycle_damage(_lr(1.1, 0.1), {"error": "diverged"})
    assert "stick phases vanish" in stick_collapse(_lr(1.162, 0.112), _lr(1.059, 0.017))
    assert "stick phases vanish" in stick_collapse(_lr(1.187, 0.133), _lr(1.088, 0.0255))
    assert stick_collapse(_lr(1.162, 0.112), _lr(1.1, 0.04)) is None  # above 0.114 / 3
    assert stick_collapse(_lr(1.1, 0.03), _lr(1.1, 0.02)) is None  # already below it before the step
    assert stick_collapse(_lr(0.2, 0.0, (0.2, 0.0)), _lr(0.2, 0.0, (0.2, 0.0))) is None  # the record does not stick
    assert cycle_damage(_lr(1.129, 0.0787), _lr(1.187, 0.133)) is None
    assert cycle_damage(_lr(1.1, 0.0), _lr(1.1, 0.0)) is None  # the model before did not stick either
    assert cycle_damage(_lr(0.2, 0.0, (0.2, 0.0)), _lr(1.0, 0.5, (0.2, 0.0))) is None


def test_sample175_wob_is_a_response_and_nothing_fed_the_cycle_is_credited(tmp_path):
    """The loop on the measured record (first 40 s at 250 Hz; calibration 0-20 s, decisions on 20-40 s):
    the recorded WOB follows the bit's angle deficit, so the law takes its trend and the WOB coupling
    that the recorded WOB's cycle made look strong is not added; the baseline's damping is held where
    the declared model stick-slips and flagged as above a steel bar's; the break-away torque of the
    stick phases is measured with its interval (docs/loop.md; at 1000 Hz the jack is added, at 250 Hz
    it is not credited, p 0.1). The record as recorded (``--channel-timing none``; the default reads it at its
    channels' timing: the next test)."""
    out = tmp_path / "s175"
    p = run_cli("loop", str(sample175_path()), "--preset", "thesis-rig", "--out", str(out), "--rate", "250",
                "--channel-timing", "none")
    assert p.returncode == 0, p.stderr
    js = json.loads((out / "loop.json").read_text())
    assert set(js) == LOOP_KEYS
    w = js["wob_input"]
    assert w["input"] == "trend" and w["response"] and w["correlation"] > 0.7
    assert js["declared"] == ["bit_hysteresis"] and "wob_coupling" not in js["final_effects"]
    assert js["adequacy"]["adequate"]
    assert all(s["error_after"] <= s["error_before"] for s in js["steps"])  # no step raises E (issue 29)
    assert js["baseline_long_run"]["model"]["stick_fraction"] > 0.03  # damping held on the cycle
    ev = json.loads((out / "evidence.json").read_text())
    # the break-away torques of the stick phases, measured directly (whatever the rounds decide after)
    measured = [c["parameters"]["static_torque_nm"] for r in ev["rounds"] for c in r
                if c["effect"] == "static_friction" and c["parameters"]["static_torque_nm"].get("source") == "stick phases"]
    assert measured and all(2.5 < t["ci95"][0] < t["value"] < t["ci95"][1] < 3.2 for t in measured)
    assert ev["record"]["calibration_s"][1] == pytest.approx(20.0, abs=0.01)
    # the stall at 28.05 s (1.43 s) is no regular cycle: its horizons are set apart from E (issue 28)
    assert [abs(s["start_s"] - 28.05) < 0.03 for s in ev["record"]["stalls"]] == [True]
    assert ev["record"]["horizons_set_apart"] and all(h["reason"] == "stall" and 27.5 < h["start_s"] < 29.5
                                                      for h in ev["record"]["horizons_set_apart"])
    assert any("held" in n for n in ev["notes"])  # the limit cycle sets the damping
    assert any("exceed the 0.1" in n for n in ev["notes"])  # and it is more than a steel bar's
    assert ev["discovery"]["balanced"] is False  # the encoders' twist does not follow the torque
    head, d = _predictions(out / "predictions.csv")
    assert d.shape[0] == 10000 and np.isfinite(d[d[:, 11] == 1, 5]).all()


# ------------------------------------------------------------------------------- bad input
def test_bad_inputs_name_what_is_wrong(tmp_path):
    t = np.arange(2000) * 2e-3
    no_torque = write_csv(Record(time_s=t, bit_speed=8 + np.sin(t)), tmp_path / "no_torque.csv")
    p = run_cli("loop", str(no_torque), "--preset", "thesis-rig", "--out", str(tmp_path / "a"))
    assert p.returncode == 2 and "torque_on_bit" in p.stderr and p.stderr.count("\n") == 1
    rec = synthetic_record((), duration_s=3.0, seed=1, fs_hz=RATE_HZ)
    short = write_csv(rec, tmp_path / "short.csv")
    p = run_cli("loop", str(short), "--preset", "thesis-rig", "--out", str(tmp_path / "b"), "--horizon", "1.0")
    assert p.returncode == 2 and "horizons" in p.stderr
    p = run_cli("loop", str(short), "--preset", "thesis-rig", "--out", str(tmp_path / "c"), "--effects", "gremlins")
    assert p.returncode == 2 and "unknown effect 'gremlins'" in p.stderr
    p = run_cli("loop", str(short), "--preset", "thesis-rig", "--out", str(tmp_path / "d"),
                "--calibration-fraction", "1.5")
    assert p.returncode == 2 and "calibration_fraction = 1.5" in p.stderr
    p = run_cli("loop", str(short), "--preset", "thesis-rig", "--out", str(tmp_path / "g"), "--gj-tolerance", "-0.1")
    assert p.returncode == 2 and "gj_tolerance = -0.1" in p.stderr
    p = run_cli("loop", str(short), "--config", str(tmp_path / "none.json"), "--out", str(tmp_path / "e"))
    assert p.returncode == 2 and "no such file" in p.stderr
    p = run_cli("loop", str(short), "--preset", "thesis-rig", "--config", "x.json", "--out", str(tmp_path / "f"))
    assert p.returncode == 2 and "not allowed with argument" in p.stderr
    with pytest.raises(ValueError, match="horizon_s = 0"):
        L.LoopOptions(horizon_s=0).validate()



def test_sample175_read_at_its_channels_timing_holds_a_steel_bars_damping_and_the_motor_passes_the_guard(tmp_path):
    """``--channel-timing auto`` on the same record at 250 Hz: the calibration part puts the top
    encoder 40 ms early and the load cell 30 ms late (the bit's equation R^2 0.73 -> 0.94); read at that
    timing the limit cycle holds the damping at a steel bar's (<= 0.1, 0.31 on the short horizons), the
    discovery step's equation balances, the model file keeps the timing, and the motor is the one candidate
    that passes the guard (the thesis's diagnosis) before the long run refuses it: a droop without inertia
    still damps the one-mode model's cycle away (docs/loop.md, "The channels' timing")."""
    out = tmp_path / "s175t"
    p = run_cli("loop", str(sample175_path()), "--preset", "thesis-rig", "--out", str(out), "--rate", "250",
                "--channel-timing", "auto")
    assert p.returncode == 0, p.stderr
    js = json.loads((out / "loop.json").read_text())
    ct = js["channel_timing"]
    assert ct["top_lead_s"] in (0.04, 0.05) and ct["torque_lag_s"] == 0.03 and ct["r2"] - ct["r2_as_recorded"] > 0.2
    model = json.loads((out / "model.json").read_text())
    assert model["channel_timing"]["torque_lag_s"] == 0.03
    ev = json.loads((out / "evidence.json").read_text())
    # held at 0.099 here (0.146 as recorded): a steel bar's, within what another CPU's long runs may move it
    assert ev["baseline"]["parameters"]["damping"]["ratios"][0] < 0.11
    assert ev["discovery"]["balanced"] is True
    # the guard's tests (gain, significance, BIC, physical parameters) pass for the motor alone; the long run
    # refuses it after
    motor = next(c for r in ev["rounds"] for c in r if c["effect"] == "top_drive_dynamics")
    assert motor["delta_bic"] > 6 and motor["relative_gain"] > 0.1
    assert "the corrected model no longer stick-slips while the record does" in motor["reasons"]
    assert not any(g in x for x in motor["reasons"] for g in ("validation gain", "p = ", "dBIC"))
    others = [c for r in ev["rounds"] for c in r if c["effect"] != "top_drive_dynamics"]
    assert others and all(any(g in x for x in c["reasons"] for g in ("validation gain", "p = ", "dBIC"))
                          for c in others)
    assert "top_drive_dynamics" not in js["final_effects"]

def test_damping_hold_is_searched_again_when_the_refit_leaves_the_cycle(monkeypatch):
    """The held damping lies at the edge of the stick-slip region: when the refit of the other
    parameters moves that edge below it (validation case 13: the motor's droop 2.51 -> 2.81), the
    search is repeated from the refit model, so the held model stick-slips like the record. A
    stand-in long run sticks below a damping edge of 0.15 before any refit and 0.11 after one."""
    from drillpy.loop import damping_hold as R
    from drillpy.loop.model import LoopModel
    meas = {"ss": 1.05, "stick_fraction": 0.12, "cycle_frequency_hz": 2.6}
    refits = []

    def long_run(m, data):
        edge = 0.11 if m.top_speed > 8.5 else 0.15
        z = m.damping_ratios[0]
        stick = min(0.3, 3.0 * (edge - z) + 0.01) if z < edge else 0.0
        mod = {"ss": 1.0 + (edge - z) if z < edge else 0.5, "stick_fraction": stick, "cycle_frequency_hz": 2.6}
        return {"measured": meas, "model": mod, "relative_error": {},
                "stick_slips": {"measured": True, "model": stick >= 0.01}}

    def refit(m, data, opt):
        refits.append(m.damping_ratios[0])
        m = m.copy()
        m.top_speed = 9.0  # a refit model: its stick-slip edge has moved
        return m, None

    monkeypatch.setattr(R, "long_run", long_run)
    monkeypatch.setattr(R, "refit", refit)
    m0 = LoopModel({"damping": {"type": "modal", "ratios": [0.25]}}, {}, 8.0, 500.0)
    held, lr, note = R.hold_damping(m0, long_run(m0, None), None, L.LoopOptions(), log=lambda *a: None)
    assert refits[0] > 0.11  # the first hold sat where only the model before the refit sticks
    assert 2 <= len(refits) <= R.HOLD_ROUNDS
    assert held.damping_held and held.damping_ratios[0] < 0.11 and lr["stick_slips"]["model"]
    assert abs(lr["model"]["stick_fraction"] - meas["stick_fraction"]) < 0.06
    assert "held at" in note


# ------------------------------------------------------------------------ the law's low-speed knot
def test_knot_family_with_the_thesis_tie_is_the_tied_law_and_is_continuous():
    """The knot family (LoopOptions.law_knot) at the thesis's knot (5 % of the mean speed) and with
    a flat piece below it is Eq. (5.1) with the tie of drillpy.records.identification, to rounding;
    at any knot the law is continuous at v_k / 5 and v_k."""
    from drillpy.loop import fitting as F
    from drillpy.records import identification as ident
    law = declared_config()["law"]
    from drillpy.records.io import RPM  # RPM per rad/s
    fd = F._FamilyData(law["wob_ref_n"], law["ref_speed"] / RPM)
    cubic = [law["a4"], law["a5"], law["a6"], law["a7"]]
    tied = ident.FAMILIES["polynomial"].build(cubic, fd, "rpm", {"gain": law["gain"]})
    v_k = 0.05 * law["ref_speed"]
    knot = F._FAMILIES["polynomial_knot"].build(cubic + [1.0, v_k], fd, "rpm", {"gain": law["gain"]})
    v = np.linspace(0.0, 30.0, 3001) / RPM  # 0-30 RPM, in rad/s
    z = np.zeros(v.size)
    w = np.full(v.size, law["wob_ref_n"])
    np.testing.assert_allclose(ident.law_eval(knot, v, z, w)[0], ident.law_eval(tied, v, z, w)[0], rtol=1e-12, atol=1e-12)
    knot = F._FAMILIES["polynomial_knot"].build(cubic + [0.6, 25.0], fd, "rpm", {"gain": law["gain"]})
    for vk in (5.0, 25.0):  # the pieces meet (the engine's thresholds are 1 % and 5 % of ref_speed)
        T = ident.law_eval(knot, np.array([vk - 1e-9, vk + 1e-9]) / RPM, np.zeros(2), np.full(2, law["wob_ref_n"]))[0]
        assert T[0] == pytest.approx(T[1], rel=1e-7)


def test_calibrated_knot_follows_a_law_that_rises_after_break_away(tmp_path):
    """The independent rig's clean record (benchmarks/independent_rig.py: a Tucker-Wang law rising
    from 1.2 N m just off rest to 2.74 N m at 3.1 rad/s, a true stick, no drillpy code): Eq. (5.1)
    with the thesis's tie cannot follow the rise (law residual 0.15 N m against 0.02 of noise) and a
    spurious 27 Hz sensor_lag used to stand in for it; with the knot calibrated the law residual is
    at most half of the tied one and the loop adds nothing (docs/loop.md, "Independent check")."""
    rig = pytest.importorskip("independent_rig")
    from drillpy.loop.fitting import law_fit_residual
    from drillpy.loop.model import LoopModel
    from drillpy.loop.effects import stripped
    from drillpy.model.config import normalize
    path = tmp_path / "clean.csv"
    rig.write_csv(rig.simulate({}, seed=1), str(path), ["independent_rig.py: clean, seed 1"])
    cfg = normalize(__import__("drillpy").load_config(preset="thesis-rig"))
    rms = {}
    for knot in (False, True):
        opt = L.LoopOptions(rate_hz=250, law_knot=knot)
        data = L.prepare(str(path), cfg, opt)
        base = stripped(analysis_config(cfg, data.dt, opt.dt_s))
        m = LoopModel(base, dict(base["law"]), 8.47, 557.1, {})
        rms[knot] = float(np.sqrt(np.mean(law_fit_residual(m, data) ** 2)))
    assert rms[False] > 0.1 and rms[True] < 0.5 * rms[False], rms
    res = L.run_loop(str(path), cfg, L.LoopOptions(rate_hz=250), log=lambda *a: None)
    assert [s.effect for s in res.steps if s.action == "add"] == []
    assert res.baseline.E_test < 0.1


def test_a_step_near_the_threshold_is_reported_as_marginal():
    """An added effect whose validation gain is below twice ``min_gain`` gets a "marginal" note
    (a 6.2 % gain, as validation case 26's fast torque_fluctuation had); a clear gain (sample 175's
    wob_coupling, 12.1 %) gets none. (No effect is added on its direct measurement any more, issue 29:
    the note for that case is gone.)"""
    from drillpy.loop.run import marginal
    opt = L.LoopOptions()
    assert "6.2 %" in marginal("torque_fluctuation", L.Evidence(relative_gain=0.062), opt)
    assert marginal("wob_coupling", L.Evidence(relative_gain=0.121), opt) is None
    assert marginal("x", L.Evidence(relative_gain=0.062), L.LoopOptions(min_gain=0.02)) is None


def test_a_soft_motor_long_run_starts_at_the_measured_top_speed(tmp_path):
    """The long run of a model with a soft motor (droop 9 rad/s per N m, command 22.8 rad/s for a
    top turning at 7.5) starts with the motor at the record's top speed (Eq. 2.10 there). Started at
    its command, the bit was flung past 28 rad/s, where the law calibrated on a Stribeck record
    (a7 < 0, speeds up to 19 rad/s) turns negative, and the run diverged: the right effect of the
    second independent check was then refused (docs/loop.md)."""
    import stribeck_rig
    from drillpy.loop.data import prepare
    from drillpy.loop.effects import stripped
    from drillpy.loop.longrun import long_run
    from drillpy.loop.model import LoopModel
    path = tmp_path / "motor.csv"
    stribeck_rig.make_record("top_drive_dynamics", 13, str(path), omega_c=23.809, cm=0.1)
    opt = L.LoopOptions(rate_hz=250)
    cfg = load_config(preset="thesis-rig")
    data = prepare(str(path), cfg, opt)
    acfg = analysis_config(cfg, data.dt, opt.dt_s)
    law = {"type": "polynomial", "speed_unit": "rpm", "wob_ref_n": 557.1, "gain": 1.36, "ref_speed": 80.0,
           "a0": 0.0, "a1": 2.15252, "a2": 1.72202, "a3": 0.0, "a4": 1.805331, "a5": -0.0216071,
           "a6": 1.969381e-4, "a7": -6.04036e-7}  # the fit of that record: negative above 28 rad/s
    base = stripped(acfg)
    base["damping"] = {"type": "modal", "ratios": [0.0397]}
    motor = {"variant": "motor", "droop_rad_s_per_nm": 9.096, "inertia_kg_m2": 0.01964, "command_rad_s": 22.758}
    lr = long_run(LoopModel(base, law, 7.517, 554.2, {"top_drive_dynamics": motor}), data)
    assert "error" not in lr, lr.get("error")
    m, r = lr["model"], lr["measured"]
    assert abs(m["ss"] / r["ss"] - 1) < 0.15 and abs(m["stick_fraction"] / r["stick_fraction"] - 1) < 0.3
