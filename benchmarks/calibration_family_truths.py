"""Does the model choice pick the truth's law family over many truths (issue 35, item 4)?

    nice -n 10 env PYTHONPATH=python python3 benchmarks/calibration_family_truths.py --per-family 3 --threads 1 \
        [--family-share 0.1] [--simulator rig_model [--reproduced-only]]

Truths: the independent whole-rig simulator (``benchmarks/whole_rig.py``: ten lumped Kelvin-Voigt
segments, a one-way motor hold, an RGD-like cut under a drooping jack, a one-way load cell, quantized
encoders, noise, glitches; it shares no code with drillpy) driven by a law of each family of
:data:`drillpy.calibration.families.FAMILIES` (``whole_rig``'s ``law`` option: the thesis's Eqs. 5.1,
5.3, 3.1, 3.2-3.3, evaluated by its own code). Truth j of family f has its own generator
(``--seed``, f's index, j): its law parameters drawn from the calibration's priors of that family
(:func:`drillpy.calibration.priors.prior_spec`; the law's coefficients built by
:func:`drillpy.calibration.families.family_law`), its motor's c_m and Omega_c from 0.16-0.30 N m s/rad
and 15.5-20.5 rad/s (as ``calibration_coverage.py``), no supply step. A draw whose record stalls (the
bit below 0.5 rad/s over more than half of it) is drawn again (counted): a stalled record carries no
cycle and the calibration is for a rig that drills.

Each record (``--duration`` s) is calibrated twice with the four families
(:func:`drillpy.calibration.posterior.calibrate_record`, the default model discrepancy, the share
``--family-share`` of the model proposals spread evenly over the families):

* at a **modest budget** (``--population``, ``--simulations``): the run under test;
* at a **larger budget** (``--large-population``, ``--large-simulations``, another seed): the
  reference for whether the data *can* tell the families apart: a truth is "distinguishable" when
  the larger run names a family (:func:`drillpy.calibration.abcsmc.model_choice`), else "not".

Printed per truth: its parameters, each run's family probabilities with their Monte Carlo standard
errors and its choice; then the confusion tables (truth family x {picked family, cannot tell}) of
the modest run, split by distinguishability, and of the larger run, and per truth family the mean
probability of every family with the Monte Carlo error of that mean (sqrt(sum s.e.^2) / n) and the
spread across truths.
"""
from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
if any((REPO / "python" / "drillpy").glob("_core*.so")):  # in-tree build, else the installed drillpy
    sys.path.insert(0, str(REPO / "python"))
sys.path.insert(0, str(REPO / "benchmarks"))

#: The families compared (all of drillpy.calibration.families.FAMILIES).
FOUR = ("polynomial_hysteretic", "polynomial", "tucker_wang", "hysteretic")
#: Short names for the tables.
SHORT = {"polynomial_hysteretic": "5.3", "polynomial": "5.1", "tucker_wang": "3.1 TW", "hysteretic": "3.2-3.3",
         None: "cannot tell"}


def draw_truth(family: str, rng: np.random.Generator, spec) -> dict:
    """One truth of ``family``: its law parameters from the calibration's priors, the motor's c_m and
    Omega_c from the coverage benchmark's ranges."""
    from drillpy.calibration.families import FAMILIES
    law = {p.name: float(p.from_unit(rng.random())) for p in spec.families[family]
           if p.name in FAMILIES[family].parameters}
    return {"law": law, "c_m": float(rng.uniform(0.16, 0.30)), "omega_c": float(rng.uniform(15.5, 20.5))}


def rig_model_truth(family: str, rng: np.random.Generator, spec) -> dict:
    """One truth of drillpy's own rig model (``--simulator rig_model``): every calibrated parameter of
    ``family`` drawn from its prior."""
    return {"values": {p.name: float(p.from_unit(rng.random())) for p in spec.families[family]}}


