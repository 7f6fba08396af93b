"""Convergence studies behind docs/numerics.md (run them with ``drillpy convergence``).

* Space: FE natural frequencies (Eq. 2.7) against the exact frequencies of the continuous
  string (transfer matrices), as the number of elements doubles; linear elements with a
  consistent mass converge at order 2 in the element size.
* Time: bit speed of the modified Euler scheme (appendix A) and of BDF2 against a BDF2 reference
  with a 32x smaller step, as dt halves, in a smooth slipping regime (orders 1 and 2) and in the
  stick-slip regime (where the stick/slip switching limits the order).
"""
from __future__ import annotations

import numpy as np

from drillpy import _core
from drillpy.model.config import engine_config, normalize, with_overrides
from drillpy.model.configuration import Configuration
from drillpy.model.simulation import natural_frequencies, simulate


def observed_orders(h, err) -> list[float]:
    """Observed orders of convergence: log(e1/e2) / log(h1/h2) for successive refinements
    (log2 of the error ratio when the step is halved each time).

    Parameters
    ----------
    h : array_like
        Step sizes, coarsest first (element size [-] or time step [s]).
    err : array_like
        Errors at those steps (same length, positive).

    Returns
    -------
    list of float
        ``len(h) - 1`` orders, one per refinement.
    """
    h, err = np.asarray(h, float), np.asarray(err, float)
    return [float(np.log(err[i - 1] / err[i]) / np.log(h[i - 1] / h[i])) for i in range(1, len(h))]


def space_study(cfg: dict, elements=(25, 50, 100, 200, 400), n_freq: int = 5) -> dict:
    """Spatial convergence: FE natural frequencies (Eq. 2.7) against the exact frequencies of the
    continuous string (transfer matrices) as the number of elements grows.

    Parameters
    ----------
    cfg : dict
        Configuration (string, boundary conditions); only the element count is changed.
    elements : sequence of int
        Numbers of finite elements to try (doubling, for the observed orders).
    n_freq : int
        Number of lowest natural frequencies compared.

    Returns
    -------
    dict
        ``elements``, ``exact_hz`` (the exact frequencies [Hz]), ``max_rel_error`` (largest
        relative error over the ``n_freq`` frequencies, per element count) and ``orders``
        (:func:`observed_orders` with h = 1 / elements; about 2 expected).
    """
    exact = np.asarray(_core.exact_frequencies(engine_config(cfg), n_freq))
    errs = []
    for n in elements:
        f = natural_frequencies(with_overrides(cfg, elements=n), n_freq)
        errs.append(float(np.max(np.abs(f - exact) / exact)))
    h = [1.0 / n for n in elements]
    return {"elements": list(elements), "exact_hz": exact.tolist(), "max_rel_error": errs,
            "orders": observed_orders(h, errs)}


def _with_step(cfg: dict, scheme: str, dt: float, duration: float, sample_every: float) -> dict:
    return normalize(Configuration.of(cfg).replace({
        "simulation.scheme": scheme, "simulation.dt_s": dt, "simulation.duration_s": duration,
        "simulation.transient_s": 0.0, "simulation.output_stride": int(round(sample_every / dt))}))


