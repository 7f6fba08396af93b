"""Cost of a controlled top drive per simulation (issue 15), measured side by side in one run.

    PYTHONPATH=python python3 benchmarks/bench_controller.py [--repeats 7] [--same-regime-speed 30]

thesis-field (20 modes, modified Euler, dt 5.12e-4 s), 200 s without recording, one thread: the
median wall time per run of the ideal drive (the thesis), the open-loop motor, and the controlled
drive with each controller; the ratio to the ideal drive (target: at most 1.3).

Two comparisons, each measured in one run with the drives interleaved (repeat r runs every drive
once, so a slow spell of the shared machine hits them all):

* the issue's, at 14 rad/s, where the drives are in different regimes (the ideal, stiff and
  soft_speed drives in stick-slip, z_torque and the sampled PI out of it). The cost then follows the
  regime: the hysteretic law (Eq. 3.3) is solved by Newton iterations when the bit acceleration is
  small (tanh not saturated), at most steps of a smooth run, at few steps of a stick-slip cycle (at
  rest the law has no hysteresis term, in slip it is saturated);
* the same regime, at ``--same-regime-speed`` (default 30 rad/s), where every drive is out of
  stick-slip (the script checks SS < 0.5 for all): the ratio measures the drive.
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

if any((Path(__file__).resolve().parents[1] / "python" / "drillpy").glob("_core*.so")):

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python"))  # in-tree build, else the installed drillpy

DRIVES = {
    "ideal": None,
    "motor": {"type": "motor", "slope_nms_rad": 5.0e4, "inertia_kg_m2": 2000.0},
    **{c: {"type": "controlled", "inertia_kg_m2": 2000.0, "controller": {"type": c}}
       for c in ("stiff", "soft_speed", "z_torque")},
    "pi (sampled 10 ms)": {"type": "controlled", "inertia_kg_m2": 2000.0,
                           "controller": {"type": "pi", "kp_nms_rad": 930.0, "ki_nm_rad": 300.0,
                                          "sample_time_s": 0.01}},
}


def measure(configs: dict, speed: float, repeats: int) -> dict:
    """Median wall time [s] and SS of one run per drive at ``speed`` [rad/s], drives interleaved.

    Parameters
    ----------
    configs : dict
        Drive name -> configuration.
    speed : float
        Top speed [rad/s].
    repeats : int
        Timed runs per drive.

    Returns
    -------
    dict
        Drive name -> (median time [s], SS [-]).
    """
    import drillpy
    ss = {name: drillpy.simulate(cfg, speed, record=False).severity for name, cfg in configs.items()}  # warm-up
    runs = {name: [] for name in configs}
    for _ in range(repeats):
        for name, cfg in configs.items():
            t0 = time.perf_counter()
            drillpy.simulate(cfg, speed, record=False)
            runs[name].append(time.perf_counter() - t0)
    return {name: (statistics.median(runs[name]), ss[name]) for name in configs}


def report(title: str, times: dict) -> float:
    """Print one comparison; returns the largest controller cost relative to the ideal drive.

    Parameters
    ----------
    title : str
        Heading.
    times : dict
        Drive name -> (median time [s], SS [-]) from :func:`measure`.

    Returns
    -------
    float
        The largest ratio of a controlled drive's median time to the ideal drive's.
    """
    ref = times["ideal"][0]
    print(title)
    print(f"{'drive':22s} {'median [s]':>11s} {'x ideal':>8s} {'SS':>7s}")
    for name, (t, ss) in times.items():
        print(f"{name:22s} {t:11.4f} {t / ref:8.2f} {ss:7.3f}")
    worst = max(t for n, (t, _) in times.items() if n not in ("ideal", "motor")) / ref
    print(f"largest controller cost: {worst:.2f} x the ideal drive")
    return worst


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--same-regime-speed", type=float, default=30.0,
                    help="top speed [rad/s] where every drive is out of stick-slip")
    a = ap.parse_args()
    import drillpy
    from drillpy.model.config import with_overrides
    base = with_overrides(drillpy.load_config(preset="thesis-field"), duration=200.0, transient=100.0)
    configs = {name: base if drive is None else with_overrides(base, top_drive=drive) for name, drive in DRIVES.items()}
    report("14 rad/s (the issue's comparison; drives in different regimes)", measure(configs, 14.0, a.repeats))
    print()
    same = measure(configs, a.same_regime_speed, a.repeats)
    report(f"{a.same_regime_speed:g} rad/s (same regime: every drive out of stick-slip)", same)
    sticking = [name for name, (_, ss) in same.items() if not ss < 0.5]
    if sticking:
        print(f"warning: SS >= 0.5 at {a.same_regime_speed:g} rad/s for {', '.join(sticking)}: not one regime")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
