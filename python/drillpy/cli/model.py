"""``drillpy`` commands on the deterministic model: report, modes, simulate, sweep, map, convergence.

Each ``_add_*`` function registers one subcommand's arguments; the ``cmd_*`` handler below it turns
them into one library call and prints the result (text, or one JSON line with ``--json``).
"""
from __future__ import annotations

import argparse
import math

import numpy as np

from drillpy.cli import (add_figure_units_arg, add_model_args, add_study_args, add_wob_arg, model_config, parse_grid, print_json, quantity,
                         renamed, study_severity)
from drillpy.jsonio import jsonable
from drillpy.model.config import with_overrides
from drillpy.model.configuration import Configuration


def _add_report(sub) -> argparse.ArgumentParser:
    """Register ``drillpy report`` on the subparsers ``sub``; returns its parser."""
    s = sub.add_parser("report", help="main job: deterministic analysis with figures")
    add_model_args(s)
    s.add_argument("--out", default="results", help="output folder")
    add_figure_units_arg(s)
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_report)
    return s


def cmd_report(a: argparse.Namespace) -> int:
    """Run the main job (:func:`drillpy.reports.preset.field_report`) into ``--out``.

    Parameters
    ----------
    a : argparse.Namespace
        Arguments of ``drillpy report``.

    Returns
    -------
    int
        Exit status 0; prints the summary (without its configuration) as JSON or as text.
    """
    from drillpy.reports.preset import field_report, print_field_summary
    s = field_report(model_config(a), a.out, progress=not a.no_progress, threads=a.threads,
                     figure_units=a.figure_units)
    if a.json:
        print_json({k: v for k, v in s.items() if k != "config"})
    else:
        print_field_summary(s)
        print(f"figures and summary.json written to {a.out}")
    return 0


def _add_modes(sub) -> argparse.ArgumentParser:
    """Register ``drillpy modes`` on the subparsers ``sub``; returns its parser."""
    s = sub.add_parser("modes", help="natural frequencies (Eq. 2.7)")
    add_model_args(s)
    s.add_argument("-n", type=int, default=5, help="number of frequencies")
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_modes)
    return s


def cmd_modes(a: argparse.Namespace) -> int:
    """Print the first ``-n`` natural frequencies [Hz] (Eq. 2.7).

    Parameters
    ----------
    a : argparse.Namespace
        Arguments of ``drillpy modes``.

    Returns
    -------
    int
        Exit status 0; prints ``{"frequencies_hz": [...]}`` or one line per mode.
    """
    from drillpy import validate
    from drillpy.model.simulation import natural_frequencies
    cfg = model_config(a)
    validate.integer("-n", a.n, 1, sum(s.elements for s in Configuration.of(cfg).string.sections))  # the free DOFs
    f = natural_frequencies(cfg, a.n)
    if a.json:
        print_json({"frequencies_hz": [float(x) for x in f]})
    else:
        for k, x in enumerate(f, 1):
            print(f"mode {k}: {x:.4f} Hz")
    return 0


def _add_simulate(sub) -> argparse.ArgumentParser:
    """Register ``drillpy simulate`` on the subparsers ``sub``; returns its parser."""
    s = sub.add_parser("simulate", help="one run: time series and stick-slip metrics")
    add_model_args(s)
    s.add_argument("--top-speed", type=quantity("--top-speed", "speed"),
                   help="top-drive speed: rad/s or with a unit (120rpm)")
    add_wob_arg(s)
    s.add_argument("--wob-kn", action=renamed("--wob", "a WOB with its unit, e.g. --wob 200kN"), help=argparse.SUPPRESS)
    s.add_argument("--out", help="folder for series.csv, summary.json and a figure")
    add_figure_units_arg(s)
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_simulate)
    return s


