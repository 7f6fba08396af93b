"""Figures of the stochastic analysis (thesis Figs. 4.2-4.9 and C.1). Axes carry units.

:func:`stochastic_figures` draws every figure of a
:class:`drillpy.uncertainty.stochastic.StochasticAnalysis`; the ``*_plot`` functions draw one figure
each from results already computed, write one PNG (unless the path is None) and return the matplotlib Figure.
"""
from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from drillpy.figures.simulation import _save, in_units, plt, time_series_plot

if TYPE_CHECKING:
    from drillpy.uncertainty.stochastic import StochasticAnalysis


def stochastic_figures(result: "StochasticAnalysis", out_dir, units: str = "si") -> list:
    """Every figure of the chapter-4 analysis, written to ``out_dir``.

    Parameters
    ----------
    result : StochasticAnalysis
        What :func:`drillpy.uncertainty.stochastic.stochastic_analysis` returned.
    out_dir : str or Path
        Output folder (created if missing).
    units : str
        Axis units of the speeds and torques (:data:`drillpy.figures.simulation.FIGURE_UNITS`): ``si``
        (rad/s, N m) or ``field`` (RPM, kft-lbf).

    Returns
    -------
    list of Path
        psd_fit.png (Figs. 4.2-4.3), eta_realizations.png (Fig. 4.4), stochastic_response.png
        (Fig. 4.5), deterministic_vs_stochastic.png (Fig. 4.6), phase_pdfs.png (Fig. 4.7),
        severity_band.png (Figs. 4.8-4.9) and conv1.png (Fig. C.1).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    r, psd = result, result.psd
    sto = r.stochastic
    paths = [out / n for n in ("psd_fit.png", "eta_realizations.png", "stochastic_response.png",
                               "deterministic_vs_stochastic.png", "phase_pdfs.png", "severity_band.png", "conv1.png")]
    psd_fit_plot(paths[0], r.freq_hz, r.periodogram, r.psd_fit.model, S_welch=r.welch_psd, f_welch=r.welch_freq_hz,
                 target=psd if hasattr(psd, "f0") else None,
                 title=f"PSD of a generated {r.fit_record_s:g}-s eta record (Figs. 4.2-4.3)")
    eta_realizations_plot(paths[1], r.eta_t_s, r.eta, t_max=200.0)
    time_series_plot(paths[2], sto.t, sto.bit_speed, sto.torque_on_bit, sto.top_speed, t_window=r.window_s,
                     title=f"One realization at {r.top_speed_rad_s:g} rad/s (Fig. 4.5)", units=units)
    deterministic_vs_stochastic_plot(paths[3], r.deterministic, sto, r.window_s, units=units)
    phase_pdf_plot(paths[4], r.phases)
    severity_band_plot(paths[5], r.study, units=units)
    conv1_plot(paths[6], r.study.conv1)
    return paths


def psd_fit_plot(path, f, S_raw, fit_model, *, S_welch=None, f_welch=None, target=None,
                 zoom=(0.03, 3.0), title="") -> plt.Figure:
    """Raw (Schuster) periodogram with the fitted Eq. (4.4) model (Figs. 4.2-4.3): full range
    and a zoom around f0.

    Parameters
    ----------
    path : str or Path
        PNG written.
    f, S_raw : ndarray
        Frequency [Hz] and raw one-sided periodogram [1/Hz].
    fit_model : PsdModel
        The fitted model of Eq. (4.4) (callable: f [Hz] -> PSD [1/Hz]).
    S_welch, f_welch : ndarray, optional
        Welch periodogram [1/Hz] and its frequencies [Hz].
    target : PsdModel, optional
        The PSD the series was generated from, if known.
    zoom : (float, float)
        Frequency range of the right panel [Hz].
    title : str
        Title of the left panel.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    fig, axes = plt.subplots(1, 2, figsize=(11.0, 4.2))
    pos = f > 0
    for ax, lim in zip(axes, (None, zoom)):
        ax.loglog(f[pos], S_raw[pos], color="0.55", lw=0.5, label="raw periodogram (Schuster)")
        if S_welch is not None:
            pw = f_welch > 0
            ax.loglog(f_welch[pw], S_welch[pw], "b", lw=1.0, label="Welch")
        ff = f[pos] if lim is None else f[pos][(f[pos] >= lim[0]) & (f[pos] <= lim[1])]
        m = fit_model
        ax.loglog(ff, m(ff), "r", lw=1.6,
                  label=f"fit (4.4): f0={m.f0:.3f} Hz, A0={m.A0:.2f}, a={m.a:.2f}, b={m.b:.2f}")
        if target is not None:
            ax.loglog(ff, target(ff), "k--", lw=1.0,
                      label=f"target: f0={target.f0:.2f}, A0={target.A0:.2f}, a={target.a:.2f}, "
                            f"b={target.b:.2f}")
        if lim is not None and ff.size:
            ax.set_xlim(*lim)
            model = m(ff)
            ax.set_ylim(model.min() / 30.0, model.max() * 10.0)
        ax.set_xlabel("frequency f [Hz]")
        ax.set_ylabel("one-sided PSD of eta [1/Hz]")
        ax.grid(alpha=0.3)
    axes[0].set_title(title or "PSD of eta (Fig. 4.2)")
    axes[1].set_title("zoom: fitted model (Fig. 4.3)")
    axes[1].legend(fontsize=7, loc="lower left")
    return _save(fig, path)