def truth_record(family: str, truth: dict, base: dict, duration: float, seed: int):
    """(cleaned drillpy Record, stalled share) of the truth of ``family`` at ``truth``: the whole-rig
    simulator's, or drillpy's rig model's (``truth['values']``: stepped at 5e-5 s, the calibration at
    2.5e-4 s, with the platform, the 10 Hz filter and sensor noise, tests/python/test_calibration.py)."""
    if "values" in truth:
        sys.path.insert(0, str(REPO / "tests" / "python"))
        from test_calibration import _truth_record
        rec = _truth_record(seed=seed, duration=duration, family=family, truth=truth["values"])
        return rec, float(np.mean(rec.bit_speed < 0.5))
    import whole_rig

    from drillpy.calibration.families import family_law
    from drillpy.records.cleaning import clean
    from drillpy.records.io import read_record
    law = family_law(base, family, truth["law"])
    res = whole_rig.simulate({"law": law, "c_m": truth["c_m"], "omega_c": truth["omega_c"], "jack_steps": []},
                             duration=duration, seed=seed)
    stalled = float(np.mean(res["clean"]["omN"] < 0.5))
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "truth.mat"
        whole_rig.write_mat(res, str(path))
        rec, _ = clean(read_record(path))
    return rec, stalled


def predictive_distance(post, rec, draws: int, base: dict) -> dict:
    """Per family, the smallest distance (no discrepancy) to the record's statistics among ``draws``
    draws of its posterior particles (systematic resampling by weight), each simulated once: the
    family's best fit found (inf for a family without particles)."""
    from drillpy.calibration.posterior import RigSimulator
    from drillpy.calibration.priors import prior_spec
    from drillpy.records import rigsim
    sim = RigSimulator(rec, rigsim.stick_threshold(rec), prior_spec({"families": list(FOUR)}), base, threads=1)
    obs, scale = np.array(list(post.observed.values())), np.array(list(post.scale.values()))
    out = {}
    for f in FOUR:
        part = post.particles[f]
        w = np.asarray(part["weight"], float)
        if w.size == 0:
            out[f] = math.inf
            continue
        cw = np.cumsum(w / w.sum())
        idx = np.unique(np.minimum(np.searchsorted(cw, (0.5 + np.arange(draws)) / draws), w.size - 1))
        d = [float(np.sqrt(np.nanmean(((sim.one(f, {k: part[k][i] for k in part if k != "weight"}) - obs) / scale) ** 2)))
             for i in idx]
        out[f] = min((x for x in d if math.isfinite(x)), default=math.inf)
    return out


def separation(fam: str, best: dict, n_stats: int, factor: float) -> tuple:
    """(log Bayes factor, verdict) of the truth's family over the best other family from their best fits'
    distances: a Gaussian synthetic likelihood of the statistics with each statistic's variance (1 +
    F^2) scale^2 (its sampling noise and the model discrepancy), log LR = K (d_o^2 - d_t^2) /
    (2 (1 + F^2)); ``can tell`` above ln 3 (a Bayes factor of 3, the model choice's threshold),
    ``favours another`` below -ln 3, else ``cannot tell``."""
    d_t = best[fam]
    d_o = min(best[g] for g in FOUR if g != fam)
    if not math.isfinite(d_t) and not math.isfinite(d_o):
        return math.nan, "cannot tell"
    if not math.isfinite(d_o) or not math.isfinite(d_t):
        llr = math.inf if math.isfinite(d_t) else -math.inf
    else:
        llr = n_stats * (d_o ** 2 - d_t ** 2) / (2.0 * (1.0 + factor ** 2))
    verdict = "can tell" if llr > math.log(3) else ("favours another" if llr < -math.log(3) else "cannot tell")
    return llr, verdict


def _run(rec, population, simulations, seed, threads, discrepancy, share):
    from drillpy import load_config
    from drillpy.calibration.posterior import calibrate_record
    cfg = load_config(preset="thesis-rig")
    cfg["calibration"] = {"families": list(FOUR)} if share is None else {"families": list(FOUR), "family_share": share}
    post = calibrate_record(rec, config=cfg, population=population, max_simulations=simulations, predictive_draws=1,
                            max_generations=40, seed=seed, threads=threads, discrepancy=discrepancy)
    return {"post": post, "p": post.model_probability, "se": post.model_probability_se,
            "choice": post.model_choice["family"],
            "reason": post.model_choice["reason"], "ess": post.model_choice["ess"], "eps": post.run["eps"][-1],
            "model_ess": dict(zip(FOUR, post.run["history"][-1]["model_ess"])),
            "sims": post.run["abc_simulations"], "stopped": post.run["stopped"]}


