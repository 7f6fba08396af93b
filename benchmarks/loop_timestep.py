"""The engine step of ``drillpy loop``'s predictions (issue 33): is a coarser step a free speed-up?

    PYTHONPATH=python python3 benchmarks/loop_timestep.py [--steps 1e-4,2.5e-4,5e-4] [--only sample175|stribeck]
        [--scheme modified_euler|exact_modal]

Two records: the test rig's sample 175 (0-40 s, 1000 Hz, every candidate) and a clean record of the
second outside simulator (``benchmarks/stribeck_rig.py``, seed 1, 250 Hz, the ``static_friction``
candidate alone: the record of ``tests/python/test_loop_gate.py``), both from ``thesis-rig`` (its
own step 1e-4 s). For each, two measurements:

* **the discretization alone**: the baseline calibrated at 1e-4 s, then that same model's
  short-horizon errors E (calibration / validation) at 2e-5 .. 1e-3 s, nothing refitted;
* **the whole loop** at each of ``--steps``: its wall time and ratio to 1e-4 s, the
  baseline's E, every first-round candidate's validation gain, and its steps (the decisions).

The first says how far the predictions are from converged at each step; the second whether the
loop's answer follows them or depends on where its least squares stop. ``--scheme`` integrates both
with that scheme (``LoopOptions.scheme``; the first's baseline is always calibrated with the modified
Euler at 1e-4 s). The machine is shared: read
the ratios.
"""
from __future__ import annotations

import argparse
import copy
import os
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "benchmarks"))
if any((REPO / "python" / "drillpy").glob("_core*.so")):  # in-tree build, else the installed drillpy
    sys.path.insert(0, str(REPO / "python"))
SAMPLE175 = REPO.parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"
FIXED_STEPS = (2e-5, 5e-5, 1e-4, 2e-4, 2.5e-4, 5e-4, 1e-3)


def records(only, folder):
    """(name, path, rate [Hz], candidate effects or None for the whole catalogue)."""
    out = []
    if only in (None, "sample175"):
        out.append(("sample 175", str(SAMPLE175), 1000.0, None))
    if only in (None, "stribeck"):
        import stribeck_rig
        path = os.path.join(folder, "stribeck_clean_1.csv")
        stribeck_rig.make_record("clean", 1, path)
        out.append(("Stribeck rig, clean, seed 1", path, 250.0, ("static_friction",)))
    return out


def fixed_model(path, rate, effects, scheme, steps) -> list:
    """The baseline calibrated at 1e-4 s, evaluated unchanged at every step of ``steps``."""
    import drillpy
    from drillpy.loop import LoopOptions, run_loop
    from drillpy.loop.model import evaluate
    kw = {} if effects is None else {"effects": effects}
    res = run_loop(path, drillpy.load_config(preset="thesis-rig"),
                   LoopOptions(rate_hz=rate, dt_s=1e-4, max_steps=0, long_run=False, discovery=False, **kw),
                   log=lambda *x: None)
    rows = []
    for dt in steps:
        m = res.baseline.model.copy()
        m.cfg = copy.deepcopy(m.cfg)
        m.cfg["simulation"]["dt_s"] = dt
        m.cfg["simulation"]["scheme"] = scheme
        try:
            ev = evaluate(m, res.data)
            rows.append((dt, ev.E_train, ev.E_test))
        except (ValueError, RuntimeError) as err:  # e.g. a step above the stability bound
            rows.append((dt, float("nan"), float("nan")))
            print(f"  dt {dt:g}: {err}")
    return rows


def whole_loop(path, rate, effects, steps, scheme) -> list:
    import drillpy
    from drillpy.loop import LoopOptions, run_loop
    kw = {} if effects is None else {"effects": effects}
    rows = []
    for dt in steps:
        t0 = time.perf_counter()
        res = run_loop(path, drillpy.load_config(preset="thesis-rig"),
                       LoopOptions(rate_hz=rate, dt_s=dt, scheme=scheme, **kw), log=lambda *x: None)
        wall = time.perf_counter() - t0
        taken = [f"{'+' if s.action == 'add' else '-' if s.action == 'remove' else '~'}{s.effect} "
                 f"({s.error_before:.4f}->{s.error_after:.4f})" for s in res.steps] or ["none"]
        gains = {c["effect"]: c.get("relative_gain", float("nan")) for c in (res.rounds[0] if res.rounds else [])}
        rows.append((dt, wall, res, taken, gains))
        print(f"  loop at dt {dt:g} s: {wall:.1f} s; baseline E {res.baseline.E_train:.4f} / {res.baseline.E_test:.4f}; "
              f"steps: {', '.join(taken)}", flush=True)
    return rows


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--steps", default="5e-5,1e-4,2.5e-4,5e-4",
                    help="engine steps of the whole loop [s], comma-separated (the ratios are to 1e-4 s when run)")
    ap.add_argument("--only", choices=("sample175", "stribeck"))
    ap.add_argument("--scheme", default="modified_euler", choices=("modified_euler", "exact_modal"),
                    help="the engine's scheme of the fixed model's rows and of the whole loop")
    ap.add_argument("--fixed-steps", default=",".join(f"{x:g}" for x in FIXED_STEPS),
                    help="steps at which the fixed baseline is evaluated [s], comma-separated")
    a = ap.parse_args()
    steps = [float(x) for x in a.steps.split(",")]
    with tempfile.TemporaryDirectory() as folder:
        for name, path, rate, effects in records(a.only, folder):
            print(f"\n## {name} ({rate:g} Hz, candidates: {', '.join(effects) if effects else 'the catalogue'})\n",
                  flush=True)
            fixed = fixed_model(path, rate, effects, a.scheme, [float(x) for x in a.fixed_steps.split(",")])
            print(f"The baseline calibrated at 1e-4 s (modified Euler), unchanged, at each step ({a.scheme}):\n")
            print("| step [s] | E calibration | E validation |")
            print("|---:|---:|---:|")
            for dt, e1, e2 in fixed:
                print(f"| {dt:g} | {e1:.4f} | {e2:.4f} |")
            print(flush=True)
            rows = whole_loop(path, rate, effects, steps, a.scheme)
            names = sorted({n for r in rows for n in r[4]})
            print("\nThe whole loop at each step:\n")
            ref = next((r[1] for r in rows if abs(r[0] - 1e-4) < 1e-12), rows[0][1])
            print("| step [s] | wall [s] | x faster | baseline E cal / val | final E val | steps | "
                  + " | ".join(f"gain {n} [%]" for n in names) + " |")
            print("|---:|---:|---:|---|---:|---|" + "---:|" * len(names))
            for dt, wall, res, taken, gains in rows:
                print(f"| {dt:g} | {wall:.1f} | {ref / wall:.2f} | {res.baseline.E_train:.4f} / "
                      f"{res.baseline.E_test:.4f} | {res.final.E_test:.4f} | {', '.join(taken)} | "
                      + " | ".join(f"{100 * gains.get(n, float('nan')):+.1f}" for n in names) + " |")
            decisions = {tuple((s.action, s.effect) for s in r[2].steps) for r in rows}
            print(f"\nthe same steps (actions and effects) at every engine step: {len(decisions) == 1}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
