"""``drillpy`` commands on measured records: analyze, predict, loop.

Each ``_add_*`` function registers one subcommand's arguments; the ``cmd_*`` handler below it turns
them into one library call (which writes the output folder) and prints the result.
"""
from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

from drillpy.text import number_text as _n
from drillpy import validate
from drillpy.cli import add_figure_units_arg, integer, print_json, threads_option
from drillpy.cli import removed_on_failure as _removed_on_failure


def _add_analyze(sub) -> argparse.ArgumentParser:
    """Register ``drillpy analyze`` on the subparsers ``sub``; returns its parser."""
    s = sub.add_parser("analyze", help="measured record(s) (.mat or .csv): one record: cleaning, cycles, "
                                       "identification, rig simulation (report.md + figures + summary.json); two or "
                                       "more: statistics across samples, thesis section 5.3 (samples.md, "
                                       "samples.json, fig5_4_boxplot.png)")
    s.add_argument("record", nargs="+",
                   help="rig MATLAB file or drillpy CSV (see README: CSV format), a folder of them, or FILE@T0:T1 "
                        "(the window T0 <= t < T1 [s] of a file as one sample)")
    s.add_argument("--out", required=True, help="output folder")
    add_figure_units_arg(s)
    s.add_argument("--t0", type=float, help="start of the analysed window [s] (every record)")
    s.add_argument("--t1", type=float, help="end of the analysed window [s] (every record)")
    s.add_argument("--cycle-at", type=float, help="time [s] inside the cycle shown in cycle.png (one record)")
    s.add_argument("--folds", type=int, help="cross-validation folds over cycles (0: none; default 5 for one record, "
                                             "0 across samples)")
    s.add_argument("--psd-fmax", type=float, default=10.0, help="upper end of the PSD-model fit band [Hz] (one record)")
    s.add_argument("--no-sim", action="store_true", help="skip the rig simulations (one record)")
    s.add_argument("--calibrate", metavar="T0:T1", help="fit and calibrate on this part [s] only and predict the rest "
                                                        "of the record (one record)")
    s.add_argument("--rig-fix", metavar="NAME=VALUE", action="append", default=[],
                   help="hold a parameter of the rig modelled whole at VALUE instead of calibrating it (repeatable; "
                        "names: drillpy.records.rigsim.RIG_PARAMETERS, e.g. static_torque_factor=1.09; NAME=free "
                        "calibrates a parameter held by default: static_torque_factor)")
    s.add_argument("--law-platform", type=float, metavar="ZETA",
                   help="identify the laws with the bit speed and the WOB brought through the torque-on-bit platform "
                        "(20 Hz, damping ratio ZETA) the measured torque went through (one record; default: as measured)")
    s.add_argument("--channel-timing", default="auto", metavar="none|auto|LEAD,LAG",
                   help="read the records the rig model's short-horizon E scores with the channels at the bit "
                        "encoder's time: auto (the default: the skew that balances the bit's equation on the "
                        "calibration part, where the record identifies one), none (as recorded) or the top encoder's "
                        "lead and the torque's lag in s, e.g. 0.04,0.03; model.json keeps it for drillpy predict")
    s.add_argument("--horizon-weight", type=float, default=1.0, metavar="W",
                   help="weight of the calibration part's short-horizon error E (0.25 s horizons restarted from the "
                        "measured state) beside the long-run metrics' mismatch in the rig calibration (default 1; "
                        "0: the long-run metrics alone)")
    s.add_argument("--horizon-channels", default="loop", choices=("loop", "all"),
                   help="the channels of that short-horizon error in the rig calibration: loop (the default: bit "
                        "speed, torque and top speed, the loop's E) or all (the WOB, the jack's state, beside them)")
    s.add_argument("--rig-metric", action="append", default=[], metavar="NAME",
                   choices=("cycle_frequency_hz", "top_in_phase", "block_stick_min", "stall_fraction"),
                   help="a metric the rig calibration matches beside its defaults (repeatable): cycle_frequency_hz, "
                        "top_in_phase (the top speed's part in phase with the bit speed) or block_stick_min (the "
                        "smallest stick fraction of the part's 5 s blocks: the cycle kept where the WOB trend dips) or stall_fraction "
                        "(the share of the time in stalls)")
    s.add_argument("--rig-search", default="4,200", metavar="STARTS,EVALUATIONS",
                   help="the rig calibration's search: Nelder-Mead starts and simulations per start (default 4,200; "
                        "8,400 searches longer, about 4 x the time)")
    g = s.add_argument_group("acceptance criterion across samples (thesis section 5.3.3)")
    g.add_argument("--max-var-mse-regularized", type=float, default=47.93,
                   help="largest acceptable Var[MSE] (Eq. 5.2) of the regularized law Eq. (3.1)")
    g.add_argument("--max-var-mse-non-regularized", type=float, default=0.26,
                   help="largest acceptable Var[MSE] of the non-regularized law Eq. (5.1)")
    g.add_argument("--cv-reference", type=float, default=0.329,
                   help="CV average the variation limit starts from (thesis Table 5.2: 0.329)")
    g.add_argument("--concrete-variation", type=float, default=0.10,
                   help="variation of the concrete resistance added to it (thesis: 0.10)")
    g.add_argument("--require-cv", action="store_true",
                   help="also reject samples whose CV exceeds the variation limit (the thesis does not)")
    s.add_argument("--json", action="store_true",
                   help="print the main numbers and the identification results (one record) or the tables across "
                        "samples as JSON")
    s.add_argument("--no-progress", action="store_true", help="no progress bar")
    s.set_defaults(func=cmd_analyze)
    return s


