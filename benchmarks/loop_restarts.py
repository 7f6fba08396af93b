"""Why the loop's least squares are restarted (docs/loop.md, "Fitted to convergence").

On the independent Tucker-Wang rig's static-friction record (``benchmarks/independent_rig.py``,
T_s 4.5 N m, seed 15, no drillpy code), the ``static_friction`` candidate of the first round is
fitted from the law refitted with the measured break-away torque, once without restarts
(``fitting.RESTARTS = 0``) and once with them; each fit is then repeated from its own result. The
script prints every ``scipy.optimize.least_squares`` call's exit (status 3: the step tolerance),
evaluations used and gradient norm, and the calibration error E_cal once and again:

    PYTHONPATH=python python3 benchmarks/loop_restarts.py [--duration 40]
"""
from __future__ import annotations

import argparse
import os
import sys
import tempfile

from scipy import optimize

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import independent_rig as rig  # noqa: E402

import drillpy  # noqa: E402
from drillpy import loop as L  # noqa: E402
from drillpy.loop import fitting as F  # noqa: E402
from drillpy.loop.run import _without, analysis_config  # noqa: E402
from drillpy.model.config import normalize  # noqa: E402

_least_squares = optimize.least_squares
CALLS = []


def _logged(*a, **k):
    r = _least_squares(*a, **k)
    CALLS.append((r.status, r.nfev, k.get("max_nfev"), float(r.optimality)))
    return r


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=40.0, help="record length [s] (40)")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "static.csv")
        rig.write_csv(rig.simulate(rig.effect_params(["static_friction"]), seed=15, duration_s=a.duration), path,
                      ["static friction"])
        cfg = normalize(drillpy.load_config(preset="thesis-rig"))
        opt = L.LoopOptions(rate_hz=250, gj_tolerance=0.0)  # the GJ held: the restarts alone
        data = L.prepare(path, cfg, opt)
    names = [F.LAW, F.DAMPING, "static_friction"]
    default = F.RESTARTS
    for restarts in (0, default):  # the whole calibration, baseline included, with and without restarts
        F.RESTARTS = restarts
        optimize.least_squares = F.optimize.least_squares = _least_squares
        m, _ = F.calibrate(analysis_config(cfg, data.dt, opt.dt_s), data, opt)
        m, _ = F.null_candidate(_without(m, "bit_hysteresis"), data, opt)
        c = m.copy()
        c.effects["static_friction"] = dict(F.CATALOGUE["static_friction"].direct(c, data)["params"])
        start = F.fit_law(c, data)
        optimize.least_squares = F.optimize.least_squares = _logged
        CALLS.clear()
        once, _ = F.fit_dynamic(start, data, names, opt)
        n_once = len(CALLS)
        again, _ = F.fit_dynamic(once, data, names, opt)
        print(f"RESTARTS = {restarts}: E_cal of the null candidate {F.e_train(m, data, 0):.4f}; the candidate from its "
              f"start {F.e_train(start, data, 0):.4f}, fitted {F.e_train(once, data, 0):.4f}, fitted again from there "
              f"{F.e_train(again, data, 0):.4f}")
        for i, (status, nfev, budget, g) in enumerate(CALLS):
            print(f"   {'first' if i < n_once else 'again'} fit, call {i + 1}: status {status}, {nfev} of {budget} "
                  f"evaluations, gradient norm {g:.3g}")
    F.RESTARTS = default


if __name__ == "__main__":
    main()
