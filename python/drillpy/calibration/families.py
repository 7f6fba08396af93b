"""The bit-rock law families the calibration compares: one table, :data:`FAMILIES`.

Each family is an equation of the thesis with its calibrated law parameters (their priors are
:data:`LAW_PARAMETERS`, physical ranges at the test rig's scale) and the builder of its engine law
from the configuration's polynomial law (the ``thesis-rig`` preset's, Eq. 5.3) and the parameter
values. The configuration's law gives what every family shares: the reference WOB (every law scales
linearly with the WOB from it), the speed unit the built law is written in (docs/units.md), the
reference speed (each family rises from rest over 1 % of it, as the polynomial families' a1 ties a0
to a2, :mod:`drillpy.records.identification`) and the hysteresis's beta2.

====================== ============ ===========================================================
family                 equation     calibrated law parameters (torques at the reference WOB)
====================== ============ ===========================================================
polynomial_hysteretic  5.3, a0 = 0  ``law_scale``: factor on the slip branch a2..a7
polynomial             5.1          ``law_scale``, ``static_torque_nm`` (gain x a0)
tucker_wang            3.1          ``tw_c0_nm``, ``tw_hump_ratio``, ``tw_peak_speed_rad_s``
hysteretic             3.2-3.3      ``hy_b0_nm``, ``hy_hump_gain``, ``hy_speed_scale_rad_s``, ``hy_beta1``
====================== ============ ===========================================================

A new family is one more row of :data:`FAMILIES` (its builder and its parameters' priors here).
"""
from __future__ import annotations

import copy
import math
from dataclasses import dataclass
from typing import Callable

#: Speed unit of a law -> its value of 1 rad/s (docs/units.md).
UNIT_PER_RAD_S = {"rad_s": 1.0, "rad/s": 1.0, "rpm": 30.0 / math.pi, "RPM": 30.0 / math.pi}
#: Exponents b4, b5 of Eq. (3.2), held at the thesis's fit (section 3.2: 0.78, 1.1): with b5 > b4 the
#: speed-dependent term rises from rest, peaks near 2.25 speed scales and decays as v^(b4 - b5).
HY_EXPONENTS = (0.78, 1.1)

# Where the ranges come from: the thesis-rig preset's Eq. (5.3) law (a0 = 0, gain 1.36, 90.36 RPM,
# 557.1 N; drillpy.model.simulation.law_torque) gives at its reference WOB 2.69 N m from 0.1 to
# 0.5 rad/s (its low-speed plateau), 2.05 N m at 10 rad/s, 1.51 at 15, 1.18 at 18 and 0.96 at
# 20 rad/s: the record's slip speeds (sample 175's bit-speed p95 is 18.4 rad/s, its mean top speed
# 8.6 rad/s, docs/calibration.md). The calibration's law_scale spreads the torque x0.6-x1.6 (the
# rock's variation between samples, priors.PARAMETERS); the same spread is applied below.
#: Law parameters of the Eq. (3.1) and (3.2)-(3.3) families: (low, high, unit, scale, source).
LAW_PARAMETERS = {
    "tw_c0_nm": (0.5, 2.5, "N m", "uniform",
                 "Eq. (3.1) c0, the torque the law tends to at high speed: the thesis-rig law's torque at the "
                 "record's fast slip speeds, 0.96-1.51 N m over 15-20 rad/s, spread x0.6-x1.6 as law_scale "
                 "(0.57-2.4 N m)"),
    "tw_hump_ratio": (0.2, 3.0, "-", "uniform",
                      "Eq. (3.1) h = alpha1 / (2 sqrt(alpha2)), the low-speed peak over c0 minus 1: the thesis-rig "
                      "law's plateau 2.69 N m over its 15-20 rad/s level is 1.8-2.8 (h 0.8-1.8), the thesis's "
                      "field fit h = 1.43 (section 3.1); 0.2-3 spans a nearly flat law to a steeper weakening"),
    "tw_peak_speed_rad_s": (0.1, 3.0, "rad/s", "log-uniform",
                            "Eq. (3.1) 1 / sqrt(alpha2), the speed of the hump's peak: the thesis-rig law is at its "
                            "plateau over 0.1-0.5 rad/s and still at 96 % of it at 3 rad/s; the field fit peaks "
                            "at 0.54 rad/s (section 3.1, docs/units.md)"),
    "hy_b0_nm": (0.15, 2.0, "N m", "uniform",
                 "Eq. (3.2) b0, the torque of the tanh term: at the thesis's shape (g 5.1, v_s 0.25 rad/s, "
                 "below) the law is 2.2-3.7 b0 over 1-20 rad/s, so the thesis-rig law's 0.96-2.69 N m there, "
                 "x0.6-x1.6, puts b0 within 0.16-2.0 N m"),
    "hy_hump_gain": (0.3, 10.0, "-", "log-uniform",
                     "Eq. (3.2) g = b2 v_s^b4, the height of the speed-dependent term (its peak is 0.55 g): the "
                     "thesis's fit g = 5.1 (section 3.2, b2 = 2.56, b3 = 0.38 in RPM); 0.3-10 from a small "
                     "hump to twice the fit's"),
    "hy_speed_scale_rad_s": (0.03, 3.0, "rad/s", "log-uniform",
                             "Eq. (3.2) v_s = b3^(-1/b5), the speed scale of the speed-dependent term (its peak "
                             "near 2.25 v_s): the thesis's fit 2.41 RPM = 0.25 rad/s; the thesis-rig law's "
                             "plateau at 0.1-0.5 rad/s puts the peak's v_s near 0.04-0.2 rad/s, up to 3 rad/s "
                             "(peak at 7 rad/s) for a law still rising over the slow slip"),
    "hy_beta1": (0.0, 0.3, "-", "uniform",
                 "Eq. (3.3) beta1, the hysteresis's amplitude: the thesis-rig law's 0.086 (Eq. 5.3, section 5.2) "
                 "and the field value 0.14 (Figs. 3.11-3.12) inside; beta2 is held at the configuration's"),
}
#: Parameters that are positive (a zero low end is refused) and those in [0, 1) (Eq. 3.3's beta1).
POSITIVE = ("tw_c0_nm", "tw_hump_ratio", "tw_peak_speed_rad_s", "hy_b0_nm", "hy_hump_gain", "hy_speed_scale_rad_s")
FRACTION = ("hy_beta1",)


