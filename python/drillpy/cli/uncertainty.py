"""``drillpy`` commands under uncertainty: frf, frf-report, robust-ss (structural, chapter 6 and
beyond) and mc (stochastic bit-rock law, chapter 4).

Each ``_add_*`` function registers one subcommand's arguments; the ``cmd_*`` handler below it turns
them into library calls and prints the result (text, or one JSON line with ``--json``).
"""
from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

from drillpy import validate
from drillpy.cli import add_figure_units_arg, add_model_args, add_study_args, add_wob_arg, integer, model_config, parse_grid, print_json
from drillpy.jsonio import jsonable
from drillpy.model.configuration import Configuration
from drillpy.uncertainty.binomial import wilson_interval


def add_uncertainty_args(p: argparse.ArgumentParser, samples: int, out: str) -> None:
    """Add the options of the structural-uncertainty commands (frf, frf-report, robust-ss).

    Parameters
    ----------
    p : argparse.ArgumentParser
        A subcommand's parser; receives the model options, ``--cb-modes``, ``--samples``, ``--seed``,
        ``--out`` and ``--json``.
    samples : int
        Default number of Monte Carlo samples.
    out : str
        Help text of ``--out``.
    """
    add_model_args(p)
    p.add_argument("--cb-modes", help="fixed-interface modes per substructure, e.g. 25,25")
    p.add_argument("--samples", type=int, default=samples, help="Monte Carlo samples")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--out", help=out)
    p.add_argument("--json", action="store_true")


def cb_config(a: argparse.Namespace, controller: bool = False) -> dict:
    """The configuration of :func:`drillpy.cli.model_config` with ``--cb-modes`` applied.

    Parameters
    ----------
    a : argparse.Namespace
        Arguments of a command registered with :func:`add_uncertainty_args`.
    controller : bool
        Whether the command accepts ``--controller`` (``robust-ss``: the time-domain runs take the
        configuration's top drive, a controlled one tuned on the nominal string). The frequency-domain
        studies (``frf``, ``frf-report``) refuse it: their FRFs are those of the string clamped at the top.

    Returns
    -------
    dict
        The configuration, with the Craig-Bampton modes per substructure when ``--cb-modes`` is given
        and the controlled top drive of ``--controller``.
    """
    validate.integer("samples", a.samples, 1, MAX_SAMPLES)
    validate.seed(a.seed)
    if a.controller is not None and not controller:  # FRFs of the random models clamped at the top (chapter 6)
        raise ValueError(f"--controller = {a.controller}: the frequency-domain studies (frf, frf-report) are those "
                         "of the string clamped at the top (the thesis's ideal drive); robust-ss takes a controller")
    cfg = model_config(a)
    if a.cb_modes:
        from drillpy.uncertainty.frf import with_cb_modes
        cfg = with_cb_modes(cfg, [int(x) for x in parse_grid(a.cb_modes, "--cb-modes")])
    elif getattr(a, "model", "SM_CB2") != "SM_full" and not _cb_modes(cfg):
        n = len(Configuration.of(cfg).string.sections)
        raise ValueError(f"--cb-modes: the configuration {cfg.get('name', '')!r} sets no craig_bampton.modes; give "
                         f"one number of fixed-interface modes per section ({n} section{'s' if n != 1 else ''}, e.g. "
                         f"{','.join(['25'] * n)}) or use thesis-ch6")
    return cfg


#: Most Monte Carlo samples of a structural study (as drillpy mc: the engine's limit).
MAX_SAMPLES = 10_000_000


def _cb_modes(cfg) -> tuple:
    """The ``craig_bampton.modes`` of a configuration (empty without the block)."""
    craig = Configuration.of(cfg).get("craig_bampton")
    return () if craig is None else craig.modes


def _eta_samples(path: str) -> np.ndarray:
    """The eta samples of ``--eta-npy``: a numeric NumPy array file (one row per sample)."""
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"--eta-npy = {path!r}: no such file")
    try:
        eta = np.load(p, allow_pickle=False)
    except (ValueError, OSError, EOFError):
        raise ValueError(f"--eta-npy = {path!r}: not a NumPy .npy array file") from None
    if not (isinstance(eta, np.ndarray) and eta.dtype.kind in "biuf"):
        raise ValueError(f"--eta-npy = {path!r}: not a numeric NumPy array (.npy)")
    return eta


