"""``drillpy loop`` on the test-rig record, sample 175 (0-40 s), with the calibration's
finite-difference Jacobian in one engine call per Jacobian (issue 33, item 2) against one call per
perturbation, measured in one run; each configuration in its own process, one after the other.

    PYTHONPATH=python python3 benchmarks/bench_loop.py [--base-tree DIR] [--rate 1000] [--repeat N]

Configurations:

* ``base`` (with ``--base-tree DIR``): the loop of another source tree with its own built extension
  (e.g. ``git archive <commit> python | tar -x -C DIR`` and that commit's ``_core*.so`` copied into
  ``DIR/python/drillpy``): the loop as it ran before issue 33;
* ``per-perturbation``: this tree with ``LoopOptions(batched_jacobian=False)``: scipy's '2-point'
  differences, one engine call per perturbed model (the trials' configurations built without
  ``copy.deepcopy`` and JSON text, as in ``batched``);
* ``declared-step``: this tree's defaults but the step rule off (``LoopOptions(step_tolerance=0)``):
  every prediction at the preset's 1e-4 s;
* ``batched``: this tree's defaults: every perturbed model of one Jacobian in one
  ``_core.predict_horizons_many`` call, at the step rule's engine step (``drillpy.loop.time_step``:
  2.5e-4 s on sample 175);
* ``exact_modal``: the defaults with ``LoopOptions(scheme="exact_modal", dt_s=1e-3)``: every
  prediction on the exact modal scheme at 1 ms instead of the modified Euler at the preset's 0.1 ms.

Prints per configuration: the wall time of ``run_loop`` (the record read, no figures, no files),
engine calls, the steps (action, effect, E before -> after) and the final validation E; then the
ratios of the wall times (with ``--repeat N``: each configuration run N times, interleaved, and the
medians compared) and whether the decisions are the same. The `drillpy loop` analysis rate
(1000 Hz) is the default. The machine is shared: read the ratios.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
SAMPLE175 = REPO.parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"
OPTIONS = {"base": {}, "per-perturbation": {"batched_jacobian": False}, "declared-step": {"step_tolerance": 0.0},
           "batched": {},
           "exact_modal": {"scheme": "exact_modal", "dt_s": 1e-3}}


def child(name: str, rate: float, record: str) -> None:
    """Run the loop in this process and print one JSON line."""
    import drillpy
    from drillpy import _core
    from drillpy.loop import LoopOptions, run_loop
    calls = {"n": 0}
    for f in ("predict_horizons", "predict_horizons_many"):  # count the engine calls
        if hasattr(_core, f):
            orig = getattr(_core, f)
            setattr(_core, f, lambda *a, _o=orig, **k: (calls.__setitem__("n", calls["n"] + 1), _o(*a, **k))[1])
    cfg = drillpy.load_config(preset="thesis-rig")
    t0 = time.perf_counter()
    res = run_loop(record, cfg, LoopOptions(rate_hz=rate, **OPTIONS[name]), log=lambda *a: None)
    wall = time.perf_counter() - t0
    steps = [[s.action, s.effect, round(s.error_before, 4), round(s.error_after, 4)] for s in res.steps]
    print(json.dumps({"wall": wall, "calls": calls["n"], "steps": steps, "baseline": res.baseline.E_test,
                      "final": res.final.E_test, "effects": list(res.final.model.effects),
                      "dt": res.baseline.model.cfg["simulation"]["dt_s"]}))


def run(name: str, tree: Path, rate: float, record: str) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree / "python"))
    p = subprocess.run([sys.executable, __file__, "--child", name, "--rate", str(rate), "--record", record],
                       env=env, capture_output=True, text=True, cwd=tree)
    if p.returncode:
        raise SystemExit(f"{name}: failed\n{p.stderr}")
    r = json.loads(p.stdout.strip().splitlines()[-1])
    print(f"{name}: {r['wall']:.1f} s, {r['calls']} engine calls, engine step {r['dt']:.3g} s; baseline E {r['baseline']:.4f}, final E "
          f"{r['final']:.4f}, effects {r['effects']}")
    for s in r["steps"]:
        print(f"  {s[0]:<6} {s[1]:<20} E {s[2]:.4f} -> {s[3]:.4f}")
    sys.stdout.flush()
    return r


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--base-tree", type=Path, help="a source tree with its built extension: the loop before")
    ap.add_argument("--rate", type=float, default=1000.0, help="analysis rate [Hz] (drillpy loop's default: 1000)")
    ap.add_argument("--record", default=str(SAMPLE175))
    ap.add_argument("--only", help="comma-separated configurations to run (default: all): " + ", ".join(OPTIONS))
    ap.add_argument("--repeat", type=int, default=1, help="runs of each configuration, interleaved; the median wall time")
    ap.add_argument("--child", choices=tuple(OPTIONS), help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.child:
        child(a.child, a.rate, a.record)
        return 0
    only = set(a.only.split(",")) if a.only else set(OPTIONS)
    if only - set(OPTIONS):
        raise SystemExit(f"--only {a.only!r}: unknown configuration(s) {sorted(only - set(OPTIONS))}; use {', '.join(OPTIONS)}")
    names = [n for n in OPTIONS if (n != "base" or a.base_tree) and n in only]
    print(f"sample 175 at {a.rate:g} Hz; {os.cpu_count()} CPUs; load average {os.getloadavg()[0]:.1f}")
    runs = {n: [] for n in names}
    for _ in range(max(a.repeat, 1)):  # interleaved: a slow spell of the shared machine hits every configuration
        for n in names:
            runs[n].append(run(n, a.base_tree.resolve() if n == "base" else REPO, a.rate, a.record))
    res = {}
    for n, rs in runs.items():
        res[n] = dict(rs[0], wall=statistics.median(r["wall"] for r in rs))
        if len(rs) > 1:
            print(f"{n}: median of {len(rs)} runs {res[n]['wall']:.1f} s (" + ", ".join(f"{r['wall']:.1f}" for r in rs) + ")")
    if "batched" in res:
        b = res["batched"]
        for n, r in res.items():
            if n not in ("batched", "base"):
                same = r["steps"] == b["steps"] and r["effects"] == b["effects"]
                print(f"{n} / batched: {r['wall'] / b['wall']:.2f} x; same decisions: {same}")
        if "base" in res:
            same = b["steps"] == res["base"]["steps"] and b["effects"] == res["base"]["effects"]
            print(f"base / batched: {res['base']['wall'] / b['wall']:.2f} x; same decisions: {same}")
        if "base" in res and "exact_modal" in res:
            e = res["exact_modal"]
            same = e["steps"] == res["base"]["steps"] and e["effects"] == res["base"]["effects"]
            print(f"base / exact_modal: {res['base']['wall'] / e['wall']:.2f} x; same decisions: {same}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
