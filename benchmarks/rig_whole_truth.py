"""The rig modelled whole on the independent whole-rig truth (benchmarks/whole_rig.py), not on its own model.

    PYTHONPATH=python python3 benchmarks/rig_whole_truth.py [--seed 5] [--duration 24] [--rig-fix NAME=VALUE|free]
        [--law-platform ZETA] [--horizon-weight W] [--horizon-channels loop|all]

Writes a record of the whole-rig truth (no jack steps, so no stall), calibrates ``rig_calibration.calibrate_rig``
(default budget) on its first half with the law identified there, predicts the second half, and prints
each metric measured / predicted, the short-horizon E of both halves (the truth has no acquisition skew:
its records are read as recorded) and the calibrated parameters next to the truth's. About 40 s.
The figures of docs/records.md section 3 on the independent truth come from this script.
"""
from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
if any((REPO / "python" / "drillpy").glob("_core*.so")):  # in-tree build, else the installed drillpy
    sys.path.insert(0, str(REPO / "python"))
sys.path.insert(0, str(REPO / "benchmarks"))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=5)
    ap.add_argument("--duration", type=float, default=24.0)
    ap.add_argument("--rig-fix", action="append", default=[], metavar="NAME=VALUE",
                    help="hold a rig parameter at VALUE (or NAME=free: calibrate one held by default)")
    ap.add_argument("--law-platform", type=float, default=None, metavar="ZETA",
                    help="identify the law with the speed and the WOB through the 20 Hz platform of this damping")
    ap.add_argument("--horizon-weight", type=float, default=1.0, metavar="W",
                    help="the calibration part's short-horizon E beside the long-run mismatch (0: the metrics alone)")
    ap.add_argument("--horizon-channels", default="loop", choices=("loop", "all"),
                    help="the objective's short-horizon channels: all (the WOB beside the others) or loop (without it)")
    a = ap.parse_args()
    import numpy as np
    from drillpy.loop.prediction import short_horizon_error
    import whole_rig
    from drillpy.records import identification as ident
    from drillpy.records import rigsim
    from drillpy.records import rig_calibration
    from drillpy.records import rig_comparison
    from drillpy.records import signals as sig
    from drillpy.records.cleaning import clean
    from drillpy.records.io import read_record
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "truth.mat"
        whole_rig.write_mat(whole_rig.simulate({"jack_steps": []}, duration=a.duration, seed=a.seed), str(path))
        rec, _ = clean(read_record(path))
    thr = rigsim.stick_threshold(rec)
    h = 0.5 * a.duration
    cal, hold = rec.select(0.0, h), rec.select(h + rec.dt, a.duration)
    cyc = sig.segment_cycles(cal.bit_speed, cal.dt, thr, valid=cal.valid())
    d = ident.FitData.from_arrays(cal.bit_speed, sig.derivative(cal.bit_speed, cal.dt), cal.torque_on_bit,
                                  cyc.branch_labels(len(cal)), cyc.cycle_id(len(cal)), wob=cal.wob, every=10,
                                  cycles=cyc, platform=None if a.law_platform is None else (1 / cal.dt, 20.0, a.law_platform))
    fixed = dict(rig_calibration.DEFAULT_FIXED)
    for it in a.rig_fix:
        name, _, val = it.partition("=")
        if val == "free":
            fixed.pop(name, None)
        else:
            fixed[name] = float(val)
    law = ident.fit_law("polynomial", d).law
    speeds = np.array([1.0, 2.0, 4.0, 8.0, 12.0, 18.0])
    p = whole_rig.DEFAULTS
    truth = [law["wob_ref_n"] * p["r_b"] * whole_rig.mu_kinetic(v, p) for v in speeds]
    print("law at the reference WOB %.1f N, T [N m] at %s rad/s: identified %s, the truth's kinetic %s" % (
        law["wob_ref_n"], " ".join(f"{v:g}" for v in speeds),
        " ".join(f"{x:.3f}" for x in ident.law_eval(law, speeds, 0.0, law["wob_ref_n"])[0]),
        " ".join(f"{x:.3f}" for x in truth)))
    c = rig_calibration.calibrate_rig(cal, law, thr, fixed=fixed, horizon_error=short_horizon_error,
                                      horizon_weight=a.horizon_weight, horizon_channels=a.horizon_channels)
    sim = rigsim.simulate_model(c.model, hold)
    pred = rig_comparison.compare(hold, sim, thr)
    e_cal = short_horizon_error(c.model, cal, c.model.command_rad_s)
    e_val = short_horizon_error(c.model, hold, sim.provenance["command_rad_s"])
    w_cal = short_horizon_error(c.model, cal, c.model.command_rad_s, channels="wob")
    w_val = short_horizon_error(c.model, hold, sim.provenance["command_rad_s"], channels="wob")
    print(f"calibrated on 0-{h:g} s (horizon weight {a.horizon_weight:g}): mismatch {c.comparison.mismatch:.3f}, "
          f"short-horizon E {e_cal:.3f}, the WOB's {w_cal:.3f}; predicting {h:g}-{a.duration:g} s: short-horizon E "
          f"{e_val:.3f}, the WOB's {w_val:.3f}")
    for k in rigsim.MATCHED_RIG + ("cycle_frequency_hz",):
        m, s = pred.measured[k], pred.simulated[k]
        print(f"  {k:22s} {m:9.3f} {s:9.3f} {100 * rig_comparison.relative_error(s, m):+7.1f} %")
    print(f"identified static torque 1.36 a0 = {1.36 * law['a0']:.3f} N m at the reference WOB "
          f"{law['wob_ref_n']:.1f} N (the truth's: mu_static r_b W_ref = "
          f"{whole_rig.DEFAULTS['mu_static'] * whole_rig.DEFAULTS['r_b'] * law['wob_ref_n']:.3f} N m before ageing)")
    print("parameters (truth: c_m 0.22 N m s/rad, J_m 0.013 kg m^2, damping 0.02, platform damping 0.05):")
    for k, v in c.model.parameters().items():
        print(f"  {k:26s} {v['value']:.4g}" + (f"  FLAG: {v['flag']}" if v["flag"] else ""))


if __name__ == "__main__":
    main()
