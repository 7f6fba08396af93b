"""Figures of ``drillpy control`` (docs/control.md): stability maps per drive, P(SS > 0.5) versus
speed with bands, the stick-slip episode with and without the tuned controllers, the tuning scores."""
from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from drillpy.figures.simulation import _save, in_units, plt
from drillpy.model.configuration import Configuration

if TYPE_CHECKING:
    from drillpy.control.study import ControlStudy


def control_figures(study: "ControlStudy", out_dir, units: str = "si") -> list:
    """Every figure of a control study, written to ``out_dir``.

    Parameters
    ----------
    study : ControlStudy
        What :func:`drillpy.control.study.control_study` returned.
    out_dir : str or Path
        Output folder.
    units : str
        Axis units (:data:`drillpy.figures.simulation.FIGURE_UNITS`): ``si`` (rad/s, kN, kN m) or
        ``field`` (RPM, klbf, kft-lbf).

    Returns
    -------
    list of Path
        The files written.
    """
    out = Path(out_dir)
    paths = [out / "maps.png", out / "p_vs_speed.png", out / "episode.png"]
    maps_plot(paths[0], study, units)
    p_vs_speed_plot(paths[1], study, units)
    episode_plot(paths[2], study, units)
    for name, t in study.tunings.items():
        paths.append(out / f"tuning_{name}.png")
        tuning_plot(paths[-1], name, t)
    return paths


def maps_plot(path, study: "ControlStudy", units: str = "si") -> plt.Figure:
    """Deterministic SS over (top speed, WOB) for every drive, with the SS = 0.5 contour; stalled
    runs marked with a red cross.

    Parameters
    ----------
    path : str or Path
        PNG file.
    study : ControlStudy
        The control study.
    units : str
        Axis units: ``si`` (rad/s, kN) or ``field`` (RPM, klbf).

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    labels = list(study.comparison)
    if study.validation_window.wobs.size == 1 or study.validation_window.speeds.size == 1:
        return _curves(path, study, labels, units)
    cols = min(3, len(labels))
    rows = math.ceil(len(labels) / cols)
    (sp, su), (wb, wu) = _window_axes(study, units)
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.4 * rows), squeeze=False)
    finite = [r["map"][np.isfinite(r["map"])] for r in study.comparison.values()]
    vmax = max([1.0] + [float(np.max(f)) for f in finite if f.size])
    for ax, label in zip(axes.flat, labels):
        m = study.comparison[label]["map"]
        shown = np.where(np.isfinite(m), m, vmax)
        im = ax.pcolormesh(sp, wb, shown, shading="nearest", vmin=0.0, vmax=vmax, cmap="viridis")
        if sp.size > 1 and wb.size > 1 and np.min(shown) < 0.5 < np.max(shown):
            ax.contour(sp, wb, shown, levels=[0.5], colors="w", linewidths=1.2)
        iw, isp = np.nonzero(~np.isfinite(m))
        if iw.size:
            ax.plot(sp[isp], wb[iw], "rx", ms=8, label="stalled")
            ax.legend(fontsize=7)
        ax.set_title(label)
        ax.set_xlabel(f"top speed [{su}]")
        ax.set_ylabel(f"WOB [{wu}]")
        fig.colorbar(im, ax=ax, label="SS [-]")
    for ax in list(axes.flat)[len(labels):]:
        ax.set_visible(False)
    return _save(fig, path)


def _window_axes(study: "ControlStudy", units: str) -> tuple:
    """The window's speeds and WOBs in the figure units, each with its unit label."""
    w = study.validation_window
    return in_units(w.speeds, "speed", units), in_units(w.wobs, "force", units)


def _curves(path, study: "ControlStudy", labels: list, units: str = "si") -> plt.Figure:
    """The map of a window with one WOB (or one speed): SS versus the other axis, one curve per drive
    (a one-row map would be shaded blank)."""
    (sp, su), (wb, wu) = _window_axes(study, units)
    one_wob = wb.size == 1
    x = sp if one_wob else wb
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    for k, label in enumerate(labels):
        m = np.asarray(study.comparison[label]["map"], float).ravel()
        ax.plot(x, m, "o-", color=f"C{k}", label=label)
        stalled = ~np.isfinite(m)
        if stalled.any():
            ax.plot(x[stalled], np.full(stalled.sum(), 0.5), "x", color=f"C{k}", ms=9, label=f"{label}: stalled")
    ax.axhline(0.5, color="k", ls="--", lw=0.8, label="SS = 0.5")
    ax.set_xlabel(f"top speed [{su}]" if one_wob else f"WOB [{wu}]")
    ax.set_ylabel("deterministic SS [-]")
    ax.set_title(f"WOB {wb[0]:.4g} {wu}" if one_wob else f"top speed {sp[0]:.4g} {su}")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return _save(fig, path)