def _add_frf(sub) -> argparse.ArgumentParser:
    """Register ``drillpy frf`` on the subparsers ``sub``; returns its parser."""
    s = sub.add_parser("frf", help="acceleration FRF envelopes under structural uncertainty (chapter 6)")
    add_uncertainty_args(s, samples=2500, out="folder for the figures, envelope.json and study.zarr (every "
                                              "sample's FRF)")
    add_study_args(s)
    s.add_argument("--model", choices=["SM_full", "SM_CB1", "SM_CB2"], default="SM_CB2", help="stochastic model")
    s.add_argument("--case", type=int, help="SM_CB2 case study 1-7 (Tables 6.1-6.7)")
    s.add_argument("--delta", type=float, help="one dispersion for every random matrix (default 0.1)")
    s.add_argument("--probability", type=float, default=0.95, help="probability level of the envelope")
    s.add_argument("--freqs", default="0.01:10:1000", help="frequencies [Hz], start:stop:num or list")
    s.set_defaults(func=cmd_frf)
    return s


def cmd_frf(a: argparse.Namespace) -> int:
    """Acceleration FRF envelope of one stochastic model (:func:`drillpy.uncertainty.frf.frf_envelope`).

    Parameters
    ----------
    a : argparse.Namespace
        Arguments of ``drillpy frf``; ``--freqs`` in Hz.

    Returns
    -------
    int
        Exit status 0; prints the envelope as JSON or its mean width [dB] per frequency band; with
        ``--out`` :func:`drillpy.reports.uncertainty.write_envelope` writes the figures and
        ``envelope.json``.
    """
    from drillpy.reports.uncertainty import write_envelope
    from drillpy.uncertainty.chapter6 import BANDS_HZ
    from drillpy.uncertainty.frf import band_widths, frf_envelope
    if a.case is not None:
        validate.integer("case", a.case, 1, 7)
    cfg = cb_config(a)
    freq = parse_grid(a.freqs, "--freqs")
    if a.out or a.scheduler != "local":  # every sample's FRF stored / computed in chunks, the same envelope
        from drillpy.study import Study, run_study
        from drillpy.uncertainty.frf import envelope_from_samples, observation_nodes
        nodes = observation_nodes(cfg)
        study = Study("frf", cfg, (), samples=a.samples, seed=a.seed,
                      options={"model": a.model, "delta": a.delta, "case": a.case, "freq_hz": freq.tolist(),
                               "nodes": list(nodes)})
        ds = run_study(study, a.out, scheduler=a.scheduler, chunk=a.chunk, threads=a.threads,
                       progress=not a.no_progress)
        env = envelope_from_samples(cfg, ds["frf_db"].values, ds["energy"].values, a.model, a.delta, a.case,
                                    seed=a.seed, freq_hz=freq, probability=a.probability, progress=False,
                                    threads=a.threads)  # the default nodes (those stored), with their labels
    else:
        env = frf_envelope(cfg, a.model, a.delta, a.case, samples=a.samples, seed=a.seed, freq_hz=freq,
                           probability=a.probability, progress=not a.no_progress, threads=a.threads)
    res = {**env.to_json(), "case": a.case}
    bands = {b: r for b, r in BANDS_HZ.items() if np.sum((env.freq_hz >= r[0]) & (env.freq_hz <= r[1])) >= 2}
    if a.out:
        title = a.model + (f" case {a.case}" if a.case else f" delta {a.delta if a.delta is not None else 0.1}")
        write_envelope(a.out, env, title, jsonable(res), cfg, seed=a.seed, samples=a.samples, model=a.model, delta=a.delta,
                       case=a.case)
    if a.json:
        print_json(res)
    else:
        print(f"{a.model}, {env.samples} samples, {int(round(100 * env.probability))} % envelope; "
              "mean width [dB] per band:")
        for band, w in zip(bands, band_widths(env, list(bands.values()))):
            print(f"  {band:24s} " + "  ".join(f"{lab.split(' ')[0]} {x:6.2f}" for lab, x in zip(env.labels, w)))
    return 0


