"""Runs in SIMD lockstep against the scalar engine, ns per step per run (issue 16), in one run.

    PYTHONPATH=python python3 benchmarks/bench_batched.py [--repeats 7] [--duration 20]

thesis-field (dt 5.12e-4 s, hysteretic law) with 10, 20, 50 and 100 retained modes: 16 top speeds
from 6 to 27 rad/s (stick-slip and smooth drilling), one thread, the SS sweep through the scalar
reference integrator (``batched=False``) and through the batched one (one run per lane of the
host's widest vector: ``_core.Simulation.batch_width()``). Repeats alternate the two paths; the
speed-up is the median of the per-repeat ratios (the machine is shared). Targets: >= 1.8 x at 20
modes, >= 1.5 x at 100 modes. The last line is parsed by other tools.
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

if any((Path(__file__).resolve().parents[1] / "python" / "drillpy").glob("_core*.so")):

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python"))  # in-tree build, else the installed drillpy

TARGETS = {20: 1.8, 100: 1.5}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--duration", type=float, default=20.0, help="simulated time per run [s]")
    a = ap.parse_args()
    import drillpy
    from drillpy import _core
    from drillpy.model.config import with_overrides
    speeds = np.linspace(6.0, 27.0, 16)
    base = drillpy.load_config(preset="thesis-field")
    steps = round(a.duration / base["simulation"]["dt_s"]) + 1
    print(f"batch width on this host: {_core.Simulation.batch_width()} runs; {speeds.size} runs of "
          f"{a.duration:g} s ({steps} steps) per sweep, 1 thread, median of {a.repeats}")
    print(f"{'modes':>5s} {'scalar ns/step/run':>19s} {'batched':>8s} {'speed-up':>9s} {'target':>7s} "
          f"{'max |dSS|/SS':>13s}")
    speedup = {}
    for modes in (10, 20, 50, 100):
        cfg = with_overrides(base, modes=modes, duration=a.duration, transient=a.duration / 2)

        def sweep(batched: bool, cfg=cfg):
            t0 = time.perf_counter()
            ss = drillpy.sweep_severity(cfg, speeds, progress=False, threads=1, batched=batched)
            return time.perf_counter() - t0, ss

        _, ss_s = sweep(False)  # warm-up, and the reference values
        _, ss_b = sweep(True)
        ts, tb = [], []
        for _ in range(a.repeats):
            ts.append(sweep(False)[0])
            tb.append(sweep(True)[0])
        ratio = statistics.median(s / b for s, b in zip(ts, tb))
        speedup[modes] = ratio
        per = 1e9 / (speeds.size * steps)
        target = f">= {TARGETS[modes]}" if modes in TARGETS else ""
        dev = float(np.max(np.abs(ss_b / ss_s - 1.0)))
        print(f"{modes:5d} {statistics.median(ts) * per:19.1f} {statistics.median(tb) * per:8.1f} "
              f"{ratio:8.2f}x {target:>7s} {dev:13.1e}")
    print(f"batched speed-up at 20 modes: {speedup[20]:.2f} x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
