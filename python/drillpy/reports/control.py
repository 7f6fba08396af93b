"""``drillpy control``: robust tuning of top-drive controllers and the drives side by side
(issue 15, items 2-4; docs/control.md).

:func:`control_study` tunes each controller on the tuning samples
(:func:`drillpy.control.tuning.tune`), then compares the ideal drive, the stiff PI, the nominal
and tuned controllers on new samples (:func:`drillpy.control.comparison.compare_drives`), and runs
a stick-slip episode and the motor torque per speed (:mod:`drillpy.control.episode`).
:func:`write_control` writes ``control.json``, ``report.md`` and the figures.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from drillpy.outputs import write_text
from drillpy.control.comparison import compare_drives, json_ready, nominal_index
from drillpy.control.episode import run_episode
from drillpy.control.tuning import FACTOR_RANGE, TUNABLE, UNITS, Window, controlled_drive, tune
from drillpy.jsonio import dumps
from drillpy.provenance import provenance, with_markdown_footer
from drillpy.reports.text import number_text

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
    k = nominal_index(window, cfg["operation"]["wob_n"])
    wob = float(window.wobs[k])
    speed = episode_speed(window.speeds, comp, tunings)
    episodes = {label: run_episode(cfg, label, drives[label], speed, wob)
                for label in ["ideal", REFERENCE, *(f"{c}_tuned" for c in tunings)]}
    t0 = cfg["simulation"]["transient_s"]
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
    t0 = study.config["simulation"]["transient_s"]
    return {"preset": study.config.get("name"), "inertia_kg_m2": study.inertia,
            "torque_limit_nm": study.torque_limit, "reference": REFERENCE,
            "tuning_window": study.tuning_window.as_dict(), "validation_window": study.validation_window.as_dict(),
            "tunings": {c: t.as_dict() for c, t in study.tunings.items()}, "drives": study.drives,
            "comparison": json_ready(study.comparison), "episode_speed_rad_s": study.episode_speed,
            "episodes": {k: e.summary(t0) for k, e in study.episodes.items()}, "motor_torque": study.motor_torque,
            "config": study.config}


def _threshold_text(r: dict) -> str:
    """A drive's deterministic threshold [rad/s] with its bisection precision and its RPM equivalent."""
    t = r["deterministic_threshold"]
    if t["threshold_rad_s"] is None:
        return "none in window"
    return (f"{t['threshold_rad_s']:.2f} +- {t['threshold_precision_rad_s']:.2f} "
            f"({t['threshold_rpm']:.1f} +- {t['threshold_precision_rpm']:.1f} RPM)")