def _add_frf_report(sub) -> argparse.ArgumentParser:
    """Register ``drillpy frf-report`` on the subparsers ``sub``; returns its parser."""
    s = sub.add_parser("frf-report", help="chapter 6 and appendix C: envelopes, case studies, Conv2, conclusions")
    add_uncertainty_args(s, samples=2500, out="output folder (default results-ch6)")
    s.add_argument("--mode-samples", type=int, default=400, help="samples per point of Conv2 versus modes")
    s.set_defaults(func=cmd_frf_report, out="results-ch6")
    return s


def cmd_frf_report(a: argparse.Namespace) -> int:
    """Run the chapter-6 study (:func:`drillpy.reports.uncertainty.chapter6_report`) into ``--out``.

    Parameters
    ----------
    a : argparse.Namespace
        Arguments of ``drillpy frf-report``.

    Returns
    -------
    int
        Exit status 0; prints the summary as JSON or the verdict on each conclusion of section 6.6.
    """
    from drillpy.reports.uncertainty import chapter6_report, print_conclusions
    validate.integer("mode_samples", a.mode_samples, 1, MAX_SAMPLES)
    s = chapter6_report(cb_config(a), a.out, samples=a.samples, mode_samples=a.mode_samples, seed=a.seed,
                        progress=not a.no_progress, threads=a.threads)
    if a.json:
        print_json(s)
    else:
        print_conclusions(s["conclusions"])
        print(f"figures and summary.json written to {a.out}")
    return 0


def _add_robust_ss(sub) -> argparse.ArgumentParser:
    """Register ``drillpy robust-ss`` on the subparsers ``sub``; returns its parser."""
    s = sub.add_parser("robust-ss", help="SS versus top speed with SM_CB2 structural uncertainty (time domain; "
                                         "--controller: a controlled top drive tuned on the nominal string)")
    add_uncertainty_args(s, samples=40, out="folder for the figure, robust_ss.json and study.zarr (one group per "
                                            "source of uncertainty)")
    add_study_args(s)
    s.add_argument("--delta", type=float, default=0.1, help="dispersion of every SM_CB2 matrix")
    s.add_argument("--speeds", default="6:27:8",
                   help="top speeds, start:stop:num or list, in rad/s or with a unit (60:250:8rpm)")
    add_wob_arg(s)
    s.add_argument("--bit-rock", action="store_true",
                   help="add the stochastic bit-rock law: eta with the thesis PSD (Eqs. 4.1-4.4)")
    s.add_argument("--eta-npy", help="eta(t) of Eq. (4.1), one row per sample (.npy), for bit-rock uncertainty")
    s.add_argument("--eta-dt", type=float, default=0.05, help="sampling step of eta [s]")
    s.add_argument("--refine", type=float, metavar="TOL",
                   help="locate each 5 %% speed by bisection to TOL [rad/s] (same samples at new speeds)")
    add_figure_units_arg(s)
    s.set_defaults(func=cmd_robust_ss)
    return s