def cmd_analyze(a: argparse.Namespace) -> int:
    """Analyse one record (:func:`drillpy.reports.analysis.analyze_record`) or several samples
    (:func:`drillpy.reports.samples.analyze_samples`, thesis section 5.3) into ``--out``.

    Parameters
    ----------
    a : argparse.Namespace
        Arguments of ``drillpy analyze``; ``--t0``/``--t1``/``--calibrate`` in s, ``--psd-fmax`` in Hz.

    Returns
    -------
    int
        Exit status 0; the library logs its progress (text) or the main results are printed as JSON.
        A progress bar over the stages (:data:`ANALYZE_STAGES`; one step per sample across
        samples) shows on stderr when it is a terminal, unless ``--no-progress``. When the command
        fails, the output folder is removed if this run created it (a folder that existed before
        is left as it is).
    """
    from drillpy.progress import log_progress
    from drillpy.records.samples import find_records
    items = find_records(a.record)
    one = len(items) == 1
    with _removed_on_failure(a.out), log_progress(
            ANALYZE_STAGES if one else ((r"\S.*: torque mean", "samples"),), "analyze",
            total=len(ANALYZE_STAGES) if one else len(items), enabled=not a.no_progress,
            echo=None if a.json else print, count=not one) as log:
        return _analyze(a, items, log)


#: ``drillpy analyze`` (one record): (start of the log line that ends a stage, the stage that follows)
ANALYZE_STAGES = (("record:", "cycles"), ("cycles:", "eta and PSD"), ("eta_exp:", "law fits"),
                  ("identification", "rig simulations"), ("rig: calibrated model", "figures"),
                  ("report.md", "done"))


def _analyze(a: argparse.Namespace, items: list, log) -> int:
    """The body of :func:`cmd_analyze` for the records ``items`` (:func:`drillpy.records.samples.find_records`).

    Parameters
    ----------
    a : argparse.Namespace
        Arguments of ``drillpy analyze``.
    items : list
        The records found.
    log : callable
        Called with each progress line.

    Returns
    -------
    int
        Exit status 0.
    """
    from drillpy.records.samples import Acceptance, SampleOptions, parse_window
    from drillpy.reports.samples import analyze_samples
    _check_analyze_options(a)
    if len(items) == 1:  # one record (or one window of it): the single-record analysis
        from drillpy.jsonio import jsonable
        from drillpy.records.analysis import AnalysisOptions
        from drillpy.reports.analysis import analyze_record
        t0, t1 = items[0][2] or (a.t0, a.t1)
        cal = None if a.calibrate is None else parse_window(a.calibrate, "--calibrate")
        opt = AnalysisOptions(t0=t0, t1=t1, cycle_at_s=a.cycle_at, folds=5 if a.folds is None else a.folds,
                              psd_fmax_hz=a.psd_fmax, simulate=not a.no_sim, calibrate=cal,
                              rig_fixed=_rig_fixed(a.rig_fix), law_platform_damping=a.law_platform,
                              channel_timing=_channel_timing(a.channel_timing), horizon_weight=a.horizon_weight,
                              horizon_channels=a.horizon_channels, rig_search=_rig_search(a.rig_search),
                              rig_metrics=tuple(a.rig_metric))
        s = analyze_record(items[0][1], a.out, opt, log=log, figure_units=a.figure_units)
        if a.json:
            keys = ("warnings", "cleaning", "cycles", "severity", "torque_statistics", "psd", "identification", "rig")
            print(json.dumps(jsonable({k: s[k] for k in keys if k in s}), default=str, allow_nan=False))
        return 0
    # two or more samples (files, a folder, FILE@T0:T1 windows): section 5.3 across samples
    acc = Acceptance(max_var_mse={"tucker_wang": a.max_var_mse_regularized,
                                  "polynomial": a.max_var_mse_non_regularized},
                     cv_reference=a.cv_reference, concrete_variation=a.concrete_variation,
                     require_cv=a.require_cv)
    opt = SampleOptions(t0=a.t0, t1=a.t1, folds=0 if a.folds is None else a.folds, acceptance=acc)
    s = analyze_samples([p if w is None else f"{p}@{w[0]!r}:{w[1]!r}" for _, p, w in items], a.out, opt, log=log)
    if a.json:
        from drillpy.jsonio import jsonable
        print(json.dumps(jsonable({k: s[k] for k in ("n_samples", "laws", "table_5_2", "across_samples",
                                                      "acceptance", "parameters")}), allow_nan=False))
    return 0


