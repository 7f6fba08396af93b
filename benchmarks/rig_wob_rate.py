"""How much of sample 175's WOB rate the rig model's jack equation explains, and what adds to it (issue 28).

    PYTHONPATH=python python3 benchmarks/rig_wob_rate.py [--record FILE.mat] [--window-s 0.041]

The rig model's jack (drill/axial.hpp) is one state, W' = g (Omega_f - v) - (W - W_s) / tau: the WOB's
rate follows the bit's speed deficit and relaxes to the jack's slow set force W_s (the WOB trend,
``rigsim.wob_trend``). Its horizons predict the WOB with an error of 0.57-0.62 of the WOB's spread
(docs/records.md, section 4, "The WOB over the next quarter second"), most of it within 75 ms of a
restart. This script asks the record directly, without a model run: on each half it regresses the
measured WOB rate (Savitzky-Golay, cubic, ``--window-s`` wide) by least squares on

1. the jack's terms: a constant (g Omega_f + W_s / tau), -v and -(W - W_s);
2. the same plus -v', the bit's acceleration: a WOB part that follows the bit speed at once (a depth of
   cut set by the speed at a given feed, as in Richard-Germay-Detournay's cut, docs/axial.md), not
   only through the angle the bit lags;
3. a constant, -v and -v' (no relaxation);
4. a constant, -v and T', the torque's rate: a WOB part that follows the torque at once (the law's
   torque falls as the bit speeds up, so this row cannot be told from row 3 by its R^2 alone; a
   cross-talk of the platform's torque into the WOB load cells would look like it);
5. a constant and -v alone;

and prints R^2 and the coefficients (g [N/rad], 1/tau [1/s], the direct term [N per rad/s]). About 5 s.

With ``--model DIR/model.json`` (``drillpy analyze RECORD --calibrate 0:20 --out DIR``) it also asks
whether such a term helps where it counts, the WOB over the 0.25 s horizons. On each half it restarts
a NumPy copy of the jack from the recorded WOB at every horizon (W = W_j - k_d (v - Omega_f), W_j the
jack's state, k_d the direct term; exact relaxation over each 1 ms sample), driven either by the bit
speed the engine predicts for the horizon or by the measured bit speed, fits g, tau, Omega_f (and
k_d) on the first half and prints the WOB's error (on the model's WOB spread) on both halves, beside
the engine's own (``Evaluation.wob``: the NumPy copy at the model's values reproduces it to a few
thousandths; the engine steps 0.1 ms). About 1 min more.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
from scipy.signal import savgol_filter

REPO = Path(__file__).resolve().parents[1]
if any((REPO / "python" / "drillpy").glob("_core*.so")):  # in-tree build, else the installed drillpy
    sys.path.insert(0, str(REPO / "python"))
SAMPLE175 = REPO.parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--record", default=str(SAMPLE175))
    ap.add_argument("--window-s", type=float, default=0.041, help="Savitzky-Golay window [s] of the rates")
    ap.add_argument("--model", default=None, help="model.json of drillpy analyze --calibrate: the horizons' check")
    a = ap.parse_args()
    from drillpy.records.cleaning import clean
    from drillpy.records.io import read_record
    from drillpy.records.rigsim import wob_trend
    raw = read_record(a.record)
    mid = float(raw.time_s[0] + raw.time_s[-1]) / 2
    for t0, t1 in ((float(raw.time_s[0]), mid), (mid, float(raw.time_s[-1]))):
        rec, _ = clean(raw.select(t0, t1))
        ok = rec.valid("wob") & rec.valid("bit_speed")
        i = np.arange(len(rec))
        w, v = (np.interp(i, i[ok], x[ok]) for x in (rec.wob, rec.bit_speed))
        n = max(5, int(round(a.window_s / rec.dt)) | 1)
        W, dW = savgol_filter(w, n, 3), savgol_filter(w, n, 3, deriv=1, delta=rec.dt)
        V, dV = savgol_filter(v, n, 3), savgol_filter(v, n, 3, deriv=1, delta=rec.dt)
        tq = np.interp(i, i[rec.valid("torque_on_bit")], rec.torque_on_bit[rec.valid("torque_on_bit")])
        dT = savgol_filter(tq, n, 3, deriv=1, delta=rec.dt)
        Ws = wob_trend(rec, float(np.mean(w)))
        use = ok.copy()
        use[:n] = use[-n:] = False  # the filters' ends
        y, one = dW[use], np.ones(use.sum())
        print(f"{t0:g}-{t1:g} s: the WOB rate's sd {y.std():.0f} N/s over {use.sum()} samples")
        for name, cols, labels in (
                ("the jack: -v, -(W - W_s)", [-V, -(W - Ws)], ("g [N/rad]", "1/tau [1/s]")),
                ("the jack and -v' (the bit speed at once)", [-V, -(W - Ws), -dV],
                 ("g [N/rad]", "1/tau [1/s]", "direct [N s/rad]")),
                ("-v and -v' (no relaxation)", [-V, -dV], ("g [N/rad]", "direct [N s/rad]")),
                ("-v and T' (the torque at once)", [-V, dT], ("g [N/rad]", "cross [N per N m]")),
                ("-v alone", [-V], ("g [N/rad]",))):
            A = np.column_stack([one] + [c[use] for c in cols])
            coef, *_ = np.linalg.lstsq(A, y, rcond=None)
            r = y - A @ coef
            print(f"  {name:42s} R^2 {1 - r.var() / y.var():.3f}; "
                  + ", ".join(f"{lab} {c:.3g}" for lab, c in zip(labels, coef[1:])))
    if a.model:
        horizons(a.record, a.model, raw, mid)
    return 0


def _jack(x, data, v) -> np.ndarray:
    """The WOB [N] of the jack with a direct term, x = (g, tau, k_d, Omega_f), over every horizon (rows)
    driven by the bit speed ``v`` (horizons x L), restarted from the recorded WOB."""
    g, tau, kd, of = x
    Ws = data.ch["W"][data.horizon_samples]  # the set force: the WOB trend, as the engine's input
    Wj = data.wob_measured[data.starts] + kd * (data.ch["v"][data.starts] - of)
    e = np.exp(-data.dt / tau)
    out = np.empty_like(v)
    for j in range(v.shape[1]):
        Wj = Ws[:, j] + (Wj - Ws[:, j]) * e + g * (of - v[:, j]) * tau * (1.0 - e)
        out[:, j] = Wj - kd * (v[:, j] - of)
    return out


def horizons(record: str, model_path: str, raw, mid: float) -> None:
    """The WOB's error over the horizons of both halves: the engine's jack, the NumPy jack refitted
    with and without the direct term, driven by the predicted and by the measured bit speed."""
    from scipy.optimize import least_squares
    from drillpy.records.cleaning import clean
    from drillpy.loop.prediction import load_model, rig_horizons
    model = load_model(model_path)
    s = model.calibration["metric_scale"]["wob_n"]
    halves = [rig_horizons(model, clean(raw.select(t0, t1))[0], model.command_rad_s)
              for t0, t1 in ((float(raw.time_s[0]), mid), (mid, float(raw.time_s[-1])))]

    def error(x, data, v):
        return ((_jack(x, data, v) - data.wob_measured[data.horizon_samples]) / s).ravel()

    def rms(r):
        return float(np.sqrt(np.mean(r ** 2)))

    print(f"\nthe WOB over the 0.25 s horizons (error on the WOB's spread {s:.1f} N; first half / second half):")
    print("  the engine's jack: " + " / ".join(
        f"{rms((ev.wob - d.wob_measured[d.horizon_samples]) / s):.3f}" for d, ev in halves))
    x0 = [model.jack_gain_n_rad, model.jack_relaxation_s, 0.0, float(np.mean(halves[0][0].ch["v"]))]
    print("  the NumPy jack at the model's values (Omega_f the mean bit speed): " + " / ".join(
        f"{rms(error(x0, d, ev.v)):.3f}" for d, ev in halves))
    for drive in ("predicted", "measured"):
        speeds = [ev.v if drive == "predicted" else d.v_meas[d.horizon_samples] for d, ev in halves]
        for label, free in (("jack refitted", (0, 1, 3)), ("jack + direct term", (0, 1, 2, 3))):
            lo, hi = np.array([0.0, 0.005, -50.0, 0.0]), np.array([2000.0, 5.0, 50.0, 30.0])
            start = np.array([x0[0], x0[1], 5.0, x0[3]])

            def full(z, free=free):
                x = np.array(x0, float)
                x[list(free)] = z
                return x
            fit = least_squares(lambda z: error(full(z), halves[0][0], speeds[0]), start[list(free)],
                                bounds=(lo[list(free)], hi[list(free)]))
            x = full(fit.x)
            print(f"  driven by the {drive} bit speed, {label:19s}: g {x[0]:.0f} N/rad, tau {x[1]:.3f} s, k_d "
                  f"{x[2]:.2f} N s/rad, Omega_f {x[3]:.2f} rad/s; error "
                  + " / ".join(f"{rms(error(x, d, v)):.3f}" for (d, _), v in zip(halves, speeds)))


if __name__ == "__main__":
    raise SystemExit(main())
