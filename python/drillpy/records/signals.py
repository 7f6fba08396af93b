"""Signal analysis of stick-slip records (thesis sections 3.2, 4.1 and 5.3).

Smoothing and derivatives (sliding-window average, the rig's 10 Hz IIR low-pass, the bit
acceleration), stick-slip cycle segmentation with per-cycle statistics (period, stick duration,
SS of Eq. 3.4), the accelerating (upper) and decelerating (lower) branches of each cycle, the mean
cycle per branch (Fig. 3.5), the experimental fluctuation process eta_exp (Eq. 4.2) on a regular
grid (Eq. 4.3; its periodogram and the PSD model of Eq. 4.4 are in :mod:`drillpy.uncertainty.process`), and the
sample statistics of Table 5.2 (mean, std, CV) and Var[MSE] (Eq. 5.2).

Arrays are SI (rad/s, rad/s^2, N m, s) unless a name says otherwise. Everything is vectorized
NumPy/SciPy; there is no per-sample Python loop.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy import signal as sps

#: Statistics of eta_exp over the 210 rig samples (section 5.3.2).
THESIS_ETA_MEAN, THESIS_ETA_STD = 7.8296e-5, 0.4674


# ------------------------------------------------------------------------------ smoothing
def swa(x, window: int) -> np.ndarray:
    """Sliding-window average (SWA, thesis section 3.2): centred moving mean over ``window`` samples.

    NaNs are skipped (the mean of the finite values inside the window); windows shrink at the
    edges. The thesis smooths the field and rig data this way before drawing the cycles.

    Parameters
    ----------
    x : array_like
        The signal, any unit (e.g. bit speed [rad/s] or torque on bit [N m]).
    window : int
        Window length [samples], at least 1; an even value is raised by one so the average stays
        centred (no lag).

    Returns
    -------
    ndarray
        Same shape and unit as ``x``; NaN only where a window holds no finite value.
    """
    x = np.asarray(x, float)
    w = int(window)
    if w < 1:
        raise ValueError(f"window = {window!r}: must be a positive number of samples")
    w |= 1
    fin = np.isfinite(x)
    k = np.ones(w)
    s = np.convolve(np.where(fin, x, 0.0), k, mode="same")
    c = np.convolve(fin.astype(float), k, mode="same")
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(c > 0, s / np.maximum(c, 1), np.nan)


def rig_lowpass(x, fs_hz: float, cutoff_hz: float = 10.0, order: int = 2) -> np.ndarray:
    """The rig's acquisition filter: second-order IIR low-pass at 10 Hz (section 5.3.1).

    A causal Butterworth filter (the LabVIEW IIR default), started at rest on the first value so
    that a constant input passes unchanged. Apply it to simulated signals before comparing them
    with the measured ones, which went through it (it delays and flattens sharp peaks such as
    the break-away torque).

    Parameters
    ----------
    x : array_like
        Uniformly sampled signal, any unit; must be all finite.
    fs_hz : float
        Sampling rate [Hz].
    cutoff_hz : float
        Cut-off frequency [Hz], in (0, fs_hz / 2); the rig's is 10 Hz.
    order : int
        Filter order (the rig's: 2).

    Returns
    -------
    ndarray
        The filtered signal, same unit and length.

    Raises
    ------
    ValueError
        For a non-positive rate, a cut-off outside (0, fs/2) or a non-finite sample.
    """
    x = np.asarray(x, float)
    if not (np.isfinite(fs_hz) and fs_hz > 0):
        raise ValueError(f"fs_hz = {fs_hz!r}: must be a positive sampling rate")
    if not (0 < cutoff_hz < fs_hz / 2):
        raise ValueError(f"cutoff_hz = {cutoff_hz!r}: must lie in (0, fs/2 = {fs_hz / 2:g}) Hz")
    if not np.all(np.isfinite(x)):
        raise ValueError("rig_lowpass: the signal has non-finite values (clean it first)")
    b, a, zi = _lowpass_design(float(fs_hz), float(cutoff_hz), int(order))
    y, _ = sps.lfilter(b, a, x, zi=zi * x[0])
    return y


@lru_cache(maxsize=64)
def _lowpass_design(fs_hz: float, cutoff_hz: float, order: int) -> tuple:
    """(b, a, zi at a unit input) of :func:`rig_lowpass` (designed once per rate: a calibration filters
    every run's channels at the same rate)."""
    b, a = sps.butter(order, cutoff_hz, btype="low", fs=fs_hz)
    return b, a, sps.lfilter_zi(b, a)


@lru_cache(maxsize=64)
def _platform_design(fs_hz: float, natural_hz: float, damping: float) -> tuple:
    """(b, a, zi at a unit input) of :func:`platform_response`."""
    wn = 2.0 * np.pi * natural_hz
    b, a = sps.bilinear([wn * wn], [1.0, 2.0 * damping * wn, wn * wn], fs=fs_hz)
    return b, a, sps.lfilter_zi(b, a)


def platform_response(x, fs_hz: float, natural_hz: float = 20.0, damping: float = 0.5) -> np.ndarray:
    """What the rig's torque load cell reads of a contact torque: the platform's second-order response.

    The rock holder sits on a platform free to rotate, held by a rod on a cantilever load cell
    (thesis section 5.3.1); "20 Hz is the first natural frequency for platform set plus electrical
    jack set". The contact torque T drives the platform (J_p, c_p, k_p) and the cell reads its
    spring force y = k_p phi_p:

        y'' + 2 zeta w_n y' + w_n^2 y = w_n^2 T,        w_n = 2 pi natural_hz

    (unit gain at rest), discretized by the bilinear transform (at 1 kHz it places 20 Hz 0.13 %
    low), started at rest on the first value. The 10 Hz acquisition filter
    (:func:`rig_lowpass`) comes after it.

    Parameters
    ----------
    x : array_like
        Uniformly sampled contact torque [N m]; must be all finite.
    fs_hz : float
        Sampling rate [Hz], above 2 natural_hz.
    natural_hz : float
        The platform's natural frequency [Hz] (the rig's: 20).
    damping : float
        Its damping ratio zeta [-], positive.

    Returns
    -------
    ndarray
        The load cell's reading [N m], same length.

    Raises
    ------
    ValueError
        For a non-positive rate or damping, a natural frequency outside (0, fs/2) or a
        non-finite sample.
    """
    x = np.asarray(x, float)
    if not (np.isfinite(fs_hz) and fs_hz > 0):
        raise ValueError(f"fs_hz = {fs_hz!r}: must be a positive sampling rate")
    if not (0 < natural_hz < fs_hz / 2):
        raise ValueError(f"natural_hz = {natural_hz!r}: must lie in (0, fs/2 = {fs_hz / 2:g}) Hz")
    if not (np.isfinite(damping) and damping > 0):
        raise ValueError(f"damping = {damping!r}: must be a positive damping ratio")
    if not np.all(np.isfinite(x)):
        raise ValueError("platform_response: the signal has non-finite values")
    b, a, zi = _platform_design(float(fs_hz), float(natural_hz), float(damping))
    y, _ = sps.lfilter(b, a, x, zi=zi * x[0])
    return y


def savgol_length(window_s: float, dt: float, size: int, minimum: int = 1) -> int:
    """Odd Savitzky-Golay window length [samples] for ``window_s`` seconds (at least ``minimum``),
    shortened to the longest odd length that fits ``size`` samples.

    Parameters
    ----------
    window_s : float
        Wanted window [s].
    dt : float
        Sampling interval [s].
    size : int
        Number of samples of the signal the window is for.
    minimum : int
        Shortest length returned when the signal is long enough [samples].

    Returns
    -------
    int
        Window length [samples].
    """
    n = max(int(round(window_s / dt)) | 1, minimum)
    if n > size:
        n = size if size % 2 else size - 1
    return n


def derivative(x, dt: float, window_s: float = 0.021, polyorder: int = 3) -> np.ndarray:
    """Time derivative by a Savitzky-Golay filter (local polynomial of ``polyorder`` over
    ``window_s`` seconds); ``window_s = 0`` gives second-order central differences.

    Used for the bit acceleration [rad/s^2] from the bit speed [rad/s], the second argument of
    the hysteretic laws (Eqs. 3.2-3.3, 5.3).

    Parameters
    ----------
    x : array_like
        Uniformly sampled signal, all finite (clean it first).
    dt : float
        Sampling interval [s].
    window_s : float
        Savitzky-Golay window [s] (21 ms by default: 21 samples at 1 kHz); when it holds no more
        than ``polyorder + 1`` samples, :func:`numpy.gradient` is used instead.
    polyorder : int
        Order of the local polynomial.

    Returns
    -------
    ndarray
        dx/dt in the unit of ``x`` per second.

    Raises
    ------
    ValueError
        If ``x`` has a non-finite value.
    """
    x = np.asarray(x, float)
    if not np.all(np.isfinite(x)):
        raise ValueError("derivative: the signal has non-finite values (clean it first)")
    n = savgol_length(window_s, dt, x.size)
    if n <= polyorder + 1:
        return np.gradient(x, dt)
    return sps.savgol_filter(x, n, polyorder, deriv=1, delta=dt, mode="interp")


def severity(bit_speed, top_speed) -> float:
    """Stick-slip severity SS = (max v_bit - min v_bit) / (2 Omega) (Eq. 3.4).

    SS = 0 without torsional oscillation; SS = 1 when the bit sticks (min 0) and reaches twice the
    top speed; the thesis calls the string stable below 0.5 (section 3.3).

    Parameters
    ----------
    bit_speed : array_like
        Bit speed over the chosen span [rad/s] (NaNs ignored).
    top_speed : float or array_like
        Top-drive speed Omega [rad/s]: a constant or a series, of which the mean (NaNs ignored)
        is used. Any consistent unit works, SS is dimensionless.

    Returns
    -------
    float
        SS [-].
    """
    om = float(np.nanmean(np.asarray(top_speed, float)))
    v = np.asarray(bit_speed, float)
    return float((np.nanmax(v) - np.nanmin(v)) / (2.0 * abs(om)))


# ------------------------------------------------------------------------------ cycles
@dataclass
class Cycles:
    """Stick-slip cycles as sample indices into the record they were found in.

    Cycle j spans ``start[j] <= i < end[j]``: it starts when the bit leaves the trough (the end
    of the stick phase, or the minimum of the speed when the bit does not stick), accelerates up
    to ``peak[j]`` (upper branch), decelerates (lower branch) and sticks from ``stick[j]``
    (``stick[j] == end[j]`` when the bit does not stick). ``valid[j]`` is False when the cycle
    touches an excluded sample. Made by :func:`segment_cycles`.

    Attributes
    ----------
    start, peak, stick, end : ndarray of int
        Per cycle: first sample, sample of the bit-speed peak, first stuck sample, and one past
        the last sample (the next cycle's start).
    valid : ndarray of bool
        Per cycle: True when every sample of the cycle was usable.
    dt : float
        Sampling interval of the record [s].
    stick_threshold : float
        Bit speed at or below which the bit counted as stuck [rad/s].
    """
    start: np.ndarray
    peak: np.ndarray
    stick: np.ndarray
    end: np.ndarray
    valid: np.ndarray
    dt: float
    stick_threshold: float

    def __len__(self) -> int:
        return self.start.size

    @property
    def period_s(self) -> np.ndarray:
        """Duration of each cycle [s] (every cycle, valid or not)."""
        return (self.end - self.start) * self.dt

    @property
    def stick_s(self) -> np.ndarray:
        """Duration of the stick phase of each cycle [s] (0 when the bit did not stick)."""
        return (self.end - self.stick) * self.dt

    def cycle_id(self, n: int) -> np.ndarray:
        """Per sample of the record: index of the valid cycle holding it, or -1.

        Parameters
        ----------
        n : int
            Number of samples of the record the cycles were found in.

        Returns
        -------
        ndarray of int64, shape (n,)
            Cycle index (into ``start``, ``end``, ...), -1 outside valid cycles; the clusters of
            :class:`drillpy.records.identification.FitData`.
        """
        out = np.full(n, -1, dtype=np.int64)
        for j in np.flatnonzero(self.valid):
            out[self.start[j]:self.end[j]] = j
        return out

    def branch_labels(self, n: int) -> np.ndarray:
        """Per sample: +1 on the accelerating (upper) branch start..peak, -1 on the decelerating
        (lower) branch peak..stick, 0 in stick phases and outside valid cycles.

        The two branches are the upper and lower paths of the torque-speed loop (Figs. 3.4, 5.7b).

        Parameters
        ----------
        n : int
            Number of samples of the record the cycles were found in.

        Returns
        -------
        ndarray of int8, shape (n,)
        """
        out = np.zeros(n, dtype=np.int8)
        for j in np.flatnonzero(self.valid):
            out[self.start[j]:self.peak[j] + 1] = 1
            out[self.peak[j] + 1:self.stick[j]] = -1
        return out

    def longest_stick(self) -> int:
        """Index of the valid cycle with the longest stick phase (the one of Figs. 5.6-5.7)."""
        s = np.where(self.valid, self.stick_s, -1.0)
        return int(np.argmax(s))


def segment_cycles(bit_speed, dt: float, stick_threshold: float, *, valid=None,
                   prominence: float | None = None, min_period_s: float = 0.1) -> Cycles:
    """Cut a bit-speed history into stick-slip cycles.

    Parameters
    ----------
    bit_speed : array [rad/s]
    dt : float
        Sampling interval [s].
    stick_threshold : float
        The bit is stuck while its speed is at or below this [rad/s] (the engine's metrics use 5 %
        of the top speed).
    valid : bool array, optional
        Samples that may be used; cycles touching any other sample are marked invalid.
    prominence : float, optional
        Minimum prominence of a speed peak that makes a cycle [rad/s]; default 25 % of the
        1-99 % range of the speed.
    min_period_s : float
        Minimum distance between two peaks [s].

    Returns
    -------
    Cycles
    """
    v = np.asarray(bit_speed, float)
    n = v.size
    ok = np.isfinite(v) if valid is None else (np.asarray(valid, bool) & np.isfinite(v))
    if ok.sum() < 3:
        raise ValueError(f"bit_speed: {int(ok.sum())} valid samples of {n}: too few to find stick-slip cycles (3 at least)")
    idx = np.arange(n)
    vf = np.where(ok, v, np.interp(idx, idx[ok], v[ok]))
    lo, hi = np.percentile(vf[ok], [1, 99])
    prom = 0.25 * (hi - lo) if prominence is None else float(prominence)
    peaks, _ = sps.find_peaks(vf, prominence=prom, distance=max(1, int(round(min_period_s / dt))))
    empty = np.zeros(0, dtype=np.int64)
    if peaks.size < 2:
        return Cycles(empty, empty, empty, empty, np.zeros(0, bool), dt, stick_threshold)
    tol = 0.01 * (hi - lo)
    bounds, sticks = [], []
    for p, q in zip(peaks[:-1], peaks[1:]):
        seg = vf[p:q]
        m = seg.min()
        low = np.flatnonzero(seg <= max(m + tol, stick_threshold))
        bounds.append(p + low[-1])
        st = np.flatnonzero(seg <= stick_threshold)
        sticks.append(p + st[0] if st.size else p + low[-1])
    bounds = np.asarray(bounds, dtype=np.int64)
    sticks = np.asarray(sticks, dtype=np.int64)
    start, end = bounds[:-1], bounds[1:]
    peak = peaks[1:-1]
    stick = sticks[1:]
    bad = np.r_[0, np.cumsum(~ok)]
    valid_c = (bad[end] - bad[start]) == 0
    return Cycles(start, peak, stick, end, valid_c, dt, stick_threshold)


def cycle_statistics(cycles: Cycles, bit_speed, top_speed=None, torque=None, wob=None) -> dict:
    """Per-cycle statistics of the valid cycles (arrays, one entry per valid cycle).

    Parameters
    ----------
    cycles : Cycles
        From :func:`segment_cycles` on the same record.
    bit_speed : array_like
        Bit speed [rad/s], one value per sample of the record.
    top_speed : array_like, optional
        Top-drive speed [rad/s]; NaN samples make that cycle's mean top speed and SS NaN (how a
        caller excludes unreliable top-speed samples).
    torque : array_like, optional
        Torque on bit [N m].
    wob : array_like, optional
        Weight on bit [N].

    Returns
    -------
    dict
        ``index`` (cycle indices), ``start_s`` (from the first sample), ``period_s``,
        ``frequency_hz``, ``stick_s``, ``slip_s``, ``max_speed``/``min_speed`` [rad/s], and when
        given ``mean_top_speed`` [rad/s] with ``ss`` (Eq. 3.4 over the cycle),
        ``torque_min``/``torque_max`` [N m], ``wob_min``/``wob_max`` [N].
    """
    j = np.flatnonzero(cycles.valid)
    v = np.asarray(bit_speed, float)
    out = {"index": j, "start_s": cycles.start[j] * cycles.dt, "period_s": cycles.period_s[j],
           "stick_s": cycles.stick_s[j]}
    out["frequency_hz"] = 1.0 / out["period_s"]
    out["slip_s"] = out["period_s"] - out["stick_s"]
    edges = np.r_[cycles.start, cycles.end[-1:]] if len(cycles) else np.zeros(0, np.int64)

    def seg(x, ufunc):  # per-cycle reduction over the contiguous cycles, then the valid ones
        if not len(cycles):
            return np.zeros(0)
        if ufunc is np.mean:
            return (np.add.reduceat(x, edges)[:-1] / np.diff(edges))[j]
        return ufunc.reduceat(x, edges)[:-1][j]

    out["max_speed"] = seg(v, np.maximum)
    out["min_speed"] = seg(v, np.minimum)
    if top_speed is not None:
        out["mean_top_speed"] = seg(np.asarray(top_speed, float), np.mean)
        out["ss"] = (out["max_speed"] - out["min_speed"]) / (2.0 * np.abs(out["mean_top_speed"]))
    if torque is not None:
        out["torque_min"] = seg(np.asarray(torque, float), np.minimum)
        out["torque_max"] = seg(np.asarray(torque, float), np.maximum)
    if wob is not None:
        out["wob_min"] = seg(np.asarray(wob, float), np.minimum)
        out["wob_max"] = seg(np.asarray(wob, float), np.maximum)
    return out


def dominant_frequency(x, fs_hz: float, fmin_hz: float = 0.5, segment_s: float = 8.0,
                       prominence: float = 10.0) -> float:
    """Frequency [Hz] of the highest Welch-PSD peak of ``x`` above ``fmin_hz``, NaN when that peak
    does not stand out: below ``prominence`` times the median PSD from half to twice its frequency
    (a record that only carries sensor noise has no cycle; white noise's highest peak is about 3
    times that median).

    Applied to the bit speed it gives the stick-slip cycle frequency (about 2.6-2.8 Hz on sample
    175, near the rig's first torsional frequency of 3 Hz, section 5.3.1).

    Parameters
    ----------
    x : array_like
        Uniformly sampled, finite signal (its mean is removed).
    fs_hz : float
        Sampling rate [Hz].
    fmin_hz : float
        Lowest frequency considered [Hz] (keeps slow drifts of the operating point out).
    segment_s : float
        Welch segment length [s] (shortened to the signal); the resolution is 1 / segment_s
        (0.125 Hz by default).
    prominence : float
        How far the peak must rise above the PSD around it.

    Returns
    -------
    float
        Frequency of the peak [Hz]; NaN when it does not stand out.
    """
    x = np.asarray(x, float)
    nper = min(x.size, int(segment_s * fs_hz))
    f, p = sps.welch(x - np.mean(x), fs=fs_hz, nperseg=nper)
    m = f >= fmin_hz
    k = int(np.argmax(p[m]))
    fk, pk = float(f[m][k]), float(p[m][k])
    around = p[(f >= 0.5 * fk) & (f <= 2.0 * fk)]
    return fk if pk >= prominence * float(np.median(around)) else float("nan")


def cycle_response(x, y, fs_hz: float, band_hz: tuple = (1.0, 6.0), segment_s: float = 8.0) -> dict:
    """Response of ``y`` to ``x`` at the cycle frequency: the highest Welch peak of ``x`` inside
    ``band_hz``, and there the phase of ``y`` relative to ``x`` (from their cross-spectrum), the ratio
    of their amplitudes and their coherence.

    On the rig, ``x`` the bit speed and ``y`` the top speed (two encoders through one filter) say how
    the drive gives way in the cycle: a droop c at the top of a bar of stiffness k gives y = x / (1 + i
    w c / k), an inertia behind it up to a quarter period more lag (docs/records.md, section 4).

    Parameters
    ----------
    x, y : array_like
        Uniformly sampled, finite signals of one length (their means are removed).
    fs_hz : float
        Sampling rate [Hz].
    band_hz : tuple
        Where the peak of ``x`` is searched [Hz].
    segment_s : float
        Welch segment length [s] (shortened to the signals).

    Returns
    -------
    dict
        ``frequency_hz``, ``phase_deg`` (positive: ``y`` leads), ``gain``, ``coherence``,
        ``in_phase`` = gain cos(phase), the part of ``y`` in phase with ``x`` per unit of ``x``, and
        ``response``, the complex ratio Y / X there (cross-spectrum over the spectrum of ``x``: the
        part of ``y`` coherent with ``x``); NaN for a ``y`` without variation, and all NaN when no
        frequency of the spectra lies in ``band_hz``.
    """
    x = np.asarray(x, float) - np.mean(x)
    y = np.asarray(y, float) - np.mean(y)
    n = min(x.size, int(segment_s * fs_hz))
    f, pxx = sps.welch(x, fs_hz, nperseg=n)
    _, pyy = sps.welch(y, fs_hz, nperseg=n)
    _, pxy = sps.csd(x, y, fs_hz, nperseg=n)  # conj(X) Y: the phase of y relative to x
    band = np.flatnonzero((f >= band_hz[0]) & (f <= band_hz[1]))
    nan = float("nan")
    if band.size == 0:  # the band lies above the Nyquist frequency or between two bins
        return {"frequency_hz": nan, "phase_deg": nan, "gain": nan, "coherence": nan, "in_phase": nan,
                "response": complex(nan, nan)}
    k = band[np.argmax(pxx[band])]
    if not (pxx[k] > 0 and pyy[k] > 0):
        return {"frequency_hz": float(f[k]), "phase_deg": nan, "gain": nan, "coherence": nan, "in_phase": nan,
                "response": complex(nan, nan)}
    gain, phase = float(np.sqrt(pyy[k] / pxx[k])), float(np.angle(pxy[k]))
    return {"frequency_hz": float(f[k]), "phase_deg": float(np.degrees(phase)), "gain": gain,
            "coherence": float(abs(pxy[k]) ** 2 / (pxx[k] * pyy[k])), "in_phase": gain * float(np.cos(phase)),
            "response": complex(pxy[k] / pxx[k])}


def stick_slip_metrics(t, bit_speed, top_speed, torque, stick_threshold: float, valid=None) -> dict:
    """Summary of a stick-slip history: the numbers the measured and simulated rig are compared on.

    Parameters
    ----------
    t : array_like
        Sample times [s] (uniform; the median step is used).
    bit_speed : array_like
        Bit speed [rad/s].
    top_speed : array_like
        Top-drive speed [rad/s].
    torque : array_like
        Torque on bit [N m].
    stick_threshold : float
        Bit speed at or below which the bit counts as stuck [rad/s]
        (:func:`drillpy.records.stick.stick_threshold`).
    valid : array_like of bool, optional
        Samples to use; default: finite bit speed and torque. The cycle frequency is taken on the
        longest run of valid samples.

    Returns
    -------
    dict
        ``ss`` (Eq. 3.4 over the valid samples), ``mean_top_speed`` [rad/s],
        ``cycle_frequency_hz`` (dominant Welch peak of the bit speed), ``n_cycles``,
        ``mean_period_s``/``median_period_s`` (segmentation; NaN without a cycle),
        ``stick_fraction`` (fraction of the valid samples at or below the stick threshold),
        ``bit_speed_p95`` [rad/s], ``torque_p5``/``torque_p95``/``torque_min``/``torque_max`` [N m].
    """
    t = np.asarray(t, float)
    v = np.asarray(bit_speed, float)
    ok = np.isfinite(v) & np.isfinite(torque) if valid is None else np.asarray(valid, bool)
    dt = float(np.median(np.diff(t)))
    cyc = segment_cycles(v, dt, stick_threshold, valid=ok)
    per = cyc.period_s[cyc.valid]  # empty when the bit does not stick-slip
    tq = np.asarray(torque, float)[ok]
    vv = v[ok]
    # dominant frequency on the longest run of valid samples
    runs = np.flatnonzero(np.diff(np.r_[0, ok.astype(np.int8), 0]))
    a, b = max(zip(runs[::2], runs[1::2]), key=lambda r: r[1] - r[0])
    return {"ss": severity(vv, np.asarray(top_speed, float)[ok]),
            "mean_top_speed": float(np.mean(np.asarray(top_speed, float)[ok])),
            "cycle_frequency_hz": dominant_frequency(v[a:b], 1.0 / dt),
            "n_cycles": int(cyc.valid.sum()),
            "mean_period_s": float(np.mean(per)) if per.size else float("nan"),
            "median_period_s": float(np.median(per)) if per.size else float("nan"),
            "stick_fraction": float(np.mean(vv <= stick_threshold)),
            "bit_speed_p95": float(np.percentile(vv, 95)),
            "torque_p5": float(np.percentile(tq, 5)), "torque_p95": float(np.percentile(tq, 95)),
            "torque_min": float(np.min(tq)), "torque_max": float(np.max(tq))}


# ------------------------------------------------------------------------------ mean cycle
def speed_window_mean(v, y, grid, half_width: float, min_count: int = 1):
    """Mean of ``y`` over the samples whose speed lies within ``half_width`` of each grid speed
    (the SWA at each bit speed of section 3.2 and Eq. 4.3).

    Parameters
    ----------
    v : array_like
        Bit speed of each sample [rad/s].
    y : array_like
        Quantity averaged, same length (torque on bit [N m], bit acceleration [rad/s^2], ...);
        pairs with a non-finite ``v`` or ``y`` are skipped.
    grid : array_like
        Bit speeds at which the mean is taken [rad/s].
    half_width : float
        Half width of the speed window [rad/s]; both window ends are included.
    min_count : int
        Fewest samples a window needs for a mean (at least 1).

    Returns
    -------
    mean : ndarray
        Mean of ``y`` per grid speed, in the unit of ``y`` (NaN where fewer than ``min_count``
        samples).
    count : ndarray of int
        Number of samples in each window.
    """
    v = np.asarray(v, float)
    y = np.asarray(y, float)
    g = np.asarray(grid, float)
    m = np.isfinite(v) & np.isfinite(y)
    order = np.argsort(v[m])
    vs, ys = v[m][order], y[m][order]
    cs = np.r_[0.0, np.cumsum(ys)]
    lo = np.searchsorted(vs, g - half_width, side="left")
    hi = np.searchsorted(vs, g + half_width, side="right")
    cnt = hi - lo
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.where(cnt >= max(1, min_count), (cs[hi] - cs[lo]) / np.maximum(cnt, 1), np.nan)
    return mean, cnt


@dataclass
class MeanCycle:
    """Mean stick-slip cycle per branch (Fig. 3.5) on a bit-speed grid [rad/s].

    ``all`` is the mean over both branches (the thesis's blue line, T_hys of Eq. 4.2), ``upper``
    and ``lower`` the means of the accelerating and decelerating branches (green lines), with the
    mean bit acceleration of each branch in each bin [rad/s^2] (to evaluate hysteretic laws on
    the mean cycle) and the sample counts. Made by :func:`mean_cycle`.

    Attributes
    ----------
    speed : ndarray
        Bit-speed grid [rad/s].
    all, upper, lower : ndarray
        Mean torque on bit per grid speed [N m]: both branches, the accelerating (upper) branch
        and the decelerating (lower) branch; NaN in bins with too few samples.
    accel_upper, accel_lower : ndarray
        Mean bit acceleration of the upper and lower branch per grid speed [rad/s^2].
    n_all, n_upper, n_lower : ndarray of int
        Number of samples averaged in each bin.
    half_width : float
        Half width of the speed window of each bin [rad/s].
    """
    speed: np.ndarray
    all: np.ndarray
    upper: np.ndarray
    lower: np.ndarray
    accel_upper: np.ndarray
    accel_lower: np.ndarray
    n_all: np.ndarray
    n_upper: np.ndarray
    n_lower: np.ndarray
    half_width: float

    def reference(self, v, branch=None) -> np.ndarray:
        """T_hys at speeds ``v``: the all-branch curve, or the branch curves where ``branch`` is
        +1 (upper) / -1 (lower); linear interpolation, NaN outside the covered speeds.

        Parameters
        ----------
        v : array_like
            Bit speeds [rad/s].
        branch : array_like of int, optional
            Per speed: +1 takes the upper curve, -1 the lower curve, 0 the all-branch curve
            (e.g. :meth:`Cycles.branch_labels`); None: the all-branch curve everywhere.

        Returns
        -------
        ndarray
            Reference torque on bit [N m], shape of ``v``.
        """
        v = np.asarray(v, float)
        out = _interp_nan(v, self.speed, self.all)
        if branch is not None:
            b = np.asarray(branch)
            out = np.where(b > 0, _interp_nan(v, self.speed, self.upper), out)
            out = np.where(b < 0, _interp_nan(v, self.speed, self.lower), out)
        return out


def _interp_nan(x, xp, fp):
    ok = np.isfinite(fp)
    if ok.sum() < 2:
        return np.full(np.shape(x), np.nan)
    y = np.interp(x, xp[ok], fp[ok], left=np.nan, right=np.nan)
    return y


def mean_cycle(bit_speed, torque, accel, labels, *, grid=None, half_width: float | None = None,
               min_count: int = 20) -> MeanCycle:
    """Mean cycle per branch by SWA at each bit speed (section 3.2, Fig. 3.5).

    Parameters
    ----------
    bit_speed, torque, accel : arrays [rad/s, N m, rad/s^2]
    labels : int array
        +1 upper branch, -1 lower branch, 0 excluded (:meth:`Cycles.branch_labels`).
    grid : array, optional
        Bit speeds [rad/s]; default 60 points from 0 to the 99th percentile of the slip speeds.
    half_width : float, optional
        Half width of the speed window [rad/s]; default one grid step.
    min_count : int
        Bins with fewer samples are NaN.
    """
    v = np.asarray(bit_speed, float)
    lab = np.asarray(labels)
    slip = lab != 0
    if slip.sum() < min_count:
        raise ValueError("mean_cycle: too few slip samples in valid cycles")
    if grid is None:
        grid = np.linspace(0.0, np.percentile(v[slip], 99), 60)
    grid = np.asarray(grid, float)
    hw = float(grid[1] - grid[0]) if half_width is None else float(half_width)
    ma, na = speed_window_mean(v[slip], torque[slip], grid, hw, min_count)
    up, lo = lab > 0, lab < 0
    mu, nu = speed_window_mean(v[up], torque[up], grid, hw, min_count)
    ml, nl = speed_window_mean(v[lo], torque[lo], grid, hw, min_count)
    au, _ = speed_window_mean(v[up], accel[up], grid, hw, min_count)
    al, _ = speed_window_mean(v[lo], accel[lo], grid, hw, min_count)
    return MeanCycle(grid, ma, mu, ml, au, al, na, nu, nl, hw)


# ------------------------------------------------------------------------------ eta_exp
@dataclass
class EtaSeries:
    """The experimental fluctuation process eta_exp(t) = T_exp / T_hys - 1 (Eq. 4.2) on the
    record's regular time grid. ``measured`` marks the samples where it was computed (slip
    samples of valid cycles); the others are linearly interpolated in time (Eq. 4.3: the
    periodogram needs a regular grid). Made by :func:`eta_exp`.

    Attributes
    ----------
    t : ndarray
        Sample times [s], from the first to the last measured sample.
    eta : ndarray
        eta_exp [-] (relative torque fluctuation) at each time.
    measured : ndarray of bool
        True where eta was computed from the torque, False where interpolated.
    """
    t: np.ndarray
    eta: np.ndarray
    measured: np.ndarray

    @property
    def fs_hz(self) -> float:
        """Sampling rate of the series [Hz] (1 / median step)."""
        return 1.0 / float(np.median(np.diff(self.t)))

    def statistics(self) -> dict:
        """Statistics of the measured samples, to compare with the thesis's mean 7.83e-5 and
        standard deviation 0.4674 over the 210 rig samples (section 5.3.2).

        Returns
        -------
        dict
            ``mean``, ``std`` (ddof = 1), ``n_measured`` and ``interpolated_fraction`` (share of
            the series that was interpolated).
        """
        e = self.eta[self.measured]
        return {"mean": float(np.mean(e)), "std": float(np.std(e, ddof=1)),
                "n_measured": int(e.size), "interpolated_fraction": float(1 - self.measured.mean())}


def eta_exp(t, bit_speed, torque, labels, mc: MeanCycle, reference: str = "mean",
            min_reference: float | None = None) -> EtaSeries:
    """Experimental eta (Eq. 4.2) with T_hys the mean of all cycles (``reference="mean"``, the
    thesis's blue line) or the branch mean curves (``reference="branch"``).

    Samples where the reference torque is below ``min_reference`` (default 5 % of its maximum) or
    undefined are not measured.

    Parameters
    ----------
    t : array_like
        Sample times [s] of the record.
    bit_speed : array_like
        Bit speed [rad/s].
    torque : array_like
        Measured torque on bit T_exp [N m].
    labels : array_like of int
        Branch of each sample (:meth:`Cycles.branch_labels`); only slip samples (label != 0) are
        measured.
    mc : MeanCycle
        Mean cycle of the same record (:func:`mean_cycle`), the reference T_hys.
    reference : str
        ``"mean"`` (all-branch curve) or ``"branch"`` (upper/lower curves by label).
    min_reference : float, optional
        Smallest reference torque a sample is measured at [N m] (avoids dividing by a near-zero
        torque).

    Returns
    -------
    EtaSeries

    Raises
    ------
    ValueError
        For an unknown ``reference`` or fewer than 2 measurable samples.
    """
    t = np.asarray(t, float)
    lab = np.asarray(labels)
    if reference not in ("mean", "branch"):
        raise ValueError(f"reference = {reference!r}: use 'mean' or 'branch'")
    ref = mc.reference(bit_speed, lab if reference == "branch" else None)
    floor = 0.05 * np.nanmax(np.abs(mc.all)) if min_reference is None else float(min_reference)
    meas = (lab != 0) & np.isfinite(ref) & (np.abs(ref) > floor) & np.isfinite(torque)
    if meas.sum() < 2:
        raise ValueError("eta_exp: fewer than 2 samples with a defined reference torque")
    e = np.full(t.size, np.nan)
    e[meas] = np.asarray(torque)[meas] / ref[meas] - 1.0
    # the regular grid spans the measured samples; the rest is interpolated (Eq. 4.3)
    i0, i1 = np.flatnonzero(meas)[[0, -1]]
    sl = slice(i0, i1 + 1)
    tt, ee, mm = t[sl], e[sl], meas[sl]
    ee = np.where(mm, ee, np.interp(tt, tt[mm], ee[mm]))
    return EtaSeries(tt, ee, mm)


# ------------------------------------------------------------------------------ PSD display
def log_binned(f, psd, bins_per_decade: float = 20.0):
    """Average a periodogram over log-spaced frequency bins (the averaged S-bar of section 4.1,
    for display; the PSD-model fit itself is :func:`drillpy.uncertainty.process.fit_psd_model`).

    Parameters
    ----------
    f : array_like
        Frequencies of the periodogram [Hz], increasing (zero and non-finite PSD values dropped).
    psd : array_like
        One-sided PSD at ``f`` [1/Hz for eta].
    bins_per_decade : float
        Number of bins per decade of frequency.

    Returns
    -------
    f_centre : ndarray
        Geometric-centre frequency of each non-empty bin [Hz].
    psd_mean : ndarray
        Mean PSD in the bin (arithmetic mean of the ordinates).
    count : ndarray of int
        Number of periodogram ordinates averaged.
    """
    f = np.asarray(f, float)
    p = np.asarray(psd, float)
    m = (f > 0) & np.isfinite(p)
    f, p = f[m], p[m]
    lf = np.log10(f)
    edges = np.arange(np.floor(lf[0] * bins_per_decade), np.ceil(lf[-1] * bins_per_decade) + 1) / bins_per_decade
    k = np.clip(np.searchsorted(edges, lf, side="right") - 1, 0, edges.size - 2)
    cnt = np.bincount(k, minlength=edges.size - 1)
    sp = np.bincount(k, weights=p, minlength=edges.size - 1)
    sl = np.bincount(k, weights=np.log(f), minlength=edges.size - 1)
    ok = cnt > 0
    return np.exp(sl[ok] / cnt[ok]), sp[ok] / cnt[ok], cnt[ok]


# ------------------------------------------------------------------------------ statistics
def sample_statistics(x) -> dict:
    """Mean, standard deviation (ddof = 1) and coefficient of variation std/mean (Table 5.2).

    The thesis relates the CV of the torque on bit to the hysteresis fluctuations
    (section 5.3.3).

    Parameters
    ----------
    x : array_like
        Values, e.g. the measured torque on bit [N m] of a sample (non-finite ones dropped).

    Returns
    -------
    dict
        ``mean`` and ``std`` (unit of ``x``), ``cv`` [-] (NaN for a zero mean) and ``n``.

    Raises
    ------
    ValueError
        With fewer than 2 finite values.
    """
    x = np.asarray(x, float)
    x = x[np.isfinite(x)]
    if x.size < 2:
        raise ValueError("sample_statistics: fewer than 2 finite values")
    m, s = float(np.mean(x)), float(np.std(x, ddof=1))
    return {"mean": m, "std": s, "cv": s / m if m != 0 else float("nan"), "n": int(x.size)}


def var_mse(reference, model) -> float:
    """Var[MSE] of Eq. (5.2): the variance of the squared differences between the windowed
    experimental torque and a model's torque at the same points (NaN pairs skipped).

    A lower value means a better fitting law; the thesis finds 20.86 for Eq. (3.1) and 0.0017 for
    Eq. (5.1) on its sample 13.

    Parameters
    ----------
    reference : array_like
        Experimental torque, windowed by bit speed (Eq. 4.3, e.g. a :class:`MeanCycle` curve)
        [N m].
    model : array_like
        A law's torque at the same points [N m].

    Returns
    -------
    float
        Var[MSE] [(N m)^4] (sample variance, ddof = 1).

    Raises
    ------
    ValueError
        With fewer than 2 finite differences.
    """
    d = np.asarray(reference, float) - np.asarray(model, float)
    d = d[np.isfinite(d)]
    if d.size < 2:
        raise ValueError("var_mse: fewer than 2 finite differences")
    return float(np.var(d ** 2, ddof=1))
