"""``bit_hysteresis``: the acceleration term of the bit-rock law, Eqs. (3.2)-(3.3) and (5.3)."""
from __future__ import annotations

from .base import Effect, Param
from ..view import view


class BitHysteresis(Effect):
    """The hysteretic term H = beta1 tanh(beta2 a) sign(v) of the bit-rock law (Eqs. 3.2-3.3; 5.3
    for the polynomial law): a law-level effect, fitted with the law on the law residual.

    Parameters ``beta1`` [-] (amplitude of H, 0-1, absent at 0) and ``beta2`` [s per speed unit of
    the law] (acceleration scale; bounded at 100 / sd(a) by :mod:`drillpy.loop.fitting`).
    """
    name = "bit_hysteresis"
    level = "law"
    params = (Param("beta1", "-", "amplitude of H (Eq. 3.3)", 0.0, 1.0, null=0.0),
              Param("beta2", "s/speed unit", "acceleration scale of H; bounded so that tanh(beta2 a) is not a "
                    "sign switch over the record's accelerations (100 / sd(a)); at that bound H is a switch on the sign of a, "
                    "which is flagged, not refused", 0.0, float("inf"), binding=False))
    change = "T = T_law(v) (1 + beta1 tanh(beta2 a) sign(v)) (Eqs. 3.2-3.3; 5.3 for the polynomial law)"
    signature = ("a law residual of the sign of the bit acceleration, proportional to the speed-dependent part of "
                 "the torque: torque above the law while the bit accelerates, below while it decelerates (the "
                 "upper and lower branches of Fig. 3.5)")
    reading = ("the bit-rock torque depends on where the bit is in the cycle, not only on its speed: the "
               "accelerating and decelerating branches of the rig's torque-speed loop (Figs. 3.5, 5.7)")
    defaults = {"beta1": 0.2, "beta2": 0.005}
    law_keys = ("beta1", "beta2")  # the law's own hysteresis term (Eq. 3.3): fitted in the law's family

    def describe(self, p):
        """The hysteresis term of Eqs. (3.2)-(3.3); see :meth:`Effect.describe`.

        Parameters
        ----------
        p : dict
            The effect's values (``beta1``, ``beta2``).
        """
        return f"H = {p['beta1']:.3g} tanh({p['beta2']:.3g} a) sign(v) on the speed-dependent torque"

    def count(self, p):
        """Two: beta1 and beta2 (fitted with the law, not by :meth:`free`); see
        :meth:`Effect.count`.

        Parameters
        ----------
        p : dict
            ``{"beta1", "beta2"}`` (not read).
        """
        return 2

    def declared(self, cfg):
        """``{"beta1", "beta2"}`` of the law when its beta1 > 0, else None; see
        :meth:`Effect.declared`.

        Parameters
        ----------
        cfg : dict or Configuration
            The declared engine configuration (its ``law``).
        """
        law = view(cfg).law
        return {"beta1": float(law.beta1), "beta2": float(law.beta2)} if float(law.get("beta1", 0)) > 0 else None

    def strip(self, cfg):
        """Set the law's beta1 to 0 (H = 0: the reversible law) when the law has one; see
        :meth:`Effect.strip`.

        Parameters
        ----------
        cfg : dict
            Engine configuration (its ``law``), modified in place.
        """
        if "beta1" in cfg["law"]:
            cfg["law"]["beta1"] = 0.0

    def configure(self, cfg, p, model):
        """Write beta1 and beta2 into the law; see :meth:`Effect.configure`.

        Parameters
        ----------
        cfg : dict
            Engine configuration (its ``law``), modified in place.
        p : dict
            ``{"beta1": [-], "beta2": [s per speed unit of the law]}``.
        model : LoopModel or None
            Not used.
        """
        cfg["law"]["beta1"], cfg["law"]["beta2"] = float(p["beta1"]), float(p["beta2"])

    def inject(self, truth, p):
        """Give the truth's law the hysteretic term; see :meth:`Effect.inject`.

        Parameters
        ----------
        truth : drillpy.loop.synthetic.Truth
            The synthetic truth; its law must have a hysteresis term (``beta1``), else ValueError.
        p : dict
            ``{"beta1", "beta2"}`` (defaults 0.2 and 0.005).
        """
        law = view(truth.cfg).law
        if "beta1" not in law:
            raise ValueError(f"bit_hysteresis: the law {law.type!r} has no hysteresis term")
        self.configure(truth.cfg, p, None)


EFFECT = BitHysteresis()
