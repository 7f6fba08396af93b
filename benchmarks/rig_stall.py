"""Can the rig model's motor torque limit predict sample 175's stall (issue 28)?

    PYTHONPATH=python python3 benchmarks/rig_stall.py --model D/model.json [--record FILE.mat]
        [--limits 8,3.2,3.1,3.0,2.95,2.9,2.85] [--ageing A,TAU_S] [--fit T0:T1]

D from ``drillpy analyze ../shared/data/testrig/sample175_0-40s.mat --calibrate T0:T1 --out D``. The record
stalls once, at 28.05 s for 1.43 s (the load cell at 3.74 N m, the top speed at 0.42 rad/s, the WOB at
647 N); the thesis's reading (section 5.3.2): the bit "achieves a reactive torque that the electrical motor
is not able to overcome". The calibrated motor gives c_m Omega_c, about 5 N m, at rest, above the 8 N m
rating's half; the ESC's current limit, which would cap it lower, is not measured. So the model is run over
the whole record (its WOB trend as the jack's set force, as in every long run) with its motor's torque
limit (``RigModel.motor_max_torque_nm``) at each of ``--limits`` N m, and prints per limit:

* the stalls (stick phases of at least ``rigsim.STALL_MIN_S``) with their starts and durations;
* the regular stick fraction and SS;
* the three longest stick phases (start and duration) and the top speed's lowest value and its time
  (the record's reliable samples), after the first 2 s: where the model comes closest to a stall;

and the record's own values in the first line. ``--ageing A,TAU_S`` runs the model with its law's static torque
ageing (``law.static_ageing`` A, ``law.static_ageing_s`` TAU_S: after tau s stuck the static torque is
(1 + A tau / (tau + TAU_S)) times the law's; not in the thesis).

``--fit T0:T1`` finds the two elements on a part of the record that holds a stall (the model's other
parameters as calibrated): over a grid of limits (2.9-4.2 N m), A (0.1-1) and tau_a (0.1-1 s), the
candidates whose run over the part has as many stalls as the part, ranked by the error of the stalls'
starts and durations and then by the part's mismatch (``rig_comparison.compare``); prints the best five,
then runs the best over the whole record and prints, per 10 s window, its stalls beside the record's:
the windows outside the part are the held-out check (a stall where the record has none is a false one).
The same for the best candidate whose limit is at least the torque the load cell holds through the part's
stall (its median): the motor gives that torque there, so a lower limit is not the rig's.
"""
from __future__ import annotations

import argparse
import dataclasses
import json
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
SAMPLE175 = REPO.parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"


def describe(rec, metrics: dict, threshold: float, reliable: np.ndarray, skip_s: float = 2.0) -> str:
    """One line: the stalls, the regular metrics, the longest stick phases and the lowest reliable top
    speed, after the first ``skip_s`` (the simulation's start from rest, as in the comparison)."""
    st = metrics["stalls"]
    t0 = float(rec.time_s[0]) + skip_s
    from drillpy.records.rig_comparison import stalls
    runs = stalls(rec.bit_speed, rec.dt, threshold, min_s=0.0)  # every stick phase, longest first below
    phases = sorted(((float(rec.time_s[a]), k * rec.dt) for a, k in runs if rec.time_s[a] >= t0), key=lambda r: -r[1])
    longest = ", ".join(f"{a:.2f} s {d:.2f} s" for a, d in phases[:3])
    ok = np.isfinite(rec.top_speed) & reliable[:len(rec)] & (rec.time_s >= t0)
    k = int(np.argmin(np.where(ok, rec.top_speed, np.inf)))
    return (f"stalls {st['count']}" + "".join(f" ({a:.2f} s, {d:.2f} s)" for a, d in zip(st["starts_s"], st["durations_s"]))
            + f"; stick fraction {metrics['stick_fraction']:.3f}, SS {metrics['ss']:.3f}; longest sticks: {longest}; "
            f"top speed lowest {rec.top_speed[k]:.2f} rad/s at {rec.time_s[k]:.2f} s")


