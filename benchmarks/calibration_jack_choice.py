"""Does the model choice see the jack (issue 35, item 2)? The rig model with and without its jack on a
record of a jack truth, with the WOB's statistics of choice.

    nice -n 10 env PYTHONPATH=python python3 benchmarks/calibration_jack_choice.py --statistics default \
        --population 100 --simulations 3000

The truth: drillpy's rig model with Eq. (5.1) at the test's truth with a command of 20 rad/s and a damping
ratio of 0.02, its jack at 180 N/rad (``tests/python/test_calibration_statistics.py``'s ``JACK_TRUTH``:
stick-slip at 2.86 Hz), stepped at 5e-5 s, with the platform, the 10 Hz filter and sensor noise, 10 s.
Two models are compared by :func:`drillpy.calibration.abcsmc.run` (equal prior probabilities): Eq.
(5.1) with every rig parameter calibrated, ``polynomial``, and the same with the jack's gain held at 0
(the WOB is then the record's slow trend, the model's input, alone), ``polynomial without jack``
(``calibration.families``' models over the rig's elements, :mod:`drillpy.calibration.elements`): the
proposals, seeds and populations of a prototype's run of that comparison (same seed, same numbers).

``--statistics``: ``default`` (the 13 of :data:`drillpy.calibration.summaries.NAMES`, with the WOB's
standard deviation), ``added`` (those and the WOB above its trend,
:func:`drillpy.calibration.summaries.wob_above_trend_std`), ``replaced`` (the WOB above its trend instead
of the WOB's standard deviation). Printed: every generation's tolerance and P(with the jack), the final
probabilities with their Monte Carlo errors and :func:`drillpy.calibration.abcsmc.model_choice`'s answer.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
if any((REPO / "python" / "drillpy").glob("_core*.so")):  # in-tree build, else the installed drillpy
    sys.path.insert(0, str(REPO / "python"))
sys.path.insert(0, str(REPO / "tests" / "python"))

#: The two models of the comparison (``calibration.families``, :mod:`drillpy.calibration.elements`).
MODELS = ["polynomial", "polynomial without jack"]


def statistic_set(which: str) -> tuple:
    """The statistics of the distance for ``--statistics``."""
    from drillpy.calibration.summaries import NAMES
    if which == "default":
        return NAMES
    if which == "added":
        return (*NAMES, "wob_above_trend_std")
    return tuple("wob_above_trend_std" if n == "wob_std" else n for n in NAMES)


def main(argv=None) -> int:
    """Run the comparison and print it (module docstring).

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.

    Returns
    -------
    int
        Exit status 0.
    """
    from test_calibration_statistics import JACK_TRUTH
    from test_calibration import _truth_record

    from drillpy.calibration import abcsmc
    from drillpy.calibration.posterior import SKIP_S, RigSimulator
    from drillpy.calibration.priors import prior_spec
    from drillpy.calibration.summaries import noise_scale, summaries
    from drillpy.model.config import load_config
    from drillpy.records import rigsim
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--statistics", choices=("default", "added", "replaced"), default="default")
    ap.add_argument("--population", type=int, default=100)
    ap.add_argument("--simulations", type=int, default=3000)
    ap.add_argument("--generations", type=int, default=12, help="at most (calibrate_record's default: 12)")
    ap.add_argument("--seed", type=int, default=3)
    ap.add_argument("--discrepancy", type=float, default=0.0, help="the model discrepancy's factor (0: none, as the "
                                                                   "prototype's run)")
    ap.add_argument("--family-share", type=float, default=0.1, help="calibration.family_share (default 0.1)")
    ap.add_argument("--threads", type=int, default=1)
    a = ap.parse_args(argv)
    names = statistic_set(a.statistics)
    rec = _truth_record(duration=10.0, truth=JACK_TRUTH)
    thr = rigsim.stick_threshold(rec)
    observed = summaries(rec, thr, SKIP_S, names)
    scale = noise_scale(rec, thr, skip_s=SKIP_S, names=names)
    spec = prior_spec({"families": MODELS, "statistics": list(names)})
    sim = RigSimulator(rec, thr, spec, load_config(preset="thesis-rig")["law"], threads=a.threads)
    start = time.perf_counter()
    res = abcsmc.run(sim, [len(spec.families[m]) for m in MODELS], observed, scale, population=a.population,
                     max_simulations=a.simulations, max_generations=a.generations, seed=a.seed, family_share=a.family_share,
                     discrepancy=a.discrepancy * scale)
    print(f"statistics {a.statistics} ({len(names)}): {res.simulations} simulations in "
          f"{time.perf_counter() - start:.0f} s, stopped: {res.stopped}")
    for h in res.history:
        print(f"  generation {h['generation']}: eps {h['eps']:.3g}, P(polynomial, with the jack) {h['model_probabilities'][0]:.3f} "
              f"+- {h['model_probability_se'][0]:.3f}, ESS {h['ess']:.0f}")
    p, se = res.posterior.model_probabilities(2)
    for name, pp, ss in zip(MODELS, p, se):
        print(f"P({name}) = {pp:.3f} +- {ss:.3f}")
    c = abcsmc.model_choice(res.posterior, MODELS, res.history, max_eps=abcsmc.choice_tolerance(a.discrepancy))
    bf = c["bayes_factor"]
    print(f"model choice: {c['family'] or 'cannot tell'} ({c['reason']}; Bayes factor "
          f"{'inf' if bf is None else f'{bf:.3g}'}, ESS {c['ess']:.0f}; 95 % bounds of models without particles "
          f"{ {k: round(v, 3) for k, v in c['upper95'].items()} })")
    # the model's WOB input: the record's slow WOB, which carries the slow part of the truth's jack response
    trend, after = rigsim.wob_trend(rec, 557.1), rec.time_s >= rec.time_s[0] + SKIP_S
    print(f"the model's WOB input (the record's WOB below {rigsim.WOB_TREND_HZ:g} Hz): sd {trend[after].std():.1f} N after "
          f"the start-up, where the truth's own input had {(25.0 * np.sin(0.2 * np.pi * rec.time_s[after])).std():.1f} N")
    # the two models at the truth's parameters, in the distance's units (each statistic's z)
    for m in MODELS:
        z = (sim.one(m, JACK_TRUTH) - observed) / scale
        print(f"at the truth's parameters, {m}: distance {np.sqrt(np.mean(z ** 2)):.2f}; "
              + ", ".join(f"{n} {v:+.2f}" for n, v in zip(names, z) if "wob" in n or abs(v) > 2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
