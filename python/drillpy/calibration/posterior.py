"""The rig model's posterior from a record: ABC-SMC over the law families and their parameters.

:func:`calibrate_record` reads and cleans a record, takes the summary statistics of a window
(:mod:`drillpy.calibration.summaries`), and runs the ABC-SMC of :mod:`drillpy.calibration.abcsmc`
with the whole rig model (:class:`drillpy.records.rigsim.RigModel`, the ``rig`` drive: motor,
coupling, jack, platform, 10 Hz filter) as the simulator, each law family of
:data:`drillpy.calibration.families.FAMILIES` with its priors (:mod:`drillpy.calibration.priors`).
The distance is the root mean square of the statistics' differences in units of their own
sampling uncertainty on the record (:func:`~drillpy.calibration.summaries.noise_scale`).

The result (:class:`Posterior`) gives the model probabilities with their Monte Carlo error, each
parameter's posterior median and 90 % interval, and the posterior predictive intervals of the
long-run statistics on a held-out window: model-averaged posterior draws simulated at that
window's operating point (its WOB trend), plus each statistic's sampling noise over a window of
that length (the calibration window's block spread scaled by the window lengths), so that the
intervals cover what a record of that length would measure; the intervals are the empirical
weighted quantiles of those samples, each held in the range its statistic can take
(:func:`predictive_intervals`).

The simulations step at :data:`SIM_DT_S` (2.5e-4 s, the preset's 1e-4 s otherwise): the evidence
that it changes the statistics no more than the preset's step does is in docs/calibration.md.
"""
from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from drillpy.calibration import abcsmc
from drillpy.calibration.elements import left_out, model_equation, parse_model
from drillpy.calibration.families import check_base, family_law
from drillpy.calibration.priors import PriorSpec, discrepancy_factor, family_share, prior_spec, split_config
from drillpy.calibration.sampler import Sampler, check_backend
from drillpy.calibration.summaries import ALL_NAMES, ALL_UNITS, BOUNDS, NAMES, noise_scale, statistics, summaries
from drillpy.model.configuration import Configuration
from drillpy.model.simulation import simulate
from drillpy.records import rigsim
from drillpy.records.io import Record
from drillpy.records.signals import platform_response, rig_lowpass

#: The simulated start-up left out of every statistic [s].
SKIP_S = 2.0
#: Statistics reported with predictive intervals.
PREDICTED = NAMES
#: Time step of the calibration's rig simulations [s] (the preset steps at 1e-4 s): as close to a
#: 5e-5 s reference as the preset's step in the ABC's noise units (docs/calibration.md,
#: "Speed"; ``benchmarks/calibration_timestep.py``), at less than half its engine time.
SIM_DT_S = 2.5e-4


def rig_model(base_law: dict, family: str, values: dict, fixed: dict, preset: str = "thesis-rig") -> rigsim.RigModel:
    """The ``rig``-drive model of ``family`` at the parameter ``values`` with the ``fixed`` rig parameters.

    Parameters
    ----------
    base_law : dict
        The configuration's polynomial law (:func:`drillpy.calibration.families.family_law`).
    family : str
        Model of the comparison: a law family, or a family without some of the rig's elements
        (``"polynomial without jack"``, :mod:`drillpy.calibration.elements`).
    values : dict
        Calibrated parameter -> value (names of :data:`drillpy.calibration.priors.PARAMETERS`); the
        parameters of the elements the model leaves out are held (:func:`~drillpy.calibration.elements.left_out`).
    fixed : dict
        Held rig parameter -> value (:data:`drillpy.calibration.priors.FIXED`).
    preset : str
        Engine preset of the rig's geometry.

    Returns
    -------
    RigModel
    """
    values = {**values, **left_out(family)}
    law = family_law(base_law, parse_model(family)[0], values)
    motor = values["motor_slope_nms_rad"] is not None  # None: the rig without its motor (an ideal drive)
    return rigsim.RigModel(law, values["damping_ratio"], "rig", values["motor_slope_nms_rad"],
                           fixed["motor_inertia_kg_m2"] if motor else None, preset=preset, command_rad_s=values["command_rad_s"],
                           jack_gain_n_rad=values["jack_gain_n_rad"], jack_relaxation_s=fixed["jack_relaxation_s"],
                           platform_damping=fixed["platform_damping"], gj_factor=fixed["gj_factor"],
                           bit_inertia_factor=fixed["bit_inertia_factor"],
                           coupling_stiffness_nm_rad=values["coupling_stiffness_nm_rad"])