def cmd_robust_ss(a: argparse.Namespace) -> int:
    """SS versus top speed [rad/s] per source of uncertainty and each one's 5 % speed
    (:func:`drillpy.uncertainty.structural.robust_severity`).

    Parameters
    ----------
    a : argparse.Namespace
        Arguments of ``drillpy robust-ss``; ``--eta-dt`` in s, ``--refine`` in rad/s.

    Returns
    -------
    int
        Exit status 0; prints the studies as JSON or, per source, SS statistics per speed and the speed
        from which P(SS > 0.5) <= 5 %; with ``--out``
        :func:`drillpy.reports.uncertainty.write_robust_severity` writes the figure and ``robust_ss.json``.
    """
    from drillpy.reports.uncertainty import write_robust_severity
    from drillpy.uncertainty.structural import robust_severity
    from drillpy.uncertainty.process import THESIS_PSD
    cfg = cb_config(a, controller=True)
    if a.bit_rock and a.eta_npy:
        raise ValueError("--bit-rock and --eta-npy: give one source of eta")
    speeds = parse_grid(a.speeds, "--speeds", "speed")
    client = cluster = None
    if a.out or a.scheduler != "local":
        from drillpy.study.cluster import open_client, parse_scheduler
        client, cluster = open_client(parse_scheduler(a.scheduler), lambda m: print(m, file=sys.stderr))
    try:
        studies, res = robust_severity(cfg, speeds, a.samples, delta=a.delta,
                                       eta_psd=THESIS_PSD if a.bit_rock else None,
                                       eta=_eta_samples(a.eta_npy) if a.eta_npy else None, eta_dt=a.eta_dt,
                                       refine=a.refine, seed=a.seed, progress=not a.no_progress, threads=a.threads,
                                       runner=_stored_runner(a, client) if a.out or client else None)
    finally:
        if cluster is not None:
            client.close()
            cluster.close()
    if a.out:
        write_robust_severity(a.out, speeds, studies, jsonable(res), cfg, seed=a.seed, delta=a.delta, samples=a.samples,
                              bit_rock=a.bit_rock or None, eta_npy=a.eta_npy, figure_units=a.figure_units)
    if a.json:
        print_json(res)
    else:
        for label, st in studies.items():
            print(f"{label}:")
            p_lo, p_hi = wilson_interval(np.clip(st.p_stick_slip, 0.0, 1.0), st.ss.shape[0])
            for v, m, lo, hi, p, a_, b_ in zip(speeds, st.mean, st.q05, st.q95, st.p_stick_slip, p_lo, p_hi):
                print(f"  {v:7.2f} rad/s  SS mean {m:.3f}  5-95 % [{lo:.3f}, {hi:.3f}]  P(SS > 0.5) {p:.2f} "
                      f"[90 % Wilson {a_:.2f}, {b_:.2f}]")
            p05 = res[label].get("p05_speed_rad_s")
            print("  P(SS > 0.5) <= 5 % from", "no crossing in range" if p05 is None else f"{p05:.2f} rad/s",
                  _robust_speed_text(res[label]))
            _precision_warning(res[label])
    return 0


def _stored_runner(a: argparse.Namespace, client):
    """A :func:`drillpy.uncertainty.structural.severity_study` that runs each source of ``robust-ss`` as a
    stored study (group ``<source>`` of ``OUT/study.zarr``) on the chosen backend; the same numbers."""
    import re
    from drillpy.study import Study, run_study
    from drillpy.uncertainty.structural import SeverityStudy

    def run(cfg, speeds, samples, *, model="SM_CB2", delta=0.1, case=None, structural=True, eta_psd=None,
            eta_dt=0.05, seed=1, label="", progress=True, threads=0):
        study = Study("structural", cfg, tuple(float(v) for v in speeds), samples=samples, seed=seed,
                      options={"model": model, "delta": delta.tolist() if hasattr(delta, "tolist") else delta,
                               "case": case, "structural": structural,
                               "psd": None if eta_psd is None else eta_psd.as_dict(), "eta_dt_s": float(eta_dt)})
        ds = run_study(study, a.out, client=client, chunk=a.chunk, threads=threads, progress=progress,
                       group=re.sub(r"[^A-Za-z0-9]+", "_", label).strip("_"))
        return SeverityStudy(speeds=np.asarray(speeds, dtype=float), ss=ds["severity"].values, label=label)
    return run


