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

    Every per-sample array below has one value per sample of the analysis grid ``t``.

    Attributes
    ----------
    source : str
        Where the record came from (its file, or ``"record"``).
    t : numpy.ndarray
        Time of each analysis sample [s] (the record's own time stamps, decimated).
    dt : float
        Analysis sampling interval [s] (the record's interval times ``decimation``).
    ch : dict
        Savitzky-Golay estimates (order 4, ``derivative_window_s``) on the analysis grid: ``v`` bit
        speed [rad/s] and ``v1``..``v3`` its derivatives [rad/s^2, rad/s^3, rad/s^4]; ``T`` torque on
        bit [N m] and ``T1``, ``T2`` [N m/s, N m/s^2]; ``top`` top speed [rad/s] and ``top1``..``top3``
        (with a top-speed channel); ``W`` WOB [N] and ``W1``, ``W2`` (with a WOB channel).
        Excluded samples are interpolated over before filtering.
    v_meas : numpy.ndarray
        Recorded bit speed [rad/s] (cleaned, excluded samples interpolated): what E compares with.
    T_meas : numpy.ndarray
        Recorded torque on bit [N m], the same way.
    valid : numpy.ndarray
        Boolean: the sample and every sample within a filter half-width of it survived the cleaning.
    has_top : bool
        The record has a top-speed channel.
    has_wob : bool
        The record has a WOB channel.
    stick_threshold : float
        Bit speed [rad/s] at or below which the bit counts as stuck: ``stick_fraction`` times the
        median recorded top speed (the declared top speed without a top-speed channel).
    t_split : float
        End of the calibration part [s]: t[0] + ``calibration_fraction`` (t[-1] - t[0]).
    starts : numpy.ndarray
        Restart sample of every horizon kept (int); horizon h predicts samples starts[h] + 1 ..
        starts[h] + L.
    is_test : numpy.ndarray
        Boolean per horizon: True for the validation part, False for the calibration part.
    L : int
        Samples per horizon, round(``horizon_s`` / dt).
    sigma_v : float
        Standard deviation of the recorded bit speed over the calibration part's valid samples
        [rad/s] (sd_v of the metric E, fixed for the whole loop).
    sigma_T : float
        Standard deviation of the recorded torque on bit over the calibration part [N m] (sd_T).
    top_meas : numpy.ndarray or None
        Recorded top speed [rad/s] (None without a top-speed channel).
    top_ok : numpy.ndarray or None
        Boolean: the top-speed sample is a measurement and valid
        (:func:`drillpy.records.rigsim.reliable_top_speed`); the top-speed term of E uses only these.
    law_train : numpy.ndarray
        Sample indices of the law residual on the calibration part: slip samples (bit speed above
        the stick threshold), valid, thinned to about 100 Hz.
    law_test : numpy.ndarray
        The same on the validation part.
    cleaning : list of str
        The cleaning's summary lines (:meth:`drillpy.records.cleaning.CleaningReport.lines`).
    decimation : int
        Decimation factor from the record's rate to the analysis rate.
    record_rate_hz : float
        The record's own sampling rate [Hz].
    record : Record or None
        The cleaned record at its own rate (the long-run check).
    batched : bool
        Step the horizons in SIMD lockstep (``LoopOptions.batched``).
    law_knot : bool
        Calibrate a polynomial law's low-speed knot (``LoopOptions.law_knot``).
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
    batched: bool = True
    law_knot: bool = True

    @property
    def horizon_samples(self) -> np.ndarray:
        """Sample indices of every horizon, shape (horizons, L)."""
        return self.starts[:, None] + 1 + np.arange(self.L)[None, :]

    def channels(self) -> tuple:
        """The optional channels the record has, as named in an effect's ``needs``.

        Returns
        -------
        tuple of str
            A subset of ``("top_speed", "wob")``.
        """
        return tuple(c for c, ok in (("top_speed", self.has_top), ("wob", self.has_wob)) if ok)


def _savgol_set(x: np.ndarray, dt: float, window_s: float, orders) -> list:
    n = signals.savgol_length(window_s, dt, x.size, minimum=7)
    return [sps.savgol_filter(x, n, 4, deriv=k, delta=dt, mode="interp") for k in orders]


def prepare(record: Record | str | Path, cfg: dict, opt: LoopOptions) -> LoopData:
    """Clean a record, estimate derivatives, decimate, cut horizons and split them.

    The record is cleaned (:func:`drillpy.records.cleaning.clean`, spikes searched in the encoder
    channels only), its channels and their derivatives estimated by Savitzky-Golay filters at the
    record's rate and decimated by the integer factor that brings it to at most ``opt.rate_hz``.
    Horizons of ``opt.horizon_s`` are cut from :data:`FIRST_START_S` on; a horizon that holds an
    excluded sample or straddles ``t_split`` is dropped.

    Parameters
    ----------
    record : Record, str or Path
        The measured record, or its file (:func:`drillpy.records.io.read_record`). It must have
        bit speed and torque on bit; top speed and WOB are optional.
    cfg : dict
        The declared configuration (normalized); its ``operation.top_speed_rad_s`` [rad/s] sets the
        stick threshold when the record has no top-speed channel.
    opt : LoopOptions
        ``horizon_s``, ``calibration_fraction``, ``rate_hz``, ``derivative_window_s`` and
        ``stick_fraction`` are used.

    Returns
    -------
    LoopData
        The record on the analysis grid with its horizons and split.

    Raises
    ------
    ValueError
        Fewer than 10 valid samples; a horizon shorter than two samples; fewer than 4 calibration
        or 4 validation horizons; a constant bit speed or torque over the calibration part; fewer
        than 20 slip samples in the calibration part for the law fit.
    """
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
                    t_split, starts, is_test, L, sv, sT, top_meas, top_ok, law_train, law_test, rep.lines(), q, fs, rec,
                    opt.batched, opt.law_knot)



def measured(data: LoopData, horizons=None) -> tuple:
    """The recorded bit speed and torque on bit over the samples of horizons.

    Parameters
    ----------
    data : LoopData
        The record on the analysis grid.
    horizons : array_like of int, optional
        Horizon indices (default: every horizon).

    Returns
    -------
    tuple of numpy.ndarray
        (bit speed [rad/s], torque on bit [N m]), each of shape (horizons, L): row h holds the
        samples that horizon predicts (:attr:`LoopData.horizon_samples`).
    """
    h = np.arange(data.starts.size) if horizons is None else np.asarray(horizons)
    s = data.horizon_samples[h]
    return data.v_meas[s], data.T_meas[s]

