"""Does the break-away torque follow the WOB? Sample 175 against the calibrated rig model (issue 28).

    PYTHONPATH=python python3 benchmarks/rig_breakaway_wob.py [--model D/model.json] [--record FILE.mat]

D from ``drillpy analyze ../shared/data/testrig/sample175_0-40s.mat --calibrate 0:20 --out D``.

The rig model scales the law's static torque with the WOB the law sees (Eq. 5.1: gain a0 W / W_ref,
section 3.3), and that WOB is the jack's state: it rises while the bit is stuck (docs/records.md,
section 3). So in the model a stick phase whose WOB has risen more above its slow trend breaks away
at a higher torque. The script measures that on the record and on the model's simulation of it, per
stick phase (``identification.breakaway_torques``: the largest torque from the stick's start to 30 ms
after its end; stick phases of at least 10 ms in the record's valid cycles, ``signals.segment_cycles``),
by least squares on

    ln T_b = c + n_trend ln W_trend + n_swing ln (W_stick / W_trend)

W_trend the WOB's 0.5 Hz trend at the stick's start (``rigsim.wob_trend``, the jack's set force), W_stick
the mean WOB over the stick phase. Printed per source: the stick phases used, n_trend and n_swing
with 95 % bootstrap intervals (2000 resamplings of the stick phases, seed 0), the mean rise of the WOB
from the stick's start to its end, and the mean break-away torque. The stall (stick phases of 0.5 s or
more, ``rig_comparison.stalls``) is left out.
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import sys
from pathlib import Path

import numpy as np

#: The repository (the default record is beside it, in ../shared). The tests import this module: it
#: leaves sys.path as it is (run it with PYTHONPATH=python from a development build).
REPO = Path(__file__).resolve().parents[1]

#: Stick phases at least this long are a stall, left out [s] (rig_comparison.stalls' default).
STALL_S = 0.5


def stick_phases(rec, threshold: float, skip_s: float = 2.0) -> dict:
    """Per stick phase of ``rec`` (after ``skip_s``): break-away torque, WOB trend at its start, mean
    WOB over it and the WOB's rise over it.

    Parameters
    ----------
    rec : Record
        A cleaned record, or a simulation as a record.
    threshold : float
        Stick threshold [rad/s].
    skip_s : float
        Start-up left out [s].

    Returns
    -------
    dict of ndarray
        ``breakaway``, ``trend``, ``stick_wob``, ``rise``.
    """
    from drillpy.records import identification, rigsim
    from drillpy.records.signals import segment_cycles
    cyc = segment_cycles(rec.bit_speed, rec.dt, threshold, valid=rec.valid("bit_speed", "torque_on_bit", "wob"))
    keep = cyc.valid & ((cyc.end - cyc.stick) * rec.dt < STALL_S) & (rec.time_s[cyc.stick] >= rec.time_s[0] + skip_s)
    keep &= (cyc.end - cyc.stick) * rec.dt >= 0.01
    tb = identification.breakaway_torques(dataclasses.replace(cyc, valid=keep), rec.torque_on_bit)
    trend = rigsim.wob_trend(rec, float(np.nanmean(rec.wob)))
    j = np.flatnonzero(keep)
    a, b = cyc.stick[j].astype(int), cyc.end[j].astype(int)
    return {"breakaway": tb, "trend": trend[a], "stick_wob": np.array([np.mean(rec.wob[x:y]) for x, y in zip(a, b)]),
            "rise": rec.wob[b - 1] - rec.wob[a]}


def exponents(ph: dict, rng: np.random.Generator, n_boot: int = 2000) -> tuple:
    """(n_trend, n_swing) by least squares and their 95 % bootstrap intervals."""
    y = np.log(ph["breakaway"])
    X = np.c_[np.ones(y.size), np.log(ph["trend"]), np.log(ph["stick_wob"] / ph["trend"])]
    fit = np.linalg.lstsq(X, y, rcond=None)[0][1:]
    boots = []
    for _ in range(n_boot):
        i = rng.integers(0, y.size, y.size)
        boots.append(np.linalg.lstsq(X[i], y[i], rcond=None)[0][1:])
    lo, hi = np.percentile(np.array(boots), [2.5, 97.5], axis=0)
    return fit, lo, hi


def report(name: str, ph: dict) -> str:
    """One line per source (module docstring)."""
    fit, lo, hi = exponents(ph, np.random.default_rng(0))
    return (f"{name}: {ph['breakaway'].size} stick phases; n_trend {fit[0]:+.2f} [{lo[0]:+.2f}, {hi[0]:+.2f}], "
            f"n_swing {fit[1]:+.2f} [{lo[1]:+.2f}, {hi[1]:+.2f}]; WOB rise over a stick {np.mean(ph['rise']):+.1f} N, "
            f"break-away torque {np.mean(ph['breakaway']):.2f} N m")


def main(argv=None) -> int:
    """Print the record's line and, with ``--model``, the model's (module docstring).

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.

    Returns
    -------
    int
        Exit status 0.
    """
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--model", help="model.json of drillpy analyze --calibrate")
    ap.add_argument("--record", default=str(REPO.parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"))
    a = ap.parse_args(argv)
    from drillpy.records import rigsim
    from drillpy.records.cleaning import clean
    from drillpy.records.io import read_record
    rec = clean(read_record(a.record))[0]
    thr = rigsim.stick_threshold(rec)
    print(report("record", stick_phases(rec, thr)))
    if a.model:
        model = rigsim.RigModel.from_dict(json.loads(Path(a.model).read_text()))
        print(report("model", stick_phases(rigsim.simulate_model(model, rec), thr)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
