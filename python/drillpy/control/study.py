"""The study of ``drillpy control`` computed (nothing drawn or written; issue 15, items 2-4; docs/control.md).

:func:`control_study` tunes each controller on the tuning samples
(:func:`drillpy.control.tuning.tune`), then compares the ideal drive, the stiff PI, the nominal
and tuned controllers on new samples (:func:`drillpy.control.comparison.compare_drives`), and runs
a stick-slip episode and the motor torque per speed (:mod:`drillpy.control.episode`).
:func:`drillpy.figures.control.control_figures` draws a :class:`ControlStudy`;
:func:`drillpy.reports.control.write_control` writes ``control.json``, ``report.md`` and the figures.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from drillpy.model.configuration import Configuration
from drillpy.control.comparison import compare_drives, json_ready, nominal_index
from drillpy.control.episode import run_episode
from drillpy.control.tuning import FACTOR_RANGE, TUNABLE, Window, controlled_drive, tune


#: the drive every difference is taken to: the stiff PI (the thesis's constant top speed, with inertia)
REFERENCE = "stiff"


@dataclass
class ControlStudy:
    """Everything ``drillpy control`` computes.

    Attributes
    ----------
    config : dict
        The configuration (its own drive: the ``ideal`` entry).
    inertia : float
        Drive inertia J [kg m^2].
    torque_limit : float or None
        Motor torque limit [N m].
    tuning_window, validation_window : Window
        The tuning and the validation samples (same speeds, WOBs, durations; other seed and count).
    tunings : dict
        Controller -> :class:`drillpy.control.tuning.Tuning`.
    drives : dict
        Label -> ``top_drive`` block compared.
    comparison : dict
        :func:`drillpy.control.comparison.compare_drives`'s result.
    episode_speed : float
        Top speed of the episodes [rad/s].
    episodes : dict
        Label -> :class:`drillpy.control.episode.Episode` at ``episode_speed``.
    motor_torque : dict
        Label -> per speed of the window, the deterministic run's ``summary`` (peak motor torque...).
    factor_range : tuple of float
        The searched factors of the nominal gains.
    """
    config: dict
    inertia: float
    torque_limit: float | None
    tuning_window: Window
    validation_window: Window
    tunings: dict
    drives: dict
    comparison: dict
    episode_speed: float
    episodes: dict
    motor_torque: dict = field(default_factory=dict)
    factor_range: tuple = FACTOR_RANGE


def control_study(cfg: dict, *, inertia: float, torque_limit: float | None, window: Window,
                  validation_samples: int, validation_seed: int, controllers=tuple(TUNABLE), grid: int = 5,
                  refine_evaluations: int = 16, bootstrap: int = 400, factor_range=FACTOR_RANGE, threads: int = 0,
                  progress=None) -> ControlStudy:
    """Tune, compare on new samples, and run the episodes (module docstring).

    Parameters
    ----------
    cfg : dict
        The configuration (e.g. the ``thesis-field`` preset); its operating point is the nominal one.
    inertia : float
        Drive inertia J [kg m^2].
    torque_limit : float or None
        Motor torque limit L [N m] of every controlled drive.
    window : Window
        Operating window and the tuning samples.
    validation_samples : int
        Samples of the comparison (drawn with ``validation_seed``).
    validation_seed : int
        Seed of the comparison's samples (must differ from ``window.seed``).
    controllers : sequence of str
        Controllers to tune (:data:`drillpy.control.tuning.TUNABLE`).
    grid : int
        Coarse grid points per gain.
    refine_evaluations : int
        Nelder-Mead evaluations after the grid.
    bootstrap : int
        Bootstrap resamples (the optimum's spread, every interval).
    factor_range : tuple of float
        Factors of the nominal gains searched (:func:`drillpy.control.tuning.tune`).
    threads : int
        OpenMP threads (0: the default).
    progress : callable, optional
        Called with a short text as the study goes.

    Returns
    -------
    ControlStudy
        The tunings, the comparison, the episodes and the motor torques.

    Raises
    ------
    ValueError
        When the validation seed is the tuning seed, or for an unknown controller.
    """
    if validation_seed == window.seed:
        raise ValueError(f"validation_seed = {validation_seed}: must differ from the tuning seed (new samples)")
    for c in controllers:
        if c not in TUNABLE:
            raise ValueError(f"controllers: {c!r} is not tunable (use {', '.join(TUNABLE)})")
    tunings = {c: tune(cfg, c, window, inertia=inertia, torque_limit=torque_limit, grid=grid,
                       refine_evaluations=refine_evaluations, bootstrap=bootstrap, factor_range=factor_range,
                       threads=threads,
                       progress=progress) for c in controllers}
    drives = {"ideal": None, REFERENCE: controlled_drive("stiff", inertia, torque_limit)}
    for c, t in tunings.items():
        drives[c] = controlled_drive(c, inertia, torque_limit)
        drives[f"{c}_tuned"] = controlled_drive(c, inertia, torque_limit, t.gains)
    val = Window(window.speeds, window.wobs, validation_samples, validation_seed, window.warmup, window.duration,
                 window.transient, window.psd)
    comp = compare_drives(cfg, drives, val, reference=REFERENCE, validation_seed=validation_seed,
                          bootstrap=bootstrap, threads=threads, progress=progress)
    k = nominal_index(window, Configuration.of(cfg).operation.wob_n)
    wob = float(window.wobs[k])
    speed = episode_speed(window.speeds, comp, tunings)
    episodes = {label: run_episode(cfg, label, drives[label], speed, wob)
                for label in ["ideal", REFERENCE, *(f"{c}_tuned" for c in tunings)]}
    t0 = Configuration.of(cfg).simulation.transient_s
    motor = {label: [run_episode(cfg, label, d, float(s), wob).summary(t0) for s in window.speeds]
             for label, d in drives.items()}
    return ControlStudy(cfg, float(inertia), torque_limit, window, val, tunings, drives, comp, speed, episodes, motor,
                        tuple(factor_range))


def episode_speed(speeds: np.ndarray, comparison: dict, tunings: dict) -> float:
    """The episodes' top speed: the lowest speed of the window where the stiff drive stick-slips
    (deterministic SS > 0.5 at the nominal WOB's row of the maps) and a tuned controller does not;
    else the lowest speed where the stiff drive stick-slips; else the lowest speed.

    Parameters
    ----------
    speeds : numpy.ndarray
        The window's speeds [rad/s].
    comparison : dict
        :func:`drillpy.control.comparison.compare_drives`'s result.
    tunings : dict
        The tuned controllers.

    Returns
    -------
    float
        The speed [rad/s].
    """
    row = comparison[REFERENCE]["nominal_row"]
    stiff = comparison[REFERENCE]["map"][row]
    tuned = np.min([comparison[f"{c}_tuned"]["map"][row] for c in tunings], axis=0) if tunings else stiff
    for cond in (stiff > 0.5) & (tuned < 0.5), stiff > 0.5:
        if np.any(cond):
            return float(speeds[np.argmax(cond)])
    return float(speeds[0])


def summary(study: ControlStudy) -> dict:
    """``control.json``: the tunings, the comparison and the episodes, in JSON types.

    Parameters
    ----------
    study : ControlStudy
        What :func:`control_study` returned.

    Returns
    -------
    dict
        ``preset``, ``inertia_kg_m2``, ``torque_limit_nm``, ``reference``, ``tuning_window``,
        ``validation_window``, ``tunings``, ``drives``, ``comparison``, ``episode_speed_rad_s``,
        ``episodes`` (summaries), ``motor_torque`` and ``config``.
    """
    t0 = Configuration.of(study.config).simulation.transient_s
    return {"preset": study.config.get("name"), "inertia_kg_m2": study.inertia,
            "torque_limit_nm": study.torque_limit, "reference": REFERENCE,
            "tuning_window": study.tuning_window.as_dict(), "validation_window": study.validation_window.as_dict(),
            "tunings": {c: t.as_dict() for c, t in study.tunings.items()}, "drives": study.drives,
            "comparison": json_ready(study.comparison), "episode_speed_rad_s": study.episode_speed,
            "episodes": {k: e.summary(t0) for k, e in study.episodes.items()}, "motor_torque": study.motor_torque,
            "config": study.config}
