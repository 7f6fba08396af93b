"""``drillpy control``: robust tuning of top-drive controllers under the chapter-4 uncertainty and the
drives side by side (issue 15; :mod:`drillpy.control.study`, :mod:`drillpy.reports.control`, docs/control.md)."""
from __future__ import annotations

import argparse
import sys

from drillpy.cli import add_figure_units_arg, integer, parse_grid, print_json, quantity, threads_option
from drillpy.model.config import load_config, with_overrides
from drillpy.model.configuration import Configuration


def _add_control(sub) -> argparse.ArgumentParser:
    """Register ``drillpy control``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The ``drillpy`` subparsers.

    Returns
    -------
    argparse.ArgumentParser
        The subcommand's parser.
    """
    s = sub.add_parser("control", help="robust tuning of top-drive controllers under uncertainty (docs/control.md)")
    src = s.add_mutually_exclusive_group(required=True)
    src.add_argument("--preset", help="built-in configuration (thesis-field, thesis-rig, ...)")
    src.add_argument("--config", help="JSON configuration file (e.g. a loop's model.json)")
    s.add_argument("--drive-inertia", type=float, required=True, metavar="J",
                   help="rotor and gearbox inertia of the top drive [kg m^2]")
    s.add_argument("--torque-limit", type=quantity("--torque-limit", "torque"),
                   help="motor torque limit: N m or with a unit (50kNm, 36900ft-lbf; default: none)")
    s.add_argument("--controllers", default="soft_speed,z_torque",
                   help="controllers to tune, comma-separated (soft_speed, z_torque)")
    s.add_argument("--speeds", help="top speeds of the operating window, start:stop:num or list, in rad/s or with "
                                    "a unit (60:180:6rpm; default: the configuration's speed x 0.5:1.25:6)")
    w = s.add_mutually_exclusive_group()
    w.add_argument("--wobs-kn", help="WOBs of the operating window, start:stop:num or list, in kN or with a unit "
                                     "(30:50:3klbf; default: the configuration's WOB x 0.8, 1, 1.2)")
    w.add_argument("--wob", type=quantity("--wob", "force"),
                   help="one WOB for the whole window: N or with a unit (200kN, 45klbf)")
    s.add_argument("--samples", type=integer("samples"), default=16, help="tuning samples per (speed, WOB)")
    s.add_argument("--validation-samples", type=integer("validation_samples"), default=48,
                   help="new samples of the comparison per (speed, WOB)")
    s.add_argument("--seed", type=integer("seed"), default=1,
                   help="seed of the tuning samples (the comparison uses seed + 1)")
    s.add_argument("--grid", type=integer("grid"), default=5, help="coarse grid points per gain")
    s.add_argument("--refine", type=integer("refine"), default=16, help="Nelder-Mead evaluations after the grid")
    s.add_argument("--factor-range", default="0.1,10",
                   help="LOW,HIGH: factors of the nominal tuning searched for every gain (log scale; default 0.1,10)")
    s.add_argument("--bootstrap", type=integer("bootstrap"), default=400, help="bootstrap resamples")
    s.add_argument("--warmup", type=float,
                   help="deterministic warm start of every run [s] (default 100; 0 with axial.type = rgd, whose "
                        "runs start in steady drilling)")
    s.add_argument("--duration", type=float, default=60.0, help="run with eta after the warm start [s]")
    s.add_argument("--transient", type=float, default=20.0, help="discarded before SS [s]")
    s.add_argument("--eta-std", type=float,
                   help="scale the Eq. (4.4) PSD of eta to this standard deviation (e.g. 0.0667: +-20 %% read as "
                        "+-3 sigma; docs/stochastic.md); default the thesis's PSD")
    s.add_argument("--threads", type=threads_option, default=0, help="OpenMP threads (0: default)")
    s.add_argument("--out", required=True, help="folder for control.json, report.md and the figures")
    add_figure_units_arg(s)
    s.add_argument("--no-progress", action="store_true", help="no progress lines on stderr")
    s.add_argument("--json", action="store_true", help="print control.json's summary as one JSON line")
    s.set_defaults(func=cmd_control)
    return s


def _grid(text, default, name: str, kind: str, unit: str | None = None):
    return default if text is None else parse_grid(text, name, kind, unit)


