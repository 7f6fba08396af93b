"""The catalogue of candidate effects of ``drillpy loop``: one module per effect, each an
:class:`~drillpy.loop.effects.base.Effect` (parameters with physical bounds and no-effect values,
the model change, its signature in the residual, its physical reading, how it is fitted, how it
enters the engine configuration and how the synthetic generator injects it).

======================= ======= ===================================================================
effect                  level   model change (parameters)
======================= ======= ===================================================================
``bit_hysteresis``      law     H = beta1 tanh(beta2 a) sign(v), Eqs. (3.2)-(3.3), (5.3)
``wob_coupling``        law     the law at the measured WOB, W_eff = W_0 (1 + k (W(t)/W_0 - 1))
``top_drive_dynamics``  dynamic open-loop motor J_m Omega' = c_m (Omega_c - Omega) - T_top
``axial_jack``          dynamic the WOB a state, W' = g (Omega_f - v) - (W - W_s) / tau (the rig's jack)
``sensor_lag``          dynamic second-order Butterworth low-pass on the recorded channels (f_c)
``torque_fluctuation``  dynamic T = T_law (1 + eta), eta coloured, forecast from the record's past
``viscous_damping``     dynamic extra viscous torque c_v v on the bit, outside the torque sensor
``string_stiffness``    dynamic GJ of the string times a factor
``static_friction``     dynamic break-away torque T_s of the non-regularized Eq. (5.1) (a0 > 0)
``string_friction``     dynamic Coulomb torque T_sf sign(v) on the bit, outside the torque sensor
``sensor_gain``         dynamic the torque channel reads s T + b (s measured from the encoders' bit equation)
======================= ======= ===================================================================

Adding an effect: one module here defining ``EFFECT`` (an Effect subclass instance), its name in
:data:`NAMES`, and its test.
"""
from __future__ import annotations

import copy
import importlib

from .base import Effect, Param

NAMES = ("bit_hysteresis", "wob_coupling", "top_drive_dynamics", "axial_jack", "sensor_lag", "torque_fluctuation",
         "viscous_damping", "string_stiffness", "static_friction", "string_friction", "sensor_gain")
CATALOGUE: dict = {n: importlib.import_module(f".{n}", __name__).EFFECT for n in NAMES}


def declared_effects(cfg: dict) -> dict:
    """The catalogue's effects a declared configuration already has, with their parameters.

    Each effect's :meth:`~drillpy.loop.effects.base.Effect.declared` reads it off the
    configuration (e.g. beta1 > 0, a motor top drive, sensors, ``bit_viscous_nms``,
    ``string_friction_nm``, a polynomial law's a0 > 0); these become the calibrated model's
    declared effects, started from their declared values.

    Parameters
    ----------
    cfg : dict or Configuration
        The declared engine configuration (normalized).

    Returns
    -------
    dict
        Effect name -> parameter dict (name -> value in the parameter's unit), in catalogue order.
    """
    out = {}
    for name, eff in CATALOGUE.items():
        p = eff.declared(cfg)
        if p is not None:
            out[name] = p
    return out


def stripped(cfg: dict) -> dict:
    """A copy of a configuration with every catalogue effect removed (its no-effect value).

    The base of a :class:`drillpy.loop.model.LoopModel`: string geometry, reduced-order model,
    law family and operation without any effect of the catalogue.

    Parameters
    ----------
    cfg : dict
        An engine configuration (normalized); not modified.

    Returns
    -------
    dict
        A deep copy with each effect's :meth:`~drillpy.loop.effects.base.Effect.strip` applied.
    """
    c = copy.deepcopy(cfg)
    for eff in CATALOGUE.values():
        eff.strip(c)
    return c


__all__ = ["CATALOGUE", "NAMES", "Effect", "Param", "declared_effects", "stripped"]
