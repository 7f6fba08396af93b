"""The rig modelled whole on sample 175: calibrated on one half, predicting the other (issue 28's targets).

    PYTHONPATH=python python3 benchmarks/rig_whole.py [--record FILE.mat] [--split 20] [--keep DIR] [--rig-fix NAME=VALUE]
        [--law-platform ZETA] [--channel-timing none|auto|LEAD,LAG] [--horizon-weight W] [--rig-search 8,400]
        [--horizon-channels loop|all] [--rig-metric NAME]

Runs ``drillpy analyze --calibrate 0:SPLIT`` and ``--calibrate SPLIT:END`` (the rig modelled whole,
``rig_calibration.calibrate_rig``: motor, jack, platform, bar and disk, its inputs the motor command and the
jack's slow WOB trend only) and prints, for each direction:

* the targets on the predicted half: SS, regular stick fraction, cycle frequency (Welch peak) and
  median period, torque p5 and p95, top-speed standard deviation, WOB standard deviation, each
  measured / predicted (relative error), the stalls of both, the short-horizon E;
* the same metrics of the calibration half itself offered as the prediction ("persistence"): how
  far the record's two halves differ by themselves, which no model driven by constants and the
  slow WOB trend can follow unless the trend explains it;
* the parameters with their 95 % intervals, physical ranges and flags;
* the predictive intervals over realizations of the model's torque fluctuation, Eq. (4.1)
  (``records.rig_fluctuation``), and which measured metrics lie in them.

About 2 x 70 s on the shared 2-core machine (2 x 5 min with `--rig-search 8,400`). Every number of docs/records.md section 4 comes from this script.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
SAMPLE175 = REPO.parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"
KEYS = ("ss", "stick_fraction", "cycle_frequency_hz", "median_period_s", "torque_p5", "torque_p95",
        "top_speed_std", "wob_std", "mean_top_speed")


def analyze(record: str, t0: float, t1: float, out: Path, fix=(), extra=()) -> dict:
    """``drillpy analyze --calibrate T0:T1`` into ``out`` (``fix``: its ``--rig-fix`` options, ``extra``: more
    options); its summary.json."""
    cmd = [sys.executable, "-m", "drillpy", "analyze", record, "--calibrate", f"{t0:g}:{t1:g}", "--out", str(out)]
    cmd += [x for f in fix for x in ("--rig-fix", f)] + list(extra)
    import os
    # the in-tree build when there is one, else the installed drillpy
    env = {"PYTHONPATH": str(REPO / "python")} if any((REPO / "python" / "drillpy").glob("_core*.so")) else {}
    subprocess.run(cmd, check=True, env={**os.environ, **env}, stdout=subprocess.DEVNULL)
    return json.loads((out / "summary.json").read_text())


#: Bit speeds [rad/s] at which the identified law is printed (its falling branch in slip).
LAW_SPEEDS = (1.0, 2.0, 4.0, 8.0, 12.0, 18.0)


def law_torques(law: dict) -> list:
    """The law's torque [N m] at :data:`LAW_SPEEDS` and its reference WOB (the engine's evaluation)."""
    sys.path.insert(0, str(REPO / "python"))
    from drillpy.records.identification import law_eval
    return list(law_eval(law, list(LAW_SPEEDS), 0.0, law["wob_ref_n"])[0])


def stall_torques(record: str, stalls: dict, params: dict, window: tuple) -> str:
    """The torques a stall is made of: the measured torque and top speed during each measured stall (the
    motor held at rest), the whole-rig model's stall torque c_m Omega_c, and the one the calibration
    half's droop line gives (``rig_calibration.droop_estimate``: known beforehand)."""
    import numpy as np
    from drillpy.records.cleaning import clean
    from drillpy.records.io import read_record
    from drillpy.records.rig_calibration import droop_estimate
    rec = clean(read_record(record))[0]
    om0, cm0 = droop_estimate(rec.select(*window))
    parts = []
    for t0, d in zip(stalls["starts_s"], stalls["durations_s"]):
        k = (rec.time_s >= t0) & (rec.time_s <= t0 + d)
        top = np.where(rec.valid("top_speed"), rec.top_speed, np.nan)[k]
        parts.append(f"at {t0:.2f} s the torque {np.nanmean(rec.torque_on_bit[k]):.2f} N m with the top speed "
                     f"{np.nanmean(top):.2f} rad/s, the WOB {np.nanmean(rec.wob[k]):.0f} N")
    model = params["motor_slope_nms_rad"]["value"] * params["command_rad_s"]["value"]
    return (f"stall torque: model c_m Omega_c {model:.2f} N m; the calibration half's droop line "
            f"{om0 * cm0:.2f} N m" + ("; measured stall " + "; ".join(parts) if parts else ""))


