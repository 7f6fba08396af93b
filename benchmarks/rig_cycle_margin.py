"""The rig model's stick-slip cycle against the WOB, and whether a larger static torque widens its margin
(issue 28, docs/records.md section 4, "Another split").

    PYTHONPATH=python python3 benchmarks/rig_cycle_margin.py --model D/model.json [--window 0:20] \
        [--static-torque-factors 1,1.05,1.1,1.15,1.2] [--realizations 6]
    PYTHONPATH=python python3 benchmarks/rig_cycle_margin.py --truth [--voltages 0.93,0.95,0.97,1]
    PYTHONPATH=python python3 benchmarks/rig_cycle_margin.py --breakaway [--record FILE.mat]

D from ``drillpy analyze ../shared/data/testrig/sample175_0-40s.mat --calibrate 0:20 --out D``. For each
static-torque factor (the law's static torque scaled, ``RigModel.static_torque_factor``; its physical
range 1-1.2) it prints the model's stick fraction with the window's WOB scaled by 0.85, 0.9 and 1
(:func:`drillpy.records.cycle_margin.model_runs`) and the long-run mismatch on the window, the mean WOB of
the record and of the model's run (whether the record's WOB trend is the jack's set force); then, at the
model's own static torque, the stick fraction at the same WOBs over ``--realizations`` realizations of
the model's torque fluctuation, Eq. (4.1) (``records.rig_fluctuation``): whether the fluctuation keeps
the bit sticking where the deterministic model does not. A few seconds.

``--truth`` asks the same of the independent whole-rig truth (``benchmarks/whole_rig.py``, seed 5, no
supply step): 30 s at each jack supply voltage (its WOB's level), the stick fraction of each 5 s block
after the first 5 s, with the mean WOB and top speed. About 10 s per voltage.

``--breakaway`` asks the record how its break-away torque depends on the WOB: for every regular stick
phase (10-500 ms below the stick threshold) the largest recorded torque from its start to 40 ms after
it, regressed by least squares on the WOB's trend below 0.5 Hz at its start and on its duration, beside
the slope a torque proportional to the WOB would have (the mean break-away torque over the mean WOB).
The recorded torque went through the 10 Hz filter and the platform, which round off a short plateau:
part of the duration's term is theirs. Then the record's 5 s blocks: mean WOB and regular stick fraction
(:func:`drillpy.records.cycle_margin.record_blocks`).
"""
from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
SAMPLE175 = REPO.parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--model", help="model.json of drillpy analyze --calibrate")
    ap.add_argument("--truth", action="store_true", help="the independent whole-rig truth at --voltages instead")
    ap.add_argument("--voltages", default="0.93,0.95,0.97,1", help="the truth's jack supply voltages")
    ap.add_argument("--breakaway", action="store_true", help="the record's break-away torques against the WOB")
    ap.add_argument("--record", default=str(SAMPLE175))
    ap.add_argument("--window", default="0:20", help="T0:T1 [s], the model's calibration part")
    ap.add_argument("--static-torque-factors", default="1,1.05,1.1,1.15,1.2")
    ap.add_argument("--realizations", type=int, default=6, help="realizations of Eq. (4.1)'s fluctuation")
    a = ap.parse_args(argv)
    if a.truth:
        return _truth([float(x) for x in a.voltages.split(",")])
    if a.breakaway:
        return _breakaway(a.record)
    if a.model is None:
        ap.error("--model DIR/model.json (or --truth)")
    import numpy as np

    from drillpy.loop.prediction import load_model
    from drillpy.records import rig_comparison, rig_fluctuation, rigsim
    from drillpy.records.cleaning import clean
    from drillpy.records.cycle_margin import model_runs
    from drillpy.records.io import read_record
    t0, t1 = (float(x) for x in a.window.split(":"))
    rec = clean(read_record(a.record).select(t0, t1))[0]
    model = load_model(a.model)
    thr = model.calibration["stick_threshold_rad_s"]
    print("static-torque factor | stick fraction at 85 / 90 / 100 % of the WOB | mismatch | SS")
    for f in (float(x) for x in a.static_torque_factors.split(",")):
        m = dataclasses.replace(model, static_torque_factor=f)
        runs = model_runs(m, rec, thr, factors=(0.85, 0.9, 1.0))
        c = rig_comparison.compare(rec, rigsim.simulate_model(m, rec), thr)
        print(f"{f:g} | " + " / ".join(f"{r['stick_fraction']:.3f}" for r in runs)
              + f" | {c.mismatch:.3f} | {c.simulated['ss']:.3f}")
    sim = rigsim.simulate_model(model, rec)
    after = sim.time_s >= sim.time_s[0] + 2.0
    print(f"mean WOB after the first 2 s: record {np.nanmean(rec.wob[rec.time_s >= rec.time_s[0] + 2.0]):.1f} N, "
          f"model {np.nanmean(sim.wob[after]):.1f} N (the jack's set force is the record's trend)")
    tf = model.torque_fluctuation
    if tf is None or a.realizations < 1:
        return 0
    span = float(rec.time_s[-1] - rec.time_s[0])
    print(f"with Eq. (4.1)'s fluctuation (std {tf['std']:.3f}), {a.realizations} realizations:")
    for f in (0.85, 0.9, 1.0):
        scaled = dataclasses.replace(rec, wob=rec.wob * f)
        st = [rig_comparison.compare(scaled, rigsim.simulate_model(
            model, scaled, eta=rig_fluctuation.realization(tf, rec.dt, span, seed=0, sample=k)), thr).simulated["stick_fraction"]
              for k in range(a.realizations)]
        print(f"  {100 * f:.0f} % of the WOB: stick fraction {min(st):.3f}-{max(st):.3f} (median {np.median(st):.3f})")
    return 0


