"""The robust top speed of a Monte Carlo study (section 4.2.2): the lowest speed from which
P(SS > 0.5) <= 5 %, located to a stated precision and with its Monte Carlo uncertainty.

On a 1 rad/s grid the speed is a linear interpolation of an estimated probability between two
grid points: less precise than it reads. :func:`refine_p_speed` bisects the bracket where the
probability crosses the level with new speeds run on the **same samples** (common random
numbers), so the bracket narrows to ``tol``; :func:`bootstrap_interval` resamples the samples
(rows) to give the interval the finite number of samples leaves on the speed.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from drillpy import _core, validate
from drillpy.uncertainty.montecarlo import P_LEVEL, SS_LEVEL


def _matrix(severity, speeds) -> tuple[np.ndarray, np.ndarray]:
    ss = np.asarray(severity, dtype=float)
    sp = np.asarray(speeds, dtype=float)
    if ss.ndim != 2 or ss.shape[1] != sp.size or ss.shape[0] == 0:
        raise ValueError(f"severity: must be a (samples x speeds) matrix with {sp.size} columns, got shape {ss.shape}")
    order = np.argsort(sp)
    return ss[:, order], sp[order]


def exceedance(severity, level: float = SS_LEVEL) -> np.ndarray:
    """P(SS > level) per speed (column): the fraction of samples above ``level``.

    Parameters
    ----------
    severity : array_like
        SS (Eq. 3.4) [-], shape (samples, n_speeds).
    level : float
        Stick-slip threshold on SS [-] (default ``SS_LEVEL`` = 0.5, section 3.3).

    Returns
    -------
    numpy.ndarray
        P(SS > level) per column, shape (n_speeds,).
    """
    return np.mean(np.asarray(severity, dtype=float) > level, axis=0)


def p_speed(severity, speeds, level: float = SS_LEVEL, prob: float = P_LEVEL) -> float | None:
    """Lowest speed from which P(SS > level) <= prob (linear interpolation between grid speeds,
    the engine's ``severity_statistics``); None without a crossing.

    The crossing is where P last falls to ``prob`` going up in speed (section 4.2.2; 20.5 rad/s
    in the thesis).

    Parameters
    ----------
    severity : array_like
        SS [-], shape (samples, n_speeds).
    speeds : array_like
        Top speeds [rad/s] of the columns (any order; sorted here).
    level : float
        Stick-slip threshold on SS [-] (default 0.5).
    prob : float
        Probability level (default ``P_LEVEL`` = 0.05).

    Returns
    -------
    float or None
        The robust speed [rad/s], or None without a crossing on the grid.
    """
    ss, sp = _matrix(severity, speeds)
    v = _core.severity_statistics(ss, list(sp), level, prob, 0.05, 0.95).p_speed
    return None if math.isnan(v) else float(v)


@dataclass
class RefinedSpeed:
    """The crossing of P(SS > level) = prob located by bisection: P > prob at ``below`` and
    P <= prob at ``above`` [rad/s]; ``speed`` is their midpoint, ``precision`` half their distance.
    ``speeds``/``severity`` hold the grid with every refinement speed added (same samples).

    Attributes
    ----------
    speed : float
        Estimate of the robust speed [rad/s]: the midpoint of the final bracket.
    precision : float
        Half the width of the final bracket [rad/s] (the bisection's precision, not the Monte
        Carlo uncertainty; see :func:`bootstrap_interval`).
    below : float
        Lower end of the bracket [rad/s], where P(SS > level) > prob.
    above : float
        Upper end of the bracket [rad/s], where P(SS > level) <= prob.
    speeds : numpy.ndarray
        The original grid plus every refinement speed [rad/s], sorted.
    severity : numpy.ndarray
        SS [-] of the same samples at ``speeds``, shape (samples, len(speeds)).
    """
    speed: float
    precision: float
    below: float
    above: float
    speeds: np.ndarray
    severity: np.ndarray


def refine_p_speed(severity, speeds, evaluate: Callable[[list], np.ndarray], *, tol: float,
                   level: float = SS_LEVEL, prob: float = P_LEVEL, max_rounds: int = 10) -> RefinedSpeed | None:
    """Bisect the highest bracket where P(SS > level) falls to ``prob`` until it is within
    ``2 tol``. ``evaluate(speeds)`` returns the SS matrix of the same samples at new speeds.
    Two speeds per round (the bracket is split in three, both run in one call). None without a
    crossing on the grid.

    Parameters
    ----------
    severity : array_like
        SS [-] of the study, shape (samples, n_speeds).
    speeds : array_like
        Top speeds [rad/s] of the columns.
    evaluate : callable
        ``evaluate(list_of_speeds)`` returns SS of the **same samples** (same seed and sample
        indices) at the given speeds [rad/s], shape (samples, 2).
    tol : float
        Target half-width of the bracket [rad/s], > 0.
    level : float
        Stick-slip threshold on SS [-] (default 0.5).
    prob : float
        Probability level (default 0.05).
    max_rounds : int
        Maximum number of bisection rounds (each one engine call with two speeds).

    Returns
    -------
    RefinedSpeed or None
        The final bracket and the extended grid, or None without a crossing.

    Raises
    ------
    ValueError
        If ``evaluate`` returns an array of the wrong shape.
    """
    validate.positive("tol", tol, "rad/s")
    ss, sp = _matrix(severity, speeds)
    p = exceedance(ss, level)
    k = [i for i in range(sp.size - 1) if p[i] > prob >= p[i + 1]]
    if not k:
        return None
    lo, hi = float(sp[k[-1]]), float(sp[k[-1] + 1])
    for _ in range(max_rounds):
        if 0.5 * (hi - lo) <= tol:
            break
        pts = [lo + (hi - lo) / 3.0, lo + 2.0 * (hi - lo) / 3.0]
        new = np.asarray(evaluate(pts), dtype=float)
        if new.shape != (ss.shape[0], 2):
            raise ValueError(f"evaluate returned shape {new.shape}, expected ({ss.shape[0]}, 2)")
        ss, sp = np.hstack([ss, new]), np.concatenate([sp, pts])
        pn = exceedance(new, level)
        if pn[1] > prob:
            lo = pts[1]
        elif pn[0] > prob:
            lo, hi = pts[0], pts[1]
        else:
            hi = pts[0]
    order = np.argsort(sp)
    return RefinedSpeed(0.5 * (lo + hi), 0.5 * (hi - lo), lo, hi, sp[order], ss[:, order])


def bootstrap_interval(severity, speeds, *, resamples: int = 400, confidence: float = 0.9, seed: int = 0,
                       level: float = SS_LEVEL, prob: float = P_LEVEL) -> dict:
    """Percentile bootstrap of the robust speed over the samples (rows resampled with
    replacement): ``{"low", "high", "confidence", "resamples", "no_crossing"}`` where
    ``no_crossing`` counts resamples without a crossing on the grid (left out of the percentiles).

    Each resample draws the samples with replacement, recomputes P(SS > level) per speed and the
    speed where it falls to ``prob``; the interval is the (1 -+ confidence)/2 quantiles of those
    speeds. It measures the uncertainty the finite number of samples leaves on the robust speed.

    Parameters
    ----------
    severity : array_like
        SS [-], shape (samples, n_speeds).
    speeds : array_like
        Top speeds [rad/s] of the columns.
    resamples : int
        Number of bootstrap resamples.
    confidence : float
        Confidence level of the interval, in (0, 1) (default 0.9).
    seed : int
        Seed of numpy's random generator for the resampling.
    level : float
        Stick-slip threshold on SS [-] (default 0.5).
    prob : float
        Probability level (default 0.05).

    Returns
    -------
    dict
        ``low``, ``high`` [rad/s] (NaN if no resample crosses), ``confidence``, ``resamples``
        and ``no_crossing``.
    """
    ss, sp = _matrix(severity, speeds)
    validate.fraction("confidence", confidence, closed=False)
    rng = np.random.default_rng(seed)
    n = ss.shape[0]
    above = (ss > level).astype(float)
    vals, none = [], 0
    for _ in range(int(resamples)):
        p = rng.multinomial(n, np.full(n, 1.0 / n)) @ above / n  # P(SS > level) of a resample of the rows
        v = _core.severity_threshold(list(sp), list(p), prob)
        if math.isnan(v):
            none += 1
        else:
            vals.append(float(v))
    a = 0.5 * (1.0 - confidence)
    lo, hi = (np.quantile(vals, [a, 1.0 - a]) if vals else (math.nan, math.nan))
    return {"low": float(lo), "high": float(hi), "confidence": confidence, "resamples": int(resamples),
            "no_crossing": none}


def robust_speed_summary(severity, speeds, refine: float | None, seed: int, evaluate) -> dict:
    """The 5 % speed of a Monte Carlo SS matrix, refined and with its bootstrap interval.

    Parameters
    ----------
    severity : ndarray
        SS [-], one row per sample, one column per speed.
    speeds : array_like
        Top-drive speeds [rad/s] of the columns.
    refine : float or None
        Bisection tolerance [rad/s] of :func:`drillpy.uncertainty.robust_speed.refine_p_speed`
        (same samples at new speeds); None: no refinement.
    seed : int
        Seed of the bootstrap resampling.
    evaluate : callable
        ``evaluate(speeds)`` returns the SS matrix of the same samples at new speeds [rad/s].

    Returns
    -------
    dict
        ``p05_speed_bracket_rad_s``, ``p05_speed_rad_s`` and ``refinement_speeds_rad_s`` when refined
        to a crossing; ``p05_speed_bootstrap`` (90 % interval over the samples) with two or more samples, and
        ``p05_speed_precision_warning`` when the grid limits its precision (:func:`grid_limit`).
    """
    out = {}
    if refine is not None:
        r = refine_p_speed(severity, speeds, evaluate, tol=refine)
        if r is not None:
            severity, speeds = r.severity, r.speeds
            out["p05_speed_bracket_rad_s"] = [r.below, r.above]
            out["p05_speed_rad_s"] = p_speed(severity, speeds)
            out["refinement_speeds_rad_s"] = [float(x) for x in r.speeds]
    if severity.shape[0] >= 2:
        out["p05_speed_bootstrap"] = b = bootstrap_interval(severity, speeds, seed=seed)
        note = grid_limit(b, speeds)
        if note:
            out["p05_speed_precision_warning"] = note
    return out


def grid_limit(interval: dict, speeds) -> str | None:
    """The warning due when the grid, not the samples, limits the precision of the 5 % speed: its
    bootstrap interval is narrower than the grid spacing where it lies (the resamples all cross
    P = 5 % in the same grid cell, and the linear interpolation in that cell decides the rest).

    Parameters
    ----------
    interval : dict
        :func:`drillpy.uncertainty.robust_speed.bootstrap_interval` (``low``, ``high`` [rad/s]).
    speeds : array_like
        The grid [rad/s] (with any refinement speeds).

    Returns
    -------
    str or None
        The warning, None when the interval spans a grid spacing or more (or there is none).
    """
    lo, hi = interval["low"], interval["high"]
    sp = np.unique(np.asarray(speeds, float))
    if not (lo == lo and hi == hi) or sp.size < 2:
        return None
    k = int(np.clip(np.searchsorted(sp, lo, side="right") - 1, 0, sp.size - 2))
    spacing = float(sp[k + 1] - sp[k])
    if hi - lo >= spacing:
        return None
    return (f"the 90 % bootstrap interval of the 5 % speed ({lo:.2f}-{hi:.2f} rad/s) is narrower than the grid "
            f"spacing there ({spacing:.3g} rad/s): the grid, not the samples, limits its precision; --refine TOL "
            "locates it by bisection on the same samples")
