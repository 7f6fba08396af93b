"""``drillpy analyze``: the full analysis of a measured record, written as a report.

:func:`analyze_record` composes :func:`drillpy.records.analysis.compute_analysis` (a
:class:`~drillpy.records.analysis.RecordAnalysis`; the held-out pieces' short-horizon error E by
:func:`drillpy.loop.prediction.short_horizon_error`) -> :func:`drillpy.figures.records.analysis_figures`
-> :func:`write_analysis` (``report.md``, ``summary.json`` and ``model.json``).
"""
from __future__ import annotations

from pathlib import Path


from drillpy.outputs import write_text
from drillpy.figures import records as figs
from drillpy.jsonio import dumps
from drillpy.provenance import provenance, with_markdown_footer
from drillpy.text import number_text
from drillpy.records import plausibility
from drillpy.records import rigsim
from drillpy.records.cycle_margin import slope_statement
from drillpy.records.io import RPM, Record
from drillpy.records.analysis import AnalysisOptions, RecordAnalysis, compute_analysis


def write_analysis(result: RecordAnalysis, out_dir: str | Path, figures=(), log=print) -> dict:
    """Write ``summary.json``, ``report.md`` and, when the rig was simulated, ``model.json``.

    Parameters
    ----------
    result : RecordAnalysis
        What :func:`drillpy.records.analysis.compute_analysis` returned.
    out_dir : str or Path
        Output folder (created if missing).
    figures : sequence of str or Path
        The figures written beside (:func:`drillpy.figures.records.analysis_figures`); their file
        names go to the summary's ``figures``.
    log : callable
        Called with each progress line.

    Returns
    -------
    dict
        The summary (content of ``summary.json``): ``result.summary`` with ``figures`` (file names)
        and ``shown_cycle_s`` ([start, end] of the cycle shown [s]).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    if result.model is not None:
        write_text((out / "model.json"), dumps(result.model.to_dict()))
        log(f"rig model written to {out / 'model.json'} (apply it to any record: drillpy predict)")
    ident = result.summary.get("rig", {}).get("identified", {})
    if "model" in ident:
        write_text((out / "model_identified.json"), dumps(ident["model"]))
        log(f"rig model identified from the record written to {out / 'model_identified.json'} (drillpy predict "
            "--draws N gives its predictive intervals)")
    S = {**result.summary, "figures": [Path(f).name for f in figures],
         "shown_cycle_s": [float(x) for x in result.shown_cycle_s]}
    prov = provenance()
    write_text((out / "summary.json"), dumps({**S, "provenance": prov}))
    write_text((out / "report.md"), with_markdown_footer(render_report(S), prov))
    log(f"report.md, summary.json and {len(S['figures'])} figures written to {out}")
    return S


def analyze_record(record: Record | str | Path, out_dir: str | Path, options: AnalysisOptions | None = None,
                   log=print, figure_units: str = "si") -> dict:
    """Analyse a measured record and write ``report.md``, figures and ``summary.json`` to ``out_dir``.

    :func:`drillpy.records.analysis.compute_analysis` -> :func:`drillpy.figures.records.analysis_figures` ->
    :func:`write_analysis`.

    Parameters
    ----------
    record : Record, str or Path
        The record or its file.
    out_dir : str or Path
        Output folder (created if missing).
    options : AnalysisOptions, optional
        Choices of the analysis.
    log : callable
        Called with each progress line.
    figure_units : str
        Axis units of the figures' torques and WOB (``si``: N m, N; ``field``: ft-lbf, lbf;
        :data:`drillpy.figures.simulation.FIGURE_UNITS`); ``summary.json`` and ``report.md`` stay SI.

    Returns
    -------
    dict
        The summary (the content of ``summary.json``).
    """
    from drillpy.figures.simulation import _unit
    _unit(figure_units, "speed")  # an unknown unit refused before the work
    from drillpy.loop.prediction import short_horizon_error
    result = compute_analysis(record, options, log=log, horizon_error=short_horizon_error)
    paths = figs.analysis_figures(result, out_dir, figure_units)
    return write_analysis(result, out_dir, paths, log=log)


# ------------------------------------------------------------------------------ report
def _f(x, spec=".3f"):
    return number_text(x, spec)


def render_report(S: dict) -> str:
    """The Markdown report of a summary (``report.md`` of ``drillpy analyze``).

    Sections: the record (source, samples, rate, window, channels and units in the file);
    the plausibility warnings (:mod:`drillpy.records.plausibility`; "none" when none); cleaning
    (artifact counts and list); stick-slip cycles (stick threshold [RPM], per-cycle period [s],
    frequency [Hz], stick and slip [s], largest bit speed [RPM] and SS (Eq. 3.4), whole-window SS
    and stick fraction, the shown cycle as Figs. 5.6-5.7, the loops as Fig. 3.5);
    sample statistics of the torque on bit [N m] and WOB [N] (Table 5.2); the identification of
    the bit-rock laws (RMSE [N m], cross-validated RMSE, R^2, Var[MSE] of Eq. 5.2, AIC, BIC,
    Akaike weights, parameters with 95 % intervals) at constant and, when measured, scaled WOB;
    eta_exp and the fit of the PSD model of Eq. (4.4) against the thesis's field values
    (Eqs. 4.2-4.4); and, when simulated, the test rig in simulation (model selection,
    calibrated damping ratio and top drive, measured versus simulated metrics, held-out
    predictions). Figures are linked by the file names
    :func:`drillpy.figures.records.analysis_figures` writes.

    Parameters
    ----------
    S : dict
        The summary of :func:`write_analysis` (``RecordAnalysis.summary`` with ``figures`` and
        ``shown_cycle_s``), as in ``summary.json``.

    Returns
    -------
    str
        The Markdown text, ending with a newline.
    """
    r, c, sv = S["record"], S["cycles"], S["severity"]
    L = [f"# Stick-slip analysis of `{Path(str(r['source'])).name}`", "",
         f"Source `{r['source']}` ({r['format']}), {r['n_samples']} samples at {r['sample_rate_hz']:.0f} Hz, "
         f"{r['window_s'][0]:.3f}-{r['window_s'][1]:.3f} s; channels {', '.join(r['channels'])} "
         f"(units in the file: {', '.join(f'{k} {u}' for k, u in r['units_in_file'].items())}).", "",
         *plausibility.markdown(S.get("warnings", [])),
         "![time series](time_series.png)", "", "## Cleaning", "",
         "| artifact | events | samples | repaired | excluded |", "|---|---:|---:|---:|---:|"]
    for k, v in S["cleaning"]["counts"].items():
        L.append(f"| {k} | {v['events']} | {v['samples']} | {v['repaired_samples']} | {v['excluded_samples']} |")
    L += ["", "Artifacts (channel, time span, samples, repair):", ""]
    for a in S["cleaning"]["artifacts"]:
        L.append(f"- {a['kind']} in {a['channel']}: {a['start_s']:.3f}-{a['end_s']:.3f} s, {a['samples']} samples; "
                 f"{a['repair']}")
    if not S["cleaning"]["artifacts"]:
        L.append("- none")
    L += ["", "![cleaning](cleaning.png)", "",
          "## Stick-slip cycles", "",
          f"Stick threshold {S['stick_threshold_rpm']:.2f} RPM (5 % of the median top speed). "
          f"{c['n_valid']} valid cycles of {c['n_found']}; dominant frequency of the bit speed "
          f"{c['dominant_frequency_hz']:.2f} Hz.", "",
          "| per cycle | mean | std | median | min | max |", "|---|---:|---:|---:|---:|---:|"]
    for key, lab in (("period_s", "period [s]"), ("frequency_hz", "frequency [Hz]"), ("stick_s", "stick [s]"),
                     ("slip_s", "slip [s]"), ("max_bit_speed_rpm", "max bit speed [RPM]"), ("ss", "SS (Eq. 3.4) [-]")):
        if key in c:
            s = c[key]
            L.append(f"| {lab} | {s['mean']:.3f} | {s['std']:.3f} | {s['median']:.3f} | {s['min']:.3f} | {s['max']:.3f} |")
    L += ["", f"Whole window: SS = {_f(sv['ss'])} (max {sv['max_bit_speed_rpm']:.1f} RPM, min "
              f"{sv['min_bit_speed_rpm']:.1f} RPM, mean top speed {sv['mean_top_speed_rpm']:.1f} RPM; mean bit speed "
              f"{sv['mean_bit_speed_rpm']:.1f} RPM), stick fraction {sv['stick_fraction']:.3f}.", "",
          "![cycle statistics](cycle_statistics.png)", "",
          f"One cycle ({S['shown_cycle_s'][0]:.3f}-{S['shown_cycle_s'][1]:.3f} s; Figs. 5.6-5.7):", "",
          "![one cycle](cycle.png)", "",
          "Torque and WOB versus bit speed, with the mean cycle per branch (Fig. 3.5):", "",
          "![loops](loops.png)", "", "## Sample statistics (Table 5.2)", ""]
    ts = S["torque_statistics"]
    L += ["| quantity | mean | std | CV |", "|---|---:|---:|---:|",
          f"| torque on bit [N m] | {ts['mean']:.4f} | {ts['std']:.4f} | {ts['cv']:.4f} |"]
    if "wob_statistics" in S:
        w = S["wob_statistics"]
        L.append(f"| WOB [N] | {w['mean']:.2f} | {w['std']:.2f} | {w['cv']:.4f} |")
    L += ["", "The thesis's samples 11-20 have a mean CV of 0.329 (Table 5.2).", "", "## Identification", "",
          S["identification"]["note"], ""]
    for key, title in (("constant_wob", "Laws evaluated at the mean WOB"),
                       ("measured_wob", "Laws scaled by the measured WOB, T = T_law W(t) / W_ref")):
        if key not in S["identification"]:
            continue
        blk = S["identification"][key]
        L += [f"### {title}", "", f"{blk['n_samples']} samples (every {S['identification']['fit_every']}th slip "
              f"sample of {blk['n_cycles']} cycles), W_ref = {blk['wob_ref_n']:.1f} N.", "",
              "| law | Eq. | k | RMSE [N m] | CV RMSE [N m] | R^2 | Var[MSE] (5.2) | AIC | BIC | dBIC | Akaike weight |",
              "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
        for row in blk["comparison"]["table"]:
            L.append(f"| {row['law']} | {row['equation']} | {row['k']} | {row['rmse_nm']:.4f} | "
                     f"{_f(row['cv_rmse_nm'], '.4f')} | {row['r2']:.3f} | {_f(row['var_mse'], '.3g')} | "
                     f"{row['aic']:.1f} | {row['bic']:.1f} | {row['delta_bic']:.1f} | {row['akaike_weight']:.3f} |")
        L += ["", blk["comparison"].get("statement", ""), "", "Parameters (95 % intervals, cluster-robust over cycles; "
              "speed unit RPM):", ""]
        for fit in blk["fits"]:
            ps = ", ".join(f"{n} = {p['value']:.4g} " + ("(at its bound: no interval)" if p["ci95"] is None
                                                          else f"[{p['ci95'][0]:.4g}, {p['ci95'][1]:.4g}]")
                           + (" (stick phases)" if p.get("source") == "stick phases" else "")
                           for n, p in fit["parameters"].items())
            fx = ", ".join(f"{k} = {v:g}" for k, v in fit["fixed"].items())
            bound = f"; at bound: {', '.join(fit['at_bound'])}" if fit["at_bound"] else ""
            L.append(f"- **{fit['law']}** (Eq. {fit['equation']}): {ps}; fixed {fx}{bound}. {fit['fixed_rule']}")
        L.append("")
    if "wob_versus_hysteresis" in S["identification"]:
        L += [S["identification"]["wob_versus_hysteresis"].get("statement", ""), ""]
    L += ["![laws](laws.png)", "", "## eta_exp and its PSD (Eqs. 4.2-4.4)", ""]
    e, p = S["eta"], S["psd"]
    fit, th = p["fit"], p["thesis_field"]
    L += [f"eta_exp = T / T_hys - 1 with T_hys the {'mean of all cycles' if e['reference'] == 'mean' else 'branch mean curves'}; "
          f"{e['n_measured']} slip samples, {100 * e['interpolated_fraction']:.1f} % of the grid interpolated "
          f"(stick phases). Mean {e['mean']:.2e}, std {e['std']:.4f} (thesis, 210 rig samples: mean "
          f"{e['thesis_rig_mean']:.2e}, std {e['thesis_rig_std']}).", "",
          f"PSD model ({p['convention']}; {p['fitter']}), band {fit['f_range_hz'][0]:.3g}-{fit['f_range_hz'][1]:.3g} Hz:", "",
          "| parameter | sample | thesis (field data) |", "|---|---:|---:|",
          f"| f0 [Hz] | {fit['f0_hz']:.3f} | {th['f0_hz']} |", f"| A0 | {fit['A0']:.2f} | {th['A0']} |",
          f"| a | {fit['a']:.2f} | {th['a']} |", f"| b | {fit['b']:.2f} | {th['b']} |",
          f"| rms of ln residuals | {fit['rms_log']:.2f} | |", "", "![psd](psd.png)", ""]
    if "cycle_balance" in S:
        cb = S["cycle_balance"]
        L += ["## The bit's equation at the cycle's frequency", ""]
        if "skipped" in cb:
            L += [f"Skipped: {cb['skipped']}.", ""]
        else:
            L += [f"The declared string as one spring k = {cb['stiffness_nm_rad']:.3f} N m/rad and the bit's inertia J = "
                  f"{cb['inertia_kg_m2']:.3g} kg m^2; at {cb['frequency_hz']:.2f} Hz (coherence {cb['coherence']:.2f}) "
                  "the record's top speed and torque per unit of bit speed leave one unknown, the string's damping c "
                  "(`drillpy.records.bit_balance`; docs/records.md, section 4). " + cb["statement"][0].upper()
                  + cb["statement"][1:] + ".", "",
                  "| channels | top encoder early [ms] | torque late [ms] | c needed [N m s/rad] | drive c_m [N m s/rad] | "
                  "rotor J_m [kg m^2] | feed = drive + string [N m s/rad] |", "|---|---:|---:|---|---:|---:|---|"]
            for label, e in (("as recorded", cb["as_recorded"]), ("best balance", cb["best"])):
                c = e["string_damping"]
                L.append(f"| {label} | {1e3 * e['top_lead_s']:.0f} | {1e3 * e['torque_lag_s']:.0f} | {c[0]:+.4f} {c[1]:+.4f}i | "
                         f"{e['motor_slope']:.3f} | {e['motor_inertia']:.4f} | {e['feed']:.4f} = {e['drive_loss']:.4f} + "
                         f"{e['string_loss']:+.4f} |")
            L.append("")
    if "identified" in S.get("rig", {}):
        L += _identified_lines(S["rig"]["identified"])
    if "rig" in S:
        rg = S["rig"]
        L += ["## Test rig in simulation", ""]
        if "skipped" in rg:
            L += [f"Skipped: {rg['skipped']}.", ""]
        else:
            L += [f"Preset `{rg['preset']}` (one elastic mode, first frequency 2.89 Hz) with the identified "
                  f"{rg['law']} law ({rg['law_rule']}). Simulated bit speed, top speed, torque and WOB pass through "
                  "the rig's 10 Hz filter; the first 2 s are discarded. Stalls (stick phases of at least "
                  f"{rigsim.STALL_MIN_S:g} s) are counted apart and left out of the regular metrics. Mismatch = rms "
                  "relative error over SS, stick fraction, cycle frequency, 95th percentile of the bit speed, 5th and "
                  "95th percentiles of the torque and the standard deviation of the top speed (the whole rig: the "
                  "median period instead of the Welch peak, and the WOB's standard deviation and the mean top speed, "
                  "which it predicts).", "",
                  "**The calibrated model is the rig modelled whole** (`rig_calibration.calibrate_rig`): the open-loop motor "
                  "(its command, the rig's speed setting, calibrated and then held; 8 N m limit), the bar and disk, "
                  "the electrical jack's WOB as a state on the record's slow WOB trend (below "
                  f"{rigsim.WOB_TREND_HZ:g} Hz), the torque platform's {rigsim.PLATFORM_HZ:g} Hz response and the "
                  "10 Hz filter. Its inputs are constants and that slow trend: it predicts the cycle. The `measured` "
                  "drive is a diagnosis only (it is fed the measured top speed, which carries the cycle).", "",
                  *_parameter_table(rg["parameters"])]
            L += ["", "The simpler drives, calibrated on the same part (damping ratio and top drive, rig_calibration.calibrate):",
                  "", "| drive | damping ratio | c_m [N m s/rad] | J_m [kg m^2] | mismatch |", "|---|---:|---:|---:|---:|"]
            for d, b in rg["simple_drives"].items():
                L.append(f"| {d}{' (diagnosis)' if d == 'measured' else ''} | {b['damping_ratio']:.3g} | "
                         f"{_f(b.get('motor_slope_nms_rad'), '.3g')} | {_f(b.get('motor_inertia_kg_m2'), '.3g')} | "
                         f"{b['mismatch']:.3f} |")
            L += ["",
                  "| case | SS | cycle freq. [Hz] | median period [s] | stick fraction | bit speed p95 [RPM] | "
                  "torque p5 [N m] | torque p95 [N m] | WOB sd [N] | mismatch | loop rms [N m] |",
                  "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
            m = rg["cases"][0]["measured"]
            L.append(f"| **measured** | {m['ss']:.3f} | {m['cycle_frequency_hz']:.2f} | {m['median_period_s']:.3f} | "
                     f"{m['stick_fraction']:.3f} | {m['bit_speed_p95'] * RPM:.1f} | {m['torque_p5']:.2f} | "
                     f"{m['torque_p95']:.2f} | {_f(m['wob_std'], '.1f')} | | |")
            for cs in rg["cases"]:
                s = cs["simulated"]
                L.append(f"| {cs['label']} | {s['ss']:.3f} | {s['cycle_frequency_hz']:.2f} | {s['median_period_s']:.3f} | "
                         f"{s['stick_fraction']:.3f} | {s['bit_speed_p95'] * RPM:.1f} | {s['torque_p5']:.2f} | "
                         f"{s['torque_p95']:.2f} | {_f(s['wob_std'], '.1f')} | {cs['mismatch']:.3f} | "
                         f"{_f(cs['loop_rms_nm'])} |")
            rec_ = rg["recommended"]
            cal_ = rg["calibration"]
            e_cal = cal_.get("short_horizon_error")
            L += ["", f"Calibrated rig model ({rec_['rule']}): {rec_['law_name']} law, modal damping ratio "
                  f"{rec_['damping_ratio']:.3g}; the calibration minimized the long-run mismatch ({cal_['mismatch']:.3f})"
                  + (f" plus {cal_['horizon_weight']:g} x the calibration part's short-horizon error over "
                     + ("every channel, the WOB's included" if cal_.get("horizon_channels") == "all" else
                        "the bit speed, torque and top speed") + f" (E {e_cal:.3f}"
                     + (f"; the WOB's {cal_['wob_horizon_error']:.3f}" if cal_.get("wob_horizon_error") is not None else "")
                     + ")" if e_cal is not None else " alone") + "; written as `model.json` (apply it to any record with "
                  "`drillpy predict model.json RECORD`).", ""]
            cm = rg.get("cycle_margin")
            if cm:  # the cycle against the WOB (records.cycle_margin)
                L += ["The calibrated model's stick fraction with the part's WOB scaled: " + ", ".join(
                    f"{100 * r['wob_factor']:.0f} % ({r['wob_n']:.0f} N) {_f(r['stick_fraction'], '.3f')}" for r in cm["model"])
                      + "; the record's 5 s blocks: " + ", ".join(
                    f"{b['wob_n']:.0f} N {b['stick_fraction']:.3f}" for b in cm["record_blocks"]) + "."
                      + (f" Inside the part, {st}." if (st := slope_statement(cm.get("wob_slope_per_100n"))) else "")
                      + (f" **Flagged**: {cm['flag']}." if cm["flag"] else ""), ""]
            if rg.get("held_out"):
                L += ["### Prediction of the held-out parts (never used by the fits)", "",
                      "| window [s] | SS meas. / pred. | stick fraction meas. / pred. | cycle freq. [Hz] meas. / pred. | "
                      "torque p5-p95 [N m] meas. / pred. | top speed sd [rad/s] meas. / pred. | WOB sd [N] meas. / "
                      "pred. | stalls meas. / pred. | short-horizon E |", "|---|---|---|---|---|---|---|---|---:|"]
                for h in rg["held_out"]:
                    w = f"{h['window_s'][0]:.1f}-{h['window_s'][1]:.1f}"
                    if "skipped" in h:
                        L.append(f"| {w} | not predicted: {h['skipped']} | | | | | | | |")
                        continue
                    m = h["metrics"]

                    def mp(k, fmt=".3f"):
                        return f"{_f(m[k]['measured'], fmt)} / {_f(m[k]['simulated'], fmt)} ({100 * m[k]['relative_error']:+.0f} %)"

                    def st(d):
                        return f"{d['count']}" + (" (" + ", ".join(f"{x:.2f} s" for x in d["durations_s"]) + ")"
                                                  if d["count"] else "")
                    L.append(f"| {w} | {mp('ss')} | {mp('stick_fraction')} | {mp('cycle_frequency_hz', '.2f')} | "
                             f"{m['torque_p5']['measured']:.2f}-{m['torque_p95']['measured']:.2f} / "
                             f"{m['torque_p5']['simulated']:.2f}-{m['torque_p95']['simulated']:.2f} | "
                             f"{mp('top_speed_std', '.2f')} | {mp('wob_std', '.1f')} | "
                             f"{st(m['stalls']['measured'])} / {st(m['stalls']['simulated'])} | "
                             f"{_f(h['short_horizon_error'])} |")
                ct = rg.get("channel_timing")
                if ct:
                    L += ["", f"The short-horizon E reads the record with the top speed {1e3 * ct['top_lead_s']:.0f} ms later "
                          f"and the torque {1e3 * ct['torque_lag_s']:.0f} ms earlier (`--channel-timing`, "
                          + ("found on the calibration part" if ct.get("from") == "auto" else "given")
                          + "; `model.json` keeps it)."]
                L.append("")
            L += ["![rig time series](rig_time_series.png)", "", "![rig loops](rig_loops.png)", ""]
    return "\n".join(L) + "\n"


def _parameter_table(params: dict) -> list:
    """report.md's table of a rig model's parameters (:meth:`drillpy.records.rigsim.RigModel.parameters`)."""
    L = ["| parameter | value | 95 % interval | physical range | source of the range | flag |", "|---|---:|---|---|---|---|"]
    for k, v in params.items():
        ci = ("held" if v.get("fixed") else "n/a") if v["ci95"] is None else f"[{v['ci95'][0]:.4g}, {v['ci95'][1]:.4g}]"
        L.append(f"| {k} [{v['unit']}] | {v['value']:.4g} | {ci} | [{v['range'][0]:g}, {v['range'][1]:g}] | "
                 f"{v['source']} | {v['flag'] or ''} |")
    return L


def _identified_lines(idf: dict) -> list:
    """report.md's section on the rig model identified from the record (analysis.identified_rig_model)."""
    L = ["## The rig model identified from the record", ""]
    if "skipped" in idf:
        return L + [f"Not built: {idf['skipped']}.", ""]
    info = idf["model"]["calibration"]["identified"]
    d = info["drive"]
    L += ["Nothing in it is fitted to the long-run metrics (docs/records.md, section 4): the drive from the bit's "
          f"equation at the cycle's frequency (c_m {d['motor_slope_nms_rad']:.3f} N m s/rad, rotor "
          f"{d['motor_inertia_kg_m2']:.4f} kg m^2, coupling rigid; the channels' timing {1e3 * d['top_lead_s']:.0f} ms "
          f"top lead, {1e3 * d['torque_lag_s']:.0f} ms torque lag), the command on the record's droop line "
          f"({info['command_rad_s']['value']:.2f} rad/s), a steel bar's damping ratio "
          f"({info['damping_ratio']['value']:g}), and Eq. (4.1)'s fluctuation at the level "
          f"{info['torque_fluctuation_std']['value']:.3f} whose eta_exp on the model's simulation is the record's; "
          f"{info['kept']}. Written as `model_identified.json`.", "",
          "Its parameters: the drive's intervals span the channel timings that balance the bit's equation as well "
          "and the window's blocks (`bit_balance.drive_interval`), the command's follows c_m along the droop line, "
          "the kept parts' are the calibration's; held, not estimated: the damping and the coupling.", "",
          *_parameter_table(idf["model"]["rig"]["parameters"]), "",
          f"Eq. (4.1)'s level: {_f(info['torque_fluctuation_std']['value'], '.3f')}, 95 % "
          + ("n/a" if not info['torque_fluctuation_std'].get('ci95') else
             "[{:.3f}, {:.3f}]".format(*info['torque_fluctuation_std']['ci95']))
          + f" ({info['torque_fluctuation_std']['from']}, through the local slope of the model's eta_exp against the "
          "level).", "",
          "| window | part | metric | measured | median | predictive interval | inside |", "|---|---|---|---:|---:|---|---|"]
    for w in idf["windows"]:
        pr = w["predictive"]
        for k, v in pr["metrics"].items():
            iv = v["interval"]
            L.append(f"| {w['window_s'][0]:.1f}-{w['window_s'][1]:.1f} s | {w['part']} | {k} | {_f(v['measured'], '.4g')} | "
                     f"{_f(v['median'], '.4g')} | [{_f(iv[0], '.4g')}, {_f(iv[1], '.4g')}] | {'yes' if v['inside'] else 'no'} |")
    return L + [""]
