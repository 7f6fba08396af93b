"""The law's low-speed knot (``LoopOptions.law_knot``, docs/loop.md "Calibration"): the law residual
of the loop's law fit on a record of the independent rig (``benchmarks/independent_rig.py``: a
Tucker-Wang law rising after the break-away, a true stick, no drillpy code) with the thesis's tie of
Eq. (5.1) and with the knot calibrated.

    PYTHONPATH=python python3 benchmarks/loop_law_knot.py [--seed 1] [--effect NAME ...]

Prints, per setting, the law residual's RMSE [N m] on the calibration part's slip samples and the
knot v_k [RPM] where the low-speed piece meets the cubic (the record's torque noise is 0.02 N m).
"""
from __future__ import annotations

import argparse
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import independent_rig as rig  # noqa: E402

import drillpy  # noqa: E402
from drillpy import loop as L  # noqa: E402
from drillpy.loop.effects import stripped  # noqa: E402
from drillpy.loop.fitting import fit_law  # noqa: E402
from drillpy.loop.model import LoopModel, law_channels, law_torque  # noqa: E402
from drillpy.loop.run import analysis_config  # noqa: E402
from drillpy.model.config import normalize  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--effect", action="append", default=[], help="inject an effect of independent_rig.py")
    a = ap.parse_args(argv)
    path = os.path.join(tempfile.mkdtemp(), "record.csv")
    rig.write_csv(rig.simulate(rig.effect_params(a.effect), seed=a.seed), path, [f"seed {a.seed}"])
    cfg = normalize(drillpy.load_config(preset="thesis-rig"))
    for knot in (False, True):
        opt = L.LoopOptions(rate_hz=250, law_knot=knot)
        data = L.prepare(path, cfg, opt)
        base = stripped(analysis_config(cfg, data.dt, opt.dt_s))
        m = fit_law(LoopModel(base, dict(base["law"]), float(base["operation"]["top_speed_rad_s"]),
                              float(base["operation"]["wob_n"]), {}), data)
        chs = law_channels(m, data)
        r = chs["T"][data.law_train] - law_torque(m, chs, data.law_train)
        print(f"{'knot calibrated' if knot else 'thesis tie     '}: law residual RMSE {np.sqrt(np.mean(r ** 2)):.4f} N m, "
              f"knot {0.05 * m.law['ref_speed']:.1f} RPM")
    return 0


if __name__ == "__main__":
    sys.exit(main())
