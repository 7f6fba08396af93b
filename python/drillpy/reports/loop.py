"""``drillpy loop`` composed: :func:`loop_record` runs the loop (:func:`drillpy.loop.run_loop`), draws its
figures (:mod:`drillpy.figures.loop`) and writes ``loop.json``, ``evidence.json``, ``predictions.csv``,
``model.json``, ``config.json`` and ``report.md`` (:func:`write_loop`).
"""
from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from drillpy.outputs import write_text
from drillpy.jsonio import dumps
from drillpy.model.config import load_config, normalize
from drillpy.model.configuration import Configuration
from drillpy.loop.effects import CATALOGUE
from drillpy.loop.options import LoopOptions
from drillpy.loop.run import LoopResult, run_loop
from drillpy.text import number_text as _f
from drillpy.records.io import RPM
from drillpy.records.plausibility import markdown
from drillpy.provenance import header, provenance, with_markdown_footer


# ---------------------------------------------------------------------------------- files
def write_predictions(path, res: LoopResult, prov: dict | None = None) -> Path:
    """predictions.csv: every sample of the analysis grid (a ``#`` provenance line, the header row,
    then numbers only; empty
    cells where no horizon covers a sample or the record has no top speed): time, the recorded bit
    speed, torque on bit and top speed, whether the recorded top speed is a measurement (1; 0: an
    artifact the cleaning filled, left out of E), the baseline's and the final model's predictions
    of the three, whether the sample is in the validation part (1) or the calibration part (0), and
    the index of the horizon that predicts it.

    Parameters
    ----------
    path : str or Path
        The CSV file to write.
    res : LoopResult
        A finished loop run.
    prov : dict, optional
        The :func:`drillpy.provenance.provenance` of the first line (default: a new one).

    Returns
    -------
    Path
        ``path``.
    """
    d = res.data
    n = d.t.size
    keys = ("bv", "bT", "btop", "fv", "fT", "ftop", "val", "hor")
    cols = {k: np.full(n, np.nan) for k in keys}
    hs = d.horizon_samples
    for key, ev in (("b", res.baseline), ("f", res.final)):
        cols[key + "v"][hs] = ev.v
        cols[key + "T"][hs] = ev.T
        if ev.top is not None:
            cols[key + "top"][hs] = ev.top
    cols["val"][hs] = d.is_test[:, None].astype(float)
    cols["hor"][hs] = np.arange(d.starts.size)[:, None]
    top = d.top_meas if d.has_top else np.full(n, np.nan)
    top_ok = d.top_ok.astype(float) if d.has_top else np.full(n, np.nan)

    def f(x):
        return "" if not np.isfinite(x) else repr(float(x))

    def i(x):
        return "" if not np.isfinite(x) else str(int(x))

    from drillpy.outputs import replacing
    with replacing(path) as tmp, open(tmp, "w", newline="") as fh:
        fh.write(header(prov) + "\r\n")  # csv.writer's line ending
        w = csv.writer(fh)
        w.writerow(["time_s", "bit_speed_rad_s", "torque_on_bit_Nm", "top_speed_rad_s", "top_speed_measured",
                    "baseline_bit_speed_rad_s", "baseline_torque_on_bit_Nm", "baseline_top_speed_rad_s",
                    "final_bit_speed_rad_s", "final_torque_on_bit_Nm", "final_top_speed_rad_s", "validation", "horizon"])
        for k in range(n):
            w.writerow([repr(float(d.t[k])), f(d.v_meas[k]), f(d.T_meas[k]), f(top[k]), i(top_ok[k])]
                       + [f(cols[c][k]) for c in ("bv", "bT", "btop", "fv", "fT", "ftop")]
                       + [i(cols["val"][k]), i(cols["hor"][k])])
    return Path(path)