def _check_analyze_options(a: argparse.Namespace) -> None:
    """Refuse a bad number among the options of ``drillpy analyze`` before any work, naming it."""
    for name in ("t0", "t1", "cycle_at"):
        if getattr(a, name) is not None:
            validate.number("--" + name.replace("_", "-"), getattr(a, name), unit="s")
    if a.folds is not None:
        validate.integer("--folds", a.folds, 0)
    validate.positive("--psd-fmax", a.psd_fmax, "Hz")
    if a.law_platform is not None:
        validate.positive("--law-platform", a.law_platform)
    _rig_search(a.rig_search)
    ct = _channel_timing(a.channel_timing)
    if isinstance(ct, tuple):
        from drillpy.records.bit_balance import MAX_SHIFT_S, timing_of
        try:
            timing_of({"top_lead_s": ct[0], "torque_lag_s": ct[1]})
        except ValueError:
            raise ValueError(f"--channel-timing = {a.channel_timing!r}: the top lead and the torque lag must be "
                             f"finite shifts within +-{MAX_SHIFT_S:g} s") from None
    for name in ("max_var_mse_regularized", "max_var_mse_non_regularized", "cv_reference", "concrete_variation",
                 "horizon_weight"):
        validate.non_negative("--" + name.replace("_", "-"), getattr(a, name))


def _add_predict(sub) -> argparse.ArgumentParser:
    """Register ``drillpy predict`` on the subparsers ``sub``; returns its parser."""
    s = sub.add_parser("predict", help="apply a calibrated rig model (model.json of analyze) to a record, no refitting")
    s.add_argument("model", help="model.json written by drillpy analyze, or posterior.json of drillpy calibrate "
                                 "(then: posterior predictive 90 %% intervals of the long-run statistics)")
    s.add_argument("record", help="rig MATLAB file or drillpy CSV")
    s.add_argument("--out", help="folder for summary.json and overlay.png")
    add_figure_units_arg(s)
    s.add_argument("--t0", type=float, help="start of the predicted window [s]")
    s.add_argument("--t1", type=float, help="end of the predicted window [s]")
    s.add_argument("--horizon", type=float, default=0.25, help="short-horizon length [s] (docs/loop.md)")
    s.add_argument("--threads", type=threads_option, default=0, help="OpenMP threads (0: default)")
    s.add_argument("--draws", type=int, default=100, help="posterior draws simulated (posterior.json), or realizations of "
                                                          "a rig model's torque fluctuation, Eq. (4.1) (model.json)")
    s.add_argument("--seed", type=int, default=0, help="seed of the posterior draws or of the realizations")
    _add_scheduler_args(s, " (posterior.json only)")
    s.add_argument("--json", action="store_true", help="print the short-horizon error and the long-run metrics")
    s.set_defaults(func=cmd_predict)
    return s


def _add_scheduler_args(s: argparse.ArgumentParser, note: str) -> None:
    """Add ``--scheduler`` and ``--chunk`` (:mod:`drillpy.calibration.sampler`) to ``s``; ``note`` ends the help."""
    s.add_argument("--scheduler", default="local",
                   help="where the rig simulations run: local (--threads threads here, default), local:N (a Dask "
                        "LocalCluster of N workers) or tcp://HOST:PORT (a running Dask scheduler); the same numbers "
                        "on any" + note)
    s.add_argument("--chunk", type=integer("chunk"),
                   help="simulations per Dask task (default: each batch in 4 tasks per worker)")


def _is_posterior(path: str) -> bool:
    """Whether ``path`` is a ``posterior.json`` of ``drillpy calibrate`` (its ``format``)."""
    try:
        return json.loads(Path(path).read_text(encoding="utf-8")).get("format") == "drillpy.posterior"
    except (OSError, ValueError, AttributeError):
        return False


