"""Convergence of the exact modal scheme (``simulation.scheme: "exact_modal"``, issue 33) against a
fine-step BDF2 reference, the step-size rule stated in docs/numerics.md, and the branch check.

    PYTHONPATH=python python3 benchmarks/exact_modal_convergence.py [--modes 20,100] [--duration 120]
        [--speeds 6,10,14,17,18.5,19.5,21,24,27] [--steps 0.512,1,2,5,10] [--ref-dt 0.0512] [--tol 0.01]

(runs against the in-tree build when there is one, else against the installed drillpy.)

Case: the thesis-field preset (Fig. 4.8's string and law, WOB 245 kN, the hysteretic law of Eqs.
3.2-3.3) from rest, ``--duration`` s runs with SS (Eq. 3.4) and the stick and slip phases taken over
the second half, at each speed of ``--speeds`` (Fig. 4.8's range 6-27 rad/s with points on both
sides of its threshold, 19.2 rad/s at 20 modes, 18.8 at 100), at 20 and 100 modes. Reference: BDF2
at ``--ref-dt`` (10x finer than the thesis's 0.512 ms). For every step of ``--steps`` [ms] the
exact modal scheme's relative SS error, the relative errors of the mean stick and slip durations
and whether the run's regime (stick-slip or not, its period in cycles) is the reference's; the
thesis's modified Euler at 0.512 ms for comparison. Prints markdown tables, the largest step that
keeps SS within ``--tol`` at every speed of each mode count, and the branch check
(``drillpy.model.convergence.branch_check``: dt against dt/2) at that step near the threshold.
"""
from __future__ import annotations

import argparse
import math
import platform
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

_TREE = Path(__file__).resolve().parents[1] / "python"
if any((_TREE / "drillpy").glob("_core*.so")):  # the in-tree build; otherwise the installed package
    sys.path.insert(0, str(_TREE))


def _machine() -> str:
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
        name = next(line.split(":", 1)[1].strip() for line in out.splitlines() if line.startswith("Model name"))
    except (OSError, subprocess.CalledProcessError, StopIteration):
        name = platform.processor() or "unknown CPU"
    return name


def _mean(x) -> float:
    x = np.asarray(x, float)
    return float(x.mean()) if x.size else math.nan