def evidence_json(res: LoopResult) -> dict:
    """The content of ``evidence.json``: everything behind the loop's decisions.

    Parameters
    ----------
    res : LoopResult
        A finished loop run.

    Returns
    -------
    dict
        ``metric``; ``decision`` (which data fitted, decided, and measure the final E); ``record`` (source, samples, rates [Hz], span, calibration and validation
        parts [s], cleaning, stick threshold [rad/s], sd of bit speed [rad/s] and torque [N m],
        horizon [s] and counts); ``options``; ``engine_dt_s`` [s]; ``time_step`` (the step rule's record, :mod:`drillpy.loop.time_step`); ``baseline`` and ``final``
        (errors, validation RMSE, law residual RMSE [N m], parameters, k); ``adequacy``,
        ``declared``, ``baseline_long_run``, ``steps``, ``rounds``, ``discovery``, ``notes``.
    """
    d = res.data

    def ev_summary(e):
        return {"error_calibration": e.E_train, "error_validation": e.E_test, "validation_rmse": e.channel_rmse,
                "law_rmse_calibration_nm": e.law_rmse_train, "law_rmse_validation_nm": e.law_rmse_test,
                "parameters": e.model.parameters(), "k": e.model.k}

    return {"metric": res.metric(), "decision": res.decision(),
            "record": {"source": d.source, "samples": int(d.t.size), "sample_rate_hz": 1.0 / d.dt,
                       "record_rate_hz": d.record_rate_hz, "decimation": d.decimation,
                       "span_s": [float(d.t[0]), float(d.t[-1])], "calibration_s": [float(d.t[0]), d.t_split],
                       "validation_s": [d.t_split, float(d.t[-1])], "cleaning": d.cleaning,
                       "stick_threshold_rad_s": d.stick_threshold, "sd_bit_speed_rad_s": d.sigma_v,
                       "sd_torque_nm": d.sigma_T, "horizon_s": d.L * d.dt,
                       "calibration_horizons": int((~d.is_test).sum()), "validation_horizons": int(d.is_test.sum()),
                       "stalls": [{"start_s": a, "duration_s": n} for a, n in d.stalls],
                       "horizons_set_apart": [{"start_s": float(d.t[s]), "reason": r}
                                              for s, r in sorted(d.set_apart.items())],
                       "channel_timing": d.channel_timing},
            "options": {k: (list(v) if isinstance(v, tuple) else v) for k, v in vars(res.options).items()},
            "engine_dt_s": Configuration.of(res.config).simulation.dt_s, "time_step": res.time_step,
            "baseline": ev_summary(res.baseline), "final": ev_summary(res.final),
            "adequacy": res.adequacy, "declared": res.declared, "baseline_long_run": res.baseline_long_run,
            "steps": [s.to_json() for s in res.steps],
            "rounds": res.rounds, "discovery": res.discovery, "notes": res.notes}


def _step_rule(step: dict) -> str:
    """The step rule's clause of report.md's engine-step line ('' when the step was given)."""
    if not step:
        return ""
    diffs = ", ".join(f"{x['difference']:.4f} at {x['dt_s']:.3g} s" for x in step["tried"])
    out = (f"; the step rule from the declared {step['declared_s']:.3g} s: the declared model's horizon predictions "
           f"differ by {diffs} of E's spreads, tolerance {step['tolerance']:g}")
    for key, what in (("baseline_difference", "the calibrated baseline"), ("final_difference", "the final model")):
        if key in step:
            out += f"; {what}: {step[key]:.4f}"
    return out


def model_config(res: LoopResult) -> dict:
    """The final model as an engine configuration (drillpy simulate / drillsim can run it).

    The effects that act through the record's inputs (the WOB coupling, the torque fluctuation) are
    not in it: a configuration cannot carry a recorded series.

    Parameters
    ----------
    res : LoopResult
        A finished loop run.

    Returns
    -------
    dict
        The normalized configuration, named ``<name>-loop``, its description naming the record and
        the effects (``config.json``).
    """
    c = Configuration.of(res.final.model.engine_config())
    return normalize(c.replace(name=f"{c.name if 'name' in c else 'model'}-loop",
                               description=("calibrated by drillpy loop on " + Path(res.data.source).name + "; effects: "
                                            + (", ".join(res.final.model.effects) or "none"))))


