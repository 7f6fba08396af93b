"""Cost of a step of the axial-torsional model against the torsional engine's (issue 34's target: at
most 2 x with the same number of torsional modes).

    PYTHONPATH=python python3 benchmarks/bench_axial.py [--duration 60] [--repeats 5]

Both runs use the ``rgd-field`` string (20 torsional modes, modified Euler at 0.5 ms, one thread,
no series recorded): the coupled model as the preset declares it (RGD bit, 10 axial modes, the
state-dependent delay on the bit's history), and the same string with the axial model removed and
the thesis's field law (Eq. 3.1-3.3, ``thesis-field``'s) at the preset's top speed and WOB. Prints
the median wall time per run and per step of each over ``--repeats`` runs, and their ratio. The
machine is shared: read the ratio.
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


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=60.0)
    ap.add_argument("--repeats", type=int, default=5)
    a = ap.parse_args()
    import drillpy
    from drillpy import _core
    from drillpy.model.config import engine_config

    coupled = drillpy.load_config(preset="rgd-field")
    coupled["simulation"].update(duration_s=a.duration, transient_s=a.duration / 2)
    torsional = drillpy.load_config(preset="rgd-field")
    del torsional["axial"]
    torsional["law"] = drillpy.load_config(preset="thesis-field")["law"]
    torsional["simulation"].update(duration_s=a.duration, transient_s=a.duration / 2, start="rest")
    law = drillpy.load_config(preset="rgd-field")
    law["axial"]["torque"] = "law"
    law["law"] = dict(drillpy.load_config(preset="thesis-field")["law"], wob_ref_n=166.8e3)
    law["simulation"].update(duration_s=a.duration, transient_s=a.duration / 2)
    steps = round(a.duration / coupled["simulation"]["dt_s"])
    med = {}
    for name, cfg in (("torsional", torsional), ("axial-torsional", coupled), ("axial, law torque", law)):
        sim = _core.Simulation(engine_config(cfg))
        times = []
        for _ in range(a.repeats):
            t0 = time.perf_counter()
            r = sim.run(record=False)
            times.append(time.perf_counter() - t0)
        med[name] = statistics.median(times)
        print(f"{name:16s} median {med[name]:.3f} s per {a.duration:g}-s run, {1e9 * med[name] / steps:.0f} ns per "
              f"step ({steps} steps, {cfg['rom']['modes']} torsional modes; SS {r.severity:.3f})")
    print(f"ratio axial-torsional / torsional per step: {med['axial-torsional'] / med['torsional']:.2f}")
    print(f"ratio axial with the law's torque / torsional per step: {med['axial, law torque'] / med['torsional']:.2f}")


if __name__ == "__main__":
    main()
