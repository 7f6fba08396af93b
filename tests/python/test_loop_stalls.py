"""Horizons the loop's E leaves out (issue 28): a stall is no part of the regular stick-slip cycle and
is reported apart; a restart whose top speed is an artifact is never fed in."""
from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
from _testrig import sample175_path

from drillpy import loop as L
from drillpy.loop.run import analysis_config
from drillpy.model.config import load_config
from drillpy.loop.synthetic import declared_config, synthetic_record

RATE_HZ = 250.0


def _overlaps(data, s, a, b):
    return a <= data.t[s + data.L] and data.t[s] <= b


def test_sample175_stall_horizons_are_set_apart_and_no_kept_horizon_touches_it():
    cfg = load_config(preset="thesis-rig")
    data = L.prepare(sample175_path(), cfg, L.LoopOptions(rate_hz=RATE_HZ))
    assert len(data.stalls) == 1  # docs/records.md: one stall, 1.43 s at 28.05 s
    a, n = data.stalls[0]
    assert abs(a - 28.05) < 0.02 and abs(n - 1.43) < 0.03
    assert data.set_apart and set(data.set_apart.values()) == {"stall"}
    for s in data.set_apart:
        assert _overlaps(data, s, a, a + n)
    assert not any(_overlaps(data, s, a, a + n) for s in data.starts)
    # the horizon grid is one grid: the kept and the set-apart restarts never coincide
    assert not set(data.set_apart) & set(int(s) for s in data.starts)


def test_a_synthetic_stall_is_set_apart_and_a_short_stick_is_not():
    rec = synthetic_record((), duration_s=8.0, seed=2, fs_hz=RATE_HZ)
    cfg = analysis_config(declared_config(), 1.0 / RATE_HZ)
    opt = L.LoopOptions(rate_hz=RATE_HZ)
    plain = L.prepare(rec, cfg, opt)
    assert plain.stalls == () and plain.set_apart == {}
    v = rec.bit_speed.copy()
    t = rec.time_s
    v[(t >= 5.0) & (t < 5.8)] = 0.0  # 0.8 s stuck: longer than rigsim.STALL_MIN_S (0.5 s)
    data = L.prepare(dataclasses.replace(rec, bit_speed=v), cfg, opt)
    a, n = data.stalls[0]
    assert len(data.stalls) == 1 and a <= 5.0 and a + n >= 5.79  # the record's own stick may adjoin it
    assert set(data.set_apart.values()) == {"stall"}
    assert len(data.set_apart) >= 3  # 0.8 s spans at least three 0.25 s horizons
    assert data.starts.size + len(data.set_apart) == plain.starts.size


def test_the_error_scale_leaves_a_stall_out_and_a_model_file_carries_it():
    """E's spreads (rig_comparison.metric_scale) are taken outside the stalls: a stall holds the
    torque near its break-away value, which would widen the torque's spread and make every error
    look smaller (sample 175, 20-30 s: docs/records.md, "One scale for E"). The loop model keeps
    the scale in model.json, and prepare scores a record on a scale given to it (drillpy predict)."""
    rec = synthetic_record((), duration_s=8.0, seed=2, fs_hz=RATE_HZ)
    cfg = analysis_config(declared_config(), 1.0 / RATE_HZ)
    opt = L.LoopOptions(rate_hz=RATE_HZ)
    v = rec.bit_speed.copy()
    t = rec.time_s
    stuck = (t >= 1.5) & (t < 2.5)  # 1 s stuck inside the calibration part (t < 4 s)
    v[stuck] = 0.0
    T = rec.torque_on_bit.copy()
    T[stuck] = np.percentile(T, 99)  # the string wound up against the stuck bit
    rec = dataclasses.replace(rec, bit_speed=v, torque_on_bit=T)
    data = L.prepare(rec, cfg, opt)
    assert len(data.stalls) == 1
    a, n = data.stalls[0]
    cal = data.valid & (data.t < data.t_split)
    out = cal & ~((data.t >= a) & (data.t < a + n))
    assert abs(data.sigma_v - np.std(data.v_meas[out])) < 1e-12
    assert abs(data.sigma_T - np.std(data.T_meas[out])) < 1e-12
    # counted in, the stall's held torque would have widened the torque's spread
    assert np.std(data.T_meas[cal]) > 1.05 * data.sigma_T
    given = L.prepare(rec, cfg, opt, scale=(2.0, 0.5))
    assert (given.sigma_v, given.sigma_T) == (2.0, 0.5)
    m = L.LoopModel(cfg, dict(cfg["law"]), 10.0, 1000.0, metric_scale=(data.sigma_v, data.sigma_T))
    back = L.LoopModel.from_dict(json.loads(json.dumps(m.to_dict())))
    assert back.metric_scale == (data.sigma_v, data.sigma_T)
    d = m.to_dict()
    d["metric_scale"] = {"bit_speed_rad_s": -1.0, "torque_on_bit_nm": 0.5}
    with pytest.raises(ValueError, match="metric_scale"):
        L.LoopModel.from_dict(d)
