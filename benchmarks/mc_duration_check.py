"""Do the Monte Carlo durations change the Fig. 4.9 statistics? (docs/stochastic.md)

Runs the same samples (same seed: the same eta realizations up to their length) with several
duration settings WARMUP,DURATION,TRANSIENT [s] and prints mean SS and P(SS > 0.5) per speed and
the 5 % speed of each. Defaults:
  100,60,20  -- drillpy's default: shared 100-s deterministic warm-up, 60 s with eta, 20 s discarded;
  0,300,200  -- Algorithm 1 literally: from rest (Eq. 2.10), eta from t = 0, 300 s, 200 s discarded.

    PYTHONPATH=python python3 benchmarks/mc_duration_check.py [--samples 100] \
        [--psd-convention two-sided-rad-s] [--settings 100,60,20 100,160,20 0,160,100 ...]
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

if any((Path(__file__).resolve().parents[1] / "python" / "drillpy").glob("_core*.so")):

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python"))  # in-tree build, else the installed drillpy

from drillpy.model.config import load_config  # noqa: E402
from drillpy.uncertainty.montecarlo import stochastic_study  # noqa: E402
from drillpy.uncertainty.process import PSD_CONVENTIONS, THESIS_PSD, convert_psd_model  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--samples", type=int, default=100)
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--psd-convention", default="one-sided-hz", choices=sorted(PSD_CONVENTIONS))
    ap.add_argument("--settings", nargs="+", default=["100,60,20", "0,300,200"],
                    help="WARMUP,DURATION,TRANSIENT in seconds, one per study")
    ap.add_argument("--threads", type=int, default=0)
    a = ap.parse_args()
    cfg = load_config(preset="thesis-field")
    psd = convert_psd_model(THESIS_PSD, a.psd_convention)
    speeds = np.linspace(6.0, 27.0, 22)
    studies = []
    for text in a.settings:
        w, d, t = (float(x) for x in text.split(","))
        t0 = time.perf_counter()
        st = stochastic_study(cfg, speeds, a.samples, a.seed, psd=psd, warmup=w, duration=d,
                              transient=t, threads=a.threads, progress=False)
        studies.append((text, st))
        print(f"{text}: {time.perf_counter() - t0:.1f} s wall")
    print(f"{a.samples} samples, seed {a.seed}, eta std {studies[0][1].eta_std:.4f} "
          f"({a.psd_convention}); columns: mean SS / P(SS > 0.5) per setting")
    print(" speed | " + " | ".join(f"{text:>15s}" for text, _ in studies))
    for k, s in enumerate(speeds):
        print(f"{s:6.1f} | " + " | ".join(f"{st.mean[k]:7.3f} {st.p_exceed[k]:7.3f}" for _, st in studies))
    ref = studies[-1][1]
    for text, st in studies:
        print(f"{text}: p05_speed_rad_s = {st.p05_speed}, deterministic threshold = "
              f"{st.deterministic_threshold}, max |mean - last| = {np.max(np.abs(st.mean - ref.mean)):.3f}, "
              f"max |P - last| = {np.max(np.abs(st.p_exceed - ref.p_exceed)):.3f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