class RigSimulator:
    """The batched simulator of the ABC: statistics of the rig model over a record's span.

    Parameters
    ----------
    record : Record
        The cleaned window (its operating point and WOB trend drive every run).
    stick_threshold : float
        [rad/s].
    spec : PriorSpec
    base_law : dict
    threads : int
        Runs at once (0: one per core) when no ``sampler`` is given.
    dt_s : float
        The engine's time step [s] (:data:`SIM_DT_S`); the output stays on the record's grid.
    sampler : Sampler, optional
        Where the batches run (:mod:`drillpy.calibration.sampler`; default ``threads`` threads here).
    scheme : str
        The engine's time integration (``simulation.scheme``: ``"modified_euler"``, the thesis's,
        by default; ``"exact_modal"``, docs/numerics.md, for a coarser step).
    """

    def __init__(self, record: Record, stick_threshold: float, spec: PriorSpec, base_law: dict, threads: int = 0,
                 dt_s: float = SIM_DT_S, sampler: Sampler | None = None, scheme: str = "modified_euler"):
        ratio = record.dt / dt_s if isinstance(dt_s, (int, float)) and math.isfinite(dt_s) and dt_s > 0 else 0.0
        if ratio < 1 - 1e-6 or abs(ratio - round(ratio)) > 1e-6 * ratio:
            raise ValueError(f"dt_s = {dt_s!r}: a time step that divides the record's sampling interval "
                             f"{record.dt:g} s (the statistics are taken on its grid)")
        self.record, self.thr, self.spec, self.base_law = record, stick_threshold, spec, base_law
        self.dt_s = float(dt_s)
        self.scheme = str(scheme)
        self.families = list(spec.families)
        self.names = tuple(spec.statistics)
        self.sampler = sampler if sampler is not None else Sampler(threads)
        self.threads = self.sampler.threads
        self.runs = 0
        self._inputs = {}

    def __getstate__(self) -> dict:
        """What a Dask worker gets: no sampler (its client), no cache of the windows' inputs."""
        return {**self.__dict__, "sampler": None, "_inputs": {}}

    def values(self, family: str, z) -> dict:
        """Parameter name -> value at unit coordinates ``z``.

        Parameters
        ----------
        family : str
            Law family.
        z : array_like
            Unit coordinates, one per parameter of the family.

        Returns
        -------
        dict
        """
        return {p.name: float(p.from_unit(zi)) for p, zi in zip(self.spec.families[family], z)}

    def one(self, family: str, values: dict, record: Record | None = None) -> np.ndarray:
        """The statistics of one run over ``record`` (default the calibration window) at its
        operating point, as :func:`drillpy.records.rigsim.simulate_model` runs the rig drive (the
        platform's response and the 10 Hz filter on the channels); NaN when the run fails.

        Parameters
        ----------
        family : str
            Law family.
        values : dict
            Parameter name -> value.
        record : Record, optional
            Another window (its operating point, WOB trend and stick threshold).

        Returns
        -------
        ndarray
            The statistics of the prior's ``statistics`` (default :data:`drillpy.calibration.summaries.NAMES`).
        """
        rec = self.record if record is None else record
        key = id(rec)
        if key not in self._inputs:
            op = rigsim.operating_point(rec)
            wob = op.get("wob_n", self.base_law["wob_ref_n"])
            self._inputs[key] = (wob, rigsim.wob_trend(rec, wob), float(rec.time_s[-1] - rec.time_s[0]),
                                 rigsim.stick_threshold(rec) if record is not None else self.thr, rec.dt)
        wob, trend, duration, thr, rec_dt = self._inputs[key]
        try:
            model = rig_model(self.base_law, family, values, self.spec.fixed)
            cfg = Configuration.of(model.config(model.command_rad_s, wob, duration_s=duration)).replace(
                {"simulation.dt_s": self.dt_s, "simulation.output_stride": max(1, int(round(rec_dt / self.dt_s))),
                 "simulation.scheme": self.scheme})
            res = simulate(cfg.engine(), model.command_rad_s, wob_series=trend, series_dt=rec_dt)
            n = min(res.t.size, len(rec))
            fs = 1.0 / float(np.median(np.diff(res.t)))
            tq = platform_response(res.torque_on_bit[:n], fs, rigsim.PLATFORM_HZ, model.platform_damping)
            vb, vt, tq, w = (rig_lowpass(x, fs) for x in (res.bit_speed[:n], res.top_speed[:n], tq, res.wob[:n]))
            k = int(np.searchsorted(res.t[:n], SKIP_S))
            return statistics(vb[k:], tq[k:], vt[k:], w[k:], 1.0 / fs, thr, self.names)
        except (ValueError, RuntimeError):
            return np.full(len(self.names), np.nan)

    def __call__(self, m: int, Z: np.ndarray) -> np.ndarray:
        fam = self.families[m]
        vals = [self.values(fam, z) for z in Z]
        self.runs += len(vals)
        return self.sampler.map(self, [(fam, v) for v in vals])


