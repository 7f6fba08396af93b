"""Robust tuning of a top-drive controller (issue 15, item 3): the gains that minimise the
probability of stick-slip over an operating window under the chapter-4 bit-rock uncertainty.

The uncertainty is the stochastic law T_sto = T_hys (1 + eta(t)) (Eq. 4.1) with eta the Gaussian
process of Eq. (4.4); a run is the chapter-4 Monte Carlo run (deterministic warm start, then
``duration`` seconds with eta, SS of Eq. 3.4 after ``transient``; :mod:`drillpy.uncertainty.montecarlo`).

Objective. Over a window of top speeds x WOBs and ``samples`` realizations of eta,

    P = mean over (WOB, sample, speed) of [SS > 0.5 or stalled]

SS > 0.5 is section 3.3's stick-slip threshold. A run is *stalled* when its mean bit speed over
the SS window is below ``STALL_FRACTION`` of the command: a drive that gives way (a soft
controller with a low integral gain, ZTorque with a long torque filter) can leave the bit stuck
with the top barely turning, and SS (Eq. 3.4: the bit speed's range over twice the mean *top*
speed) is then small although nothing is drilled. Such a run counts as a failure (its SS is
replaced by +inf in the tables the probabilities are computed from; the mean SS uses the raw SS).

    score = P + mean SS / (4 N)          (N runs in the window)

The tie-break makes the score informative where P is flat (every run in or out of stick-slip)
without letting SS outweigh one run's change of P (1 / N) while SS stays below 4.

Common random numbers. Every candidate runs the same realizations (same seed, same sample
indices, same warm start), so two candidates' scores differ by their gains, not by the draw.

Search. The gains are searched as factors of the engine's own tuning (docs/control.md): kp and ki
of the PI for ``soft_speed`` (SoftSpeed's kp = Z, ki = J w_1^2), the impedance Z and the torque
filter tau for ``z_torque``, each in [1/10, 10] x nominal on a log scale: a coarse grid, then
Nelder-Mead from its best point (SciPy, bounds, on the same random numbers).

The Monte Carlo error of the optimum. The optimum is selected on the tuning samples, so its score
there is optimistic. :func:`validate_drives` reruns the optimum, the nominal tunings and the stiff
drive on **new** samples (another seed): P with a bootstrap interval (samples resampled, every WOB
and speed of a sample together) and the paired difference to the stiff drive (same new samples).
The spread of the optimum itself is the bootstrap of the tuning: the grid and the refinement's
evaluations re-scored on resampled tuning samples give the resampled optima
(:func:`optimum_spread`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from drillpy import _core, validate
from drillpy.model.config import engine_config, with_overrides
from drillpy.model.configuration import Configuration
from drillpy.uncertainty.montecarlo import (DURATION_S, ETA_DT_S, SS_LEVEL, TRANSIENT_S, WARMUP_S, study_config,
                                            study_engine)
from drillpy.uncertainty.process import THESIS_PSD

#: a run whose mean bit speed is below this fraction of the command is stalled (module docstring)
STALL_FRACTION = 0.5
#: search range of every gain, as a factor of the nominal tuning
FACTOR_RANGE = (0.1, 10.0)
#: controllers whose gains are tuned, and the controller keys searched (top_drive.controller)
TUNABLE = {"soft_speed": ("kp_nms_rad", "ki_nm_rad"), "z_torque": ("impedance_nms_rad", "torque_filter_s")}
#: units of the searched keys
UNITS = {"kp_nms_rad": "N m s/rad", "ki_nm_rad": "N m/rad", "impedance_nms_rad": "N m s/rad", "torque_filter_s": "s"}


def controlled_drive(controller: str, inertia: float, torque_limit: float | None = None,
                     gains: dict | None = None) -> dict:
    """The ``top_drive`` block of a controlled drive (docs/control.md).

    Parameters
    ----------
    controller : str
        ``stiff``, ``pi``, ``soft_speed`` or ``z_torque``.
    inertia : float
        Drive inertia J [kg m^2].
    torque_limit : float, optional
        Motor torque limit L [N m] (None: unlimited).
    gains : dict, optional
        Other ``controller`` keys: gains that override the tuning (e.g. ``{"kp_nms_rad": 500.0}``),
        ``sample_time_s``...

    Returns
    -------
    dict
        ``{"type": "controlled", "inertia_kg_m2": J, "controller": {...}}``.
    """
    ctl = {"type": controller, **(gains or {})}
    if torque_limit is not None:
        ctl["torque_limit_nm"] = float(torque_limit)
    return {"type": "controlled", "inertia_kg_m2": inertia, "controller": ctl}


def nominal_pi_gains(cfg: dict, inertia: float) -> dict:
    """The gains of a ``pi`` controller left untuned: the ``stiff`` drive's pole placement on the string
    (kp = 2 J w_b, ki = J w_b^2, w_b = 20 w_1; docs/control.md).

    Parameters
    ----------
    cfg : dict
        The configuration (its string sets w_1).
    inertia : float
        Drive inertia J [kg m^2].

    Returns
    -------
    dict
        ``kp_nms_rad`` [N m s/rad] and ``ki_nm_rad`` [N m/rad].
    """
    from drillpy.model.config import with_overrides
    g = drive_gains(with_overrides(cfg, top_drive=controlled_drive("stiff", inertia)))
    return {"kp_nms_rad": g["kp_nms_rad"], "ki_nm_rad": g["ki_nm_rad"]}


def drive_gains(cfg: dict) -> dict:
    """The gains the engine resolves for the configuration's controlled drive.

    Parameters
    ----------
    cfg : dict
        A configuration whose ``top_drive`` is ``controlled``.

    Returns
    -------
    dict
        ``kp_nms_rad``, ``ki_nm_rad``, ``impedance_nms_rad``, ``torque_filter_s``, ``inertia_kg_m2``,
        ``torque_limit_nm``, ``top_impedance_nms_rad`` and ``omega1_rad_s`` (``Simulation.drive_gains``).

    Raises
    ------
    ValueError
        If the drive is not controlled.
    """
    g = _core.Simulation(engine_config(cfg)).drive_gains
    if g is None:
        raise ValueError(f"top_drive.type = {Configuration.of(cfg).top_drive.type!r}: has no controller gains")
    return dict(g)


@dataclass
class Window:
    """The operating window and the Monte Carlo setting of a tuning.

    Attributes
    ----------
    speeds : numpy.ndarray
        Top speeds [rad/s].
    wobs : numpy.ndarray
        Weights on bit [N].
    samples : int
        Realizations of eta per (speed, WOB).
    seed : int
        Seed of the realizations.
    warmup, duration, transient : float
        The chapter-4 run's durations [s] (:mod:`drillpy.uncertainty.montecarlo`).
    psd : PsdModel or PsdTable
        One-sided PSD of eta per Hz (default the thesis's Eq. 4.4; :mod:`drillpy.uncertainty.process`).
    """
    speeds: np.ndarray
    wobs: np.ndarray
    samples: int
    seed: int
    warmup: float = WARMUP_S
    duration: float = DURATION_S
    transient: float = TRANSIENT_S
    psd: object = THESIS_PSD

    def __post_init__(self):
        self.speeds = _positive_grid(self.speeds, "speeds")
        self.wobs = _positive_grid(self.wobs, "wobs")
        self.samples = validate.integer("samples", self.samples, 1, 100_000)
        self.seed = validate.seed(self.seed)
        self.warmup = validate.non_negative("warmup", self.warmup, "s")
        self.duration = validate.positive("duration", self.duration, "s")
        self.transient = validate.non_negative("transient", self.transient, "s")
        if self.transient >= self.duration:
            raise ValueError(f"transient = {self.transient:g}: must be shorter than the duration ({self.duration:g} s)")

    def as_dict(self) -> dict:
        """JSON-ready description.

        Returns
        -------
        dict
            The window's fields (speeds in rad/s, WOBs in N, durations in s).
        """
        return {"speeds_rad_s": self.speeds.tolist(), "wobs_n": self.wobs.tolist(), "samples": self.samples,
                "seed": self.seed, "warmup_s": self.warmup, "duration_s": self.duration,
                "transient_s": self.transient, "psd": self.psd.as_dict()}


def _positive_grid(values, name: str) -> np.ndarray:
    a = np.atleast_1d(np.asarray(values, dtype=float))
    if a.ndim != 1 or a.size == 0 or not np.all(np.isfinite(a)) or np.any(a <= 0):
        raise ValueError(f"{name} = {values!r}: must be one or more positive finite numbers")
    return a


def window_severity(cfg: dict, drive: dict | None, window: Window, *, seed: int | None = None,
                    threads: int = 0, deterministic: bool = False) -> np.ndarray:
    """SS (Eq. 3.4) of every (WOB, sample, speed) of the window with this top drive, stalled runs
    set to +inf (module docstring).

    Parameters
    ----------
    cfg : dict
        The configuration (its model, law, time step).
    drive : dict or None
        The ``top_drive`` block (None: the configuration's own drive).
    window : Window
        Speeds, WOBs, samples and durations.
    seed : int, optional
        Seed of the realizations (default ``window.seed``; another one draws new samples).
    threads : int
        OpenMP threads (0: the default).
    deterministic : bool
        Run eta = 0 once per (WOB, speed) instead (the same warm start and durations: the
        deterministic curve of Fig. 4.8); the sample axis then has length 1.

    Returns
    -------
    numpy.ndarray
        SS [-], shape (n_wobs, samples, n_speeds), +inf where the run stalled; sample i is
        realization i of the seed for every drive, speed and WOB (common random numbers).
    """
    seed = validate.seed(window.seed if seed is None else seed)
    out = []
    for w in window.wobs:
        c = study_config(with_overrides(cfg, wob=float(w), top_drive=drive), window.duration, window.transient)
        mc = study_engine(c, _zero_psd if deterministic else window.psd, ETA_DT_S, seed, window.warmup)
        ss, bit = mc.severity_and_bit_speed(list(window.speeds), 0, 1 if deterministic else window.samples,
                                            int(threads))
        out.append(np.where(bit < STALL_FRACTION * window.speeds, np.inf, ss))
    return np.stack(out)


def _zero_psd(f):
    return np.zeros_like(f)


def score(ss: np.ndarray, weights=None) -> tuple[float, float, float]:
    """The tuning objective of a window's SS (module docstring).

    Parameters
    ----------
    ss : numpy.ndarray
        SS [-], shape (n_wobs, samples, n_speeds), +inf for a stalled run.
    weights : array_like, optional
        Weight of each sample (bootstrap counts), shape (samples,); default 1.

    Returns
    -------
    tuple of float
        (score, P(SS > 0.5 or stalled), mean SS of the runs that did not stall).
    """
    w = np.ones(ss.shape[1]) if weights is None else np.asarray(weights, dtype=float)
    norm = w.sum() * ss.shape[0] * ss.shape[2]
    p = float(np.einsum("wsk,s->", (ss > SS_LEVEL).astype(float), w) / norm)
    finite = np.isfinite(ss)
    m = float(np.einsum("wsk,s->", np.where(finite, ss, 0.0), w) / max(np.einsum("wsk,s->", finite, w), 1.0))
    return p + min(m, 4.0) / (4.0 * ss.size), p, m


def stalled_fraction(ss: np.ndarray) -> float:
    """The fraction of a window's runs that stalled.

    Parameters
    ----------
    ss : numpy.ndarray
        What :func:`window_severity` returned.

    Returns
    -------
    float
        Stalled runs / runs.
    """
    return float(np.mean(np.isinf(ss)))


@dataclass
class Tuning:
    """The result of :func:`tune`.

    Attributes
    ----------
    controller : str
        The tuned controller.
    nominal : dict
        The engine's tuning (:func:`drive_gains`).
    gains : dict
        The optimum: the searched keys and their values.
    factors : dict
        The optimum as factors of the nominal gains.
    score, p_stick_slip, mean_ss : float
        The objective at the optimum on the tuning samples (optimistic: selected on them).
    nominal_score, nominal_p, nominal_mean_ss : float
        The same at the nominal tuning (same samples).
    evaluations : list of dict
        Every candidate scored: ``factors`` (log10), ``score``, ``p``, ``mean_ss``.
    spread : dict
        The bootstrap of the optimum (:func:`optimum_spread`).
    at_bound : list of str
        Gains whose optimum lies on a bound of the search range (widen it: ``factor_range``).
    factor_range : tuple of float
        The searched factors (low, high).
    """
    controller: str
    nominal: dict
    gains: dict
    factors: dict
    score: float
    p_stick_slip: float
    mean_ss: float
    nominal_score: float
    nominal_p: float
    nominal_mean_ss: float
    evaluations: list = field(default_factory=list)
    spread: dict = field(default_factory=dict)
    at_bound: list = field(default_factory=list)
    factor_range: tuple = FACTOR_RANGE

    def as_dict(self) -> dict:
        """JSON-ready result.

        Returns
        -------
        dict
            Every field; ``evaluations`` as a list.
        """
        return {"controller": self.controller, "nominal": self.nominal, "gains": self.gains, "factors": self.factors,
                "tuning_samples": {"score": self.score, "p_ss_gt_0_5": self.p_stick_slip, "mean_ss": self.mean_ss,
                                   "nominal_score": self.nominal_score, "nominal_p_ss_gt_0_5": self.nominal_p,
                                   "nominal_mean_ss": self.nominal_mean_ss},
                "spread": self.spread, "at_bound": self.at_bound, "factor_range": list(self.factor_range),
                "evaluations": self.evaluations}


def tune(cfg: dict, controller: str, window: Window, *, inertia: float, torque_limit: float | None = None,
         grid: int = 5, refine_evaluations: int = 24, bootstrap: int = 200, factor_range=FACTOR_RANGE,
         threads: int = 0, progress=None) -> Tuning:
    """Search the gains of ``controller`` minimising the score over ``window`` (module docstring).

    Parameters
    ----------
    cfg : dict
        The configuration (model, law, time step; its drive is replaced).
    controller : str
        ``soft_speed`` or ``z_torque`` (:data:`TUNABLE`).
    window : Window
        Operating window and Monte Carlo setting (the tuning samples).
    inertia : float
        Drive inertia J [kg m^2].
    torque_limit : float, optional
        Motor torque limit [N m] (None: unlimited).
    grid : int
        Points per gain of the coarse log grid over :data:`FACTOR_RANGE` (>= 2).
    refine_evaluations : int
        Most Nelder-Mead evaluations after the grid (0: the grid's best point).
    bootstrap : int
        Bootstrap resamples of the optimum (:func:`optimum_spread`; 0: none).
    factor_range : tuple of float
        (low, high) factors of the nominal gains searched (default :data:`FACTOR_RANGE`); an optimum
        on a bound is flagged in ``Tuning.at_bound``.
    threads : int
        OpenMP threads (0: the default).
    progress : callable, optional
        Called with a short text after each evaluation.

    Returns
    -------
    Tuning
        The optimum, the nominal tuning's score on the same samples and every evaluation.

    Raises
    ------
    ValueError
        For a controller without tunable gains or a bad grid size.
    """
    from scipy.optimize import minimize

    if controller not in TUNABLE:
        raise ValueError(f"controller = {controller!r}: tunable controllers are {', '.join(TUNABLE)}")
    grid = validate.integer("grid", grid, 2, 50)
    refine_evaluations = validate.integer("refine_evaluations", refine_evaluations, 0, 10_000)
    keys = TUNABLE[controller]
    nominal = drive_gains(with_overrides(cfg, top_drive=controlled_drive(controller, inertia, torque_limit)))
    f_lo, f_hi = (validate.positive("factor_range", float(f)) for f in factor_range)
    if not f_lo < 1.0 < f_hi:
        raise ValueError(f"factor_range = ({f_lo:g}, {f_hi:g}): must bracket the nominal tuning (low < 1 < high)")
    lo, hi = math.log10(f_lo), math.log10(f_hi)
    cache: dict[tuple, tuple] = {}
    tables: dict[tuple, np.ndarray] = {}

    def evaluate(x) -> float:
        x = tuple(round(float(np.clip(v, lo, hi)), 6) for v in x)
        if x not in cache:
            gains = {k: nominal[k] * 10.0 ** v for k, v in zip(keys, x)}
            ss = window_severity(cfg, controlled_drive(controller, inertia, torque_limit, gains), window,
                                 threads=threads)
            tables[x] = ss
            cache[x] = score(ss)
            if progress is not None:
                progress(f"{controller} {len(cache)}: " + ", ".join(f"{k} x {10 ** v:.3g}" for k, v in zip(keys, x))
                         + f": P {cache[x][1]:.3f}, mean SS {cache[x][2]:.3f}")
        return cache[x][0]

    axis = np.linspace(lo, hi, grid)
    for a in axis:
        for b in axis:
            evaluate((a, b))
    evaluate((0.0, 0.0))  # the nominal tuning, on the same samples
    best = min(cache, key=lambda x: (cache[x][0], abs(x[0]) + abs(x[1])))
    if refine_evaluations > 0:
        step = 0.5 * (hi - lo) / (grid - 1)
        simplex = np.array([best, (best[0] + step, best[1]), (best[0], best[1] + step)], dtype=float)
        minimize(evaluate, np.array(best, dtype=float), method="Nelder-Mead", bounds=[(lo, hi), (lo, hi)],
                 options={"initial_simplex": np.clip(simplex, lo, hi), "maxfev": refine_evaluations,
                          "xatol": 0.01, "fatol": 0.0})
        best = min(cache, key=lambda x: (cache[x][0], abs(x[0]) + abs(x[1])))
    s, p, m = cache[best]
    ns, npr, nm = cache[(0.0, 0.0)]
    evaluations = [{"log10_factors": dict(zip(keys, x)), "score": v[0], "p_ss_gt_0_5": v[1], "mean_ss": v[2]}
                   for x, v in cache.items()]
    return Tuning(controller, nominal, {k: nominal[k] * 10.0 ** v for k, v in zip(keys, best)},
                  {k: 10.0 ** v for k, v in zip(keys, best)}, s, p, m, ns, npr, nm, evaluations,
                  optimum_spread(tables, keys, bootstrap, window.seed) if bootstrap else {},
                  [k for k, v in zip(keys, best) if min(v - lo, hi - v) < 1e-6], (f_lo, f_hi))


def optimum_spread(tables: dict, keys, resamples: int, seed: int) -> dict:
    """The bootstrap of the optimum: the tuning samples resampled with replacement, every evaluated
    candidate re-scored on the resample (same weights for all: common random numbers), the best
    one kept.

    Parameters
    ----------
    tables : dict
        log10 factors -> SS table (n_wobs, samples, n_speeds) of every evaluated candidate.
    keys : sequence of str
        The searched keys, in the order of the factors.
    resamples : int
        Bootstrap resamples.
    seed : int
        Seed of numpy's generator for the resampling.

    Returns
    -------
    dict
        Per key, the 5 %, 50 % and 95 % quantiles of the resampled optima's factors
        (``{key: {"q05", "q50", "q95"}}``), ``resamples`` and ``distinct_optima`` (how many
        candidates were the optimum of some resample).
    """
    rng = np.random.default_rng([seed, 0x7E5])
    xs = list(tables)
    n = next(iter(tables.values())).shape[1]
    picks = []
    for _ in range(resamples):
        w = rng.multinomial(n, np.full(n, 1.0 / n))
        picks.append(min(xs, key=lambda x: (score(tables[x], w)[0], abs(x[0]) + abs(x[1]))))
    out = {k: {q: float(10.0 ** np.quantile([x[i] for x in picks], v)) for q, v in
               (("q05", 0.05), ("q50", 0.5), ("q95", 0.95))} for i, k in enumerate(keys)}
    return {"factors": out, "resamples": int(resamples), "distinct_optima": len(set(picks))}


def bootstrap_p(ss: np.ndarray, resamples: int, seed: int, reference: np.ndarray | None = None,
                confidence: float = 0.9) -> dict:
    """P(SS > 0.5) over a window with its percentile bootstrap interval (samples resampled), or the
    paired difference to ``reference`` (the same samples with another drive).

    Parameters
    ----------
    ss : numpy.ndarray
        SS [-], shape (n_wobs, samples, n_speeds).
    resamples : int
        Bootstrap resamples.
    seed : int
        Seed of numpy's generator.
    reference : numpy.ndarray, optional
        SS of the same samples with the reference drive; the statistic is then P(ss) - P(reference).
    confidence : float
        Level of the interval.

    Returns
    -------
    dict
        ``value``, ``low``, ``high``, ``confidence``, ``resamples``.
    """
    rng = np.random.default_rng([seed, 0xB007])
    n = ss.shape[1]

    def stat(w=None):
        v = score(ss, w)[1]
        return v - score(reference, w)[1] if reference is not None else v

    draws = [stat(rng.multinomial(n, np.full(n, 1.0 / n))) for _ in range(resamples)]
    a = (1.0 - confidence) / 2.0
    return {"value": stat(), "low": float(np.quantile(draws, a)), "high": float(np.quantile(draws, 1.0 - a)),
            "confidence": confidence, "resamples": int(resamples)}