def cmd_predict(a: argparse.Namespace) -> int:
    """Apply a calibrated rig model to a record without refitting (:mod:`drillpy.loop.prediction`, :mod:`drillpy.reports.prediction`).

    Parameters
    ----------
    a : argparse.Namespace
        Arguments of ``drillpy predict``; ``--t0``/``--t1``/``--horizon`` in s.

    Returns
    -------
    int
        Exit status 0; prints the short-horizon error E [-] and the long-run metrics measured versus
        predicted (SS, stick fraction, cycle frequency [Hz], torque p5-p95 [N m]) as JSON or text.
    """
    from drillpy.loop.prediction import describe, load_model, predict_record
    from drillpy.reports.prediction import write_prediction
    from drillpy.records.rigsim import STALL_MIN_S
    for name in ("t0", "t1"):
        if getattr(a, name) is not None:
            validate.number("--" + name, getattr(a, name), unit="s")
    validate.positive("--horizon", a.horizon, "s")
    if _is_posterior(a.model):
        from drillpy.calibration.posterior import predict_posterior
        r = predict_posterior(a.model, a.record, t0=a.t0, t1=a.t1, draws=a.draws, seed=a.seed, threads=a.threads,
                              scheduler=a.scheduler, chunk=a.chunk, log=None if a.json else print)
        if a.json:
            print_json(r)
            return 0
        st = r["statistics"]
        print(f"posterior predictive 90 % intervals on {r['window_s'][0]:g}-{r['window_s'][1]:g} s ({r['draws']} "
              f"draws): {sum(bool(v['contained']) for v in st.values())} of {len(st)} contain the measured value")
        for name, v in st.items():
            print(f"  {name}: [{v['interval90'][0]:.4g}, {v['interval90'][1]:.4g}] {v['unit']}, measured "
                  f"{v['measured']:.4g}{'' if v['contained'] else '  (outside)'}")
        return 0
    if a.scheduler != "local" or a.chunk is not None:
        opt = "--scheduler" if a.scheduler != "local" else "--chunk"
        raise ValueError(f"{opt} = {a.scheduler if opt == '--scheduler' else a.chunk!r}: only with a posterior.json of "
                         "drillpy calibrate (a model.json is one run, on --threads)")
    model = load_model(a.model)
    pred = predict_record(model, a.record, t0=a.t0, t1=a.t1, horizon_s=a.horizon, threads=a.threads,
                          realizations=a.draws, seed=a.seed)
    if a.out:
        write_prediction(pred, a.out, a.figure_units)
    s = pred.summary()
    if a.json:
        print_json({k: s[k] for k in ("short_horizon_error", "wob_horizon_error", "long_run", "predictive_intervals",
                                      "record") if s[k] is not None})  # the intervals: a rig model with Eq. (4.1)'s fluctuation
    else:
        lr = s["long_run"]
        print(f"{describe(model)} at the record's operating point; short-horizon error E = {s['short_horizon_error']:.3f}"
              + ("" if s["wob_horizon_error"] is None else f", the WOB's {s['wob_horizon_error']:.3f}"))
        art = s["record"]["artifacts"]
        print("  record's artifacts: " + ("none flagged" if not art else "; ".join(
            f"{ch} {a['excluded_samples']} sample(s) excluded, {a['repaired_samples']} repaired"
            + (f" ({', '.join(f'{k} x{n}' for k, n in a['kinds'].items())})" if a["kinds"] else "")
            for ch, a in art.items())))
        for k in ("ss", "stick_fraction", "cycle_frequency_hz"):  # n/a: no cycle to measure it on
            rel = lr[k]["relative_error"]
            print(f"  {k}: measured {_n(lr[k]['measured'], '.3f')}, predicted {_n(lr[k]['predicted'], '.3f')} "
                  f"({_n(None if rel is None else 100 * rel, '+.1f')} %)")
        tq = lr["torque_p05_p95_nm"]
        print(f"  torque p5-p95 [N m]: measured {_n(tq['measured'][0], '.2f')}-{_n(tq['measured'][1], '.2f')}, predicted "
              f"{_n(tq['predicted'][0], '.2f')}-{_n(tq['predicted'][1], '.2f')}")
        for k, unit in (("top_speed_std_rad_s", "rad/s"), ("wob_std_n", "N")):
            rel = lr[k]["relative_error"]
            print(f"  {k}: measured {_n(lr[k]['measured'], '.3g')}, predicted {_n(lr[k]['predicted'], '.3g')} "
                  f"({_n(None if rel is None else 100 * rel, '+.1f')} %)" if lr[k]["measured"] is not None
                  else f"  {k}: no data")
        ph = lr["top_in_phase"]
        if ph["measured"] is not None and ph["predicted"] is not None:
            print(f"  top speed's part in phase with the bit speed in the cycle: measured {ph['measured']:.2f}, "
                  f"predicted {ph['predicted']:.2f}")
        st = lr["stalls"]
        print(f"  stalls (stick phases of at least {STALL_MIN_S:g} s, left out of the metrics above): measured "
              + ", ".join([str(st["measured"]["count"])] + [f"{d:.2f} s" for d in st["measured"]["durations_s"]])
              + "; predicted " + ", ".join([str(st["predicted"]["count"])]
                                           + [f"{d:.2f} s" for d in st["predicted"]["durations_s"]]))
        for note in s["notes"]:
            print(f"  note: {note}")
        iv = s["predictive_intervals"]
        if iv:
            print(f"  with the torque fluctuation of Eq. (4.1), {iv['realizations']} realizations: {iv['inside']} of "
                  f"{iv['of']} measured metrics inside their {100 * iv['level']:.0f} % predictive intervals")
            for k, v in iv["metrics"].items():
                print(f"    {k}: [{_n(v['interval'][0], '.4g')}, {_n(v['interval'][1], '.4g')}], measured "
                      f"{_n(v['measured'], '.4g')}"
                      + ("" if v["inside"] else "  (outside)"))
    return 0


