"""The outputs of ``drillpy simulate --out``: one run's series, figures and summary."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from drillpy.figures import simulation as plotting
from drillpy.jsonio import dumps
from drillpy.model.configuration import Configuration
from drillpy.model.simulation import SimulationResult
from drillpy.outputs import replacing, write_text
from drillpy.provenance import header, provenance


def write_simulation(r: SimulationResult, out_dir: str | Path, figure_units: str = "si") -> list:
    """Write a run's files in ``out_dir``; returns their names.

    ``series.csv`` (time series, SI units), ``time_series.png`` and ``summary.json`` (the summary of
    ``drill/run_summary.hpp`` with the effective configuration and the provenance); with the
    axial-torsional model (``axial.type = rgd``) also ``axial.csv`` (WOB, rate of penetration, bit
    position, depth of cut and delay, SI units) and ``axial.png`` (WOB, ROP and depth of cut versus
    time). The CSV files hold the data's precision, not the float64's: the time in fixed point to
    the recording step's resolution (:func:`time_format`), the other columns at 7 significant digits
    (``%.7g``).

    Parameters
    ----------
    r : SimulationResult
        The run (:func:`drillpy.model.simulation.simulate`).
    out_dir : str or Path
        Output folder (created if needed; existing files are replaced whole).
    figure_units : str
        Axis units of the figures (``si`` or ``field``); the files stay SI.

    Returns
    -------
    list of str
        The names of the files written, relative to ``out_dir``.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    cols = np.column_stack([r.t, r.bit_speed, r.bit_accel, r.bit_angle, r.torque_on_bit, r.top_torque, r.top_speed])
    prov = provenance(start=Configuration.of(r.config).simulation.start or "rest")  # the start used
    with replacing(out / "series.csv") as tmp:
        np.savetxt(tmp, cols, delimiter=",", comments="", fmt=[time_format(r.t)] + ["%.7g"] * 6,
                   header=header(prov) + "\ntime_s,bit_speed_rad_s,bit_accel_rad_s2,bit_angle_rad,torque_on_bit_Nm,"
                          "top_torque_Nm,top_speed_rad_s")
    plotting.time_series_plot(out / "time_series.png", r.t, r.bit_speed, r.torque_on_bit, r.top_speed,
                              units=figure_units)
    files = ["series.csv", "time_series.png"]
    ax = r.axial
    if ax is not None:  # the axial-torsional model's channels (docs/axial.md), same sampling
        acols = np.column_stack([ax.t, ax.wob, ax.rop, ax.position, ax.depth_of_cut, ax.delay])
        with replacing(out / "axial.csv") as tmp:
            np.savetxt(tmp, acols, delimiter=",", comments="", fmt=[time_format(ax.t)] + ["%.7g"] * 5,
                       header=header(prov) + "\ntime_s,wob_N,rop_m_s,bit_position_m,depth_of_cut_m,delay_s")
        plotting.axial_series_plot(out / "axial.png", ax)
        files += ["axial.csv", "axial.png"]
    write_text(out / "summary.json", dumps({**r.summary(), "config": r.config, "provenance": prov}, indent=2))
    return files + ["summary.json"]


def time_format(t) -> str:
    """The ``printf`` format writing times ``t`` [s] to their step's resolution: fixed point with
    the fewest decimals (at most 9) that hold the step, e.g. ``"%.3f"`` for a 1 ms step.

    Parameters
    ----------
    t : array_like
        Recorded times [s], evenly spaced (the median step is used).

    Returns
    -------
    str
        A format such as ``"%.4f"``; ``"%.9f"`` for fewer than two times or a step finer than 1 ns.
    """
    t = np.asarray(t, float)
    if t.size < 2:
        return "%.9f"
    step = float(np.median(np.diff(t)))
    for d in range(10):
        if step > 0 and abs(round(step, d) - step) <= 1e-6 * step:
            return f"%.{d}f"
    return "%.9f"