def p_vs_speed_plot(path, study: "ControlStudy", units: str = "si") -> plt.Figure:
    """P(SS > 0.5) versus top speed at the nominal WOB for every drive, with Wilson 90 % bands.

    Parameters
    ----------
    path : str or Path
        PNG file.
    study : ControlStudy
        The control study.
    units : str
        Axis units: ``si`` (rad/s, kN) or ``field`` (RPM, klbf).

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    (sp, su), (wb, wu) = _window_axes(study, units)
    for label, r in study.comparison.items():
        (line,) = ax.plot(sp, r["p_by_speed"], "o-", label=label, ms=3)
        ax.fill_between(sp, r["p_band"][0], r["p_band"][1], color=line.get_color(), alpha=0.15)
    ax.axhline(0.05, color="k", ls=":", lw=1, label="5 %")
    k = next(iter(study.comparison.values()))["nominal_row"]
    ax.set_title(f"P(SS > 0.5 or stalled) at WOB {wb[k]:.4g} {wu}, {study.validation_window.samples} new samples")
    ax.set_xlabel(f"top speed [{su}]")
    ax.set_ylabel("P(SS > 0.5 or stalled) [-]")
    ax.set_ylim(-0.02, 1.02)
    ax.legend(fontsize=8)
    return _save(fig, path)


def episode_plot(path, study: "ControlStudy", units: str = "si") -> plt.Figure:
    """Bit speed, top speed and motor torque of the episode with each drive.

    Parameters
    ----------
    path : str or Path
        PNG file.
    study : ControlStudy
        The control study.
    units : str
        Axis units: ``si`` (rad/s, kN m) or ``field`` (RPM, kft-lbf).

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    fig, axes = plt.subplots(3, 1, figsize=(9, 8), sharex=True)
    sim = Configuration.of(study.config).simulation
    t_end = sim.duration_s
    t_start = max(sim.transient_s, t_end - 60.0)
    for label, e in study.episodes.items():
        w = e.t >= t_start
        wm = e.t_motor >= t_start
        axes[0].plot(e.t[w], _speed(e.bit_speed[w], units)[0], lw=0.8, label=f"{label} (SS {e.severity:.2f})")
        axes[1].plot(e.t[w], _speed(e.top_speed[w], units)[0], lw=0.8, label=label)
        axes[2].plot(e.t_motor[wm], _torque(e.motor_torque[wm], units)[0], lw=0.8, label=label)
    if study.torque_limit is not None:
        axes[2].axhline(_torque(study.torque_limit, units)[0], color="r", ls="--", lw=1, label="torque limit")
    su, tu = _speed(0.0, units)[1], _torque(0.0, units)[1]
    axes[0].set_ylabel(f"bit speed [{su}]")
    axes[1].set_ylabel(f"top speed [{su}]")
    axes[2].set_ylabel(f"motor torque [{tu}]")
    axes[2].set_xlabel("time [s]")
    axes[0].set_title(f"Top speed command {_speed(study.episode_speed, units)[0]:.4g} {su}")
    for ax in axes:
        ax.legend(fontsize=7, loc="upper right")
    return _save(fig, path)


def _speed(values, units: str) -> tuple:
    """Speeds [rad/s] in the figure units, with the unit's label."""
    return in_units(values, "speed", units)


def _torque(values, units: str) -> tuple:
    """Motor torques [N m] in the figure units (kN m in SI), with the unit's label."""
    if units == "si":
        return np.asarray(values, float) / 1e3, "kN m"
    return in_units(values, "torque", units)


def tuning_plot(path, name: str, tuning) -> plt.Figure:
    """The score of every evaluated gain pair (log factors of the nominal tuning), the optimum marked.

    Parameters
    ----------
    path : str or Path
        PNG file.
    name : str
        The controller.
    tuning : Tuning
        Its :class:`drillpy.control.tuning.Tuning`.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    keys = list(tuning.gains)
    x = np.array([[10 ** e["log10_factors"][k] for k in keys] for e in tuning.evaluations])
    s = np.array([e["p_ss_gt_0_5"] for e in tuning.evaluations])
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    sc = ax.scatter(x[:, 0], x[:, 1], c=s, cmap="viridis_r", s=40, edgecolors="k", linewidths=0.3)
    ax.plot([tuning.factors[keys[0]]], [tuning.factors[keys[1]]], "r*", ms=14, label="optimum")
    ax.plot([1.0], [1.0], "ks", mfc="none", ms=10, label="nominal tuning")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(f"{keys[0]} / nominal")
    ax.set_ylabel(f"{keys[1]} / nominal")
    ax.set_title(f"{name}: P(SS > 0.5 or stalled), tuning samples", fontsize=9)
    fig.colorbar(sc, ax=ax, label="P [-]")
    ax.legend(fontsize=8)
    return _save(fig, path)
