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
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
from scipy.signal import savgol_filter

REPO = Path(__file__).resolve().parents[1]
if any((REPO / "python" / "drillpy").glob("_core*")):  # in-tree build, else the installed drillpy
    sys.path.insert(0, str(REPO / "python"))
SAMPLE175 = REPO.parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--record", default=str(SAMPLE175))
    ap.add_argument("--window-s", type=float, default=0.041, help="Savitzky-Golay window [s] of the rates")
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
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
