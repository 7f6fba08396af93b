"""``string_friction``: a Coulomb torque along the string that the bit's load cell does not see."""
from __future__ import annotations

from .base import Effect, Param


class StringFriction(Effect):
    name = "string_friction"
    params = (Param("string_friction_nm", "N m", "T_sf: Coulomb torque opposing the rotation, lumped at the bit",
                    0.0, 10.0, null=0.0),)
    change = ("a Coulomb torque T_sf sign(v) on the bit outside the torque sensor, set-valued at rest (it adds to the "
              "static capacity; operation.string_friction_nm)")
    signature = ("a bit-speed residual of constant sign while the bit slips: the bit decelerates more than the "
                 "measured torque explains, by the same amount at every speed, and it sticks for longer")
    reading = ("friction of the string against its guides or the borehole wall (and of the bearings), which the load "
               "cell under the rock holder does not measure")
    defaults = {"string_friction_nm": 0.3}

    def starts(self, model, data):
        from ..model import state_channels
        chs = state_channels(model, data)
        slip = data.valid & (chs["v"] > data.stick_threshold)
        tref = float(abs(chs["T"][slip].mean()))
        return [{"string_friction_nm": f * tref} for f in (0.02, 0.1, 0.3)]

    def declared(self, cfg):
        t = float(cfg["operation"].get("string_friction_nm", 0.0))
        return {"string_friction_nm": t} if t > 0 else None

    def strip(self, cfg):
        cfg["operation"].pop("string_friction_nm", None)

    def configure(self, cfg, p, model):
        cfg["operation"]["string_friction_nm"] = float(p["string_friction_nm"])

    def inject(self, truth, p):
        self.configure(truth.cfg, p, None)


EFFECT = StringFriction()
