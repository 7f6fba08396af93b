"""Summary statistics of a record that carry the stick-slip cycle (the data of the ABC-SMC).

Each statistic is computed alike on a measured record and on its simulation, after a start-up
``skip_s`` (the simulation's transient) and on the usable samples only:

============================ ========= =========================================================
name                         unit      definition
============================ ========= =========================================================
``ss``                       -         (p99.5 - p0.5 of the bit speed) / (2 x mean top speed):
                                       Eq. (3.4) with percentiles for the extremes (one glitch
                                       does not move it)
``stick_fraction``           -         fraction of samples with the bit speed at or below the
                                       stick threshold, the stalls left out (stick phases of at
                                       least 0.5 s and the 0.1 s break-away after each,
                                       :func:`drillpy.records.rig_comparison.stalls`, as the
                                       rig comparison leaves them out of its regular metrics);
                                       all samples when nothing but stall is left
``cycle_frequency_hz``       Hz        peak of the bit speed's periodogram (Hann) in 0.5-10 Hz,
                                       parabolic interpolation between bins (at most half a bin
                                       from the peak's)
``torque_p5/p50/p95``        N m       percentiles of the torque on bit
``bit_speed_p95``            rad/s     95th percentile of the bit speed
``top_speed_mean/std``       rad/s     over the reliable top-speed samples
                                       (:func:`drillpy.records.rigsim.reliable_top_speed`)
``wob_std``                  N         standard deviation of the WOB
``psd_0.2-2/2-4/4-8``        -         share of the bit speed's fluctuation power in the band [Hz]
``wob_above_trend_std``      N         standard deviation of the WOB above the jack's trend
                                       (:func:`wob_above_trend_std`): the WOB's part the rig
                                       model must produce itself, not its input; not in the
                                       default set :data:`NAMES`
============================ ========= =========================================================

:func:`noise_scale` is each statistic's own sampling uncertainty on a record (the spread between
blocks): the ABC distance measures a simulation's statistics in those units.
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np
from scipy import fft as sp_fft
from scipy import signal

from drillpy.records.io import Record
from drillpy.records.rig_comparison import stalls
from drillpy.records.rigsim import WOB_TREND_HZ, reliable_top_speed

#: The statistics, in the order of :func:`summaries`' vector.
#: Every statistic :func:`statistics` computes, in its order.
ALL_NAMES = ("ss", "stick_fraction", "cycle_frequency_hz", "torque_p5", "torque_p50", "torque_p95", "bit_speed_p95",
             "top_speed_mean", "top_speed_std", "wob_std", "psd_0.2-2", "psd_2-4", "psd_4-8", "wob_above_trend_std")
#: Units of :data:`ALL_NAMES`.
ALL_UNITS = ("-", "-", "Hz", "N m", "N m", "N m", "rad/s", "rad/s", "rad/s", "N", "-", "-", "-", "N")
#: The statistics of the distance by default (``calibration.statistics`` chooses others among
#: :data:`ALL_NAMES`): every one but ``wob_above_trend_std``, the set every number of
#: docs/calibration.md before its section "The WOB above its trend" was measured with.
NAMES = ALL_NAMES[:13]
#: Units of :data:`NAMES`.
UNITS = ALL_UNITS[:13]
_ABOVE = ALL_NAMES.index("wob_above_trend_std")
#: Bands of the PSD shares [Hz].
BANDS = ((0.2, 2.0), (2.0, 4.0), (4.0, 8.0))
#: Search band of the cycle frequency [Hz].
CYCLE_BAND = (0.5, 10.0)
#: The range each statistic can take (a measured window never leaves it): the predictive samples are
#: held in it (:func:`drillpy.calibration.posterior.predictive_intervals`).
BOUNDS = {"ss": (0.0, np.inf), "stick_fraction": (0.0, 1.0), "cycle_frequency_hz": CYCLE_BAND,
          "top_speed_std": (0.0, np.inf), "wob_std": (0.0, np.inf), "psd_0.2-2": (0.0, 1.0), "psd_2-4": (0.0, 1.0),
          "psd_4-8": (0.0, 1.0), "wob_above_trend_std": (0.0, np.inf)}


@lru_cache(maxsize=16)
def _hann(size: int) -> np.ndarray:
    return np.hanning(size)


def _periodogram(x: np.ndarray, dt: float):
    x = x - np.mean(x)
    n = sp_fft.next_fast_len(x.size, real=True)
    p = np.abs(sp_fft.rfft(x * _hann(x.size), n)) ** 2
    return np.fft.rfftfreq(n, dt), p


def summaries(record: Record, stick_threshold: float, skip_s: float = 2.0, names=NAMES) -> np.ndarray:
    """The summary statistics ``names`` (default :data:`NAMES`) of ``record`` after ``skip_s`` seconds.

    Parameters
    ----------
    record : Record
        A cleaned record (or a simulation of one) with bit speed, top speed and torque on bit.
    stick_threshold : float
        Bit speed at or below which the bit counts as stuck [rad/s].
    skip_s : float
        Start-up left out [s].
    names : sequence of str
        Statistics of :data:`ALL_NAMES`, in the order returned.

    Returns
    -------
    ndarray
        One value per name (NaN where a channel has no usable sample).
    """
    t = record.time_s
    after = t >= t[0] + skip_s
    ok = after & record.valid("bit_speed", "torque_on_bit")
    top_ok = after & reliable_top_speed(record)
    w = None
    if record.wob is not None:
        w = record.wob[after & record.valid("wob")]
    return statistics(record.bit_speed[ok], record.torque_on_bit[ok], record.top_speed[top_ok], w, record.dt,
                      stick_threshold, names)


def statistics(bit_speed, torque, top_speed, wob, dt: float, stick_threshold: float, names=NAMES) -> np.ndarray:
    """The summary statistics ``names`` of usable samples (:func:`summaries` on arrays).

    Parameters
    ----------
    bit_speed, torque : ndarray
        Bit speed [rad/s] and torque on bit [N m], equally sampled every ``dt``.
    top_speed : ndarray
        The reliable top-speed samples [rad/s].
    wob : ndarray or None
        The WOB samples [N].
    dt : float
        Sampling interval [s].
    stick_threshold : float
        [rad/s].
    names : sequence of str
        Statistics of :data:`ALL_NAMES` (default :data:`NAMES`), in the order returned.

    Returns
    -------
    ndarray
    """
    cols = _columns(tuple(names))
    return _all_statistics(bit_speed, torque, top_speed, wob, dt, stick_threshold, bool(np.any(cols == _ABOVE)))[cols]


@lru_cache(maxsize=16)
def _columns(names: tuple) -> np.ndarray:
    return np.array([ALL_NAMES.index(n) for n in names], int)


def _all_statistics(bit_speed, torque, top_speed, wob, dt: float, stick_threshold: float, above: bool) -> np.ndarray:
    out = np.full(len(ALL_NAMES), np.nan)
    v, tq = np.asarray(bit_speed, float), np.asarray(torque, float)
    if v.size < 16:
        return out
    top = top_speed if top_speed.size > 1 else np.array([np.nan])
    mean_top = float(np.mean(top))
    lo, p95, hi = np.percentile(v, [0.5, 95, 99.5])
    out[0] = (hi - lo) / (2.0 * abs(mean_top)) if mean_top else np.nan
    regular = np.ones(v.size, bool)
    after = int(round(0.1 / dt))  # the break-away that ends a stall is not a regular cycle either
    for a, k in stalls(v, dt, stick_threshold):
        regular[a:a + k + after] = False
    if regular.sum() < 3:  # nothing but stall: the whole, as rig_comparison.record_metrics does
        regular[:] = True
    out[1] = float(np.mean(v[regular] <= stick_threshold))
    # the periodogram over the usable stretch (gaps closed: they are short next to the record)
    f, p = _periodogram(v, dt)
    band = (f >= CYCLE_BAND[0]) & (f <= CYCLE_BAND[1])
    if band.sum() >= 3:
        i = int(np.flatnonzero(band)[np.argmax(p[band])])
        f0 = f[i]
        if 0 < i < p.size - 1 and p[i - 1] > 0 and p[i + 1] > 0:
            a, b, c = np.log(p[i - 1:i + 2])
            den = a - 2 * b + c
            if den < 0:  # a peak at the band's edge may have a higher neighbour outside it
                f0 = f[i] + float(np.clip(0.5 * (a - c) / den, -0.5, 0.5)) * (f[1] - f[0])
        out[2] = f0
    out[3:6] = np.percentile(tq, [5, 50, 95])
    out[6] = p95
    out[7] = mean_top
    out[8] = float(np.std(top))
    if wob is not None and wob.size > 1:
        out[9] = float(np.std(wob))
        if above:  # a filter per run: only when asked for
            out[_ABOVE] = wob_above_trend_std(wob, dt)
    total = p[(f >= BANDS[0][0]) & (f < BANDS[-1][1])].sum()
    for j, (a, b) in enumerate(BANDS):
        out[10 + j] = p[(f >= a) & (f < b)].sum() / total if total > 0 else np.nan
    return out


def wob_above_trend_std(wob, dt: float) -> float:
    """The standard deviation of the WOB above the jack's trend: the WOB minus its zero-phase
    second-order Butterworth low-pass at :data:`drillpy.records.rigsim.WOB_TREND_HZ`, the filter of
    :func:`drillpy.records.rigsim.wob_trend` (the slow WOB the rig model is given as an input): the
    part of the WOB the model must produce itself (the jack's response to the bit's rotation).

    Parameters
    ----------
    wob : ndarray
        WOB samples [N], equally sampled every ``dt``.
    dt : float
        Sampling interval [s].

    Returns
    -------
    float
        [N]; NaN with fewer than 30 samples.
    """
    w = np.asarray(wob, float)
    n = w.size
    if n < 30 or WOB_TREND_HZ >= 0.5 / dt:
        return float("nan")
    b, a = _trend_filter(WOB_TREND_HZ, 1.0 / dt)
    return float(np.std(w - signal.filtfilt(b, a, w, padlen=min(n - 1, 3 * int(1.0 / (dt * WOB_TREND_HZ))))))


@lru_cache(maxsize=8)
def _trend_filter(cutoff: float, fs: float):
    return signal.butter(2, cutoff, fs=fs)


def noise_scale(record: Record, stick_threshold: float, blocks: int = 4, skip_s: float = 0.0,
                names=NAMES) -> np.ndarray:
    """Each statistic's sampling uncertainty over ``record``: the standard deviation of the statistic
    between ``blocks`` consecutive blocks divided by sqrt(blocks), at least 2 % of its magnitude
    (and 1e-3 of its unit), so that a statistic the blocks happen to agree on still has a scale.

    Parameters
    ----------
    record : Record
        A cleaned record.
    stick_threshold : float
        Bit speed at or below which the bit counts as stuck [rad/s].
    blocks : int
        Number of blocks (at least 2).
    skip_s : float
        Start-up left out of the record before it is cut [s].
    names : sequence of str
        Statistics of :data:`ALL_NAMES` (default :data:`NAMES`).

    Returns
    -------
    ndarray
        One positive scale per name.
    """
    t0 = float(record.time_s[0]) + skip_s
    edges = np.linspace(t0, float(record.time_s[-1]), max(int(blocks), 2) + 1)
    vals = np.array([summaries(record.select(a, b), stick_threshold, 0.0, names)
                     for a, b in zip(edges[:-1], edges[1:])])
    whole = summaries(record.select(t0, None), stick_threshold, 0.0, names)
    sd = np.nanstd(vals, axis=0, ddof=1) / np.sqrt(vals.shape[0])
    floor = np.maximum(0.02 * np.abs(whole), 1e-3)
    return np.where(np.isfinite(sd), np.maximum(sd, floor), floor)
