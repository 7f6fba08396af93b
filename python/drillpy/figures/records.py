"""Figures of measured records and their analysis (Figs. 3.5, 4.3, 5.5-5.7 and the rig comparison).

Speeds are plotted in RPM, torques in N m, WOB in N (``units="field"``: ft-lbf and lbf), times in s
(inputs in SI: rad/s, N m, N, s).
:func:`analysis_figures` draws every figure of a :class:`drillpy.records.analysis.RecordAnalysis`;
each ``*_plot`` function draws one figure from results already computed, writes one PNG and returns
its path (Agg backend via :mod:`drillpy.figures.simulation`).
"""
from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from drillpy.figures.simulation import _save, in_units, plt
from drillpy.records.io import RPM, Flag

if TYPE_CHECKING:
    from drillpy.records.analysis import RecordAnalysis

C_BIT, C_TOP, C_TQ, C_WOB = "tab:blue", "0.25", "tab:purple", "tab:green"
C_UP, C_LO, C_ALL = "tab:red", "tab:cyan", "k"


def analysis_figures(result: "RecordAnalysis", out_dir, units: str = "si") -> list:
    """Every figure of a record's analysis, written to ``out_dir``.

    Parameters
    ----------
    result : RecordAnalysis
        What :func:`drillpy.records.analysis.compute_analysis` returned.
    out_dir : str or Path
        Output folder (created if missing).
    units : str
        Axis units of torque and WOB: ``si`` (N m, N) or ``field`` (ft-lbf, lbf); speeds in RPM.

    Returns
    -------
    list of Path
        time_series.png, cleaning.png, cycle.png, loops.png, cycle_statistics.png, laws.png,
        psd.png and, when the rig was simulated, rig_time_series.png and rig_loops.png.
    """
    from drillpy.uncertainty.process import THESIS_PSD
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    r, rec = result, result.record
    paths = []

    def draw(name, plot, *args, **kwargs):  # every *_plot returns its figure: keep the file's path
        plot(out / name, *args, **kwargs)
        paths.append(out / name)
    draw("time_series.png", record_time_series_plot, r.raw, rec, r.cleaning, units=units)
    draw("cleaning.png", cleaning_plot, r.raw, rec, r.cleaning)
    draw("cycle.png", cycle_plot, rec, r.cycles, r.shown_cycle, units=units)
    draw("loops.png", loops_plot, rec, r.branch, r.mean_cycle, r.mean_cycle_wob, units=units)
    draw("cycle_statistics.png", cycle_statistics_plot, r.cycle_stats, r.stick_threshold_rad_s)
    draw("laws.png", laws_plot, rec, r.branch, r.accel_rad_s2, r.mean_cycle, r.fits["constant_wob"],
         "laws fitted at constant WOB (sample set: slip phases of valid cycles)", units=units)
    draw("psd.png", eta_psd_plot, r.eta, r.freq_hz, r.periodogram, r.psd_fit.model, THESIS_PSD, list(r.psd_band_hz))
    if r.simulations:
        draw("rig_time_series.png", rig_time_series_plot, rec, r.simulations, units=units)
        draw("rig_loops.png", rig_loops_plot, r.simulations, units=units)
    return paths


def _tq(values, units: str):
    """A record's torques [N m] in the figure units (N m or ft-lbf)."""
    return in_units(values, "record_torque", units)[0]


def _wob(values, units: str):
    """A record's WOB [N] in the figure units (N or lbf)."""
    return in_units(values, "record_force", units)[0]


def _labels(units: str) -> tuple:
    """The torque and WOB units' labels of the figure units (``N m``, ``N`` or ``ft-lbf``, ``lbf``)."""
    return in_units(0.0, "record_torque", units)[1], in_units(0.0, "record_force", units)[1]


def _rmse_label(fit, units: str) -> str:
    """A law's legend entry: its name and RMSE in the figure's torque unit."""
    return f"{fit.name} (RMSE {float(_tq(fit.rmse, units)):.3f} {_labels(units)[0]})"


