"""The outputs of ``drillpy loop``: ``loop.json``, ``evidence.json``, ``predictions.csv``,
``model.json``, ``report.md`` and the figures (residual versus signature, before/after overlays,
torque-speed loops, errors per step).

Speeds are plotted in RPM, torques in N m, times in s; the residuals and signatures of the
signature figure are normalized by the channels' standard deviations (the metric's units).
"""
from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from drillpy.model.config import normalize
from .effects import CATALOGUE
from .data import measured
from .run import LoopResult, dumps
from drillpy.figures.simulation import _save, plt
from drillpy.records.io import RPM

C_MEAS, C_BASE, C_FINAL, C_SIG = "k", "tab:red", "tab:blue", "tab:orange"


# ---------------------------------------------------------------------------------- figures
def _signature_row(axs, res: LoopResult, before, after, name: str, accepted: bool):
    d = res.data
    Yv, YT = measured(d)
    rv, rT = (Yv - before.v) / d.sigma_v, (YT - before.T) / d.sigma_T
    sv, sT = (after.v - before.v) / d.sigma_v, (after.T - before.T) / d.sigma_T
    ax = axs[0]
    rng = np.random.default_rng(0)  # only thins the scatter for display
    for part, te, cols in (("calibration", ~d.is_test, ("0.75", "0.55")), ("validation", d.is_test, (C_FINAL, C_SIG))):
        for r, s, col, ch in ((rv[te], sv[te], cols[0], "bit speed"), (rT[te], sT[te], cols[1], "torque")):
            r, s = r.ravel(), s.ravel()
            k = rng.choice(r.size, min(r.size, 2500), replace=False)
            ax.scatter(s[k], r[k], s=3, color=col, alpha=0.4, lw=0, label=f"{ch}, {part}")
    lim = np.nanpercentile(np.abs(np.r_[rv.ravel(), rT.ravel()]), 99.5)
    ax.plot([-lim, lim], [-lim, lim], "k--", lw=0.8, label="residual = signature")
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_xlabel(f"signature of {name} (prediction change) [normalized]")
    ax.set_ylabel("residual before [normalized]")
    tr = ~d.is_test
    R, S = np.r_[rv[tr].ravel(), rT[tr].ravel()], np.r_[sv[tr].ravel(), sT[tr].ravel()]
    frac = float((R @ S) ** 2 / ((R @ R) * (S @ S))) if (S @ S) > 0 else 0.0
    ax.set_title(f"{name}: explains {100 * frac:.0f} % of the calibration residual "
                 f"({'added' if accepted else 'rejected'})", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=6, markerscale=3, loc="upper left")
    ax = axs[1]
    hs = d.horizon_samples
    te = np.flatnonzero(d.is_test)
    h0 = te[: max(1, int(round(2.0 / (d.L * d.dt))))]
    # the channel the signature moves most (normalized): bit speed [RPM] or torque [N m]
    torque = float(np.sum(sT[tr] ** 2)) > float(np.sum(sv[tr] ** 2))
    r_, s_, scale, what = (rT, sT, d.sigma_T, "torque on bit [N m]") if torque else (rv, sv, d.sigma_v * RPM,
                                                                                        "bit speed [RPM]")
    for j, h in enumerate(h0):
        t = d.t[hs[h]]
        ax.plot(t, r_[h] * scale, color=C_MEAS, lw=0.8, label="residual before" if j == 0 else None)
        ax.plot(t, s_[h] * scale, color=C_SIG, lw=0.8, label="signature (after - before)" if j == 0 else None)
        ax.axvline(d.t[d.starts[h]], color="0.8", lw=0.5)
    shown = np.abs(np.r_[r_[h0].ravel(), s_[h0].ravel()]) * scale
    top = 1.3 * np.percentile(shown, 99) if shown.size else 1.0
    ax.set_ylim(-top, top)  # the sharp torque drops at stick-slip transitions would flatten the rest
    ax.set_xlabel("time [s] (validation part; grey: restarts; clipped at 1.3 x the 99th percentile)")
    ax.set_ylabel(what)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)


