"""Figures of ``drillpy loop`` (:func:`drillpy.loop.run_loop`): residual versus signature,
before/after overlays, torque-speed loops, errors per step.

:func:`loop_figures` draws every figure of a :class:`drillpy.loop.LoopResult`; each ``*_plot``
function draws one figure from it, writes one PNG (unless its path is None) and returns its matplotlib Figure. Speeds are plotted in RPM,
torques in N m, times in s; the residuals and signatures of the signature figure are normalized by
the channels' standard deviations (the metric's units).
"""
from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from drillpy.figures.simulation import _save, in_units, plt
from drillpy.records.io import RPM

if TYPE_CHECKING:
    from drillpy.loop.run import LoopResult

C_MEAS, C_BASE, C_FINAL, C_SIG = "k", "tab:red", "tab:blue", "tab:orange"

#: figure key (as in the report's links) -> file name
LOOP_FIGURES = {"signature": "residual_signature.png", "overlay": "overlay.png", "loops": "loops.png",
                "errors": "errors.png"}


def loop_figures(res: "LoopResult", out_dir, units: str = "si") -> dict:
    """Every figure of a loop run, written to ``out_dir``.

    Parameters
    ----------
    res : LoopResult
        What :func:`drillpy.loop.run_loop` returned.
    out_dir : str or Path
        Output folder (created if missing).
    units : str
        Axis unit of the torques (:data:`drillpy.figures.simulation.FIGURE_UNITS`): ``si`` (N m) or
        ``field`` (ft-lbf); speeds stay in RPM.

    Returns
    -------
    dict
        Figure key ("signature", "overlay", "loops", "errors") -> Path of the PNG written
        (:data:`LOOP_FIGURES`).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    plots = {"signature": signature_plot, "overlay": overlay_plot, "loops": loops_plot, "errors": errors_plot}
    with_units = {"overlay", "loops"}
    for k, name in LOOP_FIGURES.items():
        plots[k](out / name, res, **({"units": units} if k in with_units else {}))
    return {k: out / name for k, name in LOOP_FIGURES.items()}


def _signature_row(axs, res: "LoopResult", before, after, name: str, status: str):
    d = res.data
    from drillpy.loop.data import measured
    Yv, YT = measured(d)
    rv, rT = (Yv - before.v) / d.sigma_v, (YT - before.T) / d.sigma_T
    sv, sT = (after.v - before.v) / d.sigma_v, (after.T - before.T) / d.sigma_T
    ax = axs[0]
    rng = np.random.default_rng(0)  # only thins the scatter for display
    for part, te, cols in (("calibration", ~d.is_test, ("0.75", "0.55")), ("validation", d.is_test, (C_FINAL, C_SIG))):
        for r, s, col, ch in ((rv[te], sv[te], cols[0], "bit speed"), (rT[te], sT[te], cols[1], "torque")):
            r, s = r.ravel(), s.ravel()
            k = rng.choice(r.size, min(r.size, 2500), replace=False)
            ax.scatter(s[k], r[k], s=3, color=col, alpha=0.4, lw=0, label=f"{ch}, {part}")
    lim = np.nanpercentile(np.abs(np.r_[rv.ravel(), rT.ravel()]), 99.5)
    ax.plot([-lim, lim], [-lim, lim], "k--", lw=0.8, label="residual = signature")
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_xlabel(f"signature of {name} (prediction change) [normalized]")
    ax.set_ylabel("residual before [normalized]")
    tr = ~d.is_test
    R, S = np.r_[rv[tr].ravel(), rT[tr].ravel()], np.r_[sv[tr].ravel(), sT[tr].ravel()]
    frac = float((R @ S) ** 2 / ((R @ R) * (S @ S))) if (S @ S) > 0 else 0.0
    ax.set_title(f"{name}: explains {100 * frac:.0f} % of the calibration residual "
                 f"({status})", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=6, markerscale=3, loc="upper left")
    ax = axs[1]
    hs = d.horizon_samples
    te = np.flatnonzero(d.is_test)
    h0 = te[: max(1, int(round(2.0 / (d.L * d.dt))))]
    # the channel the signature moves most (normalized): bit speed [RPM] or torque [N m]
    torque = float(np.sum(sT[tr] ** 2)) > float(np.sum(sv[tr] ** 2))
    r_, s_, scale, what = (rT, sT, d.sigma_T, "torque on bit [N m]") if torque else (rv, sv, d.sigma_v * RPM,
                                                                                        "bit speed [RPM]")
    for j, h in enumerate(h0):
        t = d.t[hs[h]]
        ax.plot(t, r_[h] * scale, color=C_MEAS, lw=0.8, label="residual before" if j == 0 else None)
        ax.plot(t, s_[h] * scale, color=C_SIG, lw=0.8, label="signature (after - before)" if j == 0 else None)
        ax.axvline(d.t[d.starts[h]], color="0.8", lw=0.5)
    shown = np.abs(np.r_[r_[h0].ravel(), s_[h0].ravel()]) * scale
    top = 1.3 * np.percentile(shown, 99) if shown.size else 1.0
    ax.set_ylim(-top, top)  # the sharp torque drops at stick-slip transitions would flatten the rest
    ax.set_xlabel("time [s] (validation part; grey: restarts; clipped at 1.3 x the 99th percentile)")
    ax.set_ylabel(what)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)


def signature_plot(path, res: "LoopResult") -> plt.Figure:
    """Residual versus signature (normalized by the channels' standard deviations) for every step
    and the best rejected candidate of the last round; right: both over time on the validation
    part (bit speed [RPM] or torque [N m]).

    Parameters
    ----------
    path : str or Path
        PNG written.
    res : LoopResult
        A finished loop run (:func:`drillpy.loop.run_loop`).

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    rows = [(s.before, s.candidate, s.effect, STEP_ACTIONS[s.action][1]) for s in res.steps]
    last = res.last_round
    if last:
        name, ev = min(last.items(), key=lambda kv: kv[1].E_test)
        rows.append((res.final, ev, name, "rejected"))
    if not rows:
        rows = [(res.final, res.final, "(no candidate)", "rejected")]
    fig, axes = plt.subplots(len(rows), 2, figsize=(12, 4.2 * len(rows)), squeeze=False)
    for axs, (b, a, n, status) in zip(axes, rows):
        _signature_row(axs, res, b, a, n, status)
    return _save(fig, path)


def _window(res: "LoopResult", seconds: float = 2.5) -> np.ndarray:
    d = res.data
    te = np.flatnonzero(d.is_test)
    return te[: max(1, int(round(seconds / (d.L * d.dt))))]


def overlay_plot(path, res: "LoopResult", units: str = "si") -> plt.Figure:
    """Measured, baseline and final predictions of bit speed [RPM] and torque [N m] on a window
    of the validation part, and the per-horizon error [-] over the whole record.

    Parameters
    ----------
    path : str or Path
        PNG written.
    res : LoopResult
        A finished loop run (:func:`drillpy.loop.run_loop`).

    units : str
        Axis unit of the torque: ``si`` (N m) or ``field`` (ft-lbf).

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    d = res.data
    hs = d.horizon_samples
    fig, axes = plt.subplots(3, 1, figsize=(12, 9))
    w = _window(res)
    t0, t1 = d.t[d.starts[w[0]]], d.t[hs[w[-1]][-1]]
    sel = (d.t >= t0) & (d.t <= t1)
    tscale, tu = in_units(1.0, "record_torque", units)
    for ax, meas, key, scale, unit in ((axes[0], d.v_meas, "v", RPM, "bit speed [RPM]"),
                                       (axes[1], d.T_meas, "T", float(tscale), f"torque on bit [{tu}]")):
        ax.plot(d.t[sel], meas[sel] * scale, color=C_MEAS, lw=1.2, label="measured")
        for j, h in enumerate(w):
            t = d.t[hs[h]]
            ax.plot(t, getattr(res.baseline, key)[h] * scale, color=C_BASE, lw=1,
                    label=("baseline (declared model, calibrated)" if res.steps else
                           "declared model, calibrated (no effect added: final = baseline)") if j == 0 else None)
            if res.steps:
                ax.plot(t, getattr(res.final, key)[h] * scale, color=C_FINAL, lw=1,
                        label="final (" + ", ".join(step_label(s) for s in res.steps) + ")" if j == 0 else None)
            ax.axvline(d.t[d.starts[h]], color="0.85", lw=0.6)
        ax.set_ylabel(unit)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper right")
    axes[1].set_xlabel(f"time [s] (validation part; grey lines: restarts from the measured state every "
                       f"{res.options.horizon_s:g} s)")
    ax = axes[2]
    ts = d.t[d.starts]
    ax.semilogy(ts, np.sqrt(res.baseline.e_h), ".", color=C_BASE, ms=4, label="baseline")
    if res.steps:
        ax.semilogy(ts, np.sqrt(res.final.e_h), ".", color=C_FINAL, ms=4, label="final")
    ax.axvline(d.t_split, color="k", ls="--", lw=1, label="calibration | validation")
    ax.set_xlabel("horizon start [s]")
    ax.set_ylabel("horizon error sqrt(e_h) [-]")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    axes[0].set_title(f"Short-horizon predictions: validation error E {res.baseline.E_test:.3f} (baseline) -> "
                      f"{res.final.E_test:.3f} (final)")
    return _save(fig, path)


def loops_plot(path, res: "LoopResult", units: str = "si") -> plt.Figure:
    """Torque on bit [N m] versus bit speed [RPM] on the validation part: measured, baseline, final.

    Parameters
    ----------
    path : str or Path
        PNG written.
    res : LoopResult
        A finished loop run (:func:`drillpy.loop.run_loop`).

    units : str
        Axis unit of the torque: ``si`` (N m) or ``field`` (ft-lbf).

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    d = res.data
    te = d.is_test
    from drillpy.loop.data import measured
    Yv, YT = measured(d)
    tscale, tu = in_units(1.0, "record_torque", units)
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.2), sharex=True, sharey=True)
    for ax, (v, T, lab, col) in zip(axes, ((Yv, YT, "measured", C_MEAS), (res.baseline.v, res.baseline.T, "baseline", C_BASE),
                                           (res.final.v, res.final.T, "final", C_FINAL))):
        for h in np.flatnonzero(te):
            ax.plot(v[h] * RPM, T[h] * tscale, color=col, lw=0.4, alpha=0.5)
        ax.set_title(f"{lab} (validation horizons)", fontsize=10)
        ax.set_xlabel("bit speed [RPM]")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel(f"torque on bit [{tu}]")
    return _save(fig, path)


