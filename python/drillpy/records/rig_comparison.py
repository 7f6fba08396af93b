"""The rig model against a measurement: the metrics both sides are measured by, the stalls set apart.

:func:`compare` measures a simulated record (:func:`drillpy.records.rigsim.simulate_model`) and the
measured one alike: SS, the regular stick fraction, the cycle frequency, torque percentiles, the top
speed's and the WOB's spread, their mean cycles (hysteresis loops), and the stalls
(:func:`stalls`: stick phases of at least ``rigsim.STALL_MIN_S``) counted apart from the regular
cycle. :func:`relative_error` is the signed error every mismatch is built from.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from drillpy.records.io import Record
from drillpy.records.signals import (MeanCycle, cycle_response, derivative, mean_cycle, segment_cycles,
                                     stick_slip_metrics)
from drillpy.records.rigsim import MATCHED, MATCHED_RIG, STALL_MIN_S, reliable_top_speed

#: Length of the blocks of :func:`block_stick_min` [s].
BLOCK_S = 5.0


@dataclass
class RigComparison:
    """Measured versus simulated stick-slip metrics and torque-speed loops (made by :func:`compare`).

    Attributes
    ----------
    measured, simulated : dict
        :func:`drillpy.records.signals.stick_slip_metrics` of each record after the start-up, with
        ``top_speed_std`` [rad/s], and ``mean_top_speed`` [rad/s] and ``ss`` taken over the
        reliable top-speed samples.
    mismatch : float
        Root mean square of the relative errors of the metrics in :data:`MATCHED`
        (:func:`relative_error`) [-]; 0 is a perfect match.
    mean_cycle_measured, mean_cycle_simulated : MeanCycle or None
        Mean torque-speed cycle per branch of each record on a common speed grid; None when
        there is no stick-slip cycle.
    loop_rms_nm : float
        RMS difference of the upper and lower branch curves on the common speeds [N m]; NaN
        without both loops.
    """
    measured: dict
    simulated: dict
    mismatch: float
    mean_cycle_measured: MeanCycle | None   #: None when there is no stick-slip cycle
    mean_cycle_simulated: MeanCycle | None
    loop_rms_nm: float  #: rms difference of the branch mean curves on the common speeds [N m]

    def rows(self) -> list:
        """Table rows ``(metric, measured, simulated)`` for reports.

        Returns
        -------
        list of tuple
            For ``ss``, ``cycle_frequency_hz``, ``median_period_s``, ``stick_fraction``,
            ``bit_speed_p95`` [rad/s], ``torque_p5``, ``torque_p95``, ``torque_min`` and
            ``torque_max`` [N m].
        """
        keys = ("ss", "cycle_frequency_hz", "median_period_s", "stick_fraction", "bit_speed_p95",
                "torque_p5", "torque_p95", "torque_min", "torque_max")
        return [(k, self.measured[k], self.simulated[k]) for k in keys]


def _loop(rec: Record, thr: float, t_start: float, grid) -> MeanCycle | None:
    """Mean cycle per branch after t_start, or None when there is no stick-slip cycle."""
    sel = rec.time_s >= t_start
    v = rec.bit_speed[sel]
    tq = rec.torque_on_bit[sel]
    cyc = segment_cycles(v, rec.dt, thr)
    lab = cyc.branch_labels(v.size)
    try:
        return mean_cycle(v, tq, derivative(v, rec.dt), lab, grid=grid)
    except ValueError:
        return None


@dataclass
class MeasuredSide:
    """The measured record's side of :func:`compare` for simulations that start at ``t0 - t_start``
    with one drive: computed once, reused by every point of a scan (:func:`calibrate`).

    Attributes
    ----------
    t0 : float
        Start of the compared span [s].
    skip : ndarray of bool
        Samples left out of both records (the measured drive's unreliable top speed).
    metrics : dict
        The measured metrics over the span.
    grid : ndarray
        Bit-speed grid of the mean cycles [rad/s].
    cycle : MeanCycle or None
        The measured mean cycle.
    """
    t0: float
    skip: np.ndarray
    metrics: dict
    grid: np.ndarray
    cycle: MeanCycle | None


def stalls(bit_speed, dt: float, stick_threshold: float, valid=None, min_s: float = STALL_MIN_S) -> list:
    """The stalls of a record: stick phases (bit speed at or below the threshold) of at least ``min_s``.

    A stall is not part of the regular stick-slip cycle: the bit sticks at a torque the open-loop
    motor cannot overcome until the WOB is relieved (thesis section 5.3.2). Stalls are reported
    apart (count, starts, durations) and left out of the regular metrics (:func:`compare`).

    Parameters
    ----------
    bit_speed : array_like
        Bit speed [rad/s].
    dt : float
        Sampling interval [s].
    stick_threshold : float
        Bit speed at or below which the bit is stuck [rad/s].
    valid : array_like of bool, optional
        Usable samples (a phase is cut where they end); default all finite samples.
    min_s : float
        Shortest stall [s] (:data:`STALL_MIN_S`).

    Returns
    -------
    list of tuple
        ``(first_index, samples)`` per stall, in time order.
    """
    v = np.asarray(bit_speed, float)
    ok = np.isfinite(v) if valid is None else (np.asarray(valid, bool) & np.isfinite(v))
    st = ok & (v <= stick_threshold)
    d = np.diff(np.r_[0, st.astype(np.int8), 0])
    starts, ends = np.flatnonzero(d == 1), np.flatnonzero(d == -1)
    n_min = int(math.ceil(min_s / dt))
    return [(int(a), int(b - a)) for a, b in zip(starts, ends) if b - a >= n_min]


def outside_stalls(bit_speed, usable, dt: float, stick_threshold: float) -> np.ndarray:
    """The ``usable`` samples with a finite bit speed that lie outside the stalls (:func:`stalls`).

    Parameters
    ----------
    bit_speed : array_like
        Bit speed [rad/s], one sample per ``dt``.
    usable : array_like of bool
        The samples to keep where no stall covers them.
    dt : float
        Sampling interval [s].
    stick_threshold : float
        Bit speed at or below which the bit is stuck [rad/s].

    Returns
    -------
    numpy.ndarray of bool
    """
    v = np.asarray(bit_speed, float)
    ok = np.asarray(usable, bool) & np.isfinite(v)
    for a, n in stalls(v, dt, stick_threshold, valid=ok):
        ok[a:a + n] = False
    return ok


def metric_scale(bit_speed, torque, usable, dt: float, stick_threshold: float) -> tuple:
    """The scale of the short-horizon error E (docs/loop.md, "Residuals and metrics"): the standard
    deviations of the bit speed and of the torque on bit over the usable samples, the stalls left out.

    A stall holds the torque near its break-away value for a second or more; counted in the spread it
    inflates the torque's (by a quarter on 20-30 s of sample 175: docs/records.md, "One scale for E")
    and makes every error look smaller. The loop takes the scale over its calibration part and a
    model file carries it (``metric_scale``), so that ``drillpy predict`` scores a record with the
    scale the model was calibrated with: the same E for the same horizons whichever command asks.

    Parameters
    ----------
    bit_speed, torque : array_like
        Bit speed [rad/s] and torque on bit [N m], one sample per ``dt``.
    usable : array_like of bool
        The samples the scale is taken over (e.g. the valid samples of a calibration part).
    dt : float
        Sampling interval [s].
    stick_threshold : float
        Bit speed at or below which the bit is stuck [rad/s] (for :func:`stalls`).

    Returns
    -------
    tuple of float
        (sd_v [rad/s], sd_T [N m]).

    Raises
    ------
    ValueError
        If fewer than two samples are usable or a channel is constant over them.
    """
    v, T = np.asarray(bit_speed, float), np.asarray(torque, float)
    ok = outside_stalls(v, np.asarray(usable, bool) & np.isfinite(T), dt, stick_threshold)
    if ok.sum() < 2:
        raise ValueError(f"record: {int(ok.sum())} usable samples outside the stalls; the error's scale needs two")
    sv, sT = float(np.std(v[ok])), float(np.std(T[ok]))
    if not (sv > 0 and sT > 0):
        raise ValueError("record: the bit speed or the torque on bit is constant over the calibration part")
    return sv, sT


def record_metrics(rec: Record, stick_threshold: float, t0: float, skip: np.ndarray, phase: bool = True) -> dict:
    """The metrics one side of :func:`compare` is measured by, from ``t0`` on, stalls and the
    ``skip`` mask left out of the regular ones.

    Parameters
    ----------
    rec : Record
        The record (measured, or a simulation on the measured grid).
    stick_threshold : float
        Bit speed at or below which the bit is stuck [rad/s].
    t0 : float
        Start of the compared span [s].
    skip : numpy.ndarray
        Boolean per sample: samples left out (e.g. the measured top speed's artifact stretches).
    phase : bool
        Also the drive's phase in the cycle, ``top_in_phase`` (a spectral estimate: False where it is
        neither matched nor shown, e.g. the loop's long runs).

    Returns
    -------
    dict
        Metric name -> value (the keys of ``rigsim.MATCHED_RIG`` among them) and the stalls.
    """
    base = (rec.time_s >= t0) & ~skip[:len(rec)]
    sel = base & rec.valid("bit_speed", "top_speed", "torque_on_bit")
    stall = np.zeros(len(rec), bool)
    found = stalls(rec.bit_speed, rec.dt, stick_threshold, valid=sel)
    after = int(round(0.1 / rec.dt))  # the break-away that ends a stall is not a regular cycle either
    for a, k in found:
        stall[a:a + k + after] = True
    if (sel & ~stall).sum() >= 3:
        sel = sel & ~stall
    m = stick_slip_metrics(rec.time_s, rec.bit_speed, rec.top_speed, rec.torque_on_bit, stick_threshold, valid=sel)
    m["block_stick_min"] = block_stick_min(rec, sel, stick_threshold)
    m["stalls"] = {"count": len(found), "starts_s": [float(rec.time_s[a]) for a, _ in found],
                   "durations_s": [float(k * rec.dt) for _, k in found]}
    m["stall_fraction"] = float(sum(k for _, k in found) / max(int(base.sum()), 1))
    w = sel & (rec.valid("wob") if rec.wob is not None else np.zeros(len(rec), bool))
    m["wob_std"] = float(np.std(rec.wob[w])) if w.sum() > 1 else float("nan")
    m["wob_mean"] = float(np.mean(rec.wob[w])) if w.sum() > 1 else float("nan")
    ok = base & ~stall & reliable_top_speed(rec)
    if ok.sum() > 1:  # the mean top speed and SS (Eq. 3.4) from reliable top-speed samples only
        m["top_speed_std"] = float(np.std(rec.top_speed[ok]))
        m["mean_top_speed"] = float(np.mean(rec.top_speed[ok]))
        v = rec.bit_speed[sel]
        m["ss"] = float((np.max(v) - np.min(v)) / (2.0 * abs(m["mean_top_speed"])))
    else:
        m["top_speed_std"] = float("nan")
    if phase:
        m["top_in_phase"] = _top_in_phase(rec, ok & rec.valid("bit_speed"))
    return m


def block_stick_min(rec: Record, sel: np.ndarray, stick_threshold: float, block_s: float = BLOCK_S) -> float:
    """The smallest regular stick fraction over the record's consecutive blocks of ``block_s``
    (the share of a block's selected samples at or below the stick threshold; a block with fewer than
    half its samples selected is left out): 0 when the bit stops sticking in some block, as a model
    near the edge of its cycle does where the WOB trend dips (docs/records.md, section 4). NaN
    without a block.

    Parameters
    ----------
    rec : Record
        The record (measured, or a simulation on the measured grid).
    sel : numpy.ndarray
        Boolean per sample: the regular cycle's samples (stalls and skipped samples left out).
    stick_threshold : float
        Bit speed at or below which the bit is stuck [rad/s].
    block_s : float
        Block length [s].

    Returns
    -------
    float
        The smallest block stick fraction [-], or NaN.
    """
    n = max(1, int(round(block_s / rec.dt)))
    out = [float(np.mean(rec.bit_speed[a:a + n][sel[a:a + n]] <= stick_threshold))
           for a in range(0, len(rec) - n // 2, n) if sel[a:a + n].sum() >= n // 2]
    return min(out) if out else float("nan")


def _top_in_phase(rec: Record, ok: np.ndarray) -> float:
    """The part of the top speed in phase with the bit speed at the cycle frequency, per unit of bit speed
    (:func:`cycle_response`) over the span of the samples ``ok`` (the others interpolated over); NaN with
    fewer than 4 s of them."""
    idx = np.flatnonzero(ok)
    if idx.size < 4.0 / rec.dt:
        return float("nan")
    span = np.arange(idx[0], idx[-1] + 1)
    v, om = (np.interp(span, idx, x[idx]) for x in (rec.bit_speed, rec.top_speed))
    return float(cycle_response(v, om, 1.0 / rec.dt)["in_phase"])


def measured_side(measured: Record, stick_threshold: float, start_s: float, drive: str,
                  t_start: float = 2.0) -> MeasuredSide:
    """The measured side of :func:`compare` for simulations starting at ``start_s`` with ``drive``.

    Parameters
    ----------
    measured : Record
        The cleaned measurement.
    stick_threshold : float
        Bit speed at or below which the bit counts as stuck [rad/s].
    start_s : float
        The simulations' first time [s].
    drive : str
        Their drive (:data:`DRIVES`).
    t_start : float
        Start-up discarded from both [s].

    Returns
    -------
    MeasuredSide
    """
    t0 = start_s + t_start
    skip = np.zeros(len(measured), bool)
    if drive == "measured" and measured.top_speed is not None:
        skip = ~reliable_top_speed(measured)  # what drive_series interpolated was not a measurement
    grid = np.linspace(0.0, np.percentile(measured.bit_speed[measured.time_s >= t0], 99), 40)
    return MeasuredSide(t0, skip, record_metrics(measured, stick_threshold, t0, skip), grid,
                        _loop(measured, stick_threshold, t0, grid))


def compare(measured: Record, simulated: Record, stick_threshold: float, t_start: float = 2.0, *,
            side: MeasuredSide | None = None, keys: tuple | None = None, phase: bool = True) -> RigComparison:
    """Compare a simulated record with the measured one after ``t_start`` seconds of simulation
    (the start-up of the simulation is discarded from both). ``top_speed_std`` is over the
    reliable top-speed samples of the measurement (:func:`reliable_top_speed`). When the
    simulation is driven by the measured top speed, the samples where that signal is not a
    measurement (an artifact stretch the cleaning filled with the bit speed) are left out of both:
    there the drive would impose the measured stall instead of predicting it.

    Parameters
    ----------
    measured : Record
        The cleaned measurement.
    simulated : Record
        Its simulation (:func:`simulate_model`), on the same time grid.
    stick_threshold : float
        Bit speed at or below which the bit counts as stuck [rad/s] (:func:`stick_threshold`),
        the same for both records.
    t_start : float
        Start-up discarded from both, counted from the simulation's first sample [s].
    side : MeasuredSide, optional
        The measured side already computed (:func:`measured_side` with the same arguments and
        the simulation's first time and drive); default: computed here.
    keys : tuple of str, optional
        The metrics of the mismatch; default :data:`MATCHED_RIG` for the rig drive (it predicts the
        WOB's oscillation and the mean top speed), :data:`MATCHED` for the others.
    phase : bool
        Measure the simulation's ``top_in_phase`` too (always when ``keys`` holds it).

    Returns
    -------
    RigComparison
        The metrics are those of the regular cycle: stalls (:func:`stalls`) are counted apart
        (``stalls``, ``stall_fraction``) and their samples left out of the rest.
    """
    if side is None:
        side = measured_side(measured, stick_threshold, float(simulated.time_s[0]),
                             simulated.provenance.get("drive", "constant"), t_start)
    if keys is None:
        keys = MATCHED_RIG if simulated.provenance.get("drive") == "rig" else MATCHED
    m = side.metrics
    s = record_metrics(simulated, stick_threshold, side.t0, side.skip, phase or "top_in_phase" in keys)
    rel = [relative_error(s[k], m[k]) for k in keys]
    mis = float(np.sqrt(np.mean(np.square(rel))))
    mm = side.cycle
    ms = _loop(simulated, stick_threshold, side.t0, side.grid)
    loop = float("nan")
    if mm is not None and ms is not None:
        d = np.r_[mm.upper - ms.upper, mm.lower - ms.lower]
        d = d[np.isfinite(d)]
        loop = float(np.sqrt(np.mean(d ** 2))) if d.size else loop
    return RigComparison(m, s, mis, mm, ms, loop)


def relative_error(simulated: float, measured: float) -> float:
    """(simulated - measured) / |measured|; a missing simulated value (no cycle, so no period or
    frequency) counts as 100 %, and a zero measured value as the simulated value itself.

    Parameters
    ----------
    simulated : float
        Metric of the simulation.
    measured : float
        The same metric measured (a non-finite value also gives 1.0).

    Returns
    -------
    float
        Signed relative error [-].
    """
    if not np.isfinite(simulated) or not np.isfinite(measured):
        return 1.0
    return (simulated - measured) / abs(measured) if measured != 0 else float(simulated)
