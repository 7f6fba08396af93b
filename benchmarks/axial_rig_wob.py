"""Sample 175's WOB swing at the stick-slip cycle against the coupled axial-torsional rig model (issue 34).

    PYTHONPATH=python python3 -m drillpy analyze ../shared/data/testrig/sample175_0-40s.mat --calibrate 0:20 --out DIR
    PYTHONPATH=python python3 benchmarks/axial_rig_wob.py --model DIR/model.json [--t0 0 --t1 20] [--eps 30e6,60e6]

The rig model of ``drillpy analyze`` (docs/records.md section 3) has the rig's jack as a single state
fitted on the record (``axial.type = "jack"``: its gain g is the WOB per radian of the bit's lag, taken
from the WOB channel itself). This script replaces that jack by the coupled model (``axial.type =
"rgd"``, docs/axial.md): the bar's axial finite elements, a feed at the top and the Richard-Germay-
Detournay bit, whose depth of cut d = N [U(t) - U(t - t_N)] rises while the bit is stuck (the delay t_N
grows) and falls while it slips. The torque on the bit stays the rig model's law (Eq. 5.1) on the
coupled model's WOB (``axial.torque = "law"``), and the top drive its open-loop motor. Nothing of the
WOB's oscillation is fitted: the bit's parameters come from the rig's description and the literature,

* radius a = 6 mm: sample 175's 12 mm masonry bit (thesis section 5.3.2);
* N = 2 cutting edges: a masonry bit's carbide tip (an assumption: the thesis gives no count);
* feed V0 = 2 mm/s: the design's target rate of penetration, "close to 2 mm/s" (section 5.2);
* intrinsic specific energy eps, and the wear flats' contact strength sigma = eps: the concrete's
  30 MPa characteristic strength (section 5.2, "30 fck"), and twice that (``--eps``): RGD's eps is of
  the order of the rock's strength;
* zeta 0.6, gamma 1, mu 0.6: the published RGD field set (docs/axial.md, the rgd-field preset);
* the wear flat l: set so that steady drilling's WOB, a zeta eps d0 + a l sigma, is the record's mean
  WOB over the window (the jack's operating point, a slow input like the rig model's WOB trend);
* the axial string: the bar (E 220 GPa, 2.5 mm radius) with the disk's 3.3 kg (138 mm x 28.4 mm steel,
  section 5.1) at the bit; one axial mode (the bit on the bar's spring, 140 Hz: far above the 2.7 Hz
  cycle; the next mode, 1.7 kHz, would need a step below Eq. A.7's 0.06 ms), damping ratio 0.05.

Each eps runs twice: under the constant feed, and under the jack top (axial.top = "jack": the same free
feed, less kappa per N of the string's force above the record's mean WOB, kappa = 1 / (tau k) with tau
the rig model's jack relaxation and k :func:`axial_stiffness`).

Prints for the record and for the model (both channels through the rig's 10 Hz filter): the cycle
frequency (the bit speed's Welch peak), the WOB's standard deviation above 0.5 Hz, the swing at the cycle
frequency (sqrt 2 x the standard deviation of the WOB band-passed at f_c +- 0.6 Hz), its correlation
with the bit speed (band-passed alike; the sign says whether the WOB rises while the bit is stuck) and
the cross-spectral WOB per bit speed at f_c, magnitude and phase.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
RECORD = REPO.parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"

RADIUS, BLADES, FEED = 0.006, 2, 2e-3          # [m], [-], [m/s]
ZETA, GAMMA, MU = 0.6, 1.0, 0.6
BAR_RADIUS, DISK_MASS = 0.0025, 7800.0 * math.pi * 0.069 ** 2 * 0.0284  # [m], [kg] (3.31 kg)
BAND = 0.6  # half-width of the band around the cycle frequency [Hz]


def swing(t: np.ndarray, bit_speed: np.ndarray, wob: np.ndarray, ok: np.ndarray | None = None) -> dict:
    """The WOB's swing at the cycle of uniformly sampled channels (invalid samples interpolated for the
    filters and spectra, left out of the correlation and the deviations)."""
    from scipy import signal as sps
    dt = float(t[1] - t[0])
    fs = 1.0 / dt
    ok = np.ones(len(t), bool) if ok is None else ok
    idx = np.arange(len(t))
    v = np.interp(idx, idx[ok], bit_speed[ok])
    w = np.interp(idx, idx[ok], wob[ok])
    nper = min(len(t), int(8.0 * fs))
    f, pvv = sps.welch(v - v.mean(), fs=fs, nperseg=nper)
    band = (f > 0.5) & (f < 10.0)
    fc = float(f[band][np.argmax(pvv[band])])
    hp = sps.butter(2, 0.5, "highpass", fs=fs, output="sos")
    w_hp = sps.sosfiltfilt(hp, w)
    bp = sps.butter(2, [fc - BAND, fc + BAND], "bandpass", fs=fs, output="sos")
    w_bp, v_bp = sps.sosfiltfilt(bp, w), sps.sosfiltfilt(bp, v)
    _, pwv = sps.csd(w - w.mean(), v - v.mean(), fs=fs, nperseg=nper)
    k = int(np.argmin(np.abs(f - fc)))
    h = pwv[k] / pvv[k]
    return dict(fc=fc, wob_mean=float(np.mean(wob[ok])), wob_sd_hp=float(np.std(w_hp[ok])),
                swing=float(math.sqrt(2.0) * np.std(w_bp[ok])), corr=float(np.corrcoef(w_bp[ok], v_bp[ok])[0, 1]),
                corr_hp=float(np.corrcoef(w_hp[ok], v[ok])[0, 1]), h_abs=float(abs(h)),
                h_deg=float(np.degrees(np.angle(h))))


def record_swing(path: Path, t0: float, t1: float) -> dict:
    from drillpy.records.cleaning import clean
    from drillpy.records.io import read_record
    rec, _ = clean(read_record(path))
    rec = rec.select(t0, t1)
    return swing(rec.time_s, rec.bit_speed, rec.wob, rec.valid("bit_speed", "wob"))


def axial_stiffness(eps: float, blades: int = BLADES) -> float:
    """The axial stiffness between the top and the rock [N/m]: the simulated bar's E A / L (the 1.7 m of
    Table 5.1, as the thesis-rig string) in series with the cut's N a zeta eps (a bit displaced by dU
    deepens the cut by N dU)."""
    bar = 220e9 * math.pi * BAR_RADIUS ** 2 / 1.7
    return 1.0 / (1.0 / bar + 1.0 / (blades * RADIUS * ZETA * eps))


def coupled_config(model_cfg: dict, eps: float, wear_flat: float, duration: float, t_transient: float,
                   jack: tuple | None = None) -> dict:
    """The rig model's engine configuration with its jack replaced by the coupled model's RGD bit, under a
    constant feed, or with ``jack = (W_s [N], tau [s])`` under the jack top (axial.top = jack: the feed
    less kappa per N above the set force W_s, kappa = 1 / (tau k), k :func:`axial_stiffness`, so that the
    WOB relaxes towards W_s in about tau)."""
    c = json.loads(json.dumps(model_cfg))
    c["axial"] = dict(type="rgd", top="feed", rop_m_s=FEED, torque="law", modes=1, damping_ratio=0.05,
                      bit_mass_kg=DISK_MASS,
                      bit=dict(radius_m=RADIUS, blades=BLADES, specific_energy_pa=eps, contact_strength_pa=eps,
                               zeta=ZETA, wear_flat_m=wear_flat, gamma=GAMMA, mu=MU))
    c["operation"].pop("wob_n", None)  # with a feed top the WOB is the bit's response
    if jack is not None:
        c["axial"].update(top="jack", jack_admittance_m_s_n=1.0 / (jack[1] * axial_stiffness(eps)))
        c["operation"]["wob_n"] = float(jack[0])
    c["simulation"].update(start="steady", duration_s=duration, transient_s=t_transient, output_stride=1)
    c.pop("sensors", None)
    return c


def wear_flat_for(model_cfg: dict, eps: float, wob: float, jack: tuple | None = None) -> float:
    """The wear flat l that makes steady drilling's WOB the record's mean: a zeta eps d0 + a l sigma = W,
    d0 = 2 pi V0 / Omega_s at the motor's drooped steady speed, which falls as l raises the WOB and the
    law's torque with it: bisection on l, a wear flat at which the motor cannot carry steady drilling
    (no steady speed: a fold of the feed's steady state) counted as too large."""
    import drillpy
    from drillpy.model.simulation import simulate
    lo, hi = 0.0, wob / (RADIUS * eps)
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        s = simulate(drillpy.load_config(config=coupled_config(model_cfg, eps, mid, 0.01, 0.0, jack))).summary()
        w0 = math.inf if s["steady_speed_rad_s"] is None else s["steady_wob_n"]
        lo, hi = (mid, hi) if w0 < wob else (lo, mid)
    return lo


def model_swing(model_cfg: dict, eps: float, wob: float, duration: float, transient: float,
                jack_relaxation: float | None = None) -> dict:
    import drillpy
    from drillpy.model.simulation import simulate
    from drillpy.records.signals import rig_lowpass
    jack = None if jack_relaxation is None else (wob, jack_relaxation)  # the set force: the mean WOB
    flat = wear_flat_for(model_cfg, eps, wob, jack)
    r = simulate(drillpy.load_config(config=coupled_config(model_cfg, eps, flat, duration, transient, jack)))
    s = r.summary()
    if s["steady_speed_rad_s"] is None:  # no steady drilling under the motor: the run stalls, no cycle
        return dict(steady_speed=None, severity=s["severity"])
    keep = r.t >= transient
    fs = 1.0 / float(r.t[1] - r.t[0])
    v = rig_lowpass(r.bit_speed, fs)[keep]
    w = rig_lowpass(r.axial.wob, fs)[keep]
    out = swing(r.t[keep], v, w)
    d0 = s["steady_depth_of_cut_m"]
    out.update(steady_speed=s["steady_speed_rad_s"], eps=eps, wear_flat=flat, steady_wob=s["steady_wob_n"], depth=d0, cutting_wob=RADIUS * ZETA * eps * d0,
               gain=RADIUS * ZETA * eps * d0 * BLADES / (2.0 * math.pi), severity=s["severity"],
               mean_top=float(np.mean(r.top_speed[keep])), mean_bit=float(np.mean(r.bit_speed[keep])))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--model", required=True, help="model.json of drillpy analyze --calibrate (a rig model)")
    ap.add_argument("--record", default=str(RECORD))
    ap.add_argument("--t0", type=float, default=0.0)
    ap.add_argument("--t1", type=float, default=20.0)
    ap.add_argument("--eps", default="30e6,60e6", help="intrinsic specific energies [Pa], comma-separated")
    ap.add_argument("--duration", type=float, default=25.0)
    ap.add_argument("--transient", type=float, default=5.0)
    a = ap.parse_args()
    model = json.loads(Path(a.model).read_text())
    rec = record_swing(Path(a.record), a.t0, a.t1)
    head = (f"{'':>26} {'f_c Hz':>7} {'WOB mean':>9} {'sd>0.5Hz':>9} {'swing N':>8} {'corr':>6} {'corr>0.5':>8} "
            f"{'|W/v| N s':>9} {'phase':>6}")
    print(f"sample 175, {a.t0:g}-{a.t1:g} s; the coupled rig model: {a.duration:g} s, the first {a.transient:g} s "
          f"left out; both through the 10 Hz filter; feed: {FEED * 1e3:g} mm/s at the top; jack: the same free feed "
          f"relaxing the WOB to the record's mean in the rig model's {model['rig']['parameters']['jack_relaxation_s']['value']:.3f} s")
    print(head)

    def row(name, m):
        print(f"{name:>26} {m['fc']:>7.3f} {m['wob_mean']:>9.1f} {m['wob_sd_hp']:>9.1f} {m['swing']:>8.1f} "
              f"{m['corr']:>6.2f} {m['corr_hp']:>8.2f} {m['h_abs']:>9.2f} {m['h_deg']:>6.0f}")
    row("record", rec)
    tau = model["rig"]["parameters"]["jack_relaxation_s"]["value"]
    for eps, top in ((float(x), t) for x in a.eps.split(",") for t in ("feed", "jack")):
        m = model_swing(model["config"], eps, rec["wob_mean"], a.duration, a.transient,
                        tau if top == "jack" else None)
        name = f"{top} eps {eps / 1e6:g} MPa"
        if m["steady_speed"] is None:  # the feed's steady state has folded: the motor stalls under it
            print(f"{name:>26} no steady drilling: the motor cannot carry a "
                  f"{FEED * 1e3:g} mm/s feed at any speed, even without wear flats (it stalls; SS {m['severity']:.2f})")
            continue
        row(name, m)
        print(f"{'':>26} wear flat {m['wear_flat'] * 1e3:.2f} mm, d0 {m['depth'] * 1e3:.3f} mm/rev, cutting WOB "
              f"{m['cutting_wob']:.0f} of {m['steady_wob']:.0f} N, g = W_c N / 2 pi {m['gain']:.0f} N/rad; "
              f"SS {m['severity']:.2f}, mean top {m['mean_top']:.2f}, bit {m['mean_bit']:.2f} rad/s")


if __name__ == "__main__":
    # run as a script: the in-tree build when there is one, else the installed drillpy
    if any((REPO / "python" / "drillpy").glob("_core*.so")):
        sys.path.insert(0, str(REPO / "python"))
    main()
