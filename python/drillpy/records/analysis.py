"""The analysis of a measured record, computed (nothing drawn or written; ``drillpy analyze``).

read -> clean (:mod:`drillpy.records.cleaning`) -> stick-slip cycles, mean cycle, eta_exp and its PSD,
Table 5.2 statistics (:mod:`drillpy.records.signals`) -> least-squares identification of the bit-rock
laws with intervals and a comparison table (:mod:`drillpy.records.identification`) -> the test rig in
simulation with the identified law and an effective damping estimate (:mod:`drillpy.records.rigsim`).

:func:`compute_analysis` returns a :class:`RecordAnalysis`; :func:`drillpy.figures.records.analysis_figures`
draws it and :func:`drillpy.reports.analysis.write_analysis` writes its files
(:func:`drillpy.reports.analysis.analyze_record` composes the three).
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from drillpy.text import number_text as _f
from drillpy.records import (bit_balance, identification as ident, plausibility, rigsim, rig_calibration,
                             rig_comparison, rig_fluctuation, signals as sig)
from drillpy.uncertainty import process
from drillpy.records.cycle_margin import cycle_margin, margin_lines
from drillpy.records.cleaning import CleaningOptions, CleaningReport, clean
from drillpy.model.config import load_config
from drillpy.model.configuration import Configuration
from drillpy.records.io import RPM, Record, read_record


@dataclass
class AnalysisOptions:
    """Choices of :func:`compute_analysis` (times in s, frequencies in Hz).

    Attributes
    ----------
    t0, t1 : float, optional
        Analysed window of the record.
    stick_fraction : float
        The bit is stuck at or below this fraction of the median top speed.
    cycle_at_s : float, optional
        Time inside the cycle shown in the one-cycle figure (default: a cycle with a clear stick
        phase and a typical period).
    laws : tuple
        Laws to identify (:data:`drillpy.records.identification.LAWS`).
    folds : int
        Folds of the cross-validation over cycles (0: none).
    fit_rate_hz : float
        Samples used by the fits per second (the rig's channels are low-passed at 10 Hz).
    psd_fmax_hz : float
        Upper end of the PSD-model fit band (the rig's acquisition filter cuts at 10 Hz).
    eta_reference : {"mean", "branch"}
        T_hys of Eq. (4.2): the mean of all cycles (thesis) or the branch mean curves.
    simulate : bool
        Run the rig simulations (needs a top-speed channel): the rig model calibrated on the record
        (:func:`drillpy.records.rig_calibration.calibrate`), written as ``model.json``.
    preset : str
        The rig preset simulated.
    calibrate : (float, float), optional
        Calibration part [s]: cleaning, cycles, identification and the rig calibration use it only;
        the rest of the record (pieces of at least ``min_holdout_s``) is predicted by the calibrated
        model and reported with the same metrics.
    min_holdout_s : float
        Shortest held-out piece predicted [s].
    realizations : int
        Realizations of the rig model's torque fluctuation (Eq. 4.1) behind the held-out pieces'
        predictive intervals (:func:`drillpy.records.rig_fluctuation.predictive`).
    rig_fixed : dict, optional
        Parameters of the rig modelled whole held at a value instead of calibrated
        (``fixed`` of :func:`drillpy.records.rig_calibration.calibrate_rig`; None: its defaults).
    law_platform_damping : float, optional
        Identify the laws with the bit speed, its acceleration and the WOB brought through the
        torque-on-bit platform (:data:`drillpy.records.rigsim.PLATFORM_HZ`, this damping ratio) that
        the measured torque went through (:func:`drillpy.records.identification.through_platform`);
        None (default): against the speed and the WOB as measured (docs/records.md section 1).
    channel_timing : str or tuple
        The acquisition's skew at which the rig model's short-horizon error E reads a record
        (:func:`drillpy.records.bit_balance.aligned`): ``"auto"`` (default: the timing that balances
        the bit's equation on the calibration part, the string's stiffness and inertia fitted,
        :func:`drillpy.records.bit_balance.identify_timing`, where the record identifies a skew; else
        as recorded), ``"none"`` (as recorded) or (top lead, torque lag) [s].
        ``model.json`` keeps it, and ``drillpy predict`` reads the records it scores at it; the
        long-run metrics of the calibration are the record's as recorded.
    horizon_weight : float
        Weight of the calibration part's short-horizon error E beside the long-run metrics' mismatch in
        the rig calibration (:func:`drillpy.records.rig_calibration.calibrate_rig`; 0: the metrics alone).
    horizon_channels : str
        The channels of that short-horizon error: ``"loop"`` (bit speed, torque, top speed) or ``"all"``
        (the WOB beside them; ``horizon_channels`` of :func:`~drillpy.records.rig_calibration.calibrate_rig`).
    rig_search : (int, int)
        The rig calibration's Nelder-Mead starts and simulations per start (``starts``,
        ``evaluations`` of :func:`drillpy.records.rig_calibration.calibrate_rig`).
    rig_metrics : tuple of str
        Metrics of :data:`drillpy.records.rig_calibration.EXTRA_KEYS` the rig calibration matches beside
        :data:`drillpy.records.rigsim.MATCHED_RIG` (default none), e.g. ``block_stick_min``.
    """
    t0: float | None = None
    t1: float | None = None
    stick_fraction: float = 0.05
    cycle_at_s: float | None = None
    laws: tuple = ident.LAWS
    folds: int = 5
    fit_rate_hz: float = 100.0
    psd_fmax_hz: float = 10.0
    eta_reference: str = "mean"
    simulate: bool = True
    preset: str = "thesis-rig"
    calibrate: tuple | None = None
    min_holdout_s: float = 2.0
    realizations: int = 20
    rig_fixed: dict | None = None
    law_platform_damping: float | None = None
    channel_timing: str | tuple = "auto"
    horizon_weight: float = rig_calibration.HORIZON_WEIGHT
    horizon_channels: str = rig_calibration.HORIZON_CHANNELS
    rig_search: tuple = (4, 200)
    rig_metrics: tuple = ()


#: What the summary's ``rig -> calibration`` keeps of the short horizons (rig_calibration.calibrate_rig).
HORIZON_KEYS = ("horizon_weight", "horizon_channels", "short_horizon_error", "wob_horizon_error")


def _stats(x) -> dict:
    x = np.asarray(x, float)
    if x.size == 0:
        return {"n": 0}
    return {"n": int(x.size), "mean": float(np.mean(x)), "std": float(np.std(x, ddof=1)) if x.size > 1 else 0.0,
            "median": float(np.median(x)), "min": float(np.min(x)), "max": float(np.max(x))}


def choose_cycle(cycles: sig.Cycles, t, at_s: float | None = None) -> int:
    """Index of the cycle to show: the valid one containing ``at_s``, else among valid cycles with
    a stick phase and a period within 1.5 x the median, the one with the longest stick.

    The shown cycle is the one-cycle figure of the report (bit speed versus time, torque and WOB
    versus bit speed, as the thesis's Fig. 5.7). Without a candidate with a stick phase and a
    typical period, the valid cycle whose period is closest to the median is taken.

    Parameters
    ----------
    cycles : drillpy.records.signals.Cycles
        Stick-slip cycles of the record (:func:`drillpy.records.signals.segment_cycles`).
    t : ndarray
        Time of the record's samples [s], indexed by ``cycles.start`` / ``cycles.end``.
    at_s : float, optional
        A time [s] inside the cycle to show (e.g. 35.5 s for the thesis's 35.3-35.67 s cycle of
        sample 175); None: choose by the rule above.

    Returns
    -------
    int
        Index into ``cycles`` of the cycle to show.

    Raises
    ------
    ValueError
        No valid cycle, or no valid cycle contains ``at_s``.
    """
    valid = np.flatnonzero(cycles.valid)
    if valid.size == 0:
        raise ValueError("no valid stick-slip cycle in the record")
    if at_s is not None:
        hit = [j for j in valid if t[cycles.start[j]] <= at_s < t[cycles.end[j]]]
        if not hit:
            raise ValueError(f"cycle_at_s = {at_s}: no valid cycle contains this time")
        return int(hit[0])
    per = cycles.period_s
    med = np.median(per[valid])
    cand = [j for j in valid if cycles.stick_s[j] > 0 and per[j] <= 1.5 * med]
    if not cand:
        return int(valid[np.argmin(np.abs(per[valid] - med))])
    return int(max(cand, key=lambda j: cycles.stick_s[j]))


@dataclass
class RecordAnalysis:
    """The analysis of a measured record computed by :func:`compute_analysis` (nothing drawn or written).

    Speeds in rad/s, torques in N m, WOB in N, times in s, frequencies in Hz.

    Attributes
    ----------
    options : AnalysisOptions
        The choices the analysis ran with.
    raw : Record
        The record as read (within ``options.t0``-``options.t1``), before cleaning.
    record : Record
        The cleaned record analysed (the calibration part when ``options.calibrate`` is set).
    cleaning : CleaningReport
        Artifacts found and repaired by :func:`drillpy.records.cleaning.clean` on ``raw``.
    stick_threshold_rad_s : float
        The bit is stuck at or below this speed [rad/s].
    cycles : Cycles
        Stick-slip cycles of ``record`` (sample indices, stick durations [s], validity).
    cycle_stats : dict
        Per valid cycle (:func:`drillpy.records.signals.cycle_statistics`): start_s, period_s,
        stick_s, slip_s [s], frequency_hz [Hz], max_speed [rad/s] and, with a top speed, ss [-].
    branch : ndarray
        Per sample: +1 accelerating slip branch, -1 decelerating, 0 stick or excluded.
    accel_rad_s2 : ndarray
        Bit acceleration (Savitzky-Golay derivative of the bit speed) [rad/s^2].
    mean_cycle : MeanCycle
        Torque on bit [N m] of the mean cycle per branch over a bit-speed grid [rad/s].
    mean_cycle_wob : MeanCycle or None
        WOB [N] of the mean cycle per branch (None without a WOB channel).
    eta : EtaSeries
        eta_exp = T / T_hys - 1 [-] on a uniform grid (Eq. 4.2).
    freq_hz, periodogram : ndarray
        Schuster periodogram of eta_exp: frequency [Hz] and one-sided PSD [1/Hz].
    psd_fit : PsdFit
        Fit of Eq. (4.4) to the periodogram over ``psd_band_hz``.
    psd_band_hz : (float, float)
        Frequencies of the fit band [Hz].
    fits : dict
        "constant_wob" (and "measured_wob" when the WOB is measured throughout) -> list of
        :class:`drillpy.records.identification.LawFit`.
    shown_cycle : int
        Index in ``cycles`` of the cycle shown in the one-cycle figure.
    shown_cycle_s : (float, float)
        Start and end of that cycle [s].
    simulations : dict
        Rig simulations: case label -> (simulated Record, RigComparison); empty when not simulated.
    model : RigModel or None
        The rig model calibrated on ``record`` (None when not simulated).
    summary : dict
        The numbers of ``summary.json`` but for ``figures`` and ``shown_cycle_s``, which
        :func:`write_analysis` adds (JSON-ready after :func:`drillpy.jsonio.jsonable`).
    """
    options: AnalysisOptions
    raw: Record
    record: Record
    cleaning: CleaningReport
    stick_threshold_rad_s: float
    cycles: sig.Cycles
    cycle_stats: dict
    branch: np.ndarray
    accel_rad_s2: np.ndarray
    mean_cycle: sig.MeanCycle
    mean_cycle_wob: sig.MeanCycle | None
    eta: sig.EtaSeries
    freq_hz: np.ndarray
    periodogram: np.ndarray
    psd_fit: process.PsdFit
    psd_band_hz: tuple
    fits: dict
    shown_cycle: int
    shown_cycle_s: tuple
    simulations: dict = field(default_factory=dict)
    model: rigsim.RigModel | None = None
    summary: dict = field(default_factory=dict)


def compute_analysis(record: Record | str | Path, options: AnalysisOptions | None = None,
                     log=print, horizon_error=None) -> RecordAnalysis:
    """Analyse a measured record: cleaning, cycles, statistics, eta_exp and its PSD, identification
    of the bit-rock laws and the rig simulations (nothing is drawn or written).

    Parameters
    ----------
    record : Record, str or Path
        The record, or a file :func:`drillpy.records.io.read_record` reads; it needs the bit speed
        [rad/s] and the torque on bit [N m].
    options : AnalysisOptions, optional
        Choices of the analysis (default ``AnalysisOptions()``).
    log : callable
        Called with each progress line (``print`` by default).
    horizon_error : callable, optional
        ``horizon_error(model, piece, command)``: the short-horizon error E [-] of the calibrated rig
        model on a held-out piece (:func:`drillpy.loop.prediction.short_horizon_error`, which
        :func:`drillpy.reports.analysis.analyze_record` passes); None: not computed. Used with
        ``options.calibrate`` only.

    Returns
    -------
    RecordAnalysis
        Every intermediate result and the summary numbers.

    Raises
    ------
    ValueError
        The record shows no valid stick-slip cycle, ``options.calibrate`` is not T0 < T1, or
        ``options.cycle_at_s`` is in no valid cycle.
    """
    opt = options or AnalysisOptions()
    raw = read_record(record) if isinstance(record, (str, Path)) else record
    for need in ("bit_speed", "torque_on_bit"):
        raw.channel(need)  # the analysis needs these two; the error names the missing one
    if opt.t0 is not None or opt.t1 is not None:
        raw = raw.select(opt.t0, opt.t1)
    cl_opt = CleaningOptions()
    if raw.top_speed is None:
        cl_opt.stick_threshold_rad_s = None
    full, rep = clean(raw, cl_opt)
    rec = full
    if opt.calibrate is not None:
        c0, c1 = (float(x) for x in opt.calibrate)
        if not (math.isfinite(c0) and math.isfinite(c1) and c0 < c1):
            raise ValueError(f"calibrate = {opt.calibrate!r}: needs T0 < T1 [s]")
        rec = full.select(c0, c1)
    # one stick rule (rigsim.stick_threshold: a fraction of the median reliable top speed) for every number
    thr = rigsim.stick_threshold(rec, opt.stick_fraction) if raw.top_speed is not None else rep.stick_threshold_rad_s
    S: dict = {"record": {"source": rec.provenance.get("source"), "format": rec.provenance.get("format"),
                          "channels": list(rec.channels), "units_in_file": rec.units,
                          "n_samples": len(rec), "duration_s": rec.duration_s, "sample_rate_hz": rec.sample_rate_hz,
                          "window_s": [float(rec.time_s[0]), float(rec.time_s[-1])]},
               "cleaning": rep.summary()}
    warns = plausibility.check_record(rec, load_config(preset=opt.preset))  # the declared model: the rig preset
    plausibility.emit(warns)
    for w in warns:  # the rig model cannot be fitted to samples slower than its first mode (hours of runs)
        if opt.simulate and w.code == "time_unit" and w.value < w.plausible[0]:
            raise ValueError(f"{w.message}: the rig simulations are not run on such a record (--no-sim analyses "
                             "it without them)")
    S["warnings"] = [w.as_dict() for w in warns]
    log(f"record: {len(rec)} samples at {rec.sample_rate_hz:.0f} Hz over {rec.duration_s:.2f} s; "
        f"channels {', '.join(rec.channels)}")
    for line in rep.lines():
        log(f"  artifacts: {line}")

    # ---------------------------------------------------------------- cycles and statistics
    dt = rec.dt
    v, tq = rec.bit_speed, rec.torque_on_bit
    ok = rec.valid("bit_speed", "torque_on_bit")
    cyc = sig.segment_cycles(v, dt, thr, valid=ok)
    vf = np.where(np.isfinite(v), v, 0.0)
    acc = sig.derivative(vf, dt)
    lab = cyc.branch_labels(len(rec))
    cid = cyc.cycle_id(len(rec))
    if not cyc.valid.any():
        raise ValueError("no valid stick-slip cycle found: the record shows no stick-slip oscillation "
                         "(no bit-speed peak with a prominence of 25 % of its range, or excluded samples "
                         "everywhere)")
    cst = sig.cycle_statistics(cyc, v, rec.top_speed, tq, rec.wob)
    okt = ok & (rec.valid("top_speed") if rec.top_speed is not None else True)
    top_mean = float(np.mean(rec.top_speed[okt])) if rec.top_speed is not None else float("nan")
    S["stick_threshold_rpm"] = thr * RPM
    S["cycles"] = {"n_found": len(cyc), "n_valid": int(cyc.valid.sum()),
                   "period_s": _stats(cst["period_s"]), "frequency_hz": _stats(cst["frequency_hz"]),
                   "stick_s": _stats(cst["stick_s"]), "slip_s": _stats(cst["slip_s"]),
                   "max_bit_speed_rpm": _stats(cst["max_speed"] * RPM),
                   "dominant_frequency_hz": sig.dominant_frequency(vf[ok] if ok.all() else vf, 1 / dt)}
    if "ss" in cst:
        S["cycles"]["ss"] = _stats(cst["ss"])
    S["severity"] = {"ss": sig.severity(v[okt], rec.top_speed[okt]) if rec.top_speed is not None else None,
                     "mean_top_speed_rpm": top_mean * RPM, "mean_bit_speed_rpm": float(np.mean(v[ok])) * RPM,
                     "max_bit_speed_rpm": float(np.max(v[ok])) * RPM, "min_bit_speed_rpm": float(np.min(v[ok])) * RPM,
                     "stick_fraction": float(np.mean(v[ok] <= thr))}
    side = None
    if rec.top_speed is not None:
        # the one measured side: the record's SS and stick fraction are the numbers every comparison of a
        # simulation with it uses (from 2 s, the simulations' start-up, stalls counted apart)
        side = rig_comparison.measured_side(rec, thr, float(rec.time_s[0]), "constant")
        S["severity"].update(ss=side.metrics["ss"], stick_fraction=side.metrics["stick_fraction"],
                             from_s=side.t0, stalls=side.metrics["stalls"]["count"])
    after = ok & (rec.time_s >= (side.t0 if side is not None else rec.time_s[0]))  # the measured side's window
    if not np.any(v[after] <= thr):  # the bit never stops: oscillation, not stick-slip; say so before the numbers
        w = plausibility.PlausibilityWarning(
            "no_stick", "bit_speed",
            f"bit_speed: the bit never falls to the stick threshold ({thr * RPM:.3g} RPM, 5 % of the median top "
            "speed): the cycles below are torsional oscillations without a stick phase, not stick-slip, and the "
            "laws' static torque is not identified (their evidence rests on slip samples only)",
            0.0, (math.ulp(0.0), 1.0), "-")
        plausibility.emit([w])
        S["warnings"].append(w.as_dict())
    S["torque_statistics"] = sig.sample_statistics(tq[ok])  # Table 5.2
    S["torque_statistics"]["thesis_table_5_2_mean_cv_samples_11_20"] = 0.329
    if rec.wob is not None:
        S["wob_statistics"] = sig.sample_statistics(rec.wob[rec.valid("wob")])
    c = S["cycles"]
    log(f"cycles: {c['n_valid']} valid of {c['n_found']}; period {c['period_s']['mean']:.3f} s mean, "
        f"{c['period_s']['median']:.3f} s median; dominant frequency {c['dominant_frequency_hz']:.2f} Hz")
    if S["severity"]["ss"] is not None:
        log(f"SS = {S['severity']['ss']:.3f} (Eq. 3.4, mean top speed {top_mean * RPM:.1f} RPM); per cycle "
            f"{c['ss']['mean']:.3f} +/- {c['ss']['std']:.3f}; stick fraction {S['severity']['stick_fraction']:.3f} "
            f"(measured from {S['severity']['from_s']:g} s, {S['severity']['stalls']} stall(s) apart: the "
            "measured side of every comparison below)")

    # ---------------------------------------------------------------- mean cycle and eta
    mc, eta, f, p, psd = rig_fluctuation.measured(rec.time_s, v, tq, acc, lab, opt.eta_reference, opt.psd_fmax_hz)
    S["mean_cycle"] = {"speed_rpm": (mc.speed * RPM).tolist(), "all_nm": _nan_list(mc.all),
                       "upper_nm": _nan_list(mc.upper), "lower_nm": _nan_list(mc.lower),
                       "half_width_rpm": mc.half_width * RPM}
    mcw = sig.mean_cycle(v, rec.wob, acc, lab * rec.valid("wob")) if rec.wob is not None else None
    S["eta"] = {**eta.statistics(), "reference": opt.eta_reference,
                "thesis_rig_mean": sig.THESIS_ETA_MEAN, "thesis_rig_std": sig.THESIS_ETA_STD}
    band = f[(f > 0) & (f <= opt.psd_fmax_hz)]
    S["psd"] = {"fit": {**psd.as_dict(),  # continuous at f0, with ci95 / se / continuity_jump
                        "f_range_hz": [float(band[0]), float(band[-1])]},
                "thesis_field": process.THESIS_PSD.as_dict(),
                "convention": "Eq. (4.4) with natural logarithms; one-sided PSD of eta in 1/Hz, f in Hz; fit "
                              "of ln S to the raw periodogram (bias of ln of an exponential ordinate removed)",
                "fitter": "drillpy.uncertainty.process.fit_psd_model"}
    log(f"eta_exp: std {S['eta']['std']:.3f} (thesis rig average {sig.THESIS_ETA_STD}); PSD model f0 = "
        f"{psd.model.f0:.3g} Hz (95 % {psd.ci95['f0_hz'][0]:.3g}-{psd.ci95['f0_hz'][1]:.3g}"
        f"{', at the search edge' if psd.f0_ci_at_search_edge else ''}), A0 = {psd.model.A0:.2f}, a = {psd.model.a:.2f}, b = {psd.model.b:.2f} "
        f"(thesis field 0.27 Hz, -7.6, -3.13, -11.67)")

    # ---------------------------------------------------------------- identification
    every = max(1, int(round(rec.sample_rate_hz / opt.fit_rate_hz)))
    variants = {"constant_wob": False}
    if rec.wob is not None and rec.valid("wob")[ok].all():
        variants["measured_wob"] = True
    S["identification"] = {"fit_every": every, "note": ident.METHOD_NOTE}
    chain = None
    if opt.law_platform_damping is not None:
        chain = (rec.sample_rate_hz, rigsim.PLATFORM_HZ, float(opt.law_platform_damping))
        S["identification"]["law_chain"] = {
            "platform_hz": chain[1], "platform_damping": chain[2],
            "rule": "the bit speed, its acceleration and the WOB brought through the torque-on-bit platform the "
                    "measured torque went through, so that the law is fitted on both sides after the same chain"}
        log(f"identification: speed and WOB brought through the torque's platform ({chain[1]:g} Hz, damping "
            f"{chain[2]:g}) before the fits")
    fits_by = {}
    for key, use_wob in variants.items():
        data = ident.FitData.from_arrays(v, acc, tq, lab, cid, wob=rec.wob, use_wob=use_wob, every=every,
                                         cycles=cyc, platform=chain)
        fits = ident.fit_laws(data, opt.laws, mc=mc, folds=opt.folds, stick_threshold=thr)
        cmp = ident.compare_laws(fits)
        fits_by[key] = fits
        S["identification"][key] = {"n_samples": len(data), "n_cycles": int(np.unique(data.group).size),
                                    "wob_ref_n": data.wob_ref, "fits": [f.as_dict() for f in fits], "comparison": cmp}
        log(f"identification ({key.replace('_', ' ')}): {cmp.get('statement', '')}")
        for row in cmp["table"]:
            log(f"  {row['law']:<22} k={row['k']}  RMSE {row['rmse_nm']:.4f}  CV-RMSE {_f(row['cv_rmse_nm'], '.4f')}  "
                f"Var[MSE] {row['var_mse']:.3g}  BIC {row['bic']:.1f}  dBIC {row['delta_bic']:.1f}")

    if "measured_wob" in fits_by:
        S["identification"]["wob_versus_hysteresis"] = _wob_effect(fits_by)
        if "statement" in S["identification"]["wob_versus_hysteresis"]:  # with both laws of a pair identified
            log(f"identification: {S['identification']['wob_versus_hysteresis']['statement']}")

    # ---------------------------------------------------------------- the bit's equation at the cycle
    if rec.top_speed is not None and rigsim.reliable_top_speed(rec).sum() * rec.dt >= 4.0:
        try:
            S["cycle_balance"] = bit_balance.summary(rec, load_config(preset=opt.preset),
                                                     valid=rigsim.reliable_top_speed(rec))
            log(f"cycle balance: {S['cycle_balance']['statement']}")
        except ValueError as e:  # too few samples with the three channels
            S["cycle_balance"] = {"skipped": str(e)}
        else:
            try:
                di = bit_balance.drive_interval(rec, load_config(preset=opt.preset), S["cycle_balance"],
                                                valid=rigsim.reliable_top_speed(rec))
            except ValueError as e:  # a window too short for the blocks
                S["cycle_balance"]["drive_interval"] = {"skipped": str(e)}
            else:
                S["cycle_balance"]["drive_interval"] = di
                log(f"cycle balance: the drive's 95 % intervals (the balanced timings, the window's "
                    f"{sum('skipped' not in b for b in di['blocks'])} of {len(di['blocks'])} blocks with the samples the "
                    f"balance needs and the string's reduction): c_m [{di['motor_slope'][0]:.3f}, {di['motor_slope'][1]:.3f}] N m s/rad, "
                    f"J_m [{di['motor_inertia'][0]:.4f}, {di['motor_inertia'][1]:.4f}] kg m^2")

    # ---------------------------------------------------------------- rig simulation
    sims, model = {}, None
    if opt.simulate and rec.top_speed is not None and rigsim.reliable_top_speed(rec).sum() >= 10:
        held = _held_out(full, rec, opt.min_holdout_s) if opt.calibrate is not None else []
        S["rig"], sims, model = _rig_section(rec, thr, side, fits_by, opt, log, held, horizon_error)
        model.torque_fluctuation = _torque_fluctuation(S, psd, sims, opt, log)
        S["rig"]["torque_fluctuation"] = model.torque_fluctuation
        for row, piece in zip(S["rig"]["held_out"], held):
            if "metrics" in row and model.torque_fluctuation:
                row["predictive"] = rig_fluctuation.predictive(model, piece, thr, opt.realizations)
                log(f"rig: held-out {row['window_s'][0]:.1f}-{row['window_s'][1]:.1f} s, with Eq. (4.1): "
                    f"{row['predictive']['inside']} of {row['predictive']['of']} measured metrics inside their "
                    f"{100 * row['predictive']['level']:.0f} % predictive intervals ({opt.realizations} realizations)")
        if "best" in S.get("cycle_balance", {}):
            try:
                identified = identified_rig_model(rec, model, S["cycle_balance"], psd, opt)
            except (ValueError, RuntimeError) as e:
                S["rig"]["identified"] = {"skipped": str(e)}
            else:
                S["rig"]["identified"] = _identified_section(identified, rec, held, thr, opt, log)
    elif opt.simulate:
        S["rig"] = {"skipped": "the record has no top-speed channel with reliable samples to set the rig's speed"}

    j = choose_cycle(cyc, rec.time_s, opt.cycle_at_s)
    return RecordAnalysis(options=opt, raw=raw, record=rec, cleaning=rep, stick_threshold_rad_s=thr, cycles=cyc,
                          cycle_stats=cst, branch=lab, accel_rad_s2=acc, mean_cycle=mc, mean_cycle_wob=mcw, eta=eta,
                          freq_hz=f, periodogram=p, psd_fit=psd, psd_band_hz=(float(band[0]), float(band[-1])),
                          fits=fits_by, shown_cycle=j,
                          shown_cycle_s=(float(rec.time_s[cyc.start[j]]), float(rec.time_s[cyc.end[j]])),
                          simulations=sims, model=model, summary=S)


def _wob_effect(fits_by: dict) -> dict:
    """How much of the torque the hysteresis term and the measured WOB explain (RMSE drops)."""
    c = {f.name: f.rmse for f in fits_by["constant_wob"]}
    m = {f.name: f.rmse for f in fits_by["measured_wob"]}
    out = {}
    pairs = [("polynomial", "polynomial_hysteretic"), ("hysteretic_reversible", "hysteretic")]
    for rev, hys in pairs:
        if rev in c and hys in c and rev in m:
            out[rev] = {"rmse_constant_wob": c[rev], "rmse_with_hysteresis": c[hys], "rmse_measured_wob": m[rev],
                        "rmse_measured_wob_with_hysteresis": m.get(hys, float("nan"))}
    if out:
        rev = next(iter(out))
        d = out[rev]
        out["statement"] = (
            f"For the {rev} law the hysteresis term of Eq. (3.3) lowers the RMSE from {d['rmse_constant_wob']:.3f} to "
            f"{d['rmse_with_hysteresis']:.3f} N m, scaling by the measured WOB (T = T_law W / W_ref) from "
            f"{d['rmse_constant_wob']:.3f} to {d['rmse_measured_wob']:.3f} N m, and both together to "
            f"{d['rmse_measured_wob_with_hysteresis']:.3f} N m")
        alone = d["rmse_constant_wob"] - d["rmse_with_hysteresis"]
        after = d["rmse_measured_wob"] - d["rmse_measured_wob_with_hysteresis"]
        out["hysteresis_gain_alone_nm"], out["hysteresis_gain_after_wob_nm"] = alone, after
        out["statement"] += (": once the measured WOB is in, the hysteresis term adds little, so the WOB "
                             "oscillation of the cycle accounts for most of the loop the constant-WOB "
                             "hysteretic laws describe." if after < 0.25 * alone else
                             ": the hysteresis term still helps with the measured WOB in, so the two effects "
                             "are distinct.")
    return out


def _held_out(full: Record, cal: Record, min_s: float) -> list:
    """The pieces of ``full`` before and after the calibration part, at least ``min_s`` long."""
    t, a, b = full.time_s, cal.time_s[0], cal.time_s[-1]
    out = []
    for lo, hi in ((t[0], a - full.dt), (b + full.dt, t[-1])):
        if hi - lo >= min_s:
            out.append(full.select(lo, hi))
    return out


#: The metrics of the rig's tables: those of the predictive targets (issue 28) and the stalls.
METRIC_ROWS = ("ss", "stick_fraction", "cycle_frequency_hz", "median_period_s", "torque_p5", "torque_p95",
               "top_speed_std", "wob_std", "mean_top_speed")


def _metric_row(cmp: rig_comparison.RigComparison) -> dict:
    m, s = cmp.measured, cmp.simulated
    return {**{k: {"measured": m[k], "simulated": s[k], "relative_error": rig_comparison.relative_error(s[k], m[k])}
                for k in METRIC_ROWS}, "stalls": {"measured": m["stalls"], "simulated": s["stalls"]}}


def _torque_fluctuation(S: dict, psd: process.PsdFit, sims: dict, opt: AnalysisOptions, log) -> dict | None:
    """The stochastic torque of Eq. (4.1) for the calibrated rig model (:mod:`drillpy.records.rig_fluctuation`):
    the record's Eq. (4.4) shape at the level eta_exp leaves beyond the deterministic model's own.

    eta_exp (Eq. 4.2) measures every departure of a cycle from the mean cycle, and a deterministic
    model has such departures too (its cycles differ through the motor, the jack and the WOB trend):
    the same analysis of the calibrated model's simulation of the calibration window gives its
    own eta_exp. The stochastic part is what is left, var = var(record) - var(model) (None when
    nothing is left)."""
    sim = next((v[0] for k, v in sims.items() if k.endswith("(calibrated model)")), None)
    if sim is None:
        return None
    own = compute_analysis(sim, AnalysisOptions(simulate=False, folds=0, laws=("polynomial",),
                                                psd_fmax_hz=opt.psd_fmax_hz, eta_reference=opt.eta_reference),
                           log=lambda *_: None)
    rec_std, model_std = S["eta"]["std"], own.eta.statistics()["std"]
    S["rig"]["eta_exp_std"] = {"record": rec_std, "model": model_std}
    left = rec_std ** 2 - model_std ** 2
    log(f"rig: eta_exp (Eq. 4.2) std {rec_std:.3f} on the record, {model_std:.3f} on the calibrated model's own "
        f"simulation: Eq. (4.1)'s stochastic part " + (f"std {math.sqrt(left):.3f}" if left > 0 else "none"))
    if not left > 0:
        return None
    out = rig_fluctuation.identify(psd.model.as_dict(), math.sqrt(left), opt.psd_fmax_hz)
    out.update(record_eta_std=rec_std, model_eta_std=model_std)
    return out


#: The identified rig model's modal damping ratio: a steel bar's (docs/records.md, section 4).
STEEL_DAMPING = 0.01


def identified_rig_model(rec: Record, base: rigsim.RigModel, balance: dict, psd: process.PsdFit,
                         opt: "AnalysisOptions") -> rigsim.RigModel:
    """The rig modelled whole from what the record shows directly, nothing fitted to its long-run
    metrics (docs/records.md, section 4, "The level the record shows is the level the cycle needs").

    From ``base`` (the calibrated whole-rig model) it keeps the law, the jack, the platform, the GJ
    and the disk, and replaces: the drive by the one the bit's equation shows at the cycle's frequency
    (``balance["best"]`` of :func:`drillpy.records.bit_balance.summary`: c_m and J_m, J_m at least the
    range's floor, the coupling rigid at the top of its range), the command by the droop line through
    the record's means (mean top speed + mean torque / c_m), the damping by a steel bar's
    (:data:`STEEL_DAMPING`), and the torque fluctuation of Eq. (4.1) by the record's Eq. (4.4) shape at
    the level whose eta_exp (Eq. 4.2), measured on the model's simulation of ``rec`` the record's way
    (one realization, seed 0), equals the record's: eta_exp sees the fluctuation through the 10 Hz
    filter and the cycle, so its level is not the input's. Seven bisections in [0.02, 0.6].

    Parameters
    ----------
    rec : Record
        The cleaned calibration part.
    base : RigModel
        The calibrated whole-rig model (``drive = "rig"``).
    balance : dict
        :func:`drillpy.records.bit_balance.summary` of ``rec``.
    psd : PsdFit
        The Eq. (4.4) fit of the record's eta_exp.
    opt : AnalysisOptions
        ``psd_fmax_hz`` and ``eta_reference`` are used.

    Returns
    -------
    RigModel
        The model, ``calibration["identified"]`` saying how each part was obtained.

    Raises
    ------
    ValueError
        When the balance gives no positive droop, or the record's eta_exp is not positive.
    """
    best = balance["best"]
    cm = float(best["motor_slope"])
    if not (math.isfinite(cm) and cm > 0):
        raise ValueError(f"the bit's equation gives a drive slope c_m = {cm!r} N m s/rad: no droop to build the drive on")
    lo_j, _, _, _ = rigsim.RIG_PARAMETERS["motor_inertia_kg_m2"]
    _, hi_k, _, _ = rigsim.RIG_PARAMETERS["coupling_stiffness_nm_rad"]
    jm = max(float(best["motor_inertia"]), lo_j)
    ok = rigsim.reliable_top_speed(rec) & rec.valid("torque_on_bit")
    top_mean, torque_mean = float(np.mean(rec.top_speed[ok])), float(np.mean(rec.torque_on_bit[ok]))
    command = top_mean + torque_mean / cm
    # 95 % intervals: the kept parts' from the calibration, the drive's from the balance (the balanced
    # timings and the window's blocks, bit_balance.drive_interval), the command's through the droop line
    intervals = {k: v for k, v in base.intervals.items() if k in KEPT_FROM_CALIBRATION}
    di = balance.get("drive_interval") or {}
    if "motor_slope" in di:
        c_lo, c_hi = di["motor_slope"]
        _, hi_j, _, _ = rigsim.RIG_PARAMETERS["motor_inertia_kg_m2"]
        intervals["motor_slope_nms_rad"] = [c_lo, c_hi]
        intervals["motor_inertia_kg_m2"] = [min(max(di["motor_inertia"][0], lo_j), jm), min(di["motor_inertia"][1], hi_j)]
        if c_lo > 0:
            intervals["command_rad_s"] = [top_mean + torque_mean / c_hi, top_mean + torque_mean / c_lo]
    m = dataclasses.replace(base, motor_slope_nms_rad=cm, motor_inertia_kg_m2=jm, coupling_stiffness_nm_rad=hi_k,
                            command_rad_s=command, damping_ratio=STEEL_DAMPING, intervals=intervals)
    own = AnalysisOptions(simulate=False, folds=0, laws=("polynomial",), psd_fmax_hz=opt.psd_fmax_hz,
                          eta_reference=opt.eta_reference)
    eta_series = compute_analysis(rec, own, log=lambda *_: None).eta
    target = float(eta_series.statistics()["std"])
    if not target > 0:
        raise ValueError(f"the record's eta_exp has standard deviation {target!r}: no fluctuation to match")
    span = float(rec.time_s[-1] - rec.time_s[0]) + 1.0

    def shown(level: float) -> float:  # eta_exp of the model's simulation with the fluctuation at this level
        tf = rig_fluctuation.identify(psd.model.as_dict(), level, opt.psd_fmax_hz)
        sim = rigsim.simulate_model(m, rec, eta=rig_fluctuation.realization(tf, rec.dt, span, seed=0))
        return float(compute_analysis(sim, own, log=lambda *_: None).eta.statistics()["std"])
    lo, hi = 0.02, 0.6
    for _ in range(7):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if shown(mid) < target else (lo, mid)
    level = 0.5 * (lo + hi)
    # the level's 95 % interval: the record's eta_exp std over the window's blocks, through the local
    # slope of the model's eta_exp against the level (one more simulation at 1.2 times the level)
    t_lo, t_hi = _eta_std_interval(eta_series)
    slope = (shown(1.2 * level) - shown(level)) / (0.2 * level)
    level_ci = [level + (t_lo - target) / slope, level + (t_hi - target) / slope] if slope > 0 else None
    m.torque_fluctuation = {**rig_fluctuation.identify(psd.model.as_dict(), level, opt.psd_fmax_hz),
                            "record_eta_std": target,
                            "rule": "Eq. (4.1) T = (1 + eta) T_law; eta's PSD the Eq. (4.4) fit to eta_exp (Eq. 4.2) of the "
                                    "calibration window, band-limited to the fitted band, at the level whose eta_exp on the "
                                    "model's own simulation is the record's"}
    m.calibration = {**base.calibration, "command_rad_s": command, "identified": {
        "drive": {"from": "the bit's equation at the cycle's frequency (drillpy.records.bit_balance.summary)",
                  "top_lead_s": best["top_lead_s"], "torque_lag_s": best["torque_lag_s"],
                  "motor_slope_nms_rad": cm, "motor_inertia_kg_m2": jm, "coupling_stiffness_nm_rad": hi_k},
        "command_rad_s": {"value": command, "from": "the record's droop line through its means"},
        "damping_ratio": {"value": STEEL_DAMPING, "from": "a steel bar's modal damping"},
        "torque_fluctuation_std": {"value": level, "ci95": level_ci,
                                   "from": f"eta_exp of the model's simulation equal to the record's {target:.4f} "
                                           f"(95 % [{t_lo:.4f}, {t_hi:.4f}] over the window's {ETA_BLOCKS} blocks)"},
        "kept": "the law, the jack, the platform, the GJ and the disk of the calibrated whole-rig model"}}
    if "motor_inertia" in di:
        m.calibration["identified"]["drive"]["motor_inertia_ci95_as_measured"] = list(di["motor_inertia"])
    m.calibration.pop("mismatch", None)
    # held, not estimated: a steel bar's damping and a rigid coupling (no interval, no bound flag)
    base_fixed = ((base.calibration.get("per_drive") or {}).get("rig") or {}).get("fixed") or {}
    m.calibration["per_drive"] = {"rig": {"fixed": {**base_fixed, "damping_ratio": STEEL_DAMPING,
                                                    "coupling_stiffness_nm_rad": hi_k}}}
    return m


#: The calibrated whole-rig model's parameters the identified model keeps, with their intervals.
KEPT_FROM_CALIBRATION = ("jack_gain_n_rad", "jack_relaxation_s", "platform_damping", "gj_factor", "bit_inertia_factor",
                         "static_torque_factor")
#: Blocks of the window over which the record's eta_exp standard deviation gets its interval.
ETA_BLOCKS = 4


def _eta_std_interval(es) -> tuple:
    """95 % interval of the standard deviation of an eta_exp series (Eq. 4.2): its value on the whole
    series +- t(0.975, n - 1) sd / sqrt(n) of its values on :data:`ETA_BLOCKS` equal blocks."""
    from scipy import stats
    edges = np.linspace(es.t[0], es.t[-1], ETA_BLOCKS + 1)
    per = [float(np.std(es.eta[(es.t >= a) & (es.t <= b) & es.measured], ddof=1)) for a, b in zip(edges[:-1], edges[1:])]
    full = float(es.statistics()["std"])
    half = float(stats.t.ppf(0.975, ETA_BLOCKS - 1)) * float(np.std(per, ddof=1)) / math.sqrt(ETA_BLOCKS)
    return full - half, full + half


def _identified_section(m: rigsim.RigModel, rec: Record, held: list, thr: float, opt: "AnalysisOptions", log) -> dict:
    """The identified model's summary: how it was obtained, and its predictive intervals
    (:func:`drillpy.records.rig_fluctuation.predictive`) on the calibration part and each held-out piece."""
    info = m.calibration["identified"]
    d = info["drive"]
    log(f"rig, identified from the record: c_m {d['motor_slope_nms_rad']:.3f} N m s/rad, J_m "
        f"{d['motor_inertia_kg_m2']:.4f} kg m^2 (the bit's equation), command {m.command_rad_s:.2f} rad/s, damping "
        f"ratio {m.damping_ratio:g}, Eq. (4.1) level {info['torque_fluctuation_std']['value']:.3f}")
    out = {"model": m.to_dict(), "windows": []}
    for piece, label in [(rec, "calibration")] + [(p, "held out") for p in held]:
        pr = rig_fluctuation.predictive(m, piece, thr, opt.realizations)
        out["windows"].append({"window_s": [float(piece.time_s[0]), float(piece.time_s[-1])], "part": label,
                               "predictive": pr})
        log(f"rig, identified: {piece.time_s[0]:.1f}-{piece.time_s[-1]:.1f} s ({label}): {pr['inside']} of "
            f"{pr['of']} measured metrics inside their {100 * pr['level']:.0f} % predictive intervals "
            f"({opt.realizations} realizations)")
    return out


def _shown(cmp: rig_comparison.RigComparison) -> str:
    """The log's reading of a comparison: SS, stick fraction and cycle frequency, simulated (measured)."""
    return ", ".join(f"{name} {cmp.simulated[k]:.{d}f} (measured {cmp.measured[k]:.{d}f})" for k, name, d in (
        ("ss", "SS", 3), ("stick_fraction", "stick fraction", 3), ("cycle_frequency_hz", "cycle frequency [Hz]", 2)))


def _rig_section(rec: Record, thr: float, side, fits_by: dict, opt: AnalysisOptions, log, held: list,
                 horizon_error) -> tuple:
    """The rig model: the rig modelled whole and self-contained (:func:`drillpy.records.rig_calibration.calibrate_rig`:
    motor, jack, platform, with the identified sticking law) as the predictive answer, the simpler
    drives (constant, motor, and the measured top speed as a diagnosis) calibrated beside it
    (:func:`drillpy.records.rig_calibration.calibrate`) for comparison, and the prediction of the held-out pieces.
    Every case is compared with the same measured side ``side`` (:func:`drillpy.records.rig_comparison.measured_side`);
    ``horizon_error`` gives the short-horizon E (None: not computed) of the calibration part, which the
    calibration weighs by ``opt.horizon_weight`` beside the long-run metrics, and of the held-out pieces,
    read at the channels' timing ``opt.channel_timing`` resolves to on ``rec``
    (:func:`drillpy.records.bit_balance.resolve_timing`), which the model keeps."""
    preset = opt.preset
    base = Configuration.load(preset=preset)
    timing = bit_balance.resolve_timing(rec, opt.channel_timing, base, valid=rigsim.reliable_top_speed(rec))
    log(f"rig: {bit_balance.timing_line(timing)} (the held-out short-horizon E reads the records so)")

    def sticky(fits):
        return [f for f in fits if f.name.startswith("polynomial")] or list(fits)
    # the WOB is a state of the whole rig model: its law is the one identified with the WOB scaling
    wob_fits = sticky(fits_by.get("measured_wob") or fits_by["constant_wob"])
    law_w = min(wob_fits, key=lambda f: f.bic)
    law_c = min(sticky(fits_by["constant_wob"]), key=lambda f: f.bic)
    out = {"preset": preset, "preset_law": base.law.to_dict(), "preset_damping": base.damping.to_dict(), "cases": [],
           "law": law_w.name,
           "law_rule": "the non-regularized law (Eqs. 5.1, 5.3: it sticks at its static torque) with the lower BIC, "
                       "identified with the torque scaled by the measured WOB (the whole rig's WOB is a state, "
                       "and the law scales with it)"}
    sims = {}

    def case(label, model):
        sim = rigsim.simulate_model(model, rec)
        cmp = rig_comparison.compare(rec, sim, thr, side=side)
        out["cases"].append({"label": label, "law": model.law, "damping_ratio": model.damping_ratio,
                             "drive": model.drive, "predictive": model.drive in rigsim.PREDICTIVE_DRIVES,
                             "measured": cmp.measured, "simulated": cmp.simulated,
                             "mismatch": cmp.mismatch, "loop_rms_nm": cmp.loop_rms_nm})
        sims[label] = (sim, cmp)
        log(f"rig: {label}: mismatch {cmp.mismatch:.3f}, " + _shown(cmp))

    z0 = base.damping.ratios[0]
    case(f"preset law, zeta {z0:g}, constant top speed", rigsim.RigModel(base.law.to_dict(), z0, "constant",
                                                                          preset=preset))
    simple = rig_calibration.calibrate(rec, law_c.law, thr, drives=("constant", "motor", "measured"), preset=preset, log=log)
    for drive, b in simple.per_drive.items():
        m = rigsim.RigModel(law_c.law, b["damping_ratio"], drive, b.get("motor_slope_nms_rad"),
                            b.get("motor_inertia_kg_m2"), preset=preset)
        extra = (f", c_m {m.motor_slope_nms_rad:.3g}, J_m {m.motor_inertia_kg_m2:.3g}" if drive == "motor" else "")
        note = " (diagnosis: fed the measured top speed, which carries the cycle)" if drive == "measured" else ""
        case(f"{law_c.name}, {drive} drive, zeta {m.damping_ratio:.3g}{extra}{note}", m)
    out["channel_timing"] = bit_balance.applied_timing(timing)
    cal = rig_calibration.calibrate_rig(
        rec, law_w.law, thr, preset=preset, log=log, fixed=opt.rig_fixed, horizon_error=horizon_error,
        horizon_weight=opt.horizon_weight, horizon_channels=opt.horizon_channels, keys=rigsim.MATCHED_RIG + tuple(
            opt.rig_metrics), channel_timing=out["channel_timing"], starts=opt.rig_search[0], evaluations=opt.rig_search[1])
    model = cal.model
    case(f"{law_w.name}, the rig modelled whole (motor, jack, platform), zeta {model.damping_ratio:.3g} "
         "(calibrated model)", model)
    out["simple_drives"] = simple.summary()["per_drive"]
    out["calibration"] = {"mismatch": cal.comparison.mismatch, "matched": list(cal.model.calibration["matched"]),
                          "fixed": cal.per_drive["rig"]["fixed"], "per_drive": cal.per_drive,
                          **{k: model.calibration[k] for k in HORIZON_KEYS}}
    out["parameters"] = model.parameters()
    out["recommended"] = {"law": model.engine_law, "law_name": law_w.name, "damping_ratio": model.damping_ratio,
                          "static_torque_factor": model.static_torque_factor, "drive": model.drive,
                          "predictive": True, "mismatch": cal.comparison.mismatch,
                          "rule": "the rig modelled whole (rig_calibration.calibrate_rig): every parameter inside its physical "
                                  "range, inputs the motor command and the jack's slow WOB trend only"}
    flags = [f"{k}: {v['flag']}" for k, v in out["parameters"].items() if v["flag"]]
    log(f"rig: calibrated model: {law_w.name}, the rig modelled whole, damping ratio {model.damping_ratio:.3g} "
        f"(mismatch {cal.comparison.mismatch:.3f})" + ("; flagged: " + "; ".join(flags) if flags else ""))
    out["calibration_metrics"] = _metric_row(cal.comparison)
    if rec.wob is not None:  # how far the cycle sits from its edge in WOB (issue 28); model.json keeps it for predict
        out["cycle_margin"] = model.calibration["cycle_margin"] = cm = cycle_margin(model, rec, thr)
        for line in margin_lines(cm):
            log("rig: " + line)
    out["held_out"] = []
    for piece in held:
        row = {"window_s": [float(piece.time_s[0]), float(piece.time_s[-1])]}
        try:
            sim = rigsim.simulate_model(model, piece)
            cmp = rig_comparison.compare(piece, sim, thr)
            row.update(metrics=_metric_row(cmp), mismatch=cmp.mismatch)
            if horizon_error is not None:  # the loop's E, and the WOB's where the record has one
                row.update({k: horizon_error(model, piece, sim.provenance["command_rad_s"], channels=ch) for k, ch in (
                    ("short_horizon_error", "loop"), ("wob_horizon_error", "wob")) if ch == "loop" or piece.wob is not None})
            sims[f"held-out {row['window_s'][0]:.1f}-{row['window_s'][1]:.1f} s (prediction)"] = (sim, cmp)
            log(f"rig: held-out {row['window_s'][0]:.1f}-{row['window_s'][1]:.1f} s: " + _shown(cmp)
                + (f"; short-horizon E {row['short_horizon_error']:.3f}" if "short_horizon_error" in row else ""))
        except ValueError as e:
            row["skipped"] = str(e)
            log(f"rig: held-out piece not predicted: {e}")
        out["held_out"].append(row)
    return out, sims, model


def _nan_list(x) -> list:
    return [None if not np.isfinite(v) else float(v) for v in np.asarray(x, float)]
