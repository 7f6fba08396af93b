"""When the bit counts as stuck: one rule for records, cleaning, analysis and the loop.

The bit is stuck at or below a fraction (5 % by default) of the median top speed, the rule the
engine applies to simulated runs (``metrics.stick_threshold_fraction`` in ``drill/config.hpp``,
the stick phases of the stick-slip severity, thesis section 3.2).
"""
from __future__ import annotations

import numpy as np

#: Default fraction of the median top speed at or below which the bit is stuck (the engine's
#: ``metrics.stick_threshold_fraction`` default; a test keeps the two equal).
STICK_FRACTION = 0.05


def stick_threshold(top_speed, fraction: float = STICK_FRACTION) -> float:
    """The stick threshold of a record [rad/s].

    Parameters
    ----------
    top_speed : array_like
        Top-drive speed samples [rad/s] the median is taken over (non-finite samples ignored).
    fraction : float
        Fraction of the median top speed.

    Returns
    -------
    float
        ``fraction * |median(top_speed)|`` [rad/s]; NaN when no sample is finite.
    """
    v = np.asarray(top_speed, dtype=float)
    v = v[np.isfinite(v)]
    return float(fraction * abs(np.median(v))) if v.size else float("nan")
