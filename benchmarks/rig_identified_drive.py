"""The rig model with its drive read off the record's bit equation and its stochastic torque at the
record's level (issue 28), against the model ``drillpy analyze`` calibrates, on the calibration window
and the held-out one.

    PYTHONPATH=python python3 benchmarks/rig_identified_drive.py DIR/model.json [--t0 0 --t1 20] [--realizations 5]
        [--levels 0.2,0.25,0.3]

DIR from ``drillpy analyze ../shared/data/testrig/sample175_0-40s.mat --calibrate 0:20 --out DIR``. From
analyze's model it keeps the law, the jack, the platform, the bar's GJ and the disk; it replaces:

* the drive: c_m and J_m of ``bit_balance.summary`` on the calibration window (the channel timing that
  balances the bit's equation at the cycle's frequency, docs/records.md section 4), the coupling rigid
  (300 N m/rad, the top of the range), and the command on the record's droop line through its means,
  Omega_c = mean top speed + mean torque / c_m;
* the damping: a steel bar's modal damping ratio, 0.01;
* the stochastic torque of Eq. (4.1): analyze's PSD shape, its level set so that eta_exp (Eq. 4.2)
  measured on the model's simulation, the record's way, equals the record's (bisection on one
  realization: eta_exp sees the fluctuation through the 10 Hz filter and the cycle).

Prints the identified values, then per window every long-run metric: measured, the range over
``--realizations`` realizations of the fluctuation, and analyze's deterministic model; and the
mismatches. About 2 minutes.
"""
from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import numpy as np

from drillpy.loop.prediction import load_model
from drillpy.model.config import load_config
from drillpy.records import bit_balance, rig_comparison, rig_fluctuation, rigsim
from drillpy.records.analysis import AnalysisOptions, compute_analysis
from drillpy.records.cleaning import clean
from drillpy.records.io import read_record

SAMPLE175 = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"
KEYS = rigsim.MATCHED_RIG
#: A steel bar's modal damping ratio (docs/loop.md: a bar's stays below 0.1; 0.01 is a welded or clamped bar's).
STEEL_DAMPING = 0.01


def eta_exp_std(sim) -> float:
    """eta_exp's standard deviation measured on a simulated record as ``drillpy analyze`` measures the record's."""
    own = compute_analysis(sim, AnalysisOptions(simulate=False, folds=0, laws=("polynomial",)), log=lambda *_: None)
    return float(own.eta.statistics()["std"])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("model")
    ap.add_argument("--record", default=str(SAMPLE175))
    ap.add_argument("--t0", type=float, default=0.0)
    ap.add_argument("--t1", type=float, default=20.0)
    ap.add_argument("--realizations", type=int, default=5)
    ap.add_argument("--levels", default="", metavar="S1,S2,...",
                    help="also print eta_exp on the model's simulation (seed 0) at these levels of Eq. (4.1)")
    a = ap.parse_args()
    m0 = load_model(a.model)
    if not m0.torque_fluctuation:
        raise SystemExit(f"{a.model}: no torque_fluctuation (its PSD shape is needed)")
    full = read_record(a.record)
    cal, _ = clean(full.select(a.t0, a.t1))
    ok = rigsim.reliable_top_speed(cal)
    bal = bit_balance.summary(cal, load_config(preset=m0.preset), valid=ok)["best"]
    cm, jm = bal["motor_slope"], max(bal["motor_inertia"], rigsim.RIG_PARAMETERS["motor_inertia_kg_m2"][0])
    command = float(np.mean(cal.top_speed[ok]) + np.nanmean(cal.torque_on_bit) / cm)
    m = dataclasses.replace(m0, motor_slope_nms_rad=cm, motor_inertia_kg_m2=jm, coupling_stiffness_nm_rad=300.0,
                            command_rad_s=command, damping_ratio=STEEL_DAMPING)
    span = float(cal.time_s[-1] - cal.time_s[0]) + 1.0
    shape = rig_fluctuation.realization(m.torque_fluctuation, cal.dt, span, seed=0)
    target = eta_exp_std(cal)
    lo, hi = 0.05, 0.6
    for _ in range(7):  # eta_exp grows with the level: bisection
        mid = 0.5 * (lo + hi)
        sim = rigsim.simulate_model(m, cal, eta=shape * (mid / np.std(shape)))
        lo, hi = (mid, hi) if eta_exp_std(sim) < target else (lo, mid)
    level = 0.5 * (lo + hi)
    for lv in (float(x) for x in a.levels.split(",") if x.strip()):
        sim = rigsim.simulate_model(m, cal, eta=shape * (lv / np.std(shape)))
        print(f"Eq. (4.1) at {lv:g}: eta_exp {eta_exp_std(sim):.3f} on the model's simulation")
    print(f"drive from the bit's equation ({1e3 * bal['top_lead_s']:.0f} ms top lead, {1e3 * bal['torque_lag_s']:.0f} ms "
          f"torque lag): c_m {cm:.3f} N m s/rad, J_m {jm:.4f} kg m^2, command {command:.2f} rad/s; damping ratio "
          f"{STEEL_DAMPING}; Eq. (4.1) level {level:.3f} (eta_exp {target:.3f} on the record)")
    tol = 2.0 * full.dt  # the record's last sample is one interval before its nominal end
    windows = [(a.t0, a.t1)] + [(s, s + (a.t1 - a.t0)) for s in (a.t1, a.t0 - (a.t1 - a.t0))
                                if s >= full.time_s[0] - tol and s + (a.t1 - a.t0) <= full.time_s[-1] + tol]
    for t0, t1 in windows:
        rec, _ = clean(full.select(t0, t1))
        thr = rigsim.stick_threshold(rec)
        span = float(rec.time_s[-1] - rec.time_s[0]) + 1.0
        runs = []
        for seed in range(a.realizations):
            eta = rig_fluctuation.realization(m.torque_fluctuation, rec.dt, span, seed=seed)
            runs.append(rig_comparison.compare(rec, rigsim.simulate_model(m, rec, eta=eta * (level / np.std(eta))), thr))
        ref = rig_comparison.compare(rec, rigsim.simulate_model(m0, rec), thr)
        label = "calibration" if (t0, t1) == (a.t0, a.t1) else "held out"
        print(f"{t0:g}-{t1:g} s ({label}): metric, measured, identified drive ({a.realizations} realizations), analyze's model")
        for k in KEYS:
            v = [r.simulated[k] for r in runs]
            print(f"  {k:>16} {ref.measured[k]:8.3f}  [{min(v):7.3f}, {max(v):7.3f}]  {ref.simulated[k]:8.3f}")
        mis = [r.mismatch for r in runs]
        print(f"  {'mismatch':>16} {'':8s}  [{min(mis):7.3f}, {max(mis):7.3f}]  {ref.mismatch:8.3f}")


if __name__ == "__main__":
    main()
