"""The stochastic bit-rock torque of Eq. (4.1) in the rig model, identified on the record (chapter 4).

The thesis writes the bit-rock torque as T = (1 + eta(t)) T_law (Eq. 4.1), eta a centred stationary
Gaussian process whose PSD (Eq. 4.4) it identifies on the rig's records from eta_exp = T_exp / T_hys
- 1 (Eq. 4.2, T_hys the record's mean hysteresis cycle). The rig model takes it from the record it is
calibrated on:

* the shape: the fit of Eq. (4.4) to eta_exp's periodogram (:func:`drillpy.uncertainty.process.fit_psd_model`,
  ``drillpy analyze``'s ``psd.fit``), band-limited to the fitted band (up to ``psd_fmax_hz``, 10 Hz:
  the acquisition's 10 Hz filter leaves nothing measured above it, and on sample 175 the fitted slope
  a = -0.49 above f0 has no finite integral without a band limit);
* the level: the measured standard deviation of eta_exp over the calibration window (0.183 on
  sample 175, 0-20 s), to which the band-limited PSD is scaled.

A deterministic model (eta = 0) gives one value of each long-run metric; with eta each 20 s
realization gives another, and the spread of the metrics across realizations is what a measured
window of the same length can differ by at the same settings. :func:`predictive` draws ``n``
realizations (the process of :func:`drillpy.uncertainty.process.generate`: row i of a seed is the
same series on any machine) and returns each metric's predictive interval and whether the measured
value lies in it. The calibration itself (:func:`drillpy.records.rig_calibration.calibrate_rig`)
stays deterministic: the parameters are those of eta = 0 (docs/records.md, section 4).
"""
from __future__ import annotations

import math

import numpy as np

from drillpy import validate
from drillpy.records import rig_comparison, rigsim
from drillpy.records.io import Record
from drillpy.uncertainty import process

#: Frequencies of the band-limited PSD table (linear from 0 to the band's top).
TABLE_POINTS = 257
#: The long-run metrics given a predictive interval (keys of :func:`drillpy.records.rig_comparison.compare`).
METRICS = ("ss", "stick_fraction", "cycle_frequency_hz", "median_period_s", "torque_p5", "torque_p95",
           "top_speed_std", "wob_std", "mean_top_speed")


def identify(psd_fit: dict, eta_std: float, fmax_hz: float) -> dict:
    """The torque fluctuation of a record: the fitted PSD shape of Eq. (4.4), band-limited to
    ``fmax_hz`` and scaled to the measured standard deviation of eta_exp.

    Parameters
    ----------
    psd_fit : dict
        The fitted Eq. (4.4) model, ``{"type": "model_4_4", "f0_hz", "A0", "a", "b"}``
        (``PsdModel.as_dict()``; extra keys are ignored).
    eta_std : float
        Standard deviation of eta_exp (Eq. 4.2) over the calibration window [-], > 0.
    fmax_hz : float
        Top of the fitted band [Hz], > 0: the PSD is zero above it.

    Returns
    -------
    dict
        ``{"psd": {"type": "table", "f_hz", "S"}, "std", "band_hz", "shape", "rule"}``: the process
        :func:`realization` draws from, stored in ``model.json`` (``torque_fluctuation``).

    Raises
    ------
    ValueError
        When ``eta_std`` or ``fmax_hz`` is not positive and finite (naming it).
    """
    std = validate.positive("eta_std", eta_std)
    fmax = validate.positive("fmax_hz", fmax_hz)
    shape = process.PsdModel(psd_fit["f0_hz"], psd_fit["A0"], psd_fit["a"], psd_fit["b"])
    f = np.linspace(0.0, fmax, TABLE_POINTS)
    S = shape(f)
    S *= std ** 2 / float(np.sum(0.5 * (S[1:] + S[:-1]) * np.diff(f)))  # the table's integral (linear between points): std^2
    return {"psd": process.PsdTable(f, S).as_dict(), "std": std, "band_hz": [0.0, fmax],
            "shape": {k: float(psd_fit[k]) for k in ("f0_hz", "A0", "a", "b")},
            "rule": "Eq. (4.1) T = (1 + eta) T_law; eta's PSD the Eq. (4.4) fit to eta_exp (Eq. 4.2) of the "
                    "calibration window, band-limited to the fitted band and scaled to eta_exp's standard deviation"}


def measured(t, bit_speed, torque, accel, labels, reference: str = "mean", fmax_hz: float = 10.0) -> tuple:
    """Chapter 4's measurement of the torque fluctuation on a record: the mean cycle (T_hys), eta_exp of
    Eq. (4.2) against it, eta_exp's raw periodogram and the Eq. (4.4) fit to it.

    Parameters
    ----------
    t, bit_speed, torque, accel : array_like
        Time [s], bit speed [rad/s], torque on bit [N m] and bit acceleration [rad/s^2] of the record.
    labels : array_like of int
        Branch of each sample (:meth:`drillpy.records.signals.Cycles.branch_labels`).
    reference : {"mean", "branch"}
        T_hys of Eq. (4.2) (:func:`drillpy.records.signals.eta_exp`).
    fmax_hz : float
        Top of the fitted band [Hz] (the acquisition's 10 Hz filter on the rig).

    Returns
    -------
    tuple
        (:class:`~drillpy.records.signals.MeanCycle`, :class:`~drillpy.records.signals.EtaSeries`, the
        periodogram's frequencies [Hz] and ordinates [1/Hz], the :func:`~drillpy.uncertainty.process.fit_psd_model`
        result).
    """
    from drillpy.records import signals as sig
    mc = sig.mean_cycle(bit_speed, torque, accel, labels)
    eta = sig.eta_exp(t, bit_speed, torque, labels, mc, reference=reference)
    f, p = process.periodogram(eta.eta, 1.0 / eta.fs_hz)  # Schuster's raw periodogram (section 4.1)
    return mc, eta, f, p, process.fit_psd_model(f, p, averages=1.0, fmax=fmax_hz)  # Eq. (4.4)