@dataclass
class Posterior:
    """The calibration's result (:func:`calibrate_record`).

    Attributes
    ----------
    families : list of str
    model_probability, model_probability_se : dict
        Family -> posterior probability, and its Monte Carlo standard error.
    parameters : dict
        Family -> parameter -> ``median``, ``ci90`` [p5, p95], ``prior`` range, ``unit``,
        ``width_ratio`` (90 % interval / prior range).
    particles : dict
        Family -> {``weight``: [...], parameter: [...]} (the final population).
    observed, scale : dict
        The window's statistics and their scales in the distance.
    predictive : dict
        Statistic -> ``interval90``, ``median``, ``measured`` (held-out window), ``contained``.
    run : dict
        Simulations, generations, tolerances, acceptance, wall time, seed, why it stopped.
    spec : dict
        The priors and held values.
    record : dict
        The record's source, calibration window [s], stick threshold [rad/s] and the configuration's
        law the families are built on (``base_law``).
    model_choice : dict
        The family the record supports, or that it cannot tell (:func:`drillpy.calibration.abcsmc.model_choice`).
    """
    families: list
    model_probability: dict
    model_probability_se: dict
    parameters: dict
    particles: dict
    observed: dict
    scale: dict
    predictive: dict
    run: dict
    spec: dict
    record: dict = field(default_factory=dict)
    model_choice: dict = field(default_factory=dict)

    def summary(self) -> dict:
        """JSON-ready dict (``posterior.json``)."""
        return {"format": "drillpy.posterior", "version": 1, "record": self.record, "families": self.families,
                "equations": {f: model_equation(f) for f in self.families},
                "model_probability": self.model_probability, "model_probability_se": self.model_probability_se,
                "model_choice": self.model_choice, "parameters": self.parameters, "predictive": self.predictive,
                "observed": self.observed, "scale": self.scale, "units": {n: _unit(n) for n in self.observed}, "run": self.run, "priors": self.spec,
                "particles": self.particles}


def _unit(name: str) -> str:
    return ALL_UNITS[ALL_NAMES.index(name)]


def _wquantile(x, w, q):
    o = np.argsort(x)
    cw = np.cumsum(w[o]) / w.sum()
    return [float(np.interp(qq, cw - 0.5 * w[o] / w.sum(), x[o])) for qq in q]


def load_window(record, t0: float | None = None, t1: float | None = None) -> Record:
    """The record at a path, read and cleaned (or a :class:`Record` taken as cleaned), cut to [t0, t1] s.

    Parameters
    ----------
    record : str or Path or Record
        The record.
    t0, t1 : float, optional
        The window [s].

    Returns
    -------
    Record
    """
    from drillpy.records.cleaning import clean
    from drillpy.records.io import read_record
    rec = clean(read_record(record))[0] if isinstance(record, (str, Path)) else record
    if t0 is not None or t1 is not None:
        rec = rec.select(t0, t1)
    if len(rec) < 100:
        raise ValueError(f"record window [{t0}, {t1}] s: {len(rec)} samples, too short to calibrate on")
    if rec.top_speed is None:
        raise ValueError("record: no top_speed channel (the rig model's operating point needs it)")
    return rec


