"""Wall time of the rig calibration of ``drillpy analyze`` (its damping scans and the motor's grid,
:func:`drillpy.records.rig_calibration.calibrate`) on 1 thread against 2, measured in one run (issue 16).

    PYTHONPATH=python python3 benchmarks/bench_rig_calibration.py [--repeats 3]

Sample 175's calibration part (0-20 s, cleaned), the Eq. (5.1) law identified on it, the three top
drives (constant, measured, motor: 14 + 5 damping ratios each for the first two, 60 grid points and
a Nelder-Mead polish for the motor). The damping scans run in SIMD lockstep on the engine's threads, the motor's
points in a thread pool; the script checks that both thread counts give the same calibration. Medians of
``--repeats``; the machine is shared: read the ratio.
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path


REPO = Path(__file__).resolve().parents[1]
if any((REPO / "python" / "drillpy").glob("_core*.so")):  # in-tree build, else the installed drillpy
    sys.path.insert(0, str(REPO / "python"))
sys.path.insert(0, str(REPO / "benchmarks"))

from rig_calibration_part import SAMPLE175, calibration_part  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--record", default=str(SAMPLE175))
    a = ap.parse_args()
    from drillpy.records import rig_calibration
    rec, thr, law = calibration_part(a.record)
    times, cals = {1: [], 2: []}, {}
    for _ in range(a.repeats):
        for threads in (1, 2):
            t0 = time.perf_counter()
            cals[threads] = rig_calibration.calibrate(rec, law, thr, threads=threads)
            times[threads].append(time.perf_counter() - t0)
    one, two = (statistics.median(times[k]) for k in (1, 2))
    same = cals[1].summary() == cals[2].summary()
    print(f"rig calibration of sample 175 (0-20 s, drives {', '.join(cals[1].per_drive)}), median of {a.repeats}:")
    print(f"  1 thread   {one:7.2f} s")
    print(f"  2 threads  {two:7.2f} s")
    print(f"same calibration on 1 and 2 threads: {same}; chosen: {cals[2].model.drive} drive, damping ratio "
          f"{cals[2].model.damping_ratio:.3g}, mismatch {cals[2].comparison.mismatch:.3f}")
    print(f"speed-up of 2 threads over 1: {one / two:.2f} x")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
