"""drillpy's axial-torsional model (axial.type = rgd) beside the MATLAB code of Aarsnes and van de
Wouw (the distributed axial-torsional string with the RGD bit, folder ``Coupled`` of their public
repository AxialTorsionalDrillString) run under GNU Octave, on the same parameters.

    PYTHONPATH=python python3 benchmarks/axial_octave_comparison.py --matlab-dir DIR [--duration 30]

DIR is the folder holding their ``parameters.m`` and ``waveStep_transportBRI.m`` (or the checkout
whose ``Coupled`` subfolder does). Nothing is fetched: without ``octave`` on the PATH or without
DIR the script prints "skipped: ..." and exits 0. Their files are only read (``addpath``); the
driver that steps their ``waveStep_transportBRI`` is written by this script into a temporary
folder, never into the repository.

Their model: one uniform 2000 m pipe, the axial and torsional wave equations in Riemann invariants
(first-order upwind, 1000 cells), a velocity-imposed top (feed V0 and speed omega0), distributed
viscous damping -2 k v (k = 1/s for both motions), no bit mass or inertia, and the bit law of RGD
with the depth of cut transported on a grid over one blade sector (first-order upwind). drillpy is
configured with the same string, the feed top (``axial.top = feed``), the torsional damping as
Rayleigh damping D = 2 k_t M (exactly theirs), the axial damping two ways: ``axial.damping =
distributed`` with ``damping_rate_per_s = k_a`` (D = 2 k_a M, exactly theirs: the ratio k_a / omega_j
on axial mode j) and, for comparison, ``modal`` with one ratio for all axial modes, theirs on the first
mode (k_a / omega_1); and gamma = 2, because their contact torque is gamma mu a W_f, without RGD's 1/2.

Both start from steady drilling with the bit's axial speed 1 % below V0 (and the torsion disturbed
by 1 %: drillpy at the bit, theirs along the whole string) and the script prints, per operating
point, the steady WOB, torque, depth of cut and ROP (the closed forms of the bit law in each
model), the first natural frequencies, the growth rate of the disturbance over the first seconds
and the outcome after half the run (steady or stick-slip: bit speed range, stick fraction, the
dominant period and the WOB and ROP ranges).
"""
from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]

# Their parameters.m (Coupled): drill pipe radii, steel, length, damping, bit.
L, RO, RI, E, G, RHO = 2000.0, 0.0635, 0.054, 200e9, 77e9, 8e3
KA = KT = 1.0  # [1/s]: v_t = c^2 u_xx - 2 k v
BIT = dict(radius_m=0.108, specific_energy_pa=60e6, contact_strength_pa=60e6, zeta=0.6,
           wear_flat_m=0.011, mu=0.6, blades=4)
GAMMA_THEIRS = 1.0
C_A, C_T = np.sqrt(E / RHO), np.sqrt(G / RHO)

# (name, top speed [rad/s], feed [m/s], axial damping k_a [1/s]): their parameters.m's point, three
# times its feed, and that again without axial damping in either model.
POINTS = [("30 RPM, 30 m/h (their parameters.m)", np.pi, 30 / 3600, KA),
          ("30 RPM, 90 m/h", np.pi, 90 / 3600, KA),
          ("30 RPM, 90 m/h, no axial damping (k_a = 0 in both)", np.pi, 90 / 3600, 0.0)]