def _add_loop(sub) -> argparse.ArgumentParser:
    """Register ``drillpy loop`` on the subparsers ``sub``; returns its parser."""
    s = sub.add_parser("loop", help="measured record versus a declared model: residuals, the missing effects the "
                                    "evidence supports, the corrected model, errors before and after")
    s.add_argument("record", help="rig MATLAB file or drillpy CSV (see README: CSV format)")
    src = s.add_mutually_exclusive_group(required=True)
    src.add_argument("--preset", help="declared model: a built-in configuration (e.g. thesis-rig)")
    src.add_argument("--config", help="declared model: a JSON configuration file")
    s.add_argument("--out", required=True, help="output folder (loop.json, predictions.csv, report.md, figures)")
    add_figure_units_arg(s)
    s.add_argument("--horizon", type=float, default=0.25, help="prediction horizon between restarts [s]")
    s.add_argument("--calibration-fraction", type=float, default=0.5,
                   help="fraction of the record (from its start) used to calibrate; the rest validates")
    s.add_argument("--rate", type=float, default=1000.0, help="analysis sampling rate, at most [Hz]")
    s.add_argument("--min-gain", type=float, default=0.05, help="minimum relative validation improvement")
    s.add_argument("--alpha", type=float, default=0.05, help="family-wise level of the test per round")
    s.add_argument("--min-delta-bic", type=float, default=6.0, help="minimum BIC improvement (calibration part)")
    s.add_argument("--max-steps", type=int, default=6, help="at most this many effects are added")
    s.add_argument("--effects", help="comma-separated candidate effects (default: the whole catalogue)")
    s.add_argument("--dt", type=float, help="engine time step of the predictions [s] (default: the step rule, "
                                            "--step-tolerance, from the model's)")
    s.add_argument("--step-tolerance", type=float, default=0.0035,
                   help="without --dt, predict at the coarsest step (at least twice the model's) whose horizon "
                        "predictions differ from the model's step's by at most this RMS fraction of E's spreads, "
                        "which bounds any reported E's change by it (0: the model's step; docs/loop.md)")
    s.add_argument("--scheme", choices=("modified_euler", "exact_modal"), default="modified_euler",
                   help="the engine's scheme of the predictions (exact_modal: the modes exact over the step; "
                        "with --dt 1e-3 about 3 x faster on the test rig, docs/loop.md)")
    s.add_argument("--threads", type=threads_option, default=0, help="OpenMP threads (0: default)")
    s.add_argument("--scalar", action="store_true",
                   help="step the horizons with the scalar reference integrator (default: the batched SIMD one)")
    s.add_argument("--thesis-knot", action="store_true",
                   help="keep a polynomial law's low-speed pieces tied at 1 %% and 5 %% of the mean speed "
                        "(default: the knot calibrated with the law)")
    s.add_argument("--gj-tolerance", type=float, default=0.03,
                   help="relative tolerance of the declared string GJ, within which it is calibrated like the "
                        "damping; a mismatch beyond it is string_stiffness (0: GJ held as declared)")
    s.add_argument("--wob-input", choices=("auto", "measured", "trend"), default="auto",
                   help="the WOB the law takes: the recorded one where it is an input, its trend below 0.5 Hz where "
                        "the record shows it is a response of the rotation (auto, the default), or forced")
    s.add_argument("--channel-timing", default="auto", metavar="none|auto|LEAD,LAG",
                   help="bring the channels to the bit encoder's time first: auto (the default: the skew that "
                        "balances the bit's equation on the calibration part, where the record identifies one), "
                        "none (as recorded) or the top encoder's lead and the torque's lag in s, e.g. 0.04,0.03")
    s.add_argument("--long-run-fluctuation", choices=("none", "record"), default="none",
                   help="the bit-rock torque of the long runs: the law alone (none, the default) or with the "
                        "fluctuation of Eq. (4.1) the calibration part shows (record)")
    s.add_argument("--json", action="store_true", help="print the errors and the effects found as JSON")
    s.add_argument("--no-progress", action="store_true", help="no progress bar")
    s.set_defaults(func=cmd_loop)
    return s


