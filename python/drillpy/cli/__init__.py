"""The ``drillpy`` command.

  drillpy report   --preset thesis-field --out DIR      main job: frequencies, SS sweep, maps
  drillpy modes    --preset thesis-field --elements 100 -n 5 --json
  drillpy simulate --preset thesis-field --top-speed 16 --out DIR
  drillpy sweep    --preset thesis-field --law hysteretic --beta1 0.14 --speeds 6:27:22 --json
  drillpy map      --preset thesis-field --beta1 0.56 --speeds-rpm 50:160:23 --wobs-kn 22:267:12
  drillpy convergence --preset thesis-field            FE and time-step convergence orders
  drillpy analyze  ../shared/data/testrig/sample175_0-40s.mat --out DIR   measured record: report
  drillpy analyze  REC1 REC2 ... (or a folder, or REC@T0:T1) --out DIR   section 5.3 across samples
  drillpy frf      --preset thesis-ch6 --model SM_CB2 --case 4 --samples 2500 --json
  drillpy frf-report --preset thesis-ch6 --out DIR          chapter 6 and appendix C figures
  drillpy robust-ss --preset thesis-ch6 --samples 40 --speeds 6:27:8 --out DIR
  drillpy mc       --preset thesis-field --samples 500 --speeds 6:27:22 --seed 1 --json
  drillpy loop     RECORD --preset thesis-rig --out DIR      residual -> missing effect -> corrected model
  drillpy predict  MODEL.json RECORD --out DIR --json       a calibrated rig model on a record it never saw

Every error prints one line ``drillpy: error: ...`` and exits with status 2.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from drillpy.model.config import load_config, with_overrides


def parse_grid(text: str, name: str) -> np.ndarray:
    """'start:stop:num' (inclusive linspace) or a comma-separated list."""
    try:
        if ":" in text:
            a, b, n = text.split(":")
            n = int(n)
            if n < 1:
                raise ValueError
            return np.linspace(float(a), float(b), n)
        vals = [float(x) for x in text.split(",") if x.strip()]
        if not vals:
            raise ValueError
        return np.asarray(vals)
    except ValueError:
        raise ValueError(f"{name} = {text!r}: use start:stop:num or a comma-separated list") from None


def _model_args(p: argparse.ArgumentParser) -> None:
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--preset", help="built-in configuration (thesis-field, thesis-ch4, thesis-rig, thesis-ch6)")
    src.add_argument("--config", help="JSON configuration file")
    p.add_argument("--elements", type=int, help="total elements, split in proportion to section lengths")
    p.add_argument("--modes", type=int, help="elastic modes kept in the reduced-order model")
    p.add_argument("--law", choices=["hysteretic", "tucker_wang"], help="thesis bit-rock law parameter set")
    p.add_argument("--beta1", type=float, help="hysteresis amplitude of Eq. (3.3)")
    p.add_argument("--speed-unit", choices=["rad_s", "rpm"], help="speed unit of the law parameters")
    p.add_argument("--scheme", choices=["modified_euler", "bdf2"], help="time integration scheme")
    p.add_argument("--acceleration", choices=["implicit", "lagged"],
                   help="bit acceleration in Eq. (3.3): the step's own (implicit, default) or the last "
                        "step's backward difference (lagged, modified Euler only)")
    p.add_argument("--dt", type=float, help="time step [s]")
    p.add_argument("--duration", type=float, help="simulated time [s]")
    p.add_argument("--transient", type=float, help="time discarded before metrics [s]")
    p.add_argument("--threads", type=int, default=0, help="OpenMP threads (0: default)")
    p.add_argument("--start", choices=["rest", "rigid", "steady"], default="rest",
                   help="initial state: bit at rest (Eq. 2.10), string turning rigidly with the top "
                        "(Eq. 2.3) or steady drilling")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")


def _config(a) -> dict:
    base = load_config(preset=a.preset) if a.preset else load_config(path=a.config)
    return with_overrides(base, elements=a.elements, modes=a.modes, law=a.law, beta1=a.beta1,
                          speed_unit=a.speed_unit, scheme=a.scheme, acceleration=a.acceleration, dt=a.dt,
                          duration=a.duration, transient=a.transient)


def cmd_modes(a) -> int:
    from drillpy.model.simulation import natural_frequencies
    f = natural_frequencies(_config(a), a.n)
    if a.json:
        print(json.dumps({"frequencies_hz": [float(x) for x in f]}))
    else:
        for k, x in enumerate(f, 1):
            print(f"mode {k}: {x:.4f} Hz")
    return 0


def cmd_simulate(a) -> int:
    from drillpy.figures import simulation as plotting
    from drillpy.model.simulation import simulate
    cfg = _config(a)
    r = simulate(cfg, a.top_speed, None if a.wob_kn is None else a.wob_kn * 1e3, start=a.start)
    summary = r.summary()  # drill/run_summary.hpp: the keys drillsim writes
    if a.out:
        out = Path(a.out)
        out.mkdir(parents=True, exist_ok=True)
        cols = np.column_stack([r.t, r.bit_speed, r.bit_accel, r.bit_angle, r.torque_on_bit,
                                r.top_torque, r.top_speed])
        np.savetxt(out / "series.csv", cols, delimiter=",", comments="",
                   header="time_s,bit_speed_rad_s,bit_accel_rad_s2,bit_angle_rad,torque_on_bit_Nm,"
                          "top_torque_Nm,top_speed_rad_s")
        plotting.time_series(out / "time_series.png", r.t, r.bit_speed, r.torque_on_bit, r.top_speed)
        (out / "summary.json").write_text(json.dumps({**summary, "config": r.config}, indent=2))
    print(json.dumps(summary) if a.json else
          f"SS = {r.severity:.3f}, stick fraction = {r.stick_fraction:.3f}, "
          f"periodic over {r.period_cycles} cycle(s)")
    return 0


def cmd_sweep(a) -> int:
    from drillpy.figures import simulation as plotting
    from drillpy.model.simulation import severity_threshold, sweep_severity
    cfg = _config(a)
    speeds = parse_grid(a.speeds, "--speeds")
    ss = sweep_severity(cfg, speeds, progress=not a.no_progress, threads=a.threads, start=a.start)
    thr = severity_threshold(speeds, ss)
    res = {"top_speeds_rad_s": speeds.tolist(), "severity": ss.tolist(), "threshold_rad_s": thr}
    if a.refine is not None and thr is not None:
        from drillpy.model.simulation import refine_threshold
        r = refine_threshold(cfg, speeds, ss, tol=a.refine, threads=a.threads, start=a.start)
        thr = r.threshold
        res.update(threshold_rad_s=r.threshold, threshold_precision_rad_s=r.precision,
                   threshold_bracket_rad_s=[r.below, r.above], refinement_runs=[list(e) for e in r.evaluations])
    if a.out:
        out = Path(a.out)
        out.mkdir(parents=True, exist_ok=True)
        plotting.severity_curve(out / "severity_vs_top_speed.png", speeds, ss, thr)
        (out / "sweep.json").write_text(json.dumps({**res, "config": cfg}, indent=2))
    if a.json:
        print(json.dumps(res))
    else:
        for s, v in zip(speeds, ss):
            print(f"{s:8.3f} rad/s  SS = {v:.3f}")
        print("SS > 0.5 below", "no crossing in range" if thr is None else
              f"{thr:.3f} +- {res['threshold_precision_rad_s']:.3f} rad/s (bisection)" if "threshold_precision_rad_s" in res
              else f"{thr:.2f} rad/s (linear interpolation on the grid)")
    return 0


def cmd_map(a) -> int:
    from drillpy.figures import simulation as plotting
    from drillpy.model.simulation import stability_map
    cfg = _config(a)
    sp = parse_grid(a.speeds_rpm, "--speeds-rpm")
    w = parse_grid(a.wobs_kn, "--wobs-kn")
    m = stability_map(cfg, sp * np.pi / 30.0, w * 1e3, progress=not a.no_progress, threads=a.threads,
                      start=a.start)
    res = {"top_speeds_rpm": sp.tolist(), "wobs_kn": w.tolist(), "severity": m.tolist()}
    if a.out:
        out = Path(a.out)
        out.mkdir(parents=True, exist_ok=True)
        plotting.stability_maps(out / "stability_map.png", sp, w, {cfg["law"]["type"]: m})
        (out / "map.json").write_text(json.dumps({**res, "config": cfg}, indent=2))
    print(json.dumps(res) if a.json else f"stable fraction (SS < 0.5): {np.mean(m < 0.5):.3f}")
    return 0


def cmd_report(a) -> int:
    from drillpy.reports.preset import field_report, print_field_summary
    s = field_report(_config(a), a.out, progress=not a.no_progress, threads=a.threads)
    if a.json:
        print(json.dumps({k: v for k, v in s.items() if k != "config"}))
    else:
        print_field_summary(s)
        print(f"figures and summary.json written to {a.out}")
    return 0


def cmd_convergence(a) -> int:
    from drillpy.model.convergence import convergence_report
    r = convergence_report(_config(a))
    if a.json:
        print(json.dumps(r))
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


def cmd_analyze(a) -> int:
    from drillpy.records.samples import Acceptance, SampleOptions, analyze_samples, find_records
    log = (lambda *_: None) if a.json else print
    items = find_records(a.record)
    if len(items) == 1:  # one record (or one window of it): the single-record analysis
        from drillpy.reports.analysis import AnalysisOptions, _jsonable, analyze_record
        t0, t1 = items[0][2] or (a.t0, a.t1)
        cal = None if a.calibrate is None else tuple(parse_grid(a.calibrate.replace(":", ","), "--calibrate"))
        if cal is not None and len(cal) != 2:
            raise ValueError(f"--calibrate = {a.calibrate!r}: use T0:T1 [s]")
        opt = AnalysisOptions(t0=t0, t1=t1, cycle_at_s=a.cycle_at, folds=5 if a.folds is None else a.folds,
                              psd_fmax_hz=a.psd_fmax, simulate=not a.no_sim, calibrate=cal)
        s = analyze_record(items[0][1], a.out, opt, log=log)
        if a.json:
            keys = ("cleaning", "cycles", "severity", "torque_statistics", "psd", "identification", "rig")
            print(json.dumps(_jsonable({k: s[k] for k in keys if k in s}), default=str, allow_nan=False))
        return 0
    # two or more samples (files, a folder, FILE@T0:T1 windows): section 5.3 across samples
    acc = Acceptance(max_var_mse={"tucker_wang": a.max_var_mse_regularized,
                                  "polynomial": a.max_var_mse_non_regularized},
                     cv_reference=a.cv_reference, concrete_variation=a.concrete_variation,
                     require_cv=a.require_cv)
    opt = SampleOptions(t0=a.t0, t1=a.t1, folds=0 if a.folds is None else a.folds, acceptance=acc)
    s = analyze_samples([p if w is None else f"{p}@{w[0]!r}:{w[1]!r}" for _, p, w in items], a.out, opt, log=log)
    if a.json:
        from drillpy.reports.analysis import _jsonable
        print(json.dumps(_jsonable({k: s[k] for k in ("n_samples", "laws", "table_5_2", "across_samples",
                                                      "acceptance", "parameters")}), allow_nan=False))
    return 0


def cmd_predict(a) -> int:
    from drillpy.records.prediction import describe, load_model, predict_record, write_prediction
    model = load_model(a.model)
    pred = predict_record(model, a.record, t0=a.t0, t1=a.t1, horizon_s=a.horizon, threads=a.threads)
    if a.out:
        write_prediction(pred, a.out)
    s = pred.summary()
    if a.json:
        print(json.dumps({k: s[k] for k in ("short_horizon_error", "long_run")}, allow_nan=False))
    else:
        lr = s["long_run"]
        print(f"{describe(model)} at the record's operating point; short-horizon error E = {s['short_horizon_error']:.3f}")
        for k in ("ss", "stick_fraction", "cycle_frequency_hz"):
            print(f"  {k}: measured {lr[k]['measured']:.3f}, predicted {lr[k]['predicted']:.3f} "
                  f"({100 * lr[k]['relative_error']:+.1f} %)")
        tq = lr["torque_p05_p95_nm"]
        print(f"  torque p5-p95 [N m]: measured {tq['measured'][0]:.2f}-{tq['measured'][1]:.2f}, predicted "
              f"{tq['predicted'][0]:.2f}-{tq['predicted'][1]:.2f}")
    return 0


def _uncertainty_args(p: argparse.ArgumentParser, samples: int, out: str) -> None:
    _model_args(p)
    p.add_argument("--cb-modes", help="fixed-interface modes per substructure, e.g. 25,25")
    p.add_argument("--samples", type=int, default=samples, help="Monte Carlo samples")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--out", help=out)
    p.add_argument("--json", action="store_true")


def _cb_config(a) -> dict:
    cfg = _config(a)
    if a.cb_modes:
        from drillpy.uncertainty.frf import with_cb_modes
        cfg = with_cb_modes(cfg, [int(x) for x in parse_grid(a.cb_modes, "--cb-modes")])
    return cfg


def cmd_frf(a) -> int:
    from drillpy.figures import frf as frf_plots
    from drillpy.uncertainty.frf import band_widths, frf_envelope
    from drillpy.reports.uncertainty import BANDS_HZ
    cfg = _cb_config(a)
    env = frf_envelope(cfg, a.model, a.delta, a.case, samples=a.samples, seed=a.seed,
                       freq_hz=parse_grid(a.freqs, "--freqs"), probability=a.probability,
                       progress=not a.no_progress, threads=a.threads)
    res = {**env.to_json(), "case": a.case}
    bands = {b: r for b, r in BANDS_HZ.items() if np.sum((env.freq_hz >= r[0]) & (env.freq_hz <= r[1])) >= 2}
    if a.out:
        out = Path(a.out)
        out.mkdir(parents=True, exist_ok=True)
        title = a.model + (f" case {a.case}" if a.case else f" delta {a.delta if a.delta is not None else 0.1}")
        for p, label in enumerate(env.labels):
            frf_plots.envelope_figure(out / f"frf_point{p + 1}.png", {title: env}, p, f"{title}: {label}")
        (out / "envelope.json").write_text(json.dumps({**res, "config": cfg}))
    if a.json:
        print(json.dumps(res))
    else:
        print(f"{a.model}, {env.samples} samples, {int(round(100 * env.probability))} % envelope; "
              "mean width [dB] per band:")
        for band, w in zip(bands, band_widths(env, list(bands.values()))):
            print(f"  {band:24s} " + "  ".join(f"{lab.split(' ')[0]} {x:6.2f}" for lab, x in zip(env.labels, w)))
    return 0


def cmd_frf_report(a) -> int:
    from drillpy.reports.uncertainty import chapter6_report, print_conclusions
    s = chapter6_report(_cb_config(a), a.out, samples=a.samples, mode_samples=a.mode_samples, seed=a.seed,
                        progress=not a.no_progress, threads=a.threads)
    if a.json:
        print(json.dumps(s))
    else:
        print_conclusions(s["conclusions"])
        print(f"figures and summary.json written to {a.out}")
    return 0


def cmd_robust_ss(a) -> int:
    from drillpy.figures import frf as frf_plots
    from drillpy.uncertainty.process import THESIS_PSD
    from drillpy.uncertainty.structural import severity_sources, severity_study
    cfg = _cb_config(a)
    if a.bit_rock and a.eta_npy:
        raise ValueError("--bit-rock and --eta-npy: give one source of eta")
    speeds = parse_grid(a.speeds, "--speeds")
    kw = dict(seed=a.seed, progress=not a.no_progress, threads=a.threads)
    studies = severity_sources(cfg, speeds, a.samples, delta=a.delta, eta_psd=THESIS_PSD if a.bit_rock else None,
                               eta_dt=a.eta_dt, **kw)
    if a.eta_npy:
        eta = np.load(a.eta_npy)
        studies["bit-rock (eta)"] = severity_study(cfg, speeds, a.samples, delta=0.0, structural=False, eta=eta,
                                                   eta_dt=a.eta_dt, label="bit-rock (eta)", **kw)
        studies["structure + bit-rock"] = severity_study(cfg, speeds, a.samples, delta=a.delta, eta=eta,
                                                         eta_dt=a.eta_dt, label="structure + bit-rock", **kw)
    res = {label: st.to_json() for label, st in studies.items()}
    for label, st in studies.items():
        if st.ss.shape[0] < 2:
            continue
        kw_st = dict(delta=a.delta, seed=a.seed, progress=False, threads=a.threads, eta_dt=a.eta_dt, label=label,
                     structural=label != "bit-rock (eta)")
        if "bit-rock" in label:
            kw_st["eta_psd" if a.bit_rock else "eta"] = THESIS_PSD if a.bit_rock else np.load(a.eta_npy)
            if label == "bit-rock (eta)":
                kw_st["delta"] = 0.0
        res[label].update(_robust_speed(st.ss, st.speeds, a.refine, a.seed,
                                        lambda sp, kw_st=kw_st: severity_study(cfg, sp, st.ss.shape[0], **kw_st).ss))
    if a.out:
        out = Path(a.out)
        out.mkdir(parents=True, exist_ok=True)
        frf_plots.severity_bands_figure(out / "severity_bands.png", speeds, studies)
        (out / "robust_ss.json").write_text(json.dumps({**res, "config": cfg}, indent=2))
    if a.json:
        print(json.dumps(res))
    else:
        for label, st in studies.items():
            print(f"{label}:")
            for v, m, lo, hi, p in zip(speeds, st.mean, st.q05, st.q95, st.p_stick_slip):
                print(f"  {v:7.2f} rad/s  SS mean {m:.3f}  5-95 % [{lo:.3f}, {hi:.3f}]  P(SS > 0.5) {p:.2f}")
            p05 = res[label].get("p05_speed_rad_s")
            print("  P(SS > 0.5) <= 5 % from", "no crossing in range" if p05 is None else f"{p05:.2f} rad/s",
                  _robust_speed_text(res[label]))
    return 0


def _int_arg(text: str, name: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise ValueError(f"{name} = {text!r}: must be an integer") from None


def _psd_arg(a):
    from drillpy.uncertainty.process import PSD_CONVENTIONS, THESIS_PSD, PsdModel, PsdTable, convert_psd_model
    if a.psd_table:
        p = Path(a.psd_table)
        if not p.is_file():
            raise ValueError(f"--psd-table = {str(p)!r}: no such file")
        try:
            data = np.loadtxt(p, delimiter=",", ndmin=2, comments="#")
        except ValueError as e:
            raise ValueError(f"--psd-table = {str(p)!r}: {e}") from None
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
    return model


def cmd_mc(a) -> int:
    from drillpy.uncertainty import montecarlo as mcm
    from drillpy.reports.stochastic import write_figures
    cfg = _config(a)
    speeds = parse_grid(a.speeds, "--speeds")
    study = mcm.stochastic_study(
        cfg, speeds, _int_arg(a.samples, "samples"), _int_arg(a.seed, "seed"), psd=_psd_arg(a),
        eta_dt=a.eta_dt, warmup=mcm.WARMUP_S if a.warmup is None else a.warmup,
        duration=mcm.DURATION_S if a.duration is None else a.duration,
        transient=mcm.TRANSIENT_S if a.transient is None else a.transient,
        first_sample=_int_arg(a.first_sample, "first_sample"), threads=a.threads,
        progress=not a.no_progress)
    res = study.summary()
    res.update(_robust_speed(study.severity, study.speeds, a.refine, study.seed, lambda sp: mcm.stochastic_study(
        cfg, sp, study.severity.shape[0], study.seed, psd=_psd_arg(a), eta_dt=a.eta_dt,
        first_sample=study.first_sample, deterministic=False, threads=a.threads, progress=False,
        **{k: study.settings[k + "_s"] for k in ("warmup", "duration", "transient")}).severity))
    if a.out:
        res["figures"] = write_figures(study, cfg, a.out, psd=_psd_arg(a), eta_dt=a.eta_dt,
                                       threads=a.threads, progress=not a.no_progress)
    if a.json:
        print(json.dumps(res))
    else:
        print(f"{res['samples']} samples, eta std {res['eta_std']:.4f}; protocol: "
              + (f"Algorithm 1 literally (from rest, {res['duration_s']:g} s, SS after {res['transient_s']:g} s)"
                 if res["warmup_s"] == 0 else
                 f"shared {res['warmup_s']:g}-s deterministic warm start, then {res['duration_s']:g} s with eta, SS "
                 f"after {res['transient_s']:g} s (Algorithm 1 literally: --warmup 0 --duration 300 --transient 200)"))
        for r in res["speeds"]:
            print(f"{r['top_speed_rad_s']:8.3f} rad/s  mean SS = {r['mean_ss']:.3f}  "
                  f"[q05 {r['q05']:.3f}, q95 {r['q95']:.3f}]  P(SS > 0.5) = {r['p_ss_gt_0_5']:.3f}")
        p05 = res["p05_speed_rad_s"]
        print("P(SS > 0.5) <= 5 % from", "no crossing in range" if p05 is None else f"{p05:.2f} rad/s",
              _robust_speed_text(res),
              "(deterministic SS < 0.5 from",
              "no crossing" if res["deterministic_threshold_rad_s"] is None
              else f"{res['deterministic_threshold_rad_s']:.2f} rad/s)")
        if a.out:
            print(f"figures and mc.json written to {a.out}")
    return 0


def _robust_speed(severity, speeds, refine, seed, evaluate) -> dict:
    """The 5 % speed refined by bisection (``refine`` [rad/s], same samples) and its 90 % bootstrap
    interval over the samples (drillpy.uncertainty.robust_speed)."""
    from drillpy.uncertainty.robust_speed import bootstrap_interval, p_speed, refine_p_speed
    out = {}
    if refine is not None:
        r = refine_p_speed(severity, speeds, evaluate, tol=refine)
        if r is not None:
            severity, speeds = r.severity, r.speeds
            out["p05_speed_bracket_rad_s"] = [r.below, r.above]
            out["p05_speed_rad_s"] = p_speed(severity, speeds)
            out["refinement_speeds_rad_s"] = [float(x) for x in r.speeds]
    if severity.shape[0] >= 2:
        out["p05_speed_bootstrap"] = bootstrap_interval(severity, speeds, seed=seed)
    return out


def _robust_speed_text(res: dict) -> str:
    b = res.get("p05_speed_bootstrap")
    txt = ""
    if "p05_speed_bracket_rad_s" in res:
        lo, hi = res["p05_speed_bracket_rad_s"]
        txt += f"[bracket {lo:.2f}-{hi:.2f}] "
    if b and b["low"] == b["low"]:
        txt += f"[90 % bootstrap {b['low']:.2f}-{b['high']:.2f}] "
    return txt


def cmd_reproduce(a) -> int:
    from drillpy.reports.reproduce import Options, reproduce
    res = reproduce(a.chapter, a.out, Options(quick=a.quick, threads=a.threads, progress=not a.no_progress,
                                              seed=a.seed), record=a.record)
    if a.json:
        print(json.dumps(res.as_dict()))
    else:
        print((Path(a.out) / "table.md").read_text(), end="")
        print(f"figures, table.md and reproduce.json written to {a.out}")
    return 0


def cmd_loop(a) -> int:
    from drillpy.loop import LoopOptions, loop_record
    from drillpy.loop.effects import NAMES
    effects = NAMES if a.effects is None else tuple(e.strip() for e in a.effects.split(",") if e.strip())
    opt = LoopOptions(horizon_s=a.horizon, calibration_fraction=a.calibration_fraction, rate_hz=a.rate,
                      min_gain=a.min_gain, alpha=a.alpha, min_delta_bic=a.min_delta_bic, max_steps=a.max_steps,
                      effects=effects, threads=a.threads, dt_s=a.dt)
    js = loop_record(a.record, a.out, preset=a.preset, config_path=a.config, options=opt,
                     log=(lambda *_: None) if a.json else print)
    if a.json:
        print(json.dumps({k: js[k] for k in ("metric", "baseline_error", "final_error", "declared", "removed",
                                             "final_effects", "unexplained_fraction")} |
                         {"added": [s["effect"] for s in js["steps"] if s["action"] == "add"]}))
    return 0


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="drillpy", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="command", required=True)

    s = sub.add_parser("report", help="main job: deterministic analysis with figures")
    _model_args(s)
    s.add_argument("--out", default="results", help="output folder")
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_report)

    s = sub.add_parser("modes", help="natural frequencies (Eq. 2.7)")
    _model_args(s)
    s.add_argument("-n", type=int, default=5, help="number of frequencies")
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_modes)

    s = sub.add_parser("simulate", help="one run: time series and stick-slip metrics")
    _model_args(s)
    s.add_argument("--top-speed", type=float, help="top-drive speed [rad/s]")
    s.add_argument("--wob-kn", type=float, help="weight on bit [kN]")
    s.add_argument("--out", help="folder for series.csv, summary.json and a figure")
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_simulate)

    s = sub.add_parser("sweep", help="SS versus top speed (Fig. 4.8)")
    _model_args(s)
    s.add_argument("--speeds", default="6:27:22", help="top speeds [rad/s], start:stop:num or list")
    s.add_argument("--out", help="folder for the figure and sweep.json")
    s.add_argument("--refine", type=float, metavar="TOL", help="locate the threshold by bisection to TOL [rad/s]")
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_sweep)

    s = sub.add_parser("map", help="stability map over top speed x WOB (Figs. 3.11-3.12)")
    _model_args(s)
    s.add_argument("--speeds-rpm", default="50:160:23", help="top speeds [RPM]")
    s.add_argument("--wobs-kn", default="22:267:12", help="weights on bit [kN]")
    s.add_argument("--out", help="folder for the figure and map.json")
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_map)

    s = sub.add_parser("convergence", help="FE and time-step convergence studies (docs/numerics.md)")
    _model_args(s)
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_convergence)
    s = sub.add_parser("analyze", help="measured record(s) (.mat or .csv): one record: cleaning, cycles, "
                                       "identification, rig simulation (report.md + figures + summary.json); two or "
                                       "more: statistics across samples, thesis section 5.3 (samples.md, "
                                       "samples.json, fig5_4_boxplot.png)")
    s.add_argument("record", nargs="+",
                   help="rig MATLAB file or drillpy CSV (see README: CSV format), a folder of them, or FILE@T0:T1 "
                        "(the window T0 <= t < T1 [s] of a file as one sample)")
    s.add_argument("--out", required=True, help="output folder")
    s.add_argument("--t0", type=float, help="start of the analysed window [s] (every record)")
    s.add_argument("--t1", type=float, help="end of the analysed window [s] (every record)")
    s.add_argument("--cycle-at", type=float, help="time [s] inside the cycle shown in cycle.png (one record)")
    s.add_argument("--folds", type=int, help="cross-validation folds over cycles (0: none; default 5 for one record, "
                                             "0 across samples)")
    s.add_argument("--psd-fmax", type=float, default=10.0, help="upper end of the PSD-model fit band [Hz] (one record)")
    s.add_argument("--no-sim", action="store_true", help="skip the rig simulations (one record)")
    s.add_argument("--calibrate", metavar="T0:T1", help="fit and calibrate on this part [s] only and predict the rest "
                                                        "of the record (one record)")
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
    s.set_defaults(func=cmd_analyze)

    s = sub.add_parser("predict", help="apply a calibrated rig model (model.json of analyze) to a record, no refitting")
    s.add_argument("model", help="model.json written by drillpy analyze")
    s.add_argument("record", help="rig MATLAB file or drillpy CSV")
    s.add_argument("--out", help="folder for summary.json and overlay.png")
    s.add_argument("--t0", type=float, help="start of the predicted window [s]")
    s.add_argument("--t1", type=float, help="end of the predicted window [s]")
    s.add_argument("--horizon", type=float, default=0.25, help="short-horizon length [s] (docs/loop.md)")
    s.add_argument("--threads", type=int, default=0, help="OpenMP threads (0: default)")
    s.add_argument("--json", action="store_true", help="print the short-horizon error and the long-run metrics")
    s.set_defaults(func=cmd_predict)

    s = sub.add_parser("frf", help="acceleration FRF envelopes under structural uncertainty (chapter 6)")
    _uncertainty_args(s, samples=2500, out="folder for the figures and envelope.json")
    s.add_argument("--model", choices=["SM_full", "SM_CB1", "SM_CB2"], default="SM_CB2", help="stochastic model")
    s.add_argument("--case", type=int, help="SM_CB2 case study 1-7 (Tables 6.1-6.7)")
    s.add_argument("--delta", type=float, help="one dispersion for every random matrix (default 0.1)")
    s.add_argument("--probability", type=float, default=0.95, help="probability level of the envelope")
    s.add_argument("--freqs", default="0.01:10:1000", help="frequencies [Hz], start:stop:num or list")
    s.set_defaults(func=cmd_frf)

    s = sub.add_parser("frf-report", help="chapter 6 and appendix C: envelopes, case studies, Conv2, conclusions")
    _uncertainty_args(s, samples=2500, out="output folder (default results-ch6)")
    s.add_argument("--mode-samples", type=int, default=400, help="samples per point of Conv2 versus modes")
    s.set_defaults(func=cmd_frf_report, out="results-ch6")

    s = sub.add_parser("robust-ss", help="SS versus top speed with SM_CB2 structural uncertainty (time domain)")
    _uncertainty_args(s, samples=40, out="folder for the figure and robust_ss.json")
    s.add_argument("--delta", type=float, default=0.1, help="dispersion of every SM_CB2 matrix")
    s.add_argument("--speeds", default="6:27:8", help="top speeds [rad/s], start:stop:num or list")
    s.add_argument("--bit-rock", action="store_true",
                   help="add the stochastic bit-rock law: eta with the thesis PSD (Eqs. 4.1-4.4)")
    s.add_argument("--eta-npy", help="eta(t) of Eq. (4.1), one row per sample (.npy), for bit-rock uncertainty")
    s.add_argument("--eta-dt", type=float, default=0.05, help="sampling step of eta [s]")
    s.add_argument("--refine", type=float, metavar="TOL",
                   help="locate each 5 %% speed by bisection to TOL [rad/s] (same samples at new speeds)")
    s.set_defaults(func=cmd_robust_ss)

    s = sub.add_parser("reproduce", help="the thesis's studies chapter by chapter: figures under the thesis's "
                                         "numbers and a table quantity | thesis | drillpy | tolerance | pass")
    s.add_argument("--chapter", default="all", choices=["3", "4", "5", "6", "all"])
    s.add_argument("--out", required=True, help="folder for the figures, table.md and reproduce.json")
    s.add_argument("--quick", action="store_true", help="reduced studies (tests): not the thesis's settings")
    s.add_argument("--record", help="test-rig record of sample 175 for chapter 5 (default: ../shared/data/testrig)")
    s.add_argument("--seed", type=int, default=1, help="seed of the Monte Carlo studies")
    s.add_argument("--threads", type=int, default=0, help="OpenMP threads (0: default)")
    s.add_argument("--no-progress", action="store_true", help="no progress bar")
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_reproduce)

    s = sub.add_parser("mc", help="Monte Carlo of the stochastic bit-rock law (Figs. 4.4-4.9, C.1)")
    _model_args(s)
    s.add_argument("--samples", default="500", help="number of Monte Carlo samples")
    s.add_argument("--seed", default="0", help="integer seed; sample i depends only on (seed, i)")
    s.add_argument("--first-sample", default="0", help="index of the first sample (chunked runs)")
    s.add_argument("--speeds", default="6:27:22", help="top speeds [rad/s], start:stop:num or list")
    s.add_argument("--warmup", type=float, help="deterministic start-up shared by all samples [s] "
                                                "(default 100)")
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
    s.add_argument("--out", help="folder for the figures and mc.json")
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_mc)

    s = sub.add_parser("loop", help="measured record versus a declared model: residuals, the missing effects the "
                                    "evidence supports, the corrected model, errors before and after")
    s.add_argument("record", help="rig MATLAB file or drillpy CSV (see README: CSV format)")
    src = s.add_mutually_exclusive_group(required=True)
    src.add_argument("--preset", help="declared model: a built-in configuration (e.g. thesis-rig)")
    src.add_argument("--config", help="declared model: a JSON configuration file")
    s.add_argument("--out", required=True, help="output folder (loop.json, predictions.csv, report.md, figures)")
    s.add_argument("--horizon", type=float, default=0.25, help="prediction horizon between restarts [s]")
    s.add_argument("--calibration-fraction", type=float, default=0.5,
                   help="fraction of the record (from its start) used to calibrate; the rest validates")
    s.add_argument("--rate", type=float, default=1000.0, help="analysis sampling rate, at most [Hz]")
    s.add_argument("--min-gain", type=float, default=0.05, help="minimum relative validation improvement")
    s.add_argument("--alpha", type=float, default=0.05, help="family-wise level of the test per round")
    s.add_argument("--min-delta-bic", type=float, default=6.0, help="minimum BIC improvement (calibration part)")
    s.add_argument("--max-steps", type=int, default=6, help="at most this many effects are added")
    s.add_argument("--effects", help="comma-separated candidate effects (default: the whole catalogue)")
    s.add_argument("--dt", type=float, help="engine time step of the predictions [s] (default: the model's)")
    s.add_argument("--threads", type=int, default=0, help="OpenMP threads (0: default)")
    s.add_argument("--json", action="store_true", help="print the errors and the effects found as JSON")
    s.set_defaults(func=cmd_loop)
    return p


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.func(args)
    except (ValueError, RuntimeError, OSError) as e:
        print(f"drillpy: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("drillpy: interrupted", file=sys.stderr)
        return 130
