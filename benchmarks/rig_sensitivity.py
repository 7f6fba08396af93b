"""How far the calibrated rig model sits from the edge of its stick-slip cycle: one parameter moved at a time.

    PYTHONPATH=python python3 benchmarks/rig_sensitivity.py MODEL.json [--record FILE.mat] [--t0 0 --t1 20]
        [--set NAME=VALUE ...] [--only NAME,...] [--law-slope K] [--eta-std S [--seed N]]

MODEL.json is ``drillpy analyze --calibrate T0:T1``'s model (the rig modelled whole). Each row runs the
model over the record's window with one parameter moved (the others at their calibrated values) and
prints the long-run metrics the calibration matches, and the mismatch (``rig_comparison.compare``).
A cycle that vanishes (SS below 0.5, no stick phase) when a parameter moves by a few per cent of its
value marks a model whose stick-slip is marginal where the record's is robust. About 10 s.

``--set NAME=VALUE`` moves a parameter of the model first (e.g. ``static_torque_factor=1.2``: is the cycle
more robust with a higher static torque?); ``--only`` limits the rows to some parameters. ``--law-slope K``
scales the polynomial law's falling branch in slip by K about its reference speed (the cubic a4..a7 of
Eq. 5.1, the tied a1, a2 following; static torque unchanged) before the rows: how much more velocity
weakening would the cycle need to survive the inertia moves? ``--eta-std S`` runs every row with one
realization (``--seed``) of the model's torque fluctuation, Eq. (4.1) (``model.json -> torque_fluctuation``),
scaled to the standard deviation S: can the stochastic torque feed a cycle the deterministic model lacks?
The last column, the prominence of the bit speed's Welch peak over the median PSD from half to twice its
frequency (``signals.dominant_frequency`` names no cycle frequency below 10), says whether what it feeds
is a regular cycle.
"""
from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import numpy as np
from scipy import signal as sps

from drillpy.loop.prediction import load_model
from drillpy.records import rig_comparison, rig_fluctuation, rigsim
from drillpy.records.cleaning import clean
from drillpy.records.io import read_record

SAMPLE175 = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"
KEYS = ("ss", "stick_fraction", "cycle_frequency_hz", "median_period_s", "bit_speed_p95", "torque_p5", "torque_p95",
        "top_speed_std", "wob_std", "mean_top_speed")
#: Relative moves of each parameter (factors on its calibrated value).
MOVES = (0.8, 0.95, 1.05, 1.25)


def prominence(x: np.ndarray, fs: float) -> float:
    """The highest Welch peak of ``x`` above 0.5 Hz (8 s segments) over the median PSD from half to twice its
    frequency (the test of ``drillpy.records.signals.dominant_frequency``)."""
    f, p = sps.welch(x - np.mean(x), fs=fs, nperseg=min(x.size, int(8 * fs)))
    m = f >= 0.5
    k = int(np.argmax(p[m]))
    return float(p[m][k] / np.median(p[(f >= 0.5 * f[m][k]) & (f <= 2.0 * f[m][k])]))


def steeper(law: dict, k: float) -> dict:
    """The polynomial ``law`` with its slip branch f(u) = a4 + a5 u + a6 u^2 + a7 u^3 (u in the law's speed
    unit) replaced by f(u_ref) + k (f(u) - f(u_ref)), u_ref its reference speed, the tied pieces a1, a2
    (``identification._poly``: linear from the static torque at rest to the cubic at 5 % of u_ref, reached
    at 1 %) recomputed."""
    out, ref = dict(law), law["ref_speed"]

    def f(u, c):
        return c["a4"] + u * (c["a5"] + u * (c["a6"] + u * c["a7"]))
    out["a4"] = f(ref, law) * (1 - k) + k * law["a4"]
    for c in ("a5", "a6", "a7"):
        out[c] = k * law[c]
    t5 = f(0.05 * ref, out)
    out["a2"], out["a1"] = t5, (t5 - law["a0"]) / (0.01 * ref)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("model")
    ap.add_argument("--record", default=str(SAMPLE175))
    ap.add_argument("--t0", type=float, default=0.0)
    ap.add_argument("--t1", type=float, default=20.0)
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="set a parameter of the model before moving the others (repeatable)")
    ap.add_argument("--law-slope", type=float, default=None, metavar="K",
                    help="scale the law's falling branch in slip by K about its reference speed first")
    ap.add_argument("--only", default=None, help="comma-separated parameters to move (default: all)")
    ap.add_argument("--eta-std", type=float, default=None, metavar="S",
                    help="run with the model's torque fluctuation (Eq. 4.1) scaled to this standard deviation")
    ap.add_argument("--seed", type=int, default=0, help="the fluctuation's realization (with --eta-std)")
    a = ap.parse_args()
    m0 = load_model(a.model)
    for it in a.set:
        name, _, val = it.partition("=")
        if name not in rigsim.RIG_PARAMETERS:
            raise SystemExit(f"--set {it!r}: {name!r} is not a rig parameter ({', '.join(rigsim.RIG_PARAMETERS)})")
        m0 = dataclasses.replace(m0, **{name: float(val)})
    if a.law_slope is not None:
        m0 = dataclasses.replace(m0, law=steeper(m0.law, a.law_slope))
    only = None if a.only is None else set(a.only.split(","))
    rec, _ = clean(read_record(a.record).select(a.t0, a.t1))
    thr = rigsim.stick_threshold(rec)
    eta = None
    if a.eta_std is not None:
        if not m0.torque_fluctuation:
            raise SystemExit(f"--eta-std {a.eta_std}: {a.model} has no torque_fluctuation")
        eta = rig_fluctuation.realization(m0.torque_fluctuation, rec.dt, float(rec.time_s[-1] - rec.time_s[0]) + 1.0,
                                          seed=a.seed)
        eta *= a.eta_std / np.std(eta)
    print(f"{'':34s}" + " ".join(f"{k[:9]:>9s}" for k in KEYS) + "  mismatch  peak")

    def row(label, m):
        sim = rigsim.simulate_model(m, rec, eta=eta)
        c = rig_comparison.compare(rec, sim, thr)
        print(f"{label:34s}" + " ".join(f"{c.simulated[k]:9.3f}" for k in KEYS)
              + f"  {c.mismatch:8.3f} {prominence(sim.bit_speed, 1.0 / rec.dt):5.1f}")
        return c

    c = row("calibrated", m0)
    okv = rec.valid("bit_speed")
    print(f"{'measured':34s}" + " ".join(f"{c.measured[k]:9.3f}" for k in KEYS) + " " * 10
          + f" {prominence(np.interp(rec.time_s, rec.time_s[okv], rec.bit_speed[okv]), 1.0 / rec.dt):5.1f}")
    for name, (lo, hi, _, _) in rigsim.RIG_PARAMETERS.items():
        if only is not None and name not in only:
            continue
        v0 = float(getattr(m0, name))
        for f in MOVES:
            v = min(max(v0 * f, lo), hi)
            if v != v0:
                row(f"{name} x{f:g} ({v:.4g})", dataclasses.replace(m0, **{name: v}))


if __name__ == "__main__":
    main()
