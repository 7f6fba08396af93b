"""``string_stiffness``: the string's torsional stiffness GJ differs from the declared geometry's."""
from __future__ import annotations

from .base import Effect, Param

#: GJ within +-3 % of the declared is the declared geometry: a bar's radius known to +-0.75 % (a
#: tolerance of 0.02 mm on the rig's 2.5 mm) gives J_p = pi r^4 / 2 to +-3 %.
MARGIN = 0.03


class StringStiffness(Effect):
    """The string's torsional stiffness GJ differs from the declared geometry's: every section's
    modulus times a factor.

    Parameter ``gj_factor`` [-] (0.3-3, fitted in ln; absent at 1 within +-:data:`MARGIN`, the
    declared geometry's tolerance).
    """
    name = "string_stiffness"
    params = (Param("gj_factor", "-", "GJ of the string over the declared GJ (every section)", 0.3, 3.0, "log",
                    null=1.0, margin=MARGIN),)
    change = "every section's shear modulus (Young's modulus at fixed Poisson ratio) times the factor"
    signature = ("a residual at the string's natural frequency: the predicted oscillation drifts in phase against "
                 "the measured one over the horizon, and the twist read off the torque is off by the factor")
    reading = ("the bar is softer or stiffer than its nominal dimensions and modulus say: a different diameter or "
               "material, the compliance of the couplings and the disk's clamp")
    defaults = {"gj_factor": 0.85}

    def starts(self, model, data):
        """Factors 0.8, 0.9, 1.1 and 1.25; see :meth:`Effect.starts`.

        Parameters
        ----------
        model : LoopModel
            Not used.
        data : LoopData
            Not used.
        """
        return [{"gj_factor": f} for f in (0.8, 0.9, 1.1, 1.25)]

    def configure(self, cfg, p, model):
        """Multiply every section's ``youngs_modulus_pa`` by the factor (at a fixed Poisson ratio
        the shear modulus G, hence GJ, scales with it); see :meth:`Effect.configure`.

        Parameters
        ----------
        cfg : dict
            Engine configuration (its ``string.sections``), modified in place.
        p : dict
            ``{"gj_factor": [-]}``.
        model : LoopModel or None
            Not used.
        """
        for s in cfg["string"]["sections"]:
            s["youngs_modulus_pa"] = float(s["youngs_modulus_pa"]) * float(p["gj_factor"])

    def inject(self, truth, p):
        """Scale the truth's string stiffness (:meth:`configure`); see :meth:`Effect.inject`.

        Parameters
        ----------
        truth : drillpy.loop.synthetic.Truth
            The synthetic truth (its configuration).
        p : dict
            ``{"gj_factor": [-]}`` (default 0.85).
        """
        self.configure(truth.cfg, p, None)


EFFECT = StringStiffness()
