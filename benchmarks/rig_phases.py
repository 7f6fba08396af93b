"""The WOB's and the top speed's responses to the stick-slip cycle, record against rig model (issue
28): at the cycle frequency, the phase and the gain of the WOB relative to the bit speed (and the mean
of (W - mean W) x (v - mean v)), and of the top speed relative to the torque on bit, on a record window
and on the calibrated rig model's simulation of it.

    PYTHONPATH=python python3 benchmarks/rig_phases.py DIR/model.json [--t0 0 --t1 20]

DIR from ``drillpy analyze ../shared/data/testrig/sample175_0-40s.mat --calibrate 0:20 --out DIR``.
The law scales with the WOB (section 3.3), so a WOB that is low while the bit slips fast lowers the
torque in slip: a velocity weakening of its own, which feeds the cycle. Whether the model's jack
(docs/records.md, section 3) gives the record's phase and gain says whether that feed is modelled.
Both channels of each side pass the same chain (the record's: the rig's 10 Hz filter; the model's:
none), so their relative phase is comparable. The first 2 s are left out (the model's start).

The top encoder measures the bar's angle close to the drive (thesis, section 5.1), so the top speed
against the measured torque says how the drive gives way: a droop (a damper, the speed in phase with
-T) or an inertia (the speed lagging -T by a quarter period). Both sides' torque and top speed pass the
record's chain (the model's torque through the platform and the 10 Hz filter, its top speed through the
filter: ``rigsim.simulate_model``), so their relative phase is comparable; the lag maximizing the
correlation of the two channels is printed beside it.

It also prints how strongly the record's slip torque follows the WOB: the slip samples (bit speed
above the stick threshold and 1 rad/s, every 5th) fitted with T = (W / W_mean)^p (c0 + c1 v + c2 v^2)
at p = 0 (no WOB scaling), p = 1 (the law's scaling, Eq. 5.1 as ``drillpy analyze`` applies it) and p
free: an exponent above 1 would steepen the falling branch in slip, where the WOB is low.
"""
from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from scipy import signal as sps
from scipy.optimize import least_squares

from drillpy.loop.prediction import load_model
from drillpy.records import rigsim
from drillpy.records.cleaning import clean
from drillpy.records.io import read_record

SAMPLE175 = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"


def response(t: np.ndarray, v: np.ndarray, w: np.ndarray) -> dict:
    """Cycle frequency [Hz] (the bit speed's Welch peak within 1-6 Hz, 8 s segments), the WOB's phase
    relative to the bit speed there [deg] (positive: the WOB leads), its gain [N s/rad], their
    coherence and the mean of the two channels' product about their means [N rad/s]."""
    fs = 1.0 / float(np.median(np.diff(t)))
    keep = t >= t[0] + 2.0
    v, w = v[keep] - v[keep].mean(), w[keep] - w[keep].mean()
    n = int(8 * fs)
    f, pvv = sps.welch(v, fs, nperseg=n)
    _, pww = sps.welch(w, fs, nperseg=n)
    _, pvw = sps.csd(v, w, fs, nperseg=n)
    band = np.flatnonzero((f > 1.0) & (f < 6.0))
    k = band[np.argmax(pvv[band])]
    return {"f0": float(f[k]), "phase": float(np.degrees(np.angle(np.conj(pvw[k])))),
            "gain": float(np.sqrt(pww[k] / pvv[k])), "coherence": float(abs(pvw[k]) ** 2 / (pvv[k] * pww[k])),
            "product": float(np.mean(w * v))}


def top_response(t: np.ndarray, tq: np.ndarray, om: np.ndarray) -> dict:
    """Top speed ``om`` against torque ``tq`` at the cycle frequency (the torque's Welch peak within 1-6
    Hz, 8 s segments): the phase of the top speed relative to -T [deg] (negative: it lags), its gain
    [rad/s per N m], their coherence, the lag of the top speed behind the torque [ms] that makes
    their correlation most negative (searched over +-250 ms), and the mean of (T - mean T)(Omega -
    mean Omega) [W]: negative when the top gives way in phase with the torque and takes power out of
    the cycle, near zero for an inertia."""
    fs = 1.0 / float(np.median(np.diff(t)))
    keep = t >= t[0] + 2.0
    x, y = tq[keep] - tq[keep].mean(), om[keep] - om[keep].mean()
    n = int(8 * fs)
    f, pxx = sps.welch(x, fs, nperseg=n)
    _, pyy = sps.welch(y, fs, nperseg=n)
    _, pxy = sps.csd(x, y, fs, nperseg=n)
    band = np.flatnonzero((f > 1.0) & (f < 6.0))
    k = band[np.argmax(pxx[band])]
    m = int(0.25 * fs)
    corr = [np.corrcoef(x[m:-m], y[m + j:y.size - m + j])[0, 1] for j in range(-m, m + 1)]
    j = int(np.argmin(corr))
    return {"f0": float(f[k]), "phase": float((np.degrees(np.angle(-pxy[k])) + 180.0) % 360.0 - 180.0),
            "gain": float(np.sqrt(pyy[k] / pxx[k])), "coherence": float(abs(pxy[k]) ** 2 / (pxx[k] * pyy[k])),
            "lag_ms": (j - m) * 1e3 / fs, "corr": float(corr[j]), "power": float(np.mean(x * y))}


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
    ok = rec.valid("bit_speed") & rec.valid("wob")
    t = rec.time_s
    v = np.interp(t, t[ok], rec.bit_speed[ok])  # excluded samples interpolated over, for the spectra
    w = np.interp(t, t[ok], rec.wob[ok])
    sim = rigsim.simulate_model(m, rec, filtered=False)  # the rig drive at its command, the record's WOB trend
    print(f"{a.t0:g}-{a.t1:g} s; jack gain {m.jack_gain_n_rad:.1f} N/rad, relaxation {m.jack_relaxation_s:.3f} s")
    for label, r in (("record", response(t, v, w)), ("model", response(sim.time_s, sim.bit_speed, sim.wob))):
        print(f"{label:>6}: cycle {r['f0']:.3f} Hz; WOB against bit speed: phase {r['phase']:+.0f} deg, gain "
              f"{r['gain']:.1f} N s/rad, coherence {r['coherence']:.2f}; mean (W - W_mean)(v - v_mean) "
              f"{r['product']:+.1f} N rad/s")
    sim_f = rigsim.simulate_model(m, rec)  # the record's chain: platform and filter on the torque, filter on the top
    okt = rigsim.reliable_top_speed(rec) & rec.valid("torque_on_bit")
    top = np.interp(t, t[okt], rec.top_speed[okt])
    tq = np.interp(t, t[okt], rec.torque_on_bit[okt])
    for label, r in (("record", top_response(t, tq, top)),
                     ("model", top_response(sim_f.time_s, sim_f.torque_on_bit, sim_f.top_speed))):
        print(f"{label:>6}: top speed against -torque at {r['f0']:.3f} Hz: phase {r['phase']:+.0f} deg, gain "
              f"{r['gain']:.2f} rad/s per N m, coherence {r['coherence']:.2f}; most negative correlation "
              f"{r['corr']:+.2f} with the top {r['lag_ms']:+.0f} ms behind the torque; mean (T - T_mean)(Om - "
              f"Om_mean) {r['power']:+.2f} W")
    print("record's slip torque against the WOB, T = (W / W_mean)^p (c0 + c1 v + c2 v^2):")
    for p, rmse, slope in wob_exponent(rec):
        print(f"  p {p:.3f}: RMSE {rmse:.4f} N m, slope at 10 rad/s {slope:+.4f} N m s/rad")


if __name__ == "__main__":
    main()