def add_mc(sub) -> argparse.ArgumentParser:
    """Register ``drillpy mc``.

    ``--samples``, ``--seed`` and ``--first-sample`` are integers (:func:`drillpy.cli.integer`): a
    value that is not one is the one-line error ``drillpy: error: samples = 'ten': must be an
    integer``; their ranges are checked by the study.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The ``drillpy`` subparsers.

    Returns
    -------
    argparse.ArgumentParser
        The subcommand's parser.
    """
    s = sub.add_parser("mc", help="Monte Carlo of the stochastic bit-rock law (Figs. 4.4-4.9, C.1)")
    add_model_args(s)
    s.add_argument("--samples", type=integer("samples"), default=500, help="number of Monte Carlo samples")
    s.add_argument("--seed", type=integer("seed"), default=0,
                   help="integer seed; sample i depends only on (seed, i)")
    s.add_argument("--first-sample", type=integer("first_sample"), default=0,
                   help="index of the first sample (chunked runs)")
    s.add_argument("--speeds", default="6:27:22",
                   help="top speeds, start:stop:num or list, in rad/s or with a unit (60:250:22rpm)")
    add_wob_arg(s)
    s.add_argument("--warmup", type=float, help="deterministic start-up shared by all samples [s] "
                                                "(default 100; 0 with axial.type = rgd)")
    s.add_argument("--eta-dt", type=float, default=0.05, help="sampling step of eta [s]")
    g = s.add_mutually_exclusive_group()
    g.add_argument("--psd-model", help="f0,A0,a,b of Eq. (4.4) (default: the thesis's "
                                       "0.27,-7.6,-3.13,-11.67)")
    g.add_argument("--psd-table", help="CSV file with columns f_hz,S")
    s.add_argument("--psd-convention", default="one-sided-hz",
                   choices=["one-sided-hz", "two-sided-hz", "one-sided-rad-s", "two-sided-rad-s"],
                   help="convention of the PSD given by --psd-model/--psd-table or the thesis "
                        "parameters (converted to drillpy's one-sided PSD per Hz)")
    s.add_argument("--eta-std", type=float,
                   help="scale the Eq. (4.4) model to this standard deviation of eta (e.g. 0.0667: the "
                        "thesis's +-20 %% field fluctuation read as +-3 sigma; docs/stochastic.md)")
    s.add_argument("--refine", type=float, metavar="TOL",
                   help="locate the 5 %% speed by bisection to TOL [rad/s] (same samples at new speeds)")
    s.add_argument("--out", help="folder for the figures, mc.json, mc_samples.json (every sample's SS) and "
                             "study.zarr (with --first-sample 0: resumed or extended by the same command)")
    add_study_args(s)
    s.add_argument("--no-figures", action="store_true",
                   help="with --out, write mc.json and mc_samples.json only (chunks of a study to merge)")
    add_figure_units_arg(s)
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_mc)
    return s


def _add_mc_merge(sub) -> argparse.ArgumentParser:
    """Register ``drillpy mc-merge`` (:func:`drillpy.reports.stochastic.merge_outputs`)."""
    s = sub.add_parser("mc-merge", help="merge chunks of one Monte Carlo study run with --first-sample")
    s.add_argument("chunks", nargs="+", help="output folders of drillpy mc --out (or their mc_samples.json)")
    s.add_argument("--out", help="folder for the merged mc.json, mc_samples.json and Figs. 4.9 and C.1")
    add_figure_units_arg(s)
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_mc_merge)
    return s


def cmd_mc_merge(a: argparse.Namespace) -> int:
    """Merge chunks of one Monte Carlo study (``drillpy mc-merge``).

    Parameters
    ----------
    a : argparse.Namespace
        ``chunks`` (folders or ``mc_samples.json`` files), ``--out``, ``--json``.

    Returns
    -------
    int
        Exit status 0; prints the merged summary (as ``drillpy mc`` does) and writes it with ``--out``.
    """
    from drillpy.jsonio import dumps
    from drillpy.reports.stochastic import merge_outputs
    from drillpy.uncertainty.robust_speed import robust_speed_summary
    study = merge_outputs(a.chunks, a.out, a.figure_units)
    res = study.summary()
    res.update(robust_speed_summary(study.severity, study.speeds, None, study.seed, None))
    if a.json:
        print(dumps(res, indent=None))
    else:
        n = study.severity.shape[0]
        print(f"{len(a.chunks)} chunks merged: samples {study.first_sample}-{study.first_sample + n - 1}, "
              f"seed {study.seed}")
        for r in res["speeds"]:
            print(_mc_row(r))
        p05 = res["p05_speed_rad_s"]
        print("P(SS > 0.5) <= 5 % from", "no crossing in range" if p05 is None else f"{p05:.2f} rad/s",
              _robust_speed_text(res))
        _precision_warning(res)
        if a.out:
            print(f"mc.json, mc_samples.json and figures written to {a.out}")
    return 0


