"""Plausibility warnings for a configuration: values the engine accepts but no drill string has.

A value in the wrong unit passes every range check of the parser (a radius of 63.5 m is positive,
E = 207 Pa is positive) and gives numbers that look like results. :func:`check_config` compares each
physical value with the range real strings span and returns a :class:`ConfigWarning` naming the
field, the value, the range and the range's source; :func:`warn_config` issues them as Python warnings
(category :class:`ImplausibleConfiguration`), which the ``drillpy`` command prints as one line each.
A warning never stops a run: invalid values are refused by the engine.
"""
from __future__ import annotations

import contextlib
import math
import warnings
from dataclasses import dataclass

RPM = 30.0 / math.pi

#: field suffix -> (low, high, unit, source); bounds are wide: a factor of several beyond real strings,
#: so that only a unit mix-up or a typing error falls outside.
RANGES = {
    "outer_radius_m": (1e-3, 0.5, "m", "from the thesis rig's 2.5 mm bar (Table 5.1) to the largest drill collars "
                                       "(API Spec 7-1: 11 in OD, 0.14 m radius), with margin"),
    "youngs_modulus_pa": (1e10, 1e12, "Pa", "aluminium drill pipe (70 GPa) to tungsten carbide (600 GPa); steel "
                                           "207-220 GPa"),
    "density_kg_m3": (1000.0, 20000.0, "kg/m^3", "aluminium (2700) to tungsten carbide (15600); steel 7800-7850"),
    "string_length_m": (0.1, 15000.0, "m", "a lab rig (1.7 m, thesis Table 5.1) to the deepest borehole drilled "
                                           "(Kola SG-3, 12 262 m)"),
    "top_speed_rad_s": (0.0, 32.0, "rad/s", "top drives and rotary tables turn at most about 300 RPM (31 rad/s); "
                                           "the thesis studies 6-27 rad/s"),
    "wob_n": (0.0, 2e6, "N", "the heaviest field WOBs, about 450 kN (100 klbf), with a margin of 4"),
    "law_scale": (0.0, math.inf, "N m", "Eqs. 3.1-3.2: the static torque scale of the law (c0, b0) is positive: "
                                        "a negative one drives the bit"),
}


class ImplausibleConfiguration(UserWarning):
    """Category of the plausibility warnings of a configuration."""


@contextlib.contextmanager
def fitted_values():
    """A context (or, as ``@fitted_values()``, a decorator) in which the configurations a
    calibration tries raise no plausibility warning.

    A search's trial configurations are judged by their parameters' bounds and flags (the loop's
    evidence, the rig model's ``RIG_PARAMETERS``), not by the check a user's typed input gets: a
    motor's no-load command above the 32 rad/s any top drive reaches is a fitted value, not a unit
    typed wrongly. Warnings of other categories pass.
    """
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ImplausibleConfiguration)
        yield


@dataclass(frozen=True)
class ConfigWarning:
    """One implausible value of a configuration.

    Attributes
    ----------
    field : str
        The key path, e.g. ``string.sections[0].outer_radius_m``.
    value : float
        The value, in ``unit``.
    plausible : tuple of float
        (low, high) of the plausible range, in ``unit``.
    unit : str
        Unit of ``value`` and ``plausible``.
    source : str
        Where the range comes from.
    message : str
        One line with all of the above and the likely cause.
    """
    field: str
    value: float
    plausible: tuple
    unit: str
    source: str
    message: str


