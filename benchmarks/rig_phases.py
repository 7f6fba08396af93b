"""The WOB's and the top speed's responses to the stick-slip cycle, record against rig model (issue
28): at the cycle frequency, the phase and the gain of the WOB and of the top speed relative to the
bit speed, on a record window and on the calibrated rig model's simulation of it.

    PYTHONPATH=python python3 benchmarks/rig_phases.py DIR/model.json [--t0 0 --t1 20]

DIR from ``drillpy analyze ../shared/data/testrig/sample175_0-40s.mat --calibrate 0:20 --out DIR``.
Phases are of the channel relative to the bit speed at the bit speed's Welch peak within 1-6 Hz
(8 s segments; positive: the channel leads). Both channels of each side pass the same chain (the
record's: the rig's 10 Hz filter; the model's: the same filter, ``rigsim.simulate_model``), so their
relative phase is comparable. The first 2 s are left out (the model's start).

* The WOB. The law scales with the WOB (section 3.3), so a WOB that is low while the bit slips fast
  lowers the torque in slip: a velocity weakening of its own, which feeds the cycle. Whether the
  model's jack (docs/records.md, section 3) gives the record's phase and gain says whether that feed
  is modelled. The mean of (W - mean W)(v - mean v) is printed beside it.
* The top speed. The top encoder measures the bar's angle close to the drive (thesis, section 5.1),
  and both speeds come from encoders: no torque channel enters. A drive that gives way as a droop
  c (T_top = c (Omega_c - Omega), no inertia) at the top of a bar of stiffness k gives Omega = v / (1 +
  i w c / k) at the angular frequency w; an inertia behind it adds up to a quarter period of lag. That
  droop's response at the model's c_m and bar is printed for reference.

It also prints how strongly the record's slip torque follows the WOB: the slip samples (bit speed
above the stick threshold and 1 rad/s, every 5th) fitted with T = (W / W_mean)^p (c0 + c1 v + c2 v^2)
at p = 0 (no WOB scaling), p = 1 (the law's scaling, Eq. 5.1 as ``drillpy analyze`` applies it) and p
free: an exponent above 1 would steepen the falling branch in slip, where the WOB is low.
"""
from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares

from drillpy.loop.prediction import load_model
from drillpy.records import rigsim
from drillpy.records.cleaning import clean
from drillpy.records.io import read_record
from drillpy.records.signals import cycle_response

SAMPLE175 = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"
#: The bar's torsional stiffness G J / L of Table 5.1 [N m/rad] (times the model's gj_factor).
BAR_STIFFNESS = 3.08


def response(t: np.ndarray, v: np.ndarray, y: np.ndarray) -> dict:
    """:func:`drillpy.records.signals.cycle_response` of ``y`` to the bit speed ``v`` after the first 2 s,
    with the mean of the two channels' product about their means (``product``)."""
    keep = t >= t[0] + 2.0
    v, y = v[keep] - v[keep].mean(), y[keep] - y[keep].mean()
    return {**cycle_response(v, y, 1.0 / float(np.median(np.diff(t)))), "product": float(np.mean(v * y))}


def wob_exponent(rec) -> list:
    """[(p, RMSE [N m], slope dT/dv at 10 rad/s [N m s/rad])] of the slip torque fitted with
    T = (W / W_mean)^p (c0 + c1 v + c2 v^2) at p = 0, 1 and p free (in that order)."""
    ok = rec.valid("bit_speed") & rec.valid("torque_on_bit") & rec.valid("wob")
    m = ok & (rec.bit_speed > max(rigsim.stick_threshold(rec), 1.0))
    v, tq, w = rec.bit_speed[m][::5], rec.torque_on_bit[m][::5], rec.wob[m][::5]
    w = w / w.mean()
    rows = []
    for p in (0.0, 1.0, None):
        def res(x, p=p):
            return (w ** (x[3] if p is None else p)) * (x[0] + x[1] * v + x[2] * v * v) - tq
        x = least_squares(res, [2.0, -0.05, 0.0] + ([1.0] if p is None else [])).x
        rows.append((float(x[3]) if p is None else p, float(np.sqrt(np.mean(res(x) ** 2))), float(x[1] + 20.0 * x[2])))
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("model")
    ap.add_argument("--record", default=str(SAMPLE175))
    ap.add_argument("--t0", type=float, default=0.0)
    ap.add_argument("--t1", type=float, default=20.0)
    a = ap.parse_args()
    m = load_model(a.model)
    rec, _ = clean(read_record(a.record).select(a.t0, a.t1))
    t = rec.time_s

    def channel(name, ok):  # excluded samples interpolated over, for the spectra
        return np.interp(t, t[ok], getattr(rec, name)[ok])
    okw = rec.valid("bit_speed") & rec.valid("wob")
    okt = rec.valid("bit_speed") & rigsim.reliable_top_speed(rec)
    sim = rigsim.simulate_model(m, rec)  # the rig drive at its command, the record's WOB trend, the 10 Hz filter
    print(f"{a.t0:g}-{a.t1:g} s; jack gain {m.jack_gain_n_rad:.1f} N/rad, relaxation {m.jack_relaxation_s:.3f} s")
    for label, r in (("record", response(t, channel("bit_speed", okw), channel("wob", okw))),
                     ("model", response(sim.time_s, sim.bit_speed, sim.wob))):
        print(f"{label:>6}: cycle {r['frequency_hz']:.3f} Hz; WOB against bit speed: phase {r['phase_deg']:+.0f} deg, gain "
              f"{r['gain']:.1f} N s/rad, coherence {r['coherence']:.2f}; mean (W - W_mean)(v - v_mean) "
              f"{r['product']:+.1f} N rad/s")
    for label, r in (("record", response(t, channel("bit_speed", okt), channel("top_speed", okt))),
                     ("model", response(sim.time_s, sim.bit_speed, sim.top_speed))):
        print(f"{label:>6}: cycle {r['frequency_hz']:.3f} Hz; top speed against bit speed: phase {r['phase_deg']:+.0f} deg, gain "
              f"{r['gain']:.2f}, coherence {r['coherence']:.2f}")
    w = 2.0 * np.pi * r["frequency_hz"]
    h = 1.0 / (1.0 + 1j * w * m.motor_slope_nms_rad / (BAR_STIFFNESS * m.gj_factor))
    print(f"  a droop of the model's c_m {m.motor_slope_nms_rad:.3f} N m s/rad without inertia, at the top of its bar: "
          f"phase {np.degrees(np.angle(h)):+.0f} deg, gain {abs(h):.2f}")
    print("record's slip torque against the WOB, T = (W / W_mean)^p (c0 + c1 v + c2 v^2):")
    for p, rmse, slope in wob_exponent(rec):
        print(f"  p {p:.3f}: RMSE {rmse:.4f} N m, slope at 10 rad/s {slope:+.4f} N m s/rad")


if __name__ == "__main__":
    main()
