"""Does the record chain (platform and 10 Hz filter) flatten the identified law's falling branch?

    PYTHONPATH=python python3 benchmarks/rig_law_chain.py MODEL.json [--record FILE.mat] [--t0 0 --t1 20]

MODEL.json is ``drillpy analyze --calibrate T0:T1``'s rig model. Prints, with the law's torque at a few
bit speeds and its slope between 2 and 12 rad/s (the falling branch in slip):

1. on the model's own simulation of the window, whose law is known: the law identified (polynomial,
   Eq. 5.1, torque scaled by the WOB, as ``drillpy analyze``) from the contact torque and the raw speed,
   from the channels after the record chain (torque through the platform and the filter, speed and WOB
   through the filter), after the filter only, and after the chain with the speed and the WOB brought
   through the same platform (``FitData.from_arrays(platform=...)``, ``drillpy analyze --law-platform``);
   and the pure delay of the torque that fits best;
2. on the record: the same identification as measured and with the speed and the WOB through the
   platform at several damping ratios (the fit's RMSE says which the record prefers), and the pure
   delay of the torque (and WOB) that fits best;
3. a harder cycle: the preset rig under a constant top speed of 8.5 rad/s, damping ratio 0.05, a law
   falling linearly by 0.06 N m per rad/s (static torque 3.1 N m, 2.6 N m at rest in slip), sticking
   about a third of the time; its torque through the platform (damping 0.75) and the filter, as 1.

About 20 s.
"""
from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from drillpy.loop.prediction import load_model
from drillpy.records import identification as ident
from drillpy.records import rigsim
from drillpy.records import signals as sig
from drillpy.records.cleaning import clean
from drillpy.records.io import read_record

SAMPLE175 = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"
SPEEDS = np.array([1.0, 2.0, 4.0, 8.0, 12.0, 18.0])


def fill(x) -> np.ndarray:
    """``x`` with its non-finite samples bridged linearly."""
    x = np.asarray(x, float)
    ok = np.isfinite(x)
    i = np.arange(x.size)
    return np.interp(i, i[ok], x[ok]) if not ok.all() else x


def shifted(x, n: int) -> np.ndarray:
    """``x(t + n dt)``, the ends held."""
    return np.r_[x[n:], np.full(n, x[-1])] if n > 0 else (np.r_[np.full(-n, x[0]), x[:n]] if n < 0 else x)


def identify(v, tq, wob, dt, thr, platform=None, start=0.0, valid=None):
    """The polynomial law identified as ``drillpy analyze`` does (WOB-scaled, 100 Hz); (law, rmse, wob_ref)."""
    k0 = int(round(start / dt))
    v, tq, wob = v[k0:], tq[k0:], wob[k0:]
    cyc = sig.segment_cycles(v, dt, thr, valid=None if valid is None else valid[k0:])
    vf = fill(v)
    d = ident.FitData.from_arrays(v, sig.derivative(vf, dt), tq, cyc.branch_labels(v.size), cyc.cycle_id(v.size),
                                  wob=fill(wob), use_wob=True, every=max(1, int(round(0.01 / dt))), cycles=cyc,
                                  platform=platform)
    f = ident.fit_law("polynomial", d)
    return f.law, f.rmse, d.wob_ref


def line(label: str, law: dict, wref: float, rmse: float | None = None) -> None:
    T = ident.law_eval(law, SPEEDS, 0.0, wref)[0]
    s = (T[4] - T[1]) / 10.0
    print(f"  {label:44s} " + " ".join(f"{x:6.3f}" for x in T) + f"   {s:8.4f}" + ("" if rmse is None else f"  {rmse:.4f}"))