DRIVER = r"""function axval_driver(mdir, OM, V0, T1, delta, outfile, KA, OMX)
%% Steps their waveStep_transportBRI from steady drilling; writes t, vb, ob, d, W, T at the bit.
addpath(mdir);
p = parameters(); p.ka = KA;
p.omega0 = OM; p.V0 = V0; p.dNom = 2*pi*V0/(OM*p.N); p.tN = 2*pi/(p.N*OM); p.R = V0/OM;
dx = p.L/p.P; dts = dx/max(p.c_a, p.c_t)*0.99; dts = p.dt/ceil(p.dt/dts);
p.omegaMAX = OMX*OM; p.Pl = floor(1/(dts*p.omegaMAX));   %% their rule for the sector grid: OMX = 5
Nt = round(T1/p.dt);
W0 = p.K_a*p.N*p.dNom + p.Wf; T0 = p.K_t*p.N*p.dNom + p.Tf*p.Wf;
i = (1:p.P).';
h = W0/(p.Ap*p.E) + 2*p.ka*V0*(p.P - i + 0.5)*dx/p.c_a^2;   %% steady strain under the drag
f = T0/(p.Jp*p.G) + 2*p.kt*OM*(p.P - i + 0.5)*dx/p.c_t^2;
x = [h; (1 - delta)*V0*ones(p.P, 1); f; (1 - delta)*OM*ones(p.P, 1); p.dNom*(1:p.Pl).'/p.Pl];
u.wb = 0; u.tb = 0; u.obEst = OM;
out = zeros(Nt + 1, 6);
out(1, :) = [0, x(2*p.P), x(4*p.P), p.N*p.dNom, p.Ap*p.E*x(p.P), p.Jp*p.G*x(3*p.P)];
for k = 1:Nt
  [xn, y] = waveStep_transportBRI(p, x, u); x = xn(:);
  out(k + 1, :) = [k*p.dt, x(2*p.P), x(4*p.P), y(1), p.Ap*p.E*x(p.P), p.Jp*p.G*x(3*p.P)];
end
fid = fopen(outfile, 'w'); fprintf(fid, '%.10g,%.10g,%.10g,%.10g,%.10g,%.10g\n', out.'); fclose(fid);
fid = fopen([outfile '.info'], 'w'); fprintf(fid, '%.10g %.10g %d %d %.10g\n', W0, T0, p.P, p.Pl, p.dt); fclose(fid);
end
"""


def matlab_folder(d: Path) -> Path | None:
    for cand in (d, d / "Coupled"):
        if (cand / "parameters.m").is_file() and (cand / "waveStep_transportBRI.m").is_file():
            return cand
    return None


def run_octave(mdir: Path, om: float, v0: float, duration: float, delta: float, ka: float,
               omx: float = 5.0) -> tuple[dict, float]:
    """Their model from steady drilling; ``omx``: their sector grid is sized for bit speeds up to ``omx``
    times the top's (their rule 5: Courant number N / (2 pi omx) at the top's speed)."""
    with tempfile.TemporaryDirectory(prefix="axval-octave-") as tmp:
        (Path(tmp) / "axval_driver.m").write_text(DRIVER)
        out = Path(tmp) / "bit.csv"
        expr = f"axval_driver('{mdir}', {om!r}, {v0!r}, {duration!r}, {delta!r}, '{out}', {ka!r}, {omx!r})"
        t0 = time.perf_counter()
        r = subprocess.run(["octave", "--no-gui", "--quiet", "--no-init-file", "--eval", expr],
                           cwd=tmp, capture_output=True, text=True, timeout=3600)
        wall = time.perf_counter() - t0
        if r.returncode != 0 or not out.is_file():
            raise RuntimeError(f"octave failed ({r.returncode}): {r.stderr.strip()[-800:]}")
        a = np.loadtxt(out, delimiter=",")
        W0, T0, P, Pl, dt = np.loadtxt(str(out) + ".info")
    s = dict(t=a[:, 0], vb=a[:, 1], ob=a[:, 2], d=a[:, 3], wob=a[:, 4], tob=a[:, 5],
             steady_wob=W0, steady_torque=T0, steady_depth=2 * np.pi * v0 / om, steady_rop=v0,
             info=f"{int(P)} cells, {int(Pl)} sector cells, dt {dt:g} s")
    return s, wall


def drillpy_config(om: float, v0: float, duration: float, delta: float, *, ka=KA, elements=200, modes=40,
                   axial_modes=40, dt=2.5e-4, gamma=2.0 * GAMMA_THEIRS, axial_e=E, damping="modal"):
    """drillpy on their parameters; ``damping``: ``"modal"`` (the ratio k_a / omega_1 on every axial
    mode) or ``"distributed"`` (D = 2 k_a M, theirs)."""
    import drillpy
    cfg = drillpy.load_config(preset="rgd-field")
    cfg["string"] = {"lumped_inertias": [], "sections": [dict(
        name="pipe", length_m=L, elements=elements, outer_radius_m=RO, inner_radius_m=RI,
        youngs_modulus_pa=axial_e, poisson_ratio=axial_e / (2 * G) - 1, density_kg_m3=RHO)]}
    f1, f2 = C_T / (4 * L), 3 * C_T / (4 * L)  # D = 2 k_t M: ratio k_t / omega at every mode
    cfg["damping"] = {"type": "rayleigh", "pairs": [[f1, KT / (2 * np.pi * f1)], [f2, KT / (2 * np.pi * f2)]]}
    cfg["rom"] = {"modes": modes}
    ax = cfg["axial"]
    ax.update(top="feed", rop_m_s=v0, modes=axial_modes, disturbance=delta)
    if damping == "distributed":
        ax.pop("damping_ratio", None)
        ax.update(damping="distributed", damping_rate_per_s=ka)
    else:
        ax.update(damping="modal", damping_ratio=ka / (2 * np.pi * np.sqrt(axial_e / RHO) / (4 * L)))
    ax["bit"] = dict(BIT, gamma=gamma)
    cfg["operation"] = {"top_speed_rad_s": om, "bit_viscous_nms": 0.0, "string_friction_nm": 0.0}
    cfg["simulation"].update(duration_s=duration, transient_s=duration / 2, dt_s=dt, output_stride=1)
    return cfg


