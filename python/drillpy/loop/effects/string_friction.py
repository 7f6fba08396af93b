"""``string_friction``: a Coulomb torque along the string that the bit's load cell does not see."""
from __future__ import annotations

import numpy as np

from .base import Effect, Param
from ..view import view


class StringFriction(Effect):
    """A Coulomb torque T_sf sign(v) on the bit outside the torque sensor, set-valued at rest
    (``operation.string_friction_nm``, an engine extension: it adds to the static capacity of the
    stick condition).

    Parameter ``string_friction_nm`` T_sf [N m] (0-10, absent at 0). Near rest the restart state
    takes its share from the measured contact torque (:meth:`restart_torque`).
    """
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
        """2 %, 10 % and 30 % of the mean |torque on bit| over the slip samples; see
        :meth:`Effect.starts`.

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
        tref = float(abs(chs["T"][slip].mean()))
        return [{"string_friction_nm": f * tref} for f in (0.02, 0.1, 0.3)]

    def restart_torque(self, p, model, data, chs, idx):
        """The string friction's share of the torque on a bit near rest (|v| below the stick
        threshold), from the sign of the measured contact torque rather than of the speed.

        The engine's restart state carries the total torque T + T_sf sign(v). Near rest the measured
        speed is noise around zero (its sign is a coin toss: +-T_sf, a wrong twist of 2 T_sf / k, i.e.
        tens of milliseconds of wind-up, for a stuck horizon), while the contact torque is measured
        well: both frictions oppose the same slip, so a creeping bit's contact torque has the sign
        of its speed, and a stuck bit's string friction carries what the contact does not, in the
        model's own split (``string_share`` in ``drill/euler_bit.hpp``: the contact up to the static torque T_s,
        the string friction the rest up to T_sf). The estimate inverts that split,
        share = sign(T) T_sf clip((|T| - T_s) / T_sf, 0, 1): none while the contact alone can hold
        the bit (|T| < T_s), all of T_sf once the contact torque exceeds T_s by T_sf, and across the
        set-valued plateau (|T| = T_s, where the split is not observable) a ramp through its middle.

        See :meth:`Effect.restart_torque`.

        Parameters
        ----------
        p : dict
            ``{"string_friction_nm": T_sf [N m]}``.
        model : LoopModel
            The model (T_s of a polynomial law with a0 > 0 at the law's WOB input W_eff; 0 otherwise).
        data : LoopData
            The record (its stick threshold [rad/s]).
        chs : dict
            State channels (``v`` [rad/s], ``T`` [N m], ``W_eff`` [N]).
        idx : array_like of int
            Restart sample indices.

        Returns
        -------
        numpy.ndarray or None
            share - T_sf sign(v) [N m] at the restarts near rest (replacing the engine's
            T_sf sign(v) by the share), 0 elsewhere; None when T_sf <= 0.
        """
        tsf = float(p["string_friction_nm"])
        v, T = chs["v"][idx], chs["T"][idx]
        if tsf <= 0.0:
            return None
        law = model.engine_config()["law"]  # every trial: the dict (a view: ~30 us of schema lookups)
        ts = np.zeros(v.size)
        if str(law["type"]).startswith("polynomial") and float(law.get("a0", 0.0)) > 0:
            ts = float(law["gain"]) * float(law["a0"]) * np.asarray(chs["W_eff"][idx], float) / float(law["wob_ref_n"])
        share = np.sign(T) * tsf * np.clip((np.abs(T) - ts) / tsf, 0.0, 1.0)
        near = np.abs(v) < data.stick_threshold
        return np.where(near, share - tsf * np.sign(v), 0.0)

    def declared(self, cfg):
        """``{"string_friction_nm"}`` of the operation when > 0, else None; see
        :meth:`Effect.declared`.

        Parameters
        ----------
        cfg : dict or Configuration
            The declared engine configuration.
        """
        t = float(view(cfg).operation.get("string_friction_nm", 0.0))
        return {"string_friction_nm": t} if t > 0 else None

    def strip(self, cfg):
        """Remove ``operation.string_friction_nm``; see :meth:`Effect.strip`.

        Parameters
        ----------
        cfg : dict
            Engine configuration, modified in place.
        """
        cfg["operation"].pop("string_friction_nm", None)

    def configure(self, cfg, p, model):
        """Set ``operation.string_friction_nm`` to T_sf; see :meth:`Effect.configure`.

        Parameters
        ----------
        cfg : dict
            Engine configuration, modified in place.
        p : dict
            ``{"string_friction_nm": T_sf [N m]}``.
        model : LoopModel or None
            Not used.
        """
        cfg["operation"]["string_friction_nm"] = float(p["string_friction_nm"])

    def inject(self, truth, p):
        """Configure the truth with T_sf (:meth:`configure`); see :meth:`Effect.inject`.

        Parameters
        ----------
        truth : drillpy.loop.synthetic.Truth
            The synthetic truth (its configuration).
        p : dict
            ``{"string_friction_nm": T_sf [N m]}`` (default 0.3).
        """
        self.configure(truth.cfg, p, None)


EFFECT = StringFriction()
