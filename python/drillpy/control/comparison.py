"""Top drives side by side (issue 15, items 2-3): deterministic stability maps and thresholds, and
the probability of stick-slip under the chapter-4 bit-rock uncertainty on **new** samples.

For every drive (the ideal drive of the thesis, the stiff PI, the nominal and tuned SoftSpeed and
ZTorque controllers):

* the deterministic stability map SS(WOB, speed) (eta = 0 with the Monte Carlo's warm start and
  durations, Fig. 4.8's curve per WOB) and the speed below which SS > 0.5 at the nominal WOB, by
  ``drillpy sweep``'s bisection (:func:`drive_threshold`: one threshold per string, drive and WOB
  across the commands);
* on validation samples (a seed the tuning never saw, the same samples for every drive: common
  random numbers): P(SS > 0.5 or stalled) over the window with its bootstrap interval, the paired
  difference to the reference drive, the same per speed at the nominal WOB with a Wilson 90 %
  band, and the 5 % speed (the lowest speed from which P <= 5 %, section 4.2.2) with its bootstrap
  interval (:mod:`drillpy.uncertainty.robust_speed`).

A stalled run (:data:`drillpy.control.tuning.STALL_FRACTION`) counts as stick-slip in the maps and
the probabilities: its SS is +inf in the tables. The deterministic threshold is SS's (as ``drillpy
sweep`` reads it); the map marks the stalls.
"""
from __future__ import annotations

import numpy as np

from drillpy.jsonio import jsonable
from drillpy.control.tuning import Window, bootstrap_p, score, stalled_fraction, window_severity
from drillpy.uncertainty.binomial import wilson_interval
from drillpy.model.config import with_overrides
from drillpy.model.configuration import Configuration
from drillpy.uncertainty.robust_speed import bootstrap_interval, exceedance, grid_limit, p_speed

#: SS a stalled run enters the crossings with (a large finite stand-in for +inf)
STALLED_SS = 1e3


def p_window(ss: np.ndarray, confidence: float = 0.9) -> dict:
    """P(SS > 0.5 or stalled) over a window with its Wilson interval, the samples (rows of every cell,
    drawn independently) as the binomial trials: 0 of 9 is P <= 0.23 at 90 %, never [0, 0].

    Parameters
    ----------
    ss : numpy.ndarray
        SS [-], shape (n_wobs, samples, n_speeds).
    confidence : float
        Level of the interval.

    Returns
    -------
    dict
        ``value``, ``low``, ``high``, ``confidence``, ``trials`` (the samples) and ``method`` (``"wilson"``).
    """
    value = score(ss)[1]
    low, high = wilson_interval(value, ss.shape[1], confidence)
    return {"value": value, "low": float(low), "high": float(high), "confidence": confidence,
            "trials": int(ss.shape[1]), "method": "wilson"}


def drive_threshold(cfg: dict, drive: dict | None, wob: float, speeds, *, threads: int = 0) -> dict:
    """The deterministic threshold of a drive at one WOB: ``drillpy sweep``'s definition
    (:func:`drillpy.model.threshold.stick_slip_threshold`), so the same string, drive and WOB give one
    threshold in every command. The runs are the configuration's (its duration, transient and start,
    no warm start), the sweep on the window's speeds, then bisection to
    :data:`drillpy.model.threshold.DEFAULT_TOL_RAD_S`.

    Parameters
    ----------
    cfg : dict
        The configuration.
    drive : dict or None
        The ``top_drive`` block (None: the configuration's own drive).
    wob : float
        Weight on bit [N].
    speeds : array_like
        The window's top speeds [rad/s]: the grid the bisection starts from.
    threads : int
        OpenMP threads (0: the default).

    Returns
    -------
    dict
        :func:`drillpy.model.threshold.stick_slip_threshold`'s keys (``threshold_rad_s``, its
        ``threshold_precision_rad_s``, ``threshold_rpm``, ...; ``threshold_rad_s`` None when SS does not
        fall through 0.5 in the window).
    """
    from drillpy.model.simulation import sweep_severity
    from drillpy.model.threshold import stick_slip_threshold
    c = with_overrides(cfg, wob=float(wob), top_drive=drive)
    return stick_slip_threshold(c, speeds, sweep_severity(c, speeds, progress=False, threads=threads),
                                threads=threads)


def nominal_index(window: Window, wob: float) -> int:
    """Index of the window's WOB closest to ``wob``.

    Parameters
    ----------
    window : Window
        The operating window.
    wob : float
        The nominal WOB [N].

    Returns
    -------
    int
        Row of the nominal WOB.
    """
    return int(np.argmin(np.abs(window.wobs - wob)))


