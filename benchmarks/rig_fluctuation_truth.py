"""Eq. (4.1)'s torque fluctuation in the rig model, identified on records of the independent whole-rig truth.

    PYTHONPATH=python python3 benchmarks/rig_fluctuation_truth.py [--sd 0,0.05,0.1,0.2] [--tau 0.01,0.1] [--seed 5]

For each truth torque fluctuation (benchmarks/whole_rig.py's ``eta``: an Ornstein-Uhlenbeck process of
standard deviation ``eta_sd`` and correlation time ``eta_tau`` multiplying its Stribeck contact torque;
no jack steps), writes a 40 s record, runs ``drillpy analyze --calibrate 0:20`` on it and prints
what the rig model identified (``rig.torque_fluctuation``: eta_exp's standard deviation on the record,
on the deterministic model's own simulation, the stochastic part left) and how many of the held-out
20-40 s metrics lie in their 90 % predictive intervals. The truth's law, structure and sensors differ
from the model's (ten segments, Stribeck with ageing, a one-way load cell, quantized encoders, noise),
so the identified level is not expected to equal eta_sd: it should grow with it, and be small
without it. About 80 s per record.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "benchmarks"))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sd", default="0,0.05,0.1,0.2", help="truth eta_sd values, comma-separated")
    ap.add_argument("--tau", default="0.01", help="truth eta_tau values [s], comma-separated")
    ap.add_argument("--seed", type=int, default=5)
    a = ap.parse_args()
    import whole_rig
    env = {**os.environ, "PYTHONPATH": str(REPO / "python")} if any((REPO / "python" / "drillpy").glob("_core*.so")) \
        else dict(os.environ)
    print(f"{'eta_sd':>7s} {'eta_tau':>8s} {'record':>8s} {'model':>8s} {'identified':>10s}  held-out inside 90 %")
    with tempfile.TemporaryDirectory() as tmp:
        for tau in (float(x) for x in a.tau.split(",")):
            for sd in (float(x) for x in a.sd.split(",")):
                path = Path(tmp) / f"truth_{sd:g}_{tau:g}.mat"
                res = whole_rig.simulate({"jack_steps": [], "eta_sd": sd, "eta_tau": tau}, duration=40.0, seed=a.seed)
                whole_rig.write_mat(res, str(path))
                out = Path(tmp) / f"an_{sd:g}_{tau:g}"
                subprocess.run([sys.executable, "-m", "drillpy", "analyze", str(path), "--calibrate", "0:20",
                                "--out", str(out)], check=True, env=env, stdout=subprocess.DEVNULL)
                rig = json.loads((out / "summary.json").read_text())["rig"]
                fl, es = rig.get("torque_fluctuation") or {}, rig.get("eta_exp_std", {})
                held = [h for h in rig["held_out"] if "predictive" in h]
                iv = held[0]["predictive"] if held else None
                print(f"{sd:7.3f} {tau:8.3f} {es.get('record', float('nan')):8.3f} "
                      f"{es.get('model', float('nan')):8.3f} {fl.get('std', 0.0):10.3f}  "
                      + (f"{iv['inside']} of {iv['of']}" if iv else "none (no stochastic part left)"), flush=True)


if __name__ == "__main__":
    main()