def _artifact_spans(ax, rec, report, alpha=0.25):
    """Shade the artifact spans (top speed) on an axis."""
    done = set()
    for a in report.artifacts:
        if a.kind in ("spike", "oscillation", "gap", "nonfinite", "flatline") and (a.start_s, a.end_s) not in done:
            ax.axvspan(a.start_s, max(a.end_s, a.start_s + 0.02), color="orange", alpha=alpha, lw=0)
            done.add((a.start_s, a.end_s))


def record_time_series_plot(path, raw, rec, report, title="", units="si") -> plt.Figure:
    """Fig. 5.5: bit and top speed, torque on bit and WOB of the whole record; raw top speed in
    light red where cleaning changed it, artifact spans shaded.

    Parameters
    ----------
    path : str or Path
        PNG written.
    raw : Record
        The record as read (speeds [rad/s]).
    rec : Record
        The cleaned record (speeds [rad/s], torque [N m], WOB [N]).
    report : CleaningReport
        Artifacts found by the cleaning (their spans [s] are shaded).
    title : str
        Figure title.

    units : str
        Axis units of torque and WOB (:data:`drillpy.figures.simulation.FIGURE_UNITS`): ``si`` (N m, N)
        or ``field`` (ft-lbf, lbf); speeds stay in RPM.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    tu, wu = _labels(units)
    n = 1 + (rec.torque_on_bit is not None) + (rec.wob is not None)
    fig, axes = plt.subplots(n, 1, figsize=(11, 2.4 * n + 0.6), sharex=True)
    axes = np.atleast_1d(axes)
    ax = axes[0]
    if rec.top_speed is not None:
        changed = rec.flagged("top_speed", Flag.REPAIRED) | rec.flagged("top_speed", Flag.UNRELIABLE)
        if changed.any() and raw.top_speed is not None and raw.top_speed.size == rec.top_speed.size:
            ax.plot(raw.time_s, raw.top_speed * RPM, color="tab:red", lw=0.4, alpha=0.6,
                    label="top speed as recorded (artifacts)")
        ax.plot(rec.time_s, rec.top_speed * RPM, color=C_TOP, lw=0.5, label="top speed (cleaned)")
    ax.plot(rec.time_s, rec.bit_speed * RPM, color=C_BIT, lw=0.6, label="bit speed")
    _artifact_spans(ax, rec, report)
    ax.set_ylabel("speed [RPM]")
    ax.legend(fontsize=8, loc="lower left", ncol=3)
    k = 1
    if rec.torque_on_bit is not None:
        axes[k].plot(rec.time_s, _tq(rec.torque_on_bit, units), color=C_TQ, lw=0.5)
        axes[k].set_ylabel(f"torque on bit [{tu}]")
        k += 1
    if rec.wob is not None:
        axes[k].plot(rec.time_s, _wob(rec.wob, units), color=C_WOB, lw=0.5)
        axes[k].set_ylabel(f"WOB [{wu}]")
    for a in axes:
        a.grid(alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    axes[0].set_title(title or "Measured record (cf. Fig. 5.5); shaded: artifacts found by the cleaning")
    return _save(fig, path)


def cleaning_plot(path, raw, rec, report) -> plt.Figure:
    """Raw versus cleaned channel around the largest artifact stretch and the first spike.

    Parameters
    ----------
    path : str or Path
        PNG written.
    raw, rec : Record
        The record as read and cleaned (speeds [rad/s]).
    report : CleaningReport
        Artifacts found by the cleaning.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    arts = [a for a in report.artifacts if a.kind in ("oscillation", "spike", "nonfinite", "gap", "time", "flatline")]
    show = sorted(arts, key=lambda a: -a.samples)[:1] + [a for a in arts if a.kind == "spike"][:1]
    show = list({(a.start_s, a.channel): a for a in show}.values())
    if not show:
        fig, ax = plt.subplots(figsize=(7, 2.5))
        ax.text(0.5, 0.5, "no artifact found", ha="center", va="center", transform=ax.transAxes)
        ax.set_axis_off()
        return _save(fig, path)
    fig, axes = plt.subplots(1, len(show), figsize=(6 * len(show), 3.6), squeeze=False)
    for ax, a in zip(axes[0], show):
        pad = max(0.15, 0.3 * (a.end_s - a.start_s))
        m = (rec.time_s >= a.start_s - pad) & (rec.time_s <= a.end_s + pad)
        name = a.channel if a.channel != "time" else rec.channels[0]
        x_raw = getattr(raw, name)
        if x_raw is not None and x_raw.size == rec.time_s.size:
            ax.plot(raw.time_s[m], x_raw[m] * (RPM if "speed" in name else 1), color="tab:red", lw=0.8,
                    label=f"{name} as recorded")
        ax.plot(rec.time_s[m], getattr(rec, name)[m] * (RPM if "speed" in name else 1), "k", lw=1.0,
                label=f"{name} cleaned")
        if name != "bit_speed" and rec.bit_speed is not None:
            ax.plot(rec.time_s[m], rec.bit_speed[m] * RPM, color=C_BIT, lw=0.8, label="bit speed")
        ax.axvspan(a.start_s, a.end_s, color="orange", alpha=0.2, lw=0)
        ax.set_title(f"{a.kind}: {a.start_s:.3f}-{a.end_s:.3f} s ({a.samples} samples)", fontsize=9)
        ax.set_xlabel("time [s]")
        ax.set_ylabel("speed [RPM]" if "speed" in name else name)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="lower right")
    return _save(fig, path)