def cmd_simulate(a: argparse.Namespace) -> int:
    """Run one simulation at ``--top-speed`` and ``--wob`` (SI or with a unit); print its stick-slip metrics.

    With ``--out`` the run's files are written by :func:`drillpy.reports.simulation.write_simulation`
    (``series.csv``, ``time_series.png``, ``summary.json``; ``axial.csv`` and ``axial.png`` for the
    axial-torsional model).

    Parameters
    ----------
    a : argparse.Namespace
        Arguments of ``drillpy simulate``.

    Returns
    -------
    int
        Exit status 0; prints the summary as JSON or SS, stick fraction and periodic cycles as text.
    """
    from drillpy.jsonio import dumps
    from drillpy.model.simulation import simulate
    # the effective configuration (overrides, operating point and start) is the one saved
    r = simulate(with_overrides(model_config(a), top_speed=a.top_speed))
    if a.out:
        from drillpy.reports.simulation import write_simulation
        write_simulation(r, a.out, a.figure_units)
    text = (f"SS = {r.severity:.3f}, stick fraction = {r.stick_fraction:.3f}, "
            f"periodic over {r.period_cycles} cycle(s)")
    ax = r.axial  # the axial-torsional model (axial.type = rgd): WOB, ROP and bit bounce beside SS
    if ax is not None:
        # kN for a field string's WOB, N for a rig's (below 10 kN: a swing of tens of N would print as 0.0 kN)
        k, unit = (1e3, "kN") if abs(ax.steady_wob) >= 1e4 else (1.0, "N")
        text += (f"\nWOB = {ax.mean_wob / k:.1f} +- {ax.wob_std / k:.1f} {unit} (steady {ax.steady_wob / k:.1f} {unit}), "
                 f"ROP = {ax.mean_rop * 3600:.2f} +- {ax.rop_std * 3600:.2f} m/h (steady {ax.steady_rop * 3600:.2f} m/h), "
                 f"bit bounce fraction = {ax.bounce_fraction:.3f}, MSE = {ax.mse / 1e6:.1f} MPa "
                 f"(steady {ax.steady_mse / 1e6:.1f} MPa)")
        if not math.isfinite(ax.steady_speed):  # a motor that cannot carry steady drilling
            text += "\nno steady drilling under the top drive: it stalls (the run starts from the command's steady drilling)"
        elif ax.steady_speed != r.config["operation"]["top_speed_rad_s"]:  # a drooping drive
            text += f"\nsteady drilling under the top drive at {ax.steady_speed:.3f} rad/s"
    print(dumps(r.summary(), indent=None) if a.json else text)
    return 0


def _add_sweep(sub) -> argparse.ArgumentParser:
    """Register ``drillpy sweep`` on the subparsers ``sub``; returns its parser."""
    s = sub.add_parser("sweep", help="SS versus top speed (Fig. 4.8)")
    add_model_args(s)
    s.add_argument("--speeds", default="6:27:22",
                   help="top speeds, start:stop:num or list, in rad/s or with a unit (50:160:23rpm)")
    add_wob_arg(s)
    s.add_argument("--out", help="folder for the figure, sweep.json and study.zarr")
    add_figure_units_arg(s)
    add_study_args(s)
    s.add_argument("--refine", type=float, metavar="TOL", default=0.02,
                   help="half-width of the threshold's bisection bracket [rad/s] (default 0.02)")
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_sweep)
    return s


def cmd_sweep(a: argparse.Namespace) -> int:
    """SS versus top speed [rad/s], the threshold below which SS > 0.5 by bisection
    (:func:`drillpy.model.threshold.stick_slip_threshold`, ``--refine`` its precision) and every other
    crossing of SS through 0.5 with its direction (``crossings``: ``"falling"``, stick-slip
    below the speed; ``"rising"``, stick-slip above it).

    Parameters
    ----------
    a : argparse.Namespace
        Arguments of ``drillpy sweep``.

    Returns
    -------
    int
        Exit status 0; prints the sweep as JSON or one line per speed and the threshold; with
        ``--out`` :func:`drillpy.reports.preset.write_sweep` writes the figure and ``sweep.json``.
    """
    from drillpy.model.simulation import severity_crossings, sweep_severity
    from drillpy.model.threshold import format_threshold, stick_slip_threshold
    from drillpy.reports.preset import write_sweep
    cfg = model_config(a)
    speeds = parse_grid(a.speeds, "--speeds", "speed")
    from drillpy.study import Study
    ss = study_severity(lambda: Study("sweep", cfg, tuple(speeds.tolist()), options={"start": a.start}), a,
                        lambda: sweep_severity(cfg, speeds, progress=not a.no_progress, threads=a.threads,
                                               start=a.start))
    thr = stick_slip_threshold(cfg, speeds, ss, tol=a.refine, threads=a.threads, start=a.start)
    crossings = severity_crossings(speeds, ss)
    res = {"top_speeds_rad_s": speeds.tolist(), "severity": ss.tolist(), **thr, "crossings": crossings}
    if a.out:
        write_sweep(a.out, speeds, ss, thr["threshold_rad_s"], jsonable(res), cfg, start=a.start,
                    figure_units=a.figure_units)  # NaN as null
    if a.json:
        print_json(res)
    else:
        for s, v in zip(speeds, ss):
            print(f"{s:8.3f} rad/s  SS = {v:.3f}")
        print(format_threshold(thr))
        # the last falling crossing is the threshold, answered by the bisection: not printed twice
        falling = [i for i, c in enumerate(crossings) if c["direction"] == "falling"]
        others = [c for i, c in enumerate(crossings) if thr["threshold_rad_s"] is None or i != falling[-1]]
        for c in others:
            print(f"SS crosses 0.5 {c['direction']} at {c['speed_rad_s']:.2f} rad/s: stick-slip "
                  f"{'below' if c['direction'] == 'falling' else 'above'} it (linear interpolation on the grid)")
        if not crossings:
            print("SS does not cross 0.5 in range (SS", "> 0.5" if ss.min() > 0.5 else "<= 0.5", "throughout)")
    return 0


