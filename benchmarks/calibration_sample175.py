"""The Bayesian calibration's target on sample 175 (issue 35): a posterior and the law families'
probabilities from at least 1e5 simulations, and the posterior predictive intervals against the
held-out half.

    PYTHONPATH=python python3 benchmarks/calibration_sample175.py [--simulations 100000] \
        [--population 1000] [--window 0:20] [--heldout 20:40] [--seed 0] [--out results/calibration175]

Runs :func:`drillpy.reports.calibration.calibrate_to_folder` (what ``drillpy calibrate`` runs) and
prints the wall time and simulations per second measured in this run, the model probabilities
with their Monte Carlo standard errors, every parameter's median and 90 % interval, and each
statistic's predictive interval against its measured value on the held-out window. Every number
of docs/calibration.md, "Sample 175", is printed by this script. The machine is shared: read the
rate, not the time, as the engine's.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
if any((REPO / "python" / "drillpy").glob("_core*.so")):  # in-tree build, else the installed drillpy
    sys.path.insert(0, str(REPO / "python"))
SAMPLE175 = REPO.parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"


def _window(text: str) -> tuple:
    a, b = (float(x) for x in text.split(":"))
    return a, b


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--record", default=str(SAMPLE175))
    ap.add_argument("--simulations", type=int, default=100000)
    ap.add_argument("--population", type=int, default=1000)
    ap.add_argument("--generations", type=int, default=40)
    ap.add_argument("--window", type=_window, default=(0.0, 20.0))
    ap.add_argument("--heldout", type=_window, default=(20.0, 40.0))
    ap.add_argument("--draws", type=int, default=200)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--out", default=str(REPO / "results" / "calibration175"))
    a = ap.parse_args()
    from drillpy.reports.calibration import calibrate_to_folder, summary_lines
    t0 = time.perf_counter()
    s = calibrate_to_folder(a.record, a.out, preset="thesis-rig", t0=a.window[0], t1=a.window[1], heldout=a.heldout,
                            population=a.population, max_simulations=a.simulations, max_generations=a.generations,
                            predictive_draws=a.draws, seed=a.seed, threads=a.threads,
                            log=lambda line: print(f"[{time.perf_counter() - t0:7.0f} s] {line}", flush=True))
    wall = time.perf_counter() - t0
    print(f"\nsample 175, calibrated on {a.window[0]:g}-{a.window[1]:g} s, held out {a.heldout[0]:g}-{a.heldout[1]:g} s; "
          f"with the {a.draws} predictive draws, the whole run {wall:.0f} s")
    print("\n".join(summary_lines(s)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