def _number(value) -> float | None:
    """``value`` as a float, None when it is not a real number (the engine names that error)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value)


def check_value(field: str, key: str, value, hint: str = "") -> list:
    """The warning of one value outside its range of :data:`RANGES` (empty when inside, or NaN).

    Parameters
    ----------
    field : str
        The field named.
    key : str
        Its range in :data:`RANGES`.
    value : float
        The value, in the range's unit.
    hint : str
        The likely cause, appended to the message.

    Returns
    -------
    list of ConfigWarning
    """
    lo, hi, unit, source = RANGES[key]
    v = _number(value)
    if v is None or lo <= v <= hi or math.isnan(v):
        return []
    msg = (f"{field} = {v:g} {unit}: outside the plausible {lo:g}-{hi:g} {unit} ({source})"
           + (f"; {hint}" if hint else ""))
    return [ConfigWarning(field, v, (lo, hi), unit, source, msg)]


def check_speed(field: str, speed_rad_s: float) -> list:
    """The warning of a top speed above what top drives turn (a speed typed in RPM as rad/s, usually).

    Parameters
    ----------
    field : str
        The field or option named.
    speed_rad_s : float
        The speed [rad/s].

    Returns
    -------
    list of ConfigWarning
    """
    v = _number(speed_rad_s)
    if v is None or not v > 0:  # not a number, zero, negative or NaN: the engine's error, not a warning
        return []
    hint = (f"if {v:g} was meant in RPM, it is {v / RPM:.3g} rad/s: give the unit (e.g. 120rpm)"
            if RANGES["top_speed_rad_s"][0] <= v / RPM <= RANGES["top_speed_rad_s"][1] else "")
    return check_value(field, "top_speed_rad_s", v, hint)


def check_config(cfg: dict) -> list:
    """Every implausible value of a configuration.

    Parameters
    ----------
    cfg : dict
        A configuration (the JSON schema).

    Returns
    -------
    list of ConfigWarning
        Checks: each section's outer radius, Young's modulus and density (except a section named
        ``"coupling"``, the shaft coupling of :func:`drillpy.records.rigsim.add_coupling`, whose radius
        only sets its stiffness), the string's total length, the
        operating top speed and WOB, and the sign of the law's static torque scale (``b0``, ``c0``).
    """
    out = []
    def block(x, key, kind=dict):  # a malformed block is the engine's error: nothing to check here
        v = x.get(key) if isinstance(x, dict) else None
        return v if isinstance(v, kind) else kind()
    sections = block(block(cfg, "string"), "sections", list)
    for i, s in enumerate(sections):
        if not isinstance(s, dict):
            continue
        if s.get("name") == "coupling":  # a shaft coupling (rigsim.add_coupling): its radius sets k_c, not a bar's
            continue
        for key, hint in (("outer_radius_m", "a radius in mm or inches typed as metres?"),
                          ("youngs_modulus_pa", "a modulus in GPa typed as Pa?"),
                          ("density_kg_m3", "a density in g/cm^3 typed as kg/m^3?")):
            if key in s:
                out += check_value(f"string.sections[{i}].{key}", key, s[key], hint)
    lengths = [_number(s.get("length_m")) for s in sections if isinstance(s, dict)]
    if lengths and None not in lengths:
        out += check_value("string.sections[*].length_m (total)", "string_length_m", sum(lengths))
    op = block(cfg, "operation")
    if "top_speed_rad_s" in op:
        out += check_speed("operation.top_speed_rad_s", op["top_speed_rad_s"])
    wob = _number(op.get("wob_n"))
    if wob is not None and wob >= 0:  # a negative WOB is the engine's error, not a warning
        out += check_value("operation.wob_n", "wob_n", wob, "a WOB in kN, klbf or kg typed as N?")
    law = block(cfg, "law")
    for key in ("b0", "c0"):
        v = _number(law.get(key))
        if v is not None and v < 0:
            out += check_value(f"law.{key}", "law_scale", v)
    return out


def warn(found: list) -> None:
    """Issue each warning as a Python warning of category :class:`ImplausibleConfiguration`.

    Parameters
    ----------
    found : list of ConfigWarning
        The warnings (:func:`check_config`, :func:`check_speed`).
    """
    for w in found:
        warnings.warn(w.message, ImplausibleConfiguration, stacklevel=3)


def warn_config(cfg: dict) -> None:
    """:func:`warn` the warnings of :func:`check_config`.

    Parameters
    ----------
    cfg : dict
        A configuration.
    """
    warn(check_config(cfg))
