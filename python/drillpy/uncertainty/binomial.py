"""Intervals for probabilities estimated from a finite number of runs: the Wilson score interval.

A probability counted over n independent runs, P = k / n, is not known to better than its binomial
uncertainty: 0 stick-slip runs out of 9 does not mean P = 0, but P <= 0.23 at 90 %. The Wilson score
interval (Wilson 1927; Brown, Cai and DasGupta 2001 recommend it for small n) keeps its coverage near
the nominal level down to a few runs and never collapses to a point at P = 0 or 1, unlike the normal
approximation or a bootstrap of the runs.
"""
from __future__ import annotations

from statistics import NormalDist

import numpy as np

from drillpy import validate


def wilson_interval(p, n: int, confidence: float = 0.9) -> tuple[np.ndarray, np.ndarray]:
    """Two-sided Wilson score interval of proportions ``p`` observed over ``n`` independent runs each.

    Parameters
    ----------
    p : array_like
        Observed proportions in [0, 1] (k / n; a mean of such proportions is accepted as is).
    n : int
        Independent runs behind each proportion (>= 1).
    confidence : float
        Confidence level, in (0, 1) (default 0.9).

    Returns
    -------
    tuple of numpy.ndarray
        Lower and upper bounds, same shape as ``p``.

    Raises
    ------
    ValueError
        Naming ``n``, ``confidence`` or ``p`` when out of range.
    """
    validate.integer("n", n, 1)
    validate.fraction("confidence", confidence, closed=False)
    p = np.asarray(p, dtype=float)
    if np.any((p < 0) | (p > 1)) or not np.all(np.isfinite(p)):
        raise ValueError(f"p = {p.tolist()!r}: proportions must lie in [0, 1]")
    # the standard normal quantile from the standard library (Wichura's AS 241, to the last bits of
    # SciPy's): mc and control need no scipy.stats, whose import alone took 0.7 s of a 5 s mc run
    z = NormalDist().inv_cdf(0.5 + 0.5 * confidence)
    z2n = z * z / n
    centre = (p + 0.5 * z2n) / (1.0 + z2n)
    half = z * np.sqrt(p * (1.0 - p) / n + z2n / (4.0 * n)) / (1.0 + z2n)
    # at p = 0 (1) the lower (upper) bound is exactly 0 (1); rounding must not move it off the count
    lo = np.where(p == 0.0, 0.0, np.clip(centre - half, 0.0, 1.0))
    hi = np.where(p == 1.0, 1.0, np.clip(centre + half, 0.0, 1.0))
    return lo, hi
