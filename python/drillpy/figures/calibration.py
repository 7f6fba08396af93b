"""Figures of a Bayesian calibration (:class:`drillpy.calibration.posterior.Posterior`): the
posterior marginals against the priors, one parameter pair, and the posterior predictive intervals
against a held-out window. Each ``*_plot`` writes one PNG and returns its figure."""
from __future__ import annotations

import numpy as np
from matplotlib.ticker import NullFormatter

from drillpy.figures.simulation import _save, plt


def marginals_plot(path, summary: dict) -> plt.Figure:
    """Posterior marginals (weighted histograms) of every family's parameters over their prior ranges,
    titled with the family's probability.

    Parameters
    ----------
    path : str or Path or None
        PNG to write (None: draw only).
    summary : dict
        ``Posterior.summary()``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fams = summary["families"]
    names = sorted({p for f in fams for p in summary["parameters"].get(f, {})},
                   key=lambda n: [p for f in fams for p in summary["priors"]["families"][f]].index(n))
    cols = min(4, len(names))
    rows = -(-len(names) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(3.3 * cols, 2.6 * rows), squeeze=False)
    for ax in axes.flat[len(names):]:
        ax.set_visible(False)
    colors = ("tab:blue", "tab:orange", "tab:green", "tab:red")
    for ax, name in zip(axes.flat, names):
        for k, fam in enumerate(fams):
            part = summary["particles"].get(fam, {})
            if name not in part or not part[name]:
                continue
            pr = summary["priors"]["families"][fam][name]
            lo, hi = pr["range"]
            log = pr["scale"] == "log-uniform"
            bins = np.geomspace(lo, hi, 25) if log else np.linspace(lo, hi, 25)
            w = np.asarray(part["weight"]) * summary["model_probability"][fam] / max(np.sum(part["weight"]), 1e-300)
            ax.hist(part[name], bins=bins, weights=w, alpha=0.55, color=colors[k % 4],
                    label=f"{fam} (P = {summary['model_probability'][fam]:.2f})")
            if log:
                ax.set_xscale("log")
                ax.xaxis.set_minor_formatter(NullFormatter())
            ax.set_xlim(lo, hi)
        unit = next(summary["priors"]["families"][f][name]["unit"] for f in fams
                    if name in summary["priors"]["families"][f])
        ax.set_xlabel(f"{name} [{unit}]")
        ax.set_yticks([])
    for row in axes:
        row[0].set_ylabel("posterior density")
    axes[0][0].legend(fontsize=7, loc="upper left")
    return _save(fig, path)


def pair_plot(path, summary: dict, family: str, x: str, y: str) -> plt.Figure:
    """The posterior particles of ``family`` in the plane of two parameters (size by weight).

    Parameters
    ----------
    path : str or Path or None
        PNG to write.
    summary : dict
        ``Posterior.summary()``.
    family : str
        Law family.
    x, y : str
        Parameter names.

    Returns
    -------
    matplotlib.figure.Figure
    """
    part = summary["particles"][family]
    pri = summary["priors"]["families"][family]
    fig, ax = plt.subplots(figsize=(4.2, 3.6))
    w = np.asarray(part["weight"])
    ax.scatter(part[x], part[y], s=8 + 400 * w / max(w.max(), 1e-300), alpha=0.5)
    for axis, name, setter in ((ax.xaxis, x, ax.set_xlim), (ax.yaxis, y, ax.set_ylim)):
        setter(*pri[name]["range"])
    if pri[x]["scale"] == "log-uniform":
        ax.set_xscale("log")
    if pri[y]["scale"] == "log-uniform":
        ax.set_yscale("log")
    ax.set_xlabel(f"{x} [{pri[x]['unit']}]")
    ax.set_ylabel(f"{y} [{pri[y]['unit']}]")
    ax.set_title(f"{family}: posterior particles", fontsize=9)
    return _save(fig, path)


def predictive_plot(path, summary: dict) -> plt.Figure:
    """Posterior predictive 90 % intervals of the statistics, each divided by its measured value on
    the held-out window (1 = measured).

    Parameters
    ----------
    path : str or Path or None
        PNG to write.
    summary : dict
        ``Posterior.summary()``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    pred = summary["predictive"]
    names = [n for n in pred if pred[n]["measured"]]
    fig, ax = plt.subplots(figsize=(7, 3.2))
    for i, n in enumerate(names):
        m = pred[n]["measured"]
        lo, hi = (v / m for v in pred[n]["interval90"])
        lo, hi = min(lo, hi), max(lo, hi)
        ax.plot([i, i], [lo, hi], color="tab:blue" if pred[n]["contained"] else "tab:red", lw=4)
        ax.plot(i, pred[n]["median"] / m, "k_", ms=10)
    ax.axhline(1.0, color="k", lw=0.8)
    ax.set_xticks(range(len(names)))
    ax.set_xticklabels(names, rotation=45, ha="right", fontsize=8)
    ax.set_ylabel("predicted / measured")
    ax.set_title("posterior predictive 90 % intervals on the held-out window", fontsize=9)
    return _save(fig, path)


def posterior_map_plot(path, smap) -> plt.Figure:
    """The posterior stability map: P(SS > 0.5 or a stall) over the motor command x WOB, with the
    P = 0.5 contour and the cells' Wilson 90 % interval widths as text, beside P(stall).

    Parameters
    ----------
    path : str or Path or None
        PNG to write.
    smap : drillpy.calibration.stability.StabilityMap
        The map (:func:`drillpy.calibration.stability.stability_map`).

    Returns
    -------
    matplotlib.figure.Figure
    """
    x, y = np.asarray(smap.speeds), np.asarray(smap.wobs)
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.0), squeeze=False)
    panels = (("P(SS > 0.5 or a stall)", smap.p_unstable), ("P(stall)", smap.p_stall))
    for ax, (label, p) in zip(axes[0], panels):
        pc = ax.pcolormesh(x, y, p, shading="nearest", cmap="viridis", vmin=0.0, vmax=1.0)
        if min(p.shape) >= 2 and np.nanmin(p) < 0.5 < np.nanmax(p):
            ax.contour(x, y, p, levels=[0.5], colors="w", linewidths=1.5)
        if label.startswith("P(SS"):
            for i, w in enumerate(y):
                for j, s in enumerate(x):
                    lo, hi = smap.ci90[0, i, j], smap.ci90[1, i, j]
                    ax.text(s, w, f"{p[i, j]:.2f}\n[{lo:.2f}, {hi:.2f}]", ha="center", va="center", fontsize=6,
                            color="w" if p[i, j] < 0.6 else "k")
        ax.set_xlabel("motor command [rad/s]")
        ax.set_ylabel("WOB (the jack's set force) [N]")
        ax.set_title(label, fontsize=10)
        fig.colorbar(pc, ax=ax)
    fig.suptitle(f"posterior stability map: {smap.settings.get('samples', '?')} samples, each a posterior draw "
                 "with its own eta (Eq. 4.1)", fontsize=9)
    return _save(fig, path)