def _breakaway(path: str) -> int:
    """The record's break-away torques regressed on the WOB trend and the stick duration (module docstring)."""
    import numpy as np

    from drillpy.records import rigsim
    from drillpy.records.cleaning import clean
    from drillpy.records.io import read_record
    rec = clean(read_record(path))[0]
    v, torque = rec.bit_speed, rec.torque_on_bit
    trend = rigsim.wob_trend(rec, float(np.nanmean(rec.wob)))
    stuck = v <= rigsim.stick_threshold(rec)
    lag = int(round(0.04 / rec.dt))
    rows, i = [], 0
    while i < len(v):
        if not stuck[i]:
            i += 1
            continue
        e = i
        while e < len(v) and stuck[e]:
            e += 1
        if 0.01 <= (e - i) * rec.dt <= 0.5 and i > 0 and e < len(v):
            rows.append(((e - i) * rec.dt, float(np.nanmax(torque[i:e + lag])), float(trend[i])))
        i = e
    dur, tb, w = np.array(rows).T
    X = np.c_[np.ones_like(w), w, dur]
    coef, *_ = np.linalg.lstsq(X, tb, rcond=None)
    res = tb - X @ coef
    se = np.sqrt(np.diag(np.linalg.inv(X.T @ X)) * (res @ res) / (len(tb) - 3))
    print(f"{len(tb)} regular stick phases, WOB trend {w.min():.0f}-{w.max():.0f} N, break-away torque "
          f"{tb.mean():.2f} +- {tb.std():.2f} N m")
    print(f"break-away torque = {coef[0]:.2f} (+- {se[0]:.2f}) N m + {coef[1]:.4f} (+- {se[1]:.4f}) N m/N x WOB "
          f"+ {coef[2]:.1f} (+- {se[2]:.1f}) N m/s x duration; R^2 {1 - (res @ res) / np.sum((tb - tb.mean()) ** 2):.2f}")
    print(f"a torque proportional to the WOB: {tb.mean() / w.mean():.4f} N m/N")
    from drillpy.records.cycle_margin import record_blocks
    print("the record's 5 s blocks (stalls left out): " + ", ".join(
        f"{b['window_s'][0]:g} s {b['wob_n']:.0f} N {b['stick_fraction']:.3f}"
        for b in record_blocks(rec, rigsim.stick_threshold(rec))))
    return 0


def _truth(voltages: list) -> int:
    """The independent whole-rig truth's stick fraction per 5 s block at each jack supply voltage."""
    import tempfile

    import numpy as np

    sys.path.insert(0, str(REPO / "benchmarks"))
    import whole_rig
    from drillpy.records import rigsim
    from drillpy.records.cleaning import clean
    from drillpy.records.cycle_margin import record_blocks
    from drillpy.records.io import read_record
    print("jack voltage | mean WOB [N] | mean top speed [rad/s] | stick fraction per 5 s block")
    for u in voltages:
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "truth.mat"
            whole_rig.write_mat(whole_rig.simulate({"jack_voltage": u, "jack_steps": []}, duration=30.0, seed=5),
                                str(path))
            part = clean(read_record(path))[0].select(5.0, None)
        blocks = record_blocks(part, rigsim.stick_threshold(part))
        print(f"{u:g} | {np.nanmean(part.wob):.0f} | {np.nanmean(part.top_speed):.2f} | "
              + ", ".join(f"{b['stick_fraction']:.3f}" for b in blocks))
    return 0


if __name__ == "__main__":
    sys.exit(main())
