"""The damping hold of ``drillpy loop``: when the record stick-slips and the calibrated model does
not, the damping ratios are set by the measured limit cycle instead of by the short horizons
(docs/loop.md, "Calibration")."""
from __future__ import annotations

import math

import numpy as np

from .data import LoopData
from .fitting import refit
from .longrun import long_run
from .model import LoopModel
from .options import LoopOptions
from .side_by_side import task_map
from .view import view

#: Rounds of the damping hold: search, refit, and again while the refit model has left the cycle.
HOLD_ROUNDS = 3


def hold_damping(model: LoopModel, lr: dict, data: LoopData, opt: LoopOptions, log) -> tuple:
    """When the record stick-slips and the calibrated model does not, the short horizons have
    over-damped it (a prediction that cannot follow the phase scores better when damped towards the
    mean): the damping ratios are scaled down to the value whose long run matches the record's SS and
    stick fraction best (a geometric grid down to a tenth of it), then held while the rest is
    recalibrated. The best match lies near the edge of the stick-slip region, where the refit's
    small changes of the other parameters can take the model off the cycle: while the refit model
    no longer stick-slips, the search is repeated from it (grid 1.6 to 0.4), at most
    :data:`HOLD_ROUNDS` times.

    Parameters
    ----------
    model : LoopModel
        The calibrated model (its ``damping_held``: a re-hold after a step searches around it).
    lr : dict
        Its long run (:func:`drillpy.loop.longrun.long_run`).
    data : LoopData
        The record on the analysis grid.
    opt : LoopOptions
        The loop's options (the refit's).
    log : callable
        Called with the note.

    Returns
    -------
    tuple
        (model, long run, note), or the inputs with note None when nothing is held.
    """
    retune = model.damping_held
    first_hold = not retune
    if not lr or "error" in lr or not lr["stick_slips"]["measured"] or model.damping_ratios is None \
            or (lr["stick_slips"]["model"] and not retune):
        return model, lr, None
    meas = lr["measured"]
    z_first = model.damping_ratios

    def mismatch(r):
        if "error" in r:
            return math.inf
        m = r["model"]
        return abs((m["ss"] or 0.0) - meas["ss"]) / meas["ss"] + abs(
            (m["stick_fraction"] or 0.0) - meas["stick_fraction"]) / max(meas["stick_fraction"], 0.01)

    held, new_lr = None, lr
    for _ in range(HOLD_ROUNDS):
        z0 = model.damping_ratios
        factors = np.geomspace(1.6, 0.4, 13) if retune else np.geomspace(1.0, 0.1, 13)[1:]
        best = (mismatch(new_lr) if retune else math.inf, 1.0, new_lr)
        runs = task_map(lambda f, _: long_run(_scaled(model, z0, float(f)), data), factors, opt)  # side by side
        for f, r in zip(factors, runs):
            best = min(best, (mismatch(r), float(f), r), key=lambda b: b[0])
        f = best[1]
        if retune and f == 1.0:
            break
        held = _scaled(model, z0, f)
        held.damping_held = True
        held, _ = refit(held, data, opt)
        new_lr = long_run(held, data)
        model, retune = held, True
        if "error" in new_lr or new_lr["stick_slips"]["model"]:
            break
    if held is None:
        return model, lr, None
    z0, z = [round(x, 4) for x in z_first], [round(x, 4) for x in held.damping_ratios]
    if first_hold:
        note = (f"the short-horizon calibration gives damping ratios {z0}, with which the model does not "
                f"stick-slip while the record does (SS {lr['model']['ss']:.3f} against {meas['ss']:.3f}); the "
                f"ratios are held at {z}, the value whose long run matches the record's SS and stick fraction "
                "best, and the rest is recalibrated")
    else:
        note = (f"damping ratios re-held at {z} (from {z0}): the value whose long run matches the record's SS "
                "and stick fraction best with this step's model")
    log(note)
    return held, new_lr, note


def _scaled(model: LoopModel, z0: list, f: float) -> LoopModel:
    """A copy of ``model`` with the damping ratios ``z0`` scaled by ``f``."""
    m = model.copy()
    m.cfg = view(m.cfg).replace({"damping.ratios": [z * f for z in z0]}).to_dict()
    return m