def psd_option(a: argparse.Namespace):
    """The PSD of eta selected by ``--psd-table``, ``--psd-model``, ``--psd-convention`` and ``--eta-std``.

    Parameters
    ----------
    a : argparse.Namespace
        Arguments of ``drillpy mc``: ``--psd-table`` (CSV ``f_hz,S``, S in the given convention),
        ``--psd-model`` (``f0,A0,a,b`` of Eq. 4.4, f0 in Hz), ``--eta-std`` (standard deviation of eta [-]).

    Returns
    -------
    PsdModel or PsdTable
        One-sided PSD per Hz (:mod:`drillpy.uncertainty.process`); the thesis's model by default.

    Raises
    ------
    ValueError
        One-line messages naming the option at fault.
    """
    from drillpy.uncertainty.process import PSD_CONVENTIONS, THESIS_PSD, PsdModel, PsdTable, convert_psd_model
    if a.psd_table:
        p = Path(a.psd_table)
        if not p.is_file():
            raise ValueError(f"--psd-table = {str(p)!r}: no such file")
        try:
            with warnings.catch_warnings():  # an empty file: refused below, not a warning
                warnings.simplefilter("ignore", UserWarning)
                data = np.loadtxt(p, delimiter=",", ndmin=2, comments="#")
        except ValueError as e:
            raise ValueError(f"--psd-table = {str(p)!r}: {e}") from None
        if data.size == 0:
            raise ValueError(f"--psd-table = {str(p)!r}: no data (needs rows f_hz,S)")
        if data.shape[1] != 2:
            raise ValueError(f"--psd-table = {str(p)!r}: needs two columns f_hz,S (one-sided, 1/Hz)")
        if getattr(a, "eta_std", None) is not None:
            raise ValueError("--eta-std scales the Eq. (4.4) model: not with --psd-table")
        return PsdTable(data[:, 0], data[:, 1] * PSD_CONVENTIONS[a.psd_convention])
    if a.psd_model:
        try:
            f0, A0, aa, b = (float(x) for x in a.psd_model.split(","))
        except ValueError:
            raise ValueError(f"--psd-model = {a.psd_model!r}: use f0,A0,a,b") from None
        model = convert_psd_model(PsdModel(f0, A0, aa, b), a.psd_convention)
    else:
        model = convert_psd_model(THESIS_PSD, a.psd_convention)
    if getattr(a, "eta_std", None) is not None:
        from drillpy.uncertainty.process import scaled_to_std
        try:
            model = scaled_to_std(model, a.eta_std)
        except ValueError:
            raise ValueError(f"--eta-std = {a.eta_std!r}: must be a positive number") from None
        except OverflowError:  # std ** 2 beyond the float range
            raise ValueError(f"--eta-std = {a.eta_std!r}: too large (its square overflows)") from None
    return model


