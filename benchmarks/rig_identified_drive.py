"""The rig model with its drive read off the record's bit equation and its stochastic torque at the
record's level (issue 28), against the model ``drillpy analyze`` calibrates, on the calibration window
and the held-out one.

    PYTHONPATH=python python3 benchmarks/rig_identified_drive.py DIR/model.json [--t0 0 --t1 20] [--realizations 5]
        [--levels 0.2,0.25,0.3]

DIR from ``drillpy analyze ../shared/data/testrig/sample175_0-40s.mat --calibrate 0:20 --out DIR``. The model
is ``drillpy.records.analysis.identified_rig_model``'s (``model_identified.json`` of the same analyze run):
from analyze's model it keeps the law, the jack, the platform, the bar's GJ and the disk; it replaces:

* the drive: c_m and J_m of ``bit_balance.summary`` on the calibration window (the channel timing that
  balances the bit's equation at the cycle's frequency, docs/records.md section 4), the coupling rigid
  (300 N m/rad, the top of the range), and the command on the record's droop line through its means,
  Omega_c = mean top speed + mean torque / c_m;
* the damping: a steel bar's modal damping ratio, 0.01;
* the stochastic torque of Eq. (4.1): analyze's PSD shape, its level set so that eta_exp (Eq. 4.2)
  measured on the model's simulation, the record's way, equals the record's (bisection on one
  realization: eta_exp sees the fluctuation through the 10 Hz filter and the cycle). The realizations
  are drawn from its PSD table as ``drillpy predict --draws`` draws them.

Prints the identified values, then per window every long-run metric: measured, the range over
``--realizations`` realizations of the fluctuation, and analyze's deterministic model; and the
mismatches. About 2 minutes.
"""
from __future__ import annotations

import argparse
from pathlib import Path


from drillpy.loop.prediction import load_model
from drillpy.model.config import load_config
from drillpy.records import bit_balance, rig_comparison, rig_fluctuation, rigsim
from drillpy.records.analysis import AnalysisOptions, compute_analysis, identified_rig_model
from drillpy.records.cleaning import clean
from drillpy.records.io import read_record

SAMPLE175 = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"
KEYS = rigsim.MATCHED_RIG


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
    full = read_record(a.record)
    cal, _ = clean(full.select(a.t0, a.t1))
    opt = AnalysisOptions(simulate=False, folds=0, laws=("polynomial",))
    psd = compute_analysis(cal, opt, log=lambda *_: None).psd_fit
    balance = bit_balance.summary(cal, load_config(preset=m0.preset), valid=rigsim.reliable_top_speed(cal))
    m = identified_rig_model(cal, m0, balance, psd, opt)
    how = m.calibration["identified"]
    d = how["drive"]
    span = float(cal.time_s[-1] - cal.time_s[0]) + 1.0
    for lv in (float(x) for x in a.levels.split(",") if x.strip()):
        tf = rig_fluctuation.identify(psd.model.as_dict(), lv, opt.psd_fmax_hz)
        sim = rigsim.simulate_model(m, cal, eta=rig_fluctuation.realization(tf, cal.dt, span, seed=0))
        print(f"Eq. (4.1) at {lv:g}: eta_exp {eta_exp_std(sim):.3f} on the model's simulation")
    print(f"drive from the bit's equation ({1e3 * d['top_lead_s']:.0f} ms top lead, {1e3 * d['torque_lag_s']:.0f} ms "
          f"torque lag): c_m {d['motor_slope_nms_rad']:.3f} N m s/rad, J_m {d['motor_inertia_kg_m2']:.4f} kg m^2, command "
          f"{m.command_rad_s:.2f} rad/s; damping ratio {m.damping_ratio}; Eq. (4.1) level "
          f"{how['torque_fluctuation_std']['value']:.3f} (eta_exp {m.torque_fluctuation['record_eta_std']:.3f} on the record)")
    tol = 2.0 * full.dt  # the record's last sample is one interval before its nominal end
    windows = [(a.t0, a.t1)] + [(s, s + (a.t1 - a.t0)) for s in (a.t1, a.t0 - (a.t1 - a.t0))
                                if s >= full.time_s[0] - tol and s + (a.t1 - a.t0) <= full.time_s[-1] + tol]
    for t0, t1 in windows:
        rec, _ = clean(full.select(t0, t1))
        thr = rigsim.stick_threshold(rec)
        span = float(rec.time_s[-1] - rec.time_s[0]) + 1.0
        runs = [rig_comparison.compare(rec, rigsim.simulate_model(m, rec, eta=rig_fluctuation.realization(
            m.torque_fluctuation, rec.dt, span, seed=0, sample=i)), thr) for i in range(a.realizations)]
        ref = rig_comparison.compare(rec, rigsim.simulate_model(m0, rec), thr)
        label = "calibration" if (t0, t1) == (a.t0, a.t1) else "held out"
        print(f"{t0:g}-{t1:g} s ({label}): metric, measured, identified ({a.realizations} realizations), analyze's model")
        for k in KEYS:
            v = [r.simulated[k] for r in runs]
            print(f"  {k:>16} {ref.measured[k]:8.3f}  [{min(v):7.3f}, {max(v):7.3f}]  {ref.simulated[k]:8.3f}")
        mis = [r.mismatch for r in runs]
        print(f"  {'mismatch':>16} {'':8s}  [{min(mis):7.3f}, {max(mis):7.3f}]  {ref.mismatch:8.3f}")


if __name__ == "__main__":
    main()