def calibrate_record(record, *, preset: str | None = None, config_path: str | None = None, config: dict | None = None,
                     t0: float | None = None, t1: float | None = None, heldout: tuple | None = None,
                     population: int = 200, max_simulations: int = 20000, max_generations: int = 12,
                     predictive_draws: int = 100, seed: int = 0, threads: int = 0, dt_s: float = SIM_DT_S,
                     scheduler: str | None = None, chunk: int | None = None, discrepancy: float | None = None,
                     log=None) -> Posterior:
    """Posterior of the rig model given a record (module docstring).

    Parameters
    ----------
    record : str or Path or Record
        The record (.mat or .csv) or a cleaned :class:`Record`.
    preset, config_path, config : optional
        Exactly one: the declared model (its law is the families' base; a configuration's
        ``calibration`` section sets the priors, :mod:`drillpy.calibration.priors`).
    t0, t1 : float, optional
        The calibration window [s].
    heldout : tuple of float, optional
        (t0, t1) of a held-out window [s] for the predictive intervals; default the calibration
        window itself.
    population : int
        Particles per generation.
    max_simulations : int
        Simulation budget.
    max_generations : int
        Generations after the prior's.
    predictive_draws : int
        Posterior draws simulated for the predictive intervals.
    seed : int
        Seed of every random draw (same seed, same numbers, whatever ``threads``, ``scheduler`` or
        ``chunk``).
    threads : int
        Simulations at once on threads (0: one per core).
    dt_s : float
        The rig simulations' time step [s] (:data:`SIM_DT_S`).
    scheduler : str, optional
        ``local`` (or None: ``threads`` threads here), ``local:N`` (a Dask LocalCluster of N workers)
        or ``tcp://HOST:PORT`` (:mod:`drillpy.calibration.sampler`).
    chunk : int, optional
        Simulations per Dask task (default: each batch cut into 4 tasks per worker).
    discrepancy : float, optional
        The model discrepancy's factor (:func:`drillpy.calibration.priors.discrepancy_factor`): each
        statistic's discrepancy standard deviation in units of its window-to-window spread on the
        record; default the configuration's ``calibration.discrepancy``, else
        :data:`~drillpy.calibration.priors.DEFAULT_DISCREPANCY`. It enters the ABC as noise on the
        simulated statistics (:func:`drillpy.calibration.abcsmc.run`) and the predictive intervals.
    log : callable, optional
        Progress lines (and the LocalCluster's dashboard address).

    Returns
    -------
    Posterior

    Raises
    ------
    ValueError
        Naming the field and the value (configuration, priors, window, budget, scheduler, chunk).
    """
    given = [x is not None for x in (preset, config_path, config)]
    if sum(given) != 1:
        raise ValueError("calibrate: give exactly one of preset, config_path or config")
    for k, v in (("population", population), ("max_simulations", max_simulations),
                 ("predictive_draws", predictive_draws)):
        if not isinstance(v, (int, np.integer)) or v < 1:
            raise ValueError(f"{k} = {v!r}: a positive integer")
    if not isinstance(max_generations, (int, np.integer)) or max_generations < 0:
        raise ValueError(f"max_generations = {max_generations!r}: a non-negative integer")
    check_backend(scheduler, chunk)
    if discrepancy is not None:
        discrepancy_factor(discrepancy, "discrepancy")
    if config_path is not None:
        config = json.loads(Path(config_path).read_text())
    section = {}
    if config is not None:
        config, section = split_config(config)
        cfg = Configuration.load(config=config)
    else:
        cfg = Configuration.load(preset=preset)
    spec = prior_spec(section)
    factor = discrepancy_factor(section.get("discrepancy") if discrepancy is None else discrepancy,
                                "calibration.discrepancy" if discrepancy is None else "discrepancy")
    share = family_share(section.get("family_share"))
    base_law = cfg.law.to_dict()
    check_base(base_law)  # the law's type, checked before any run
    rec = load_window(record, t0, t1)
    thr = rigsim.stick_threshold(rec)
    names = spec.statistics
    observed = summaries(rec, thr, SKIP_S, names)
    scale = noise_scale(rec, thr, skip_s=SKIP_S, names=names)
    ok = np.isfinite(observed)
    if not ok.all():
        missing = [n for n, o in zip(names, ok) if not o]
        raise ValueError(f"record: statistics {', '.join(missing)} cannot be measured on the window")
    disc = factor * scale  # the discrepancy's standard deviation of each statistic, in its unit
    target = load_window(record, *heldout) if heldout is not None else rec
    with Sampler(threads, scheduler, chunk, log) as sampler:
        sim = RigSimulator(rec, thr, spec, base_law, dt_s=dt_s, sampler=sampler)
        dims = [len(spec.families[f]) for f in sim.families]
        start, cpu = time.perf_counter(), time.process_time()
        res = abcsmc.run(sim, dims, observed, scale, population=population, max_simulations=max_simulations,
                         max_generations=max_generations, seed=seed, discrepancy=disc,
                         family_share=share, log=log)
        wall, cpu = time.perf_counter() - start, time.process_time() - cpu
        post = res.posterior
        # posterior predictive on the held-out window
        jobs = [(sim.families[m], sim.values(sim.families[m], z)) for m, z in zip(post.model, post.z)]
        predictive = _predictive(sim, jobs, post.weight, target, scale, float(rec.time_s[-1] - rec.time_s[0]),
                                 predictive_draws, seed, disc)
        backend = sampler.describe()
    p, se = post.model_probabilities(len(dims))
    parameters, particles = {}, {}
    for m, fam in enumerate(sim.families):
        sel = np.flatnonzero(post.model == m)
        particles[fam] = {"weight": post.weight[sel].tolist()}
        parameters[fam] = {}
        for j, pr in enumerate(spec.families[fam]):
            vals = np.array([float(pr.from_unit(post.z[i][j])) for i in sel])
            particles[fam][pr.name] = vals.tolist()
            if sel.size == 0:
                continue
            lo, med, hi = _wquantile(vals, post.weight[sel], (0.05, 0.5, 0.95))
            if pr.scale == "log-uniform":
                ratio = math.log(hi / lo) / math.log(pr.high / pr.low)
            else:
                ratio = (hi - lo) / (pr.high - pr.low)
            parameters[fam][pr.name] = {"median": med, "ci90": [lo, hi], "prior": [pr.low, pr.high],
                                        "unit": pr.unit, "width_ratio": ratio}
    run = {"simulations": res.simulations + int(predictive_draws), "abc_simulations": res.simulations,
           "generations": len(res.populations) - 1, "population": population, "stopped": res.stopped,
           "eps": [h["eps"] for h in res.history], "history": res.history, "wall_s": wall,
           "simulations_per_s": res.simulations / wall if wall > 0 else None, "cpu_s": cpu, "seed": seed,
           "threads": backend.get("threads"), "backend": backend, "dt_s": sim.dt_s, "method": "ABC-SMC with model choice (drillpy.calibration.abcsmc)",
           "heldout_s": list(heldout) if heldout is not None else None,
           "family_share": share,
           "discrepancy": {"factor": factor, "sd": dict(zip(names, map(float, disc))),
                           "eps_floor": abcsmc.discrepancy_floor(disc, scale),
                           "method": "noisy ABC under model error (Wilkinson 2013): N(0, sd^2) on each simulated "
                                     "statistic, sd = factor x its window-to-window spread on the record"}}
    rec_info = {"source": str(record) if isinstance(record, (str, Path)) else rec.provenance.get("source"),
                "window_s": [float(rec.time_s[0]), float(rec.time_s[-1])], "stick_threshold_rad_s": thr,
                "base_law": base_law}
    return Posterior(sim.families, dict(zip(sim.families, map(float, p))), dict(zip(sim.families, map(float, se))),
                     parameters, particles, dict(zip(names, map(float, observed))), dict(zip(names, map(float, scale))),
                     predictive, run, spec.summary(), rec_info, abcsmc.model_choice(post, sim.families, res.history,
                                                                          max_eps=abcsmc.choice_tolerance(factor)))