def run_drillpy(om, v0, duration, delta, ka, damping="modal"):
    import drillpy
    from drillpy.model.simulation import simulate
    # distributed: the axial modes' ratio falls as 1 / omega_j, and 40 axial modes leave the highest one
    # unstable (a truncation artefact, the script's "as the axial modes grow" lines): 80 modes at 0.1 ms
    am, dt = (80, 1e-4) if damping == "distributed" else (40, 2.5e-4)
    cfg = drillpy_config(om, v0, duration, delta, ka=ka, damping=damping, axial_modes=am, dt=dt)
    t0 = time.perf_counter()
    r = simulate(drillpy.load_config(config=cfg))
    wall = time.perf_counter() - t0
    ax = r.axial
    s = r.summary()
    return dict(t=ax.t, vb=ax.rop, ob=r.bit_speed, d=ax.depth_of_cut, wob=ax.wob, tob=r.torque_on_bit,
                steady_wob=s["steady_wob_n"], steady_torque=s["steady_torque_nm"],
                steady_depth=s["steady_depth_of_cut_m"], steady_rop=s["steady_rop_m_s"],
                info=f"200 elements, 40 torsional + {am} axial modes, dt {dt * 1e3:g} ms, {damping} axial damping",
                cfg=cfg), wall


def axial_fe_frequencies(n_el: int, n: int) -> np.ndarray:
    """Fixed-free axial frequencies [Hz] of the bar elements drillpy's axial string uses
    (k_e = E A / h [1 -1; -1 1], m_e = rho A h / 6 [2 1; 1 2], docs/axial.md)."""
    h = L / n_el
    K = np.zeros((n_el + 1, n_el + 1))
    M = np.zeros_like(K)
    for e in range(n_el):
        K[e:e + 2, e:e + 2] += E / h * np.array([[1, -1], [-1, 1]])
        M[e:e + 2, e:e + 2] += RHO * h / 6 * np.array([[2, 1], [1, 2]])
    w2 = np.linalg.eigvals(np.linalg.solve(M[1:, 1:], K[1:, 1:])).real
    return np.sqrt(np.sort(w2)[:n]) / (2 * np.pi)


def envelope_growth(t, x, scale: float, t_end: float = 10.0) -> float:
    """Growth rate [1/s] of the disturbance while it is small: the least-squares slope of ln(range of
    x over 1-s windows) from 0.5 s to t_end, over the windows whose range stays below 20 % of scale
    (the same rule for both models; NaN with fewer than three such windows)."""
    ts, lr = [], []
    for a in np.arange(0.5, t_end, 1.0):
        r = np.ptp(x[(t >= a) & (t < a + 1.0)])
        if r >= 0.2 * scale:
            break
        ts.append(a + 0.5)
        lr.append(np.log(r))
    return float(np.polyfit(ts, lr, 1)[0]) if len(ts) >= 3 else float("nan")


def dominant_period(t, x) -> float:
    y = x - x.mean()
    n = len(y)
    F = np.abs(np.fft.rfft(y * np.hanning(n)))
    f = np.fft.rfftfreq(n, t[1] - t[0])
    k = int(np.argmax(F[1:]) + 1)
    return float(1.0 / f[k])


def outcome(s: dict, om: float) -> dict:
    t = s["t"]
    m = t >= t[-1] / 2
    ob = s["ob"][m]
    return dict(ob_min=ob.min(), ob_max=ob.max(), stick=float(np.mean(ob < 0.05 * om)),
                period=dominant_period(t[m], ob), vb_min=s["vb"][m].min(), vb_max=s["vb"][m].max(),
                wob_min=s["wob"][m].min(), wob_max=s["wob"][m].max(), tob_mean=s["tob"][m].mean())