def rel(a: float, b: float) -> str:
    return f"{100 * (a - b) / abs(b):+.1f} %" if b else "n/a"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--record", default=str(SAMPLE175))
    ap.add_argument("--split", type=float, default=20.0)
    ap.add_argument("--end", type=float, default=40.0)
    ap.add_argument("--rig-fix", action="append", default=[], metavar="NAME=VALUE",
                    help="passed to drillpy analyze: hold a rig parameter instead of calibrating it")
    ap.add_argument("--law-platform", type=float, default=None, metavar="ZETA",
                    help="passed to drillpy analyze: identify the law with the speed and the WOB through the platform")
    ap.add_argument("--channel-timing", default="auto", metavar="none|auto|LEAD,LAG",
                    help="drillpy analyze's --channel-timing: the channels' timing the short-horizon E reads the records at")
    ap.add_argument("--horizon-weight", default="1", metavar="W",
                    help="drillpy analyze's --horizon-weight: the calibration part's short-horizon E beside the long-run "
                         "mismatch (0: the long-run metrics alone)")
    ap.add_argument("--horizon-channels", default="loop", choices=("loop", "all"),
                    help="drillpy analyze's --horizon-channels: the short-horizon error's channels (all: the WOB too)")
    ap.add_argument("--rig-search", default="4,200", metavar="STARTS,EVALUATIONS",
                    help="drillpy analyze's --rig-search: the rig calibration's starts and simulations per start")
    ap.add_argument("--rig-metric", action="append", default=[], metavar="NAME",
                    help="drillpy analyze's --rig-metric (repeatable): a metric matched beside the defaults, e.g. "
                         "block_stick_min")
    ap.add_argument("--keep", default=None, help="write the two analyses into DIR/calT0 (kept) instead of a temporary directory")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        if a.keep:
            tmp = a.keep
            Path(tmp).mkdir(parents=True, exist_ok=True)
        for (c0, c1) in ((0.0, a.split), (a.split, a.end)):
            extra = ([] if a.law_platform is None else ["--law-platform", f"{a.law_platform:g}"]) + [
                "--channel-timing", a.channel_timing, "--horizon-weight", a.horizon_weight,
                "--rig-search", a.rig_search, "--horizon-channels", a.horizon_channels] + [
                x for m in a.rig_metric for x in ("--rig-metric", m)]
            S = analyze(a.record, c0, c1, Path(tmp) / f"cal{c0:g}", a.rig_fix, extra)
            rg = S["rig"]
            cal = rg["calibration_metrics"]
            e_cal = rg["calibration"].get("short_horizon_error")
            print(f"\n== calibrated on {c0:g}-{c1:g} s (mismatch {rg['calibration']['mismatch']:.3f}"
                  + (f", short-horizon E {e_cal:.3f} at weight {rg['calibration']['horizon_weight']:g}" if e_cal else "")
                  + (f", the WOB's {rg['calibration']['wob_horizon_error']:.3f}"
                     if rg["calibration"].get("wob_horizon_error") is not None else "")
                  + ") ==")
            law = rg["recommended"]["law"]
            print(f"  law {rg['recommended']['law_name']} at its reference WOB {law['wob_ref_n']:.1f} N, T [N m] at "
                  + ", ".join(f"{v:g}" for v in LAW_SPEEDS) + " rad/s: "
                  + " ".join(f"{x:.3f}" for x in law_torques(law)))
            for h in rg["held_out"]:
                if "skipped" in h:
                    print(f"  {h['window_s']}: not predicted: {h['skipped']}")
                    continue
                m = h["metrics"]
                print(f"  predicting {h['window_s'][0]:.1f}-{h['window_s'][1]:.1f} s: short-horizon E "
                      f"{h['short_horizon_error']:.3f}" + (f", the WOB's {h['wob_horizon_error']:.3f}" if "wob_horizon_error"
                                                            in h else "") + f", long-run mismatch {h['mismatch']:.3f}")
                print(f"  {'metric':22s} {'measured':>9s} {'predicted':>10s} {'error':>9s}   "
                      f"{'persistence':>11s} {'error':>9s}")
                within = 0
                for k in KEYS:
                    mk, sk, pk = m[k]["measured"], m[k]["simulated"], cal[k]["measured"]
                    within += k not in ("median_period_s", "mean_top_speed") and abs(sk - mk) <= 0.1 * abs(mk)
                    print(f"  {k:22s} {mk:9.3f} {sk:10.3f} {rel(sk, mk):>9s}   {pk:11.3f} {rel(pk, mk):>9s}")
                st = m["stalls"]
                print(f"  stalls: measured {st['measured']['count']} {st['measured']['durations_s']}, "
                      f"predicted {st['simulated']['count']} {st['simulated']['durations_s']}")
                print("  " + stall_torques(a.record, st["measured"], rg["parameters"], (c0, c1)))
                print(f"  targets within 10 %: {within} of 7")
                iv = h.get("predictive")
                if iv:
                    fl = rg["torque_fluctuation"]
                    print(f"  with Eq. (4.1)'s torque fluctuation (std {fl['std']:.3f}: eta_exp {fl['record_eta_std']:.3f} "
                          f"measured, {fl['model_eta_std']:.3f} the deterministic model's own), {iv['realizations']} "
                          f"realizations: {iv['inside']} of {iv['of']} measured metrics inside their "
                          f"{100 * iv['level']:.0f} % predictive intervals")
                    for k, v in iv["metrics"].items():
                        print(f"    {k:22s} [{v['interval'][0]:9.4g}, {v['interval'][1]:9.4g}] measured {v['measured']:9.4g}"
                              + ("" if v["inside"] else "  outside"))
            print("  parameters (value, 95 % interval, range, flag):")
            for k, v in rg["parameters"].items():
                ci = "n/a" if v["ci95"] is None else f"[{v['ci95'][0]:.4g}, {v['ci95'][1]:.4g}]"
                print(f"    {k:22s} {v['value']:10.4g} {ci:24s} [{v['range'][0]:g}, {v['range'][1]:g}] {v['unit']}"
                      + (f"  FLAG: {v['flag']}" if v["flag"] else ""))
            if rg.get("cycle_margin"):
                from drillpy.records.cycle_margin import margin_lines
                for line in margin_lines(rg["cycle_margin"]):
                    print(f"  cycle margin: {line}")
            diag = next((c for c in rg["cases"] if c["drive"] == "measured"), None)
            if diag:
                print(f"  diagnosis (measured top speed fed in): damping ratio {diag['damping_ratio']:.3g}, "
                      f"mismatch {diag['mismatch']:.3f} on the calibration part")


if __name__ == "__main__":
    main()