def compare_drives(cfg: dict, drives: dict, window: Window, *, reference: str, validation_seed: int,
                   bootstrap: int = 400, threads: int = 0, progress=None) -> dict:
    """Every drive's deterministic map and its Monte Carlo statistics on validation samples.

    Parameters
    ----------
    cfg : dict
        The configuration (its ``operation.wob_n`` is the nominal WOB).
    drives : dict
        Label -> ``top_drive`` block (None: the configuration's own drive).
    window : Window
        Speeds, WOBs, samples (the validation sample count) and durations.
    reference : str
        Label of the drive the differences are taken to (e.g. ``stiff``).
    validation_seed : int
        Seed of the validation samples (not the tuning's).
    bootstrap : int
        Bootstrap resamples of every interval.
    threads : int
        OpenMP threads (0: the default).
    progress : callable, optional
        Called with a short text after each drive.

    Returns
    -------
    dict
        Per label: ``map`` (SS, n_wobs x n_speeds), ``deterministic_threshold_rad_s`` (None: no
        crossing) at the nominal WOB by bisection with ``deterministic_threshold`` (:func:`drive_threshold`:
        its precision, RPM equivalent, bracket and runs), ``p_window`` (:func:`p_window`, Wilson) and ``p_vs_reference``
        (:func:`drillpy.control.tuning.bootstrap_p`, paired),
        ``mean_ss`` (runs that did not stall), ``stalled_fraction``, ``p_by_speed``, ``p_band`` (low, high), ``p05_speed_rad_s`` and
        ``p05_interval``, ``p05_precision_warning`` (:func:`drillpy.uncertainty.robust_speed.grid_limit`, None when the
        samples, not the grid, set the interval), ``p05_reading``, ``nominal_row`` (the nominal WOB's row); plus ``severity`` (the validation SS tables, not JSON).
    """
    if reference not in drives:
        raise ValueError(f"reference = {reference!r}: not one of the drives ({', '.join(drives)})")
    k = nominal_index(window, Configuration.of(cfg).operation.wob_n)
    tables = {}
    for label, d in drives.items():
        tables[label] = window_severity(cfg, d, window, seed=validation_seed, threads=threads)
        if progress is not None:
            progress(f"validation samples: {label} done")
    out = {}
    for label, drive in drives.items():
        ss = tables[label]
        det = window_severity(cfg, drive, window, seed=validation_seed, threads=threads, deterministic=True)[:, 0]
        at = np.minimum(ss[k], STALLED_SS)  # the engine's statistics take finite SS; a stall stays above 0.5
        p = exceedance(at)
        low, high = wilson_interval(p, at.shape[0])
        p05 = p_speed(at, window.speeds)
        iv = bootstrap_interval(at, window.speeds, resamples=bootstrap, seed=validation_seed)
        thr = drive_threshold(cfg, drive, window.wobs[k], window.speeds, threads=threads)
        out[label] = {
            "map": det, "deterministic_threshold_rad_s": thr["threshold_rad_s"], "deterministic_threshold": thr,
            "p_window": p_window(ss),
            "p_vs_reference": bootstrap_p(ss, bootstrap, validation_seed, reference=tables[reference]),
            "mean_ss": score(ss)[2], "stalled_fraction": stalled_fraction(ss), "p_by_speed": p, "p_band": (low, high), "p05_speed_rad_s": p05,
            "p05_interval": iv, "p05_precision_warning": grid_limit(iv, window.speeds),
            "p05_reading": _p05_reading(p, window.speeds, p05), "nominal_row": k, "severity": ss}
    return out


def _p05_reading(p: np.ndarray, speeds: np.ndarray, p05) -> str:
    """How to read the 5 % speed when the grid has no crossing."""
    if p05 is not None:
        return "crossing"
    if np.all(p <= 0.05):
        return f"below the window: P <= 5 % from {speeds.min():g} rad/s"
    return f"above the window: P > 5 % at {speeds.max():g} rad/s"


def json_ready(result: dict) -> dict:
    """The comparison without its SS tables, in JSON types (for control.json).

    Parameters
    ----------
    result : dict
        What :func:`compare_drives` returned.

    Returns
    -------
    dict
        The same keys per drive, ``severity`` left out (:func:`drillpy.jsonio.jsonable`).
    """
    return jsonable({label: {k: v for k, v in r.items() if k != "severity"} for label, r in result.items()})
