"""The record as the loop sees it: cleaned, differentiated, decimated, cut into horizons and split
into a calibration and a validation part (:class:`LoopData`, :func:`prepare`)."""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy import signal as sps

from drillpy.records import signals
from drillpy.records.cleaning import CleaningOptions, clean
from drillpy.records.io import Record, read_record
from drillpy.records.rigsim import reliable_top_speed
from .options import LoopOptions

#: Channels the cleaning searches for spikes: the encoders (the load cells' torque and WOB drop
#: sharply, and genuinely, when the bit nearly sticks).
ENCODER_CHANNELS = ("bit_speed", "top_speed")
#: The first horizon starts this late [s]: the sensors' delay sqrt(2)/omega_c is at most 0.11 s
#: (cutoffs from 2 Hz), and restarts are placed that much before a horizon.
FIRST_START_S = 0.12


@dataclass
class LoopData:
    """A cleaned record on the analysis grid, split into calibration and validation horizons.

    ``ch`` holds Savitzky-Golay estimates of the recorded channels and their derivatives
    (``v``, ``v1``, ``v2``, ``v3``: bit speed and its first three derivatives; ``T``, ``T1``, ``T2``;
    ``top``..``top3``; ``W``, ``W1``, ``W2``); ``v_meas`` and ``T_meas`` are the recorded values the
    predictions are compared with. Horizon h starts at sample ``starts[h]`` and predicts the next
    ``L`` samples; ``is_test[h]`` marks the validation horizons.
    """
    source: str
    t: np.ndarray
    dt: float
    ch: dict
    v_meas: np.ndarray
    T_meas: np.ndarray
    valid: np.ndarray
    has_top: bool
    has_wob: bool
    stick_threshold: float
    t_split: float
    starts: np.ndarray
    is_test: np.ndarray
    L: int
    sigma_v: float
    sigma_T: float
    top_meas: np.ndarray | None
    top_ok: np.ndarray | None  #: top-speed samples that are measurements (not an artifact the cleaning filled)
    law_train: np.ndarray
    law_test: np.ndarray
    cleaning: list
    decimation: int
    record_rate_hz: float
    record: Record | None = None  #: the cleaned record at its own rate (the long-run check)

    @property
    def horizon_samples(self) -> np.ndarray:
        """Sample indices of every horizon, shape (horizons, L)."""
        return self.starts[:, None] + 1 + np.arange(self.L)[None, :]

    def channels(self) -> tuple:
        return tuple(c for c, ok in (("top_speed", self.has_top), ("wob", self.has_wob)) if ok)


def _savgol_set(x: np.ndarray, dt: float, window_s: float, orders) -> list:
    n = signals.savgol_length(window_s, dt, x.size, minimum=7)
    return [sps.savgol_filter(x, n, 4, deriv=k, delta=dt, mode="interp") for k in orders]


