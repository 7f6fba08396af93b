"""The exact modal scheme with the thesis's hysteretic law on the axial WOB (issue 34): from which
starts and at which steps does it reach the fine modified Euler's stick-slip cycle?

    PYTHONPATH=python python3 benchmarks/axial_law_starts.py

The ``rgd-field`` string at 8 rad/s and 150 kN with thesis-field's law (Eqs. 3.2-3.3) on the axial W
(``benchmarks/axial_scheme_convergence.py``'s "law" case), 60 s runs, the second half measured, from
nine starts (``axial.disturbance``: the bit's axial speed (1 - disturbance) V0 at the start) and with
the law's hysteresis beta1 at the thesis's 0.14, at 0.07 and at 0. Prints SS per start for the
modified Euler at 0.05 ms and the exact scheme at 1-4 ms; then, for beta1 from 0.142 to 0.155, how
many starts end without stick-slip on the modified Euler at 0.05 and 0.1 ms and on the exact scheme at
1 and 2.5 ms (the model's own band of two regimes). About 20 s.
"""
from __future__ import annotations

import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "benchmarks"))
if any((REPO / "python" / "drillpy").glob("_core*.so")):  # in-tree build, else the installed drillpy
    sys.path.insert(0, str(REPO / "python"))

STARTS = (0.0, 0.001, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0)
RUNS = (("modified_euler", 5e-5), ("exact_modal", 1e-3), ("exact_modal", 1.5e-3), ("exact_modal", 2e-3),
        ("exact_modal", 2.5e-3), ("exact_modal", 3e-3), ("exact_modal", 4e-3))


def severity(scheme: str, dt: float, disturbance: float, beta1: float) -> float:
    import drillpy
    from drillpy.model.simulation import simulate
    from axial_scheme_convergence import config
    c = config("law", scheme, dt, 60.0)
    c["axial"]["disturbance"] = disturbance
    c["law"]["beta1"] = beta1
    return simulate(drillpy.load_config(config=c), record=False).summary()["severity"]


def main() -> int:
    print("SS per start (axial.disturbance " + ", ".join(f"{d:g}" for d in STARTS) + "); 'no stick' counts SS < 0.6")
    for beta1 in (0.14, 0.07, 0.0):
        print(f"\nbeta1 = {beta1:g}")
        for scheme, dt in RUNS:
            ss = [severity(scheme, dt, d, beta1) for d in STARTS]
            print(f"  {scheme:<14} {1e3 * dt:4.2f} ms: " + " ".join(f"{x:.3f}" for x in ss)
                  + f"   no stick from {sum(x < 0.6 for x in ss)} of {len(ss)} starts")
            sys.stdout.flush()
    print("\nstarts (of 9) that end without stick-slip, by beta1")
    scan = (("modified_euler", 5e-5), ("modified_euler", 1e-4), ("exact_modal", 1e-3), ("exact_modal", 2.5e-3))
    print("  beta1  " + "  ".join(f"{s[:5]} {1e3 * dt:g} ms" for s, dt in scan))
    for beta1 in (0.14, 0.142, 0.145, 0.148, 0.15, 0.155):
        counts = [sum(severity(s, dt, d, beta1) < 0.6 for d in STARTS) for s, dt in scan]
        print(f"  {beta1:<6g} " + "  ".join(f"{c:>12d}" for c in counts))
        sys.stdout.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())