def cmd_loop(a: argparse.Namespace) -> int:
    """Measured record versus a declared model: the missing effects and the corrected model
    (:func:`drillpy.reports.loop.loop_record`, which writes ``--out``).

    Parameters
    ----------
    a : argparse.Namespace
        Arguments of ``drillpy loop``; ``--horizon``/``--dt`` in s, ``--rate`` in Hz.

    Returns
    -------
    int
        Exit status 0; the loop logs its steps (text) or the errors and effects are printed as JSON.
        A progress bar counts the candidate fits (stderr, when a terminal; off with ``--no-progress``).
    """
    from drillpy.loop import LoopOptions
    from drillpy.reports.loop import loop_record
    from drillpy.loop.effects import NAMES
    effects = NAMES if a.effects is None else tuple(e.strip() for e in a.effects.split(",") if e.strip())
    opt = LoopOptions(horizon_s=a.horizon, calibration_fraction=a.calibration_fraction, rate_hz=a.rate,
                      min_gain=a.min_gain, alpha=a.alpha, min_delta_bic=a.min_delta_bic, max_steps=a.max_steps,
                      effects=effects, threads=a.threads, dt_s=a.dt, step_tolerance=a.step_tolerance, scheme=a.scheme, batched=not a.scalar,
                      law_knot=not a.thesis_knot, gj_tolerance=a.gj_tolerance,
                      wob_input=a.wob_input, channel_timing=_channel_timing(a.channel_timing),
                      long_run_fluctuation=a.long_run_fluctuation)
    from drillpy.progress import log_progress
    with log_progress(((r"  null candidate", "candidates"), (r"  candidate ", "candidates"), (r"  remove ", "backward")),
                      "loop", enabled=not a.no_progress, echo=None if a.json else print, count=True) as log:
        js = loop_record(a.record, a.out, preset=a.preset, config_path=a.config, options=opt, log=log,
                         figure_units=a.figure_units)
    if a.json:
        print_json({k: js[k] for k in ("metric", "baseline_error", "final_error", "declared", "removed",
                                       "final_effects", "confusable", "unexplained_fraction", "warnings")} |
                   {"added": [s["effect"] for s in js["steps"] if s["action"] == "add"]})
    return 0


def _rig_search(text: str) -> tuple:
    """``--rig-search STARTS,EVALUATIONS`` -> (starts, evaluations), both integers >= 1."""
    try:
        starts, evaluations = (int(x) for x in text.split(","))
    except ValueError:
        raise ValueError(f"--rig-search = {text!r}: use STARTS,EVALUATIONS, two integers (e.g. 8,400)") from None
    if starts < 1 or evaluations < 1:
        raise ValueError(f"--rig-search = {text!r}: the starts and the evaluations must each be at least 1")
    return starts, evaluations


def _channel_timing(text: str):
    """``--channel-timing``: "none", "auto" or "LEAD,LAG" [s] -> LoopOptions.channel_timing."""
    if text in ("none", "auto"):
        return text
    parts = text.split(",")
    try:
        if len(parts) != 2:
            raise ValueError
        return tuple(float(x) for x in parts)
    except ValueError:
        raise ValueError(f"--channel-timing = {text!r}: use none, auto or LEAD,LAG in s (e.g. 0.04,0.03)") from None


