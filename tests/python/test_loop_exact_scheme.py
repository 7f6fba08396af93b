"""The loop's short horizons on the exact modal scheme under a static torque (issue 33): a bit that
comes to rest stays at rest, and the predictions move continuously with the parameters."""
from __future__ import annotations

import numpy as np

from drillpy.loop import LoopOptions
from drillpy.loop.data import prepare
from drillpy.loop.model import LoopModel, predict
from drillpy.loop.synthetic import declared_config, synthetic_record
from drillpy.model.config import normalize

#: The law the loop's static-friction candidate starts from on validation case 18 (its law fitted
#: on the law residual with the measured 4.48 N m break-away torque): 4.48 N m at rest, falling to
#: the sliding 2.24 N m by 0.1 rad/s.
LAW = {"type": "polynomial", "speed_unit": "rpm", "wob_ref_n": 557.1, "a0": 0.0, "a1": 2.056553621255884,
       "a2": 1.6452429144202454, "a3": 1.0282889703424637e-09, "a4": 1.6126325236399472,
       "a5": 0.008593602660676639, "a6": -0.00011112954498467532, "a7": 2.1963481878587364e-07,
       "ref_speed": 80.00000088683169, "gain": 1.36}


def test_a_landing_bit_stays_at_rest_and_the_predictions_are_continuous_in_the_damping():
    """The bit's equation solved at the law's jump at v = 0 gives a speed known only to the
    solvers' tolerance (1e-12 (1 + |Omega| + |w|)); one at 1.05e-11 rad/s counted as moving broke
    the bit away backwards on the next step, and a 0.1 % change of the damping moved a horizon's
    bit speed by 0.56 rad/s (the modified Euler's: 0.010). Every 0.1 % step of the damping ratio
    now moves every horizon's bit speed by less than 0.05 rad/s and its torque by less than 0.5 N m,
    and no predicted speed is negative."""
    rec = synthetic_record({"static_friction": {}}, duration_s=40.0, seed=18, fs_hz=500.0)
    data = prepare(rec, normalize(declared_config()), LoopOptions(rate_hz=500.0, dt_s=2e-4))
    preds = []
    for zeta in 0.07018426 * (1.0 + 1e-3 * np.arange(-4, 5)):
        cfg = normalize(declared_config())
        cfg["simulation"].update(scheme="exact_modal", dt_s=2e-4)
        cfg["damping"]["ratios"] = [float(zeta)]
        m = LoopModel(cfg, dict(LAW), 8.472049035536726, 558.2075933003468,
                      {"static_friction": {"static_torque_nm": 4.48070889569666, "source": "stick phases"}},
                      gj_factor=1.0165682163349534)
        v, T = predict(m, data)
        preds.append((np.asarray(v), np.asarray(T)))
    for v, _ in preds:
        assert v.min() > -1e-6
    jumps = [float(np.abs(b[0] - a[0]).max()) for a, b in zip(preds, preds[1:])]
    assert max(jumps) < 0.05, jumps
    # the torque reported at a landing sample is the step's mean, as at every other sample: 0.152 N m
    # per step of the damping on every step (with the landing step's mean against the sliding steps'
    # end torques, one step jumped by 1.056 N m where a landing crossed a sample)
    torque_jumps = [float(np.abs(b[1] - a[1]).max()) for a, b in zip(preds, preds[1:])]
    assert max(torque_jumps) < 0.5, torque_jumps
