"""The main job: a deterministic analysis of a preset, reproducing the thesis's chapter 2-4 numbers.

Writes figures and ``summary.json`` into an output folder and returns the summary:
natural frequencies (Eq. 2.7), SS versus top speed with its threshold (Fig. 4.8), the
stick/slip phases and periodic regime of one run with the preset and of a converged reference
(all modes, BDF2; Fig. 4.6), and stability maps for the
hysteretic models 1-3 (Figs. 3.11-3.12) with a quantified check of the thesis's conclusions.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from drillpy.figures import simulation as plotting
from drillpy.model.config import with_overrides
from drillpy.model.simulation import (natural_frequencies, severity_threshold, simulate, stability_map,
                         sweep_severity)

THESIS_FREQUENCIES_HZ = [0.13, 0.42, 0.74, 1.07, 1.41]
THESIS_THRESHOLD_RAD_S = 16.0
MODEL_BETA1 = {"model 1 (reversible, beta1 = 0)": 0.0, "model 2 (beta1 = 0.14)": 0.14,
               "model 3 (beta1 = 0.56)": 0.56}


def map_conclusions(speeds_rpm: np.ndarray, wobs_kn: np.ndarray, maps: dict) -> dict:
    """Quantify the two conclusions of section 3.3 on the maps.

    Quadrants split the grid at the median speed and WOB. 'stable_fraction_high_speed_low_wob'
    is the fraction of cells with SS < 0.5 in the high-speed / low-WOB quadrant;
    'mean_ss_low_speed_high_wob' is the mean SS in the low-speed / high-WOB quadrant.
    """
    hs = speeds_rpm >= np.median(speeds_rpm)
    lw = wobs_kn <= np.median(wobs_kn)
    out = {}
    for label, m in maps.items():
        q_stable = m[np.ix_(lw, hs)]
        q_severe = m[np.ix_(~lw, ~hs)]
        out[label] = {
            "stable_fraction_all": float(np.mean(m < 0.5)),
            "stable_fraction_high_speed_low_wob": float(np.mean(q_stable < 0.5)),
            "mean_ss_low_speed_high_wob": float(np.mean(q_severe)),
            "max_ss": float(np.max(m)),
        }
    labels = list(maps)
    first, last = out[labels[0]], out[labels[-1]]
    out["hysteresis_enlarges_stable_region"] = bool(
        last["stable_fraction_high_speed_low_wob"] > first["stable_fraction_high_speed_low_wob"]
        or last["stable_fraction_all"] > first["stable_fraction_all"])
    out["hysteresis_raises_ss_low_speed_high_wob"] = bool(
        last["mean_ss_low_speed_high_wob"] > first["mean_ss_low_speed_high_wob"])
    return out


def _run_summary(run, top_speed: float) -> dict:
    return {"top_speed_rad_s": top_speed, "severity": run.severity,
            "stick_fraction": run.stick_fraction,
            "stick_durations_s": run.stick_durations.round(3).tolist(),
            "slip_durations_s": run.slip_durations.round(3).tolist(),
            "period_cycles": run.period_cycles,
            "period_stick_s": run.period_stick.round(3).tolist(),
            "period_slip_s": run.period_slip.round(3).tolist()}


def field_report(cfg: dict, out_dir: str | Path, *, speeds=None, map_speeds_rpm=None,
                 map_wobs_kn=None, progress: bool = True, threads: int = 0) -> dict:
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    summary: dict = {"preset": cfg.get("name"), "config": cfg}

    f = natural_frequencies(cfg, 5)
    summary["frequencies_hz"] = [round(float(x), 4) for x in f]
    summary["thesis_frequencies_hz"] = THESIS_FREQUENCIES_HZ

    speeds = np.arange(6.0, 28.0) if speeds is None else np.asarray(speeds, float)
    ss = sweep_severity(cfg, speeds, progress=progress, threads=threads)
    thr = severity_threshold(speeds, ss)
    summary["sweep"] = {"top_speeds_rad_s": speeds.tolist(), "severity": ss.round(4).tolist(),
                        "threshold_rad_s": thr, "thesis_threshold_rad_s": THESIS_THRESHOLD_RAD_S}
    plotting.severity_curve(out / "severity_vs_top_speed.png", speeds, ss, thr,
                            title=f"{cfg.get('name')}: SS vs top speed (Fig. 4.8)")

    op_speed = cfg["operation"]["top_speed_rad_s"]
    summary["run"] = _run_summary(simulate(cfg, op_speed), op_speed)
    # Converged reference for the periodic regime (section 4.2.1): all modes, BDF2, long run.
    n_free = sum(sec["elements"] for sec in cfg["string"]["sections"])
    duration = max(400.0, cfg["simulation"]["duration_s"])
    ref_cfg = with_overrides(cfg, modes=n_free, scheme="bdf2", duration=duration, transient=duration / 2)
    ref = simulate(ref_cfg, op_speed)
    summary["reference_run"] = {**_run_summary(ref, op_speed), "modes": n_free, "scheme": "bdf2",
                                "duration_s": duration}
    t_end = ref.t[-1]
    plotting.time_series(out / "time_series.png", ref.t, ref.bit_speed, ref.torque_on_bit,
                         ref.top_speed, t_window=(max(0.0, t_end - 60.0), t_end),
                         title=f"{cfg.get('name')}: {op_speed:g} rad/s at the top, all modes, BDF2 "
                               "(last 60 s)")

    if cfg["law"]["type"] == "hysteretic":
        sp_rpm = np.linspace(50, 160, 23) if map_speeds_rpm is None else np.asarray(map_speeds_rpm, float)
        w_kn = np.linspace(22, 267, 12) if map_wobs_kn is None else np.asarray(map_wobs_kn, float)
        maps = {}
        for label, beta1 in MODEL_BETA1.items():
            c = with_overrides(cfg, beta1=beta1)
            maps[label] = stability_map(c, sp_rpm * np.pi / 30.0, w_kn * 1e3, progress=progress,
                                        threads=threads)
        plotting.stability_maps(out / "stability_maps.png", sp_rpm, w_kn, maps)
        summary["stability_maps"] = {
            "top_speeds_rpm": sp_rpm.tolist(), "wobs_kn": w_kn.tolist(),
            "severity": {k: v.round(4).tolist() for k, v in maps.items()},
            "conclusions": map_conclusions(sp_rpm, w_kn, maps),
        }
    (out / "summary.json").write_text(json.dumps(summary, indent=2))
    return summary


def print_field_summary(s: dict) -> None:
    print(f"natural frequencies [Hz]: {s['frequencies_hz']}  (thesis {s['thesis_frequencies_hz']})")
    sw = s["sweep"]
    thr = "none in range" if sw["threshold_rad_s"] is None else f"{sw['threshold_rad_s']:.2f} rad/s"
    print(f"SS > 0.5 below {thr}  (thesis {sw['thesis_threshold_rad_s']} rad/s)")
    for key, label in (("run", "preset"), ("reference_run", "all modes, BDF2")):
        r = s[key]
        print(f"run at {r['top_speed_rad_s']} rad/s ({label}): SS = {r['severity']:.3f}, stick "
              f"fraction = {r['stick_fraction']:.3f}, periodic over {r['period_cycles']} cycle(s)")
        if r["period_cycles"]:
            print(f"  stick durations {r['period_stick_s']} s, slip durations {r['period_slip_s']} s")
    print("  thesis (section 4.2.1): 3-cycle, stick (1.34, 2.53, 2.48) s, slip (5.4, 6.28, 6.41) s")
    if "stability_maps" in s:
        c = s["stability_maps"]["conclusions"]
        for label in MODEL_BETA1:
            m = c[label]
            print(f"{label}: stable fraction {m['stable_fraction_all']:.2f} (high speed/low WOB "
                  f"{m['stable_fraction_high_speed_low_wob']:.2f}), mean SS low speed/high WOB "
                  f"{m['mean_ss_low_speed_high_wob']:.2f}")
        print(f"hysteresis enlarges stable region: {c['hysteresis_enlarges_stable_region']}; "
              f"raises SS at low speed/high WOB: {c['hysteresis_raises_ss_low_speed_high_wob']}")


def write_sweep(out_dir: str | Path, speeds, severity, threshold: float | None, summary: dict, cfg: dict) -> Path:
    """Write the outputs of an SS sweep (``drillpy sweep --out``).

    Parameters
    ----------
    out_dir : str or Path
        Folder created if missing; receives ``severity_vs_top_speed.png`` and ``sweep.json``.
    speeds : array_like
        Top-drive speeds [rad/s].
    severity : array_like
        SS (Eq. 3.4) at each speed [-].
    threshold : float or None
        Speed below which SS > 0.5 [rad/s], drawn on the figure; None without a crossing.
    summary : dict
        JSON summary of the sweep, written with the configuration under ``"config"``.
    cfg : dict
        Configuration the sweep ran with.

    Returns
    -------
    Path
        The output folder.
    """
    from drillpy.figures import simulation as plotting
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    plotting.severity_curve(out / "severity_vs_top_speed.png", speeds, severity, threshold)
    (out / "sweep.json").write_text(json.dumps({**summary, "config": cfg}, indent=2))
    return out


def write_map(out_dir: str | Path, speeds_rpm, wobs_kn, severity, summary: dict, cfg: dict) -> Path:
    """Write the outputs of a stability map (``drillpy map --out``).

    Parameters
    ----------
    out_dir : str or Path
        Folder created if missing; receives ``stability_map.png`` and ``map.json``.
    speeds_rpm : array_like
        Top-drive speeds [RPM].
    wobs_kn : array_like
        Weights on bit [kN].
    severity : ndarray
        SS [-] over speed x WOB, as returned by :func:`drillpy.model.simulation.stability_map`.
    summary : dict
        JSON summary of the map, written with the configuration under ``"config"``.
    cfg : dict
        Configuration the map ran with (its law type labels the panel).

    Returns
    -------
    Path
        The output folder.
    """
    from drillpy.figures import simulation as plotting
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    plotting.stability_maps(out / "stability_map.png", speeds_rpm, wobs_kn, {cfg["law"]["type"]: severity})
    (out / "map.json").write_text(json.dumps({**summary, "config": cfg}, indent=2))
    return out