def eta_realizations_plot(path, t, eta, t_max=None) -> plt.Figure:
    """Independent realizations of eta(t) (Fig. 4.4).

    Parameters
    ----------
    path : str or Path
        PNG written.
    t : ndarray
        Time [s], shape (n,).
    eta : ndarray
        Realizations of eta [-], shape (n,) or (k, n).
    t_max : float, optional
        Last time shown [s].

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    fig, ax = plt.subplots(figsize=(7.0, 3.6))
    sel = slice(None) if t_max is None else t <= t_max
    for k, e in enumerate(np.atleast_2d(eta)):
        ax.plot(t[sel], e[sel], lw=0.8, label=f"realization {k + 1}")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("eta [-]")
    ax.set_title("Independent realizations of eta (Fig. 4.4)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return _save(fig, path)


def deterministic_vs_stochastic_plot(path, det, sto, t_window, units="si") -> plt.Figure:
    """Bit and top speed of the deterministic and the stochastic model side by side (Fig. 4.6).

    Parameters
    ----------
    path : str or Path
        PNG written.
    det, sto : SimulationResult
        Deterministic and stochastic runs (speeds in rad/s, SS in ``severity``).
    t_window : (float, float)
        Time window shown [s].
    units : str
        Axis units: ``si`` (rad/s) or ``field`` (RPM); the data stay in rad/s.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    fig, axes = plt.subplots(1, 2, figsize=(11.0, 3.8), sharey=True)
    for ax, r, label in zip(axes, (det, sto), ("deterministic", "stochastic")):
        sel = (r.t >= t_window[0]) & (r.t <= t_window[1])
        ax.plot(r.t[sel], in_units(r.bit_speed[sel], "speed", units)[0], "b", lw=0.8, label="bit")
        ax.plot(r.t[sel], in_units(r.top_speed[sel], "speed", units)[0], "k--", lw=0.8, label="top drive")
        ax.set_xlabel("time [s]")
        ax.set_title(f"{label} bit-rock interaction (SS = {r.severity:.2f})", fontsize=10)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel(f"speed [{in_units(0.0, 'speed', units)[1]}]")
    axes[0].legend(fontsize=8)
    return _save(fig, path)