def signature_figure(path, res: LoopResult) -> Path:
    """Residual versus signature for every step (and the best rejected candidate of the last
    round)."""
    rows = [(s["before"], s["candidate"], s["effect"], True) for s in res.steps]
    last = res.last_round
    if last:
        name, ev = min(last.items(), key=lambda kv: kv[1].E_test)
        rows.append((res.final, ev, name, False))
    if not rows:
        rows = [(res.final, res.final, "(no candidate)", False)]
    fig, axes = plt.subplots(len(rows), 2, figsize=(12, 4.2 * len(rows)), squeeze=False)
    for axs, (b, a, n, ok) in zip(axes, rows):
        _signature_row(axs, res, b, a, n, ok)
    return _save(fig, path)


def _window(res: LoopResult, seconds: float = 2.5) -> np.ndarray:
    d = res.data
    te = np.flatnonzero(d.is_test)
    return te[: max(1, int(round(seconds / (d.L * d.dt))))]


def overlay_figure(path, res: LoopResult) -> Path:
    """Measured, baseline and final predictions of bit speed and torque on a window of the
    validation part, and the per-horizon error over the whole record."""
    d = res.data
    hs = d.horizon_samples
    fig, axes = plt.subplots(3, 1, figsize=(12, 9))
    w = _window(res)
    t0, t1 = d.t[d.starts[w[0]]], d.t[hs[w[-1]][-1]]
    sel = (d.t >= t0) & (d.t <= t1)
    for ax, meas, key, scale, unit in ((axes[0], d.v_meas, "v", RPM, "bit speed [RPM]"),
                                       (axes[1], d.T_meas, "T", 1.0, "torque on bit [N m]")):
        ax.plot(d.t[sel], meas[sel] * scale, color=C_MEAS, lw=1.2, label="measured")
        for j, h in enumerate(w):
            t = d.t[hs[h]]
            ax.plot(t, getattr(res.baseline, key)[h] * scale, color=C_BASE, lw=1,
                    label=("baseline (declared model, calibrated)" if res.steps else
                           "declared model, calibrated (no effect added: final = baseline)") if j == 0 else None)
            if res.steps:
                ax.plot(t, getattr(res.final, key)[h] * scale, color=C_FINAL, lw=1,
                        label="final (+ " + ", ".join(s["effect"] for s in res.steps) + ")" if j == 0 else None)
            ax.axvline(d.t[d.starts[h]], color="0.85", lw=0.6)
        ax.set_ylabel(unit)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper right")
    axes[1].set_xlabel(f"time [s] (validation part; grey lines: restarts from the measured state every "
                       f"{res.options.horizon_s:g} s)")
    ax = axes[2]
    ts = d.t[d.starts]
    ax.semilogy(ts, np.sqrt(res.baseline.e_h), ".", color=C_BASE, ms=4, label="baseline")
    if res.steps:
        ax.semilogy(ts, np.sqrt(res.final.e_h), ".", color=C_FINAL, ms=4, label="final")
    ax.axvline(d.t_split, color="k", ls="--", lw=1, label="calibration | validation")
    ax.set_xlabel("horizon start [s]")
    ax.set_ylabel("horizon error sqrt(e_h) [-]")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    axes[0].set_title(f"Short-horizon predictions: validation error E {res.baseline.E_test:.3f} (baseline) -> "
                      f"{res.final.E_test:.3f} (final)")
    return _save(fig, path)


def loops_figure(path, res: LoopResult) -> Path:
    """Torque on bit versus bit speed on the validation part: measured, baseline, final."""
    d = res.data
    te = d.is_test
    Yv, YT = measured(d)
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.2), sharex=True, sharey=True)
    for ax, (v, T, lab, col) in zip(axes, ((Yv, YT, "measured", C_MEAS), (res.baseline.v, res.baseline.T, "baseline", C_BASE),
                                           (res.final.v, res.final.T, "final", C_FINAL))):
        for h in np.flatnonzero(te):
            ax.plot(v[h] * RPM, T[h], color=col, lw=0.4, alpha=0.5)
        ax.set_title(f"{lab} (validation horizons)", fontsize=10)
        ax.set_xlabel("bit speed [RPM]")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("torque on bit [N m]")
    return _save(fig, path)


