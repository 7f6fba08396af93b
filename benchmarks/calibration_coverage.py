"""Calibration of the calibration (issue 35): on records of an independent truth, how often do the
90 % posterior intervals contain the true parameters, and the 90 % predictive intervals the
held-out statistics?

    PYTHONPATH=python python3 benchmarks/calibration_coverage.py [--truths 6] [--population 100] \
        [--simulations 2000] [--duration 24] [--first-truth 0] [--discrepancy F] [--simulator rig_model]

``--first-truth N`` skips the first N truths of the seed's sequence (to choose an option such as the
model discrepancy's factor ``--discrepancy`` on truths other than the reported ones).

The truth is ``benchmarks/whole_rig.py`` (ten lumped Kelvin-Voigt segments, an exponential Stribeck
law with static-friction ageing, an RGD-like cut under a drooping jack, a one-way load cell on a
20 Hz platform, quantized encoders, noise and glitches; it shares no code with drillpy), run
without the supply step (no stall) at ``--truths`` operating points: its open-loop motor's slope
c_m and no-load command Omega_c drawn inside the calibration's priors around the rig's (c_m
0.16-0.30 N m s/rad, Omega_c 15.5-20.5 rad/s), each with its own seed. The two parameters have the
same meaning in the truth and in drillpy's rig model (the motor: T = c_m (Omega_c - Omega)); the
others (damping, coupling, jack, law) have none in common, so they are not scored. Each record is
calibrated (:func:`drillpy.calibration.posterior.calibrate_record`) on its first half and predicts
its second half. Printed per truth: the model-averaged 90 % intervals of c_m and Omega_c with the
truth, the family probabilities, and how many predictive intervals contain the held-out
statistic; then the coverage over all truths and the histogram of the truths' ranks under the
posterior (the posterior mass below the truth: uniform when the posterior is calibrated). With a handful of truths the coverage is itself
uncertain: a binomial 90 % interval is printed beside it.

``--simulator rig_model [--reproduced-only]`` is the control: truths of drillpy's own rig model (no structural misfit),
each with its law family drawn from the calibration's prior model probabilities (equal over the
default families) and every calibrated parameter from its prior (``calibration_family_truths.py``'s
``rig_model_truth``, stepped at 5e-5 s with the platform, the 10 Hz filter and sensor noise); a draw
whose record stalls (the bit below 0.5 rad/s over more than half of it) is drawn again, counted. Every
parameter the default families share is scored. On such truths a sound ABC gives uniform ranks
(simulation-based calibration, Talts et al. 2018) when run without a model discrepancy
(``--discrepancy 0``): with one, the posterior is that of "record = model + discrepancy" and its
ranks bunch in the middle. Each truth's distance at its own parameters (one run of the calibration's
simulator at them, in the ABC's units) says whether the simulator reproduces its record at all, and
the rank histograms are split by it; ``--reproduced-only`` redraws the truths it does not reproduce, so
that the ABC's machinery alone is under test (a selection on the truth's parameters and record, not on
the posterior).
"""
from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
if any((REPO / "python" / "drillpy").glob("_core*.so")):  # in-tree build, else the installed drillpy
    sys.path.insert(0, str(REPO / "python"))
sys.path.insert(0, str(REPO / "benchmarks"))

#: whole_rig parameter -> drillpy's calibrated parameter of the same meaning.
SHARED = {"c_m": "motor_slope_nms_rad", "omega_c": "command_rad_s"}
#: Redraws of a rig-model truth whose record stalls, at most.
REDRAWS = 20


def _mixture(summary: dict, name: str) -> tuple:
    """(values, weights) of ``name`` over every family's particles, each family weighted by its
    probability (``Posterior.summary()``)."""
    vals, ws = [], []
    for fam in summary["families"]:
        part = summary["particles"][fam]
        w = np.asarray(part["weight"], float)
        if w.size == 0 or name not in part:
            continue
        vals.append(np.asarray(part[name], float))
        ws.append(w / w.sum() * summary["model_probability"][fam])
    return np.concatenate(vals), np.concatenate(ws)


