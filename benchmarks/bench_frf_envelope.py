"""Benchmark: one FRF envelope study (section 6.6) against a dense-solve baseline.

  PYTHONPATH=python python3 benchmarks/bench_frf_envelope.py [--samples 2500] [--freqs 1000]

Target (issue 4): SM_CB2 on thesis-ch6 (25 + 25 fixed-interface modes, 51 DOFs), 2500 samples,
1000 frequencies, three observation points, in at most 20 s wall on 2 cores. The engine uses one
eigen-decomposition per realization and partial fractions per frequency. The baseline, measured in
the same run on a few samples, is what the hint warns against: a dense complex solve per frequency
and sample (NumPy's batched LAPACK solve), extrapolated to the full study. Both are checked to give
the same curves. The machine is shared: the load average and the CPU time are printed with the
wall time.
"""
from __future__ import annotations

import argparse
import os
import time

import numpy as np

import drillpy as d
from drillpy.model.config import engine_config
from drillpy.uncertainty import frf as F


def dense_baseline_db(sm, basis_rows, bit, omega, seed, i):
    m = sm.sample_matrices(seed, i)
    Z = (m["K"][None] - omega[:, None, None] ** 2 * m["M"][None]) + 1j * omega[:, None, None] * m["D"][None]
    q = np.linalg.solve(Z, np.broadcast_to(bit, (omega.size, bit.size))[..., None])[..., 0]
    a = -(omega ** 2)[:, None] * (q @ basis_rows.T)
    return 20 * np.log10(np.abs(a))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--samples", type=int, default=2500)
    p.add_argument("--freqs", type=int, default=1000)
    p.add_argument("--baseline-samples", type=int, default=8)
    a = p.parse_args()
    cfg = d.load_config(preset="thesis-ch6")
    f = F.default_frequencies(a.freqs)
    print(f"thesis-ch6, SM_CB2 (every delta = 0.1), {a.samples} samples x {f.size} frequencies x 3 points; "
          f"OpenMP threads available: {d._core.max_threads()}; load average before: {os.getloadavg()[0]:.2f}")
    res = {}
    for threads in (2, 1):
        t0, c0 = time.perf_counter(), os.times()
        env = F.frf_envelope(cfg, "SM_CB2", 0.1, samples=a.samples, freq_hz=f, progress=False, threads=threads)
        wall, c1 = time.perf_counter() - t0, os.times()
        cpu = (c1.user - c0.user) + (c1.system - c0.system)
        res[threads] = (wall, cpu, env)
        print(f"engine, {threads} thread(s): wall {wall:7.2f} s, CPU {cpu:7.2f} s "
              f"({1e3 * cpu / a.samples:.2f} ms CPU per sample), load average {os.getloadavg()[0]:.2f}")
    np.testing.assert_array_equal(res[1][2].upper_db, res[2][2].upper_db)
    print(f"speed-up 1 -> 2 threads: {res[1][0] / res[2][0]:.2f} (identical envelopes)")

    sm = F.stochastic_model(cfg, "SM_CB2", 0.1)
    cb = d._core.craig_bampton(engine_config(cfg))
    nodes = F.observation_nodes(cfg)
    rows = cb["psi"][[n - 1 for n in nodes]]
    bit = cb["psi"][-1]
    omega = 2 * np.pi * f
    t0 = time.perf_counter()
    worst = 0.0
    for i in range(a.baseline_samples):
        ref = dense_baseline_db(sm, rows, bit, omega, 1, i)
        eng = sm.frf_db(f, nodes, sample=i, seed=1)
        worst = max(worst, float(np.abs(ref - eng).max()))
    per = (time.perf_counter() - t0) / a.baseline_samples
    print(f"baseline (dense solve per frequency, NumPy): {1e3 * per:.1f} ms per sample -> "
          f"{per * a.samples:.1f} s extrapolated for {a.samples} samples (NumPy batched LAPACK solve)")
    print(f"engine vs baseline on {a.baseline_samples} samples: max |difference| {worst:.2e} dB")
    print(f"ratio baseline / engine (2 threads, wall): {per * a.samples / res[2][0]:.1f}; "
          f"target <= 20 s wall: {'met' if res[2][0] <= 20 else 'NOT met'} ({res[2][0]:.2f} s)")


if __name__ == "__main__":
    main()
