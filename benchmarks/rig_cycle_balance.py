"""Sample 175's bit equation at the cycle's frequency (issue 28): which string, drive and channel
timing the record balances with (``drillpy.records.bit_balance``).

    PYTHONPATH=python python3 benchmarks/rig_cycle_balance.py [--record FILE] [--model DIR/model.json]

For the windows 0-20 s and 20-40 s of the cleaned record it prints

1. the channel timing that best fits the bit's equation in the time domain (``timing_fit``: the top
   encoder's lead and the torque's lag on a 10 ms grid, with k and J free), and the fit at no timing;
2. at the cycle's frequency (``cycle_balance``), for the readings: the table's bar and disk with the
   channels as recorded; the torque 30 ms late; the torque 30 ms late and the top encoder 40 ms early;
   the torque 30 ms late and the top encoder on the bar where the stiffness between the encoders is the
   one the time-domain fit gives at no top lead (the rest of the bar above it): the string damping c
   each needs (a steel bar's is about +0.01 N m s/rad, real), the drive's impedance at the motor
   (droop c_m, rotor J_m) and the cycle's energy terms;
3. with ``--model``: the same on that rig model's own simulation, whose string, drive and timing are
   known (the method's check: its drive impedance against the model's c_m + i w J_m).
"""
from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import drillpy
from drillpy.records import bit_balance, rigsim
from drillpy.records.cleaning import clean
from drillpy.records.io import read_record

SAMPLE175 = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"


def row(label: str, b: bit_balance.CycleBalance) -> str:
    c, z = b.string_damping, b.drive_at_motor
    return (f"  {label:<44} c {c.real:+.4f}{c.imag:+.4f}i   drive c_m {z.real:.3f}, J_m {b.motor_inertia:+.4f}   "
            f"feed {b.feed:.4f} = drive {b.drive_loss:.4f} + string {b.string_loss:+.4f}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--record", default=str(SAMPLE175))
    ap.add_argument("--model", help="a rig model.json of drillpy analyze: the method checked on its simulation")
    a = ap.parse_args()
    k, J = bit_balance.string_of(drillpy.load_config(preset="thesis-rig"))
    print(f"the table's bar and disk (thesis-rig preset): k {k:.3f} N m/rad, J {J:.5f} kg m^2")
    grid = np.arange(-0.06, 0.0601, 0.01)
    for t0, t1 in ((0.0, 20.0), (20.0, 40.0)):
        rec, _ = clean(read_record(a.record).select(t0, t1))
        ok = rigsim.reliable_top_speed(rec)
        fits = bit_balance.timing_fit(rec, grid, np.arange(-0.02, 0.0701, 0.01), valid=ok)
        best = fits[0]
        none = next(f for f in fits if abs(f["top_lead_s"]) < 1e-9 and abs(f["torque_lag_s"]) < 1e-9)
        lag_only = max((f for f in fits if abs(f["top_lead_s"]) < 1e-9), key=lambda f: f["r2"])
        print(f"{t0:g}-{t1:g} s, time domain (k, J free): best top lead {best['top_lead_s'] * 1e3:+.0f} ms, torque lag "
              f"{best['torque_lag_s'] * 1e3:+.0f} ms: R^2 {best['r2']:.3f}, k {best['stiffness']:.3f}, J {best['inertia']:.5f}; "
              f"no top lead: torque lag {lag_only['torque_lag_s'] * 1e3:+.0f} ms, R^2 {lag_only['r2']:.3f}, k "
              f"{lag_only['stiffness']:.3f}, J {lag_only['inertia']:.5f}; no timing: R^2 {none['r2']:.3f}, k "
              f"{none['stiffness']:.3f}, J {none['inertia']:.5f}")
        k_enc = lag_only["stiffness"]
        above = 1.0 / (1.0 / k - 1.0 / k_enc) if k_enc > k else None
        b0 = bit_balance.cycle_balance(rec, k, J, valid=ok)
        print(f"  at the cycle's frequency {b0.frequency_hz:.2f} Hz (coherence {b0.coherence:.2f}): Y {abs(b0.top):.3f} at "
              f"{np.degrees(np.angle(b0.top)):+.0f} deg, G {abs(b0.torque):.4f} N m s/rad at {np.degrees(np.angle(b0.torque)):+.0f} deg")
        print(row("the table's string, channels as recorded", b0))
        print(row("the torque 30 ms late", bit_balance.cycle_balance(rec, k, J, torque_lag_s=0.03, valid=ok)))
        print(row("the torque 30 ms late, the top 40 ms early", bit_balance.cycle_balance(
            rec, k, J, torque_lag_s=0.03, top_lead_s=0.04, valid=ok)))
        if above is not None:
            print(row(f"the torque 30 ms late, k {k_enc:.2f} below the encoder", bit_balance.cycle_balance(
                rec, k_enc, J, torque_lag_s=0.03, stiffness_above=above, valid=ok))
                  + f"   ({above:.1f} N m/rad above it: {1.7 * k / above:.2f} m of the 1.7 m bar)")
        if a.model:
            from drillpy.loop.prediction import load_model
            m = load_model(a.model)
            sim = rigsim.simulate_model(m, rec)
            km, Jm = bit_balance.string_of(m.config(float(np.mean(sim.top_speed))))
            keep = sim.time_s >= sim.time_s[0] + 2.0
            b = bit_balance.cycle_balance(sim, km, Jm, valid=keep)
            w = 2.0 * np.pi * b.frequency_hz
            true = m.motor_slope_nms_rad + 1j * w * m.motor_inertia_kg_m2
            print(row("the model's own simulation (as recorded)", b)
                  + f"   the model's c_m {true.real:.3f}, J_m {m.motor_inertia_kg_m2:.4f}, modal c "
                    f"{2 * m.damping_ratio * np.sqrt(km * Jm):.4f}")


if __name__ == "__main__":
    main()