#: Sampling-noise replicates per simulated predictive draw (:func:`predictive_intervals`).
NOISE_REPLICATES = 50


def predictive_intervals(stats: np.ndarray, weight: np.ndarray, noise: np.ndarray, rng: np.random.Generator,
                         replicates: int = NOISE_REPLICATES, names=NAMES) -> list:
    """Posterior predictive (5 %, 50 %, 95 %) of each statistic: the empirical weighted quantiles of
    the simulated statistics plus their sampling noise.

    Each row of ``stats`` (one simulated draw, weight ``weight``) gets ``replicates`` normal draws
    of the statistic's sampling noise ``noise``, each held in the range the statistic can take
    (:data:`drillpy.calibration.summaries.BOUNDS`: a stick fraction is not negative); the
    quantiles are those of that weighted sample (midpoint interpolation of its cumulative weight),
    so they lie within the range of the sample and never outside the statistic's.

    Parameters
    ----------
    stats : ndarray
        Simulated statistics, draws x :data:`~drillpy.calibration.summaries.NAMES` (NaN: failed).
    weight : ndarray
        Weight of each draw (non-negative).
    noise : ndarray
        Each statistic's sampling standard deviation over the predicted window.
    rng : numpy.random.Generator
        The noise's generator.
    replicates : int
        Noise draws per simulated draw.
    names : sequence of str
        The statistics of the columns (default :data:`~drillpy.calibration.summaries.NAMES`).

    Returns
    -------
    list
        Per statistic, (p5, p50, p95), or None when fewer than two draws have it.
    """
    stats, weight = np.atleast_2d(np.asarray(stats, float)), np.asarray(weight, float)
    eps = rng.standard_normal((replicates,) + stats.shape)
    out = []
    for k, name in enumerate(names):
        ok = np.isfinite(stats[:, k]) & (weight > 0)
        if ok.sum() < 2:
            out.append(None)
            continue
        lo, hi = BOUNDS.get(name, (-np.inf, np.inf))
        x = np.clip(stats[ok, k][None, :] + noise[k] * eps[:, ok, k], lo, hi).ravel()
        w = np.broadcast_to(weight[ok][None, :], (replicates, int(ok.sum()))).ravel()
        out.append(tuple(_wquantile(x, w, (0.05, 0.5, 0.95))))
    return out


