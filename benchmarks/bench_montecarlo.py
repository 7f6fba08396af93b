"""Benchmark of the Fig. 4.9 study: samples x 22 top speeds on thesis-field (dt = 0.512 ms).

Targets (issue 3): 500 samples x 22 speeds in <= 60 s wall on the 2-core machine; speed-up on
2 threads >= 1.7 (1-thread and 2-thread runs of the same samples, measured in this run; their
results must be bit-identical). The machine is shared: the script prints the load average and the
CPU time as well, so a busy machine can be recognized.

    PYTHONPATH=python python3 benchmarks/bench_montecarlo.py [--samples 500] [--speedup-samples 100]
    (--speedup-samples 0 times the study alone)
"""
from __future__ import annotations

import argparse
import os
import resource
import sys
import time
from pathlib import Path

import numpy as np

if any((Path(__file__).resolve().parents[1] / "python" / "drillpy").glob("_core*.so")):

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python"))  # in-tree build, else the installed drillpy

from drillpy.model.config import load_config  # noqa: E402
from drillpy.uncertainty.montecarlo import DURATION_S, TRANSIENT_S, WARMUP_S, stochastic_study  # noqa: E402


def cpu_seconds() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def timed(cfg, speeds, samples, threads):
    w0, c0 = time.perf_counter(), cpu_seconds()
    st = stochastic_study(cfg, speeds, samples, seed=1, threads=threads, progress=False,
                          deterministic=False)
    return st, time.perf_counter() - w0, cpu_seconds() - c0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--samples", type=int, default=500)
    ap.add_argument("--speedup-samples", type=int, default=100)
    args = ap.parse_args()
    cfg = load_config(preset="thesis-field")
    speeds = np.linspace(6.0, 27.0, 22)
    dt = cfg["simulation"]["dt_s"]
    steps = DURATION_S / dt
    print(f"thesis-field: {cfg['rom']['modes']} modes, {cfg['simulation']['scheme']}, dt = {dt * 1e3:.3f} ms; "
          f"per run {DURATION_S:g} s stochastic ({TRANSIENT_S:g} s discarded) after a shared "
          f"{WARMUP_S:g}-s deterministic warm-up; {os.cpu_count()} CPUs")
    print(f"load average at start: {os.getloadavg()}")

    n = args.speedup_samples
    same = True
    if n > 0:  # --speedup-samples 0 skips the check (to time the study alone)
        s1, w1, c1 = timed(cfg, speeds, n, 1)
        s2, w2, c2 = timed(cfg, speeds, n, 2)
        same = np.array_equal(s1.severity, s2.severity)
        print(f"speed-up check, {n} samples x 22 speeds: 1 thread {w1:.2f} s wall ({c1:.2f} s CPU), "
              f"2 threads {w2:.2f} s wall ({c2:.2f} s CPU): speed-up {w1 / w2:.2f} "
              f"(target >= 1.7); bit-identical: {same}")

    st, w, c = timed(cfg, speeds, args.samples, 2)
    runs = args.samples * len(speeds)
    print(f"Fig. 4.9 study, {args.samples} samples x 22 speeds = {runs} runs on 2 threads: "
          f"{w:.2f} s wall (target <= 60 s), {c:.2f} s CPU, {1e3 * c / runs:.2f} ms CPU per run "
          f"({1e9 * c / runs / steps:.1f} ns per step)")
    print(f"  p05_speed_rad_s = {st.p05_speed}, Conv1({args.samples}) = {st.conv1[-1]:.4f}")
    print(f"load average at end: {os.getloadavg()}")
    return 0 if same else 1


if __name__ == "__main__":
    raise SystemExit(main())
