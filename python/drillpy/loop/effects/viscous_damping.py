"""``viscous_damping``: an extra viscous torque on the bit that the torque sensor does not see."""
from __future__ import annotations

from .base import Effect, Param
from ..view import view


class ViscousDamping(Effect):
    """An extra viscous torque c_v v on the bit, outside the torque sensor
    (``operation.bit_viscous_nms``).

    Parameter ``bit_viscous_nms`` c_v [N m s/rad] (0-10, absent at 0). Confounded with the string
    damping at a constant top speed (see :attr:`confounded_with`); not a candidate while the
    damping ratios are held by the limit cycle.
    """
    name = "viscous_damping"
    params = (Param("bit_viscous_nms", "N m s/rad", "c_v: viscous torque per unit bit speed", 0.0, 10.0, null=0.0),)
    change = "an extra torque c_v v on the bit, outside the torque sensor (operation.bit_viscous_nms)"
    signature = ("a bit-speed residual growing with the bit speed over the horizon: the bit decelerates more than "
                 "the measured torque explains")
    reading = ("drag of the water added while drilling (section 5.3.1, step 5) on the disk and bit, and the lower "
               "bearing")
    #: With a constant top speed Omega, -c_v v = c_v (Omega - v) - c_v Omega: a string damping (which the
    #: calibration of the modal damping ratio absorbs) plus a constant torque c_v Omega outside the
    #: sensor, which ``string_friction`` describes while the bit slips. The effect is identifiable as
    #: such only when the top speed varies.
    #: While the damping ratios are held by the limit cycle (loop.damping_hold.hold_damping) an extra viscous
    #: torque would undo that choice: it is then not a candidate.
    confounded_with = ("damping",)
    confounded_note = ("a viscous torque at the bit is one such element that this record cannot tell from the damping "
                       "(with the top at a steady speed, -c_v v is a string damping plus a constant: viscous_damping is "
                       "confounded with it, docs/loop.md), so it is not named")
    defaults = {"bit_viscous_nms": 0.03}

    def starts(self, model, data):
        """1 %, 5 % and 20 % of c_ref = |mean T| / mean v over the slip samples (the viscous
        coefficient that would carry the whole mean torque); see :meth:`Effect.starts`.

        Parameters
        ----------
        model : LoopModel
            The current model (its state channels).
        data : LoopData
            The record on the analysis grid.
        """
        from ..model import state_channels
        chs = state_channels(model, data)
        slip = data.valid & (chs["v"] > data.stick_threshold)
        cref = float(abs(chs["T"][slip].mean()) / max(chs["v"][slip].mean(), 1e-9))
        return [{"bit_viscous_nms": f * cref} for f in (0.01, 0.05, 0.2)]

    def declared(self, cfg):
        """``{"bit_viscous_nms"}`` of the operation when > 0, else None; see :meth:`Effect.declared`.

        Parameters
        ----------
        cfg : dict or Configuration
            The declared engine configuration.
        """
        cv = float(view(cfg).operation.get("bit_viscous_nms", 0.0))
        return {"bit_viscous_nms": cv} if cv > 0 else None

    def strip(self, cfg):
        """Set ``operation.bit_viscous_nms`` to 0; see :meth:`Effect.strip`.

        Parameters
        ----------
        cfg : dict
            Engine configuration, modified in place.
        """
        cfg["operation"]["bit_viscous_nms"] = 0.0

    def configure(self, cfg, p, model):
        """Set ``operation.bit_viscous_nms`` to c_v; see :meth:`Effect.configure`.

        Parameters
        ----------
        cfg : dict
            Engine configuration, modified in place.
        p : dict
            ``{"bit_viscous_nms": c_v [N m s/rad]}``.
        model : LoopModel or None
            Not used.
        """
        cfg["operation"]["bit_viscous_nms"] = float(p["bit_viscous_nms"])

    def inject(self, truth, p):
        """Configure the truth with c_v (:meth:`configure`); see :meth:`Effect.inject`.

        Parameters
        ----------
        truth : drillpy.loop.synthetic.Truth
            The synthetic truth (its configuration).
        p : dict
            ``{"bit_viscous_nms": c_v [N m s/rad]}`` (default 0.03).
        """
        self.configure(truth.cfg, p, None)


EFFECT = ViscousDamping()
