"""drillpy loop: synthetic records with known effects (found, error reduced, nothing added when
nothing is missing), the metric recomputed from the outputs, the recursive estimate of the
fluctuation, the guard, sample 175, and bad input."""
from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest

from conftest import run_cli
from _testrig import sample175_path
from loop_synthetic import CASES, DURATION_S, LOOP_DT_S, RATE_HZ, run_case

from drillpy import loop as L
from drillpy.records import Record, write_csv
from drillpy.synthetic import declared_config, synthetic_record

LOOP_KEYS = {"metric", "baseline_error", "steps", "final_error", "parameters"}
STEP_KEYS = {"effect", "error_before", "error_after", "evidence"}


def _case_id(case) -> str:
    eff, seed = case
    return ("+".join(eff) or "none") + f"-seed{seed}-" + "-".join(
        f"{k}{v:g}" for p in eff.values() for k, v in p.items())


@pytest.mark.parametrize("case", CASES, ids=[_case_id(c) for c in CASES])
def test_synthetic_effect_is_found_and_reduces_the_error(case):
    """One effect: named first, validation error after <= 0.6 x before. None: nothing added.
    Two: both found. (The table of docs/loop.md: benchmarks/loop_synthetic.py.)"""
    eff, seed = case
    r = run_case(eff, seed)
    if not eff:
        assert r["found"] == [], r
    elif len(eff) == 1:
        assert r["found"] and r["found"][0] in eff, r
        assert r["first_after"] <= 0.6 * r["baseline"], r
    else:
        assert set(eff) <= set(r["found"]), r


def test_fitted_parameters_are_the_injected_ones():
    """The sensor's cutoff and the motor's droop come back from the records they were put in."""
    r = run_case({"sensor_lag": {"lowpass_hz": 6.0}}, 2)  # cases of the table: computed once
    assert r["params"]["sensor_lag"]["lowpass_hz"] == pytest.approx(6.0, rel=0.1)
    r = run_case({"top_drive_dynamics": {"slope_nms_rad": 0.25, "inertia_kg_m2": 0.02}}, 1)
    p = r["params"]["top_drive_dynamics"]
    assert p["variant"] == "motor"
    assert p["droop_rad_s_per_nm"] == pytest.approx(1 / 0.25, rel=0.1)
    assert p["inertia_kg_m2"] == pytest.approx(0.02, rel=0.2)


def test_noise_free_declared_model_predicts_its_own_record():
    """Restarted from the states read off a noise-free record of the declared model itself, the
    calibrated model predicts the record: E below 0.05 (the channel spreads are 1)."""
    rec = synthetic_record((), duration_s=8.0, seed=3, fs_hz=RATE_HZ, noise=0.0)
    res = L.run_loop(rec, declared_config(), L.LoopOptions(rate_hz=RATE_HZ, dt_s=1e-4, max_steps=0),
                     log=lambda *a: None)
    assert res.baseline.E_test < 0.05
    assert res.baseline.channel_rmse["bit_speed_rad_s"] < 0.05 * res.data.sigma_v


@pytest.fixture(scope="module")
def two_effect_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("loop")
    rec = synthetic_record({"top_drive_dynamics": {}, "wob_coupling": {}}, duration_s=DURATION_S, seed=4,
                           fs_hz=RATE_HZ)
    path = write_csv(rec, out / "record.csv")
    cfg = out / "declared.json"
    cfg.write_text(json.dumps(declared_config()))
    p = run_cli("loop", str(path), "--config", str(cfg), "--out", str(out / "res"), "--rate", str(RATE_HZ),
                "--dt", str(LOOP_DT_S))
    assert p.returncode == 0, p.stderr
    return out / "res"


def _predictions(path):
    with open(path) as fh:
        rows = list(csv.reader(fh))
    head = rows[0]
    data = np.array([[float(x) if x else np.nan for x in r] for r in rows[1:]])
    return head, data


def test_outputs_have_the_interface_keys_and_the_metric_is_what_it_says(two_effect_run):
    out = two_effect_run
    js = json.loads((out / "loop.json").read_text())
    assert set(js) == LOOP_KEYS
    assert [s["effect"] for s in js["steps"]] == ["top_drive_dynamics", "wob_coupling"]
    for s in js["steps"]:
        assert set(s) == STEP_KEYS
        assert s["error_after"] < s["error_before"]
    assert js["steps"][0]["error_before"] == js["baseline_error"]
    assert js["steps"][-1]["error_after"] == js["final_error"]
    assert set(js["parameters"]["effects"]) == {"top_drive_dynamics", "wob_coupling"}
    head, d = _predictions(out / "predictions.csv")
    assert head == ["time_s", "bit_speed_rad_s", "torque_on_bit_Nm", "baseline_bit_speed_rad_s",
                    "baseline_torque_on_bit_Nm", "final_bit_speed_rad_s", "final_torque_on_bit_Nm", "validation",
                    "horizon"]
    ev = json.loads((out / "evidence.json").read_text())
    sv, sT = ev["record"]["sd_bit_speed_rad_s"], ev["record"]["sd_torque_nm"]
    # E recomputed from predictions.csv: the validation rows, both channels normalized
    val = d[:, 7] == 1
    for col_v, col_T, key in ((3, 4, "baseline_error"), (5, 6, "final_error")):
        e2 = 0.5 * (np.mean((d[val, col_v] - d[val, 1]) ** 2) / sv ** 2 + np.mean((d[val, col_T] - d[val, 2]) ** 2) / sT ** 2)
        assert math.sqrt(e2) == pytest.approx(js[key], rel=1e-9)
    # calibration rows all precede the validation rows
    assert np.max(d[d[:, 7] == 0, 0]) < np.min(d[val, 0])
    assert "validation part" in js["metric"] and "restarted every 0.25 s" in js["metric"]
    report = (out / "report.md").read_text()
    for section in ("## Metrics", "## Result", "### Physical reading", "## Evidence per round", "## Figures"):
        assert section in report
    for fig in ("residual_signature.png", "overlay.png", "loops.png", "errors.png"):
        assert (out / fig).stat().st_size > 10_000
    model = json.loads((out / "model.json").read_text())
    assert model["top_drive"]["type"] == "motor"