# ---------------------------------------------------------------------------------- report


def _damping(d) -> str:
    """A configuration's ``damping`` block (a :class:`~drillpy.model.configuration.Block`) in words."""
    if d.type == "modal":
        return "modal damping ratios " + ", ".join(f"{r:g}" for r in d.ratios)
    return "Rayleigh damping " + ", ".join(f"{z:g} at {f:g} Hz" for f, z in d.pairs)


def _params(p: dict) -> str:
    def one(k, v):
        if isinstance(v, dict):
            ci = v.get("ci95")
            txt = f"{k} = {v['value']:.4g}" + (f" [{ci[0]:.3g}, {ci[1]:.3g}]" if ci else "")
            return txt + (" (at bound)" if v.get("at_bound") else "")
        return f"{k} = {v:.4g}" if isinstance(v, float) else f"{k} = {v}"
    return ", ".join(one(k, v) for k, v in p.items()) or "-"


def _lr(x: dict | None) -> str:
    if not x:
        return "n/a"
    return (f"SS {_f(x.get('ss'), '.3f')}, stick {_f(x.get('stick_fraction'), '.3f')}, "
            f"{_f(x.get('cycle_frequency_hz'), '.2f')} Hz")


def reading(name: str, p: dict) -> str:
    """Physical reading of an effect found, with its fitted parameters.

    Parameters
    ----------
    name : str
        The effect's catalogue name.
    p : dict
        Its parameter values (name -> value in the parameter's unit; see :func:`values`).

    Returns
    -------
    str
        One sentence on the values (e.g. a motor's droop in RPM per N m, a filter's group delay in
        ms) followed by the effect's reading on the rig.
    """
    e = CATALOGUE[name]
    return f"{e.describe(p)}. On the rig: {e.reading}."


def values(params: dict) -> dict:
    """Parameter values from a step's evidence (entries with intervals) or a model's effects.

    Parameters
    ----------
    params : dict
        Parameter name -> value, or -> ``{"value", "ci95", ...}``
        (:func:`drillpy.loop.fitting.parameter_evidence`).

    Returns
    -------
    dict
        Parameter name -> value.
    """
    return {k: (v["value"] if isinstance(v, dict) and "value" in v else v) for k, v in params.items()}


