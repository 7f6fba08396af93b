"""Figures of chapter 6 and appendix C: FRF envelopes (Figs. 6.1-6.12), Conv2 (Figs. C.2-C.4),
Craig-Bampton frequency convergence, and SS bands under structural uncertainty.

:func:`chapter6_figures` draws every figure of a :class:`drillpy.uncertainty.chapter6.Chapter6Study`;
the ``*_plot`` functions draw one figure each from results already computed, write one PNG and
return its matplotlib Figure. FRFs are in dB re 1 rad/s^2 per N m, frequencies in Hz.
"""
from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from drillpy.figures.simulation import _save, in_units, plt

if TYPE_CHECKING:
    from drillpy.uncertainty.chapter6 import Chapter6Study

COLORS = ("tab:blue", "tab:red", "tab:green", "tab:orange", "tab:purple")


def chapter6_figures(study: "Chapter6Study", out_dir) -> list:
    """Every figure of the chapter-6 study, written to ``out_dir``.

    Parameters
    ----------
    study : Chapter6Study
        What :func:`drillpy.uncertainty.chapter6.chapter6_study` returned.
    out_dir : str or Path
        Output folder (created if missing).

    Returns
    -------
    list of Path
        cb_frequency_convergence.png; fig6_1..3_models_point*.png (Figs. 6.1-6.3);
        fig6_4..12_cases*_point*.png (Figs. 6.4-6.12); figC_2_conv2_samples.png (Fig. C.2);
        figC_<3+k>_conv2_modes_<substructure>.png (Figs. C.3-C.4).
    """
    from drillpy.uncertainty.chapter6 import FIGURE_PAIRS
    from drillpy.uncertainty.frf import CASE_TITLES
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    labels = study.point_labels
    paths = []

    def draw(name, plot, *args):  # every *_plot returns its figure: keep the file's path
        plot(out / name, *args)
        paths.append(out / name)
    draw("cb_frequency_convergence.png", cb_convergence_plot, study.cb_modes, study.cb_rel_errors)
    for p in range(3):
        draw(f"fig6_{p + 1}_models_point{p + 1}.png", envelope_plot, study.models, p,
             f"SM_full / SM_CB1 / SM_CB2, delta = 0.1: {labels[p]} (Fig. 6.{p + 1})")
    fig_no = 4
    for group in FIGURE_PAIRS.values():
        envs = {f"case {c}: {CASE_TITLES[c].split(' (')[0]}": study.cases[c] for c in group}
        for p in range(3):
            draw(f"fig6_{fig_no}_cases{''.join(map(str, group))}_point{p + 1}.png", envelope_plot, envs, p,
                 f"SM_CB2 cases {', '.join(map(str, group))}: {labels[p]} (Fig. 6.{fig_no})")
            fig_no += 1
    draw("figC_2_conv2_samples.png", conv2_samples_plot, study.models["SM_CB2"])
    for k, (name, curves) in enumerate(study.conv2_curves.items()):
        draw(f"figC_{3 + k}_conv2_modes_{name}.png", conv2_modes_plot, study.conv2_modes, curves, name, labels)
    return paths