#: a loop step's action -> (sign, participle) of its label
STEP_ACTIONS = {"add": ("+", "added"), "remove": ("-", "removed"), "recalibrate": ("~", "recalibrated")}


def step_label(step: dict) -> str:
    """The label of a loop step from its action: ``"+ bit_hysteresis (added)"``, ``"- bit_hysteresis
    (removed)"``, ``"~ string_stiffness (recalibrated)"``.

    Parameters
    ----------
    step : Step
        A step of :attr:`drillpy.loop.LoopResult.steps` (its ``action`` and ``effect``).

    Returns
    -------
    str
        The label.
    """
    sign, done = STEP_ACTIONS[step.action]
    return f"{sign} {step.effect} ({done})"


def errors_plot(path, res: "LoopResult") -> plt.Figure:
    """Validation and calibration error E [-] after each step, and every candidate of every round.

    Parameters
    ----------
    path : str or Path
        PNG written.
    res : LoopResult
        A finished loop run (:func:`drillpy.loop.run_loop`).

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.2))
    ev = [res.baseline] + [s.after for s in res.steps]
    labels = ["baseline"] + [step_label(s) for s in res.steps]
    x = np.arange(len(ev))
    ax = axes[0]
    ax.bar(x - 0.2, [e.E_train for e in ev], 0.4, color="0.6", label="calibration part")
    ax.bar(x + 0.2, [e.E_test for e in ev], 0.4, color=C_FINAL, label="validation part")
    ax.set_xticks(x, labels, rotation=20, fontsize=8)
    ax.set_xlim(-1.0, max(len(ev), 2))
    ax.set_ylabel("normalized prediction error E [-]")
    ax.grid(alpha=0.3, axis="y")
    ax.legend(fontsize=8)
    ax = axes[1]
    from drillpy.loop.effects import CATALOGUE
    names = list(CATALOGUE)
    for r, cands in enumerate(res.rounds):
        for c in cands:
            if c.get("error_test_after") is None:
                continue
            y = names.index(c["effect"])
            ax.plot(c["error_test_after"], y + 0.12 * (r - len(res.rounds) / 2), "o" if c["accepted"] else "x",
                    color=f"C{r}", ms=6, label=f"round {r + 1}" if c is cands[0] else None)
        cur = cands[0].get("error_test_before") if cands else None
        if cur is not None:
            ax.axvline(cur, color=f"C{r}", ls=":", lw=1)
    ax.set_yticks(range(len(names)), names, fontsize=8)
    ax.set_xlabel("validation error E with the candidate [-]")
    ax.set_title("candidates per round (o: passes the guard, x: rejected; dotted: current model)", fontsize=9)
    ax.grid(alpha=0.3)
    if ax.get_legend_handles_labels()[0]:  # no round, no legend (matplotlib would warn)
        ax.legend(fontsize=7)
    return _save(fig, path)