def phase_pdf_plot(path, study) -> plt.Figure:
    """PDFs of the random stick and slip durations with the deterministic values (Fig. 4.7).

    Parameters
    ----------
    path : str or Path
        PNG written.
    study : PhaseStudy
        Stick and slip durations [s] (:func:`drillpy.uncertainty.montecarlo.phase_study`).

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    fig, axes = plt.subplots(1, 2, figsize=(11.0, 3.8))
    for ax, x, d, name in zip(axes, (study.stick, study.slip),
                              (study.deterministic_stick, study.deterministic_slip),
                              ("stick", "slip")):
        if x.size >= 2 and np.ptp(x) > 0:
            grid = np.linspace(x.min() - 0.1 * np.ptp(x), x.max() + 0.1 * np.ptp(x), 400)
            ax.hist(x, bins=40, density=True, color="0.85", label=f"{x.size} phases")
            from scipy.stats import gaussian_kde  # imported when drawn, off the import path of `drillpy mc`

            ax.plot(grid, gaussian_kde(x)(grid), "k", lw=1.5, label="kernel density")
        for k, v in enumerate(d):
            ax.axvline(v, color="r", ls="-", lw=1.2,
                       label="deterministic" + (f" ({study.deterministic_period_cycles}-cycle)"
                                                if study.deterministic_period_cycles else "")
                       if k == 0 else None)
        ax.set_xlabel(f"{name} duration [s]")
        ax.set_ylabel("probability density [1/s]")
        ax.set_title(f"{name} phases at {study.speed:g} rad/s", fontsize=10)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    return _save(fig, path)


def severity_band_plot(path, study, level=0.5, prob=0.05, units="si") -> plt.Figure:
    """Mean SS with the 90 % band, the deterministic curve and P(SS > level) (Fig. 4.9).

    Parameters
    ----------
    path : str or Path
        PNG written.
    study : StochasticStudy
        SS samples versus top speed [rad/s] (:func:`drillpy.uncertainty.montecarlo.stochastic_study`).
    level : float
        Stability threshold of SS [-].
    prob : float
        Exceedance probability marked [-].
    units : str
        Axis units: ``si`` (rad/s) or ``field`` (RPM); the data stay in rad/s.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7.0, 6.4), sharex=True,
                                 gridspec_kw={"height_ratios": [2, 1]})
    sp, su = in_units(study.speeds, "speed", units)
    a1.fill_between(sp, study.q05, study.q95, color="tab:blue", alpha=0.25,
                    label="5 %-95 % band (90 % region)")
    a1.plot(sp, study.mean, "b-", lw=1.6, label=f"mean ({study.severity.shape[0]} samples)")
    if study.deterministic is not None:
        a1.plot(sp, study.deterministic, "k--", lw=1.2, label="deterministic")
    a1.axhline(level, color="r", ls="--", lw=1.0, label=f"threshold SS = {level}")
    a1.set_ylabel("stick-slip severity SS [-]")
    a1.set_title("Random SS for the stochastic bit-rock interaction (Fig. 4.9)")
    a1.grid(alpha=0.3)
    a1.legend(fontsize=8)
    a2.plot(sp, study.p_exceed, "m.-", label=f"P(SS > {level})")
    a2.axhline(prob, color="r", ls="--", lw=1.0, label=f"{prob:.0%}")
    if study.p05_speed is not None:
        p05 = float(in_units(study.p05_speed, "speed", units)[0])
        a2.axvline(p05, color="m", ls=":", label=f"P <= {prob:.0%} from {p05:.2f} {su}")
        a1.axvline(p05, color="m", ls=":")
    if study.deterministic_threshold is not None:
        det = float(in_units(study.deterministic_threshold, "speed", units)[0])
        a2.axvline(det, color="k", ls=":", label=f"deterministic: {det:.2f} {su}")
    a2.set_xlabel(f"top-drive speed [{su}]")
    a2.set_ylabel("probability [-]")
    a2.set_ylim(-0.03, 1.03)
    a2.grid(alpha=0.3)
    a2.legend(fontsize=8)
    return _save(fig, path)


def conv1_plot(path, conv1) -> plt.Figure:
    """Convergence function n_s -> Conv1(n_s) of Eq. (C.1) (Fig. C.1).

    Parameters
    ----------
    path : str or Path
        PNG written.
    conv1 : array_like
        Conv1 after 1, 2, ... samples [(rad/s)^0.5].

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    fig, ax = plt.subplots(figsize=(6.4, 3.8))
    n = np.arange(1, len(conv1) + 1)
    ax.plot(n, conv1, "k", lw=1.2)
    ax.set_xlabel("number of samples n_s [-]")
    ax.set_ylabel("Conv1(n_s) [(rad/s)^0.5]")
    ax.set_title("Convergence of the Monte Carlo estimate (Eq. C.1, Fig. C.1)")
    ax.grid(alpha=0.3)
    return _save(fig, path)

