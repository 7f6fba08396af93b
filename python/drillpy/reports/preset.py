"""The main job: a deterministic analysis of a preset, reproducing the thesis's chapter 2-4 numbers.

Writes figures and ``summary.json`` into an output folder and returns the summary:
natural frequencies (Eq. 2.7), SS versus top speed with its threshold (Fig. 4.8), the
stick/slip phases and periodic regime of one run with the preset and of a converged reference
(all modes, BDF2; Fig. 4.6), and stability maps for the
hysteretic models 1-3 (Figs. 3.11-3.12) with a quantified check of the thesis's conclusions.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from drillpy.outputs import write_text
from drillpy.figures import simulation as plotting
from drillpy.model.config import with_overrides
from drillpy.model.configuration import Configuration
from drillpy.provenance import provenance
from drillpy.model.simulation import natural_frequencies, simulate, stability_map, sweep_severity
from drillpy.model.threshold import format_threshold, stick_slip_threshold
from drillpy.jsonio import dumps

THESIS_FREQUENCIES_HZ = [0.13, 0.42, 0.74, 1.07, 1.41]
#: Fig. 4.8's threshold [rad/s] and the preset that reproduces it (WOB 200 kN, all 100 modes;
#: docs/presets.md): printed only beside that configuration, never beside another one.
THESIS_THRESHOLD_RAD_S = 16.0
THESIS_THRESHOLD_PRESET = "thesis-ch4"
#: Section 4.2.1's periodic regime at 16 rad/s and the preset whose converged run reproduces it (3 cycles;
#: README): printed only beside that configuration.
THESIS_PERIODIC_REGIME = "3-cycle, stick (1.34, 2.53, 2.48) s, slip (5.4, 6.28, 6.41) s"
THESIS_PERIODIC_PRESET = "thesis-field"
MODEL_BETA1 = {"model 1 (reversible, beta1 = 0)": 0.0, "model 2 (beta1 = 0.14)": 0.14,
               "model 3 (beta1 = 0.56)": 0.56}


def map_conclusions(speeds_rpm: np.ndarray, wobs_kn: np.ndarray, maps: dict) -> dict:
    """Quantify the two conclusions of section 3.3 on the stability maps of Figs. 3.11-3.12.

    The thesis reads from the maps that hysteresis in the bit-rock law (models 2 and 3,
    beta1 = 0.14 and 0.56) enlarges the stable region, and that where the string is unstable
    (low top speed, high WOB) hysteresis makes the stick-slip more severe. A cell is stable when
    its SS (Eq. 3.4) is below 0.5. Quadrants split the grid at the median speed and the median
    WOB (a cell on the median belongs to the high-speed and the low-WOB side).

    Parameters
    ----------
    speeds_rpm : ndarray
        Top-drive speeds of the map's columns [RPM], shape (n_speeds,).
    wobs_kn : ndarray
        Weights on bit of the map's rows [kN], shape (n_wobs,).
    maps : dict
        Model label -> SS map [-] of shape (n_wobs, n_speeds), as returned by
        :func:`drillpy.model.simulation.stability_map`. The first entry is taken as the
        reversible reference (model 1) and the last as the most hysteretic model (model 3),
        as in :data:`MODEL_BETA1`.

    Returns
    -------
    dict
        Per model label a dict with ``stable_fraction_all`` (fraction of all cells with
        SS < 0.5), ``stable_fraction_high_speed_low_wob`` (the same in the high-speed / low-WOB
        quadrant), ``mean_ss_low_speed_high_wob`` (mean SS in the low-speed / high-WOB
        quadrant) and ``max_ss`` (largest SS of the map); and two verdicts comparing the last
        model with the first: ``hysteresis_enlarges_stable_region`` (True when either stable
        fraction grows) and ``hysteresis_raises_ss_low_speed_high_wob`` (True when the mean SS
        of the low-speed / high-WOB quadrant rises).
    """
    hs = speeds_rpm >= np.median(speeds_rpm)
    lw = wobs_kn <= np.median(wobs_kn)
    out = {}
    for label, m in maps.items():
        q_stable = m[np.ix_(lw, hs)]
        q_severe = m[np.ix_(~lw, ~hs)]
        out[label] = {
            "stable_fraction_all": float(np.mean(m < 0.5)),
            "stable_fraction_high_speed_low_wob": float(np.mean(q_stable < 0.5)),
            "mean_ss_low_speed_high_wob": float(np.mean(q_severe)),
            "max_ss": float(np.max(m)),
        }
    labels = list(maps)
    first, last = out[labels[0]], out[labels[-1]]
    out["hysteresis_enlarges_stable_region"] = bool(
        last["stable_fraction_high_speed_low_wob"] > first["stable_fraction_high_speed_low_wob"]
        or last["stable_fraction_all"] > first["stable_fraction_all"])
    out["hysteresis_raises_ss_low_speed_high_wob"] = bool(
        last["mean_ss_low_speed_high_wob"] > first["mean_ss_low_speed_high_wob"])
    return out


def _run_summary(run, top_speed: float) -> dict:
    return {"top_speed_rad_s": top_speed, "severity": run.severity,
            "stick_fraction": run.stick_fraction,
            "stick_durations_s": run.stick_durations.round(3).tolist(),
            "slip_durations_s": run.slip_durations.round(3).tolist(),
            "period_cycles": run.period_cycles,
            "period_stick_s": run.period_stick.round(3).tolist(),
            "period_slip_s": run.period_slip.round(3).tolist()}


def thesis_threshold(cfg: dict) -> float | None:
    """Fig. 4.8's threshold [rad/s] when ``cfg`` is exactly the configuration that reproduces it
    (:data:`THESIS_THRESHOLD_PRESET`, no override), else None.

    Parameters
    ----------
    cfg : dict
        A configuration.

    Returns
    -------
    float or None
        :data:`THESIS_THRESHOLD_RAD_S` or None.
    """
    from drillpy.model.config import load_config
    return THESIS_THRESHOLD_RAD_S if cfg == load_config(preset=THESIS_THRESHOLD_PRESET) else None


def field_report(cfg: dict, out_dir: str | Path, *, speeds=None, map_speeds_rpm=None,
                 map_wobs_kn=None, progress: bool = True, threads: int = 0, figure_units: str = "si") -> dict:
    """Run the main job on a preset (``drillpy report``) and write its figures and summary.

    Computes, in order: the first five natural frequencies of the clamped string (Eq. 2.7),
    compared with the thesis's (0.13, 0.42, 0.74, 1.07, 1.41) Hz of section 4.2.1; SS (Eq. 3.4)
    versus the top-drive speed with the speed below which SS > 0.5 by bisection
    (:func:`drillpy.model.threshold.stick_slip_threshold`; Fig. 4.8's 16 rad/s belongs to ``thesis-ch4``);
    one run at the configuration's operating top speed with the preset's own settings and one
    converged reference at that speed (all free modes, BDF2, at least 400 s with the first half
    discarded) with their stick/slip phases and periodic regime (Fig. 4.6, section 4.2.1); and,
    when the bit-rock law is hysteretic, the stability maps of models 1-3 (beta1 = 0, 0.14,
    0.56; Figs. 3.11-3.12) with :func:`map_conclusions`.

    Figures written into ``out_dir``: ``severity_vs_top_speed.png``, ``time_series.png`` (last
    60 s of the reference run) and, for a hysteretic law, ``stability_maps.png``; the summary
    goes to ``summary.json``.

    Parameters
    ----------
    cfg : dict
        Configuration (e.g. the ``thesis-field`` preset as loaded by
        :func:`drillpy.model.config.load_config`); its ``operation.top_speed_rad_s`` sets the
        speed of the single runs.
    out_dir : str or Path
        Output folder, created if missing.
    speeds : array_like, optional
        Top-drive speeds of the SS sweep [rad/s] (default 6, 7, ..., 27 rad/s, the range
        B = [6, 27] rad/s of Fig. 4.8).
    map_speeds_rpm : array_like, optional
        Top-drive speeds of the stability maps [RPM] (default 23 points from 50 to 160 RPM).
    map_wobs_kn : array_like, optional
        Weights on bit of the stability maps [kN] (default 12 points from 22 to 267 kN).
    progress : bool
        Show progress bars during the sweeps.
    threads : int
        Engine threads (0: all cores).
    figure_units : str
        Axis units of the figures (``si`` or ``field``, :data:`drillpy.figures.simulation.FIGURE_UNITS`);
        ``summary.json`` stays SI.

    Returns
    -------
    dict
        The summary written to ``summary.json``: ``preset`` (name), ``config``,
        ``frequencies_hz`` and ``thesis_frequencies_hz`` [Hz]; ``sweep`` with
        ``top_speeds_rad_s`` [rad/s], ``severity`` [-], the threshold's keys of
        :func:`drillpy.model.threshold.stick_slip_threshold` and ``thesis_threshold_rad_s`` [rad/s]
        (None unless the configuration is :func:`thesis_threshold`'s); ``run`` and ``reference_run`` with
        ``top_speed_rad_s``, ``severity``, ``stick_fraction``, ``stick_durations_s`` and
        ``slip_durations_s`` [s], ``period_cycles`` (stick-slip cycles per period, 0 when not
        periodic), ``period_stick_s`` and ``period_slip_s`` [s] (``reference_run`` also has
        ``modes``, ``scheme``, ``duration_s`` and, for the configuration that reproduces it,
        ``thesis_periodic_regime``); for a hysteretic law ``stability_maps`` with
        ``top_speeds_rpm``, ``wobs_kn``, ``severity`` (label -> map) and ``conclusions``
        (:func:`map_conclusions`).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    summary: dict = {"preset": cfg.get("name"), "config": cfg}
    view = Configuration.of(cfg)

    f = natural_frequencies(cfg, 5)
    summary["frequencies_hz"] = [round(float(x), 4) for x in f]
    summary["thesis_frequencies_hz"] = THESIS_FREQUENCIES_HZ

    speeds = np.arange(6.0, 28.0) if speeds is None else np.asarray(speeds, float)
    ss = sweep_severity(cfg, speeds, progress=progress, threads=threads)
    thr = stick_slip_threshold(cfg, speeds, ss, threads=threads)
    thesis = thesis_threshold(cfg)
    summary["sweep"] = {"top_speeds_rad_s": speeds.tolist(), "severity": ss.round(4).tolist(), **thr,
                        "thesis_threshold_rad_s": thesis}
    plotting.severity_plot(out / "severity_vs_top_speed.png", speeds, ss, thr["threshold_rad_s"],
                           title=f"{cfg.get('name')}: SS vs top speed" + (" (Fig. 4.8)" if thesis else ""),
                           units=figure_units)

    op_speed = view.operation.top_speed_rad_s
    summary["run"] = _run_summary(simulate(cfg, op_speed), op_speed)
    # Converged reference for the periodic regime (section 4.2.1): all modes, BDF2, long run.
    n_free = sum(sec.elements for sec in view.string.sections)
    duration = max(400.0, view.simulation.duration_s)
    ref_cfg = with_overrides(cfg, modes=n_free, scheme="bdf2", duration=duration, transient=duration / 2)
    ref = simulate(ref_cfg, op_speed)
    summary["reference_run"] = {**_run_summary(ref, op_speed), "modes": n_free, "scheme": "bdf2",
                                "duration_s": duration}
    from drillpy.model.config import load_config
    if cfg == load_config(preset=THESIS_PERIODIC_PRESET):
        summary["reference_run"]["thesis_periodic_regime"] = THESIS_PERIODIC_REGIME
    t_end = ref.t[-1]
    plotting.time_series_plot(out / "time_series.png", ref.t, ref.bit_speed, ref.torque_on_bit,
                         ref.top_speed, t_window=(max(0.0, t_end - 60.0), t_end),
                         title=f"{cfg.get('name')}: {op_speed:g} rad/s at the top, all modes, BDF2 "
                               "(last 60 s)", units=figure_units)

    if view.law.type == "hysteretic":
        sp_rpm = np.linspace(50, 160, 23) if map_speeds_rpm is None else np.asarray(map_speeds_rpm, float)
        w_kn = np.linspace(22, 267, 12) if map_wobs_kn is None else np.asarray(map_wobs_kn, float)
        maps = {}
        for label, beta1 in MODEL_BETA1.items():
            c = with_overrides(cfg, beta1=beta1)
            maps[label] = stability_map(c, sp_rpm * np.pi / 30.0, w_kn * 1e3, progress=progress,
                                        threads=threads)
        plotting.stability_map_plot(out / "stability_maps.png", sp_rpm, w_kn, maps, units=figure_units)
        summary["stability_maps"] = {
            "top_speeds_rpm": sp_rpm.tolist(), "wobs_kn": w_kn.tolist(),
            "severity": {k: v.round(4).tolist() for k, v in maps.items()},
            "conclusions": map_conclusions(sp_rpm, w_kn, maps),
        }
    write_text((out / "summary.json"), dumps({**summary, "provenance": provenance()}))
    return summary


def print_field_summary(s: dict) -> None:
    """Print a field-report summary beside the thesis's numbers, one finding per line.

    Prints the natural frequencies [Hz], the SS > 0.5 threshold (:func:`drillpy.model.threshold.format_threshold`,
    Fig. 4.8's value only beside ``thesis-ch4``), SS, stick fraction and periodic regime of the preset run
    and of the converged reference (section 4.2.1's regime only beside ``thesis-field``) and, when present, the stable fractions and the two section-3.3 verdicts of the stability
    maps.

    Parameters
    ----------
    s : dict
        The summary returned by :func:`field_report` (or read back from its ``summary.json``).
    """
    print(f"natural frequencies [Hz]: {s['frequencies_hz']}  (thesis {s['thesis_frequencies_hz']})")
    sw = s["sweep"]
    thesis = sw.get("thesis_threshold_rad_s")
    print(format_threshold(sw) + (f"  (thesis Fig. 4.8: {thesis} rad/s)" if thesis is not None else ""))
    for key, label in (("run", "preset"), ("reference_run", "all modes, BDF2")):
        r = s[key]
        print(f"run at {r['top_speed_rad_s']} rad/s ({label}): SS = {r['severity']:.3f}, stick "
              f"fraction = {r['stick_fraction']:.3f}, periodic over {r['period_cycles']} cycle(s)")
        if r["period_cycles"]:
            print(f"  stick durations {r['period_stick_s']} s, slip durations {r['period_slip_s']} s")
    if s["reference_run"].get("thesis_periodic_regime"):
        print(f"  thesis (section 4.2.1): {s['reference_run']['thesis_periodic_regime']}")
    if "stability_maps" in s:
        c = s["stability_maps"]["conclusions"]
        for label in MODEL_BETA1:
            m = c[label]
            print(f"{label}: stable fraction {m['stable_fraction_all']:.2f} (high speed/low WOB "
                  f"{m['stable_fraction_high_speed_low_wob']:.2f}), mean SS low speed/high WOB "
                  f"{m['mean_ss_low_speed_high_wob']:.2f}")
        print(f"hysteresis enlarges stable region: {c['hysteresis_enlarges_stable_region']}; "
              f"raises SS at low speed/high WOB: {c['hysteresis_raises_ss_low_speed_high_wob']}")


def write_sweep(out_dir: str | Path, speeds, severity, threshold: float | None, summary: dict, cfg: dict,
                start: str | None = None, figure_units: str = "si") -> Path:
    """Write the outputs of an SS sweep (``drillpy sweep --out``).

    Parameters
    ----------
    out_dir : str or Path
        Folder created if missing; receives ``severity_vs_top_speed.png`` and ``sweep.json``.
    speeds : array_like
        Top-drive speeds [rad/s].
    severity : array_like
        SS (Eq. 3.4) at each speed [-].
    threshold : float or None
        Speed below which SS > 0.5 [rad/s], drawn on the figure; None without a crossing.
    summary : dict
        JSON summary of the sweep, written with the configuration under ``"config"`` (its ``sweep``
        block set to the speeds run, so ``drillsim --job sweep`` repeats the sweep).
    cfg : dict
        Configuration the sweep ran with.
    start : str, optional
        Initial state of the runs (``rest``, ``rigid``, ``steady``), recorded in the provenance
        (default: the configuration's ``simulation.start``, else ``rest``).
    figure_units : str
        Axes of the figure (:data:`drillpy.figures.simulation.FIGURE_UNITS`: ``si`` or ``field``).

    Returns
    -------
    Path
        The output folder.
    """
    from drillpy.figures import simulation as plotting
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    plotting.severity_plot(out / "severity_vs_top_speed.png", speeds, severity, threshold, units=figure_units)
    start = start or _start(cfg)  # the start used
    # the grid run, in the configuration: drillsim --job sweep on it repeats the sweep
    cfg = Configuration.of(cfg).replace(sweep={"top_speeds_rad_s": [float(v) for v in speeds], "wobs_n": []}).to_dict()
    write_text((out / "sweep.json"), dumps({**summary, "config": cfg, "provenance": provenance(start=start)}))
    return out


def _start(cfg) -> str:
    """The initial state a configuration's runs take (``simulation.start``; ``rest`` without a
    ``simulation`` block)."""
    sim = Configuration.of(cfg).get("simulation")
    return "rest" if sim is None else sim.start


def write_map(out_dir: str | Path, speeds_rpm, wobs_kn, severity, summary: dict, cfg: dict,
              start: str | None = None, figure_units: str = "si") -> Path:
    """Write the outputs of a stability map (``drillpy map --out``).

    Parameters
    ----------
    out_dir : str or Path
        Folder created if missing; receives ``stability_map.png`` and ``map.json``.
    speeds_rpm : array_like
        Top-drive speeds [RPM].
    wobs_kn : array_like
        Weights on bit [kN].
    severity : ndarray
        SS [-] over speed x WOB, as returned by :func:`drillpy.model.simulation.stability_map`.
    summary : dict
        JSON summary of the map, written with the configuration under ``"config"`` (its ``sweep`` block
        set to the grid run, so ``drillsim --job sweep`` repeats the map).
    cfg : dict
        Configuration the map ran with (its law type labels the panel).
    start : str, optional
        Initial state of the runs (``rest``, ``rigid``, ``steady``), recorded in the provenance
        (default: the configuration's ``simulation.start``, else ``rest``).
    figure_units : str
        Axes of the figure (:data:`drillpy.figures.simulation.FIGURE_UNITS`: ``si`` or ``field``).

    Returns
    -------
    Path
        The output folder.
    """
    from drillpy.figures import simulation as plotting
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    plotting.stability_map_plot(out / "stability_map.png", speeds_rpm, wobs_kn,
                                {Configuration.of(cfg).law.type: severity}, units=figure_units)
    start = start or _start(cfg)  # the start used
    cfg = Configuration.of(cfg).replace(sweep={"top_speeds_rad_s": [float(v) * np.pi / 30.0 for v in speeds_rpm],
                                               "wobs_n": [float(w) * 1e3 for w in wobs_kn]}).to_dict()  # [rad/s, N]
    write_text((out / "map.json"), dumps({**summary, "config": cfg, "provenance": provenance(start=start)}))
    return out