def model_averaged_interval(summary: dict, name: str, level: float = 0.9) -> tuple:
    """The ``level`` interval of ``name`` under the model-averaged posterior."""
    v, w = _mixture(summary, name)
    o = np.argsort(v)
    cw = np.cumsum(w[o]) / w.sum()
    a = (1 - level) / 2
    return float(np.interp(a, cw, v[o])), float(np.interp(1 - a, cw, v[o]))


def rank(summary: dict, name: str, truth: float) -> float:
    """The truth's rank under the model-averaged posterior: the posterior mass below it (uniform over
    many truths when the posterior is calibrated: simulation-based calibration's rank statistic)."""
    v, w = _mixture(summary, name)
    return float(np.sum(w[v <= truth]) / np.sum(w))


def whole_rig_truth(i: int, rng, duration: float) -> tuple:
    """(record, {drillpy parameter: true value}, label) of truth ``i`` of the independent whole rig."""
    import whole_rig

    from drillpy.records.cleaning import clean
    from drillpy.records.io import read_record
    truth = {"c_m": float(rng.uniform(0.16, 0.30)), "omega_c": float(rng.uniform(15.5, 20.5)), "jack_steps": []}
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "truth.mat"
        whole_rig.write_mat(whole_rig.simulate(truth, duration=duration, seed=100 + i), str(path))
        rec, _ = clean(read_record(path))
    return rec, {name: truth[k] for k, name in SHARED.items()}, "", None


def rig_model_truth(i: int, rng, duration: float, reproduced_only: bool = False) -> tuple:
    """(record, {drillpy parameter: true value}, label, (family, values)) of truth ``i`` of drillpy's own
    rig model: its family from the prior model probabilities, its parameters from their priors, redrawn
    (at most :data:`REDRAWS` times) while the record stalls, and with ``reproduced_only`` while the
    calibration's simulator does not reproduce the record at the truth's parameters
    (:func:`distance_at_truth` above :data:`REPRODUCED`); the parameters every default family shares
    are scored."""
    import calibration_family_truths as cft

    from drillpy import load_config
    from drillpy.calibration.families import DEFAULT_FAMILIES
    from drillpy.calibration.priors import prior_spec
    spec = prior_spec({})
    base = load_config(preset="thesis-rig")["law"]
    shared = [p.name for p in spec.families[DEFAULT_FAMILIES[0]]
              if all(p.name in [q.name for q in spec.families[f]] for f in DEFAULT_FAMILIES)]
    for redraw in range(REDRAWS * (10 if reproduced_only else 1)):
        family = DEFAULT_FAMILIES[int(rng.integers(len(DEFAULT_FAMILIES)))]
        truth = cft.rig_model_truth(family, rng, spec)
        rec, stalled = cft.truth_record(family, truth, base, duration, seed=100 + i)
        if stalled <= 0.5 and (not reproduced_only
                               or distance_at_truth(rec, 0.5 * duration, family, truth["values"]) <= REPRODUCED):
            break
    return rec, {k: truth["values"][k] for k in shared}, f"{family}, redrawn {redraw}x;", (family, truth["values"])


def distance_at_truth(rec, t1: float, family: str, values: dict) -> float:
    """The distance (root mean square in the statistics' noise units, as the ABC's, without a
    discrepancy) between the calibration window's statistics and one run of the calibration's
    simulator at the truth's own parameters: about 1 where the simulator reproduces the truth's
    record, far more where the record's WOB trend, which the simulator takes as the jack's set
    force, is not the truth's set force (the jack's slow response: the bit lifting off or stalling)."""
    from drillpy import load_config
    from drillpy.calibration.posterior import SKIP_S, RigSimulator
    from drillpy.calibration.priors import prior_spec
    from drillpy.calibration.summaries import noise_scale, summaries
    from drillpy.records import rigsim
    part = rec.select(None, t1)
    thr = rigsim.stick_threshold(part)
    sim = RigSimulator(part, thr, prior_spec({}), load_config(preset="thesis-rig")["law"], threads=1)
    z = (sim.one(family, values) - summaries(part, thr, SKIP_S)) / noise_scale(part, thr, skip_s=SKIP_S)
    return float(np.sqrt(np.nanmean(z ** 2)))


