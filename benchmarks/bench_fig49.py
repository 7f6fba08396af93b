"""Wall time of the Fig. 4.9 study in its thesis-faithful configuration, scalar against batched
(issue 16), and the speed-up of 2 threads over 1, measured in one run.

    PYTHONPATH=python python3 benchmarks/bench_fig49.py [--samples 500] [--speeds 6:27:22]
        [--exact-dt 5] [--skip-scalar]

(500 samples take about 8 minutes on the scalar path with 2 threads: a run of 300 s at 100 modes
is 586 000 steps at about 150 ns; with fewer samples the script also prints the times scaled to
500, every run costing the same.)

The study of ``drillpy reproduce`` (docs/validation.md, Fig. 4.9): the thesis-ch4 preset (100
modes), Algorithm 1 literally (from rest, 300 s runs, SS after 200 s), eta with the shape of Eq.
(4.4) and std 0.0667, ``--samples`` x the 22 speeds 6 .. 27 rad/s. Three timings of the same Monte
Carlo block (``MonteCarlo.severity``):

* before: the scalar integrator (``batched=False``, the engine before issue 16), 2 threads;
* after: the batched SIMD integrator, 2 threads;
* after on 1 thread (the 2-thread speed-up is after-1 / after-2, target >= 1.8).

Every variant runs the same samples. The script checks that 1 and 2 threads give identical bits
and prints how far the batched study is from the scalar one: per run (a 300 s run from rest in
stick-slip under a random load amplifies the rounding differences of the batched path's exp/log
and summation order; docs/numerics.md) and in what the study reports, P(SS > 0.5) per speed and
the 5 % speed. The machine is shared: read the ratios.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

if any((Path(__file__).resolve().parents[1] / "python" / "drillpy").glob("_core*.so")):

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python"))  # in-tree build, else the installed drillpy


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--samples", type=int, default=500)
    ap.add_argument("--speeds", default="6:27:22", help="first:last:count [rad/s] (default: the thesis's 6 .. 27)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--exact-dt", type=float, default=0.0,
                    help="also time the study with simulation.scheme exact_modal at this step [ms] (issue 33)")
    ap.add_argument("--skip-scalar", action="store_true", help="skip the scalar (before) timing")
    a = ap.parse_args()
    import drillpy
    from drillpy import _core
    from drillpy.reports.reproduce import ALGORITHM1, MC_ETA_STD
    from drillpy.uncertainty.montecarlo import ETA_DT_S, study_config, study_engine
    from drillpy.uncertainty.process import THESIS_PSD, scaled_to_std
    from drillpy.uncertainty.robust_speed import p_speed
    lo, hi, n = a.speeds.split(":")
    speeds = list(np.linspace(float(lo), float(hi), int(n)))
    cfg = drillpy.load_config(preset="thesis-ch4")
    c = study_config(cfg, ALGORITHM1["duration"], ALGORITHM1["transient"])
    mc = study_engine(c, scaled_to_std(THESIS_PSD, MC_ETA_STD), ETA_DT_S, a.seed, ALGORITHM1["warmup"])
    print(f"Fig. 4.9 study: thesis-ch4 ({c['rom']['modes']} modes, dt {c['simulation']['dt_s']:g} s), "
          f"{a.samples} samples x {len(speeds)} speeds, {ALGORITHM1['duration']:g} s runs from rest; "
          f"{_core.Simulation.batch_width()} runs per SIMD batch on this host")

    def timed(threads: int, batched: bool) -> tuple:
        t0 = time.perf_counter()
        ss = np.asarray(mc.severity(speeds, 0, a.samples, None, threads, batched))
        return time.perf_counter() - t0, ss

    after, ss_batched = timed(2, True)
    print(f"after  (batched SIMD,      2 threads): {after:8.1f} s", flush=True)
    if a.exact_dt > 0:
        ce = drillpy.with_overrides(c, scheme="exact_modal", dt=a.exact_dt * 1e-3)
        me = study_engine(ce, scaled_to_std(THESIS_PSD, MC_ETA_STD), ETA_DT_S, a.seed, ALGORITHM1["warmup"])
        t0 = time.perf_counter()
        ss_exact = np.asarray(me.severity(speeds, 0, a.samples, None, 2, True))
        exact = time.perf_counter() - t0
        dpe = float(np.max(np.abs(np.mean(ss_exact > 0.5, axis=0) - np.mean(ss_batched > 0.5, axis=0))))
        pe = ["none" if v is None else f"{v:.2f}" for v in (p_speed(s, speeds) for s in (ss_batched, ss_exact))]
        print(f"exact_modal at {a.exact_dt:g} ms (batched, 2 threads): {exact:8.1f} s; "
              f"{after / exact:.2f} x faster than modified_euler at {c['simulation']['dt_s'] * 1e3:g} ms; "
              f"largest |P(SS > 0.5) difference| {dpe:.3f}; 5 % speed {pe[0]} (modified_euler) vs {pe[1]} "
              f"(exact_modal) rad/s", flush=True)
    if a.skip_scalar:
        return 0
    before, ss_scalar = timed(2, False)
    print(f"before (scalar integrator, 2 threads): {before:8.1f} s", flush=True)
    one, ss_one = timed(1, True)
    print(f"after  (batched SIMD,      1 thread):  {one:8.1f} s", flush=True)
    rel = np.abs(ss_batched - ss_scalar) / np.maximum(np.abs(ss_scalar), 1e-12)
    same_bits = bool(np.array_equal(ss_one, ss_batched))
    dp = float(np.max(np.abs(np.mean(ss_batched > 0.5, axis=0) - np.mean(ss_scalar > 0.5, axis=0))))
    p05 = ["none" if v is None else f"{v:.2f}" for v in (p_speed(s, speeds) for s in (ss_scalar, ss_batched))]
    print(f"batched vs scalar: relative SS difference per run median {np.median(rel):.1e}, largest {rel.max():.1e}; "
          f"largest |P(SS > 0.5) difference| over the speeds {dp:.3f}; 5 % speed {p05[0]} vs {p05[1]} rad/s")
    print(f"1 vs 2 threads identical bits: {same_bits}")
    if a.samples != 500:  # every run costs the same: the wall time scales with the samples
        k = 500 / a.samples
        print(f"scaled to the thesis's 500 samples: before {k * before:.0f} s, after {k * after:.0f} s (2 threads), "
              f"after {k * one:.0f} s (1 thread)")
    print(f"speed-up after / before (2 threads): {before / after:.2f} x")
    print(f"speed-up of 2 threads over 1 (batched): {one / after:.2f} x")
    return 0 if same_bits else 1


if __name__ == "__main__":
    sys.exit(main())