def envelope_plot(path, envelopes: dict, point: int, title: str = "") -> plt.Figure:
    """Statistical envelopes at one observation point, one shaded band per entry of
    ``envelopes``, with the sample mean and the nominal model.

    Parameters
    ----------
    path : str or Path
        PNG written.
    envelopes : dict
        Label -> FRFEnvelope (acceleration FRF [dB re 1 rad/s^2 per N m] over frequency [Hz]).
    point : int
        Index of the observation point.
    title : str
        Figure title (default: the point's label).

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    fig, ax = plt.subplots(figsize=(7.2, 4.2))
    first = next(iter(envelopes.values()))
    ax.plot(first.freq_hz, first.nominal_db[:, point], "k--", lw=0.9, label="mean model (nominal)")
    for (label, env), color in zip(envelopes.items(), COLORS):
        pct = int(round(100 * env.probability))
        ax.fill_between(env.freq_hz, env.lower_db[:, point], env.upper_db[:, point], color=color,
                        alpha=0.18, lw=0, label=f"{label}: {pct} % envelope")
        for bound in (env.lower_db[:, point], env.upper_db[:, point]):
            ax.plot(env.freq_hz, bound, color=color, lw=0.4, alpha=0.9)
        ax.plot(env.freq_hz, env.mean_db[:, point], color=color, lw=0.8, label=f"{label}: sample mean")
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("acceleration 20 log10|a| [dB re 1 rad/s² per N m]")
    ax.set_title(title or first.labels[point], fontsize=10)
    ax.set_xlim(first.freq_hz[0], first.freq_hz[-1])
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="lower right")
    return _save(fig, path)


def conv2_samples_plot(path, env, title: str = "") -> plt.Figure:
    """Conv2(n_s) of Eq. (C.2) versus the number of samples (Fig. C.2), one curve per point,
    relative to its final value.

    Parameters
    ----------
    path : str or Path
        PNG written.
    env : FRFEnvelope
        The envelope whose samples' energies give Conv2 [rad/s^1.5 per N m].
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    c = env.conv2()
    n = np.arange(1, c.shape[0] + 1)
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    for p, label in enumerate(env.labels):
        ax.plot(n, c[:, p] / c[-1, p], lw=1.0, label=f"{label} (final {c[-1, p]:.3g} rad/s^1.5 per N m)")
    ax.set_xlabel("number of Monte Carlo samples n_s")
    ax.set_ylabel("Conv2(n_s) / Conv2(final) [-]")
    ax.set_title(title or f"Conv2 versus samples, {env.model} (Fig. C.2)", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    return _save(fig, path)


def conv2_modes_plot(path, modes, curves: dict, substructure: str, labels) -> plt.Figure:
    """Conv2 (Eq. C.2) versus the fixed-interface modes of one substructure (Figs. C.3-C.4), one
    panel per observation point.

    Parameters
    ----------
    path : str or Path
        PNG written.
    modes : sequence of int
        Fixed-interface modes of the substructure.
    curves : dict
        Scenario -> Conv2 [rad/s^1.5 per N m], shape (len(modes), n_points).
    substructure : str
        Name of the substructure.
    labels : sequence of str
        Names of the observation points.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    n_points = len(labels)
    fig, axes = plt.subplots(1, n_points, figsize=(4.2 * n_points, 3.8), squeeze=False)
    for p, ax in enumerate(axes[0]):
        for (scenario, c), color in zip(curves.items(), COLORS):
            ax.plot(modes, c[:, p], "o-", ms=3, color=color, label=scenario)
        ax.set_xlabel(f"{substructure} fixed-interface modes")
        ax.set_ylabel("Conv2 [rad/s^1.5 per N m]")
        ax.set_title(labels[p], fontsize=9)
        ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=7)
    fig.suptitle(f"Conv2 versus {substructure} modes", fontsize=10)
    return _save(fig, path)


def cb_convergence_plot(path, modes, rel_errors) -> plt.Figure:
    """Relative error of the Craig-Bampton natural frequencies against the full FE model.

    Parameters
    ----------
    path : str or Path
        PNG written.
    modes : sequence of int
        Fixed-interface modes per substructure.
    rel_errors : array_like
        |f_CB / f_FE - 1| [-], shape (len(modes), n_frequencies).

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    e = np.asarray(rel_errors)
    for j in range(e.shape[1]):
        ax.semilogy(modes, e[:, j], "o-", ms=3, label=f"mode {j + 1}")
    ax.set_xlabel("fixed-interface modes per substructure")
    ax.set_ylabel("|f_CB / f_FE - 1| [-]")
    ax.set_title("Craig-Bampton natural frequencies versus the full FE model", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7, ncol=2)
    return _save(fig, path)


def severity_bands_plot(path, speeds, studies: dict, level: float = 0.5, title: str = "", units: str = "si") -> plt.Figure:
    """SS versus top speed: sample mean and 5-95 % band of each uncertainty source (top), and the
    band width q95 - q05 of each source (bottom).

    Parameters
    ----------
    path : str or Path
        PNG written.
    speeds : array_like
        Top-drive speeds [rad/s].
    studies : dict
        Label -> SeverityStudy (SS [-] per sample and speed; one sample: a single curve).
    level : float
        Stability threshold of SS [-].
    title : str
        Figure title.
    units : str
        Axis units (:data:`drillpy.figures.simulation.FIGURE_UNITS`): ``si`` (rad/s) or ``field`` (RPM).

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    speeds, su = in_units(speeds, "speed", units)
    fig, (ax, aw) = plt.subplots(2, 1, figsize=(7.0, 6.4), sharex=True, gridspec_kw={"height_ratios": [3, 2]})
    for (label, st), color in zip(studies.items(), ("k",) + COLORS):
        if st.ss.shape[0] == 1:
            ax.plot(speeds, st.ss[0], ".-", color=color, label=label)
            continue
        ax.fill_between(speeds, st.q05, st.q95, color=color, alpha=0.2, lw=0)
        ax.plot(speeds, st.mean, ".-", color=color, lw=1.0, label=f"{label}: mean and 5-95 % band")
        aw.plot(speeds, st.band_width, ".-", color=color, lw=1.0, label=label)
    ax.axhline(level, color="r", ls="--", lw=0.8, label=f"SS = {level}")
    ax.set_ylabel("stick-slip severity SS [-]")
    ax.set_title(title or "SS under structural (SM_CB2) and bit-rock uncertainty", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    aw.set_xlabel(f"top-drive speed [{su}]")
    aw.set_ylabel("band width q95 - q05 [-]")
    aw.grid(alpha=0.3)
    aw.legend(fontsize=7)
    return _save(fig, path)