def fit(model, rec, thr: float, t0: float, t1: float) -> int:
    """``--fit``: the grid search on the part [t0, t1] and the best candidate over the whole record."""
    import itertools

    from drillpy.records import rig_comparison, rigsim
    part = rec.select(t0, t1)
    side = rig_comparison.measured_side(part, thr, float(part.time_s[0]), "rig")
    meas = side.metrics["stalls"]
    print(f"part {t0:g}-{t1:g} s: {meas['count']} stall(s) at {meas['starts_s']} s for {meas['durations_s']} s")
    if not meas["count"]:
        print("the part has no stall: nothing to find the elements on (--fit needs a part that holds one)")
        return 1
    rows = []
    for lim, amp, tau in itertools.product(np.arange(2.9, 4.25, 0.1), (0.1, 0.2, 0.4, 0.6, 0.8, 1.0), (0.1, 0.3, 1.0)):
        m = dataclasses.replace(model, motor_max_torque_nm=float(lim), static_ageing=amp, static_ageing_s=tau)
        cmp = rig_comparison.compare(part, rigsim.simulate_model(m, part), thr, side=side)
        st = cmp.simulated["stalls"]
        if st["count"] != meas["count"]:
            continue
        err = sum(abs(a - b) + abs(c - d) for a, b, c, d in zip(st["starts_s"], meas["starts_s"], st["durations_s"],
                                                                meas["durations_s"]))
        rows.append((err, cmp.mismatch, float(lim), amp, tau, st))
    rows.sort(key=lambda r: (round(r[0], 1), r[1]))
    print(f"{len(rows)} of 252 candidates have the part's stall count; the best (error of the stalls' starts and "
          "durations [s], mismatch):")
    for err, mis, lim, amp, tau, st in rows[:5]:
        print(f"  limit {lim:.1f} N m, A {amp:g}, tau_a {tau:g} s: error {err:.2f} s, mismatch {mis:.3f}; stalls "
              f"{[round(x, 2) for x in st['starts_s']]} s for {[round(x, 2) for x in st['durations_s']]} s")
    if not rows:
        return 1
    # through its stall the rig's motor gives the torque the load cell holds: a limit below it is not the rig's
    floor = float(np.nanmedian(np.concatenate([part.torque_on_bit[(part.time_s >= a) & (part.time_s < a + d)]
                                               for a, d in zip(meas["starts_s"], meas["durations_s"])])))
    plausible = [r for r in rows if r[2] >= floor - 1e-9]
    print(f"the load cell through the part's stall(s): median {floor:.2f} N m, the least limit the record allows; "
          + (f"the best candidate at or above it: limit {plausible[0][2]:.1f} N m, A {plausible[0][3]:g}, tau_a "
             f"{plausible[0][4]:g} s, error {plausible[0][0]:.2f} s, mismatch {plausible[0][1]:.3f}" if plausible
             else "no candidate at or above it"))
    for label, row in (("the best", rows[0]), ("the best at or above that torque", plausible[0] if plausible else None)):
        if row is not None:
            print(f"{label} over the whole record:")
            windows(model, rec, thr, t0, t1, *row[2:5])
    return 0


def windows(model, rec, thr: float, t0: float, t1: float, lim: float, amp: float, tau: float) -> None:
    """The model with these elements over the whole record: per 10 s window its stalls and stick fraction
    beside the record's (the windows outside [t0, t1] held out)."""
    from drillpy.records import rig_comparison, rigsim
    best = dataclasses.replace(model, motor_max_torque_nm=lim, static_ageing=amp, static_ageing_s=tau)
    sim = rigsim.simulate_model(best, rec)
    for w0 in np.arange(float(rec.time_s[0]), float(rec.time_s[-1]) - 1.0, 10.0):
        piece, spiece = rec.select(w0, w0 + 10.0), sim.select(w0, w0 + 10.0)
        # the whole record's run has its start-up in the first window only: no window but that skips its start
        skip = 2.0 if w0 == float(rec.time_s[0]) else 0.0
        sm = rig_comparison.measured_side(piece, thr, float(piece.time_s[0]), "rig", t_start=skip).metrics
        cm = rig_comparison.compare(piece, spiece, thr, t_start=skip).simulated
        tag = "part" if t0 <= w0 < t1 else "held out"
        print(f"  {w0:g}-{w0 + 10:g} s ({tag}): record stalls {sm['stalls']['count']} "
              f"{[round(x, 2) for x in sm['stalls']['starts_s']]}, model {cm['stalls']['count']} "
              f"{[round(x, 2) for x in cm['stalls']['starts_s']]} for {[round(x, 2) for x in cm['stalls']['durations_s']]} s; "
              f"stick fraction {sm['stick_fraction']:.3f} / {cm['stick_fraction']:.3f}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--model", required=True, help="model.json of drillpy analyze --calibrate")
    ap.add_argument("--record", default=str(SAMPLE175))
    ap.add_argument("--limits", default="8,3.2,3.1,3.0,2.95,2.9,2.85", help="motor torque limits [N m], comma-separated")
    ap.add_argument("--ageing", default=None, metavar="A,TAU_S", help="the law's static torque ageing (default none)")
    ap.add_argument("--fit", default=None, metavar="T0:T1", help="find the limit and the ageing on this part's stalls")
    a = ap.parse_args(argv)
    from drillpy.records import rig_comparison, rigsim
    from drillpy.records.cleaning import clean
    from drillpy.records.io import read_record
    rec = clean(read_record(a.record))[0]
    thr = rigsim.stick_threshold(rec)
    model = rigsim.RigModel.from_dict(json.loads(Path(a.model).read_text()))
    if model.drive != "rig":
        raise SystemExit(f"--model: drive {model.drive!r}: the motor's torque limit belongs to the rig drive")
    if a.ageing:
        amp, tau = (float(x) for x in a.ageing.split(","))
        model = dataclasses.replace(model, law={**model.law, "static_ageing": amp, "static_ageing_s": tau})
        print(f"the law's static torque aged: A {amp:g}, tau_a {tau:g} s")
    if a.fit:
        return fit(model, rec, thr, *(float(x) for x in a.fit.split(":")))
    side = rig_comparison.measured_side(rec, thr, float(rec.time_s[0]), "rig")
    print(f"record: {describe(rec, side.metrics, thr, rigsim.reliable_top_speed(rec))}")
    for lim in (float(x) for x in a.limits.split(",")):
        m = dataclasses.replace(model, motor_max_torque_nm=lim)
        sim = rigsim.simulate_model(m, rec)
        cmp = rig_comparison.compare(rec, sim, thr, side=side)
        print(f"limit {lim:5.2f} N m: {describe(sim, cmp.simulated, thr, np.ones(len(sim), bool))}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