def _fmt(r: dict) -> str:
    return (", ".join(f"{SHORT[f]} {r['p'][f]:.2f}+-{r['se'][f]:.2f} (ESS {r['model_ess'][f]:.1f})" for f in FOUR)
            + f" -> {SHORT[r['choice']]} (ESS {r['ess']:.0f}, eps {r['eps']:.3g}, {r['sims']} sims, stopped: "
            f"{r['stopped']})")


def confusion(rows: list, key: str, title: str) -> str:
    """A markdown confusion table: truth family x {picked family, cannot tell}."""
    cols = list(FOUR) + [None]
    out = [f"{title}", "", "| truth \\ picked | " + " | ".join(SHORT[c] for c in cols) + " | truths |",
           "|---" * (len(cols) + 2) + "|"]
    for f in FOUR:
        sel = [r for r in rows if r["family"] == f]
        if not sel:
            continue
        counts = [sum(r[key]["choice"] == c for r in sel) for c in cols]
        out.append(f"| {SHORT[f]} | " + " | ".join(str(c) for c in counts) + f" | {len(sel)} |")
    return "\n".join(out)


def mean_probabilities(rows: list, key: str) -> str:
    """Per truth family, every family's mean probability +- its Monte Carlo error (sqrt(sum se^2) / n)
    [min-max over the truths]."""
    out = ["| truth \\ P(family) | " + " | ".join(SHORT[f] for f in FOUR) + " |", "|---" * (len(FOUR) + 1) + "|"]
    for f in FOUR:
        sel = [r[key] for r in rows if r["family"] == f]
        if not sel:
            continue
        cells = []
        for g in FOUR:
            p = np.array([r["p"][g] for r in sel])
            se = math.sqrt(sum(r["se"][g] ** 2 for r in sel)) / len(sel)
            cells.append(f"{p.mean():.2f} +- {se:.2f} [{p.min():.2f}, {p.max():.2f}]")
        out.append(f"| {SHORT[f]} | " + " | ".join(cells) + " |")
    return "\n".join(out)


