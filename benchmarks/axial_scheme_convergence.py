"""Convergence of the coupled axial-torsional model's two schemes (``simulation.scheme`` modified_euler
and exact_modal, drill/axial_torsional.hpp) against a fine-step modified Euler reference, and their
cost at matched accuracy.

    PYTHONPATH=python python3 benchmarks/axial_scheme_convergence.py [--duration 60] [--repeats 3] \
        [--timed 600]

Two cases on the ``rgd-field`` string at 8 rad/s and 150 kN (where the modified Euler's metrics
converge; the preset's 4 rad/s is chaotic and its 60-s metrics move by 10-20 % with the step of
either scheme): RGD's torque, and the thesis's hysteretic law (Eqs. 3.2-3.3, thesis-field's, W_ref
245 kN) on the axial WOB (``axial.torque = "law"``). The reference is the modified Euler at 0.05 ms.
For each scheme and step it prints the physical metrics over the second half of the run (SS, stick
fraction, mean ROP, ROP and WOB standard deviations, bounce fraction), the largest relative error of
SS, mean ROP, ROP std and WOB std against the reference, and the wall time per simulated second of
stepping (the median over ``--repeats`` runs of ``--timed`` simulated seconds less that of runs of
10 steps, which build the model; one thread, no series recorded). Then, per tolerance, the largest
step of each scheme whose error and that of every smaller step is within it, and the ratio of their
steps and wall times. The machine is shared: the script prints ``uptime`` before and after.
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]

SPEED = 8.0
STEPS = {"modified_euler": (5e-4, 1e-3, 2e-3, 3e-3, 5e-3),
         "exact_modal": (5e-4, 1e-3, 2e-3, 3e-3, 5e-3, 1e-2, 2e-2)}
KEYS = ("severity", "mean_rop_m_s", "rop_std_m_s", "wob_std_n")


def config(case: str, scheme: str, dt: float, duration: float) -> dict:
    import drillpy
    c = drillpy.load_config(preset="rgd-field")
    if case == "law":
        c["axial"]["torque"] = "law"
        c["law"] = drillpy.load_config(preset="thesis-field")["law"]
    c["operation"]["top_speed_rad_s"] = SPEED
    c["simulation"].update(scheme=scheme, dt_s=dt, duration_s=duration, transient_s=duration / 2)
    return c


def run(case: str, scheme: str, dt: float, duration: float, repeats: int, timed: float) -> tuple[dict, float]:
    """The summary of a run of `duration` and the wall time per simulated second of stepping [s/s]: the
    median over `repeats` runs of `timed` seconds less the median of as many runs of 10 steps (the
    model's construction, the same in both)."""
    import drillpy
    from drillpy.model.simulation import simulate
    cfg = drillpy.load_config(config=config(case, scheme, dt, duration))
    long = drillpy.load_config(config=config(case, scheme, dt, timed))
    short = drillpy.load_config(config=config(case, scheme, dt, 10 * dt))

    def wall(c) -> float:
        walls = []
        for _ in range(repeats):
            t0 = time.perf_counter()
            simulate(c, record=False)
            walls.append(time.perf_counter() - t0)
        return statistics.median(walls)

    s = simulate(cfg, record=False).summary()
    return s, max(0.0, wall(long) - wall(short)) / (timed - 10 * dt)


def error(s: dict, ref: dict) -> float:
    return max(abs(s[k] / ref[k] - 1.0) for k in KEYS)


def _cell(best: tuple[float, float] | None) -> str:
    return "none" if best is None else f"{best[0] * 1e3:g}, {best[1] * 1e3:.2f} ms/s"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=60.0)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--timed", type=float, default=600.0, help="simulated seconds of the timed runs")
    a = ap.parse_args()
    print("uptime:", subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())
    print(f"rgd-field string, {SPEED:g} rad/s, 150 kN, {a.duration:g} s (second half measured), one thread")
    for case in ("rgd", "law"):
        ref, ref_wall = run(case, "modified_euler", 5e-5, a.duration, 1, a.duration)
        print(f"\ncase {case} ({'RGD torque' if case == 'rgd' else 'thesis law on the axial WOB'}); "
              f"reference modified_euler 0.05 ms ({ref_wall * 1e3:.1f} ms per simulated s)")
        print("| scheme | dt [ms] | SS | stick | mean ROP [mm/s] | ROP std [mm/s] | WOB std [kN] | bounce "
              "| max rel. error | wall [ms / simulated s] |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        print(f"| reference | 0.05 | {ref['severity']:.4f} | {ref['stick_fraction']:.4f} | "
              f"{ref['mean_rop_m_s'] * 1e3:.3f} | {ref['rop_std_m_s'] * 1e3:.3f} | {ref['wob_std_n'] / 1e3:.3f} | "
              f"{ref['bounce_fraction']:.3f} | 0 | {ref_wall * 1e3:.2f} |")
        rows = {}
        for scheme, steps in STEPS.items():
            rows[scheme] = []
            for dt in steps:
                s, wall = run(case, scheme, dt, a.duration, a.repeats, a.timed)
                e = error(s, ref)
                rows[scheme].append((dt, e, wall))
                print(f"| {scheme} | {dt * 1e3:g} | {s['severity']:.4f} | {s['stick_fraction']:.4f} | "
                      f"{s['mean_rop_m_s'] * 1e3:.3f} | {s['rop_std_m_s'] * 1e3:.3f} | {s['wob_std_n'] / 1e3:.3f} | "
                      f"{s['bounce_fraction']:.3f} | {e:.4f} | {wall * 1e3:.2f} |")
        print("\n| tolerance | modified_euler: dt [ms], wall | exact_modal: dt [ms], wall | steps ratio | wall ratio |")
        print("|---:|---|---|---:|---:|")
        for tol in (0.005, 0.01, 0.02, 0.05):
            best = {}
            for scheme, r in rows.items():
                ok = None
                for dt, e, wall in r:  # steps ascending: the largest step with it and all smaller ones within tol
                    if e > tol:
                        break
                    ok = (dt, wall)
                best[scheme] = ok
            me, ex = best["modified_euler"], best["exact_modal"]
            ratio = (f"{ex[0] / me[0]:.2f} | {me[1] / ex[1]:.2f}" if me and ex else "- | -")
            print(f"| {tol:g} | {_cell(me)} | {_cell(ex)} | {ratio} |")
    print("\nuptime:", subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())


if __name__ == "__main__":
    if any((REPO / "python" / "drillpy").glob("_core*.so")):
        sys.path.insert(0, str(REPO / "python"))
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    main()
