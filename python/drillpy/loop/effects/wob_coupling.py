"""``wob_coupling``: the law at the measured weight on bit (axial-torsional coupling)."""
from __future__ import annotations

import numpy as np

from .base import Effect, Param
from ..view import view


class WobCoupling(Effect):
    """The law evaluated at the measured WOB, W_eff = W_0 (1 + k (W(t)/W_0 - 1)), instead of the
    constant W_0: a law-level effect (axial-torsional coupling), fitted with the law.

    Parameter ``gain`` k [-] (relative torque change per relative WOB change, -5 to 5; absent at 0;
    k = 1 is the law's own proportional W/W_ref scaling). Needs a WOB channel.
    """
    name = "wob_coupling"
    level = "law"
    params = (Param("gain", "-", "k: relative torque change per relative WOB change", -5.0, 5.0, null=0.0),)
    change = "T = T_law(v, a) (1 + k (W(t)/W_0 - 1)), the measured WOB W(t) as an input"
    signature = "a law residual proportional to T_law (W(t) - W_0) / W_0"
    reading = ("axial-torsional coupling: the WOB oscillates with the stick-slip cycle (section 5.3.2) and slowly "
               "with the electrical jack's on-off control, and the cutting torque follows it")
    needs = ("wob",)
    defaults = {"gain": 1.0}

    def law_params(self, p):
        """The gain k, fitted with the law (it sets the law's WOB input, :meth:`wob_input`); see
        :meth:`Effect.law_params`.

        Parameters
        ----------
        p : dict
            ``{"gain"}`` (not read).
        """
        return self.params

    def describe(self, p):
        """The gain k of the WOB in the law; see :meth:`Effect.describe`.

        Parameters
        ----------
        p : dict
            The effect's values (``gain``).
        """
        return f"the torque follows the WOB with gain k = {p['gain']:.3g} (k = 1: proportional)"

    def count(self, p):
        """One: the gain k (fitted with the law); see :meth:`Effect.count`.

        Parameters
        ----------
        p : dict
            ``{"gain"}`` (not read).
        """
        return 1

    def wob_input(self, p, model, w):
        """W_eff = W_0 (1 + k (w / W_0 - 1)) [N], W_0 the model's ``wob``; see
        :meth:`Effect.wob_input`.

        Parameters
        ----------
        p : dict
            ``{"gain": k [-]}``.
        model : LoopModel
            The model (its constant WOB W_0 [N]).
        w : numpy.ndarray or None
            Recorded WOB [N] per sample; None (no WOB channel) returns None.
        """
        return None if w is None else model.wob * (1.0 + p["gain"] * (np.asarray(w) / model.wob - 1.0))

    def inject(self, truth, p):
        """Set the truth's law WOB ``wob_law`` = W_0 (1 + k (W/W_0 - 1)) from its WOB series; see
        :meth:`Effect.inject`.

        Parameters
        ----------
        truth : drillpy.loop.synthetic.Truth
            The synthetic truth (its ``operation.wob_n`` W_0 [N] and WOB series [N]).
        p : dict
            ``{"gain": k [-]}`` (default 1).
        """
        w0 = float(view(truth.cfg).operation.wob_n)
        truth.wob_law = w0 * (1.0 + p["gain"] * (truth.wob / w0 - 1.0))


EFFECT = WobCoupling()
