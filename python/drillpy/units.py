"""Units typed by the user: a number with an optional unit suffix, converted to SI.

A small explicit table (no unit library): the quantities a command takes and the units a drilling
engineer types. A plain number is SI (rad/s, N, N m, m), as it always was; ``120rpm``, ``45klbf``,
``200 kN``, ``16rad/s`` carry their unit. Unit names are case-insensitive.
"""
from __future__ import annotations

import math
import re

import numpy as np

#: quantity -> (SI unit, {unit name: factor to SI})
UNITS = {
    "speed": ("rad/s", {"rad/s": 1.0, "rad_s": 1.0, "rpm": math.pi / 30.0}),
    "force": ("N", {"n": 1.0, "kn": 1e3, "lbf": 4.4482216152605, "klbf": 4448.2216152605}),
    "torque": ("N m", {"nm": 1.0, "n_m": 1.0, "knm": 1e3, "ft-lbf": 1.3558179483314004,
                       "ft_lbf": 1.3558179483314004, "kft-lbf": 1355.8179483314004}),
    "length": ("m", {"m": 1.0, "ft": 0.3048, "in": 0.0254}),
}

_VALUE = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?|[-+]?inf|nan)\s*([a-z][a-z/_\-]*)?\s*$",
                    re.IGNORECASE)


def _factor(unit: str | None, quantity: str, default: str | None) -> float:
    si, table = UNITS[quantity]
    key = (unit or default or si).lower()
    if key == si.lower():
        return 1.0
    if key not in table:
        raise KeyError(key)
    return table[key]


def parse_quantity(text: str, quantity: str, name: str, default: str | None = None) -> float:
    """A value with an optional unit suffix, in SI.

    Parameters
    ----------
    text : str
        E.g. ``"120rpm"``, ``"45 klbf"``, ``"16"``.
    quantity : str
        A key of :data:`UNITS` (``"speed"``, ``"force"``, ``"torque"``, ``"length"``).
    name : str
        The option named in the error, e.g. ``"--top-speed"``.
    default : str, optional
        Unit of a plain number (default the SI unit).

    Returns
    -------
    float
        The value in the quantity's SI unit.

    Raises
    ------
    ValueError
        ``"<name> = '<text>': ..."`` for something that is not a number with one of the quantity's units.
    """
    si, table = UNITS[quantity]
    units = ", ".join(sorted({si, *table}))
    m = _VALUE.match(text)
    if not m:
        raise ValueError(f"{name} = {text!r}: must be a number with an optional {quantity} unit ({units})")
    try:
        return float(m.group(1)) * _factor(m.group(2), quantity, default)
    except KeyError:
        raise ValueError(f"{name} = {text!r}: unknown {quantity} unit {m.group(2)!r} (use {units})") from None


def split_unit(text: str, quantity: str) -> tuple[str, str | None]:
    """``"50:160:23rpm"`` -> ``("50:160:23", "rpm")``: a grid's trailing unit, when it is one of the quantity's.

    Parameters
    ----------
    text : str
        A grid option's value.
    quantity : str
        A key of :data:`UNITS`.

    Returns
    -------
    tuple
        The text without the unit and the unit (None when there is none).
    """
    si, table = UNITS[quantity]
    m = re.search(r"([a-z][a-z/_\-]*)\s*$", text, re.IGNORECASE)
    if m and m.group(1).lower() in {si.lower(), *table}:
        return text[:m.start()].strip(), m.group(1)
    return text, None


def grid_in_si(values: np.ndarray, unit: str | None, quantity: str, default: str | None = None,
               to: str | None = None) -> np.ndarray:
    """Grid values typed in ``unit`` (or ``default``) converted to SI (or to the unit ``to``).

    Parameters
    ----------
    values : ndarray
        The grid as typed.
    unit : str or None
        Its unit (:func:`split_unit`).
    quantity : str
        A key of :data:`UNITS`.
    default : str, optional
        Unit of a grid without one (default the SI unit).
    to : str, optional
        Unit of the result (default the SI unit); values typed in it are returned unchanged.

    Returns
    -------
    ndarray
        The grid in SI (or in ``to``).
    """
    v = np.asarray(values, float)
    source, target = (unit or default or UNITS[quantity][0]).lower(), (to or UNITS[quantity][0]).lower()
    return v if source == target else v * (_factor(source, quantity, None) / _factor(target, quantity, None))