def _predictive(sim: RigSimulator, jobs: list, weight: np.ndarray, target: Record, scale: np.ndarray,
                calibration_s: float, draws: int, seed: int, discrepancy=None) -> dict:
    """Posterior predictive 90 % intervals of the statistics on ``target`` (module docstring):
    ``draws`` particles of ``jobs`` [(family, values)] taken by systematic resampling on ``weight``,
    each distinct particle simulated once at the target's operating point and weighted by its count,
    with each statistic's sampling noise ``scale`` (over ``calibration_s`` seconds) scaled to the
    target's length and, in quadrature, the model ``discrepancy``'s standard deviation (the same on
    any window: the model's error, not the record's sampling) (:func:`predictive_intervals`)."""
    rng = np.random.default_rng([seed, 10 ** 6])
    cw = np.cumsum(weight / weight.sum())
    picks = np.minimum(np.searchsorted(cw, (rng.random() + np.arange(int(draws))) / int(draws)), len(jobs) - 1)
    idx, count = np.unique(picks, return_counts=True)
    pred = sim.sampler.map(sim, [jobs[i] for i in idx], target)
    len_t = float(target.time_s[-1] - target.time_s[0]) - SKIP_S
    noise = scale * math.sqrt(max(calibration_s - SKIP_S, 1e-9) / max(len_t, 1e-9))
    if discrepancy is not None:
        noise = np.hypot(noise, discrepancy)
    q = predictive_intervals(pred, count.astype(float), noise, rng, names=sim.names)
    measured = summaries(target, rigsim.stick_threshold(target), SKIP_S, sim.names)
    out = {}
    for k, name in enumerate(sim.names):
        if q[k] is None:
            continue
        lo, med, hi = q[k]
        mk = float(measured[k])
        out[name] = {"interval90": [lo, hi], "median": med, "measured": mk,
                     "contained": bool(lo <= mk <= hi) if math.isfinite(mk) else None, "unit": _unit(name)}
    return out


