"""The record as the loop sees it: cleaned, differentiated, decimated, cut into horizons and split
into a calibration and a validation part (:class:`LoopData`, :func:`prepare`)."""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy import signal as sps

from drillpy.records import bit_balance, rig_comparison, signals
from drillpy.records.cleaning import CleaningOptions, clean
from drillpy.records.io import Record, read_record
from drillpy.records.rig_comparison import metric_scale, stalls
from drillpy.records.rigsim import WOB_TREND_HZ, reliable_top_speed, wob_trend
from .options import LoopOptions
from .view import view

#: Channels the cleaning searches for spikes: the encoders (the load cells' torque and WOB drop
#: sharply, and genuinely, when the bit nearly sticks).
ENCODER_CHANNELS = ("bit_speed", "top_speed")
#: The first horizon starts this late [s]: the sensors' delay sqrt(2)/omega_c is at most 0.11 s
#: (cutoffs from 2 Hz), and restarts are placed that much before a horizon.
FIRST_START_S = 0.12
#: The WOB is a response of the string's rotation, not an input, when its part above
#: :data:`drillpy.records.rigsim.WOB_TREND_HZ` correlates with the bit's angle deficit at least this
#: well (the best lag within :data:`RESPONSE_LAG_S`): sample 175 gives 0.81, the synthetic truths,
#: whose WOB is an exogenous band-limited input, below it (``tests/python/test_loop_wob.py``).
RESPONSE_R = 0.5
#: Lags searched for the WOB-response correlation [s]: the rig's WOB leads the deficit by about 35 ms.
RESPONSE_LAG_S = 0.1


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
        Standard deviation of the recorded bit speed over the calibration part's valid samples,
        stalls left out [rad/s] (sd_v of the metric E, fixed for the whole loop;
        :func:`drillpy.records.rig_comparison.metric_scale`).
    sigma_T : float
        Standard deviation of the recorded torque on bit over the same samples [N m] (sd_T).
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
    wob_response : dict or None
        :func:`wob_response` of the record (None without a WOB channel), with ``"input"``: the WOB
        the law takes, ``"measured"`` (the recorded WOB, an input) or ``"trend"`` (its slow part
        below 0.5 Hz: the recorded WOB is a response of the rotation and carries the cycle).
    wob_measured : numpy.ndarray or None
        The recorded WOB on the analysis grid [N] when the law takes its trend (the WOB state a
        restart starts from); None otherwise.
    stalls : tuple
        The record's stalls (:func:`drillpy.records.rig_comparison.stalls`: stick phases of at least
        ``rigsim.STALL_MIN_S``) as ``(start [s], duration [s])``.
    set_apart : dict
        Horizons cut like the others but left out of E (restart sample -> reason): ``"stall"``
        (the horizon overlaps a stall: the bit stuck at a torque the motor cannot overcome until the
        WOB is relieved, no part of the regular cycle, reported apart as in ``drillpy predict``) or
        ``"top-speed artifact at the restart"`` (the restart's top speed is not a measurement: an
        artifact is never fed in).
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
    wob_response: dict | None = None
    wob_measured: np.ndarray | None = None
    stalls: tuple = ()
    set_apart: dict = dataclasses.field(default_factory=dict)
    channel_timing: dict | None = None  #: the shifts applied (LoopOptions.channel_timing; "auto" without a skew: 0, the timing found under "refused"), None: as recorded
    _sides: dict = dataclasses.field(default_factory=dict, repr=False, compare=False)

    def measured_side(self, start_s: float, drive: str):
        """The long-run comparison's measured side of :attr:`record` for simulations from ``start_s``
        with this drive (:func:`drillpy.records.rig_comparison.measured_side`, no start-up
        discarded), computed once per (start, drive).

        Parameters
        ----------
        start_s : float
            The simulation's first time [s].
        drive : str
            The simulation's drive (its provenance's ``drive``).

        Returns
        -------
        drillpy.records.rig_comparison.MeasuredSide
        """
        key = (float(start_s), drive)
        if key not in self._sides:
            self._sides[key] = rig_comparison.measured_side(self.record, self.stick_threshold, *key, 0.0)
        return self._sides[key]

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


