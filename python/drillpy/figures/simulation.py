"""Figures of deterministic simulations: time series, SS versus top speed, stability maps.

Matplotlib with the Agg backend (files only, no screen needed); axes carry units. Every ``*_plot``
function draws one figure from results already computed, writes one PNG (unless its path is None) and returns its matplotlib Figure.
"""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

RPM = 30.0 / np.pi  # rad/s -> RPM

#: Units of the figures' axes (``units=`` of every plot of :mod:`drillpy.figures`; ``--figure-units``
#: of the commands): figure quantity -> unit, a unit of :data:`drillpy.units.UNITS`. ``si`` is the SI
#: one (the stability map keeps the thesis's RPM and kN), ``field`` the one a drilling engineer reads
#: on the rig. ``record_force`` and ``record_torque`` are a measured record's WOB and torque (rig scale:
#: N and N m, or lbf and ft-lbf); ``length`` a depth or a string length.
FIGURE_UNITS = {"si": {"speed": "rad/s", "force": "kN", "torque": "N m", "record_force": "N",
                       "record_torque": "N m", "length": "m"},
                "field": {"speed": "rpm", "force": "klbf", "torque": "kft-lbf", "record_force": "lbf",
                          "record_torque": "ft-lbf", "length": "ft"}}
_LABEL = {"rad/s": "rad/s", "rpm": "RPM", "kn": "kN", "klbf": "klbf", "n m": "N m", "kft-lbf": "kft-lbf",
          "n": "N", "lbf": "lbf", "ft-lbf": "ft-lbf", "m": "m", "ft": "ft"}
#: figure quantity -> quantity of :data:`drillpy.units.UNITS`
_KIND = {"record_force": "force", "record_torque": "torque"}


def _unit(units: str, quantity: str) -> str:
    """The axis unit of ``quantity`` in the figure units ``units`` (``si`` or ``field``)."""
    if units not in FIGURE_UNITS:
        raise ValueError(f"units = {units!r}: use one of {', '.join(FIGURE_UNITS)}")
    return FIGURE_UNITS[units][quantity]


def _convert(values, quantity: str, unit: str, source: str | None = None):
    """SI ``values`` (or values in ``source``) in ``unit`` (:func:`drillpy.units.grid_in_si`)."""
    from drillpy.units import grid_in_si
    return grid_in_si(np.asarray(values, float), source, _KIND.get(quantity, quantity), to=unit)


def in_units(values, quantity: str, units: str = "si", source: str | None = None):
    """Values for an axis in the figure units, and the unit's label.

    Parameters
    ----------
    values : array_like
        The values, SI (or in ``source``).
    quantity : str
        A figure quantity (a key of ``FIGURE_UNITS["si"]``: ``speed``, ``force``, ``torque``, ...).
    units : str
        ``si`` or ``field`` (:data:`FIGURE_UNITS`).
    source : str, optional
        Unit of ``values`` when not SI (e.g. ``"kN"``).

    Returns
    -------
    tuple
        (ndarray in the axis unit, its label such as ``"RPM"``).
    """
    u = _unit(units, quantity)
    return _convert(values, quantity, u, source), _LABEL[u.lower()]


def _save(fig, path):
    """Lay out ``fig`` and return it; with a ``path``, write it there atomically first (130 dpi, parent
    folders created, the drillpy version as the image's ``Software`` metadata) and close it (a closed
    figure still displays and saves). Every ``*_plot`` of :mod:`drillpy.figures` ends here, so each
    returns its :class:`matplotlib.figure.Figure`, and ``path=None`` draws without writing."""
    from drillpy import __version__
    fig.tight_layout()
    if path is None:
        return fig
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    from drillpy.outputs import replacing
    with replacing(path) as tmp:  # whole or not at all
        fig.savefig(tmp, dpi=130, metadata={"Software": f"drillpy {__version__}"}, format=path.suffix[1:] or "png")
    plt.close(fig)
    return fig


