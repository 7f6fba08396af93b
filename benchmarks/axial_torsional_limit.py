"""The coupled model (axial.type = rgd) against the torsional engine in the limit where the RGD bit's
torque is a constant: the cutting torque share T_c / T0 taken to zero.

    PYTHONPATH=python python3 benchmarks/axial_torsional_limit.py [--duration 10] [--scheme exact_modal --dt 0.005]
        [--drive motor]

Why not the infinite axial stiffness: (1) the configuration cannot stiffen the axial string alone,
since a section's G = E / (2 (1 + nu)) with nu in (-1, 0.5) ties E to G (at most E = 3 G: 231 GPa
for G = 77 GPa); (2) even a rigid string does not freeze the depth of cut: with a feed top the bit
is at U = V0 t, so d = N [U(t) - U(t - t_N)] = N V0 t_N(t), and t_N, from Phi(t) - Phi(t - t_N) =
2 pi / N, follows the bit's rotation over the last blade sector. The RGD torque
T = a^2 eps d / 2 + T_f is then a state-dependent-delay law, which no law of the torsional engine is.
The torque is a constant only when its cutting part a^2 eps d / 2 vanishes against the contact part
T_f: this script scales the intrinsic specific energy eps by s (the rgd-field bit, feed top at
30 m/h, 4 rad/s, 10 axial modes) and runs the torsional engine on the same string with the
constant-torque law that is its limit, the polynomial law (Eq. 5.1) with a0 = a2 = a4 = T0 and the
other coefficients zero: T = T0 sign(Omega), stuck while |T| <= T0, T0 the coupled model's steady
torque T_c + T_f. Both start from steady drilling with the bit 1 % slower, on the same scheme and step
(the preset's modified Euler at 0.5 ms by default; ``--scheme exact_modal``: the coupled exact modal
step against the torsional engine's, exact_modal.hpp). ``--drive motor`` turns both strings with the
same open-loop motor (drives/motor.hpp: J_m 2000 kg m^2, c_m drooping the top by 20 % under T0 at the
command): both start at their own steady drilling speed under it, Omega_s = Omega_c - T0 / c_m (the
coupled model's T0 depends on Omega_s through the depth of cut, to first order in the cutting share).

Prints, per s: T_c / T0, the largest difference of the bit speed (over Omega) and of the torque on
bit (over T0) between the two runs, both over T_c / T0 (constant: first order in the cutting share),
and the severities.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]

OMEGA, FEED = 4.0, 30 / 3600


MOTOR_INERTIA, MOTOR_DROOP = 2000.0, 0.2


def _scheme(c: dict, scheme: str | None, dt: float | None) -> None:
    if scheme is not None:
        c["simulation"]["scheme"] = scheme
    if dt is not None:
        c["simulation"]["dt_s"] = dt


def motor(torque: float) -> dict:
    """The open-loop motor that droops the top by MOTOR_DROOP under `torque` at OMEGA (no torque limit)."""
    return dict(type="motor", inertia_kg_m2=MOTOR_INERTIA, slope_nms_rad=torque / (MOTOR_DROOP * OMEGA))


def coupled_config(scale: float, duration: float, zeta: float | None = None, scheme: str | None = None,
                   dt: float | None = None) -> dict:
    import drillpy
    c = drillpy.load_config(preset="rgd-field")
    c["axial"].update(top="feed", rop_m_s=FEED)
    c["axial"]["bit"]["specific_energy_pa"] *= scale
    if zeta is not None:
        c["axial"]["bit"]["zeta"] = zeta
    c["operation"].pop("wob_n")
    c["operation"]["top_speed_rad_s"] = OMEGA
    c["simulation"].update(duration_s=duration, transient_s=duration / 2, output_stride=1)
    _scheme(c, scheme, dt)
    return c


def constant_torque_config(torque: float, duration: float, scheme: str | None = None, dt: float | None = None) -> dict:
    """The same string, the torsional engine, T = torque sign(Omega) (stuck while |T| <= torque)."""
    import drillpy
    c = drillpy.load_config(preset="rgd-field")
    del c["axial"]
    c["law"] = dict(type="polynomial", a0=torque, a1=0.0, a2=torque, a3=0.0, a4=torque, a5=0.0, a6=0.0,
                    a7=0.0, ref_speed=1.0, gain=1.0, wob_ref_n=1e5, speed_unit="rad_s")
    c["operation"].update(wob_n=1e5, top_speed_rad_s=OMEGA)
    c["simulation"].update(duration_s=duration, transient_s=duration / 2, output_stride=1)
    _scheme(c, scheme, dt)
    return c


def compare(scale: float, duration: float = 10.0, zeta: float | None = None, scheme: str | None = None,
            dt: float | None = None, drive: str = "ideal") -> dict:
    """Both runs and their differences; with drive "motor" the motor of motor(T0 at OMEGA) on both, and
    dtop the largest difference of the top speeds over OMEGA."""
    import drillpy
    from drillpy.model.simulation import simulate
    cc = coupled_config(scale, duration, zeta, scheme, dt)
    b = cc["axial"]["bit"]
    Tf = b["gamma"] * b["mu"] * b["radius_m"] ** 2 * b["wear_flat_m"] * b["contact_strength_pa"] / 2
    td = None
    if drive == "motor":  # RGD's T0 at the command (d0 = 2 pi V0 / Omega), for the slope; each model
        d0 = 2.0 * np.pi * FEED / OMEGA  # then solves its own Omega_s
        td = motor(0.5 * b["radius_m"] ** 2 * b["specific_energy_pa"] * d0 + Tf)
        cc["top_drive"] = td
    rc = simulate(drillpy.load_config(config=cc))
    sc = rc.summary()
    T0 = sc["steady_torque_nm"]
    ct = constant_torque_config(T0, duration, scheme, dt)
    if td is not None:
        ct["top_drive"] = td
    rt = simulate(drillpy.load_config(config=ct))
    d = rc.axial.depth_of_cut
    return dict(scale=scale, T0=T0, Tc=T0 - Tf, share=(T0 - Tf) / T0,
                d_dev=float(np.max(np.abs(d / sc["steady_depth_of_cut_m"] - 1.0))),
                dspeed=float(np.max(np.abs(rc.bit_speed - rt.bit_speed)) / OMEGA),
                dtop=float(np.max(np.abs(rc.top_speed - rt.top_speed)) / OMEGA),
                dtorque=float(np.max(np.abs(rc.torque_on_bit - rt.torque_on_bit)) / T0),
                ss_coupled=sc["severity"], ss_torsional=rt.summary()["severity"],
                top_mean=float(np.mean(rc.top_speed)))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=10.0)
    ap.add_argument("--scheme", default=None, help="simulation.scheme of both runs (default: the preset's)")
    ap.add_argument("--dt", type=float, default=None, help="simulation.dt_s of both runs (default: the preset's)")
    ap.add_argument("--drive", choices=("ideal", "motor"), default="ideal",
                    help="the top drive of both runs (motor: J_m 2000 kg m^2, 20 %% droop under T0)")
    a = ap.parse_args()
    print(f"rgd-field string, feed top {FEED * 3600:g} m/h, {OMEGA:g} rad/s, {a.duration:g} s; "
          f"eps scaled by s; torsional engine: T = T0 sign(Omega); "
          f"scheme {a.scheme or 'preset'}, dt {a.dt or 'preset'}, drive {a.drive}")
    print(f"{'s':>8} {'Tc/T0':>10} {'max|dOmega|/Omega':>18} {'/(Tc/T0)':>9} {'max|dT|/T0':>11} "
          f"{'/(Tc/T0)':>9} {'max|dtop|/Omega':>15} {'max|d/d0-1|':>11} {'SS coupled':>10} {'SS torsional':>12}")
    for s in (1.0, 1e-1, 1e-2, 1e-3, 1e-4, 1e-6, 1e-9, 1e-12):
        r = compare(s, a.duration, scheme=a.scheme, dt=a.dt, drive=a.drive)
        print(f"{s:>8.0e} {r['share']:>10.3e} {r['dspeed']:>18.3e} {r['dspeed'] / r['share']:>9.4f} "
              f"{r['dtorque']:>11.3e} {r['dtorque'] / r['share']:>9.4f} {r['dtop']:>15.3e} {r['d_dev']:>11.4f} "
              f"{r['ss_coupled']:>10.4f} {r['ss_torsional']:>12.4f}")


if __name__ == "__main__":
    # run as a script: the in-tree build when there is one, else the installed drillpy (imported by a test, the
    # module leaves sys.path alone: a Dask worker spawned later inherits it and would import the source tree)
    if any((REPO / "python" / "drillpy").glob("_core*.so")):
        sys.path.insert(0, str(REPO / "python"))
    main()