def wob_response(rec: Record) -> dict | None:
    """Whether the recorded WOB is an input of the torsional dynamics or a response of them.

    The part of the WOB above :data:`~drillpy.records.rigsim.WOB_TREND_HZ` is correlated with the
    part of the bit's angle deficit -int (v - mean v) dt above the same frequency (second-order
    Butterworth, zero phase) at the best lag within +-:data:`RESPONSE_LAG_S`. On the test rig the
    jack's feed compresses the axial compliance while the bit lags its steady rotation (the WOB
    rises while stuck and falls in slip, thesis Figs. 5.6-5.7; ``drill/axial.hpp``): the
    correlation is high and the WOB per radian of deficit positive. An exogenous WOB (a hook-load
    variation, the synthetic truths' band-limited input) shows no such correlation.

    Parameters
    ----------
    rec : Record
        A cleaned record with bit speed and WOB.

    Returns
    -------
    dict or None
        ``{"correlation", "lag_s", "gain_n_rad", "response"}``: the correlation at the best lag (a
        positive lag: the WOB follows the deficit), the regression slope of the WOB's fast part on the
        deficit's [N/rad] and whether the WOB is a response (correlation at least :data:`RESPONSE_R`
        and a positive slope); a correlation of 0 when the WOB or the deficit has no part above the
        trend's frequency. None without a WOB channel or when the record is too short for the filter
        (under five periods of the trend's frequency).
    """
    if rec.wob is None or rec.bit_speed is None:
        return None
    ok = rec.valid("bit_speed", "wob") & np.isfinite(rec.bit_speed) & np.isfinite(rec.wob)
    fs = rec.sample_rate_hz
    if ok.sum() < 10 or len(rec) * rec.dt < 5.0 / WOB_TREND_HZ or WOB_TREND_HZ >= 0.5 * fs:
        return None
    i = np.arange(len(rec))
    v, w = np.interp(i, i[ok], rec.bit_speed[ok]), np.interp(i, i[ok], rec.wob[ok])
    b, a = sps.butter(2, WOB_TREND_HZ / (0.5 * fs), "high")
    deficit = sps.filtfilt(b, a, -np.cumsum(v - v.mean()) * rec.dt)
    wh = sps.filtfilt(b, a, w)
    if not (np.std(wh[ok]) > 1e-9 * (1.0 + abs(float(np.mean(w)))) and np.std(deficit[ok]) > 0):
        return {"correlation": 0.0, "lag_s": 0.0, "gain_n_rad": 0.0, "response": False}  # no fast part to follow
    m = int(round(RESPONSE_LAG_S * fs))
    core = ok.copy()
    core[:m], core[len(core) - m:] = False, False
    best = (-np.inf, 0)
    for k in range(-m, m + 1, max(1, int(round(0.002 * fs)))):
        d = np.roll(deficit, k)  # d[j] = deficit[j - k]: the WOB follows the deficit by k samples
        r = float(np.corrcoef(d[core], wh[core])[0, 1])
        best = max(best, (r, k))
    r, k = best
    d = np.roll(deficit, k)
    gain = float(np.polyfit(d[core], wh[core], 1)[0])
    return {"correlation": r, "lag_s": k / fs, "gain_n_rad": gain, "response": bool(r >= RESPONSE_R and gain > 0)}