def errors_figure(path, res: LoopResult) -> Path:
    """Validation and calibration error after each step, and every candidate of every round."""
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.2))
    ev = [res.baseline] + [s["after"] for s in res.steps]
    labels = ["baseline"] + [f"+ {s['effect']}" for s in res.steps]
    x = np.arange(len(ev))
    ax = axes[0]
    ax.bar(x - 0.2, [e.E_train for e in ev], 0.4, color="0.6", label="calibration part")
    ax.bar(x + 0.2, [e.E_test for e in ev], 0.4, color=C_FINAL, label="validation part")
    ax.set_xticks(x, labels, rotation=20, fontsize=8)
    ax.set_xlim(-1.0, max(len(ev), 2))
    ax.set_ylabel("normalized prediction error E [-]")
    ax.grid(alpha=0.3, axis="y")
    ax.legend(fontsize=8)
    ax = axes[1]
    names = list(CATALOGUE)
    for r, cands in enumerate(res.rounds):
        for c in cands:
            if c.get("error_test_after") is None:
                continue
            y = names.index(c["effect"])
            ax.plot(c["error_test_after"], y + 0.12 * (r - len(res.rounds) / 2), "o" if c["accepted"] else "x",
                    color=f"C{r}", ms=6, label=f"round {r + 1}" if c is cands[0] else None)
        cur = cands[0].get("error_test_before") if cands else None
        if cur is not None:
            ax.axvline(cur, color=f"C{r}", ls=":", lw=1)
    ax.set_yticks(range(len(names)), names, fontsize=8)
    ax.set_xlabel("validation error E with the candidate [-]")
    ax.set_title("candidates per round (o: passes the guard, x: rejected; dotted: current model)", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    return _save(fig, path)


# ---------------------------------------------------------------------------------- files
def write_predictions(path, res: LoopResult) -> Path:
    """predictions.csv: every sample of the analysis grid (header row first, numbers only; empty
    cells where no horizon covers a sample or the record has no top speed): time, the recorded bit
    speed, torque on bit and top speed, whether the recorded top speed is a measurement (1; 0: an
    artifact the cleaning filled, left out of E), the baseline's and the final model's predictions
    of the three, whether the sample is in the validation part (1) or the calibration part (0), and
    the index of the horizon that predicts it."""
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

    with open(path, "w", newline="") as fh:
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
    d = res.data

    def ev_summary(e):
        return {"error_calibration": e.E_train, "error_validation": e.E_test, "validation_rmse": e.channel_rmse,
                "law_rmse_calibration_nm": e.law_rmse_train, "law_rmse_validation_nm": e.law_rmse_test,
                "parameters": e.model.parameters(), "k": e.model.k}

    return {"metric": res.metric(),
            "record": {"source": d.source, "samples": int(d.t.size), "sample_rate_hz": 1.0 / d.dt,
                       "record_rate_hz": d.record_rate_hz, "decimation": d.decimation,
                       "span_s": [float(d.t[0]), float(d.t[-1])], "calibration_s": [float(d.t[0]), d.t_split],
                       "validation_s": [d.t_split, float(d.t[-1])], "cleaning": d.cleaning,
                       "stick_threshold_rad_s": d.stick_threshold, "sd_bit_speed_rad_s": d.sigma_v,
                       "sd_torque_nm": d.sigma_T, "horizon_s": d.L * d.dt,
                       "calibration_horizons": int((~d.is_test).sum()), "validation_horizons": int(d.is_test.sum())},
            "options": {k: (list(v) if isinstance(v, tuple) else v) for k, v in vars(res.options).items()},
            "engine_dt_s": res.config["simulation"]["dt_s"],
            "baseline": ev_summary(res.baseline), "final": ev_summary(res.final),
            "adequacy": res.adequacy, "declared": res.declared, "baseline_long_run": res.baseline_long_run,
            "steps": [{k: s[k] for k in ("action", "effect", "error_before", "error_after", "evidence", "long_run")}
                      for s in res.steps],
            "rounds": res.rounds, "discovery": res.discovery, "notes": res.notes}


def model_config(res: LoopResult) -> dict:
    """The final model as an engine configuration (drillpy simulate / drillsim can run it)."""
    c = res.final.model.engine_config()
    c["name"] = f"{c.get('name', 'model')}-loop"
    c["description"] = ("calibrated by drillpy loop on " + Path(res.data.source).name + "; effects: "
                        + (", ".join(res.final.model.effects) or "none"))
    return normalize(c)


# ---------------------------------------------------------------------------------- report
def _f(x, fmt=".4f"):
    return "n/a" if x is None or (isinstance(x, float) and not math.isfinite(x)) else format(x, fmt)


def _damping(d: dict) -> str:
    if d.get("type") == "modal":
        return "modal damping ratios " + ", ".join(f"{r:g}" for r in d["ratios"])
    return "Rayleigh damping " + ", ".join(f"{z:g} at {f:g} Hz" for f, z in d["pairs"])


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
    """Physical reading of an effect found, with its fitted parameters."""
    e = CATALOGUE[name]
    if name == "top_drive_dynamics":
        if p.get("variant") == "motor":
            c = 1.0 / p["droop_rad_s_per_nm"]
            txt = (f"the top drive gives way: a motor with droop {p['droop_rad_s_per_nm'] * RPM:.3g} RPM per N m "
                   f"(c_m = {c:.3g} N m s/rad), inertia {p['inertia_kg_m2']:.3g} kg m^2 (time constant "
                   f"{p['inertia_kg_m2'] / c:.3g} s), no-load speed {p['command_rad_s'] * RPM:.1f} RPM, stall torque "
                   f"{c * p['command_rad_s']:.2f} N m")
        else:
            txt = "the top follows the measured top speed (kinematic drive) better than any constant"
    elif name == "sensor_lag":
        fc = p["lowpass_hz"]
        txt = (f"the recorded channels went through a low-pass at {fc:.3g} Hz (group delay "
               f"{1e3 * math.sqrt(2) / (2 * math.pi * fc):.1f} ms)")
    elif name == "wob_coupling":
        txt = f"the torque follows the WOB with gain k = {p['gain']:.3g} (k = 1: proportional)"
    elif name == "bit_hysteresis":
        txt = f"H = {p['beta1']:.3g} tanh({p['beta2']:.3g} a) sign(v) on the speed-dependent torque"
    elif name == "torque_fluctuation":
        txt = (f"a torque fluctuation of standard deviation {p.get('std', float('nan')):.3g} that persists over "
               f"tau = {p['tau_s']:.3g} s")
    else:
        txt = "; ".join(f"{q.meaning}: {p[q.name]:.4g} {q.unit}" for q in e.params if q.name in p)
    return f"{txt}. On the rig: {e.reading}."


def values(params: dict) -> dict:
    """Parameter values from a step's evidence (entries with intervals) or a model's effects."""
    return {k: (v["value"] if isinstance(v, dict) and "value" in v else v) for k, v in params.items()}


def render_report(res: LoopResult, files: dict) -> str:
    d, b, f = res.data, res.baseline, res.final
    o = res.options
    L = [f"# drillpy loop: `{Path(d.source).name}`", "",
         f"Declared model `{res.config.get('name')}` ({res.config['rom']['modes']} mode(s), law "
         f"`{res.config['law']['type']}`, {_damping(res.config['damping'])}), calibrated on the record, then "
         f"extended by the effects of the catalogue the evidence supports.", "",
         "## Data", "",
         f"- {d.t.size} samples at {1 / d.dt:g} Hz (record {d.record_rate_hz:g} Hz, decimated by {d.decimation}), "
         f"{d.t[0]:.3f}-{d.t[-1]:.3f} s; cleaning: {'; '.join(d.cleaning)}.",
         f"- **calibration part** t < {d.t_split:.3f} s ({int((~d.is_test).sum())} horizons), **validation part** "
         f"t >= {d.t_split:.3f} s ({int(d.is_test.sum())} horizons), horizons of {o.horizon_s:g} s. Nothing is fitted "
         "on the validation part; the errors reported are the validation part's.",
         f"- engine step {res.config['simulation']['dt_s']:.3g} s (modified Euler); derivatives by Savitzky-Golay "
         f"filters of {o.derivative_window_s:g} s (order 4).", ""]
    L += ["## Metrics", "",
          "- **Law residual**: r_law = T - T_model(v, a, W) on the slip samples (bit speed above "
          f"{d.stick_threshold * RPM:.2f} RPM, every {max(1, int(round(0.01 / d.dt)))}th sample), the model's law "
          "evaluated on the measured bit speed v, acceleration a and the law's WOB input W; reported as its RMSE [N m].",
          "- **Dynamic residual**: every horizon the model restarts from the state that reproduces the measured bit "
          "speed, bit acceleration, torque on bit and top speed (exact for one mode) and is integrated by the engine "
          "over the horizon, driven by the inputs it takes from the record; residual = measured - predicted bit speed "
          "and torque on bit.",
          f"- **Error E** (loop.json `metric`): E = sqrt( 1/2 [ mean (v_pred - v)^2 / sd_v^2 + mean (T_pred - T)^2 / "
          f"sd_T^2 ] ) over all samples of the part's horizons; sd_v = {d.sigma_v:.4g} rad/s "
          f"({d.sigma_v * RPM:.3g} RPM), sd_T = {d.sigma_T:.4g} N m (calibration part, fixed). E = 1: as far off as "
          "the channels' own spread.",
          f"- **Guard** (an effect is added only if all hold): validation gain >= {100 * o.min_gain:g} %; one-sided "
          f"t-test of the per-horizon log error ratio over the validation horizons (effective number from their "
          f"autocorrelation) with p < {o.alpha:g} / (candidates in the round) (Bonferroni); BIC on the calibration "
          f"part lower by more than {o.min_delta_bic:g} (n_eff = residual samples / autocorrelation time). Among the "
          "candidates that pass, the one with the lowest validation error is added and the model is refitted.", ""]
    a = res.adequacy
    L += ["## Baseline", "",
          f"- declared effects: {', '.join(res.declared) or 'none'}; calibrated modal damping ratios "
          f"{b.model.damping_ratios}.",
          f"- validation error E = {b.E_test:.4f}; trivial predictors: channel means {a['mean_predictor_error']:.4f}, "
          f"value held from the restart {a['hold_last_predictor_error']:.4f} -> "
          + ("**adequate** (better than both)." if a["adequate"] else
             "**not adequate**: the declared model predicts no better than a trivial predictor; nothing is attributed."),
          f"- long run (the model simulated over the record): measured {_lr(res.baseline_long_run.get('measured'))}; "
          f"model {_lr(res.baseline_long_run.get('model'))}.", ""]
    L += ["## Result", "",
          "| step | action | effect | E before | E after | gain | p | dBIC | parameters [95 %] | long run after |",
          "|---|---|---|---:|---:|---:|---:|---:|---|---|"]
    for k, s in enumerate(res.steps, 1):
        e = s["evidence"]
        L.append(f"| {k} | {s['action']} | `{s['effect']}` | {s['error_before']:.4f} | {s['error_after']:.4f} | "
                 f"{100 * (1 - s['error_after'] / s['error_before']):.1f} % | {e['p_value']:.2g} | {e['delta_bic']:.1f} | "
                 f"{_params(e.get('parameters', {}))} | {_lr((s.get('long_run') or {}).get('after'))} |")
    if not res.steps:
        L.append("| - | | (none: no candidate beats the null candidate) | | | | | | | |")
    L += ["", f"Validation error **{b.E_test:.4f} -> {f.E_test:.4f}** (calibration {b.E_train:.4f} -> {f.E_train:.4f}); "
          f"validation RMSE bit speed {b.channel_rmse['bit_speed_rad_s'] * RPM:.2f} -> "
          f"{f.channel_rmse['bit_speed_rad_s'] * RPM:.2f} RPM, torque {b.channel_rmse['torque_on_bit_nm']:.3f} -> "
          f"{f.channel_rmse['torque_on_bit_nm']:.3f} N m; law residual RMSE (validation) {_f(b.law_rmse_test)} -> "
          f"{_f(f.law_rmse_test)} N m.", ""]
    added = [s for s in res.steps if s["action"] == "add"]
    if added:
        L += ["### Physical reading", ""]
        for s in added:
            L.append(f"- **{s['effect']}**: {reading(s['effect'], s['after'].model.effects[s['effect']])}")
        L.append("")
    disc = res.discovery
    if disc.get("terms") is not None:
        L += ["### What the catalogue cannot name", "",
              f"The final model's residual of the bit's equation of motion, regressed on a library of terms "
              f"({disc.get('method', '')}): **unexplained: {100 * disc['unexplained_fraction']:.0f} % of the residual**.", ""]
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


def write_outputs(res: LoopResult, out: Path) -> dict:
    out = Path(out)
    js = res.loop_json()
    (out / "loop.json").write_text(dumps(js))
    (out / "evidence.json").write_text(dumps(evidence_json(res)))
    (out / "model.json").write_text(dumps(res.final.model.to_dict()))
    (out / "config.json").write_text(dumps(model_config(res)))
    write_predictions(out / "predictions.csv", res)
    files = {"signature": signature_figure(out / "residual_signature.png", res).name,
             "overlay": overlay_figure(out / "overlay.png", res).name,
             "loops": loops_figure(out / "loops.png", res).name,
             "errors": errors_figure(out / "errors.png", res).name}
    (out / "report.md").write_text(render_report(res, files))
    return js