def _add_calibrate(sub) -> argparse.ArgumentParser:
    """Register ``drillpy calibrate`` on the subparsers ``sub``; returns its parser."""
    s = sub.add_parser("calibrate", help="Bayesian calibration of the rig model on a record (ABC-SMC): the posterior "
                                         "of its parameters, the law families' probabilities with their Monte Carlo "
                                         "error, posterior predictive intervals (posterior.json + figures)")
    s.add_argument("record", help="rig MATLAB file or drillpy CSV")
    src = s.add_mutually_exclusive_group(required=True)
    src.add_argument("--preset", help="declared model: a built-in configuration (thesis-rig); default priors")
    src.add_argument("--config", help="declared model: a JSON configuration, its 'calibration' section the priors "
                                      "(docs/calibration.md)")
    s.add_argument("--out", required=True, help="output folder (posterior.json, marginals.png, pair.png, "
                                                "predictive.png)")
    s.add_argument("--t0", type=float, help="start of the calibration window [s]")
    s.add_argument("--t1", type=float, help="end of the calibration window [s]")
    s.add_argument("--heldout", metavar="T0:T1", help="held-out window [s] of the predictive intervals (default: the "
                                                      "calibration window)")
    s.add_argument("--population", type=int, default=200, help="particles per generation")
    s.add_argument("--simulations", type=int, default=20000, help="simulation budget")
    s.add_argument("--generations", type=int, default=12, help="generations after the prior's, at most")
    s.add_argument("--draws", type=int, default=100, help="posterior draws of the predictive intervals")
    s.add_argument("--seed", type=int, default=0, help="seed (same seed, same numbers)")
    s.add_argument("--threads", type=threads_option, default=0, help="simulations at once (0: one per core)")
    s.add_argument("--discrepancy", type=float, metavar="F",
                   help="model discrepancy: each statistic's standard deviation in units of its window-to-window "
                        "spread on the record (noisy ABC under model error; 0: none; default the configuration's "
                        "calibration.discrepancy, else the built-in default; docs/calibration.md)")
    _add_scheduler_args(s, ", the posterior stability map of --map included")
    s.add_argument("--map", metavar="A:B:N,A:B:N", help="also the posterior stability map P(SS > 0.5) over N motor "
                                                       "commands from A to B [rad/s] x N WOB from A to B [N] "
                                                       "(e.g. 6:30:7,400:800:5), stored in OUT/map.zarr")
    s.add_argument("--map-samples", type=int, default=40, help="Monte Carlo samples of the map (posterior draw and "
                                                              "torque fluctuation each)")
    s.add_argument("--json", action="store_true", help="print the model probabilities, parameters and predictive "
                                                       "intervals as JSON")
    s.set_defaults(func=cmd_calibrate)
    return s


def cmd_calibrate(a: argparse.Namespace) -> int:
    """Bayesian calibration of the rig model (:func:`drillpy.reports.calibration.calibrate_to_folder`).

    Parameters
    ----------
    a : argparse.Namespace
        Arguments of ``drillpy calibrate``; ``--t0``/``--t1``/``--heldout`` in s.

    Returns
    -------
    int
        Exit status 0; prints the model probabilities (with their Monte Carlo error), each parameter's
        median and 90 % interval, and the predictive intervals against the held-out window.
    """
    from drillpy.reports.calibration import calibrate_to_folder, summary_lines
    for name in ("t0", "t1"):
        if getattr(a, name) is not None:
            validate.number("--" + name, getattr(a, name), unit="s")
    from drillpy.records.samples import parse_window
    held = None if a.heldout is None else parse_window(a.heldout, "--heldout")
    grids = None if a.map is None else _map_grids(a.map)
    if not 2 <= a.map_samples <= 100000:
        raise ValueError(f"--map-samples = {a.map_samples}: an integer from 2 to 100000")
    if a.discrepancy is not None:
        from drillpy.calibration.priors import discrepancy_factor
        discrepancy_factor(a.discrepancy, "--discrepancy")
    with _removed_on_failure(a.out):
        s = calibrate_to_folder(a.record, a.out, map_grids=grids, map_samples=a.map_samples, preset=a.preset,
                                config_path=a.config, t0=a.t0, t1=a.t1, heldout=held, population=a.population,
                                max_simulations=a.simulations, max_generations=a.generations,
                                predictive_draws=a.draws, seed=a.seed, threads=a.threads, scheduler=a.scheduler,
                                chunk=a.chunk, discrepancy=a.discrepancy, log=None if a.json else print)
    smap = s.get("stability_map")
    if a.json:
        extra = {} if smap is None else {"stability_map": _map_json(smap)}
        print_json({k: s[k] for k in ("model_probability", "model_probability_se", "model_choice", "parameters",
                                      "predictive")}
                   | {"simulations": s["run"]["simulations"], "wall_s": s["run"]["wall_s"]} | extra)
        return 0
    print("\n".join(summary_lines(s)))
    if smap is not None:
        from drillpy.reports.calibration import map_lines
        print("\n".join(map_lines(smap)))
    return 0


def _add_posterior_map(sub) -> argparse.ArgumentParser:
    """Register ``drillpy posterior-map`` on the subparsers ``sub``; returns its parser."""
    s = sub.add_parser("posterior-map", help="the posterior stability map P(SS > 0.5) of a calibration's "
                                              "posterior.json over motor command x WOB (docs/calibration.md)")
    s.add_argument("posterior", help="posterior.json written by drillpy calibrate")
    s.add_argument("--map", required=True, metavar="A:B:N,A:B:N",
                   help="the grid: N motor commands from A to B [rad/s], N WOB values from A to B [N]")
    s.add_argument("--samples", type=int, default=40, help="Monte Carlo samples (posterior draw and torque "
                                                            "fluctuation each)")
    s.add_argument("--seed", type=int, default=0, help="seed of the draws and of the fluctuation")
    s.add_argument("--threads", type=threads_option, default=0, help="runs at once (0: one per core)")
    _add_scheduler_args(s, " backend")
    s.add_argument("--out", help="folder for map.zarr and map.png")
    s.add_argument("--json", action="store_true", help="print the grid and P with its 90 %% interval as JSON")
    s.set_defaults(func=cmd_posterior_map)
    return s