def prepare(record: Record | str | Path, cfg: dict, opt: LoopOptions, scale: tuple | None = None) -> LoopData:
    """Clean a record, estimate derivatives, decimate, cut horizons and split them.

    The record is cleaned (:func:`drillpy.records.cleaning.clean`, spikes searched in the encoder
    channels only), its channels and their derivatives estimated by Savitzky-Golay filters at the
    record's rate and decimated by the integer factor that brings it to at most ``opt.rate_hz``.
    Horizons of ``opt.horizon_s`` are cut from :data:`FIRST_START_S` on; a horizon that holds an
    excluded sample or straddles ``t_split`` is dropped; one that overlaps a stall, or whose restart's
    top speed is not a measurement, is set apart (``LoopData.set_apart``, out of E: issue 28).

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
    scale : tuple of float, optional
        (sd_v [rad/s], sd_T [N m]): the scale of the metric E when it was set elsewhere (a model's
        calibration part: ``drillpy predict``); default the calibration part's spreads, stalls left
        out (:func:`drillpy.records.rig_comparison.metric_scale`).

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
    timing = None
    if opt.channel_timing != "none" and rec.top_speed is not None:
        # identified on the calibration part: the validation part is unseen
        part = rec.select(None, rec.time_s[0] + opt.calibration_fraction * (rec.time_s[-1] - rec.time_s[0]))
        timing = bit_balance.resolve_timing(part, opt.channel_timing, cfg, valid=reliable_top_speed(part))
        if timing["top_lead_s"] or timing["torque_lag_s"]:
            raw = bit_balance.aligned(raw, timing["top_lead_s"], timing["torque_lag_s"])
            rec, rep = clean(raw, CleaningOptions(spike_channels=ENCODER_CHANNELS))
    wresp = wob_response(rec)
    if wresp is None and rec.wob is not None and opt.wob_input != "auto":  # too short to test: the option decides
        wresp = {"correlation": None, "lag_s": None, "gain_n_rad": None, "response": False}
    wob_meas = None
    if wresp is not None:
        mode = opt.wob_input if opt.wob_input != "auto" else ("trend" if wresp["response"] else "measured")
        wresp["input"] = mode
        if mode == "trend":  # the law takes the WOB known beforehand: the jack's slow trend
            wob_meas = rec.wob
            rec = dataclasses.replace(rec, wob=wob_trend(rec, float(np.nanmean(rec.wob))))
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
    top_ref = float(np.median(ch["top"][ok])) if has_top else float(view(cfg).operation.top_speed_rad_s)
    thr = opt.stick_fraction * abs(top_ref)
    t_split = float(t[0] + opt.calibration_fraction * (t[-1] - t[0]))
    L = int(round(opt.horizon_s / dt))
    if L < 2:
        raise ValueError(f"horizon_s = {opt.horizon_s}: shorter than two samples of {dt:g} s")
    starts, is_test, apart = [], [], {}
    cum = np.r_[0, np.cumsum(~ok)]
    stuck = [(float(t[a]), float(t[min(a + n, t.size - 1)])) for a, n in stalls(v_meas, dt, thr)]
    top_ok = (reliable_top_speed(rec)[::q] & ok) if has_top else None
    first = int(math.ceil(FIRST_START_S / dt))  # room for the restart before a lagging sensor's horizon
    for s in range(first, t.size - L, L):
        if cum[s + L + 1] - cum[s] > 0:
            continue  # an excluded sample in the horizon
        if any(a <= t[s + L] and t[s] <= b for a, b in stuck):
            apart[s] = "stall"
            continue
        if has_top and not top_ok[s]:
            apart[s] = "top-speed artifact at the restart"
            continue
        if t[s + L] < t_split:
            starts.append(s), is_test.append(False)
        elif t[s] >= t_split:
            starts.append(s), is_test.append(True)
    starts, is_test = np.asarray(starts, dtype=np.int64), np.asarray(is_test, bool)
    n_tr, n_te = int((~is_test).sum()), int(is_test.sum())
    if n_tr < 4 or n_te < 4:
        raise ValueError(f"record: {n_tr} calibration and {n_te} validation horizons of {opt.horizon_s:g} s; need "
                         f"at least 4 each (a longer record, a shorter horizon_s or another calibration_fraction)")
    sv, sT = metric_scale(v_meas, T_meas, ok & (t < t_split), dt, thr) if scale is None else map(float, scale)
    top_meas = filled(rec.top_speed)[::q] if has_top else None
    if wob_meas is not None:
        wob_meas = _savgol_set(filled(wob_meas), rec.dt, opt.derivative_window_s, (0,))[0][::q]
    if not (sv > 0 and sT > 0):
        raise ValueError(f"scale = ({sv}, {sT}): the spreads of the metric E must be positive")
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
                    opt.batched, opt.law_knot, wresp, wob_meas, tuple((a, b - a) for a, b in stuck), apart, timing)



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

