"""Is a coarser time step good enough for the calibration's rig simulations (issue 35)?

    PYTHONPATH=python python3 benchmarks/calibration_timestep.py [--draws 300] [--steps 1e-4,2e-4,2.5e-4,5e-4]
    PYTHONPATH=python python3 benchmarks/calibration_timestep.py --steps 2.5e-4,5e-4@exact_modal,1e-3@exact_modal
    PYTHONPATH=python python3 benchmarks/calibration_timestep.py --profile 40

``--profile N`` instead runs N prior draws at the calibration's step under ``cProfile`` and prints
where a run's time goes (the engine, the configuration, the filters, the statistics).

Draws parameter sets from the calibration's priors (both law families, alternately), simulates the
rig model over sample 175's 0-20 s window at each step and at a 5e-5 s reference (what
:class:`drillpy.calibration.posterior.RigSimulator` does: the platform, the 10 Hz filter, the
statistics of :mod:`drillpy.calibration.summaries` after 2 s), and prints, per step, the distance
of its statistics from the reference's in the ABC's own units (each statistic over its sampling
uncertainty on the record, the spread between the window's blocks: the distance eps = 1 is "as close
as the record's own blocks are to each other"): the median, the 90th percentile and the share of
draws within 0.1 and within 1 unit, with the time per run (engine, platform, filters, statistics; one
thread). Twice: over all the draws, and over those whose reference lies within ``--near`` units of
the record's own statistics (the draws the ABC can accept: its first tolerance on sample 175 is
about 23). A step is good enough when its distances are as small as those of the step it replaces
(both are measured against the same reference). The prior's tail holds runs that stall for good
(the motor at its 8 N m limit: stick fraction 1, far from the record) and runs at the edge of a
stall, where any change of step can tip the run. A step written ``DT@exact_modal`` runs the exact
modal scheme (docs/numerics.md) at DT instead of the modified Euler; the reference is always the
modified Euler at ``--reference``.
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
SAMPLE175 = REPO.parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--record", default=str(SAMPLE175))
    ap.add_argument("--draws", type=int, default=300)
    ap.add_argument("--profile", type=int, default=0)
    ap.add_argument("--steps", default="1e-4,2e-4,2.5e-4,5e-4")
    ap.add_argument("--reference", type=float, default=5e-5)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--near", type=float, default=20.0)
    a = ap.parse_args()
    from drillpy.calibration.abcsmc import distance
    from drillpy.calibration.posterior import SKIP_S, RigSimulator, load_window
    from drillpy.calibration.priors import prior_spec
    from drillpy.calibration.summaries import NAMES, noise_scale, summaries
    from drillpy.model.config import load_config
    from drillpy.records import rigsim
    rec = load_window(a.record, 0.0, 20.0)
    thr = rigsim.stick_threshold(rec)
    spec = prior_spec({})
    scale = noise_scale(rec, thr, skip_s=SKIP_S)
    observed = summaries(rec, thr, SKIP_S)
    base = load_config(preset="thesis-rig")["law"]
    if a.profile:
        return _profile(RigSimulator(rec, thr, spec, base, threads=1), a.profile, a.seed)
    steps = [a.reference] + [s.strip() for s in a.steps.split(",")]

    def simulator(step):
        dt, _, scheme = str(step).partition("@")
        return RigSimulator(rec, thr, spec, base, threads=1, dt_s=float(dt), scheme=scheme or "modified_euler")

    sims = {dt: simulator(dt) for dt in steps}
    rng = np.random.default_rng(a.seed)
    fams = list(spec.families)
    dist = {dt: [] for dt in steps[1:]}
    worst = {dt: np.zeros(len(NAMES)) for dt in steps[1:]}
    near = []
    cost = dict.fromkeys(steps, 0.0)
    for i in range(a.draws):
        fam = fams[i % len(fams)]
        v = sims[a.reference].values(fam, rng.random(len(spec.families[fam])))
        ref = None
        for dt in steps:
            t = time.perf_counter()
            s = sims[dt].one(fam, v)
            cost[dt] += time.perf_counter() - t
            if ref is None:
                ref = s
                near.append(bool(distance(ref, observed, scale)[0] <= a.near))
                continue
            d = (s - ref) / scale
            dist[dt].append(float(np.sqrt(np.mean(d ** 2))))
            worst[dt] = np.where(near[-1], np.fmax(worst[dt], np.abs(d)), worst[dt])
    near = np.array(near)
    print(f"{a.draws} prior draws on {Path(a.record).name} 0-20 s ({near.sum()} within {a.near:g} units of the record), "
          f"distance of the statistics from a {a.reference:g} s step in noise units (RMS over the statistics):")
    print("| step [s] | time per run [ms] | draws | median | p90 | max | within 0.1 | within 1 | failed |"
          " worst statistic near the record (max) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    print(f"| {a.reference:g} | {1e3 * cost[a.reference] / a.draws:.1f} | reference | | | | | | | |")
    for dt in steps[1:]:
        d = np.array(dist[dt])
        k = int(np.argmax(worst[dt]))
        for label, sel in (("all", np.ones(d.size, bool)), ("near", near)):
            ok = d[sel & np.isfinite(d)]
            if ok.size == 0:
                continue
            tail = f"{NAMES[k]} ({worst[dt][k]:.2f})" if label == "near" else ""
            print(f"| {dt} | {1e3 * cost[dt] / a.draws:.1f} | {label} ({ok.size}) | {np.median(ok):.3f} | "
                  f"{np.percentile(ok, 90):.2f} | {ok.max():.2f} | {np.mean(ok <= 0.1):.2f} | {np.mean(ok <= 1.0):.2f} | "
                  f"{int((sel & ~np.isfinite(d)).sum())} | {tail} |")
    return 0


def _profile(sim, n: int, seed: int) -> int:
    import cProfile
    import pstats
    rng = np.random.default_rng(seed)
    fam = sim.families[0]
    vals = [sim.values(fam, rng.random(len(sim.spec.families[fam]))) for _ in range(n)]
    sim.one(fam, vals[0])  # the caches (filter designs, the WOB trend) filled
    t = time.perf_counter()
    for v in vals:
        sim.one(fam, v)
    wall = time.perf_counter() - t
    print(f"{n} runs of {fam} at dt = {sim.dt_s:g} s, one thread: {1e3 * wall / n:.1f} ms per run without the profiler")
    pr = cProfile.Profile()
    pr.enable()
    for v in vals:
        sim.one(fam, v)
    pr.disable()
    pstats.Stats(pr).sort_stats("cumulative").print_stats(18)
    return 0


if __name__ == "__main__":
    sys.exit(main())
