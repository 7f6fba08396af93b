"""One validator for options given in Python: every refusal names the field and the value.

The engine's configuration is validated by the engine itself (``drill/config.hpp``); these helpers
check the options that live on the Python side (cleaning, the loop, studies, records) with one
wording: ``"<field> = <value>: must be ..."``. Booleans are never accepted as numbers.
"""
from __future__ import annotations

import math
import numbers

__all__ = ["number", "positive", "non_negative", "fraction", "integer", "seed"]


def _is_number(value) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def number(field: str, value, *, lo: float = -math.inf, hi: float = math.inf,
           lo_closed: bool = True, hi_closed: bool = True, unit: str = "") -> float:
    """A finite real number in an interval.

    Parameters
    ----------
    field : str
        Name of the option, as the user wrote it (e.g. ``"cleaning.max_fill_s"``).
    value : object
        The value given.
    lo, hi : float
        Bounds of the interval (infinite: unbounded on that side).
    lo_closed, hi_closed : bool
        Whether each bound belongs to the interval.
    unit : str
        Unit named in the message, e.g. ``"rad/s"``.

    Returns
    -------
    float
        The value as a float.

    Raises
    ------
    ValueError
        ``"<field> = <value>: must be a number in [lo, hi)"`` (or the plainer wording for the
        usual intervals) when the value is not a finite number in the interval.
    """
    ok = _is_number(value) and math.isfinite(value)
    if ok:
        v = float(value)
        ok = (v >= lo if lo_closed else v > lo) and (v <= hi if hi_closed else v < hi)
    if not ok:
        raise ValueError(f"{field} = {value!r}: must be {_describe(lo, hi, lo_closed, hi_closed)}"
                         + (f" [{unit}]" if unit else ""))
    return float(value)


def _describe(lo, hi, lo_closed, hi_closed) -> str:
    if hi == math.inf and lo == 0:
        return "a non-negative number" if lo_closed else "a positive number"
    if lo == -math.inf and hi == math.inf:
        return "a finite number"
    left = "[" if lo_closed and lo != -math.inf else "("
    right = "]" if hi_closed and hi != math.inf else ")"
    return f"a number in {left}{lo:g}, {hi:g}{right}"


def positive(field: str, value, unit: str = "") -> float:
    """A finite number > 0 (see :func:`number`).

    Parameters
    ----------
    field : str
        Name of the option, as the user wrote it.
    value : object
        The value given.
    unit : str
        Unit named in the message, e.g. ``"rad/s"``.

    Returns
    -------
    float
        The value as a float.

    Raises
    ------
    ValueError
        ``"<field> = <value>: must be a positive number"``.
    """
    return number(field, value, lo=0.0, lo_closed=False, unit=unit)


def non_negative(field: str, value, unit: str = "") -> float:
    """A finite number >= 0 (see :func:`number`).

    Parameters
    ----------
    field : str
        Name of the option, as the user wrote it.
    value : object
        The value given.
    unit : str
        Unit named in the message, e.g. ``"s"``.

    Returns
    -------
    float
        The value as a float.

    Raises
    ------
    ValueError
        ``"<field> = <value>: must be a non-negative number"``.
    """
    return number(field, value, lo=0.0, unit=unit)


def fraction(field: str, value, *, closed: bool = True) -> float:
    """A number in [0, 1] (``closed``) or in (0, 1) (see :func:`number`).

    Parameters
    ----------
    field : str
        Name of the option, as the user wrote it.
    value : object
        The value given.
    closed : bool
        True: 0 and 1 are allowed; False: the open interval (0, 1).

    Returns
    -------
    float
        The value as a float.

    Raises
    ------
    ValueError
        ``"<field> = <value>: must be a number in [0, 1]"`` (or ``(0, 1)``).
    """
    return number(field, value, lo=0.0, hi=1.0, lo_closed=closed, hi_closed=closed)


def integer(field: str, value, minimum: int | None = None, maximum: int | None = None) -> int:
    """An integer (not a bool, not a float) within optional bounds.

    Parameters
    ----------
    field : str
        Name of the option.
    value : object
        The value given.
    minimum, maximum : int, optional
        Inclusive bounds.

    Returns
    -------
    int
        The value as a Python int.

    Raises
    ------
    ValueError
        ``"<field> = <value>: must be an integer >= minimum"`` (or ``between minimum and maximum``).
    """
    ok = isinstance(value, numbers.Integral) and not isinstance(value, bool)
    if ok:
        ok = (minimum is None or int(value) >= minimum) and (maximum is None or int(value) <= maximum)
    if not ok:
        if minimum is not None and maximum is not None:
            what = f"an integer between {minimum} and {maximum}"
        elif minimum is not None:
            what = f"an integer >= {minimum}"
        elif maximum is not None:
            what = f"an integer <= {maximum}"
        else:
            what = "an integer"
        raise ValueError(f"{field} = {value!r}: must be {what}")
    return int(value)


def seed(value, field: str = "seed") -> int:
    """A random seed: an integer in [0, 2^64) (the engine's Philox key).

    Parameters
    ----------
    value : object
        The seed given.
    field : str
        Name of the option in the message (default ``"seed"``).

    Returns
    -------
    int
        The seed as a Python int.

    Raises
    ------
    ValueError
        ``"<field> = <value>: must be an integer between 0 and 2^64 - 1"`` (bools refused).
    """
    ok = isinstance(value, numbers.Integral) and not isinstance(value, bool) and 0 <= int(value) < 2**64
    if not ok:
        raise ValueError(f"{field} = {value!r}: must be an integer between 0 and 2^64 - 1")
    return int(value)
