"""The engine step of ``drillpy loop``'s predictions (issue 33): the loop on a record at several steps,
its errors, every candidate's validation gain, its decisions and its wall time, measured in one run.

    PYTHONPATH=python python3 benchmarks/loop_timestep.py [--steps 1e-4,2.5e-4,5e-4] [--record FILE]
        [--preset thesis-rig] [--rate 1000]

Default record: the test rig's sample 175 (0-40 s) with the ``thesis-rig`` preset, whose own step is
1e-4 s (it serves long runs from rest). Short horizons restarted from the measured state every
0.25 s need no such step: the loop's default, :data:`drillpy.loop.options.HORIZON_DT_S`, is chosen
from this script's output (the same decisions, every gain within a fraction of the 5 % gate). Each
step runs the whole loop (calibration, candidates, long runs) with ``LoopOptions(dt_s=step)``; the
ratio is the wall time of the first step over each. The machine is shared: read the ratios.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
if any((REPO / "python" / "drillpy").glob("_core*")):  # in-tree build, else the installed drillpy
    sys.path.insert(0, str(REPO / "python"))
SAMPLE175 = REPO.parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--steps", default="1e-4,2.5e-4,5e-4", help="engine steps [s], comma-separated")
    ap.add_argument("--record", default=str(SAMPLE175))
    ap.add_argument("--preset", default="thesis-rig")
    ap.add_argument("--rate", type=float, default=1000.0, help="analysis rate [Hz]")
    a = ap.parse_args()
    import drillpy
    from drillpy.loop import LoopOptions, run_loop
    rows = []
    for dt in (float(x) for x in a.steps.split(",")):
        t0 = time.perf_counter()
        res = run_loop(a.record, drillpy.load_config(preset=a.preset), LoopOptions(rate_hz=a.rate, dt_s=dt),
                       log=lambda *x: None)
        wall = time.perf_counter() - t0
        steps = [f"{'+' if s['action'] == 'add' else '-' if s['action'] == 'remove' else '~'}{s['effect']} "
                 f"({s['error_before']:.4f}->{s['error_after']:.4f})" for s in res.steps] or ["none"]
        gains = {c["effect"]: c.get("relative_gain", float("nan")) for c in (res.rounds[0] if res.rounds else [])}
        rows.append((dt, wall, res, steps, gains))
        print(f"dt {dt:g} s: {wall:.1f} s; E calibration {res.baseline.E_train:.4f}, validation "
              f"{res.baseline.E_test:.4f} -> final {res.final.E_test:.4f}; steps: {', '.join(steps)}", flush=True)
    names = sorted({n for r in rows for n in r[4]})
    print("\n| step [s] | wall [s] | x faster | E cal | E val (baseline) | E val (final) | damping | steps |")
    print("|---:|---:|---:|---:|---:|---:|---:|---|")
    for dt, wall, res, steps, _ in rows:
        z = res.final.model.damping_ratios or []
        print(f"| {dt:g} | {wall:.1f} | {rows[0][1] / wall:.2f} | {res.baseline.E_train:.4f} | {res.baseline.E_test:.4f} | "
              f"{res.final.E_test:.4f} | {', '.join(f'{x:.4f}' for x in z)} | {', '.join(steps)} |")
    print("\nfirst round's validation gains [%] (the gate asks >= 5 %):")
    print("| candidate | " + " | ".join(f"{r[0]:g} s" for r in rows) + " |")
    print("|---|" + "---:|" * len(rows))
    for n in names:
        print(f"| {n} | " + " | ".join(f"{100 * r[4].get(n, float('nan')):+.2f}" for r in rows) + " |")
    same = len({tuple(r[3]) for r in rows}) == 1
    print(f"\nthe same steps at every engine step: {same}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
