"""Single runs, SS sweeps and stability maps through the C++ engine (appendix B)."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from drillpy import _core, validate
from drillpy.model import plausibility
from drillpy.model.config import engine_config, to_json_text, with_overrides
from drillpy.progress import progress_bar


class SimulationResult:
    """Time series (SI, absolute frame) and metrics of one run: the engine's ``_core.RunReport``
    with the configuration it ran; its fields are the report's, read from it on first use (they
    are declared once, in the engine's binding); :meth:`summary` is the run's summary.json content
    (``drill/run_summary.hpp``, shared with drillsim).

    Attributes
    ----------
    t : ndarray
        Recorded times [s].
    bit_speed, bit_accel, bit_angle : ndarray
        Bit speed [rad/s], acceleration [rad/s^2] and angle [rad].
    torque_on_bit : ndarray
        Torque of the bit-rock law on the bit [N m] (the string friction left out).
    top_torque : ndarray
        Torque the top drive applies [N m].
    top_speed : ndarray
        Top-drive speed [rad/s].
    wob : ndarray
        Weight on bit the law saw [N]: the input, or the axial jack's state (``axial``,
        ``drill/axial.hpp``).
    severity : float
        Stick-slip severity SS, Eq. (3.4), over t >= transient [dimensionless]; NaN when undefined.
    mean_top_speed : float
        Mean top speed over t >= transient [rad/s].
    stick_fraction : float
        Fraction of the time after the transient with the bit stuck.
    stick_durations, slip_durations : ndarray
        Durations of the complete stick and slip phases after the transient [s].
    slip_first : bool
        Whether the first complete phase is a slip phase.
    period_cycles : int
        Stick-slip cycles after which the phase durations repeat (0: no periodic regime found).
    period_stick, period_slip : ndarray
        Stick and slip durations of one period [s].
    final_q, final_qdot : ndarray
        Reduced state (modal coordinates and their rates) at the end of the run.
    config : dict
        The normalized configuration the run used.
    report : _core.RunReport
        The engine's report the fields come from.

    Parameters
    ----------
    report : _core.RunReport
        The engine's report of the run.
    config : dict
        The normalized configuration the run used.
    """

    def __init__(self, report: "_core.RunReport", config: dict):
        self.report = report
        self.config = config

    def __getattr__(self, name: str):
        # the report's fields (t, bit_speed, ..., final_qdot): read once, then kept as attributes
        report = self.__dict__.get("report")
        if report is None or name.startswith("_"):
            raise AttributeError(name)
        value = getattr(report, name)
        self.__dict__[name] = value
        return value

    def __repr__(self) -> str:
        return (f"SimulationResult(severity={self.severity!r}, stick_fraction={self.stick_fraction!r}, "
                f"period_cycles={self.period_cycles!r}, samples={len(self.t)})")

    @property
    def axial(self) -> "_core.AxialReport | None":
        """The axial channels and metrics of a run of the axial-torsional model (``axial.type = rgd``,
        ``drill/axial_torsional.hpp``): WOB [N], rate of penetration [m/s], depth of cut [m], delay
        t_N [s] series and their metrics after the transient (``mean_wob``, ``wob_std``,
        ``mean_rop``, ``rop_std``, ``bounce_fraction``, ``mse``); None for the other models.

        Returns
        -------
        _core.AxialReport or None
            The engine's axial report, or None when the run has no axial degrees of freedom.
        """
        if self.report is None or not self.report.axial.present:
            return None
        return self.report.axial

    def summary(self) -> dict:
        """The run's summary (keys and units of ``drill/run_summary.hpp``, the summary.json of
        ``drillsim --job run`` and ``drillpy simulate`` without ``config`` and ``job``).

        Returns
        -------
        dict
            Severity, stick fraction, phase statistics and period of the run (NaN as None).
        """
        if self.report is None:
            raise ValueError("summary: this result holds no engine report")
        return self.report.summary()


def _engine(cfg) -> "_core.Simulation":
    return _core.Simulation(engine_config(cfg))


def simulate(cfg: "dict | _core.Config", top_speed: float | None = None, wob: float | None = None, *,
             top_speed_series=None, wob_series=None, eta_series=None, series_dt: float = 1e-3,
             series_t0: float = 0.0, bit_viscous: float | None = None,
             string_friction: float | None = None, record: bool = True,
             q0=None, qdot0=None, top_speed0: float | None = None,
             start: str | None = None) -> SimulationResult:
    """Run one simulation (the reduced-order model of Eq. 2.9 driven at the top, the bit-rock
    law of the configuration at the bit).

    Parameters
    ----------
    cfg : dict or _core.Config
        The configuration (:func:`drillpy.model.config.engine_config`).
    top_speed : float, optional
        Top-drive speed [rad/s]; default the configuration's ``operation.top_speed_rad_s``.
    wob : float, optional
        Weight on bit [N]; default ``operation.wob_n``.
    top_speed_series, wob_series : array_like, optional
        Top speed [rad/s] and WOB [N] as time series, sampled every ``series_dt`` from
        ``series_t0`` and interpolated linearly (they replace the constants).
    eta_series : array_like, optional
        Torque fluctuation eta(t) of the stochastic law, Eq. (4.1) [dimensionless], on the same grid.
    series_dt : float
        Sampling interval of the series [s].
    series_t0 : float
        Time of the series' first sample [s].
    bit_viscous : float, optional
        Viscous torque at the bit [N m s/rad]; overrides ``operation.bit_viscous_nms``.
    string_friction : float, optional
        Coulomb torque along the string [N m]; overrides ``operation.string_friction_nm``
        (``torque_on_bit`` leaves it out).
    record : bool
        Keep the time series (False: metrics only, less memory).
    q0, qdot0 : array_like, optional
        Initial reduced state (modal coordinates and rates); overrides ``start``.
    top_speed0 : float, optional
        Initial speed of a motor top drive [rad/s] (otherwise it starts at its command).
    start : str, optional
        ``"rest"``: Eq. (2.10), bit at rest and string untwisted (Algorithm 1's initialization);
        ``"rigid"``: Eq. (2.3), the whole string turning with the top; ``"steady"``: steady
        drilling at the initial top speed and WOB. Default: the configuration's
        ``simulation.start``; given, it is also set there in the result's ``config``.

    Returns
    -------
    SimulationResult
        Time series and metrics of the run.

    Raises
    ------
    ValueError
        Naming the field and the value for an invalid configuration, input or start mode.
    """
    for name, unit, v in (("top_speed", "rad/s", top_speed), ("wob", "N", wob), ("bit_viscous", "N m s/rad", bit_viscous),
                          ("string_friction", "N m", string_friction), ("top_speed0", "rad/s", top_speed0)):
        if v is not None:  # the type only: the ranges are the configuration's (C++) checks
            validate.number(name, v, unit=unit)
    if top_speed is not None:  # a run's own speed bypasses the configuration's check (Config.validate)
        validate.positive("operation.top_speed_rad_s", top_speed, "rad/s")
        plausibility.warn(plausibility.check_speed("top_speed", top_speed))
    if wob is not None:  # so does its own WOB: the configuration's check (the engine's message) and warning
        if wob < 0:
            engine_config(with_overrides(cfg if isinstance(cfg, dict) else cfg.to_dict(), wob=wob))
        plausibility.warn(plausibility.check_value("wob", "wob_n", wob, "a WOB in kN, klbf or kg typed as N?"))
    if start is not None:
        _check_start(start)
        cfg = _with_start(cfg, start)
    sim = _engine(cfg)
    start = sim.config.start
    if start == "steady" and q0 is None:
        om0 = sim.config.top_speed_rad_s if top_speed is None else top_speed
        if top_speed_series is not None:
            om0 = float(np.asarray(top_speed_series, dtype=float)[0])
        w0 = sim.config.wob_n if wob is None else wob
        if wob_series is not None:
            w0 = float(np.asarray(wob_series, dtype=float)[0])
        q0, qdot0, top_speed0 = sim.steady_state(om0, w0, with_top_speed=True)
    if start == "rigid" and q0 is None:
        q0 = qdot0 = np.zeros(sim.reduced_matrices()["M"].shape[0])
    r = sim.run(top_speed=top_speed, wob=wob, top_speed_series=_opt(top_speed_series),
                wob_series=_opt(wob_series), eta_series=_opt(eta_series), series_dt=series_dt,
                series_t0=series_t0, bit_viscous=bit_viscous, string_friction=string_friction,
                record=record,
                q0=_opt(q0), qdot0=_opt(qdot0),
                top_speed0=None if top_speed0 is None else float(top_speed0))
    return SimulationResult(r, sim.config.to_dict())


def simulate_many(cfgs, *, top_speed_series=None, series_dt: float = 1e-3, series_t0: float = 0.0,
                  record: bool = True, threads: int = 0, batched: bool = True):
    """Run several configurations at their operation points, in parallel (``drill/run_many.hpp``).

    Configurations whose models differ at most in their modal damping (a damping scan) step in
    SIMD lockstep, one run per vector lane, where the batched integrator supports them (ideal top
    drive, modified Euler); a run's numbers do not depend on the runs beside it. Otherwise each
    runs through the scalar reference integrator, as :func:`simulate` would.

    Parameters
    ----------
    cfgs : sequence of dict or _core.Config
        The configurations; each run starts as its ``simulation.start`` says.
    top_speed_series : array_like, optional
        Top speed [rad/s] driving every run, sampled every ``series_dt`` from ``series_t0`` [s]
        (default: each configuration's constant ``operation.top_speed_rad_s``).
    series_dt, series_t0 : float
        Sampling of ``top_speed_series`` [s].
    record : bool
        Keep the time series. Runs made in lockstep have empty ``bit_angle`` and ``top_torque``
        (the batched path does not form them).
    threads : int
        OpenMP threads (0: the default).
    batched : bool
        ``False``: every run through the scalar reference integrator.

    Returns
    -------
    results : list of SimulationResult or None
        Per configuration, None where the run failed.
    errors : list of str
        Per configuration, the failed run's error message (e.g. diverged at a time), else ``""``.

    Raises
    ------
    ValueError
        Naming the field and the value for an invalid configuration or series.
    """
    sims = [_engine(c) for c in cfgs]
    reports, errors = _core.run_many(sims, _opt(top_speed_series), series_dt, series_t0, bool(record), int(threads),
                                     bool(batched))
    results = [None if r is None else SimulationResult(r, s.config.to_dict()) for s, r in zip(sims, reports)]
    return results, list(errors)


#: initial states of a run (``Simulation::start_state`` in simulation.hpp)
START_MODES = ("rest", "rigid", "steady")


def _check_start(start: str | None) -> None:
    if start is not None and start not in START_MODES:
        raise ValueError(f"start = {start!r}: use 'rest' (Eq. 2.10), 'rigid' (Eq. 2.3) or 'steady' "
                         "(steady drilling)")


def _with_start(cfg, start: str):
    """``cfg`` (dict or ``_core.Config``) starting as ``start`` says (``simulation.start``)."""
    c = engine_config(cfg)
    if c.start == start:
        return c
    return engine_config(with_overrides(c.to_dict(), start=start))


def _opt(x):
    return None if x is None else np.ascontiguousarray(x, dtype=float)


def _grid(values, name: str) -> np.ndarray:
    try:
        a = np.atleast_1d(np.asarray(values, dtype=float))
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {values!r}: must be a non-empty 1-D list of numbers") from None
    if a.ndim != 1 or a.size == 0:
        raise ValueError(f"{name} = {values!r}: must be a non-empty 1-D list of numbers")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} = {values!r}: must be finite")
    return a


def sweep_severity(cfg: "dict | _core.Config", speeds, wobs=None, *, progress: bool = True,
                   threads: int = 0, start: str | None = None, batched: bool = True) -> np.ndarray:
    """The stick-slip severity SS (Eq. 3.4) at each top speed (and WOB), runs in parallel.

    Parameters
    ----------
    cfg : dict or _core.Config
        The configuration.
    speeds : array_like
        Top-drive speeds [rad/s].
    wobs : array_like, optional
        Weights on bit [N]; default the configuration's.
    progress : bool
        Show a progress bar on stderr.
    threads : int
        OpenMP threads (0: the default).
    start : str, optional
        Initial state of every run: ``"rest"`` (Eq. 2.10), ``"rigid"`` (Eq. 2.3) or ``"steady"``;
        between the thresholds the string is bistable, so the start decides. Default: the
        configuration's ``simulation.start``.
    batched : bool
        Step the runs in SIMD lockstep, one run per vector lane, where the batched integrator
        supports the configuration (ideal top drive, modified Euler, diagonal damping); a run's
        result does not depend on the runs that share its batch. ``False``: one run at a time
        through the scalar reference integrator (the two agree to rounding: SS within 1e-4).

    Returns
    -------
    ndarray
        SS, shape (len(speeds),) without ``wobs``, else (len(wobs), len(speeds)).

    Raises
    ------
    KeyboardInterrupt
        On Ctrl-C (the engine stops at its next chunk).
    """
    _check_start(start)
    sp = _grid(speeds, "speeds")
    wb = None if wobs is None else _grid(wobs, "wobs")
    plausibility.warn(plausibility.check_speed("speeds (highest)", float(np.max(sp))))
    sim = _engine(cfg)
    total = sp.size * (1 if wb is None else wb.size)
    with progress_bar(total, "SS sweep", progress) as cb:
        out = sim.sweep(list(sp), [] if wb is None else list(wb), cb, threads, start, bool(batched))
    return out[0] if wb is None else out


def stability_map(cfg: dict, speeds_rad_s, wobs_n, *, progress: bool = True,
                  threads: int = 0, start: str | None = None) -> np.ndarray:
    """SS (Eq. 3.4) over a WOB x top-speed grid: the stability maps of Figs. 3.11-3.12.

    Parameters
    ----------
    cfg : dict or _core.Config
        The configuration.
    speeds_rad_s : array_like
        Top-drive speeds [rad/s].
    wobs_n : array_like
        Weights on bit [N].
    progress : bool
        Show a progress bar on stderr.
    threads : int
        OpenMP threads (0: the default).
    start : str, optional
        Initial state of every run (see :func:`sweep_severity`; default the configuration's).

    Returns
    -------
    ndarray
        SS, shape (len(wobs_n), len(speeds_rad_s)).
    """
    return sweep_severity(cfg, speeds_rad_s, wobs_n, progress=progress, threads=threads, start=start)


@dataclass
class RefinedThreshold:
    """A stick-slip threshold located by bisection.

    Attributes
    ----------
    threshold : float
        Midpoint of the final bracket [rad/s].
    precision : float
        Half the final bracket's width [rad/s].
    below : float
        Top speed with SS > level [rad/s].
    above : float
        Top speed with SS <= level [rad/s].
    evaluations : list
        (top speed [rad/s], SS) of every run the refinement made.
    """
    threshold: float
    precision: float
    below: float
    above: float
    evaluations: list


def refine_threshold(cfg: dict, speeds, severities, *, level: float = 0.5, tol: float = 0.05, threads: int = 0,
                     start: str | None = None, max_rounds: int = 12) -> RefinedThreshold | None:
    """The top speed below which SS > ``level``, located to ``tol`` by new runs (a linear
    interpolation on a coarse grid is less precise than it reads, and SS jumps at the threshold).

    Starts from the highest grid bracket where SS crosses ``level`` from above and splits it in
    three per round (two runs in parallel), keeping the upper crossing.

    Parameters
    ----------
    cfg : dict or _core.Config
        The configuration.
    speeds : array_like
        The grid's top speeds [rad/s].
    severities : array_like
        SS at those speeds (e.g. from :func:`sweep_severity` with the same ``start``).
    level : float
        The SS level (0.5: the thesis's stick-slip threshold).
    tol : float
        Half-width of the final bracket [rad/s].
    threads : int
        OpenMP threads (0: the default).
    start : str, optional
        Initial state of every run (see :func:`sweep_severity`; default the configuration's).
    max_rounds : int
        At most this many rounds of two runs.

    Returns
    -------
    RefinedThreshold or None
        None when SS does not cross ``level`` from above on the grid.
    """
    sp, ss = np.asarray(speeds, float), np.asarray(severities, float)
    validate.positive("tol", tol, "rad/s")
    _no_nan(sp, ss)
    order = np.argsort(sp)
    sp, ss = sp[order], ss[order]
    k = [i for i in range(sp.size - 1) if ss[i] > level >= ss[i + 1]]
    if not k:
        return None
    lo, hi = float(sp[k[-1]]), float(sp[k[-1] + 1])
    evals = []
    for _ in range(max_rounds):
        if 0.5 * (hi - lo) <= tol:
            break
        pts = [lo + (hi - lo) / 3.0, lo + 2.0 * (hi - lo) / 3.0]
        v = sweep_severity(cfg, pts, progress=False, threads=threads, start=start)
        evals += list(zip(pts, map(float, v)))
        if v[1] > level:      # still stick-slip at 2/3: the crossing is above it
            lo = pts[1]
        elif v[0] > level:    # between the two points
            lo, hi = pts[0], pts[1]
        else:                 # already smooth at 1/3
            hi = pts[0]
    return RefinedThreshold(0.5 * (lo + hi), 0.5 * (hi - lo), lo, hi, evals)


def _no_nan(speeds, severities) -> None:
    sp, ss = np.asarray(speeds, float).ravel(), np.asarray(severities, float).ravel()
    bad = np.flatnonzero(np.isnan(ss))
    if bad.size:
        at = f" at {sp[bad[0]]:g} rad/s" if sp.size == ss.size else ""
        raise ValueError(f"severities[{bad[0]}] = nan{at}: SS is not a number ({bad.size} of {ss.size}; a failed "
                         "run?): a crossing cannot be located through it")


def severity_threshold(speeds, severities, level: float = 0.5) -> float | None:
    """The top speed below which SS > ``level``, by linear interpolation on the grid.

    Parameters
    ----------
    speeds : array_like
        Top speeds [rad/s].
    severities : array_like
        SS at those speeds.
    level : float
        The SS level (0.5: the thesis's threshold).

    Returns
    -------
    float or None
        The crossing [rad/s]; None without one.

    Raises
    ------
    ValueError
        Naming the first NaN SS and its speed (a crossing through a missing value is no answer).
    """
    _no_nan(speeds, severities)
    v = _core.severity_threshold(list(map(float, speeds)), list(map(float, severities)), level)
    return None if math.isnan(v) else v


def severity_crossings(speeds, severities, level: float = 0.5) -> list[dict]:
    """Every crossing of the SS curve through ``level``, with its direction, by linear
    interpolation on the grid (increasing speed).

    A ``"falling"`` crossing (SS > ``level`` just below it, <= ``level`` just above) is the
    thesis's case: stick-slip below the speed; the last one is :func:`severity_threshold`. A
    ``"rising"`` crossing (SS <= ``level`` below, > ``level`` above) bounds stick-slip from below:
    stick-slip above the speed.

    Parameters
    ----------
    speeds : array_like
        Top speeds [rad/s] (any order; sorted here).
    severities : array_like
        SS at those speeds.
    level : float
        The SS level (0.5: the thesis's threshold).

    Returns
    -------
    list of dict
        ``{"speed_rad_s": float, "direction": "falling" | "rising"}`` in increasing speed; empty
        when SS stays on one side of ``level`` over the grid.

    Raises
    ------
    ValueError
        If ``severities`` has not one value per speed.
    """
    sp, ss = np.asarray(speeds, float).ravel(), np.asarray(severities, float).ravel()
    if sp.size != ss.size:
        raise ValueError(f"severities has {ss.size} values for {sp.size} speeds: one per speed needed")
    _no_nan(sp, ss)
    order = np.argsort(sp, kind="stable")
    sp, ss = sp[order], ss[order]
    out = []
    for i in range(sp.size - 1):
        a, b = ss[i], ss[i + 1]
        if (a > level) == (b > level):
            continue
        f = (a - level) / (a - b)
        out.append({"speed_rad_s": float(sp[i] + f * (sp[i + 1] - sp[i])),
                    "direction": "falling" if a > level else "rising"})
    return out


def natural_frequencies(cfg: dict, n: int) -> np.ndarray:
    """The first natural frequencies of the string clamped at the top, free at the bit (Eq. 2.7).

    Parameters
    ----------
    cfg : dict or _core.Config
        The configuration (its finite-element mesh).
    n : int
        How many frequencies.

    Returns
    -------
    ndarray
        Frequencies [Hz], ascending.
    """
    return np.asarray(_core.natural_frequencies(engine_config(cfg), int(n)))


def law_torque(law: dict, speed, acceleration=0.0, wob=None) -> np.ndarray:
    """The torque on bit of a bit-rock law (Eqs. 3.1-3.3, 5.1-5.3).

    Parameters
    ----------
    law : dict
        The ``law`` section of a configuration (docs/units.md).
    speed : array_like
        Bit speed [rad/s].
    acceleration : float or array_like
        Bit acceleration [rad/s^2] (the hysteretic laws' branch, Eq. 3.3).
    wob : float or array_like, optional
        Weight on bit [N]; default the law's ``wob_ref_n``.

    Returns
    -------
    ndarray
        Torque on bit [N m].
    """
    v = np.atleast_1d(np.asarray(speed, dtype=float))
    a = np.broadcast_to(np.asarray(acceleration, dtype=float), v.shape)
    w = np.broadcast_to(np.asarray(law["wob_ref_n"] if wob is None else wob, dtype=float), v.shape)
    T, _, _ = _core.law_torque(to_json_text(law), v, np.ascontiguousarray(a), np.ascontiguousarray(w))
    return T
