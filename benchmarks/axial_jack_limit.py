"""The rig's jack (axial.type = "jack", one WOB state) against the coupled model it reduces (issue 34).

    PYTHONPATH=python python3 benchmarks/axial_jack_limit.py [--duration 30] [--blades 1,2,4]

The jack of the rig model (drill/axial.hpp) is one state, W' = g (Omega_f - v) - (W - W_s) / tau. The
coupled model (axial.type = "rgd") with the jack top (axial.top = "jack") and RGD's cut gives the same
equation at first order. Take a bit that lags its steady rotation within the last blade sector, a
quasi-static axial string, and the jack's feed X' = V0 + kappa (W_s - W). Then

    W' = k (V0 + kappa (W_s - W) - d0 v / (2 pi)),   k = 1 / (1 / k_bar + 1 / (N a zeta eps)),

that is the jack with g = k d0 / (2 pi), tau = 1 / (kappa k) and Omega_f = 2 pi V0 / d0.

The two differ in their memory. RGD's cut remembers the lag over the last sector `t_N = 2 pi / (N
Omega)`, and under stick-slip `t_N` itself swings with the bit's past speed. The jack forgets it in
`tau`. So they agree where the jack forgets first, `t_N >> tau`.

This script runs both on the rig:
- the same string (Table 5.1), motor (its rating, 17.27 rad/s), law (Eq. 5.1 identified on sample
  175, on the WOB) and damping as `benchmarks/axial_rig_wob.py`;
- the coupled model with N blades, eps = sigma 30 MPa, a 2 mm/s feed, the wear flat that puts steady
  drilling's WOB at W_s = 565 N, and kappa for tau = 0.1 s;
- the torsional engine with the jack of the g above and the same tau and W_s.

It prints, after the first 5 s: SS, the stick fraction, the cycle frequency, the WOB's mean and its
standard deviation above 0.5 Hz, the WOB's correlation with the bit speed at the cycle, and the mean
top speed.
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "benchmarks"))

SET_FORCE, TAU, EPS, COMMAND = 565.0, 0.1, 30e6, 17.27  # the rgd-rig preset's (docs/presets.md)
TRANSIENT = 5.0


def _stats(r) -> dict:
    from axial_rig_wob import swing
    keep = r.t >= TRANSIENT
    wob = r.wob if r.axial is None else r.axial.wob
    m = swing(r.t[keep], r.bit_speed[keep], wob[keep])
    return dict(ss=r.severity, stick=r.stick_fraction, fc=m["fc"], wob_mean=m["wob_mean"], wob_sd=m["wob_sd_hp"],
                corr=m["corr"], top=float(np.mean(r.top_speed[keep])))


def compare(blades: int, duration: float = 30.0) -> dict:
    """Both models' statistics and the jack's parameters for a cut of `blades` cutting edges."""
    import drillpy
    from axial_rig_wob import RADIUS, axial_stiffness, coupled_config
    from drillpy.model.simulation import simulate
    from drillpy.records import rigsim
    rig = drillpy.load_config(preset="rgd-rig")  # its law (Eq. 5.1 identified on sample 175), motor, damping
    law, td = rig["law"], rig["top_drive"]
    motor = (td["slope_nms_rad"], td["inertia_kg_m2"], td["max_torque_nm"])
    base = rigsim.rig_config(law, 0.03, top_speed=COMMAND, wob=SET_FORCE, motor=motor, duration_s=duration)
    k = axial_stiffness(EPS, blades)
    kappa = 1.0 / (TAU * k)

    def coupled(flat: float, d: float) -> dict:
        c = coupled_config(base, EPS, flat, d, TRANSIENT if d > TRANSIENT else 0.0, (SET_FORCE, TAU))
        c["axial"]["bit"]["blades"] = blades
        c["axial"]["jack_admittance_m_s_n"] = kappa
        c["simulation"]["output_stride"] = 1
        return c

    lo, hi = 0.0, SET_FORCE / (RADIUS * EPS)  # the wear flat of steady drilling at the set force
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        s = simulate(drillpy.load_config(config=coupled(mid, 0.01))).summary()
        w0 = math.inf if s["steady_speed_rad_s"] is None else s["steady_wob_n"]
        lo, hi = (mid, hi) if w0 < SET_FORCE else (lo, mid)
    rc = simulate(drillpy.load_config(config=coupled(lo, duration)))
    sc = rc.summary()
    gain = k * sc["steady_depth_of_cut_m"] / (2.0 * math.pi)
    jack = rigsim.rig_config(law, 0.03, top_speed=COMMAND, wob=SET_FORCE, motor=motor, axial=(gain, TAU),
                             duration_s=duration)
    jack["simulation"].update(output_stride=1, start="steady")
    rj = simulate(drillpy.load_config(config=jack))
    return dict(blades=blades, gain=gain, kappa=kappa, t_n=2.0 * math.pi / (blades * sc["steady_speed_rad_s"]),
                coupled=_stats(rc), jack=_stats(rj))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=30.0)
    ap.add_argument("--blades", default="1,2,4")
    a = ap.parse_args()
    print(f"the rig under its motor at {COMMAND} rad/s, W_s {SET_FORCE:g} N, tau {TAU:g} s, eps {EPS / 1e6:g} MPa; "
          f"{a.duration:g} s, the first {TRANSIENT:g} s left out")
    print(f"{'N':>2} {'model':>8} {'t_N s':>6} {'g N/rad':>8} {'SS':>6} {'stick':>6} {'f_c Hz':>7} {'WOB mean':>9} "
          f"{'WOB sd':>7} {'corr':>6} {'top':>6}")
    for n in (int(x) for x in a.blades.split(",")):
        r = compare(n, a.duration)
        for name in ("coupled", "jack"):
            m = r[name]
            print(f"{n:>2} {name:>8} {r['t_n']:>6.3f} {r['gain']:>8.2f} {m['ss']:>6.3f} {m['stick']:>6.3f} "
                  f"{m['fc']:>7.3f} {m['wob_mean']:>9.1f} {m['wob_sd']:>7.2f} {m['corr']:>6.2f} {m['top']:>6.3f}")


if __name__ == "__main__":
    # run as a script: the in-tree build when there is one, else the installed drillpy
    if any((REPO / "python" / "drillpy").glob("_core*.so")):
        sys.path.insert(0, str(REPO / "python"))
    main()
