"""Is the rig model's stick-slip marginal because its static torque is too low? Three diagnostics of a model.

    PYTHONPATH=python python3 benchmarks/rig_static_torque.py MODEL.json [--t0 0 --t1 20] [--factors 1,1.05,1.1,1.2,1.3]

MODEL.json is ``drillpy analyze --calibrate T0:T1``'s model (the rig modelled whole) and T0-T1 its calibration
window of sample 175. Prints

1. what the record chain does to the break-away peak on the model's own simulation: the break-away torques
   (``identification.breakaway_torques``, scaled to the law's reference WOB) of the contact torque, of the
   platform's reading through the 10 Hz filter (what the record shows; the static torque is identified from it)
   and of the contact torque through the filter alone; their ratio is the factor the identified static torque
   would need (``static_torque_factor``);
2. the bit's stick fraction per 2 s of the record and of the model, beside the record's WOB trend (the
   model's input): where each sticks;
3. the model's static torque times each factor, alone and with the motor inertia 5 % and 20 % lower and the
   bit inertia 25 % higher (``benchmarks/rig_sensitivity.py``'s moves that stop the cycle): does a higher
   static torque keep the cycle?

A few seconds. The figures of docs/records.md section 4 ("The static torque") come from this script.
"""
from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import numpy as np

from drillpy.loop.prediction import load_model
from drillpy.records import identification as ident
from drillpy.records import rig_comparison, rigsim
from drillpy.records import signals as sig
from drillpy.records.cleaning import clean
from drillpy.records.io import read_record

SAMPLE175 = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"
KEYS = ("ss", "stick_fraction", "cycle_frequency_hz", "torque_p5", "torque_p95", "top_speed_std")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("model")
    ap.add_argument("--record", default=str(SAMPLE175))
    ap.add_argument("--t0", type=float, default=0.0)
    ap.add_argument("--t1", type=float, default=20.0)
    ap.add_argument("--factors", default="1,1.05,1.1,1.2,1.3")
    a = ap.parse_args()
    m0 = load_model(a.model)
    rec, _ = clean(read_record(a.record).select(a.t0, a.t1))
    thr = rigsim.stick_threshold(rec)
    law, ref = m0.engine_law, m0.law["wob_ref_n"]

    # 1. the break-away peak through the record chain, on the model's own simulation
    op = rigsim.operating_point(rec)
    res = rigsim._run(m0, rec, m0.command_rad_s, op["wob_n"])
    fs = 1.0 / float(np.median(np.diff(res.t)))
    keep = res.t >= 2.0

    def lp(x):
        return sig.rig_lowpass(x, fs)[keep]

    read = sig.platform_response(res.torque_on_bit, fs, rigsim.PLATFORM_HZ, m0.platform_damping)
    raw = sig.segment_cycles(res.bit_speed[keep], 1 / fs, thr)
    fil = sig.segment_cycles(lp(res.bit_speed), 1 / fs, thr)
    b_raw = ident.breakaway_torques(raw, res.torque_on_bit[keep], res.wob[keep], ref)
    b_rec = ident.breakaway_torques(fil, lp(read), lp(res.wob), ref)
    b_iir = ident.breakaway_torques(fil, lp(res.torque_on_bit), lp(res.wob), ref)
    print(f"static torque the engine runs 1.36 a0 = {law['gain'] * law['a0']:.3f} N m (identified "
          f"{m0.law['gain'] * m0.law['a0']:.3f} x factor {m0.static_torque_factor:g}) at W_ref {ref:.1f} N")
    print(f"break-away torques of the model's simulation, {a.t0:g}-{a.t1:g} s: contact {b_raw.mean():.3f} N m "
          f"({b_raw.size} stick phases); platform + 10 Hz filter (as recorded) {b_rec.mean():.3f} "
          f"(ratio {b_rec.mean() / b_raw.mean():.3f}: factor {b_raw.mean() / b_rec.mean():.3f}); 10 Hz filter "
          f"alone {b_iir.mean():.3f} (ratio {b_iir.mean() / b_raw.mean():.3f})")

    # 2. where the record and the model stick
    sim = rigsim.simulate_model(m0, rec)
    trend = rigsim.wob_trend(rec, op["wob_n"])
    ok = rec.valid("bit_speed")
    print("stick fraction per 2 s (raw, at or below the stick threshold %.3f rad/s), bit speed minimum [rad/s]:" % thr)
    for t in np.arange(a.t0, a.t1 - 1e-9, 2.0):
        k, ks = (rec.time_s >= t) & (rec.time_s < t + 2) & ok, (sim.time_s >= t) & (sim.time_s < t + 2)
        print(f"  {t:4.0f}-{t + 2:<4.0f} s: record {np.mean(rec.bit_speed[k] <= thr):.3f} (min {rec.bit_speed[k].min():5.2f})"
              f"  model {np.mean(sim.bit_speed[ks] <= thr):.3f} (min {sim.bit_speed[ks].min():5.2f})"
              f"  WOB trend {trend[k].mean():6.1f} N")

    # 3. a higher static torque against the moves that stop the cycle
    print(f"{'':32s}" + " ".join(f"{k[:9]:>9s}" for k in KEYS) + "  mismatch")
    for f in (float(x) for x in a.factors.split(",")):
        m = dataclasses.replace(m0, static_torque_factor=m0.static_torque_factor * f)
        for lab, mm in (("", m),
                        ("J_m x0.95", dataclasses.replace(m, motor_inertia_kg_m2=0.95 * m.motor_inertia_kg_m2)),
                        ("J_m x0.8", dataclasses.replace(m, motor_inertia_kg_m2=0.8 * m.motor_inertia_kg_m2)),
                        ("bit x1.25", dataclasses.replace(m, bit_inertia_factor=min(1.25 * m.bit_inertia_factor, 1.4)))):
            c = rig_comparison.compare(rec, rigsim.simulate_model(mm, rec), thr)
            print(f"static torque x{f:<5g} {lab:10s}" + " ".join(f"{c.simulated[k]:9.3f}" for k in KEYS)
                  + f"  {c.mismatch:8.3f}")


if __name__ == "__main__":
    main()
