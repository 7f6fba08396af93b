"""The damping scan of ``drillpy analyze`` in SIMD lockstep against one run per model, in one run
(issue 16).

    PYTHONPATH=python python3 benchmarks/bench_damping_scan.py [--repeats 5] [--threads 1]

Sample 175's calibration part (0-20 s, cleaned) and the Eq. (5.1) law identified on it, as
``drillpy analyze`` has them; the scan of :func:`drillpy.records.rig_calibration.calibrate`: its grid of
12 damping ratios log-spaced from 0.01 to 1 for the constant and the measured drive, each model
simulated over the 20 s and compared with the record (the measured side computed once per drive,
as the scan does). ``scalar``: the models one by one through
the scalar reference integrator (``simulate_models(batched=False)``, what the scan did before);
``batched``: the models in SIMD lockstep, one damping ratio per vector lane
(``simulate_models``). Repeats alternate the two; the speed-up is the median of the per-repeat
ratios (the machine is shared); the simulations' share (``simulate_models``, the rest is the
comparison with the record) is timed too. The script fails if a mismatch differs by more than 1e-6
relative between the two paths (they agree to rounding).
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
if any((REPO / "python" / "drillpy").glob("_core*.so")):  # in-tree build, else the installed drillpy
    sys.path.insert(0, str(REPO / "python"))
sys.path.insert(0, str(REPO / "benchmarks"))

from rig_calibration_part import SAMPLE175, calibration_part  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--threads", type=int, default=1, help="engine threads of both paths")
    ap.add_argument("--record", default=str(SAMPLE175))
    a = ap.parse_args()
    from drillpy import _core
    from drillpy.records import rigsim
    from drillpy.records import rig_comparison
    rec, thr, law = calibration_part(a.record)
    grid = [float(z) for z in np.geomspace(0.01, 1.5, 14) if z <= 1.0]
    models = [rigsim.RigModel(law, z, drive) for drive in ("constant", "measured") for z in grid]
    by_drive = {drive: [m for m in models if m.drive == drive] for drive in ("constant", "measured")}

    def scan(batched):
        out = []
        for drive, ms in by_drive.items():
            t0 = time.perf_counter()
            sims = rigsim.simulate_models(ms, rec, threads=a.threads, batched=batched)
            engine[batched][-1] += time.perf_counter() - t0
            side = rig_comparison.measured_side(rec, thr, float(rec.time_s[0]), drive)
            out += [rig_comparison.compare(rec, s, thr, side=side).mismatch for s in sims]
        return np.array(out)

    times, engine = {True: [], False: []}, {True: [], False: []}
    result = {}
    for _ in range(a.repeats):
        for batched in (False, True):
            engine[batched].append(0.0)
            t0 = time.perf_counter()
            result[batched] = scan(batched)
            times[batched].append(time.perf_counter() - t0)
    ratios = [s / b for s, b in zip(times[False], times[True])]
    gap = float(np.max(np.abs(result[True] - result[False]) / np.abs(result[False])))
    print(f"damping scan of sample 175 (0-20 s): {len(models)} models ({len(grid)} damping ratios x constant, "
          f"measured drive), {a.threads} thread(s), batch width {_core.Simulation.batch_width()}, "
          f"median of {a.repeats}:")
    print(f"  {'':28s} {'scan':>8s} {'of it, simulations':>19s}")
    print(f"  {'scalar, one model at a time':28s} {statistics.median(times[False]):7.3f}s "
          f"{statistics.median(engine[False]):18.3f}s")
    print(f"  {'batched, SIMD lockstep':28s} {statistics.median(times[True]):7.3f}s "
          f"{statistics.median(engine[True]):18.3f}s")
    print(f"simulations alone, batched over scalar: "
          f"{statistics.median([s / b for s, b in zip(engine[False], engine[True])]):.2f} x")
    print(f"largest relative mismatch difference between the paths: {gap:.2e}")
    print(f"damping scan speed-up, batched over scalar: {statistics.median(ratios):.2f} x")
    return 0 if gap <= 1e-6 else 1


if __name__ == "__main__":
    raise SystemExit(main())
