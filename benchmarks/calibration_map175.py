"""The posterior stability map of sample 175 (issue 35, item 3): P(SS > 0.5) over the motor command x
WOB from a calibration's posterior and the stochastic law of chapter 4, in one Monte Carlo.

    PYTHONPATH=python python3 benchmarks/calibration_map175.py [--posterior results/calibration175/posterior.json] \
        [--speeds 6:30:7] [--wobs 400:800:5] [--samples 40] [--seed 0] [--out results/calibration175/map.zarr]

Runs :func:`drillpy.calibration.stability.stability_map` on the posterior that
``benchmarks/calibration_sample175.py`` writes, stores the map in Zarr and prints P(SS > 0.5, a stall
counted as unstable) per cell with its Wilson 90 % interval, P(stall), the wall time and the runs per
second.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
if any((REPO / "python" / "drillpy").glob("_core*.so")):  # in-tree build, else the installed drillpy
    sys.path.insert(0, str(REPO / "python"))


def _grid(text: str) -> np.ndarray:
    a, b, n = text.split(":")
    return np.linspace(float(a), float(b), int(n))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--posterior", default=str(REPO / "results" / "calibration175" / "posterior.json"))
    ap.add_argument("--speeds", type=_grid, default=_grid("6:30:7"), help="motor commands A:B:N [rad/s]")
    ap.add_argument("--wobs", type=_grid, default=_grid("400:800:5"), help="WOB A:B:N [N]")
    ap.add_argument("--samples", type=int, default=40)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--out", default=None, help="Zarr store (default: map.zarr beside the posterior)")
    a = ap.parse_args()
    from drillpy.calibration.stability import stability_map
    t0 = time.perf_counter()
    m = stability_map(a.posterior, a.speeds, a.wobs, samples=a.samples, seed=a.seed, threads=a.threads)
    wall = time.perf_counter() - t0
    out = m.save(a.out or Path(a.posterior).with_name("map.zarr"))
    runs = m.severity.size
    print(f"{runs} runs ({a.samples} samples x {a.wobs.size} WOB x {a.speeds.size} commands, "
          f"{m.settings['duration_s']:g} s each) in {wall:.0f} s, {runs / wall:.0f} runs per second; "
          f"{m.settings['failed_runs']} failed; stored in {out}")
    print("samples per family: " + ", ".join(f"{f} {m.families.count(f)}" for f in sorted(set(m.families))))
    print("\nP(SS > 0.5 or a stall) [Wilson 90 % interval]; rows WOB [N], columns command [rad/s]")
    print("| WOB \\ command | " + " | ".join(f"{s:g}" for s in a.speeds) + " |")
    print("|---" * (a.speeds.size + 1) + "|")
    for i, w in enumerate(a.wobs):
        print(f"| {w:g} | " + " | ".join(f"{m.p_unstable[i, j]:.2f} [{m.ci90[0, i, j]:.2f}, {m.ci90[1, i, j]:.2f}]"
                                         for j in range(a.speeds.size)) + " |")
    print("\nP(stall)")
    print("| WOB \\ command | " + " | ".join(f"{s:g}" for s in a.speeds) + " |")
    print("|---" * (a.speeds.size + 1) + "|")
    for i, w in enumerate(a.wobs):
        print(f"| {w:g} | " + " | ".join(f"{m.p_stall[i, j]:.2f}" for j in range(a.speeds.size)) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