def _add_map(sub) -> argparse.ArgumentParser:
    """Register ``drillpy map`` on the subparsers ``sub``; returns its parser."""
    s = sub.add_parser("map", help="stability map over top speed x WOB (Figs. 3.11-3.12)")
    add_model_args(s)
    s.add_argument("--speeds-rpm", default="50:160:23",
                   help="top speeds, start:stop:num or list, in RPM or with a unit (5:17:13rad/s)")
    s.add_argument("--wobs-kn", default="22:267:12",
                   help="weights on bit, start:stop:num or list, in kN or with a unit (5:60:12klbf)")
    s.add_argument("--out", help="folder for the figure, map.json and study.zarr")
    add_figure_units_arg(s)
    add_study_args(s)
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_map)
    return s


def cmd_map(a: argparse.Namespace) -> int:
    """SS over top speed [RPM] x weight on bit [kN] (Figs. 3.11-3.12).

    Parameters
    ----------
    a : argparse.Namespace
        Arguments of ``drillpy map``.

    Returns
    -------
    int
        Exit status 0; prints the map as JSON or its stable fraction (SS < 0.5); with ``--out``
        :func:`drillpy.reports.preset.write_map` writes the figure and ``map.json``.
    """
    from drillpy.model.simulation import stability_map
    from drillpy.reports.preset import write_map
    cfg = model_config(a)
    sp = parse_grid(a.speeds_rpm, "--speeds-rpm", "speed", "rpm", to="rpm")  # the map's axes: RPM and kN
    w = parse_grid(a.wobs_kn, "--wobs-kn", "force", "kN", to="kN")
    from drillpy.study import Study
    speeds, wobs = sp * np.pi / 30.0, w * 1e3
    m = study_severity(lambda: Study("map", cfg, tuple(speeds.tolist()), wobs=tuple(wobs.tolist()),
                                     options={"start": a.start}), a, lambda: stability_map(cfg, speeds, wobs, progress=not a.no_progress, threads=a.threads,
                                                start=a.start))
    res = {"top_speeds_rpm": sp.tolist(), "wobs_kn": w.tolist(), "severity": m.tolist()}
    if a.out:
        write_map(a.out, sp, w, m, jsonable(res), cfg, start=a.start, figure_units=a.figure_units)  # NaN written as null
    if a.json:
        print_json(res)
    else:
        print(f"stable fraction (SS < 0.5): {np.mean(m < 0.5):.3f}")
    return 0


def _add_convergence(sub) -> argparse.ArgumentParser:
    """Register ``drillpy convergence`` on the subparsers ``sub``; returns its parser."""
    s = sub.add_parser("convergence", help="FE and time-step convergence studies (docs/numerics.md)")
    add_model_args(s)
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_convergence)
    return s


def cmd_convergence(a: argparse.Namespace) -> int:
    """FE (frequencies) and time-step (bit speed [rad/s]) convergence orders (docs/numerics.md).

    Parameters
    ----------
    a : argparse.Namespace
        Arguments of ``drillpy convergence``.

    Returns
    -------
    int
        Exit status 0; prints :func:`drillpy.model.convergence.convergence_report` as JSON or tables.
    """
    from drillpy.model.convergence import convergence_report
    for opt, value in (("--dt", a.dt), ("--scheme", a.scheme)):
        if value is not None:  # the study sets both itself: a silently ignored option misleads
            raise ValueError(f"{opt} = {value}: convergence runs its own ladder of time steps with both schemes")
    r = convergence_report(model_config(a))
    if a.json:
        print_json(r)
        return 0
    sp = r["space"]
    print("FE frequencies vs exact (max relative error over the first 5):")
    for n, e in zip(sp["elements"], sp["max_rel_error"]):
        print(f"  {n:5d} elements  {e:.3e}")
    print("  observed orders:", ", ".join(f"{o:.2f}" for o in sp["orders"]))
    for key, title in (("time_slip", "slip regime"), ("time_stick_slip", "stick-slip regime")):
        t = r[key]
        print(f"time integration, {title} ({t['top_speed_rad_s']} rad/s, {t['duration_s']} s; "
              f"max |bit speed error| vs BDF2 at dt = {t['reference_dt_s']:.2e} s):")
        print("  dt [s]      modified_euler   bdf2")
        for i, dt in enumerate(t["dt_s"]):
            print(f"  {dt:.2e}   {t['modified_euler']['max_error_rad_s'][i]:.3e}        "
                  f"{t['bdf2']['max_error_rad_s'][i]:.3e}")
        print("  orders: modified_euler", ", ".join(f"{o:.2f}" for o in t["modified_euler"]["orders"]),
              "| bdf2", ", ".join(f"{o:.2f}" for o in t["bdf2"]["orders"]))
    return 0


#: subcommand -> function registering it (``drillpy.cli.build_parser`` orders them)
SUBCOMMANDS = {"report": _add_report, "modes": _add_modes, "simulate": _add_simulate, "sweep": _add_sweep,
               "map": _add_map, "convergence": _add_convergence}