def time_study(cfg: dict, top_speed: float, duration: float, rigid_start: bool,
               dts=(2e-3, 1e-3, 5e-4, 2.5e-4), sample_every: float = 0.01) -> dict:
    """Time convergence: max |bit speed - reference| over the run for both schemes and each dt.

    The reference is BDF2 with a step 32 times smaller than the smallest of ``dts``. Every run
    keeps its whole length (no transient) and is compared on samples every ``sample_every``
    seconds.

    Parameters
    ----------
    cfg : dict
        Configuration (model, law); its scheme, time step and durations are replaced.
    top_speed : float
        Top speed [rad/s] (e.g. 30 rad/s for smooth slipping, 16 rad/s for stick-slip on the
        thesis field model).
    duration : float
        Simulated time [s].
    rigid_start : bool
        True: start with the whole string turning with the top, untwisted (Eq. 2.3,
        ``q0 = qdot0 = 0``); False: start from rest (Eq. 2.10, :func:`simulate`'s default).
    dts : sequence of float
        Time steps to compare [s], halving.
    sample_every : float
        Output sampling interval of the compared bit speed [s] (every round(sample_every / dt)
        steps, so it should be a multiple of every dt).

    Returns
    -------
    dict
        The settings, ``reference_dt_s``, ``reference_min_bit_speed`` [rad/s] and, for
        "modified_euler" (appendix A) and "bdf2", ``max_error_rad_s`` per dt and the observed
        ``orders``.
    """
    m = Configuration.of(cfg).rom.modes
    start = dict(q0=np.zeros(m), qdot0=np.zeros(m)) if rigid_start else {}
    ref_dt = min(dts) / 32
    ref = simulate(_with_step(cfg, "bdf2", ref_dt, duration, sample_every), top_speed, **start)
    out = {"top_speed_rad_s": top_speed, "duration_s": duration, "rigid_start": rigid_start,
           "dt_s": list(dts), "reference_dt_s": ref_dt,
           "reference_min_bit_speed": float(ref.bit_speed.min())}
    for scheme in ("modified_euler", "bdf2"):
        errs = []
        for dt in dts:
            r = simulate(_with_step(cfg, scheme, dt, duration, sample_every), top_speed, **start)
            errs.append(float(np.max(np.abs(r.bit_speed - ref.bit_speed))))
        out[scheme] = {"max_error_rad_s": errs, "orders": observed_orders(dts, errs)}
    return out


def convergence_report(cfg: dict) -> dict:
    """The convergence studies of docs/numerics.md (``drillpy convergence``).

    Parameters
    ----------
    cfg : dict
        Configuration.

    Returns
    -------
    dict
        ``space`` (:func:`space_study`), ``time_slip`` (30 rad/s for 10 s from a rigid start:
        smooth slipping) and ``time_stick_slip`` (16 rad/s for 20 s: stick-slip), each from
        :func:`time_study`.
    """
    return {"space": space_study(cfg),
            "time_slip": time_study(cfg, 30.0, 10.0, rigid_start=True),
            "time_stick_slip": time_study(cfg, 16.0, 20.0, rigid_start=False)}


def branch_check(cfg: dict, top_speed: float | None = None, *, dt: float | None = None, rel_tol: float = 0.05,
                 threads: int = 0) -> dict:
    """Whether a run's regime depends on its time step: the run at ``dt`` and at ``dt / 2``.

    Next to the stick-slip threshold the field model is bistable (docs/numerics.md): a large step
    of the exact modal scheme can put a run on the other branch (stick-slip instead of a small
    limit cycle, or the reverse). Both runs are made (in parallel); the run is flagged when one
    sticks and the other does not, when their periods differ in cycles, or when their SS (Eq. 3.4)
    differ by more than ``rel_tol`` relative.

    Parameters
    ----------
    cfg : dict
        The configuration (any scheme; the check is meant for ``exact_modal`` at a large step).
    top_speed : float, optional
        Top speed [rad/s] (default: the configuration's).
    dt : float, optional
        The step to check [s] (default: the configuration's ``simulation.dt_s``).
    rel_tol : float
        Relative SS difference that flags the run.
    threads : int
        OpenMP threads (0: the default).

    Returns
    -------
    dict
        ``dt_s`` (dt, dt / 2), ``severity``, ``stick_fraction`` and ``period_cycles`` of both runs,
        ``relative_difference`` of their SS and ``flagged``.
    """
    from drillpy.model.simulation import simulate_many

    c = Configuration.from_dict(cfg)
    step = float(c.simulation.dt_s if dt is None else dt)
    speed = float(c.operation.top_speed_rad_s if top_speed is None else top_speed)
    cfgs = [with_overrides(c, dt=h, top_speed=speed) for h in (step, step / 2)]
    res, err = simulate_many(cfgs, record=False, threads=threads)
    for e in err:
        if e:
            raise RuntimeError(e)
    ss = [float(r.severity) for r in res]
    stick = [float(r.stick_fraction) for r in res]
    cycles = [int(r.period_cycles) for r in res]
    rel = abs(ss[0] - ss[1]) / max(abs(ss[1]), 1e-12)
    flagged = (stick[0] > 0) != (stick[1] > 0) or cycles[0] != cycles[1] or rel > rel_tol
    return {"top_speed_rad_s": speed, "dt_s": [step, step / 2], "severity": ss, "stick_fraction": stick,
            "period_cycles": cycles, "relative_difference": rel, "flagged": bool(flagged)}