def header(title: str) -> None:
    print(title)
    print(f"  {'':44s} " + " ".join(f"{v:6g}" for v in SPEEDS) + "   slope 2-12  RMSE")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("model")
    ap.add_argument("--record", default=str(SAMPLE175))
    ap.add_argument("--t0", type=float, default=0.0)
    ap.add_argument("--t1", type=float, default=20.0)
    a = ap.parse_args()
    m = load_model(a.model)
    full, _ = clean(read_record(a.record))
    rec = full.select(a.t0, a.t1)
    thr = rigsim.stick_threshold(rec)
    fs = 1.0 / rec.dt
    zp = m.platform_damping

    # 1. the model's own simulation: its law is known
    sim = rigsim.simulate_model(m, rec)  # the record chain: platform and filter
    res = rigsim._run(m, rec, sim.provenance["command_rad_s"], float(np.mean(rec.wob)))
    n, vb, _, tq, w = rigsim._channels(res, rec, False, None)  # the contact torque and the raw speed
    header(f"1. the {a.t0:g}-{a.t1:g} s model's own simulation (platform damping {zp:.3g}); T [N m] at bit speeds [rad/s]:")
    law_raw, r_raw, wref = identify(vb, tq, w, rec.dt, thr, start=2.0)
    line("the model's law (the truth)", m.engine_law, wref)
    line("identified from the contact torque, raw speed", law_raw, wref, r_raw)
    iir = [sig.rig_lowpass(x, fs) for x in (vb, tq, w)]
    law, r, wr = identify(*iir, rec.dt, thr, start=2.0)
    line("after the 10 Hz filter only", law, wr, r)
    law, r, wr = identify(sim.bit_speed, sim.torque_on_bit, sim.wob, rec.dt, thr, start=2.0)
    line("after the chain, as measured", law, wr, r)
    law, r, wr = identify(sim.bit_speed, sim.torque_on_bit, sim.wob, rec.dt, thr, (fs, rigsim.PLATFORM_HZ, zp), start=2.0)
    line(f"after the chain, speed and WOB through P({zp:.2f})", law, wr, r)
    best = min((identify(sim.bit_speed, shifted(sim.torque_on_bit, int(round(L * 1e-3 * fs))), sim.wob, rec.dt, thr,
                         start=2.0)[1], L) for L in range(-10, 31, 5))
    print(f"  the torque's pure delay that fits best: {best[1]} ms (RMSE {best[0]:.4f})")

    # 2. the record
    header(f"2. the record, {a.t0:g}-{a.t1:g} s:")
    ok = rec.valid("bit_speed", "torque_on_bit")
    law, r, wr = identify(rec.bit_speed, rec.torque_on_bit, rec.wob, rec.dt, thr, valid=ok)
    line("as measured", law, wr, r)
    for z in (0.05, 0.2, 0.4, 0.75, 1.0, 1.5):
        law, r, wr = identify(rec.bit_speed, rec.torque_on_bit, rec.wob, rec.dt, thr, (fs, rigsim.PLATFORM_HZ, z),
                              valid=ok)
        line(f"speed and WOB through P({z:.2f})", law, wr, r)
    for both in (False, True):
        rows = []
        for L in range(-10, 31, 5):
            k = int(round(L * 1e-3 * fs))
            rows.append((identify(rec.bit_speed, shifted(rec.torque_on_bit, k), shifted(rec.wob, k) if both else rec.wob,
                                  rec.dt, thr, valid=ok)[1], L))
        print(f"  the torque's pure delay that fits best{' (the WOB delayed alike)' if both else ''}: {min(rows)[1]} ms "
              f"(RMSE " + ", ".join(f"{L} ms {e:.4f}" for e, L in rows) + ")")

    # 3. a cycle that sticks a third of the time
    from drillpy.model.simulation import simulate
    a5 = -0.06 / 1.36 / (60 / (2 * np.pi))
    law = {"type": "polynomial", "speed_unit": "rpm", "wob_ref_n": 500.0, "a0": 3.1 / 1.36, "a1": 0.0,
           "a2": 2.6 / 1.36, "a3": 0.0, "a4": 2.6 / 1.36, "a5": a5, "a6": 0.0, "a7": 0.0, "ref_speed": 90.0,
           "gain": 1.36}
    cfg = rigsim.rig_config(law, 0.05, duration_s=14.0, top_speed=8.5)
    cfg["simulation"]["dt_s"], cfg["simulation"]["output_stride"] = 5e-5, 20
    r = simulate(cfg)
    dt = float(r.t[1] - r.t[0])
    W = np.full(r.t.size, 500.0)
    th = 0.05 * 8.5
    vf = sig.rig_lowpass(r.bit_speed, 1 / dt)
    Tf = sig.rig_lowpass(sig.platform_response(r.torque_on_bit, 1 / dt, rigsim.PLATFORM_HZ, 0.75), 1 / dt)
    header(f"3. a cycle that sticks a third of the time (stick fraction {np.mean(vf[r.t >= 2] <= th):.2f}, known law):")
    line("the law (the truth)", law, 500.0)
    for label, v, tq, pl in (("identified from the contact torque, raw speed", r.bit_speed, r.torque_on_bit, None),
                             ("after the 10 Hz filter only", vf, sig.rig_lowpass(r.torque_on_bit, 1 / dt), None),
                             ("after the chain, as measured", vf, Tf, None),
                             ("after the chain, speed and WOB through P(0.75)", vf, Tf,
                              (1 / dt, rigsim.PLATFORM_HZ, 0.75))):
        law_i, rm, wr = identify(v, tq, W, dt, th, pl, start=2.0)
        line(label, law_i, wr, rm)


if __name__ == "__main__":
    main()
