"""Figures of chapter 6 and appendix C: FRF envelopes (Figs. 6.1-6.12), Conv2 (Figs. C.2-C.4),
Craig-Bampton frequency convergence, and SS bands under structural uncertainty."""
from __future__ import annotations

import numpy as np

from drillpy.figures.simulation import _save, plt

COLORS = ("tab:blue", "tab:red", "tab:green", "tab:orange", "tab:purple")


def envelope_figure(path, envelopes: dict, point: int, title: str = ""):
    """Statistical envelopes at one observation point, one shaded band per entry of
    ``envelopes`` (label -> FRFEnvelope), with the sample mean and the nominal model."""
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


def conv2_samples_figure(path, env, title: str = ""):
    """Conv2(n_s) of Eq. (C.2) versus the number of samples (Fig. C.2), one curve per point."""
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


def conv2_modes_figure(path, modes, curves: dict, substructure: str, labels):
    """Conv2 (Eq. C.2) versus the fixed-interface modes of one substructure (Figs. C.3-C.4);
    ``curves``: scenario -> array (len(modes), n_points); one panel per point."""
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


def cb_convergence_figure(path, modes, rel_errors):
    """Relative error of the Craig-Bampton natural frequencies against the full FE model."""
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


def severity_bands_figure(path, speeds, studies: dict, level: float = 0.5, title: str = ""):
    """SS versus top speed: sample mean and 5-95 % band of each uncertainty source (top), and the
    band width q95 - q05 of each source (bottom); ``studies``: label -> SeverityStudy."""
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
    aw.set_xlabel("top-drive speed [rad/s]")
    aw.set_ylabel("band width q95 - q05 [-]")
    aw.grid(alpha=0.3)
    aw.legend(fontsize=7)
    return _save(fig, path)
