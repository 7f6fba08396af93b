"""Cost of a controlled top drive per simulation (issue 15), measured side by side in one run.

    PYTHONPATH=python python3 benchmarks/bench_controller.py [--repeats 7]

thesis-field (20 modes, modified Euler, dt 5.12e-4 s), 200 s at 14 rad/s without recording, one
thread: the median wall time per run of the ideal drive (the thesis), the open-loop motor, and the
controlled drive with each controller; the ratio to the ideal drive (target: at most 1.3).
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python"))

DRIVES = {
    "ideal": None,
    "motor": {"type": "motor", "slope_nms_rad": 5.0e4, "inertia_kg_m2": 2000.0},
    **{c: {"type": "controlled", "inertia_kg_m2": 2000.0, "controller": {"type": c}}
       for c in ("stiff", "soft_speed", "z_torque")},
    "pi (sampled 10 ms)": {"type": "controlled", "inertia_kg_m2": 2000.0,
                           "controller": {"type": "pi", "kp_nms_rad": 930.0, "ki_nm_rad": 300.0,
                                          "sample_time_s": 0.01}},
}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeats", type=int, default=7)
    a = ap.parse_args()
    import drillpy
    from drillpy.model.config import with_overrides
    base = with_overrides(drillpy.load_config(preset="thesis-field"), duration=200.0, transient=100.0)
    times = {}
    for name, drive in DRIVES.items():
        cfg = base if drive is None else with_overrides(base, top_drive=drive)
        drillpy.simulate(cfg, 14.0, record=False)  # warm-up (tuning, caches)
        runs = []
        for _ in range(a.repeats):
            t0 = time.perf_counter()
            r = drillpy.simulate(cfg, 14.0, record=False)
            runs.append(time.perf_counter() - t0)
        times[name] = (statistics.median(runs), r.severity)
    ref = times["ideal"][0]
    print(f"{'drive':22s} {'median [s]':>11s} {'x ideal':>8s} {'SS':>7s}")
    for name, (t, ss) in times.items():
        print(f"{name:22s} {t:11.4f} {t / ref:8.2f} {ss:7.3f}")
    worst = max(t for n, (t, _) in times.items() if n != "ideal" and n != "motor") / ref
    print(f"largest controller cost: {worst:.2f} x the ideal drive")
    return 0


if __name__ == "__main__":
    sys.exit(main())