def predict_posterior(posterior, record, *, t0: float | None = None, t1: float | None = None, draws: int = 100,
                      seed: int = 0, threads: int = 0, scheduler: str | None = None, chunk: int | None = None,
                      log=None) -> dict:
    """Posterior predictive 90 % intervals of the long-run statistics on a record window, from a
    calibration's ``posterior.json`` (``drillpy predict POSTERIOR.json RECORD``).

    Parameters
    ----------
    posterior : str or Path or dict
        ``posterior.json`` of ``drillpy calibrate`` (or its dict, :meth:`Posterior.summary`).
    record : str or Path or Record
        The record to predict.
    t0, t1 : float, optional
        Its window [s].
    draws : int
        Posterior draws simulated.
    seed : int
        Seed of the draws and of the statistics' sampling noise.
    threads : int
        Simulations at once on threads (0: one per core).
    scheduler : str, optional
        ``local`` (or None: threads), ``local:N`` or ``tcp://HOST:PORT`` (:mod:`drillpy.calibration.sampler`);
        the same numbers on any.
    chunk : int, optional
        Simulations per Dask task.
    log : callable, optional
        Receives the LocalCluster's dashboard address.

    Returns
    -------
    dict
        Statistic -> ``interval90``, ``median``, ``measured``, ``contained``, ``unit``; and
        ``window_s``, ``draws``, ``model_probability``.

    Raises
    ------
    ValueError
        When the file is not a drillpy posterior, or naming a bad ``draws``, ``scheduler`` or ``chunk``.
    """
    s = read_posterior(posterior)
    if not isinstance(draws, (int, np.integer)) or draws < 2:
        raise ValueError(f"draws = {draws!r}: an integer of at least 2")
    check_backend(scheduler, chunk)
    spec, jobs, weight = posterior_particles(s)
    target = load_window(record, t0, t1)
    win = s["record"]["window_s"]
    with Sampler(threads, scheduler, chunk, log) as sampler:
        sim = RigSimulator(target, rigsim.stick_threshold(target), spec, s["record"]["base_law"],
                           dt_s=float(s["run"].get("dt_s", 1e-4)),  # a posterior written before dt_s ran at 1e-4 s
                           sampler=sampler)
        disc = s["run"].get("discrepancy", {}).get("sd")  # none in a posterior written before the discrepancy
        names = spec.statistics
        out = _predictive(sim, jobs, weight, target, np.array([s["scale"][n] for n in names]),
                          float(win[1] - win[0]), draws, seed, None if disc is None else np.array([disc[n] for n in names]))
    return {"statistics": out, "window_s": [float(target.time_s[0]), float(target.time_s[-1])], "draws": int(draws),
            "model_probability": s["model_probability"]}


def read_posterior(posterior) -> dict:
    """A calibration's ``posterior.json`` (a path, or its dict, :meth:`Posterior.summary`), checked.

    Parameters
    ----------
    posterior : str or Path or dict

    Returns
    -------
    dict

    Raises
    ------
    ValueError
        When it is not a drillpy posterior.
    """
    s = json.loads(Path(posterior).read_text()) if isinstance(posterior, (str, Path)) else posterior
    if not isinstance(s, dict) or s.get("format") != "drillpy.posterior":
        raise ValueError(f"{posterior if isinstance(posterior, (str, Path)) else 'posterior'}: not a drillpy posterior "
                         f"(format = {s.get('format') if isinstance(s, dict) else None!r}; write one with drillpy "
                         "calibrate)")
    return s


def posterior_particles(s: dict) -> tuple:
    """The final population of a posterior (:func:`read_posterior`): its priors, the particles
    [(family, parameter values)] and their weights across the families (each family's weights
    times its model probability; they sum to 1).

    Parameters
    ----------
    s : dict

    Returns
    -------
    (PriorSpec, list, ndarray)
    """
    from drillpy.calibration.priors import Prior
    fams = s["families"]
    spec = PriorSpec({f: tuple(Prior(n, *p["range"], p["unit"], p["scale"], p.get("source", ""))
                               for n, p in s["priors"]["families"][f].items()) for f in fams}, s["priors"]["fixed"],
                     tuple(s["priors"].get("statistics", NAMES)))  # a posterior written before the option: NAMES
    jobs, weight = [], []
    for f in fams:
        part = s["particles"][f]
        w = np.asarray(part["weight"], float)
        for i in range(w.size):
            jobs.append((f, {n: float(part[n][i]) for n in s["priors"]["families"][f]}))
        weight.extend(w / max(w.sum(), 1e-300) * s["model_probability"][f] if w.size else [])
    weight = np.asarray(weight, float)
    return spec, jobs, weight / max(weight.sum(), 1e-300)