def main(argv=None) -> int:
    """Run the truths and print the tables (module docstring).

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.

    Returns
    -------
    int
        Exit status 0.
    """
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--per-family", type=int, default=3)
    ap.add_argument("--first", type=int, default=0, help="skip the first N truths of each family (truth j has its own "
                                                         "seeds: the others are those of a run without --first)")
    ap.add_argument("--families", default=",".join(FOUR), help="truth families (comma-separated)")
    ap.add_argument("--duration", type=float, default=10.0, help="record length [s]")
    ap.add_argument("--population", type=int, default=100)
    ap.add_argument("--simulations", type=int, default=1500)
    ap.add_argument("--large-population", type=int, default=200)
    ap.add_argument("--large-simulations", type=int, default=5000)
    ap.add_argument("--no-large", action="store_true", help="skip the larger-budget run")
    ap.add_argument("--draws", type=int, default=10, help="posterior draws per family for its best fit")
    ap.add_argument("--simulator", choices=("whole_rig", "rig_model"), default="whole_rig",
                    help="the truths' simulator: the independent whole rig (default) or drillpy's own rig model at a "
                         "finer step (the declared model: no structural misfit)")
    ap.add_argument("--reproduced-only", action="store_true",
                    help="with --simulator rig_model: redraw a truth until the calibration's simulator reproduces its "
                         "record at its own parameters (calibration_coverage.distance_at_truth)")
    ap.add_argument("--seed", type=int, default=35)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--discrepancy", type=float, default=None, help="the model discrepancy's factor (default drillpy's)")
    ap.add_argument("--family-share", type=float, default=None,
                    help="calibration.family_share (default drillpy's: drillpy.calibration.priors.DEFAULT_FAMILY_SHARE)")
    a = ap.parse_args(argv)
    from calibration_coverage import REPRODUCED, distance_at_truth
    from drillpy import load_config
    from drillpy.calibration.priors import prior_spec
    base = load_config(preset="thesis-rig")["law"]
    spec = prior_spec({"families": list(FOUR)})
    rows = []
    start = time.perf_counter()
    for fi, fam in enumerate(a.families.split(",")):
        for j in range(a.first, a.first + a.per_family):
            rng = np.random.default_rng([a.seed, FOUR.index(fam), j])
            for redraw in range(200 if a.reproduced_only else 20):
                truth = (draw_truth if a.simulator == "whole_rig" else rig_model_truth)(fam, rng, spec)
                rec, stalled = truth_record(fam, truth, base, a.duration, seed=1000 + 10 * FOUR.index(fam) + j)
                if stalled <= 0.5 and (not a.reproduced_only or "values" not in truth
                                       or distance_at_truth(rec, None, fam, truth["values"]) <= REPRODUCED):
                    break
            cseed = a.seed + 100 * FOUR.index(fam) + j
            row = {"family": fam, "truth": truth, "redraws": redraw, "stalled": stalled,
                   "modest": _run(rec, a.population, a.simulations, cseed, a.threads, a.discrepancy,
                                      a.family_share)}
            if not a.no_large:
                row["large"] = _run(rec, a.large_population, a.large_simulations, cseed + 50000, a.threads,
                                    a.discrepancy, a.family_share)
                post = row["large"]["post"]
                best = predictive_distance(post, rec, a.draws, base)
                factor = post.run["discrepancy"]["factor"]
                row["best"], (row["llr"], row["separable"]) = best, separation(fam, best, len(post.observed), factor)
            rows.append(row)
            if "values" in truth:
                law = ", ".join(f"{k} {v:.3g}" for k, v in truth["values"].items())
            else:
                law = (", ".join(f"{k} {v:.3g}" for k, v in truth["law"].items())
                       + f"; c_m {truth['c_m']:.3f}, Omega_c {truth['omega_c']:.2f}")
            print(f"truth {SHORT[fam]} #{j + 1} ({law}; "
                  f"redrawn {redraw}x, bit below 0.5 rad/s {stalled:.2f}) [{time.perf_counter() - start:.0f} s]",
                  flush=True)
            print("  modest: " + _fmt(row["modest"]), flush=True)
            if "large" in row:
                print("  larger: " + _fmt(row["large"]), flush=True)
                print("  best fit of each family (larger run's posterior, {} draws): ".format(a.draws)
                      + ", ".join(f"{SHORT[g]} {row['best'][g]:.2f}" for g in FOUR)
                      + f"; log LR truth's family over the best other {row['llr']:.2f}: {row['separable']}", flush=True)
    print()
    if a.no_large:
        print(confusion(rows, "modest", f"Modest budget ({a.population} particles, {a.simulations} simulations)"))
    else:
        for label, sel in (("the best fits can tell the truth's family (log LR > ln 3)",
                            [r for r in rows if r["separable"] == "can tell"]),
                           ("the best fits cannot tell (|log LR| <= ln 3)",
                            [r for r in rows if r["separable"] == "cannot tell"]),
                           ("another family's best fit is better (log LR < -ln 3)",
                            [r for r in rows if r["separable"] == "favours another"])):
            for key, budget in (("modest", f"{a.population} particles, {a.simulations} simulations"),
                                ("large", f"{a.large_population} particles, {a.large_simulations} simulations")):
                print(confusion(sel, key, f"{budget}; {label}: {len(sel)} truths"))
                print()
    print()
    print("Mean model probability +- its Monte Carlo error [min, max over the truths], modest budget:")
    print(mean_probabilities(rows, "modest"))
    if not a.no_large:
        print()
        print("The same, larger budget:")
        print(mean_probabilities(rows, "large"))
    print(f"\n{len(rows)} truths in {time.perf_counter() - start:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
