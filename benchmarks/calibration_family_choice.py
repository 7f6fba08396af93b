"""Does the calibration's model choice pick the truth's law family (issue 35)?

    PYTHONPATH=python python3 benchmarks/calibration_family_choice.py --truth polynomial \
        --families polynomial,tucker_wang [--population 300] [--simulations 10000] [--seed 1] [--threads 2] \
        [--family-share 0.1]

A record of drillpy's own rig model with a known law (the truth of ``tests/python/test_calibration.py``:
``--truth polynomial`` is Eq. 5.1 with a static torque of 3 N m, stick-slip with SS 0.53;
``--truth tucker_wang`` is Eq. 3.1 with c0 1.3 N m, h 1, peak at 0.5 rad/s, smooth drilling),
stepped at 5e-5 s, through the platform and the 10 Hz filter, with sensor noise, ``--duration``
seconds long, is calibrated (:func:`drillpy.calibration.posterior.calibrate_record`) with the
families ``--families`` and the share ``--family-share`` of the model proposals spread evenly over them
(``calibration.family_share``). Printed: the families' probabilities with their Monte Carlo error, the
model choice (:func:`drillpy.calibration.abcsmc.model_choice`) and every generation's tolerance,
probabilities, errors, ESS and each family's ESS and proposals.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
if any((REPO / "python" / "drillpy").glob("_core*.so")):  # in-tree build, else the installed drillpy
    sys.path.insert(0, str(REPO / "python"))
sys.path.insert(0, str(REPO / "tests" / "python"))


def main(argv=None) -> int:
    """Run one comparison and print it (module docstring).

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.

    Returns
    -------
    int
        Exit status 0.
    """
    from test_calibration import TRUTH, TW_TRUTH, _config, _truth_record

    from drillpy.calibration.families import FAMILIES
    from drillpy.calibration.posterior import calibrate_record

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--truth", choices=("polynomial", "tucker_wang"), default="polynomial")
    ap.add_argument("--families", default="polynomial,tucker_wang", help="comma-separated, of " + ", ".join(FAMILIES))
    ap.add_argument("--duration", type=float, default=8.0, help="record length [s]")
    ap.add_argument("--population", type=int, default=300)
    ap.add_argument("--simulations", type=int, default=10000)
    ap.add_argument("--generations", type=int, default=40)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--family-share", type=float, default=None,
                    help="calibration.family_share (default drillpy's: drillpy.calibration.priors.DEFAULT_FAMILY_SHARE)")
    a = ap.parse_args(argv)
    fams = a.families.split(",")
    rec = _truth_record(duration=a.duration, family=a.truth, truth=TRUTH if a.truth == "polynomial" else TW_TRUTH)
    start = time.perf_counter()
    section = {"families": fams} if a.family_share is None else {"families": fams, "family_share": a.family_share}
    post = calibrate_record(rec, config=_config(**section), population=a.population,
                            max_simulations=a.simulations, max_generations=a.generations, predictive_draws=4,
                            seed=a.seed, threads=a.threads)
    print(f"truth {a.truth}: {post.run['abc_simulations']} simulations in {time.perf_counter() - start:.1f} s, "
          f"final eps {post.run['eps'][-1]:.3g} ({post.run['stopped']})")
    last = post.run["history"][-1]
    for f, ess in zip(fams, last["model_ess"]):
        print(f"  P({f}) = {post.model_probability[f]:.3f} +- {post.model_probability_se[f]:.3f}, ESS {ess:.1f}")
    c = post.model_choice
    print(f"model choice: {c['family'] or 'cannot tell'} ({c['reason']}; ESS {c['ess']:.0f})")
    for h in post.run["history"]:
        print(f"  generation {h['generation']}: eps {h['eps']:.3g}, P "
              + ", ".join(f"{p:.3f}+-{s:.3f}" for p, s in zip(h["model_probabilities"], h["model_probability_se"]))
              + f", ESS {h['ess']:.0f} (per family " + ", ".join(f"{e:.1f}" for e in h["model_ess"])
              + "; proposals " + ", ".join(str(n) for n in h["model_proposals"]) + ")")
    return 0


if __name__ == "__main__":
    sys.exit(main())
