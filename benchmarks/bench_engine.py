"""Engine speed against the plain NumPy loop, and the parallel speed-up of the SS sweep.

    python3 benchmarks/bench_engine.py

Case: thesis-field (100 elements, 20 modes), dt = 0.512 ms, 100 s of simulated time.
Targets (issue 2): engine >= 50x faster than NumPy on one core; 22-speed sweep >= 1.7x faster
on 2 threads than on 1.
"""
from __future__ import annotations

import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import drillpy  # noqa: E402
from numpy_rom import run_modified_euler  # noqa: E402


def best_of(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    cfg = drillpy.with_overrides(drillpy.load_config(preset="thesis-field"), elements=100,
                                 dt=5.12e-4, duration=100.0, transient=50.0)
    speed = 16.0
    t_np = best_of(lambda: run_modified_euler(cfg, speed), 1)
    t_engine = best_of(lambda: drillpy.simulate(cfg, speed, record=False), 5)
    ref = run_modified_euler(cfg, speed, duration=2.0)
    eng = drillpy.simulate(drillpy.with_overrides(cfg, duration=2.0, transient=1.0), speed)
    stride = cfg["simulation"]["output_stride"]
    agree = float(np.max(np.abs(ref[::stride] - eng.bit_speed)))
    print(f"single run, 100 s at dt = 0.512 ms ({cfg['rom']['modes']} modes):")
    print(f"  numpy loop    {t_np:8.3f} s")
    print(f"  engine        {t_engine:8.4f} s")
    print(f"  ratio         {t_np / t_engine:8.1f} x   (target >= 50)")
    print(f"  max |v_numpy - v_engine| over the first 2 s: {agree:.2e} rad/s")

    speeds = np.arange(6.0, 28.0)
    sweep_cfg = drillpy.load_config(preset="thesis-field")
    t1 = best_of(lambda: drillpy.sweep_severity(sweep_cfg, speeds, progress=False, threads=1), 2)
    t2 = best_of(lambda: drillpy.sweep_severity(sweep_cfg, speeds, progress=False, threads=2), 2)
    print(f"22-speed SS sweep ({sweep_cfg['simulation']['duration_s']:.0f} s each):")
    print(f"  1 thread      {t1:8.3f} s")
    print(f"  2 threads     {t2:8.3f} s")
    print(f"  speed-up      {t1 / t2:8.2f} x   (target >= 1.7)")


if __name__ == "__main__":
    main()
