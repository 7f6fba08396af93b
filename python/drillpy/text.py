"""Numbers in report text: one rule for a value that is missing."""
from __future__ import annotations

import math


def number_text(x, spec: str = ".4f") -> str:
    """``format(x, spec)``, or ``"n/a"`` when ``x`` is None or a float that is not finite.

    Parameters
    ----------
    x : float or int or None
        The value.
    spec : str
        Format specification, e.g. ``".3f"`` or ``".3g"``.

    Returns
    -------
    str
        The formatted value.
    """
    return "n/a" if x is None or (isinstance(x, float) and not math.isfinite(x)) else format(x, spec)