def cycle_plot(path, rec, cycles, j, window_s=3.0, units="si") -> plt.Figure:
    """Figs. 5.6-5.7: a window of ``window_s`` around cycle j (bit and top speed, torque, WOB) and
    the cycle itself: bit speed versus time, torque versus bit speed, WOB versus bit speed (red
    dot: start of the cycle; arrows: direction).

    Parameters
    ----------
    path : str or Path
        PNG written.
    rec : Record
        The cleaned record (speeds [rad/s], torque [N m], WOB [N]).
    cycles : Cycles
        Stick-slip cycles of ``rec``.
    j : int
        Index of the cycle shown.
    window_s : float
        Length of the window on the left [s].

    units : str
        Axis units of torque and WOB (:data:`drillpy.figures.simulation.FIGURE_UNITS`): ``si`` (N m, N)
        or ``field`` (ft-lbf, lbf); speeds stay in RPM.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    t = rec.time_s
    tu, wu = _labels(units)
    tq = _tq(rec.torque_on_bit, units)
    wob = None if rec.wob is None else _wob(rec.wob, units)
    a, b = cycles.start[j], cycles.end[j]
    tc = 0.5 * (t[a] + t[b])
    m = (t >= tc - window_s / 2) & (t <= tc + window_s / 2)
    has_w = rec.wob is not None
    fig = plt.figure(figsize=(13, 7.5))
    gs = fig.add_gridspec(3, 3, width_ratios=[1.6, 1, 1])
    ax1 = fig.add_subplot(gs[0, 0])
    ax1.plot(t[m], rec.bit_speed[m] * RPM, color=C_BIT, lw=1, label="bit speed")
    if rec.top_speed is not None:
        ax1.plot(t[m], rec.top_speed[m] * RPM, color=C_TOP, lw=0.7, label="top speed")
    ax1.set_ylabel("speed [RPM]")
    ax1.legend(fontsize=8, loc="upper right")
    ax2 = fig.add_subplot(gs[1, 0], sharex=ax1)
    ax2.plot(t[m], tq[m], color=C_TQ, lw=1)
    ax2.set_ylabel(f"torque on bit [{tu}]")
    ax3 = fig.add_subplot(gs[2, 0], sharex=ax1)
    if has_w:
        ax3.plot(t[m], wob[m], color=C_WOB, lw=1)
    ax3.set_ylabel(f"WOB [{wu}]")
    ax3.set_xlabel("time [s]")
    for ax in (ax1, ax2, ax3):
        ax.axvspan(t[a], t[b], color="gold", alpha=0.25, lw=0)
        ax.axvline(t[cycles.peak[j]], color="0.5", ls=":", lw=0.8)
        ax.grid(alpha=0.3)
    ax1.set_title(f"Stick-slip cycles around {tc:.2f} s (cf. Fig. 5.6); shaded: the cycle on the right", fontsize=10)
    sl = slice(a, b + 1)
    v = rec.bit_speed[sl] * RPM
    ax4 = fig.add_subplot(gs[:, 1])
    ax4.plot(t[sl], v, color=C_BIT)
    ax4.plot(t[a], v[0], "ro")
    ax4.set_xlabel("time [s]")
    ax4.set_ylabel("bit speed [RPM]")
    ax4.set_title("(a) bit speed", fontsize=10)
    ax5 = fig.add_subplot(gs[:2, 2])
    _arrow_path(ax5, v, tq[sl], C_TQ)
    ax5.set_ylabel(f"torque on bit [{tu}]")
    ax5.set_title("(b) torque vs bit speed", fontsize=10)
    ax6 = fig.add_subplot(gs[2, 2], sharex=ax5)
    if has_w:
        _arrow_path(ax6, v, wob[sl], C_WOB)
    ax6.set_ylabel(f"WOB [{wu}]")
    ax6.set_xlabel("bit speed [RPM]")
    ax6.set_title("(c) WOB vs bit speed", fontsize=10)
    for ax in (ax4, ax5, ax6):
        ax.grid(alpha=0.3)
    fig.suptitle(f"One cycle {t[a]:.3f}-{t[b]:.3f} s: period {t[b] - t[a]:.3f} s, stick "
                 f"{cycles.stick_s[j]:.3f} s (cf. Fig. 5.7)", fontsize=11)
    return _save(fig, path)


def _arrow_path(ax, x, y, color):
    ax.plot(x, y, color=color, lw=1.2)
    ax.plot(x[0], y[0], "ro")
    n = len(x)
    for k in np.linspace(n * 0.1, n * 0.9, 5).astype(int):
        k2 = min(k + max(1, n // 50), n - 1)
        ax.annotate("", xy=(x[k2], y[k2]), xytext=(x[k], y[k]),
                    arrowprops=dict(arrowstyle="->", color="r", lw=1.2))


def loops_plot(path, rec, labels, mc, mcw=None, units="si") -> plt.Figure:
    """Torque (and WOB) versus bit speed over all valid cycles with the mean cycle per branch
    (Fig. 3.5): thin lines, red on the accelerating branch, cyan on the decelerating one.

    Parameters
    ----------
    path : str or Path
        PNG written.
    rec : Record
        The cleaned record (bit speed [rad/s], torque [N m], WOB [N]).
    labels : ndarray
        Per sample: +1 accelerating branch, -1 decelerating, 0 neither.
    mc : MeanCycle
        Mean cycle of the torque [N m] over bit speed [rad/s].
    mcw : MeanCycle, optional
        Mean cycle of the WOB [N] (a second panel).

    units : str
        Axis units of torque and WOB (:data:`drillpy.figures.simulation.FIGURE_UNITS`): ``si`` (N m, N)
        or ``field`` (ft-lbf, lbf); speeds stay in RPM.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    v = rec.bit_speed * RPM
    tu, wu = _labels(units)
    panels = [(f"torque on bit [{tu}]", rec.torque_on_bit, mc, _tq)]
    if rec.wob is not None and mcw is not None:
        panels.append((f"WOB [{wu}]", rec.wob, mcw, _wob))
    fig, axes = plt.subplots(1, len(panels), figsize=(6.5 * len(panels), 4.8), squeeze=False)
    for ax, (lab, y, m, conv) in zip(axes[0], panels):
        for s, col in ((1, C_UP), (-1, C_LO)):
            yy = np.where(labels == s, conv(y, units), np.nan)
            ax.plot(v, yy, color=col, lw=0.25, alpha=0.35)
        ax.plot(m.speed * RPM, conv(m.upper, units), color="darkred", lw=2.2, label="mean, accelerating (upper) branch")
        ax.plot(m.speed * RPM, conv(m.lower, units), color="navy", lw=2.2, label="mean, decelerating (lower) branch")
        ax.plot(m.speed * RPM, conv(m.all, units), color=C_ALL, lw=2, ls="--",
                label="mean of all cycles" + (" (T_hys of Eq. 4.2)" if m is mc else ""))
        ax.set_xlabel("bit speed [RPM]")
        ax.set_ylabel(lab)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    axes[0][0].set_title("Slip phases of all valid cycles and their mean cycle (cf. Fig. 3.5)", fontsize=10)
    return _save(fig, path)


