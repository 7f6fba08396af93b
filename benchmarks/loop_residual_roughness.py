"""How smoothly the loop's calibration error moves with the parameters, on a validation case and a
scheme: the rough landscape that stops a least-squares fit short (docs/loop.md, "The exact modal
scheme").

    PYTHONPATH=python python3 benchmarks/loop_residual_roughness.py [--seed 18] [--scheme exact_modal]

Runs the loop's baseline calibration on the case's record (``loop_validation.py``'s case of that seed,
kind ``single``), adds the case's effect as the loop's candidate starts it (its direct measurement,
held, and the law refitted on the law residual with it: ``fitting.fit_law``), and prints the
calibration error ``e_train`` at relative steps of 0.1 % (-4 .. +4) of every free parameter (the law's
coefficients, the damping ratio, the GJ factor). A smooth row changes by similar amounts from step to
step; a rough one jumps by far more than its neighbours.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import loop_validation as lv  # noqa: E402
from drillpy.loop import LoopOptions, run_loop  # noqa: E402
from drillpy.loop import fitting as F  # noqa: E402
from drillpy.loop.effects import CATALOGUE  # noqa: E402
from drillpy.loop.model import residual_vector  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seed", type=int, default=18)
    ap.add_argument("--scheme", choices=("modified_euler", "exact_modal"), default="exact_modal")
    a = ap.parse_args(argv)
    case = next(c for c in lv.CASES if c.seed == a.seed and c.kind == "single")
    (name,) = case.effects
    rec = lv.synthetic_record(case.effects, duration_s=lv.DURATION_S, seed=case.seed, fs_hz=lv.RATE_HZ,
                              noise=case.noise)
    opt = LoopOptions(rate_hz=lv.RATE_HZ, dt_s=lv.LOOP_DT_S, scheme=a.scheme, effects=(name,), max_steps=0,
                      long_run=False, discovery=False)
    res = run_loop(rec, lv.declared_config(), opt, log=lambda *x: None)
    data, m = res.data, res.baseline.model.copy()
    d = CATALOGUE[name].direct(m, data)
    m.effects[name] = dict(d["params"]) if d and d["significant"] else dict(CATALOGUE[name].defaults)
    s = F.fit_law(m, data) if CATALOGUE[name].reshapes_law else m
    x0, _, _, where = F._pack(s, data, [F.LAW, F.DAMPING, F.GJ] + list(s.effects))
    print(f"seed {a.seed} ({name}), {a.scheme} at {lv.LOOP_DT_S:g} s: e_train at 0.1 % steps of each parameter")
    for i, w in enumerate(where):
        es = []
        for k in range(-4, 5):
            x = x0.copy()
            x[i] = x0[i] * (1 + k * 1e-3) if x0[i] != 0 else k * 1e-3
            r = residual_vector(F._unpack(s, x, where, data.law_knot, trial=True), data, opt.threads, check=False)
            es.append(float(np.sqrt(r @ r)))
        steps = np.abs(np.diff(es))
        print(f"  {w[0]:>8} {str(w[1]):<10} " + " ".join(f"{e:.5f}" for e in es)
              + f"   largest step / median step {steps.max() / max(np.median(steps), 1e-12):.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
