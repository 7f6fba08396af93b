"""Single runs, SS sweeps and stability maps through the C++ engine (appendix B)."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from drillpy import _core
from drillpy.model.config import engine_config, to_json_text
from drillpy.progress import progress_bar


@dataclass
class SimulationResult:
    """Time series (SI, absolute frame) and metrics of one run (the fields of the engine's
    ``_core.RunReport``, whose docstrings give their units).

    ``severity`` is SS of Eq. (3.4) over t >= transient; ``stick_durations`` and
    ``slip_durations`` are complete phases after the transient; ``period_cycles`` is the number
    of stick-slip cycles after which the phase durations repeat (0 when no periodic regime).
    ``report`` is the engine's ``_core.RunReport`` the fields come from; :meth:`summary` is the
    run's summary.json content (drill/run_summary.hpp, shared with drillsim).
    """
    t: np.ndarray
    bit_speed: np.ndarray
    bit_accel: np.ndarray
    bit_angle: np.ndarray
    torque_on_bit: np.ndarray
    top_torque: np.ndarray
    top_speed: np.ndarray
    severity: float
    mean_top_speed: float
    stick_fraction: float
    stick_durations: np.ndarray
    slip_durations: np.ndarray
    slip_first: bool
    period_cycles: int
    period_stick: np.ndarray
    period_slip: np.ndarray
    final_q: np.ndarray
    final_qdot: np.ndarray
    config: dict = field(repr=False, default_factory=dict)
    report: "_core.RunReport | None" = field(repr=False, default=None, compare=False)

    def summary(self) -> dict:
        """The run's summary (keys and units of drill/run_summary.hpp, the summary.json of
        ``drillsim --job run`` and ``drillpy simulate`` without ``config`` and ``job``)."""
        if self.report is None:
            raise ValueError("summary: this result holds no engine report")
        return self.report.summary()


#: the fields of SimulationResult that come from the engine's RunReport (RunReport.to_dict keys)
_REPORT_FIELDS = ("t", "bit_speed", "bit_accel", "bit_angle", "torque_on_bit", "top_torque", "top_speed",
                  "severity", "mean_top_speed", "stick_fraction", "stick_durations", "slip_durations",
                  "slip_first", "period_cycles", "period_stick", "period_slip", "final_q", "final_qdot")


def _engine(cfg) -> "_core.Simulation":
    return _core.Simulation(engine_config(cfg))


def simulate(cfg: "dict | _core.Config", top_speed: float | None = None, wob: float | None = None, *,
             top_speed_series=None, wob_series=None, eta_series=None, series_dt: float = 1e-3,
             series_t0: float = 0.0, bit_viscous: float | None = None,
             string_friction: float | None = None, record: bool = True,
             q0=None, qdot0=None, top_speed0: float | None = None,
             start: str = "rest") -> SimulationResult:
    """Run one simulation of ``cfg``.

    top_speed [rad/s] and wob [N] default to the configuration's operation point. Series inputs
    (top speed [rad/s], WOB [N], torque fluctuation eta of Eq. 4.1) are sampled every
    ``series_dt`` seconds from ``series_t0`` and interpolated linearly. ``start="rest"`` starts
    from Eq. (2.10) (bit at rest, string untwisted), ``start="rigid"`` from Eq. (2.3) (the whole
    string turning with the top, untwisted), ``start="steady"`` from steady drilling at the
    initial top speed; ``q0``/``qdot0`` give any reduced state instead (with ``top_speed0`` the
    initial speed of a motor top drive, which otherwise starts at its command).
    ``bit_viscous`` [N m s/rad] and ``string_friction`` [N m] override ``operation.bit_viscous_nms``
    and ``operation.string_friction_nm``; ``torque_on_bit`` leaves the string friction out.
    ``cfg`` is a dict or a ``_core.Config`` (:func:`drillpy.model.config.engine_config`).
    """
    sim = _engine(cfg)
    _check_start(start)
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
    return SimulationResult(**{k: getattr(r, k) for k in _REPORT_FIELDS},
                            config=sim.config.to_dict(), report=r)


#: initial states of a run (``Simulation::start_state`` in simulation.hpp)
START_MODES = ("rest", "rigid", "steady")


def _check_start(start: str) -> None:
    if start not in START_MODES:
        raise ValueError(f"start = {start!r}: use 'rest' (Eq. 2.10), 'rigid' (Eq. 2.3) or 'steady' "
                         "(steady drilling)")


def _opt(x):
    return None if x is None else np.ascontiguousarray(x, dtype=float)


def _grid(values, name: str) -> np.ndarray:
    a = np.atleast_1d(np.asarray(values, dtype=float))
    if a.ndim != 1 or a.size == 0:
        raise ValueError(f"{name} = {values!r}: must be a non-empty 1-D list of numbers")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} = {values!r}: must be finite")
    return a


def sweep_severity(cfg: "dict | _core.Config", speeds, wobs=None, *, progress: bool = True,
                   threads: int = 0, start: str = "rest") -> np.ndarray:
    """SS (Eq. 3.4) for each top speed [rad/s] (and WOB [N]), computed in parallel.

    Every run starts from Eq. (2.10) (``start="rest"``), Eq. (2.3) (``start="rigid"``) or from
    steady drilling (``start="steady"``); between the thresholds the string is bistable.
    Returns shape (len(speeds),) without ``wobs``, else (len(wobs), len(speeds)).
    Ctrl-C stops the sweep (KeyboardInterrupt); the bar goes to stderr.
    """
    _check_start(start)
    sp = _grid(speeds, "speeds")
    wb = None if wobs is None else _grid(wobs, "wobs")
    sim = _engine(cfg)
    total = sp.size * (1 if wb is None else wb.size)
    with progress_bar(total, "SS sweep", progress) as cb:
        out = sim.sweep(list(sp), [] if wb is None else list(wb), cb, threads, start)
    return out[0] if wb is None else out


def stability_map(cfg: dict, speeds_rad_s, wobs_n, *, progress: bool = True,
                  threads: int = 0, start: str = "rest") -> np.ndarray:
    """SS over a WOB x top-speed grid (Figs. 3.11-3.12): shape (len(wobs_n), len(speeds_rad_s))."""
    return sweep_severity(cfg, speeds_rad_s, wobs_n, progress=progress, threads=threads, start=start)


@dataclass
class RefinedThreshold:
    """A stick-slip threshold located by bisection: SS > ``level`` at ``below`` [rad/s] and SS <=
    ``level`` at ``above``; ``threshold`` is their midpoint, ``precision`` half their distance."""
    threshold: float
    precision: float
    below: float
    above: float
    evaluations: list  #: (top speed [rad/s], SS) of every run the refinement made


def refine_threshold(cfg: dict, speeds, severities, *, level: float = 0.5, tol: float = 0.05, threads: int = 0,
                     start: str = "rest", max_rounds: int = 12) -> RefinedThreshold | None:
    """Locate the top speed below which SS > ``level`` to ``tol`` [rad/s] (issue: a linear
    interpolation on a coarse grid is less precise than it reads, and SS jumps at the threshold).

    Starts from the highest grid bracket where SS crosses ``level`` from above and splits it in three
    per round (two runs in parallel), keeping the upper crossing; None without a crossing.
    """
    sp, ss = np.asarray(speeds, float), np.asarray(severities, float)
    if not (isinstance(tol, (int, float)) and math.isfinite(tol) and tol > 0):
        raise ValueError(f"tol = {tol!r}: must be a positive number [rad/s]")
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


def severity_threshold(speeds, severities, level: float = 0.5) -> float | None:
    """Top speed below which SS > level (linear interpolation; None if no crossing)."""
    v = _core.severity_threshold(list(map(float, speeds)), list(map(float, severities)), level)
    return None if math.isnan(v) else v


def natural_frequencies(cfg: dict, n: int) -> np.ndarray:
    """First n natural frequencies [Hz] of the clamped string (Eq. 2.7)."""
    return np.asarray(_core.natural_frequencies(engine_config(cfg), int(n)))


def law_torque(law: dict, speed, acceleration=0.0, wob=None) -> np.ndarray:
    """Torque on bit [N m] of a law (dict as in the config) at SI speed and acceleration."""
    v = np.atleast_1d(np.asarray(speed, dtype=float))
    a = np.broadcast_to(np.asarray(acceleration, dtype=float), v.shape)
    w = np.broadcast_to(np.asarray(law["wob_ref_n"] if wob is None else wob, dtype=float), v.shape)
    T, _, _ = _core.law_torque(to_json_text(law), v, np.ascontiguousarray(a), np.ascontiguousarray(w))
    return T