def cycle_statistics_plot(path, cst, stick_threshold) -> plt.Figure:
    """Per-cycle period, stick duration and SS versus the cycle's start time.

    Parameters
    ----------
    path : str or Path
        PNG written.
    cst : dict
        Per-cycle statistics (:func:`drillpy.records.signals.cycle_statistics`): start_s,
        period_s, stick_s [s], optionally ss [-].
    stick_threshold : float
        Stick threshold [rad/s] (shown in the title in RPM).

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    keys = [("period_s", "period [s]"), ("stick_s", "stick duration [s]")]
    if "ss" in cst:
        keys.append(("ss", "SS of the cycle (Eq. 3.4) [-]"))
    fig, axes = plt.subplots(len(keys), 1, figsize=(9, 2.3 * len(keys) + 0.5), sharex=True)
    for ax, (k, lab) in zip(np.atleast_1d(axes), keys):
        ax.plot(cst["start_s"], cst[k], "o-", ms=3, lw=0.6)
        ax.axhline(np.median(cst[k]), color="r", ls="--", lw=0.8, label=f"median {np.median(cst[k]):.3f}")
        ax.set_ylabel(lab)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper right")
        if k == "ss":
            ax.axhline(0.5, color="k", ls=":", lw=0.8)
    np.atleast_1d(axes)[-1].set_xlabel("cycle start [s]")
    np.atleast_1d(axes)[0].set_title(f"Per-cycle statistics ({len(cst['period_s'])} valid cycles; stick: bit "
                                     f"speed <= {stick_threshold * RPM:.2f} RPM)", fontsize=10)
    return _save(fig, path)


def laws_plot(path, rec, labels, accel, mc, fits, subtitle="", units="si") -> plt.Figure:
    """Fitted laws over the data: slip samples (grey), mean cycle branches, and each law; the
    hysteretic laws are drawn twice, at the mean acceleration of each branch.

    Parameters
    ----------
    path : str or Path
        PNG written.
    rec : Record
        The cleaned record (bit speed [rad/s], torque [N m]).
    labels : ndarray
        Per sample: +1 accelerating branch, -1 decelerating, 0 neither.
    accel : ndarray
        Bit acceleration [rad/s^2] (unused: the branches' mean accelerations are drawn).
    mc : MeanCycle
        Mean cycle of the torque [N m] over bit speed [rad/s].
    fits : list of LawFit
        The fitted laws.
    subtitle : str
        Second line of the title.

    units : str
        Axis units of torque and WOB (:data:`drillpy.figures.simulation.FIGURE_UNITS`): ``si`` (N m, N)
        or ``field`` (ft-lbf, lbf); speeds stay in RPM.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    v = rec.bit_speed * RPM
    tu = _labels(units)[0]
    m = labels != 0
    fig, ax = plt.subplots(figsize=(9, 5.5))
    ax.plot(v[m][::5], _tq(rec.torque_on_bit[m][::5], units), ".", color="0.8", ms=1.5, label="slip samples")
    ax.plot(mc.speed * RPM, _tq(mc.upper, units), color="darkred", lw=2.5, alpha=0.5, label="data: accelerating branch")
    ax.plot(mc.speed * RPM, _tq(mc.lower, units), color="navy", lw=2.5, alpha=0.5, label="data: decelerating branch")
    sp = mc.speed[1:]
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, f in enumerate(fits):
        col = colors[k % len(colors)]
        hyst = f.law.get("beta1", 0.0) > 0
        if hyst:
            up = np.interp(sp, mc.speed, np.nan_to_num(mc.accel_upper))
            lo = np.interp(sp, mc.speed, np.nan_to_num(mc.accel_lower))
            ax.plot(sp * RPM, _tq(f.predict(sp, up), units), color=col, lw=1.6, label=_rmse_label(f, units))
            ax.plot(sp * RPM, _tq(f.predict(sp, lo), units), color=col, lw=1.6, ls="--")
        else:
            ax.plot(sp * RPM, _tq(f.predict(sp, 0.0), units), color=col, lw=1.6, label=_rmse_label(f, units))
    hi = np.nanpercentile(_tq(rec.torque_on_bit[m], units), 99.5)
    ax.set_ylim(0, hi * 1.1)
    ax.set_xlabel("bit speed [RPM]")
    ax.set_ylabel(f"torque on bit [{tu}]")
    ax.set_title("Fitted bit-rock laws (hysteretic: solid accelerating, dashed decelerating)\n" + subtitle,
                 fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper right")
    return _save(fig, path)


def eta_psd_plot(path, eta, f, p, model, thesis, band) -> plt.Figure:
    """eta_exp(t) over 5 s and its periodogram with the log-binned average, the fitted PSD model
    (Eq. 4.4) over the fit band and the thesis's field model.

    Parameters
    ----------
    path : str or Path
        PNG written.
    eta : EtaSeries
        eta_exp [-] on a uniform time grid [s].
    f, p : ndarray
        Periodogram of eta_exp: frequency [Hz], one-sided PSD [1/Hz].
    model, thesis : PsdModel
        The fitted model and the thesis's field model (callables: f [Hz] -> PSD [1/Hz]).
    band : (float, float)
        Fit band [Hz].

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    from drillpy.records.signals import log_binned
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(9, 7.5))
    t0 = eta.t[0] + 0.5 * (eta.t[-1] - eta.t[0])
    m = (eta.t >= t0) & (eta.t <= t0 + 5)
    a1.plot(eta.t[m], eta.eta[m], color="0.6", lw=0.6, label="interpolated (stick phases)")
    a1.plot(eta.t[m], np.where(eta.measured[m], eta.eta[m], np.nan), "k", lw=0.7, label="eta_exp (slip samples)")
    a1.set_xlabel("time [s]")
    a1.set_ylabel("eta_exp [-]")
    a1.set_title("Experimental fluctuation process eta_exp = T / T_hys - 1 (Eq. 4.2)", fontsize=10)
    a1.legend(fontsize=8, loc="upper right")
    a1.grid(alpha=0.3)
    keep = f > 0
    f, p = f[keep], p[keep]
    a2.loglog(f, p, color="0.75", lw=0.4, label="raw periodogram (Schuster)")
    fb, pb, _ = log_binned(f, p)
    a2.loglog(fb, pb, "b.-", ms=3, lw=0.8, label="log-binned average (display)")
    ff = np.geomspace(f[0], f[-1], 400)
    inb = (ff >= band[0]) & (ff <= band[1])
    a2.loglog(ff[inb], model(ff[inb]), "r", lw=2,
              label=f"fit: f0 {model.f0:.2f} Hz, A0 {model.A0:.2f}, a {model.a:.2f}, b {model.b:.2f}")
    a2.loglog(ff, thesis(ff), "k--", lw=1.2,
              label=f"thesis field model (f0 {thesis.f0} Hz, A0 {thesis.A0}, a {thesis.a}, b {thesis.b})")
    a2.axvspan(band[1], f[-1], color="0.9", lw=0)
    a2.set_xlabel("frequency [Hz]")
    a2.set_ylabel("PSD of eta [1/Hz] (one-sided)")
    a2.set_title("PSD of eta_exp and the model of Eq. (4.4) (grey band: outside the fit band)", fontsize=10)
    a2.grid(alpha=0.3, which="both")
    a2.legend(fontsize=8, loc="lower left")
    return _save(fig, path)


def _case_axes(n, rows_per_case, size):
    """Axes for n cases, two cases per row, ``rows_per_case`` stacked panels per case."""
    ncol = 1 if n == 1 else 2
    nrow = -(-n // ncol)
    fig, axes = plt.subplots(nrow * rows_per_case, ncol, figsize=(size[0] * ncol, size[1] * nrow), squeeze=False)
    blocks = []
    for k in range(nrow * ncol):
        r, col = divmod(k, ncol)
        block = [axes[rows_per_case * r + i][col] for i in range(rows_per_case)]
        if k < n:
            blocks.append(block)
        else:
            for ax in block:
                ax.set_axis_off()
    return fig, blocks


def rig_time_series_plot(path, rec, sims, window_s=2.0, units="si") -> plt.Figure:
    """Measured versus simulated bit speed and torque on bit over a window after the start-up,
    one block of two panels per simulated case.

    Parameters
    ----------
    path : str or Path
        PNG written.
    rec : Record
        The measured record (speeds [rad/s], torque [N m]).
    sims : dict
        Case label -> (simulated Record, RigComparison).
    window_s : float
        Length of the window shown [s], starting at 75 % of the record.

    units : str
        Axis units of torque and WOB (:data:`drillpy.figures.simulation.FIGURE_UNITS`): ``si`` (N m, N)
        or ``field`` (ft-lbf, lbf); speeds stay in RPM.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    t = rec.time_s
    tu = _labels(units)[0]
    t0 = t[0] + 0.75 * (t[-1] - t[0])
    m = (t >= t0) & (t <= t0 + window_s)
    fig, blocks = _case_axes(len(sims), 2, (7.0, 5.0))
    for k, ((label, (sim, cmp)), (a1, a2)) in enumerate(zip(sims.items(), blocks)):
        ms = (sim.time_s >= t0) & (sim.time_s <= t0 + window_s)
        a1.plot(t[m], rec.bit_speed[m] * RPM, color=C_BIT, lw=1.2, label="measured bit speed")
        a1.plot(sim.time_s[ms], sim.bit_speed[ms] * RPM, "r", lw=1.2, label="simulated bit speed")
        a1.plot(sim.time_s[ms], sim.top_speed[ms] * RPM, color=C_TOP, lw=0.7, label="top speed (drive)")
        a2.plot(t[m], _tq(rec.torque_on_bit[m], units), color=C_BIT, lw=1.2, label="measured")
        a2.plot(sim.time_s[ms], _tq(sim.torque_on_bit[ms], units), "r", lw=1.2, label="simulated")
        a1.set_title(label + f"  (mismatch {cmp.mismatch:.3f})", fontsize=9)
        a1.set_ylabel("speed [RPM]")
        a2.set_ylabel(f"torque on bit [{tu}]")
        a2.set_xlabel("time [s]")
        for a in (a1, a2):
            a.grid(alpha=0.3)
        if k == 0:
            a1.legend(fontsize=7, loc="upper left", ncol=3)
            a2.legend(fontsize=7, loc="lower left", ncol=2)
    return _save(fig, path)


def rig_loops_plot(path, sims, units="si") -> plt.Figure:
    """Torque versus bit speed: mean cycle per branch, measured versus simulated, per case.

    Parameters
    ----------
    path : str or Path
        PNG written.
    sims : dict
        Case label -> (simulated Record, RigComparison with the mean cycles [N m over rad/s]).

    units : str
        Axis units of torque and WOB (:data:`drillpy.figures.simulation.FIGURE_UNITS`): ``si`` (N m, N)
        or ``field`` (ft-lbf, lbf); speeds stay in RPM.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    tu = _labels(units)[0]
    fig, blocks = _case_axes(len(sims), 1, (6.2, 4.2))
    for k, ((label, (sim, cmp)), (ax,)) in enumerate(zip(sims.items(), blocks)):
        mm, ms = cmp.mean_cycle_measured, cmp.mean_cycle_simulated
        if mm is not None:
            ax.plot(mm.speed * RPM, _tq(mm.upper, units), color="darkred", lw=2, label="measured, accelerating")
            ax.plot(mm.speed * RPM, _tq(mm.lower, units), color="navy", lw=2, label="measured, decelerating")
        if ms is not None:
            ax.plot(ms.speed * RPM, _tq(ms.upper, units), color="darkred", lw=1.4, ls="--", label="simulated, accelerating")
            ax.plot(ms.speed * RPM, _tq(ms.lower, units), color="navy", lw=1.4, ls="--", label="simulated, decelerating")
            extra = f"loop rms {float(_tq(cmp.loop_rms_nm, units)):.3f} {tu}"
        else:
            m = sim.time_s >= sim.time_s[0] + 2.0
            ax.plot(sim.bit_speed[m] * RPM, _tq(sim.torque_on_bit[m], units), ".", color="0.5", ms=1,
                    label="simulated (no stick-slip cycle)")
            extra = "simulation: no stick-slip cycle"
        ax.set_title(_wrap(label, 70) + "\n" + extra, fontsize=9)
        ax.set_xlabel("bit speed [RPM]")
        ax.set_ylabel(f"torque on bit [{tu}]")
        ax.grid(alpha=0.3)
        if k == 0:
            ax.legend(fontsize=7)
    return _save(fig, path)


def _wrap(s, width=48):
    import textwrap
    return "\n".join(textwrap.wrap(s, width))


def prediction_overlay_plot(path, rec, sim, stick_threshold, label, window_s=3.0, units="si") -> plt.Figure:
    """A model's prediction of a record it was not calibrated on: bit speed, top speed and torque
    on bit over the whole record (top) and over a window in its middle (bottom), measured and
    simulated, with the stick threshold.

    Parameters
    ----------
    path : str or Path
        PNG written.
    rec, sim : Record
        Measured and predicted records (speeds [rad/s], torque [N m]).
    stick_threshold : float
        Stick threshold [rad/s].
    label : str
        What the prediction is (in the title).
    window_s : float
        Length of the middle window [s].

    units : str
        Axis units of torque and WOB (:data:`drillpy.figures.simulation.FIGURE_UNITS`): ``si`` (N m, N)
        or ``field`` (ft-lbf, lbf); speeds stay in RPM.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    fig, axes = plt.subplots(3, 1, figsize=(9.0, 7.5))
    t, ts = rec.time_s, sim.time_s
    tm = t[0] + 0.5 * (t[-1] - t[0])
    for ax, sel, sels in ((axes[0], slice(None), slice(None)),
                          (axes[1], (t >= tm) & (t <= tm + window_s), (ts >= tm) & (ts <= tm + window_s))):
        ax.plot(t[sel], rec.bit_speed[sel] * RPM, color=C_BIT, lw=0.8, label="measured bit speed")
        ax.plot(ts[sels], sim.bit_speed[sels] * RPM, "r", lw=0.8, alpha=0.8, label="predicted bit speed")
        ax.plot(ts[sels], sim.top_speed[sels] * RPM, color=C_TOP, lw=0.7, label="predicted top speed")
        ax.axhline(stick_threshold * RPM, color="k", lw=0.6, ls=":", label="stick threshold")
        ax.set_ylabel("speed [RPM]")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7, loc="upper right", ncol=4)
    axes[0].set_title(f"prediction ({label})", fontsize=9)
    sel = (t >= tm) & (t <= tm + window_s)
    sels = (ts >= tm) & (ts <= tm + window_s)
    axes[2].plot(t[sel], _tq(rec.torque_on_bit[sel], units), color=C_BIT, lw=1.0, label="measured")
    axes[2].plot(ts[sels], _tq(sim.torque_on_bit[sels], units), "r", lw=1.0, label="predicted")
    axes[2].set_ylabel(f"torque on bit [{_labels(units)[0]}]")
    axes[2].set_xlabel("time [s]")
    axes[2].grid(alpha=0.3)
    axes[2].legend(fontsize=7)
    fig.tight_layout()
    return _save(fig, path)


def samples_boxplot(path, samples: list) -> plt.Figure:
    """Fig. 5.4: box plot of the per-cycle SS (Eq. 3.4), one box per sample, SS = 0.5 marked.

    SS below 0.5 is the thesis's stable region (section 3.3). A sample without a cycle with SS
    keeps its label and gets no box.

    Parameters
    ----------
    path : str or Path
        Image file to write (``fig5_4_boxplot.png`` in :func:`drillpy.reports.samples.analyze_samples`).
    samples : list of dict
        :func:`drillpy.records.samples.analyze_sample` results (``sample`` and ``cycles["ss"]`` are used).

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    fig, ax = plt.subplots(figsize=(max(5.0, 0.9 * len(samples) + 2.5), 4.2))
    data = [np.asarray(s["cycles"]["ss"], float) for s in samples]
    labels = [f"{s['sample']}\n(n={len(d)})" for s, d in zip(samples, data)]
    pos = [i for i, d in enumerate(data, 1) if d.size]
    if pos:
        ax.boxplot([data[i - 1] for i in pos], positions=pos, widths=0.6, showmeans=True)
    ax.set_xticks(range(1, len(samples) + 1))
    ax.set_xticklabels(labels, fontsize=8)
    ax.set_xlim(0.4, len(samples) + 0.6)
    ax.axhline(0.5, color="tab:red", ls="--", lw=0.8, label="SS = 0.5 (stable below)")
    ax.set_ylabel("stick-slip severity SS per cycle (Eq. 3.4)")
    ax.set_title("per-cycle SS by sample (Fig. 5.4)")
    ax.legend(loc="best", fontsize=8)
    return _save(fig, path)
