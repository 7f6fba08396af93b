"""The stick-slip threshold: one definition for every command, report and figure.

The threshold is the top speed below which SS > 0.5 (Fig. 4.8), located by bisection
(:func:`drillpy.model.simulation.refine_threshold`) from the grid's highest falling crossing, and
reported with its precision (half the final bracket) and its RPM equivalent. A linear interpolation
on the grid is not the threshold: SS jumps at the threshold, and the interpolation reads more
precisely than it is.
"""
from __future__ import annotations

import math

from drillpy.model.simulation import refine_threshold

#: Half-width of the final bisection bracket of every reported threshold [rad/s].
DEFAULT_TOL_RAD_S = 0.02
RAD_S_TO_RPM = 30.0 / math.pi


def stick_slip_threshold(cfg: dict, speeds, severities, *, tol: float = DEFAULT_TOL_RAD_S, threads: int = 0,
                         start: str | None = None) -> dict:
    """The threshold of a sweep, by bisection from its grid.

    Parameters
    ----------
    cfg : dict
        The configuration the sweep ran with.
    speeds, severities : array_like
        The sweep's top speeds [rad/s] and SS [-].
    tol : float
        Half-width of the final bracket [rad/s].
    threads : int
        OpenMP threads (0: the default).
    start : str, optional
        Initial state of the runs (default: the configuration's).

    Returns
    -------
    dict
        ``threshold_rad_s`` (None when SS does not cross 0.5 from above on the grid),
        ``threshold_precision_rad_s``, ``threshold_rpm``, ``threshold_precision_rpm``,
        ``threshold_bracket_rad_s`` and ``refinement_runs`` (top speed, SS); ``threshold_method``
        is ``"bisection"``.
    """
    r = refine_threshold(cfg, speeds, severities, tol=tol, threads=threads, start=start)
    if r is None:
        return {"threshold_rad_s": None, "threshold_method": "bisection"}
    return {"threshold_rad_s": r.threshold, "threshold_precision_rad_s": r.precision,
            "threshold_rpm": r.threshold * RAD_S_TO_RPM, "threshold_precision_rpm": r.precision * RAD_S_TO_RPM,
            "threshold_bracket_rad_s": [r.below, r.above], "refinement_runs": [list(e) for e in r.evaluations],
            "threshold_method": "bisection"}


def format_threshold(t: dict) -> str:
    """One line for a threshold of :func:`stick_slip_threshold`.

    Parameters
    ----------
    t : dict
        Its result (or a summary holding the same keys).

    Returns
    -------
    str
        E.g. ``"SS > 0.5 below 19.17 +- 0.02 rad/s (183.1 +- 0.2 RPM, bisection)"``.
    """
    if t.get("threshold_rad_s") is None:
        return "SS > 0.5 below: none on the grid (SS never falls through 0.5 as the speed rises)"
    return (f"SS > 0.5 below {t['threshold_rad_s']:.2f} +- {t['threshold_precision_rad_s']:.2f} rad/s "
            f"({t['threshold_rpm']:.1f} +- {t['threshold_precision_rpm']:.1f} RPM, bisection)")
