"""``static_friction``: a break-away torque at the bit (the non-regularized Eq. 5.1, a0 > 0)."""
from __future__ import annotations

import numpy as np

from .base import Effect, Param


def _a0(law: dict, torque: float, wob: float) -> float:
    """a0 of Eq. (5.1) whose static torque gain a0 W / W_ref is ``torque`` at ``wob``."""
    return float(torque) * float(law["wob_ref_n"]) / (float(law["gain"]) * float(wob))


class StaticFriction(Effect):
    name = "static_friction"
    params = (Param("static_torque_nm", "N m", "T_s: torque the string must exceed to break the stuck bit away "
                    "(gain a0 W / W_ref of Eq. 5.1)", 0.0, 20.0, null=0.0),)
    change = ("the law's static torque: the bit stays stuck while the string torque is below T_s (Eq. 5.1 with "
              "a0 > 0; a1 re-tied so that the law falls linearly from T_s to the slip branch)")
    signature = ("bit-speed residuals at the stick-slip transitions: the measured bit stays stuck after the model's "
                 "breaks away, and the torque keeps rising while the model's drops")
    reading = ("the rock holder's break-away (static) friction: the bit sticks, the string winds up, and it breaks "
               "away at a torque above the sliding one (the stick phases of the rig, e.g. at 28-30 s of sample 175)")
    #: Synthetic truth: 4.5 N m, 1.7 x the declared law's torque at low speed (2.69 N m at 0.1 rad/s).
    defaults = {"static_torque_nm": 4.5}

    def _check(self, law):
        if not str(law["type"]).startswith("polynomial"):
            raise ValueError(f"static_friction: the law {law['type']!r} has no static torque (Eq. 5.1 needed)")

    def starts(self, model, data):
        self._check(model.law)
        from ..model import state_channels
        chs = state_channels(model, data)
        slip = data.valid & (chs["v"] > data.stick_threshold)
        t95 = float(np.percentile(np.abs(chs["T"][slip]), 95))
        return [{"static_torque_nm": f * t95} for f in (0.6, 0.9, 1.2)]

    def declared(self, cfg):
        law = cfg["law"]
        if str(law["type"]).startswith("polynomial") and float(law.get("a0", 0.0)) > 0:
            return {"static_torque_nm": float(law["gain"]) * float(law["a0"]) * float(cfg["operation"]["wob_n"])
                    / float(law["wob_ref_n"])}
        return None

    def strip(self, cfg):
        law = cfg["law"]
        if str(law["type"]).startswith("polynomial"):
            self._set(law, 0.0)

    @staticmethod
    def _set(law, a0):
        ref = float(law["ref_speed"])
        law["a0"] = float(a0)
        law["a1"] = (float(law["a2"]) - float(a0)) / (0.01 * ref)  # the tie of drillpy.identification

    def configure(self, cfg, p, model):
        self._check(cfg["law"])
        self._set(cfg["law"], _a0(cfg["law"], p["static_torque_nm"], cfg["operation"]["wob_n"]))

    def inject(self, truth, p):
        self.configure(truth.cfg, p, None)


EFFECT = StaticFriction()
