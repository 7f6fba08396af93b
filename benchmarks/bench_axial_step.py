"""Cost of a step per run of the axial-torsional model against the torsional engine's, on the scalar
and on the batched path, at 20 and 100 torsional modes (issue 34's target: coupled / torsional at
most 2 x with the same number of torsional modes).

    PYTHONPATH=python python3 benchmarks/bench_axial_step.py [--duration 10] [--runs 8] [--repeats 3]

Each case is a sweep of ``--runs`` top speeds (2 to 9 rad/s) on one thread (``sweep(threads=1)``):
``batched=False`` runs them one by one (the scalar path), ``batched=True`` in lanes of the batched
path (the torsional engine's SIMD lockstep, batched_integrator.hpp; the coupled model's
AxialTorsional::run_lanes). The string is ``rgd-field``'s with ``--modes`` torsional modes; the
coupled model is the preset's (RGD bit, 10 axial modes, hook load), the torsional one the same string
without the axial model and with the thesis's field law (Eqs. 3.1-3.3, ``thesis-field``'s) at the
preset's WOB. Both use modified Euler at the same step: the preset's 0.5 ms, or at 100 modes 0.8 of
the torsional bound of Eq. (A.7). Prints the median over ``--repeats`` of the wall time per step and
per run [ns] and the ratios coupled / torsional. The machine may be shared: read the ratios with the
load (printed).
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
if any((REPO / "python" / "drillpy").glob("_core*.so")):  # in-tree build, else the installed drillpy
    sys.path.insert(0, str(REPO / "python"))


def configs(modes: int, duration: float) -> tuple[dict, dict]:
    """The coupled and the torsional configuration at `modes` torsional modes and one common step."""
    import drillpy
    from drillpy import _core
    from drillpy.model.config import engine_config

    coupled = drillpy.load_config(preset="rgd-field")
    coupled["rom"]["modes"] = modes
    torsional = drillpy.load_config(preset="rgd-field")
    torsional["rom"]["modes"] = modes
    del torsional["axial"]
    torsional["law"] = drillpy.load_config(preset="thesis-field")["law"]
    dt = coupled["simulation"]["dt_s"]
    bound = _core.Simulation(engine_config(torsional)).stability_bound  # Eq. (A.7) at these modes
    if dt >= bound:
        dt = 0.8 * bound
    for c in (coupled, torsional):
        c["simulation"].update(dt_s=dt, duration_s=duration, transient_s=duration / 2)
    return coupled, torsional


def per_step(cfg: dict, speeds: list[float], batched: bool, repeats: int) -> float:
    """Median wall time per step and per run [ns] of the sweep over `speeds` on one thread."""
    from drillpy import _core
    from drillpy.model.config import engine_config

    sim = _core.Simulation(engine_config(cfg))
    steps = round(cfg["simulation"]["duration_s"] / cfg["simulation"]["dt_s"])
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        sim.sweep(speeds, [], None, 1, None, batched)
        times.append(time.perf_counter() - t0)
    return 1e9 * statistics.median(times) / (steps * len(speeds))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=10.0, help="simulated seconds per run at 20 modes")
    ap.add_argument("--runs", type=int, default=8, help="runs per sweep (top speeds)")
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    from drillpy import _core

    speeds = [2.0 + 7.0 * k / max(1, a.runs - 1) for k in range(a.runs)]
    print(f"load average {os.getloadavg()[0]:.2f} {os.getloadavg()[1]:.2f} {os.getloadavg()[2]:.2f}; "
          f"{a.runs} runs per sweep, one thread, batch width {_core.Simulation.batch_width()}")
    print(f"{'modes':>5s} {'dt [ms]':>8s} {'torsional scalar':>17s} {'torsional batched':>18s} "
          f"{'coupled scalar':>15s} {'coupled batched':>16s} {'ratio scalar':>13s} {'ratio batched':>14s}")
    for modes in (20, 100):
        coupled, torsional = configs(modes, a.duration)
        # the same number of steps at both mode counts
        duration = a.duration * coupled["simulation"]["dt_s"] / 0.0005
        for c in (coupled, torsional):
            c["simulation"].update(duration_s=duration, transient_s=duration / 2)
        ts, tb = (per_step(torsional, speeds, b, a.repeats) for b in (False, True))
        cs, cb = (per_step(coupled, speeds, b, a.repeats) for b in (False, True))
        print(f"{modes:5d} {1e3 * coupled['simulation']['dt_s']:8.4f} {ts:17.0f} {tb:18.0f} {cs:15.0f} {cb:16.0f} "
              f"{cs / ts:13.2f} {cb / tb:14.2f}")
    print("ns per step per run; ratios coupled / torsional at the same modes (target <= 2)")


if __name__ == "__main__":
    main()