def _rel(a: float, b: float) -> float:
    if math.isnan(a) and math.isnan(b):
        return 0.0
    return abs(a - b) / max(abs(b), 1e-12)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--modes", default="20,100")
    ap.add_argument("--duration", type=float, default=120.0, help="run length [s]; SS over its second half")
    ap.add_argument("--speeds", default="6,10,14,17,18.5,19.5,21,24,27", help="top speeds [rad/s]")
    ap.add_argument("--steps", default="0.512,1,2,5,10", help="exact modal steps [ms]")
    ap.add_argument("--ref-dt", type=float, default=0.0512, help="BDF2 reference step [ms]")
    ap.add_argument("--tol", type=float, default=0.01, help="relative SS tolerance of the step rule")
    ap.add_argument("--threads", type=int, default=2)
    a = ap.parse_args()
    import drillpy
    from drillpy.model.convergence import branch_check
    from drillpy.model.simulation import simulate_many

    modes = [int(m) for m in a.modes.split(",")]
    speeds = [float(s) for s in a.speeds.split(",")]
    steps = [float(s) * 1e-3 for s in a.steps.split(",")]
    base = drillpy.load_config(preset="thesis-field")
    print(f"# exact_modal convergence on {_machine()}, thesis-field from rest, {a.duration:g} s runs "
          f"(SS and phases over the second half); reference BDF2 at {a.ref_dt:g} ms")
    t_start = time.perf_counter()
    rule = {}
    for m in modes:
        def cfg(scheme: str, dt: float, speed: float, m=m) -> dict:
            return drillpy.with_overrides(base, modes=m, scheme=scheme, dt=dt, duration=a.duration,
                                          transient=a.duration / 2, top_speed=speed)

        variants = [("bdf2", a.ref_dt * 1e-3), ("modified_euler", 5.12e-4)] + [("exact_modal", dt) for dt in steps]
        cfgs = [cfg(s, dt, v) for s, dt in variants for v in speeds]
        t0 = time.perf_counter()
        res, err = simulate_many(cfgs, record=False, threads=a.threads)
        wall = time.perf_counter() - t0
        bad = [e for e in err if e]
        if bad:
            print(f"{len(bad)} runs failed: {bad[0]}")
            return 1
        by = {(s, dt): res[k * len(speeds):(k + 1) * len(speeds)] for k, (s, dt) in enumerate(variants)}
        ref = by[("bdf2", a.ref_dt * 1e-3)]
        print(f"\n## {m} modes ({len(cfgs)} runs, {wall:.0f} s wall on {a.threads} threads)\n")
        print("Reference (BDF2):\n")
        print("| speed [rad/s] | SS | mean stick [s] | mean slip [s] | period [cycles] |")
        print("|---|---|---|---|---|")
        for v, r in zip(speeds, ref):
            print(f"| {v:g} | {r.severity:.4f} | {_mean(r.stick_durations):.3f} | {_mean(r.slip_durations):.3f} | "
                  f"{r.period_cycles} |")
        print("\nError against the reference, worst over the speeds (and the speed where it is worst):\n")
        print("| scheme | dt [ms] | SS rel. error | stick duration rel. error | slip duration rel. error | "
              "regime differs at |")
        print("|---|---|---|---|---|---|")
        worst_ss = {}
        for s, dt in variants[1:]:
            rs = by[(s, dt)]
            ess = [_rel(r.severity, q.severity) for r, q in zip(rs, ref)]
            est = [_rel(_mean(r.stick_durations), _mean(q.stick_durations)) for r, q in zip(rs, ref)]
            esl = [_rel(_mean(r.slip_durations), _mean(q.slip_durations)) for r, q in zip(rs, ref)]
            regime = [f"{v:g}" for v, r, q in zip(speeds, rs, ref)
                      if (r.stick_fraction > 0) != (q.stick_fraction > 0) or r.period_cycles != q.period_cycles]
            k1, k2, k3 = int(np.argmax(ess)), int(np.argmax(est)), int(np.argmax(esl))
            print(f"| {s} | {dt * 1e3:g} | {ess[k1]:.2%} ({speeds[k1]:g}) | {est[k2]:.2%} ({speeds[k2]:g}) | "
                  f"{esl[k3]:.2%} ({speeds[k3]:g}) | {', '.join(regime) or '-'} |")
            if s == "exact_modal":
                worst_ss[dt] = max(ess)
        print("\nSS relative error per speed (exact_modal):\n")
        print("| dt [ms] | " + " | ".join(f"{v:g}" for v in speeds) + " |")
        print("|---|" + "---|" * len(speeds))
        for dt in steps:
            rs = by[("exact_modal", dt)]
            print(f"| {dt * 1e3:g} | " + " | ".join(f"{_rel(r.severity, q.severity):.2%}" for r, q in zip(rs, ref)) + " |")
        ok = [dt for dt in steps if worst_ss[dt] <= a.tol]
        rule[m] = max(ok) if ok else None
        print(f"\nlargest step with SS within {a.tol:.1%} of the reference at every speed: "
              f"{'none' if rule[m] is None else f'{rule[m] * 1e3:g} ms'}")
    print("\n## Branch check near the threshold (drillpy.model.convergence.branch_check: dt against dt/2)\n")
    print("| modes | speed [rad/s] | dt [ms] | SS at dt | SS at dt/2 | flagged |")
    print("|---|---|---|---|---|---|")
    for m in modes:
        dt = rule.get(m) or steps[-1]
        for v in (18.5, 19.0, 19.5):
            c = drillpy.with_overrides(base, modes=m, scheme="exact_modal", dt=dt, duration=a.duration,
                                       transient=a.duration / 2)
            b = branch_check(c, v, threads=a.threads)
            print(f"| {m} | {v:g} | {dt * 1e3:g} | {b['severity'][0]:.4f} | {b['severity'][1]:.4f} | "
                  f"{'yes' if b['flagged'] else 'no'} |")
    print(f"\ntotal {time.perf_counter() - t_start:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