def cmd_mc(a: argparse.Namespace) -> int:
    """Monte Carlo of the stochastic bit-rock law (:func:`drillpy.uncertainty.montecarlo.stochastic_study`).

    Parameters
    ----------
    a : argparse.Namespace
        Arguments of ``drillpy mc``; ``--samples``, ``--seed``, ``--first-sample`` are ints,
        ``--speeds`` in rad/s, ``--warmup``/``--duration``/``--transient``/``--eta-dt`` in s.

    Returns
    -------
    int
        Exit status 0; prints the study's summary as JSON or SS statistics per speed and the speed from
        which P(SS > 0.5) <= 5 %; with ``--out`` :func:`drillpy.reports.stochastic.write_figures` writes
        the figures and ``mc.json`` (:func:`drillpy.reports.stochastic.write_summary` with ``--no-figures``).
    """
    from drillpy.reports.stochastic import write_figures, write_summary
    from drillpy.uncertainty.robust_speed import robust_speed_summary
    from drillpy.uncertainty import montecarlo as mcm
    cfg = model_config(a)
    speeds = parse_grid(a.speeds, "--speeds", "speed")
    psd = psd_option(a)
    durations = dict(warmup=mcm.default_warmup(cfg) if a.warmup is None else a.warmup,
                     duration=mcm.DURATION_S if a.duration is None else a.duration,
                     transient=mcm.TRANSIENT_S if a.transient is None else a.transient)
    if a.first_sample == 0 and (a.out or a.scheduler != "local"):  # a stored or distributed study
        from drillpy.study import compute_study, mc_study
        data = compute_study(mc_study(cfg, speeds, a.samples, a.seed, psd=psd, eta_dt=a.eta_dt, **durations),
                             a.out, scheduler=a.scheduler, chunk=a.chunk, threads=a.threads, progress=not a.no_progress)
        study = mcm.from_study_data(data)
    else:
        study = mcm.stochastic_study(cfg, speeds, a.samples, a.seed, psd=psd, eta_dt=a.eta_dt, **durations,
                                     first_sample=a.first_sample, threads=a.threads, progress=not a.no_progress)
    res = study.summary()
    res.update(robust_speed_summary(study.severity, study.speeds, a.refine, study.seed, lambda sp: mcm.stochastic_study(
        cfg, sp, study.severity.shape[0], study.seed, psd=psd, eta_dt=a.eta_dt,
        first_sample=study.first_sample, deterministic=False, threads=a.threads, progress=False,
        **{k: study.settings[k + "_s"] for k in ("warmup", "duration", "transient")}).severity))
    if a.out and a.no_figures:
        write_summary(study, a.out, res)
    elif a.out:
        res["figures"] = write_figures(study, cfg, a.out, psd=psd, eta_dt=a.eta_dt,
                                       threads=a.threads, progress=not a.no_progress, figure_units=a.figure_units)
    if a.json:
        print_json(res)
    else:
        print(f"{res['samples']} samples, eta std {res['eta_std']:.4f}; protocol: "
              + (f"Algorithm 1 literally (from rest, {res['duration_s']:g} s, SS after {res['transient_s']:g} s)"
                 if res["warmup_s"] == 0 else
                 f"shared {res['warmup_s']:g}-s deterministic warm start, then {res['duration_s']:g} s with eta, SS "
                 f"after {res['transient_s']:g} s (Algorithm 1 literally: --warmup 0 --duration 300 --transient 200)"))
        for r in res["speeds"]:
            print(_mc_row(r))
        p05 = res["p05_speed_rad_s"]
        print("P(SS > 0.5) <= 5 % from", "no crossing in range" if p05 is None else f"{p05:.2f} rad/s",
              _robust_speed_text(res),
              "(eta = 0 with this study's warm start: SS < 0.5 from",
              "no crossing" if res["deterministic_threshold_rad_s"] is None
              else f"{res['deterministic_threshold_rad_s']:.2f} rad/s by grid interpolation; the model's "
                   "threshold is drillpy sweep's)")
        _precision_warning(res)
        if a.out:
            print(f"figures and mc.json written to {a.out}")
    return 0


def _mc_row(r: dict) -> str:
    """One speed of an ``mc`` summary: mean SS, its 5-95 % band, P(SS > 0.5) with its 90 % Wilson interval."""
    lo, hi = r["p_ss_gt_0_5_wilson90"]
    return (f"{r['top_speed_rad_s']:8.3f} rad/s  mean SS = {r['mean_ss']:.3f}  [q05 {r['q05']:.3f}, q95 {r['q95']:.3f}]  "
            f"P(SS > 0.5) = {r['p_ss_gt_0_5']:.3f} [90 % Wilson {lo:.3f}, {hi:.3f}]")


def _precision_warning(res: dict) -> None:
    """Print the warning of a 5 % speed whose precision the grid limits (stderr, one line)."""
    if res.get("p05_speed_precision_warning"):
        print(f"drillpy: warning: {res['p05_speed_precision_warning']}", file=sys.stderr)


def _robust_speed_text(res: dict) -> str:
    """The bisection bracket and bootstrap interval [rad/s] of a robust-speed summary, as text."""
    b = res.get("p05_speed_bootstrap")
    txt = ""
    if "p05_speed_bracket_rad_s" in res:
        lo, hi = res["p05_speed_bracket_rad_s"]
        txt += f"[bracket {lo:.2f}-{hi:.2f}] "
    if b and b["low"] == b["low"]:
        txt += f"[90 % bootstrap {b['low']:.2f}-{b['high']:.2f}] "
    return txt


#: subcommand -> function registering it (``drillpy.cli.build_parser`` orders them)
SUBCOMMANDS = {"frf": _add_frf, "frf-report": _add_frf_report, "robust-ss": _add_robust_ss, "mc": add_mc,
               "mc-merge": _add_mc_merge}