def render_report(res: LoopResult, files: dict) -> str:
    """The text of ``report.md``: plausibility warnings ("none" when none), data, metrics, baseline,
    steps, physical readings, the discovery step, the evidence of every round, the final parameters,
    figures and notes.

    Parameters
    ----------
    res : LoopResult
        A finished loop run.
    files : dict
        Figure key (``signature``, ``overlay``, ``loops``, ``errors``) -> file name relative to the
        report; the figures absent are not linked.

    Returns
    -------
    str
        Markdown text.
    """
    d, b, f = res.data, res.baseline, res.final
    o = res.options
    cfg = Configuration.of(res.config)
    L = [f"# drillpy loop: `{Path(d.source).name}`", "",
         f"Declared model `{res.config.get('name')}` ({cfg.rom.modes} mode(s), law "
         f"`{cfg.law.type}`, {_damping(cfg.damping)}), calibrated on the record, then "
         f"extended by the effects of the catalogue the evidence supports.", "",
         *markdown(res.warnings), "## Data", "",
         f"- {d.t.size} samples at {1 / d.dt:g} Hz (record {d.record_rate_hz:g} Hz, decimated by {d.decimation}), "
         f"{d.t[0]:.3f}-{d.t[-1]:.3f} s; cleaning: {'; '.join(d.cleaning)}.",
         f"- **calibration part** t < {d.t_split:.3f} s ({int((~d.is_test).sum())} horizons), **validation part** "
         f"t >= {d.t_split:.3f} s ({int(d.is_test.sum())} horizons), horizons of {o.horizon_s:g} s. Nothing is fitted "
         "on the validation part; the errors reported are the validation part's.",
         f"- engine step {cfg.simulation.dt_s:.3g} s ({cfg.simulation.scheme.replace('_', ' ')}"
         + _step_rule(res.time_step) + f"); derivatives by Savitzky-Golay filters of {o.derivative_window_s:g} s "
         "(order 4).", ""]
    L += ["## Metrics", "",
          "- **Law residual**: r_law = T - T_model(v, a, W) on the slip samples (bit speed above "
          f"{d.stick_threshold * RPM:.2f} RPM, every {max(1, int(round(0.01 / d.dt)))}th sample), the model's law "
          "evaluated on the measured bit speed v, acceleration a and the law's WOB input W; reported as its RMSE [N m].",
          "- **Dynamic residual**: every horizon the model restarts from the state that reproduces the measured bit "
          "speed, bit acceleration, torque on bit and top speed (exact for one mode) and is integrated by the engine "
          "over the horizon, driven by the inputs it takes from the record; residual = measured - predicted bit speed "
          "and torque on bit.",
          ("- **Error E** (loop.json `metric`): E = sqrt( 1/3 [ mean (v_pred - v)^2 / sd_v^2 + mean (T_pred - T)^2 / "
           "sd_T^2 + mean (top_pred - top)^2 / sd_v^2 ] ) (the top-speed term counts zero where the recorded top "
           "speed is not a measurement)" if d.has_top else
           "- **Error E** (loop.json `metric`): E = sqrt( 1/2 [ mean (v_pred - v)^2 / sd_v^2 + mean (T_pred - T)^2 / "
           "sd_T^2 ] )") +
          f" over all samples of the part's horizons; sd_v = {d.sigma_v:.4g} rad/s "
          f"({d.sigma_v * RPM:.3g} RPM), sd_T = {d.sigma_T:.4g} N m (calibration part, fixed). E = 1: as far off as "
          "the channels' own spread.",
          f"- **Guard** (an effect is added only if all hold): validation gain >= {100 * o.min_gain:g} %; one-sided "
          f"t-test of the per-horizon log error ratio over the validation horizons (effective number from their "
          f"autocorrelation) with p < {o.alpha:g} / (candidates in the round) (Bonferroni); BIC on the calibration "
          f"part lower by more than {o.min_delta_bic:g} (n_eff = residual samples / autocorrelation time). Among the "
          "candidates that pass, the one with the lowest validation error is added and the model is refitted; the "
          f"refitted model must itself lower E by {100 * o.min_gain:g} % against the current model, or the next "
          "candidate is tried. A direct measurement (static friction's break-away torques) only proposes a "
          "candidate; a recalibration proposed by the calibration part must lower E on the validation part.",
          f"- **Which data decide**: {res.decision()['decided_on']}. **The final E** is measured on the "
          f"{res.decision()['final_error_on']}.", ""]
    a = res.adequacy
    L += ["## Baseline", "",
          f"- declared effects: {', '.join(res.declared) or 'none'}; calibrated modal damping ratios "
          f"{b.model.damping_ratios}" + (f"; string GJ x {b.model.gj_factor:.4f} (calibrated within the declared "
                                         f"geometry's +-{100 * b.model.gj_tolerance:g} %)" if b.model.gj_free else "")
          + ".",
          f"- validation error E = {b.E_test:.4f}; trivial predictors: channel means {a['mean_predictor_error']:.4f}, "
          f"value held from the restart {a['hold_last_predictor_error']:.4f} -> "
          + ("**adequate** (better than both)." if a["adequate"] else
             "**not adequate**: the declared model predicts no better than a trivial predictor; nothing is attributed."),
          "- long run (the model simulated over the record"
          + ("" if b.model.fluctuation is None else ", its bit-rock torque with the fluctuation of Eq. (4.1) the "
             f"calibration part shows, eta_exp std {b.model.fluctuation['std']:.3g}: --long-run-fluctuation record")
          + f"): measured {_lr(res.baseline_long_run.get('measured'))}; "
          f"model {_lr(res.baseline_long_run.get('model'))}.", ""]
    L += ["## Result", "",
          "| step | action | effect | E before | E after | gain | p | dBIC | parameters [95 %] | long run after |",
          "|---|---|---|---:|---:|---:|---:|---:|---|---|"]
    for k, s in enumerate(res.steps, 1):
        e = s.evidence
        alt = "".join(f" or `{r['effect']}`" for r in e.rivals or [] if r["verdict"] == "confusable")
        L.append(f"| {k} | {s.action} | `{s.effect}`{alt} | {s.error_before:.4f} | {s.error_after:.4f} | "
                 f"{100 * (1 - s.error_after / s.error_before):.1f} % | {e.p_value:.2g} | {e.delta_bic:.1f} | "
                 f"{_params(e.parameters or {})} | {_lr((s.long_run or {}).get('after'))} |")
    if not res.steps:
        L.append("| - | | (none: no candidate beats the null candidate) | | | | | | | |")
    L += ["", f"Validation error **{b.E_test:.4f} -> {f.E_test:.4f}** (calibration {b.E_train:.4f} -> {f.E_train:.4f}); "
          f"validation RMSE bit speed {b.channel_rmse['bit_speed_rad_s'] * RPM:.2f} -> "
          f"{f.channel_rmse['bit_speed_rad_s'] * RPM:.2f} RPM, torque {b.channel_rmse['torque_on_bit_nm']:.3f} -> "
          f"{f.channel_rmse['torque_on_bit_nm']:.3f} N m; law residual RMSE (validation) {_f(b.law_rmse_test)} -> "
          f"{_f(f.law_rmse_test)} N m.", ""]
    added = [s for s in res.steps if s.action == "add"]
    if added:
        L += ["### Physical reading", ""]
        for s in added:
            L.append(f"- **{s.effect}**: {reading(s.effect, s.after.model.effects[s.effect])}"
                     + (f" **Not told apart from a rival**: {s.evidence.confusable}."
                        if s.evidence.confusable else ""))
        L.append("")
    disc = res.discovery
    if disc.get("terms") is not None:
        L += ["### What the catalogue cannot name", "",
              f"The final model's residual of the bit's equation of motion, regressed on a library of terms "
              f"({disc.get('method', '')}): **unexplained: {100 * disc['unexplained_fraction']:.0f} % of the residual**"
              + (" (a residual of an equation that does not balance: not a model mismatch)." if disc.get("balanced") is False
                 else "."), ""]
        if disc.get("warning"):
            L += [f"**Warning**: {disc['warning']}.", ""]
        for t in disc["terms"]:
            ci = t.get("ci95") or [math.nan, math.nan]
            L.append(f"- `{t['name']}`: {t['coefficient']:.4g} {t['unit']} [{ci[0]:.3g}, {ci[1]:.3g}], explains "
                     f"{100 * t['explained_fraction']:.0f} %: {t['reading']}")
        L.append("")
    elif disc.get("skipped"):
        L += [f"Discovery step skipped: {disc['skipped']}.", ""]
    L += ["## Evidence per round", ""]
    for r, cands in enumerate(res.rounds, 1):
        L += [f"Round {r}:", "", "| candidate | E_val with it | gain | p | dBIC | explained | decision |",
              "|---|---:|---:|---:|---:|---:|---|"]
        for c in cands:
            if c.get("error_test_after") is None:
                L.append(f"| `{c['effect']}` | | | | | | {'; '.join(c['reasons'])} |")
                continue
            L.append(f"| `{c['effect']}` | {c['error_test_after']:.4f} | {100 * c['relative_gain']:+.1f} % | "
                     f"{c['p_value']:.2g} | {c['delta_bic']:.1f} | {c['explained_fraction']:.2f} | "
                     f"{'passes' if c['accepted'] else 'rejected: ' + '; '.join(c['reasons'])} |")
        L.append("")
    if res.rounds:
        L += [f"What each candidate of the last round fitted, and what it would mean on the rig (round "
              f"{len(res.rounds)}):", ""]
        for c in res.rounds[-1]:
            if c.get("parameters"):  # a candidate whose fit failed has none
                L.append(f"- `{c['effect']}` ({'passes' if c['accepted'] else 'rejected'}): "
                         f"{reading(c['effect'], values(c['parameters']))}")
        L.append("")
    L += ["Explained = (R.S)^2 / (|R|^2 |S|^2): the fraction of the calibration residual R (both channels, "
          "normalized) that the candidate's signature S (its change of the predictions) accounts for.", "",
          "## Parameters", "", "```json", dumps(f.model.parameters()), "```", "",
          "`model.json` holds the final model (`drillpy predict model.json RECORD` applies it to another record); "
          "`config.json` the same model as an engine configuration (`drillpy simulate --config config.json`), without "
          "the WOB coupling and the torque fluctuation, which need the record's WOB and past torque.", ""]
    L += ["## Figures", ""]
    for key, cap in (("signature", "Residual versus signature"), ("overlay", "Before/after predictions"),
                     ("loops", "Torque-speed loops (validation)"), ("errors", "Errors per step and candidate")):
        if key in files:
            L += [f"{cap}:", "", f"![{key}]({files[key]})", ""]
    if res.notes:
        L += ["## Notes", ""] + [f"- {n}" for n in res.notes] + [""]
    return "\n".join(L)


