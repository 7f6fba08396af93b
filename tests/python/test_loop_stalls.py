"""Horizons the loop's E leaves out (issue 28): a stall is no part of the regular stick-slip cycle and
is reported apart; a restart whose top speed is an artifact is never fed in."""
from __future__ import annotations

import dataclasses


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
