"""``wob_coupling``: the law at the measured weight on bit (axial-torsional coupling)."""
from __future__ import annotations

import numpy as np

from .base import Effect, Param


class WobCoupling(Effect):
    name = "wob_coupling"
    level = "law"
    params = (Param("gain", "-", "k: relative torque change per relative WOB change", -5.0, 5.0, null=0.0),)
    change = "T = T_law(v, a) (1 + k (W(t)/W_0 - 1)), the measured WOB W(t) as an input"
    signature = "a law residual proportional to T_law (W(t) - W_0) / W_0"
    reading = ("axial-torsional coupling: the WOB oscillates with the stick-slip cycle (section 5.3.2) and slowly "
               "with the electrical jack's on-off control, and the cutting torque follows it")
    needs = ("wob",)
    defaults = {"gain": 1.0}

    def count(self, p):
        return 1

    def wob_input(self, p, model, w):
        return None if w is None else model.wob * (1.0 + p["gain"] * (np.asarray(w) / model.wob - 1.0))

    def inject(self, truth, p):
        w0 = float(truth.cfg["operation"]["wob_n"])
        truth.wob_law = w0 * (1.0 + p["gain"] * (truth.wob / w0 - 1.0))


EFFECT = WobCoupling()