def report_text(study: ControlStudy) -> str:
    """The Markdown report (``report.md``).

    Parameters
    ----------
    study : ControlStudy
        What :func:`control_study` returned.

    Returns
    -------
    str
        The report, without the provenance footer.
    """
    c, tw, vw = study.comparison, study.tuning_window, study.validation_window
    lines = [f"# Top-drive control under uncertainty: {study.config.get('name', '')}", "",
             f"Drive inertia J = {study.inertia:g} kg m^2; motor torque limit "
             f"{'none' if study.torque_limit is None else f'{study.torque_limit:g} N m'}. Operating window: speeds "
             f"{', '.join(f'{s:.4g}' for s in tw.speeds)} rad/s x WOB {', '.join(f'{w / 1e3:g}' for w in tw.wobs)} kN. "
             f"Uncertainty: the chapter-4 stochastic bit-rock law (Eq. 4.1; eta's PSD {tw.psd.as_dict()}), runs of {tw.duration:g} s "
             f"after a {tw.warmup:g} s deterministic warm start, SS after {tw.transient:g} s.", "",
             f"Tuning: {tw.samples} samples (seed {tw.seed}) per (speed, WOB), common random numbers. "
             f"Comparison: {vw.samples} new samples (seed {vw.seed}), the same for every drive.", "",
             "## Tuned gains", "",
             f"Searched: each gain x {study.factor_range[0]:g} to x {study.factor_range[1]:g} of the nominal tuning "
             "(log scale). A gain on a bound of that range is flagged: the best value may lie beyond it.", "",
             "| controller | gain | nominal | tuned | factor | bootstrap 5-95 % of the factor | P tuning samples: nominal -> tuned |",
             "|---|---|---|---|---|---|---|"]
    for name, t in study.tunings.items():
        for key in TUNABLE[name]:
            sp = t.spread.get("factors", {}).get(key)
            band = f"{sp['q05']:.3g} - {sp['q95']:.3g}" if sp else "n/a"
            bound = " (**on the search bound**)" if key in t.at_bound else ""
            lines.append(f"| {name} | {key} [{UNITS[key]}] | {t.nominal[key]:.4g} | {t.gains[key]:.4g} | "
                         f"{t.factors[key]:.3g}{bound} | {band} | {t.nominal_p:.3f} -> {t.p_stick_slip:.3f} |")
    lines += ["", "## The drives on new samples", "",
              "P = P(SS > 0.5 or stalled) over the whole window (90 % Wilson interval, the samples as trials); a run "
              "is stalled when "
              "its mean bit speed is below half the command (the bit stuck, SS then small). The difference to the "
              "stiff drive is paired (same samples). Threshold: the speed below which the deterministic SS > 0.5 "
              "at the nominal WOB, located by bisection from the window's speeds with its precision (half the "
              "final bracket) and its RPM equivalent: drillpy sweep's definition, so `drillpy sweep` with the "
              "same drive and WOB gives the same value; 5 % speed: the lowest speed from which P <= 5 % "
              "(section 4.2.2) with its 90 % bootstrap interval.", "",
              "| drive | P window | P - P(stiff) | stalled runs | mean SS | deterministic threshold, bisection [rad/s] | "
              "5 % speed [rad/s] |",
              "|---|---|---|---|---|---|---|"]
    for label, r in c.items():
        pw, pd, iv = r["p_window"], r["p_vs_reference"], r["p05_interval"]
        p05 = (f"{r['p05_speed_rad_s']:.2f} [{number_text(iv['low'], '.2f')}, {number_text(iv['high'], '.2f')}]"
               if r["p05_speed_rad_s"] is not None else r["p05_reading"])
        lines.append(f"| {label} | {pw['value']:.3f} [{pw['low']:.3f}, {pw['high']:.3f}] | "
                     f"{pd['value']:+.3f} [{pd['low']:+.3f}, {pd['high']:+.3f}] | {r['stalled_fraction']:.3f} | "
                     f"{r['mean_ss']:.3f} | "
                     f"{_threshold_text(r)} | {p05} |")
    t0 = study.config["simulation"]["transient_s"]
    lines += ["", f"## Stick-slip episode at {study.episode_speed:.4g} rad/s (nominal WOB)", "",
              "| drive | SS | stick fraction | peak motor torque [N m] | mean motor torque [N m] | within limit |",
              "|---|---|---|---|---|---|"]
    for label, e in study.episodes.items():
        s = e.summary(t0)
        within = "n/a" if s["within_limit"] is None else ("yes" if s["within_limit"] else "NO")
        lines.append(f"| {label} | {s['ss']:.3f} | {s['stick_fraction']:.3f} | {s['peak_motor_torque_nm']:.4g} | "
                     f"{s['mean_motor_torque_nm']:.4g} | {within} |")
    lines += ["", "## Peak motor torque per speed (deterministic runs, nominal WOB) [N m]", "",
              "| drive | " + " | ".join(f"{s:.4g}" for s in tw.speeds) + " |", "|---|" + "---|" * len(tw.speeds)]
    for label, rows in study.motor_torque.items():
        lines.append(f"| {label} | " + " | ".join(f"{r['peak_motor_torque_nm']:.3g}" for r in rows) + " |")
    lines += ["", "Motor torque: the interval mean of u = J Omega' + T_top on the recorded series "
              "(drillpy.control.episode); the ideal drive's is the string's top torque.", "",
              "Figures: maps.png (deterministic SS per drive), p_vs_speed.png (P(SS > 0.5) at the nominal WOB, "
              "Wilson 90 % bands), episode.png (bit speed, top speed, motor torque), tuning_*.png (the score of every "
              "evaluated gain pair)."]
    return "\n".join(lines) + "\n"


def write_control(study: ControlStudy, out_dir, figure_units: str = "si") -> dict:
    """Write ``control.json``, ``report.md`` and the figures to ``out_dir``.

    Parameters
    ----------
    study : ControlStudy
        What :func:`control_study` returned.
    out_dir : str or Path
        Output folder (created if missing).
    figure_units : str
        Axis units of the figures (``si`` or ``field``, :data:`drillpy.figures.simulation.FIGURE_UNITS`);
        ``control.json`` and ``report.md`` stay SI.

    Returns
    -------
    dict
        The content of ``control.json``.
    """
    from drillpy.figures.control import control_figures

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    js = summary(study)
    prov = provenance(seed=study.tuning_window.seed, samples=study.tuning_window.samples,
                      validation_seed=study.validation_window.seed, validation_samples=study.validation_window.samples)
    js["figures"] = [p.name for p in control_figures(study, out, figure_units)]
    write_text((out / "control.json"), dumps({**js, "provenance": prov}))
    write_text((out / "report.md"), with_markdown_footer(report_text(study), prov))
    return js