def test_eta_estimate_recovers_a_line_and_the_forecast_starts_from_it():
    """The recursive weighted least squares gives the level and slope of a straight eta exactly,
    and the forecast starts at the level with the slope (d/ds of the free response at 0)."""
    rec = synthetic_record((), duration_s=4.0, seed=1, fs_hz=RATE_HZ, noise=0.0)
    cfg = L._analysis_config(declared_config(), 1.0 / RATE_HZ)
    data = L.prepare(rec, cfg, L.LoopOptions(rate_hz=RATE_HZ))
    m = L.LoopModel(cfg, dict(cfg["law"]), cfg["operation"]["top_speed_rad_s"], cfg["operation"]["wob_n"],
                    {"torque_fluctuation": {"tau_s": 0.7, "memory_s": 0.2}})
    chs = L.state_channels(m, data)
    eta = 0.1 + 0.05 * data.t  # a torque 10 % above the law, rising by 5 % per second
    chs["T"] = L.law_torque(m, chs) * (1.0 + eta)
    level, slope = L.eta_estimate(m, data, chs)
    slip = np.flatnonzero(data.valid & (chs["v"] > data.stick_threshold))
    k = slip[slip > 50][::7]
    assert np.allclose(level[k], eta[k], atol=1e-9)
    assert np.allclose(slope[k], 0.05, atol=1e-7)
    lead = np.array([0.0, 1e-6])
    f = L.eta_forecast(m, level[k], slope[k], lead)
    assert np.allclose(f[:, 0], level[k])
    assert np.allclose((f[:, 1] - f[:, 0]) / 1e-6, slope[k], atol=1e-5)


def test_guard_refuses_a_candidate_that_changes_nothing():
    rec = synthetic_record((), duration_s=8.0, seed=2, fs_hz=RATE_HZ)
    opt = L.LoopOptions(rate_hz=RATE_HZ, dt_s=LOOP_DT_S)
    cfg = L._analysis_config(declared_config(), 1.0 / RATE_HZ, LOOP_DT_S)
    data = L.prepare(rec, cfg, opt)
    base = L.evaluate(L.calibrate(cfg, data), data)
    e = L.evidence(base, base, data, 6, opt)
    assert e["relative_gain"] == 0.0 and e["explained_fraction"] == 0.0
    assert not e["accepted"] and len(e["reasons"]) == 3
    assert e["level"] == pytest.approx(opt.alpha / 6)


def test_sample175_calibrated_on_one_part_validated_on_the_other(tmp_path):
    """The loop runs on the measured record (first 40 s): calibration on 0-20 s, errors on 20-40 s;
    the WOB coupling is the best candidate there and the sensor cutoff it fits is the rig's 10 Hz."""
    out = tmp_path / "s175"
    p = run_cli("loop", str(sample175_path()), "--preset", "thesis-rig", "--out", str(out), "--rate", "250")
    assert p.returncode == 0, p.stderr
    js = json.loads((out / "loop.json").read_text())
    assert set(js) == LOOP_KEYS
    assert 0.5 < js["baseline_error"] < 1.5 and js["final_error"] <= js["baseline_error"]
    ev = json.loads((out / "evidence.json").read_text())
    assert ev["record"]["calibration_s"][1] == pytest.approx(20.0, abs=0.01)
    assert ev["record"]["validation_s"] == pytest.approx([20.0, 40.0], abs=0.01)
    first = {c["effect"]: c for c in ev["rounds"][0]}
    assert "bit_hysteresis" not in first  # the preset's law (Eq. 5.3) declares it
    best = max(first.values(), key=lambda c: c.get("relative_gain", -1))
    assert best["effect"] == "wob_coupling" and best["relative_gain"] > 0.05
    assert first["sensor_lag"]["parameters"]["lowpass_hz"] == pytest.approx(10.0, rel=0.15)
    head, d = _predictions(out / "predictions.csv")
    assert d.shape[0] == 10000 and np.isfinite(d[d[:, 7] == 1, 3]).all()


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
    p = run_cli("loop", str(short), "--config", str(tmp_path / "none.json"), "--out", str(tmp_path / "e"))
    assert p.returncode == 2 and "no such file" in p.stderr
    p = run_cli("loop", str(short), "--preset", "thesis-rig", "--config", "x.json", "--out", str(tmp_path / "f"))
    assert p.returncode == 2 and "not allowed with argument" in p.stderr
    with pytest.raises(ValueError, match="horizon_s = 0"):
        L.LoopOptions(horizon_s=0).validate()