def prepare(record: Record | str | Path, cfg: dict, opt: LoopOptions) -> LoopData:
    """Clean a record, estimate derivatives, decimate, cut horizons and split them."""
    raw = read_record(record) if isinstance(record, (str, Path)) else record
    for need in ("bit_speed", "torque_on_bit"):
        raw.channel(need)
    rec, rep = clean(raw, CleaningOptions(spike_channels=ENCODER_CHANNELS))
    names = ["bit_speed", "torque_on_bit"] + [c for c in ("top_speed", "wob") if getattr(rec, c) is not None]
    valid = rec.valid(*names)
    if valid.sum() < 10:
        raise ValueError("record: fewer than 10 valid samples after cleaning")
    fs = rec.sample_rate_hz
    q = max(1, int(math.floor(fs / opt.rate_hz + 1e-9)))
    idx = np.arange(len(rec))

    def filled(x):
        ok = valid & np.isfinite(x)
        return np.interp(idx, idx[ok], x[ok])

    ch = {}
    spec = {"v": ("bit_speed", (0, 1, 2, 3)), "T": ("torque_on_bit", (0, 1, 2)),
            "top": ("top_speed", (0, 1, 2, 3)), "W": ("wob", (0, 1, 2))}
    for key, (name, orders) in spec.items():
        x = getattr(rec, name)
        if x is None:
            continue
        for k, y in zip(orders, _savgol_set(filled(x), rec.dt, opt.derivative_window_s, orders)):
            ch[key if k == 0 else f"{key}{k}"] = y[::q]
    # samples within a filter half-width of an excluded sample are excluded too
    half = max(int(round(opt.derivative_window_s / rec.dt)) // 2, 3)
    bad = np.convolve((~valid).astype(float), np.ones(2 * half + 1), mode="same") > 0
    ok = (~bad)[::q]
    t = rec.time_s[::q]
    dt = rec.dt * q
    v_meas, T_meas = filled(rec.bit_speed)[::q], filled(rec.torque_on_bit)[::q]
    has_top, has_wob = rec.top_speed is not None, rec.wob is not None
    top_ref = float(np.median(ch["top"][ok])) if has_top else float(cfg["operation"]["top_speed_rad_s"])
    thr = opt.stick_fraction * abs(top_ref)
    t_split = float(t[0] + opt.calibration_fraction * (t[-1] - t[0]))
    L = int(round(opt.horizon_s / dt))
    if L < 2:
        raise ValueError(f"horizon_s = {opt.horizon_s}: shorter than two samples of {dt:g} s")
    starts, is_test = [], []
    cum = np.r_[0, np.cumsum(~ok)]
    first = int(math.ceil(FIRST_START_S / dt))  # room for the restart before a lagging sensor's horizon
    for s in range(first, t.size - L, L):
        if cum[s + L + 1] - cum[s] > 0:
            continue  # an excluded sample in the horizon
        if t[s + L] < t_split:
            starts.append(s), is_test.append(False)
        elif t[s] >= t_split:
            starts.append(s), is_test.append(True)
    starts, is_test = np.asarray(starts, dtype=np.int64), np.asarray(is_test, bool)
    n_tr, n_te = int((~is_test).sum()), int(is_test.sum())
    if n_tr < 4 or n_te < 4:
        raise ValueError(f"record: {n_tr} calibration and {n_te} validation horizons of {opt.horizon_s:g} s; need "
                         f"at least 4 each (a longer record, a shorter horizon_s or another calibration_fraction)")
    train = ok & (t < t_split)
    sv, sT = float(np.std(v_meas[train])), float(np.std(T_meas[train]))
    top_meas = filled(rec.top_speed)[::q] if has_top else None
    top_ok = (reliable_top_speed(rec)[::q] & ok) if has_top else None
    if not (sv > 0 and sT > 0):
        raise ValueError("record: the bit speed or the torque on bit is constant over the calibration part")
    every = max(1, int(round(0.01 / dt)))  # law fits on 100 Hz: the channels are smooth at that scale
    slip = ok & (ch["v"] > thr)
    sub = np.zeros(t.size, bool)
    sub[::every] = True
    law_train = np.flatnonzero(slip & sub & (t < t_split))
    law_test = np.flatnonzero(slip & sub & (t >= t_split))
    if law_train.size < 20:
        raise ValueError(f"record: only {law_train.size} slip samples in the calibration part to fit the law")
    return LoopData(str(rec.provenance.get("source", "record")), t, dt, ch, v_meas, T_meas, ok, has_top, has_wob, thr,
                    t_split, starts, is_test, L, sv, sT, top_meas, top_ok, law_train, law_test, rep.lines(), q, fs, rec)



def measured(data: LoopData, horizons=None) -> tuple:
    h = np.arange(data.starts.size) if horizons is None else np.asarray(horizons)
    s = data.horizon_samples[h]
    return data.v_meas[s], data.T_meas[s]