#: A truth whose record the simulator reproduces at the truth's parameters within this distance
#: counts as reproduced (twice a right model's distance without a discrepancy, sqrt(2): the
#: record's and the run's sampling noise).
REPRODUCED = 2.0 * np.sqrt(2.0)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--truths", type=int, default=6)
    ap.add_argument("--population", type=int, default=100)
    ap.add_argument("--simulations", type=int, default=2000)
    ap.add_argument("--duration", type=float, default=24.0)
    ap.add_argument("--seed", type=int, default=35)
    ap.add_argument("--first-truth", type=int, default=0,
                    help="skip this many truths of the seed's sequence (truth i has its own seeds: 100 + i for the "
                         "record, seed + i for the calibration), so that a factor can be chosen on truths other "
                         "than the reported ones")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--dt", type=float, default=None, help="the calibration's time step [s] (default SIM_DT_S)")
    ap.add_argument("--discrepancy", type=float, default=None,
                    help="the model discrepancy's factor (drillpy calibrate --discrepancy; default drillpy's)")
    ap.add_argument("--simulator", choices=("whole_rig", "rig_model"), default="whole_rig",
                    help="the truths: the independent whole rig (default) or drillpy's own rig model (the control)")
    ap.add_argument("--reproduced-only", action="store_true",
                    help="with --simulator rig_model: redraw a truth until the calibration's simulator reproduces its "
                         "record at its own parameters (the ABC's machinery alone under test)")
    ap.add_argument("--bins", type=int, default=5, help="bins of the rank histograms")
    ap.add_argument("--figure", help="also draw the rank histograms (simulation-based calibration) into this PNG")
    a = ap.parse_args()
    from scipy import stats

    from drillpy.calibration.posterior import calibrate_record
    rng = np.random.default_rng(a.seed)
    if a.simulator == "whole_rig":
        make = whole_rig_truth
    else:
        def make(i, rng, duration):
            return rig_model_truth(i, rng, duration, a.reproduced_only)
    hits, ranks, widths, values = {}, {}, {}, {}
    reproduced = []  # per truth (rig_model): the simulator reproduces its record at its parameters
    pred_in = pred_n = 0
    h = 0.5 * a.duration
    if a.first_truth < 0:
        ap.error(f"--first-truth = {a.first_truth}: a non-negative integer")
    for i in range(a.first_truth + a.truths):
        if a.simulator == "whole_rig" and i < a.first_truth:  # its truths draw from the one sequence
            rng.uniform(size=2)
            continue
        if i < a.first_truth:
            continue
        rec, truth, label, own = make(i, rng if a.simulator == "whole_rig" else np.random.default_rng([a.seed, i]),
                                      a.duration)
        post = calibrate_record(rec, preset="thesis-rig", t0=0.0, t1=h, heldout=(h + rec.dt, a.duration),
                                population=a.population, max_simulations=a.simulations, predictive_draws=100,
                                seed=a.seed + i, threads=a.threads, discrepancy=a.discrepancy,
                                **({} if a.dt is None else {"dt_s": a.dt}))
        s = post.summary()
        line = [f"truth {i + 1}:"] + ([label] if label else [])
        if own is not None:
            d = distance_at_truth(rec, h, *own)
            reproduced.append(d <= REPRODUCED)
            part = rec.select(2.0, h)  # what the record shows after the start-up: lift-off, a runaway WOB, no cycle
            line.append(f"distance at the truth {d:.3g} ({'reproduced' if reproduced[-1] else 'NOT reproduced'}; "
                        f"record: WOB {np.mean(part.wob):.0f} N, bit-speed sd {np.std(part.bit_speed):.2f} rad/s, "
                        f"bit below 0.5 rad/s {np.mean(part.bit_speed < 0.5):.2f});")
        for name, value in truth.items():
            lo, hi = model_averaged_interval(s, name)
            ok = lo <= value <= hi
            hits[name] = hits.get(name, 0) + ok
            ranks.setdefault(name, []).append(rank(s, name, value))
            values.setdefault(name, []).append(value)
            widths.setdefault(name, []).append(hi - lo)
            line.append(f"{name} {value:.3g} in [{lo:.3g}, {hi:.3g}] {'yes' if ok else 'NO'} "
                        f"(rank {ranks[name][-1]:.2f});")
        pin = sum(v["contained"] for v in s["predictive"].values())
        pred_in += pin
        pred_n += len(s["predictive"])
        line.append("P(" + ", ".join(f"{f} {p:.2f}+-{s['model_probability_se'][f]:.2f}"
                                     for f, p in s["model_probability"].items()) + ");")
        line.append(f"predictive {pin}/{len(s['predictive'])}; {s['run']['abc_simulations']} simulations, "
                    f"eps {s['run']['eps'][-1]:.3g}")
        print(" ".join(line), flush=True)

    def binom(k, n):
        lo = stats.beta.ppf(0.05, k, n - k + 1) if k > 0 else 0.0
        hi = stats.beta.ppf(0.95, k + 1, n - k) if k < n else 1.0
        return f"{k}/{n} = {k / n:.2f} (90 % interval [{lo:.2f}, {hi:.2f}])"

    for k in ranks:
        print(f"coverage of the 90 % posterior interval, {k}: {binom(hits[k], a.truths)}")
        counts = np.histogram(ranks[k], bins=a.bins, range=(0.0, 1.0))[0]
        # uniform ranks (a calibrated posterior): chi-square over the bins, a.truths / bins expected in each
        chi2 = stats.chisquare(counts)
        print(f"  rank histogram of the truth under the posterior ({a.bins} bins of {1 / a.bins:.2g}): "
              f"{counts.tolist()}; uniform: chi-square p = {chi2.pvalue:.2g}; mean rank {np.mean(ranks[k]):.2f} (0.5 "
              "when calibrated)")
        print(f"  90 % interval width: median {np.median(widths[k]):.3g}, mean {np.mean(widths[k]):.3g}")
        if a.simulator == "rig_model":  # the truths against the prior they were drawn from (a selection shows here)
            from drillpy.calibration.families import DEFAULT_FAMILIES
            from drillpy.calibration.priors import prior_spec
            par = {q.name: q for q in prior_spec({}).families[DEFAULT_FAMILIES[0]]}[k]
            c = np.histogram([float(par.to_unit(x)) for x in values[k]], bins=a.bins, range=(0.0, 1.0))[0]
            print(f"  the truths: median {np.median(values[k]):.3g} (the prior's {float(par.from_unit(0.5)):.3g}); "
                  f"their ranks under the prior {c.tolist()}")
        if reproduced:
            for flag, label in ((True, "reproduces"), (False, "does not reproduce")):
                r = [x for x, ok in zip(ranks[k], reproduced) if ok == flag]
                if r:
                    c = np.histogram(r, bins=a.bins, range=(0.0, 1.0))[0]
                    print(f"  the truths whose record the simulator {label} at their parameters ({len(r)}): rank "
                          f"histogram {c.tolist()}, uniform: chi-square p = {stats.chisquare(c).pvalue:.2g}, "
                          f"inside the 90 % interval {sum(0.05 <= x <= 0.95 for x in r)} of {len(r)}")
    print(f"coverage of the 90 % predictive intervals of the held-out statistics: {binom(pred_in, pred_n)}")
    if a.figure:
        _rank_figure(a.figure, ranks, a.bins, a.truths, a.simulator)
        print(f"rank histograms: {a.figure}")
    return 0


def _rank_figure(path: str, ranks: dict, bins: int, n: int, simulator: str) -> None:
    """The simulation-based calibration's rank histograms, one panel per shared parameter, with the
    band a uniform histogram of ``n`` ranks stays in 90 % of the time (binomial, per bin)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from scipy import stats
    fig, axes = plt.subplots(1, len(ranks), figsize=(4.2 * len(ranks), 3.2), layout="constrained")
    lo, hi = stats.binom.ppf([0.05, 0.95], n, 1.0 / bins)
    for ax, (k, r) in zip(np.atleast_1d(axes), ranks.items()):
        ax.axhspan(lo, hi, color="0.88", label="90 % band of a uniform rank")
        ax.hist(r, bins=bins, range=(0.0, 1.0), color="C0", edgecolor="white")
        ax.set(xlabel=f"rank of the true {k} under the posterior", ylabel="truths", xlim=(0, 1))
        ax.legend(fontsize=8, loc="upper center")
    fig.suptitle(f"Simulation-based calibration over {n} " + ("independent truths (benchmarks/whole_rig.py)"
                 if simulator == "whole_rig" else "truths of drillpy's own rig model"))
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())