@dataclass(frozen=True)
class Family:
    """A law family of the comparison.

    Attributes
    ----------
    equation : str
        The thesis's equation(s) and reading.
    parameters : tuple of str
        Its calibrated law parameters (priors: :data:`LAW_PARAMETERS`,
        :data:`drillpy.calibration.priors.PARAMETERS`).
    build : callable
        ``build(base, values, u)`` -> the engine law: ``base`` the configuration's polynomial law,
        ``values`` parameter -> value, ``u`` the value of 1 rad/s in the law's speed unit.
    """
    equation: str
    parameters: tuple
    build: Callable


def _rise(base: dict) -> float:
    """The tanh rate of Eqs. (3.1)-(3.2) [1 / speed_unit]: the same slope at rest per unit of torque
    as the polynomial families' a1, which reaches a2 at 1 % of the reference speed."""
    return 1.0 / (0.01 * float(base["ref_speed"]))


def _polynomial(base: dict, values: dict, static: bool) -> dict:
    """Eq. (5.1) (``static``: a0 from the static torque, no hysteresis) or Eq. (5.3) regularized
    (a0 = 0), the slip branch a2..a7 times ``law_scale``; a1 ties a0 to a2 at 1 % of ref_speed."""
    law = copy.deepcopy(base)
    for k in ("a2", "a3", "a4", "a5", "a6", "a7"):
        law[k] = float(base.get(k, 0.0)) * values["law_scale"]
    if static:
        law["type"] = "polynomial"
        law["a0"] = float(values["static_torque_nm"]) / float(base.get("gain", 1.36))
        law.pop("beta1", None)
        law.pop("beta2", None)
    else:
        law["type"] = "polynomial_hysteretic"
        law["a0"] = 0.0
        law.setdefault("beta1", 0.0)
        law.setdefault("beta2", 0.0)
    law["a1"] = (law["a2"] - law["a0"]) / (0.01 * float(base["ref_speed"]))
    return law


def _tucker_wang(base: dict, values: dict, u: float) -> dict:
    """Eq. (3.1) T = c0 [tanh(alpha0 v) + alpha1 v / (1 + alpha2 v^2)], v in the base's unit:
    alpha2 = 1 / v_p^2 and alpha1 = 2 h / v_p put the hump's peak c0 h at v_p."""
    vp = values["tw_peak_speed_rad_s"] * u
    return {"type": "tucker_wang", "speed_unit": base["speed_unit"], "wob_ref_n": base["wob_ref_n"],
            "c0": float(values["tw_c0_nm"]), "alpha0": _rise(base),
            "alpha1": 2.0 * values["tw_hump_ratio"] / vp, "alpha2": 1.0 / vp ** 2}