def cmd_posterior_map(a: argparse.Namespace) -> int:
    """The posterior stability map of an existing calibration (:func:`drillpy.reports.calibration.map_to_folder`).

    Parameters
    ----------
    a : argparse.Namespace
        Arguments of ``drillpy posterior-map``.

    Returns
    -------
    int
        Exit status 0; prints P(SS > 0.5 or a stall) per cell with its Wilson 90 % interval (text or JSON).
    """
    from drillpy.reports.calibration import map_lines, map_to_folder
    grids = _map_grids(a.map, "--map")
    validate.integer("--samples", a.samples, 2, 100000)
    validate.integer("--seed", a.seed, 0, 2 ** 63 - 1)
    if not _is_posterior(a.posterior):
        raise ValueError(f"posterior = {a.posterior!r}: not a posterior.json of drillpy calibrate")
    with _removed_on_failure(a.out):
        smap, files = map_to_folder(a.posterior, a.out, grids, samples=a.samples, seed=a.seed, threads=a.threads,
                                    scheduler=a.scheduler, chunk=a.chunk)
    if a.json:
        print_json(_map_json(smap))
        return 0
    print("\n".join(map_lines(smap) + (["written: " + ", ".join(files)] if files else [])))
    return 0


def _map_json(smap) -> dict:
    """A stability map's grid, P(SS > 0.5 or a stall), its 90 % interval and P(stall), as JSON lists."""
    return {"speeds_rad_s": smap.speeds.tolist(), "wobs_n": smap.wobs.tolist(), "p_unstable": smap.p_unstable.tolist(),
            "ci90": smap.ci90.tolist(), "p_stall": smap.p_stall.tolist()}


def _map_grids(text: str, name: str = "--map") -> tuple:
    """``--map A:B:N,A:B:N``: (motor commands [rad/s], WOB [N]), each N values from A to B."""
    import math

    import numpy as np
    try:
        parts = text.split(",")
        if len(parts) != 2:
            raise ValueError
        grids = []
        for part in parts:
            lo, hi, n = part.split(":")
            lo, hi, n = float(lo), float(hi), int(n)
            if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo <= hi and 1 <= n <= 100
                    and (n == 1 or lo < hi)):
                raise ValueError
            grids.append(np.linspace(lo, hi, n))
    except ValueError:
        raise ValueError(f"{name} = {text!r}: give COMMANDS,WOBS as A:B:N,A:B:N (rad/s, N; 0 < A < B, 1 <= N <= 100; "
                         "A = B with N = 1)") from None
    return tuple(grids)


#: subcommand -> function registering it (``drillpy.cli.build_parser`` orders them)
SUBCOMMANDS = {"analyze": _add_analyze, "predict": _add_predict, "loop": _add_loop, "calibrate": _add_calibrate,
               "posterior-map": _add_posterior_map}


def _rig_fixed(items) -> dict | None:
    """``--rig-fix NAME=VALUE`` options over the calibration's defaults (``rig_calibration.DEFAULT_FIXED``;
    ``NAME=free`` calibrates a parameter held by default); None without options (the defaults). Every
    option is checked before the analysis starts: the name among the rig's parameters, the value
    inside its physical range (``rigsim.RIG_PARAMETERS``)."""
    if not items:
        return None
    from drillpy.records.rig_calibration import DEFAULT_FIXED
    from drillpy.records.rigsim import RIG_PARAMETERS
    out = dict(DEFAULT_FIXED)
    for it in items:
        name, sep, val = str(it).partition("=")
        name, val = name.strip(), val.strip()
        if not sep or not val:
            raise ValueError(f"--rig-fix = {it!r}: give NAME=VALUE or NAME=free, e.g. static_torque_factor=1.09")
        if name not in RIG_PARAMETERS:
            raise ValueError(f"--rig-fix = {it!r}: {name!r} is not a parameter of the rig model "
                             f"(one of {', '.join(RIG_PARAMETERS)})")
        if val == "free":
            out.pop(name, None)
            continue
        lo, hi, unit = RIG_PARAMETERS[name][:3]
        try:
            x = float(val)
        except ValueError:
            x = math.nan
        if not lo <= x <= hi:
            raise ValueError(f"--rig-fix = {it!r}: {name} must be a number within its physical range "
                             f"[{lo:g}, {hi:g}]{'' if unit == '-' else ' ' + unit}")
        out[name] = x
    return out
