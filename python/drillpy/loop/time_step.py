"""The loop's engine step: the coarsest step whose horizon predictions stay within a stated accuracy
of the declared step's (issue 33, "a step-size rule that keeps a stated accuracy").

The declared configuration's step serves long runs from rest (``thesis-rig``: 1e-4 s); the loop's
horizons restart every 0.25 s from a measured state, and their predictions converge at coarser steps
on some records and not on others (the declared model's d below at 2.5e-4 s: 0.0033 on sample 175; at
2e-4 s already 0.0040 on the Stribeck rig's record, ``benchmarks/loop_timestep.py``). The rule
measures it, record by record:

    d(h) = max over the parts P (calibration, validation) of
           sqrt(mean_c mean_(horizons in P, samples) ((y_c(h) - y_c(h_0)) / s_c)^2)

the RMS difference between the predictions of one model at a step h and at the declared step h_0, per
channel c (bit speed, torque and, with a top-speed channel, top speed) in units of the spreads s_c
that E divides by (:func:`drillpy.loop.model.score`). E of a part is the same RMS norm of that part's
residual (with the top speed's term zero where it is not a measurement, which only shrinks it), so
the triangle inequality bounds what the step does to it: |E(h) - E(h_0)| <= d(h) on either part, for
every model whose d is measured. The loop takes the coarsest step h (dividing the analysis interval, at least
twice the declared one) with d(h) <= :data:`STEP_TOLERANCE` for the declared model before its
calibration, confirms it on the calibrated baseline (or returns to the declared step) and reports
d(h) of the final model (``loop.json`` -> ``time_step``).
"""
from __future__ import annotations

import math

import numpy as np

from .data import LoopData
from .model import LoopModel, predict
from .options import STEP_TOLERANCE
#: Coarser steps tried, as multiples of the declared one (each rounded to a divisor of the analysis interval).
FACTORS = (2.0, 2.5, 4.0, 5.0, 10.0, 20.0, 25.0, 50.0, 100.0)


def at_step(model: LoopModel, dt_s: float) -> LoopModel:
    """A copy of ``model`` whose engine step is ``dt_s`` [s] (nothing else changed).

    Parameters
    ----------
    model : LoopModel
        The model.
    dt_s : float
        The engine step [s].

    Returns
    -------
    LoopModel
    """
    m = model.copy()
    m.cfg["simulation"]["dt_s"] = float(dt_s)
    return m


def candidate_steps(analysis_dt: float, declared_dt: float) -> list:
    """The coarser steps the rule tries, ascending [s]: ``analysis_dt`` / k for the integers k nearest
    below ``analysis_dt`` / (f ``declared_dt``), f in :data:`FACTORS`, each at least twice ``declared_dt``
    and at most ``analysis_dt``.

    Parameters
    ----------
    analysis_dt : float
        The analysis sampling interval [s].
    declared_dt : float
        The declared engine step [s] (after :func:`drillpy.loop.run.analysis_config`).

    Returns
    -------
    list of float
    """
    k0 = max(1, math.ceil(analysis_dt / declared_dt - 1e-9))
    ks = sorted({max(1, math.floor(k0 / f + 1e-9)) for f in FACTORS if k0 / f >= 1.0 - 1e-9}, reverse=True)
    return [analysis_dt / k for k in ks if analysis_dt / k >= 2.0 * declared_dt * (1 - 1e-9)]


def step_difference(model: LoopModel, data: LoopData, dt_s: float, reference=None, threads: int = 0) -> float:
    """d(h) of the module's docstring: the RMS difference between the model's horizon predictions at
    ``dt_s`` and at its own step, in units of E's spreads [-].

    Parameters
    ----------
    model : LoopModel
        The model (at its own step, the reference).
    data : LoopData
        The record on the analysis grid.
    dt_s : float
        The step compared [s].
    reference : tuple, optional
        ``predict(model, data, top=True)`` when already at hand.
    threads : int
        Engine threads.

    Returns
    -------
    float
        d [-] (the larger of the two parts'); inf where the coarser step's predictions are not finite
        (beyond the scheme's bound).
    """
    ref = reference if reference is not None else predict(model, data, threads=threads, top=True)
    try:
        got = predict(at_step(model, dt_s), data, threads=threads, top=True, check=False)
    except (ValueError, RuntimeError):  # a step the engine refuses (its stability bound)
        return math.inf
    scales = (data.sigma_v, data.sigma_T, data.sigma_v)[:3 if data.has_top else 2]
    sq = sum(np.mean(((g - r) / s) ** 2, axis=1) for g, r, s in zip(got, ref, scales)) / len(scales)  # per horizon
    d = max(float(np.sqrt(np.mean(sq[part]))) for part in (~data.is_test, data.is_test) if part.any())
    return d if math.isfinite(d) else math.inf


def choose_step(model: LoopModel, data: LoopData, tolerance: float = STEP_TOLERANCE, threads: int = 0) -> tuple:
    """The coarsest step of :func:`candidate_steps` whose d(h) is within ``tolerance``, trying them in
    ascending order and stopping at the first beyond it.

    Parameters
    ----------
    model : LoopModel
        The model the differences are measured on (at the declared step).
    data : LoopData
        The record on the analysis grid.
    tolerance : float
        The largest d [-] a step may have.
    threads : int
        Engine threads.

    Returns
    -------
    tuple
        (step [s], its d [-], the steps tried as a list of (step [s], d [-])); the model's own step
        and d 0 when none passes.
    """
    h0 = float(model.cfg["simulation"]["dt_s"])
    ref = predict(model, data, threads=threads, top=True)
    best, tried = (h0, 0.0), []
    for h in candidate_steps(data.dt, h0):
        d = step_difference(model, data, h, ref, threads)
        tried.append((h, d))
        if d > tolerance:
            break
        best = (h, d)
    return best[0], best[1], tried