MODELS = ("octave", "drillpy, distributed", "drillpy, modal, ratio of mode 1", "drillpy, modal, ratio of mode 2")


def feed_boundary(mdir: Path, om: float, lo: float, hi: float, steps: int, delta: float, models=MODELS,
                  omx: float = 5.0) -> dict:
    """The feed [m/s] at which steady drilling turns unstable at top speed om, in each model:
    bisection on the sign of the bit speed's growth rate (windows from 2.5 s to 12 s, after the
    fastest-decaying modes), between a stable lo and an unstable hi."""
    def rate(model, v0):
        if model == "octave":
            s, _ = run_octave(mdir, om, v0, 12.0, delta, KA, omx)
        elif model == "drillpy, distributed":
            s, _ = run_drillpy(om, v0, 12.0, delta, KA, "distributed")
        elif model == "drillpy, modal, ratio of mode 1":
            s, _ = run_drillpy(om, v0, 12.0, delta, KA)
        else:  # drillpy with the axial ratio theirs has on the second axial mode
            import drillpy
            from drillpy.model.simulation import simulate
            cfg = drillpy_config(om, v0, 12.0, delta)
            cfg["axial"]["damping_ratio"] = KA / (2 * np.pi * 3 * C_A / (4 * L))
            r = simulate(drillpy.load_config(config=cfg))
            s = dict(t=r.axial.t, ob=r.bit_speed)
        t, ob = s["t"], s["ob"]
        m = t >= 2.0
        r = envelope_growth(t[m] - 2.0, ob[m], om, t_end=10.0)
        if np.isnan(r):  # grown past 20 % of the top speed within the windows: unstable
            r = float("inf") if np.ptp(ob[m]) >= 0.2 * om else r
        return r
    out = {}
    for model in models:
        a, b = lo, hi
        ra, rb = rate(model, a), rate(model, b)
        trail = [(a, ra), (b, rb)]
        if not (ra < 0.0 < rb):
            out[model] = (None, trail)
            continue
        for _ in range(steps):
            c = 0.5 * (a + b)
            rc = rate(model, c)
            trail.append((c, rc))
            a, b = (c, b) if rc < 0.0 else (a, c)
        out[model] = ((a, b), trail)
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--matlab-dir", type=Path, default=None,
                    help="folder with their parameters.m and waveStep_transportBRI.m (or its parent)")
    ap.add_argument("--duration", type=float, default=30.0, help="simulated time per run [s]")
    ap.add_argument("--disturbance", type=float, default=0.01)
    ap.add_argument("--boundary", action="store_true",
                    help="also bisect the feed at which steady drilling turns unstable at 30 RPM "
                         "(between 30 and 120 m/h) in both models")
    ap.add_argument("--sector-courant", type=float, default=None,
                    help="size their depth-of-cut grid for this Courant number at the top's speed instead of their "
                         "rule (bit speeds up to 5 x the top's: Courant N / (10 pi) = 0.127); near 1 their transport of "
                         "the rock surface is nearly exact, but bit speeds above 1 / C times the top's break it")
    a = ap.parse_args()
    omx = 5.0 if a.sector_courant is None else BIT["blades"] / (2 * np.pi * a.sector_courant)
    if shutil.which("octave") is None:
        print("skipped: octave is not on the PATH (Debian: apt-get install octave)")
        return 0
    mdir = matlab_folder(a.matlab_dir.resolve()) if a.matlab_dir is not None else None
    if mdir is None:
        print(f"skipped: no parameters.m and waveStep_transportBRI.m in --matlab-dir {a.matlab_dir} "
              "(their repository's Coupled folder)")
        return 0
    from drillpy import _core
    from drillpy.model.config import engine_config

    cfg0 = drillpy_config(np.pi, 30 / 3600, 1.0, a.disturbance)
    ft = np.asarray(_core.natural_frequencies(engine_config(cfg0), 2)).ravel()
    fa = axial_fe_frequencies(200, 2)
    print("natural frequencies of the string, fixed top, free bit [Hz]:")
    print(f"  torsional: wave equation (theirs, continuum) {C_T / (4 * L):.4f}, {3 * C_T / (4 * L):.4f}; "
          f"drillpy (200 elements) {ft[0]:.4f}, {ft[1]:.4f}")
    print(f"  axial:     wave equation (theirs, continuum) {C_A / (4 * L):.4f}, {3 * C_A / (4 * L):.4f}; "
          f"drillpy's bar elements (200) {fa[0]:.4f}, {fa[1]:.4f}")
    for name, om, v0, ka in POINTS:
        oc, wall_o = run_octave(mdir, om, v0, a.duration, a.disturbance, ka, omx)
        runs = [oc] + [run_drillpy(om, v0, a.duration, a.disturbance, ka, damping)[0]
                       for damping in ("distributed", "modal")]
        print(f"\n{name}: top speed {om:.4f} rad/s, feed {v0 * 3600:.0f} m/h, {a.duration:g} s, "
              f"start: steady drilling, bit {a.disturbance:g} slower")
        print(f"  Octave ({oc['info']}): {wall_o:.1f} s wall;  drillpy ({runs[1]['info']} / modal)")
        cols = ("Octave", "distributed", "modal")

        def row(label, f, fmt):
            return (label, [f(r) for r in runs], fmt)
        rows = [row("steady WOB [kN]", lambda r: r["steady_wob"] / 1e3, ".3f"),
                row("steady torque [kN m]", lambda r: r["steady_torque"] / 1e3, ".4f"),
                row("steady depth of cut [mm/rev]", lambda r: r["steady_depth"] * 1e3, ".4f"),
                row("steady ROP [m/h]", lambda r: r["steady_rop"] * 3600, ".3f"),
                row("bit WOB at t = 0 [kN]", lambda r: r["wob"][0] / 1e3, ".3f"),
                row("growth rate of the bit's axial speed range while small [1/s]",
                    lambda r: envelope_growth(r["t"], r["vb"], v0), ".3f"),
                row("growth rate of the bit speed range while small [1/s]",
                    lambda r: envelope_growth(r["t"], r["ob"], om), ".3f"),
                row("dominant period of the bit speed over 0-6 s [s]",
                    lambda r: dominant_period(r["t"][r["t"] < 6.0], r["ob"][r["t"] < 6.0]), ".3f")]
        late = f"second half ({a.duration / 2:g}-{a.duration:g} s)"
        us = [outcome(r, om) for r in runs]
        for label, key, scale, fmt in (("bit speed min [rad/s]", "ob_min", 1, ".3f"),
                                       ("bit speed max [rad/s]", "ob_max", 1, ".3f"),
                                       ("stick fraction (bit speed < 5 % of the top's)", "stick", 1, ".3f"),
                                       ("dominant period of the bit speed [s]", "period", 1, ".3f"),
                                       ("bit axial speed min [mm/s]", "vb_min", 1e3, ".3f"),
                                       ("bit axial speed max [mm/s]", "vb_max", 1e3, ".3f"),
                                       ("WOB min [kN]", "wob_min", 1e-3, ".2f"),
                                       ("WOB max [kN]", "wob_max", 1e-3, ".2f"),
                                       ("mean torque on bit [kN m]", "tob_mean", 1e-3, ".4f")):
            rows.append((f"{late}: {label}", [u[key] * scale for u in us], fmt))
        w = max(len(r[0]) for r in rows)
        print(f"  {'':{w}}  " + "  ".join(f"{c:>11}" for c in cols))
        for label, xs, fmt in rows:
            print(f"  {label:{w}}  " + "  ".join(f"{x:>11{fmt}}" for x in xs))
    # Their depth of cut is transported over one blade sector by first-order upwind at a Courant number
    # of 0.13 (their grid rule): a numerical diffusion of the rock surface that damps a ripple of 10 Hz
    # by about 90 % over a sector. Their parameters.m's point with that grid at Courant 0.95 (nearly
    # exact; valid while the bit turns below 1.05 x the top's speed, the linear growth here) beside
    # drillpy with their distributed damping, as the axial modes converge.
    name, om, v0, ka = POINTS[0]
    print(f"\n{name}: the growth of the disturbance (bit speed range, 2-12 s) and its period")
    for omx_c, label in ((5.0, "their sector grid rule (Courant 0.127)"),
                         (BIT["blades"] / (2 * np.pi * 0.95), "their sector grid at Courant 0.95")):
        s, _ = run_octave(mdir, om, v0, 12.0, a.disturbance, ka, omx_c)
        m = s["t"] >= 2.0
        print(f"  Octave, {label} ({s['info']}): growth "
              f"{envelope_growth(s['t'][m] - 2.0, s['ob'][m], om):.3f} 1/s, period "
              f"{dominant_period(s['t'][m], s['ob'][m]):.4f} s")
    import drillpy
    from drillpy.model.simulation import simulate
    for el, am, dt in ((200, 80, 1e-4), (200, 199, 4e-5), (400, 160, 5e-5)):
        cfg = drillpy_config(om, v0, 12.0, a.disturbance, elements=el, axial_modes=am, dt=dt, damping="distributed")
        r = simulate(drillpy.load_config(config=cfg))
        t, ob = r.axial.t, r.bit_speed
        m = t >= 2.0
        print(f"  drillpy, distributed, {el} elements, {am} axial modes, dt {dt * 1e3:g} ms: growth "
              f"{envelope_growth(t[m] - 2.0, ob[m], om):.3f} 1/s, period {dominant_period(t[m], ob[m]):.4f} s")
    # Their axial damping is mass-proportional (ratio k_a / omega_k on the k-th axial mode); drillpy's
    # one ratio for all axial modes can take it on one mode only: the growth at the second point as
    # drillpy's ratio takes the values theirs has on axial modes 1, 2 and 3.
    import drillpy
    from drillpy.model.simulation import simulate
    name, om, v0, ka = POINTS[1]
    print(f"\n{name}: drillpy's growth rates as its axial damping ratio takes theirs on mode k")
    for k in (1, 2, 3):
        cfg = drillpy_config(om, v0, 10.0, a.disturbance)
        zr = KA / (2 * np.pi * (2 * k - 1) * C_A / (4 * L))
        cfg["axial"]["damping_ratio"] = zr
        r = simulate(drillpy.load_config(config=cfg))
        print(f"  k = {k}: ratio {zr:.4f}: growth of the bit's axial speed range "
              f"{envelope_growth(r.axial.t, r.axial.rop, v0):.3f} 1/s, of the bit speed range "
              f"{envelope_growth(r.axial.t, r.bit_speed, om):.3f} 1/s")
    # drillpy's convergence in its axial modes at their parameters.m's point (100 elements, 20
    # torsional modes, the rgd-field preset's 10 axial modes and more).
    name, om, v0, ka = POINTS[0]
    print(f"\n{name}: drillpy (100 elements, 20 torsional modes) as the axial modes grow")
    for damping in ("modal", "distributed"):
        for am, dt in ((10, 5e-4), (20, 5e-4), (40, 2.5e-4), (99, 1e-4)):
            cfg = drillpy_config(om, v0, 10.0, a.disturbance, elements=100, modes=20, axial_modes=am, dt=dt,
                                 damping=damping)
            r = simulate(drillpy.load_config(config=cfg))
            t = r.axial.t
            print(f"  {damping:11s} {am:3d} axial modes, dt {dt * 1e3:g} ms: growth of the bit speed range "
                  f"{envelope_growth(t, r.bit_speed, om):.3f} 1/s, dominant period over 2-10 s "
                  f"{dominant_period(t[t >= 2.0], r.bit_speed[t >= 2.0]):.3f} s")
    if a.boundary:
        om = np.pi
        res = feed_boundary(mdir, om, 30 / 3600, 120 / 3600, 5, a.disturbance, omx=omx)
        print(f"\nstability boundary of steady drilling at {om:.4f} rad/s: the feed where the bit speed's "
              "growth rate (2.5-12 s) changes sign")
        for model, (bracket, trail) in res.items():
            pts = ", ".join(f"{v * 3600:.1f} m/h: {r:+.3f}/s" for v, r in trail)
            if bracket is None:
                print(f"  {model}: no sign change between the ends ({pts})")
            else:
                print(f"  {model}: between {bracket[0] * 3600:.1f} and {bracket[1] * 3600:.1f} m/h ({pts})")
    return 0


if __name__ == "__main__":
    # run as a script: the in-tree build when there is one, else the installed drillpy (imported by a test, the
    # module leaves sys.path alone, as benchmarks/axial_torsional_limit.py)
    if any((REPO / "python" / "drillpy").glob("_core*.so")):
        sys.path.insert(0, str(REPO / "python"))
    sys.exit(main())