def cmd_control(a: argparse.Namespace) -> int:
    """Tune, compare and write the report (:func:`drillpy.control.study.control_study`, :func:`drillpy.reports.control.write_control`).

    Parameters
    ----------
    a : argparse.Namespace
        Arguments of ``drillpy control``.

    Returns
    -------
    int
        Exit status 0; prints one line per drive (P over the window, the 5 % speed) or, with
        ``--json``, the drives' statistics and the tuned gains.
    """
    import numpy as np

    from drillpy import validate
    from drillpy.control.tuning import Window
    from drillpy.model.threshold import format_threshold
    from drillpy.control.study import REFERENCE, control_study
    from drillpy.reports.control import write_control
    cfg = load_config(preset=a.preset) if a.preset else load_config(path=a.config)
    cfg = with_overrides(cfg)
    validate.positive("--drive-inertia", a.drive_inertia, "kg m^2")
    if a.torque_limit is not None:
        validate.positive("--torque-limit", a.torque_limit, "N m")
    controllers = [c.strip() for c in a.controllers.split(",") if c.strip()]
    if not controllers:
        raise ValueError(f"--controllers = {a.controllers!r}: name at least one of soft_speed, z_torque")
    factor_range = parse_grid(a.factor_range, "--factor-range")
    if factor_range.size != 2:
        raise ValueError(f"--factor-range = {a.factor_range!r}: give LOW,HIGH (e.g. 0.1,10)")
    validate.integer("--validation-samples", a.validation_samples, 1, 100_000)
    validate.integer("--bootstrap", a.bootstrap, 1, 100_000)
    validate.integer("--grid", a.grid, 2, 50)
    validate.integer("--refine", a.refine, 0, 10_000)
    validate.seed(a.seed, "--seed")
    if a.seed == 2**64 - 1:
        raise ValueError(f"--seed = {a.seed}: must be below 2^64 - 1 (the comparison uses seed + 1)")
    ax = Configuration.of(cfg).axial
    if ax.type == "rgd" and ax.top == "feed":
        raise ValueError("axial.top = 'feed': drillpy control's window is top speeds x WOBs, and with a constant "
                         "feed the WOB is the bit's response, not an input (use axial.top = hook_load)")
    op = Configuration.of(cfg).operation
    speeds = _grid(a.speeds, op.top_speed_rad_s * np.linspace(0.5, 1.25, 6), "--speeds", "speed")
    wobs = (np.array([a.wob]) if a.wob is not None
            else _grid(a.wobs_kn, op.wob_n * np.array([0.8, 1.0, 1.2]), "--wobs-kn", "force", "kN"))
    from drillpy.uncertainty.process import THESIS_PSD, scaled_to_std
    psd = THESIS_PSD
    if a.eta_std is not None:
        validate.positive("--eta-std", a.eta_std)
        psd = scaled_to_std(THESIS_PSD, a.eta_std)
    from drillpy.uncertainty.montecarlo import default_warmup
    warmup = default_warmup(cfg) if a.warmup is None else a.warmup
    window = Window(speeds, wobs, a.samples, a.seed, warmup=warmup, duration=a.duration, transient=a.transient,
                    psd=psd)

    def progress(text: str) -> None:
        if not a.no_progress:
            print(f"drillpy control: {text}", file=sys.stderr, flush=True)

    study = control_study(cfg, inertia=a.drive_inertia, torque_limit=a.torque_limit, window=window,
                          validation_samples=a.validation_samples, validation_seed=a.seed + 1,
                          controllers=controllers, grid=a.grid, refine_evaluations=a.refine,
                          bootstrap=a.bootstrap, factor_range=tuple(factor_range), threads=a.threads,
                          progress=progress)
    js = write_control(study, a.out, figure_units=a.figure_units)
    if a.json:
        print_json({"reference": REFERENCE, "tunings": {c: {"gains": t["gains"], "factors": t["factors"],
                                                        "at_bound": t["at_bound"]}
                                                        for c, t in js["tunings"].items()},
                    "drives": {k: {key: r[key] for key in ("p_window", "p_vs_reference", "stalled_fraction", "mean_ss",
                                                           "deterministic_threshold_rad_s",
                                                           "deterministic_threshold", "p05_speed_rad_s",
                                                           "p05_interval", "p05_precision_warning")}
                               for k, r in js["comparison"].items()},
                    "episode_speed_rad_s": js["episode_speed_rad_s"], "episodes": js["episodes"]})
        return 0
    for c, t in study.tunings.items():
        print(f"{c}: tuned " + ", ".join(f"{k} = {v:.4g} ({t.factors[k]:.3g} x nominal"
                                         + (", on the search bound)" if k in t.at_bound else ")")
                                         for k, v in t.gains.items()))
    wob_kn = float(study.validation_window.wobs[next(iter(study.comparison.values()))["nominal_row"]]) / 1e3
    for label, r in study.comparison.items():
        pw, p05 = r["p_window"], r["p05_speed_rad_s"]
        print(f"{label:18s} P(SS > 0.5 or stalled) = {pw['value']:.3f} [{pw['low']:.3f}, {pw['high']:.3f}] "
              f"(90 % Wilson, {pw['trials']} samples)  5 % speed "
              + (f"{p05:.2f} rad/s" if p05 is not None else r["p05_reading"]))
        print(f"{'':18s} deterministic at WOB {wob_kn:g} kN: {format_threshold(r['deterministic_threshold'])}")
        if p05 is not None and r["p05_precision_warning"]:
            print(f"drillpy: warning: {label}: {r['p05_precision_warning']}", file=sys.stderr)
    print(f"report.md, control.json and figures written to {a.out}")
    return 0


SUBCOMMANDS = {"control": _add_control}