def write_loop(res: LoopResult, out, files: dict | None = None) -> dict:
    """Write the files of a loop run: ``loop.json``, ``evidence.json``, ``model.json``,
    ``config.json``, ``predictions.csv`` and ``report.md``.

    Parameters
    ----------
    res : LoopResult
        A finished loop run (:func:`drillpy.loop.run_loop`).
    out : str or Path
        Output folder (created if missing).
    files : dict, optional
        Figure key -> file (str or Path) of the figures written beside
        (:func:`drillpy.figures.loop.loop_figures`); the report links them.

    Returns
    -------
    dict
        The content of ``loop.json`` (:meth:`LoopResult.loop_json`).
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    js = res.loop_json()
    prov = provenance()
    write_text((out / "loop.json"), dumps({**js, "provenance": prov}))
    write_text((out / "evidence.json"), dumps({**evidence_json(res), "provenance": prov}))
    write_text((out / "model.json"), dumps(res.final.model.to_dict()))
    write_text((out / "config.json"), dumps(model_config(res)))
    write_predictions(out / "predictions.csv", res, prov)
    report = render_report(res, {k: Path(v).name for k, v in (files or {}).items()})
    write_text((out / "report.md"), with_markdown_footer(report, prov))
    return js


def loop_record(record, out_dir, *, preset: str | None = None, config_path: str | None = None,
                config: dict | None = None, options: LoopOptions | None = None, log=print,
                figure_units: str = "si") -> dict:
    """``drillpy loop``: run the loop and write its figures and files to ``out_dir``.

    :func:`drillpy.loop.run_loop` (compute: a :class:`~drillpy.loop.run.LoopResult`) -> :func:`drillpy.figures.loop.loop_figures`
    (residual_signature.png, overlay.png, loops.png, errors.png) -> :func:`write_loop`
    (``loop.json``, ``evidence.json``, ``predictions.csv``, ``model.json``, ``config.json``, ``report.md``).

    Parameters
    ----------
    record : Record, str or Path
        The measured record or its file.
    out_dir : str or Path
        Output folder (created if missing).
    preset, config_path, config : optional
        The declared model: a preset name, a configuration file or a configuration dict
        (:func:`drillpy.model.config.load_config`).
    options : LoopOptions, optional
        Choices of the loop (horizon [s], analysis rate [Hz], guard thresholds...).
    log : callable
        Called with each progress line.
    figure_units : str
        Axis unit of the figures' torques (``si``: N m; ``field``: ft-lbf); the files stay SI.

    Returns
    -------
    dict
        The content of ``loop.json``.
    """
    from drillpy.figures.loop import loop_figures
    cfg = load_config(preset=preset, path=config_path, config=config)
    res = run_loop(record, cfg, options, log=log)
    js = write_loop(res, out_dir, loop_figures(res, out_dir, figure_units))
    log(f"loop.json, predictions.csv, report.md and figures written to {Path(out_dir)}")
    return js