def severity_plot(path, speeds, ss, threshold=None, level=0.5, title="", extra=None, units="si") -> plt.Figure:
    """SS versus top speed (Fig. 4.8).

    Parameters
    ----------
    path : str or Path
        PNG written.
    speeds : array_like
        Top-drive speeds [rad/s].
    ss : array_like
        Stick-slip severity at each speed [-].
    threshold : float, optional
        Speed below which SS exceeds ``level`` [rad/s], drawn as a vertical line.
    level : float
        Stability threshold of SS [-].
    title : str
        Figure title (default: a generic one).
    extra : list of (str, array_like, array_like), optional
        Further curves: label, speeds [rad/s], SS [-].
    units : str
        Axis units (:data:`FIGURE_UNITS`): ``si`` (rad/s) or ``field`` (RPM); the data stay in rad/s.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    u = _unit(units, "speed")
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    ax.plot(_convert(speeds, "speed", u), ss, "k.-", label="SS (deterministic)")
    for label, sp, s in extra or []:
        ax.plot(_convert(sp, "speed", u), s, ".-", label=label)
    ax.axhline(level, color="r", ls="--", label=f"stability threshold SS = {level}")
    if threshold is not None:
        thr = float(_convert(threshold, "speed", u))
        ax.axvline(thr, color="r", ls=":", label=f"SS > {level} below {thr:.1f} {_LABEL[u]}")
    ax.set_xlabel(f"top-drive speed [{_LABEL[u]}]")
    ax.set_ylabel("stick-slip severity SS [-]")
    ax.set_title(title or "Stick-slip severity versus top speed")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return _save(fig, path)


def stability_map_plot(path, speeds_rpm, wobs_kn, maps: dict, vmax=None, units="si") -> plt.Figure:
    """One panel per model: SS over top speed x WOB (Figs. 3.11-3.12), shared colour scale, the
    contour SS = 0.5 in white.

    Parameters
    ----------
    path : str or Path
        PNG written.
    speeds_rpm : array_like
        Top-drive speeds of the grid [RPM].
    wobs_kn : array_like
        Weights on bit of the grid [kN].
    maps : dict
        Panel label -> SS [-], shape (len(wobs_kn), len(speeds_rpm)); one speed or one WOB gives a
        strip without the SS = 0.5 contour.
    vmax : float, optional
        Upper end of the colour scale [-] (default: the largest SS of all maps).
    units : str
        Axis units (:data:`FIGURE_UNITS`): ``si`` keeps the thesis's RPM and kN, ``field`` draws RPM and klbf.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    n = len(maps)
    vmax = vmax or max(float(np.nanmax(m)) for m in maps.values())
    wu = _unit(units, "force")
    wobs = _convert(wobs_kn, "force", wu, source="kN")
    fig, axes = plt.subplots(1, n, figsize=(4.6 * n, 4.0), squeeze=False)
    for ax, (label, m) in zip(axes[0], maps.items()):
        pc = ax.pcolormesh(speeds_rpm, wobs, m, shading="nearest", cmap="jet", vmin=0, vmax=vmax)
        if min(np.shape(m)) >= 2:  # a contour needs a 2-D grid (a map of one speed or one WOB is a strip)
            ax.contour(speeds_rpm, wobs, m, levels=[0.5], colors="w", linewidths=1.5)
        ax.set_xlabel("top-drive speed [RPM]")
        ax.set_ylabel(f"weight on bit [{_LABEL[wu.lower()]}]")
        ax.set_title(label, fontsize=10)
        fig.colorbar(pc, ax=ax, label="SS [-]")
    return _save(fig, path)


def time_series_plot(path, t, bit_speed, torque_on_bit, top_speed=None, t_window=None, title="",
                     units="si") -> plt.Figure:
    """Bit speed and torque on bit versus time (Figs. 4.6, 5.5).

    Parameters
    ----------
    path : str or Path
        PNG written.
    t : ndarray
        Time [s].
    bit_speed, top_speed : ndarray
        Bit and top-drive speed [rad/s] (``top_speed`` optional).
    torque_on_bit : ndarray
        Torque on bit [N m] (plotted in kN m above 1000 N m).
    t_window : (float, float), optional
        Time window shown [s] (default: all).
    title : str
        Figure title.
    units : str
        Axis units (:data:`FIGURE_UNITS`): ``si`` (rad/s, N m or kN m) or ``field`` (RPM, kft-lbf).

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    su, tu = _unit(units, "speed"), _unit(units, "torque")
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7.0, 5.0), sharex=True)
    sel = slice(None) if t_window is None else (t >= t_window[0]) & (t <= t_window[1])
    a1.plot(t[sel], _convert(bit_speed, "speed", su)[sel], "b", lw=0.8, label="bit")
    if top_speed is not None:
        a1.plot(t[sel], _convert(top_speed, "speed", su)[sel], "k--", lw=0.8, label="top drive")
    a1.set_ylabel(f"speed [{_LABEL[su]}]")
    a1.legend(fontsize=8, loc="upper right")
    a1.grid(alpha=0.3)
    tob = np.asarray(torque_on_bit)[sel]
    if tu == "N m":
        kilo = np.nanmax(np.abs(tob)) > 1e3 if tob.size else False
        a2.plot(t[sel], tob / 1e3 if kilo else tob, "m", lw=0.8)
        a2.set_ylabel("torque on bit [kN m]" if kilo else "torque on bit [N m]")
    else:
        a2.plot(t[sel], _convert(tob, "torque", tu), "m", lw=0.8)
        a2.set_ylabel(f"torque on bit [{_LABEL[tu]}]")
    a2.set_xlabel("time [s]")
    a2.grid(alpha=0.3)
    if title:
        a1.set_title(title)
    return _save(fig, path)



def axial_series_plot(path, axial, title="") -> plt.Figure:
    """The axial channels of an axial-torsional run (docs/axial.md) versus time: WOB [kN], the bit's
    rate of penetration [m/h] and depth of cut per revolution [mm], each beside its value at RGD's
    steady drilling (dashed); bit bounce shows as W = 0 with a negative depth of cut.

    Parameters
    ----------
    path : str or Path
        PNG written.
    axial : _core.AxialReport
        The run's axial report (``SimulationResult.axial``).
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, written to ``path`` (then closed) unless ``path`` is None.
    """
    t = np.asarray(axial.t)
    rows = (("WOB [kN]", np.asarray(axial.wob) / 1e3, axial.steady_wob / 1e3),
            ("ROP [m/h]", np.asarray(axial.rop) * 3600.0, axial.steady_rop * 3600.0),
            ("depth of cut [mm/rev]", np.asarray(axial.depth_of_cut) * 1e3, axial.steady_depth * 1e3))
    fig, axes = plt.subplots(3, 1, figsize=(7.0, 6.0), sharex=True)
    for ax, (label, y, steady) in zip(axes, rows):
        ax.plot(t, y, "b", lw=0.8)
        ax.axhline(steady, color="k", ls="--", lw=0.8, label="steady drilling")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8, loc="upper right")
    axes[-1].set_xlabel("time [s]")
    if title:
        axes[0].set_title(title)
    return _save(fig, path)