def of_record(record: Record, threshold: float, fmax_hz: float = 10.0, reference: str = "mean") -> dict | None:
    """The torque fluctuation a record shows, as the thesis measures it (chapter 4, :func:`measured`),
    built into a process by :func:`identify` (the drillpy loop's long runs:
    ``LoopOptions.long_run_fluctuation``).

    Parameters
    ----------
    record : Record
        Cleaned, with bit speed and torque on bit.
    threshold : float
        Stick threshold [rad/s].
    fmax_hz : float
        Top of the fitted band [Hz].
    reference : {"mean", "branch"}
        T_hys of Eq. (4.2).

    Returns
    -------
    dict or None
        :func:`identify`'s process, or None when the record has no valid stick-slip cycle.
    """
    from drillpy.records import signals as sig
    v, tq = record.bit_speed, record.torque_on_bit
    cyc = sig.segment_cycles(v, record.dt, threshold, valid=record.valid("bit_speed", "torque_on_bit"))
    if not cyc.valid.any():
        return None
    acc = sig.derivative(np.where(np.isfinite(v), v, 0.0), record.dt)
    _, eta, _, _, psd = measured(record.time_s, v, tq, acc, cyc.branch_labels(len(record)), reference, fmax_hz)
    return identify(psd.model.as_dict(), float(eta.statistics()["std"]), fmax_hz)


def realization(fluctuation: dict, dt: float, duration: float, seed: int = 0, sample: int = 0) -> np.ndarray:
    """One realization of eta on a grid of step ``dt`` [s] covering ``duration`` [s].

    Parameters
    ----------
    fluctuation : dict
        From :func:`identify`.
    dt : float
        Step of the series [s] (the record's).
    duration : float
        Length it must cover [s].
    seed : int
        Random seed.
    sample : int
        Index of the realization (row ``sample`` of :func:`drillpy.uncertainty.process.generate`).

    Returns
    -------
    numpy.ndarray
        eta [-] at 0, dt, 2 dt, ...
    """
    psd = process.psd_from_dict(fluctuation["psd"])
    _, eta = process.generate(psd, dt=dt, duration=duration, seed=seed, first_sample=sample)
    return eta[0]


def predictive(model: rigsim.RigModel, record: Record, threshold: float, n: int = 20, seed: int = 0,
               level: float = 0.9) -> dict:
    """Predictive intervals of the long-run metrics of ``model`` on ``record``'s window, over ``n``
    realizations of its torque fluctuation (Eq. 4.1).

    Parameters
    ----------
    model : RigModel
        A model with ``torque_fluctuation`` (:func:`identify`).
    record : Record
        The cleaned record whose window is predicted (its operating point and WOB trend, as
        :func:`drillpy.records.rigsim.simulate_model`).
    threshold : float
        Stick threshold [rad/s].
    n : int
        Realizations, 2 to 1000.
    seed : int
        Random seed (realization i is row i of the seed: the same numbers on any machine).
    level : float
        Central probability of the intervals, in (0, 1).

    Returns
    -------
    dict
        ``realizations``, ``seed``, ``level``; ``metrics``: name -> ``measured``, ``median``,
        ``interval`` [low, high], ``inside``; ``inside`` (how many measured metrics lie in their
        interval) and ``of``; ``stalls``: the measured count and the fraction of realizations
        with at least one stall.

    Raises
    ------
    ValueError
        When the model has no torque fluctuation, or ``n`` or ``level`` is out of range (naming it).
    """
    fl = model.torque_fluctuation
    if not fl:
        raise ValueError("model: torque_fluctuation: the model has none (a model.json of drillpy analyze "
                         "from before Eq. (4.1) was part of the rig model); re-run drillpy analyze --calibrate")
    n = validate.integer("realizations", n, 2, 1000)
    if not (isinstance(level, float) and 0.0 < level < 1.0):
        raise ValueError(f"level = {level!r}: must be a number in (0, 1)")
    duration = float(record.time_s[-1] - record.time_s[0]) + 2 * record.dt
    rows, stalled, measured = [], 0, None
    for i in range(n):
        eta = realization(fl, record.dt, duration, seed, i)
        sim = rigsim.simulate_model(model, record, eta=eta)
        cmp = rig_comparison.compare(record, sim, threshold)
        measured = cmp.measured
        rows.append([float(cmp.simulated[k]) for k in METRICS])
        stalled += cmp.simulated["stalls"]["count"] > 0
    X = np.asarray(rows)
    q = (0.5 - level / 2, 0.5, 0.5 + level / 2)
    out = {}
    for j, k in enumerate(METRICS):
        lo, med, hi = (float(v) for v in np.quantile(X[:, j], q))
        m = float(measured[k])
        out[k] = {"measured": m, "median": med, "interval": [lo, hi], "inside": bool(lo <= m <= hi)}
    inside = sum(v["inside"] for v in out.values() if math.isfinite(v["measured"]))
    return {"realizations": n, "seed": seed, "level": level, "metrics": out, "inside": inside,
            "of": sum(math.isfinite(v["measured"]) for v in out.values()),
            "stalls": {"measured": measured["stalls"]["count"], "fraction_with_a_stall": stalled / n}}