def _hysteretic(base: dict, values: dict, u: float) -> dict:
    """Eqs. (3.2)-(3.3) T = b0 [tanh(b1 v) + b2 |v|^b4 sign(v) / (1 + b3 |v|^b5) (1 + H)],
    H = beta1 tanh(beta2 a) sign(v): b3 = v_s^-b5 and b2 = g v_s^-b4 make the speed-dependent term
    g x^b4 / (1 + x^b5) of x = v / v_s; b4, b5 the thesis's (:data:`HY_EXPONENTS`), beta2 the
    base's (0: no hysteresis)."""
    vs = values["hy_speed_scale_rad_s"] * u
    b4, b5 = HY_EXPONENTS
    return {"type": "hysteretic", "speed_unit": base["speed_unit"], "wob_ref_n": base["wob_ref_n"],
            "b0": float(values["hy_b0_nm"]), "b1": _rise(base), "b2": values["hy_hump_gain"] * vs ** -b4,
            "b3": vs ** -b5, "b4": b4, "b5": b5, "beta1": float(values["hy_beta1"]),
            "beta2": float(base.get("beta2", 0.0))}


#: The families: name -> :class:`Family` (module docstring).
FAMILIES = {
    "polynomial_hysteretic": Family("5.3 (regularized, hysteretic)", ("law_scale",),
                                    lambda base, values, u: _polynomial(base, values, False)),
    "polynomial": Family("5.1 (non-regularized, sticks)", ("law_scale", "static_torque_nm"),
                         lambda base, values, u: _polynomial(base, values, True)),
    "tucker_wang": Family("3.1 (Tucker-Wang, regularized)", ("tw_c0_nm", "tw_hump_ratio", "tw_peak_speed_rad_s"),
                          _tucker_wang),
    "hysteretic": Family("3.2-3.3 (hysteretic, regularized)",
                         ("hy_b0_nm", "hy_hump_gain", "hy_speed_scale_rad_s", "hy_beta1"), _hysteretic),
}
#: The families compared when the configuration names none: Eqs. (5.3) and (5.1) (the four-family
#: comparison of docs/calibration.md is selected with ``calibration.families``).
DEFAULT_FAMILIES = ("polynomial_hysteretic", "polynomial")
#: The law types the families are built on.
BASE_TYPES = ("polynomial", "polynomial_hysteretic")


def check_base(base: dict) -> None:
    """Refuse a configuration law the families cannot be built on.

    Parameters
    ----------
    base : dict
        The configuration's engine law.

    Raises
    ------
    ValueError
        Naming ``law.type`` or ``law.speed_unit`` and the value.
    """
    if base.get("type") not in BASE_TYPES:
        raise ValueError(f"law.type = {base.get('type')!r}: the calibration's families are built on an Eq. (5.1)/(5.3) "
                         "law (its reference WOB and speed): give a 'polynomial' or 'polynomial_hysteretic' law")
    if base.get("speed_unit") not in UNIT_PER_RAD_S:
        raise ValueError(f"law.speed_unit = {base.get('speed_unit')!r}: use rad_s or rpm")


def family_law(base: dict, family: str, values: dict) -> dict:
    """The engine law of ``family`` at the parameter ``values``, built on the configuration's law ``base``.

    Parameters
    ----------
    base : dict
        A ``polynomial`` or ``polynomial_hysteretic`` engine law (its ``wob_ref_n``, ``speed_unit``,
        ``ref_speed`` and ``beta2`` are the families').
    family : str
        A name of :data:`FAMILIES`.
    values : dict
        Parameter -> value; the family's :attr:`Family.parameters` are read, others ignored.

    Returns
    -------
    dict
        The engine law (``law`` section of a configuration).

    Raises
    ------
    ValueError
        Naming the family, the law's type or a missing parameter.
    """
    check_base(base)
    fam = FAMILIES.get(family)
    if fam is None:
        raise ValueError(f"family = {family!r}: use {', '.join(FAMILIES)}")
    missing = [p for p in fam.parameters if p not in values]
    if missing:
        raise ValueError(f"family {family!r}: parameter {missing[0]!r} missing (give {', '.join(fam.parameters)})")
    return fam.build(base, values, UNIT_PER_RAD_S[base["speed_unit"]])
