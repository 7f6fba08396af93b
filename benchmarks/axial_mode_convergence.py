"""Convergence of the rgd-field preset in its axial modes: the growth rate of the steady state's 1 %
disturbance and the severity as the retained axial modes grow (10, the preset's, to 80).

    PYTHONPATH=python python3 benchmarks/axial_mode_convergence.py

On a uniform pipe with a heavy axial damping ratio (the MATLAB comparison's string,
benchmarks/axial_octave_comparison.py) 10 axial modes leave the highest one unstable; this checks
the preset's own string (drill pipe and BHA, 5 % axial damping) at 4 rad/s (stick-slip) and
12 rad/s (steady drilling), 20 s each with a 10 s transient. The time step shrinks with the modes
(the bound of Eq. A.7 over the axial modes).
"""
from __future__ import annotations

import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
if any((REPO / "python" / "drillpy").glob("_core*.so")):  # in-tree build, else the installed drillpy
    sys.path.insert(0, str(REPO / "python"))
sys.path.insert(0, str(REPO / "benchmarks"))


def main() -> None:
    import drillpy
    from drillpy.model.simulation import simulate

    from axial_octave_comparison import envelope_growth
    print(f"{'top speed':>10} {'axial modes':>11} {'dt [ms]':>8} {'growth [1/s]':>13} {'SS':>7} {'stick':>7}")
    for om in (4.0, 12.0):
        for modes, dt in ((10, 5e-4), (20, 5e-4), (40, 2.5e-4), (80, 1e-4)):
            c = drillpy.load_config(preset="rgd-field")
            c["axial"]["modes"] = modes
            c["operation"]["top_speed_rad_s"] = om
            c["simulation"].update(dt_s=dt, duration_s=20.0, transient_s=10.0)
            r = simulate(drillpy.load_config(config=c))
            s = r.summary()
            print(f"{om:>10g} {modes:>11d} {dt * 1e3:>8g} {envelope_growth(r.t, r.bit_speed, om):>13.3f} "
                  f"{s['severity']:>7.3f} {s['stick_fraction']:>7.3f}")


if __name__ == "__main__":
    main()
