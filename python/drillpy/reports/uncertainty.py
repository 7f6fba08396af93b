"""The chapter-6 study with figures and the thesis's conclusions checked on measured widths.

:func:`chapter6_study` computes, on a configuration such as ``thesis-ch6`` (a :class:`Chapter6Study`):

  * Craig-Bampton natural frequencies versus the full FE model as modes per substructure grow;
  * SM_full, SM_CB1 and SM_CB2 at delta = 0.1 (Figs. 6.1-6.3);
  * SM_CB2 case studies 1-7 (Tables 6.1-6.7, Figs. 6.4-6.12);
  * Conv2 (Eq. C.2) versus samples (Fig. C.2) and versus DP and BHA modes (Figs. C.3-C.4);

:func:`drillpy.figures.frf.chapter6_figures` draws it, :func:`write_chapter6` writes ``summary.json``
and :func:`chapter6_report` composes the three. :func:`conclusions` turns envelope widths (dB,
averaged over frequency bands) into a verdict on each conclusion of section 6.6.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from drillpy.outputs import write_text
from drillpy.uncertainty.frf import band_widths, cb_frequencies, conv2_vs_modes, default_frequencies, frf_envelope
from drillpy.model.simulation import natural_frequencies
from drillpy.provenance import provenance
from drillpy.jsonio import dumps

# Frequency bands [Hz]: below the first resonance (0.31 Hz on thesis-ch6), then low, mid, high.
BANDS_HZ = {"very low 0.01-0.25 Hz": (0.01, 0.25), "low 0.25-2 Hz": (0.25, 2.0), "mid 2-5 Hz": (2.0, 5.0),
            "high 5-10 Hz": (5.0, 10.0), "whole 0.01-10 Hz": (0.01, 10.0)}
FIGURE_PAIRS = {"6.4-6.6": (1, 2, 3), "6.7-6.9": (4, 5), "6.10-6.12": (6, 7)}


def widths_table(envs: dict) -> dict:
    """Mean envelope widths per frequency band: label -> band -> [mean width per point] [dB].

    The width is upper - lower quantile of the acceleration FRF envelope [dB re 1 rad/s^2 per
    N m], averaged over each band of :data:`BANDS_HZ` (very low 0.01-0.25 Hz, low 0.25-2 Hz,
    mid 2-5 Hz, high 5-10 Hz, whole 0.01-10 Hz) by
    :func:`drillpy.uncertainty.frf.band_widths`.

    Parameters
    ----------
    envs : dict
        Label (e.g. "SM_CB2", "case 4") -> :class:`drillpy.uncertainty.frf.FRFEnvelope`.

    Returns
    -------
    dict
        Label -> band name (the keys of :data:`BANDS_HZ`) -> list of the mean widths [dB], one
        per observation point (P_obs1-3), rounded to 0.001 dB.
    """
    return {label: {b: band_widths(env, [rng])[0].round(3).tolist() for b, rng in BANDS_HZ.items()}
            for label, env in envs.items()}


def conclusions(models: dict, cases: dict) -> list[dict]:
    """Check each conclusion of section 6.6 on the envelopes.

    Seven claims are tested, each per observation point on the band-mean widths of
    :func:`widths_table` (:data:`BANDS_HZ`): the three stochastic models agree at delta = 0.1
    (Figs. 6.1-6.3: whole-band widths within a factor 1.5 and sample-mean curves within 2 dB);
    damping uncertainty gives the thinnest envelopes (case 2 below cases 1 and 3, Figs. 6.4-6.6);
    stiffness uncertainty dominates at very low frequency (case 3 above 1 and 2 over
    0.01-0.25 Hz); DP uncertainty widens the envelopes more than BHA uncertainty (case 4 above
    case 5, Figs. 6.7-6.9); interface-DOF uncertainty gives thinner envelopes than inner-DOF
    uncertainty (case 7 below case 6, Figs. 6.10-6.12); the envelopes widen from the low to the
    mid to the high band for every model and case; and with DP uncertainty (case 4) the
    thinnest envelope between 2 and 5 Hz lies within 0.3 Hz of 3.7 Hz.

    Parameters
    ----------
    models : dict
        "SM_full", "SM_CB1" and "SM_CB2" -> :class:`drillpy.uncertainty.frf.FRFEnvelope` at
        dispersion delta = 0.1.
    cases : dict
        Case study 1..7 (int) -> FRFEnvelope of SM_CB2 (Tables 6.1-6.7).

    Returns
    -------
    list of dict
        One entry per claim, in the order above, with ``claim`` (the thesis's statement),
        ``test`` (the criterion applied), ``holds`` (bool) and the measured evidence:
        ``widths_db`` (study -> mean widths per point [dB]) for most claims, plus
        ``width_ratio_max_over_min`` and ``mean_curve_gap_db`` [dB] (model agreement),
        ``widths_db_high_band`` (case 4 vs 5 over 5-10 Hz), ``by_study`` and
        ``does_not_hold_for`` (widening with frequency) or ``thinnest_at_hz`` [Hz] (case 4).
    """
    W = {k: {b: band_widths(e, [r])[0] for b, r in BANDS_HZ.items()} for k, e in {**models, **cases}.items()}
    whole, vlow = "whole 0.01-10 Hz", "very low 0.01-0.25 Hz"
    out = []

    w = np.array([W[m][whole] for m in ("SM_full", "SM_CB1", "SM_CB2")])
    ratio = w.max(axis=0) / w.min(axis=0)
    mean_gap = np.array([[np.mean(np.abs(models[a].mean_db[:, p] - models[b].mean_db[:, p]))
                          for p in range(w.shape[1])] for a, b in (("SM_full", "SM_CB2"), ("SM_CB1", "SM_CB2"))])
    out.append({"claim": "the three stochastic models agree at delta = 0.1 (Figs. 6.1-6.3)",
                "test": "per point, whole-band mean widths within a factor 1.5 and sample-mean curves within 2 dB "
                        "(mean absolute difference)",
                "widths_db": {m: W[m][whole].round(2).tolist() for m in ("SM_full", "SM_CB1", "SM_CB2")},
                "width_ratio_max_over_min": ratio.round(3).tolist(),
                "mean_curve_gap_db": {"SM_full vs SM_CB2": mean_gap[0].round(3).tolist(),
                                      "SM_CB1 vs SM_CB2": mean_gap[1].round(3).tolist()},
                "holds": bool((ratio <= 1.5).all() and (mean_gap < 2.0).all())})

    out.append({"claim": "damping uncertainty gives the thinnest envelopes (case 2 vs cases 1 and 3)",
                "test": "per point, whole-band mean width of case 2 below those of cases 1 and 3",
                "widths_db": {f"case {c}": W[c][whole].round(2).tolist() for c in (1, 2, 3)},
                "holds": bool((W[2][whole] < np.minimum(W[1][whole], W[3][whole])).all())})

    out.append({"claim": "stiffness uncertainty dominates at very low frequency (case 3 vs 1 and 2)",
                "test": f"per point, mean width over {vlow} of case 3 above those of cases 1 and 2",
                "widths_db": {f"case {c}": W[c][vlow].round(3).tolist() for c in (1, 2, 3)},
                "holds": bool((W[3][vlow] > np.maximum(W[1][vlow], W[2][vlow])).all())})

    out.append({"claim": "DP uncertainty widens the envelopes more than BHA uncertainty (case 4 vs 5)",
                "test": "per point, whole-band mean width of case 4 above that of case 5",
                "widths_db": {f"case {c}": W[c][whole].round(2).tolist() for c in (4, 5)},
                "widths_db_high_band": {f"case {c}": W[c]["high 5-10 Hz"].round(2).tolist() for c in (4, 5)},
                "holds": bool((W[4][whole] > W[5][whole]).all())})

    out.append({"claim": "interface-DOF uncertainty gives thinner envelopes than inner-DOF uncertainty (7 vs 6)",
                "test": "per point, whole-band mean width of case 7 below that of case 6",
                "widths_db": {f"case {c}": W[c][whole].round(2).tolist() for c in (6, 7)},
                "holds": bool((W[7][whole] < W[6][whole]).all())})

    order = ("low 0.25-2 Hz", "mid 2-5 Hz", "high 5-10 Hz")
    grows = {}
    for label in ("SM_full", "SM_CB1", "SM_CB2", *range(1, 8)):
        w3 = np.array([W[label][b] for b in order])
        grows[label if isinstance(label, str) else f"case {label}"] = {
            "widths_db": w3.round(2).tolist(), "increasing": bool((np.diff(w3, axis=0) > 0).all())}
    fails = [k for k, v in grows.items() if not v["increasing"]]
    out.append({"claim": "the envelopes widen with frequency",
                "test": "for every model and case, per point, mean width increasing from the low (0.25-2 Hz) to "
                        "the mid (2-5 Hz) to the high (5-10 Hz) band; widths_db rows are the bands, columns the points",
                "by_study": grows, "does_not_hold_for": fails,
                "holds": not fails})

    f = cases[4].freq_hz
    sel = (f >= 2.0) & (f <= 5.0)
    fmin = [float(f[sel][np.argmin(cases[4].width_db[sel, p])]) for p in range(cases[4].width_db.shape[1])]
    out.append({"claim": "with DP uncertainty (case 4) the envelopes become thinner around 3.7 Hz",
                "test": "per point, the frequency of the thinnest case-4 envelope between 2 and 5 Hz within 0.3 Hz "
                        "of 3.7 Hz",
                "thinnest_at_hz": [round(x, 2) for x in fmin],
                "holds": bool(all(abs(x - 3.7) <= 0.3 for x in fmin))})
    return out


def print_conclusions(rows: list[dict]) -> None:
    """Print each verdict of :func:`conclusions` as "[holds] claim" or "[does NOT hold] claim",
    followed by its evidence (every key but ``claim``, ``holds`` and ``test``), one per line.

    Parameters
    ----------
    rows : list of dict
        The verdicts returned by :func:`conclusions` (or the ``conclusions`` of a chapter-6
        ``summary.json``).
    """
    for r in rows:
        print(f"[{'holds' if r['holds'] else 'does NOT hold'}] {r['claim']}")
        for k, v in r.items():
            if k not in ("claim", "holds", "test"):
                print(f"    {k}: {v}")


@dataclass
class Chapter6Study:
    """The chapter-6 study computed by :func:`chapter6_study` (nothing drawn or written).

    Attributes
    ----------
    preset : str or None
        Name of the configuration.
    samples : int
        Monte Carlo samples per envelope.
    mode_samples : int
        Samples per point of Conv2 versus modes.
    seed : int
        Seed of every study (sample i from (seed, i)).
    freq_hz : ndarray
        Frequency grid of the FRFs [Hz].
    fe_frequencies_hz : ndarray
        First 8 natural frequencies of the full FE model [Hz].
    cb_modes : list of int
        Fixed-interface modes per substructure of the Craig-Bampton convergence study.
    cb_rel_errors : list of ndarray
        Per entry of ``cb_modes``: |f_CB / f_FE - 1| of the first 8 modes [-].
    nominal_max_abs_db : float
        Largest difference of the nominal FRFs, modal ROM versus Craig-Bampton [dB].
    models : dict
        "SM_full" / "SM_CB1" / "SM_CB2" -> FRFEnvelope at delta = 0.1 (Figs. 6.1-6.3); FRFs in dB
        re 1 rad/s^2 per N m.
    cases : dict
        Case 1..7 -> FRFEnvelope of SM_CB2 (Tables 6.1-6.7, Figs. 6.4-6.12).
    conv2_modes : list of int
        Fixed-interface modes of the Conv2-versus-modes study (Figs. C.3-C.4).
    conv2_curves : dict
        Substructure name -> scenario -> Conv2 [rad/s^1.5 per N m], shape (len(conv2_modes), n_points).
    conclusions : list of dict
        The conclusions of section 6.6 checked on the widths (:func:`conclusions`).
    summary : dict
        The content of ``summary.json`` (JSON-ready; widths in dB, frequencies in Hz).
    """
    preset: str | None
    samples: int
    mode_samples: int
    seed: int
    freq_hz: np.ndarray
    fe_frequencies_hz: np.ndarray
    cb_modes: list
    cb_rel_errors: list
    nominal_max_abs_db: float
    models: dict
    cases: dict
    conv2_modes: list
    conv2_curves: dict
    conclusions: list
    summary: dict = field(default_factory=dict)

    @property
    def point_labels(self) -> list:
        """Names of the observation points."""
        return self.models["SM_CB2"].labels


CONV2_SCENARIOS = {"DP and BHA, delta = 0.1": dict(delta=0.1), "BHA only (case 5)": dict(case=5),
                   "DP only (case 4)": dict(case=4)}


def chapter6_study(cfg: dict, *, samples: int = 2500, mode_samples: int = 400, seed: int = 1, freq_hz=None,
                   modes=(1, 2, 3, 5, 7, 10, 15, 20, 25), progress: bool = True, threads: int = 0) -> Chapter6Study:
    """Run the chapter-6 study (nothing is drawn or written).

    Parameters
    ----------
    cfg : dict
        Configuration with Craig-Bampton substructures (e.g. the ``thesis-ch6`` preset).
    samples : int
        Monte Carlo samples per envelope.
    mode_samples : int
        Samples per point of Conv2 versus modes.
    seed : int
        Seed (sample i from (seed, i)).
    freq_hz : array_like, optional
        Frequency grid [Hz] (default :func:`drillpy.uncertainty.frf.default_frequencies`).
    modes : sequence of int
        Fixed-interface modes of the Conv2-versus-modes study.
    progress : bool
        Show progress bars.
    threads : int
        Engine threads (0: all cores).

    Returns
    -------
    Chapter6Study
        Envelopes, convergence studies, conclusions and the summary.
    """
    f = default_frequencies() if freq_hz is None else np.asarray(freq_hz, dtype=float)
    kw = dict(samples=samples, seed=seed, freq_hz=f, progress=progress, threads=threads)
    summary: dict = {"preset": cfg.get("name"), "samples": samples, "seed": seed,
                     "frequencies_hz": [float(f[0]), float(f[-1]), int(f.size)], "bands_hz": BANDS_HZ}

    n_fe = 8
    fe = natural_frequencies(cfg, n_fe)
    mode_list = [m for m in (3, 5, 7, 10, 15, 20, 25, 35, 50) if 2 * m + 1 >= n_fe]
    errs = [np.abs(cb_frequencies(cfg, n_fe, [m] * len(cfg["string"]["sections"])) / fe - 1.0) for m in mode_list]
    summary["cb_convergence"] = {"fe_frequencies_hz": fe.round(5).tolist(), "modes": mode_list,
                                 "max_rel_error_first5": [float(e[:5].max()) for e in errs],
                                 "max_rel_error_first8": [float(e.max()) for e in errs]}

    nominal = nominal_agreement(cfg, f)
    summary["nominal_modal_rom_vs_cb_max_abs_db"] = nominal
    models = {m: frf_envelope(cfg, m, 0.1, **kw) for m in ("SM_full", "SM_CB1", "SM_CB2")}
    cases = {c: frf_envelope(cfg, "SM_CB2", case=c, **kw) for c in range(1, 8)}
    summary["widths_db"] = widths_table({**models, **{f"case {c}": e for c, e in cases.items()}})
    concl = conclusions(models, cases)
    summary["conclusions"] = concl

    c2 = models["SM_CB2"].conv2()
    summary["conv2_samples"] = {"n": [int(n) for n in (100, 500, 1000, 1500, 2000, samples) if n <= samples],
                                "relative_to_final": [(c2[n - 1] / c2[-1]).round(4).tolist()
                                                      for n in (100, 500, 1000, 1500, 2000, samples) if n <= samples]}
    curves_by = {}
    for k, name in enumerate(s["name"] for s in cfg["string"]["sections"]):
        curves_by[name] = {sc: conv2_vs_modes(cfg, k, modes, "SM_CB2", samples=mode_samples, seed=seed, freq_hz=f,
                                              progress=progress, threads=threads, **a)
                           for sc, a in CONV2_SCENARIOS.items()}
    summary["conv2_modes"] = {"modes": list(modes), "samples": mode_samples,
                              "curves": {name: {sc: c.round(6).tolist() for sc, c in curves.items()}
                                         for name, curves in curves_by.items()}}
    return Chapter6Study(preset=cfg.get("name"), samples=samples, mode_samples=mode_samples, seed=seed, freq_hz=f,
                         fe_frequencies_hz=fe, cb_modes=mode_list, cb_rel_errors=errs, nominal_max_abs_db=nominal,
                         models=models, cases=cases, conv2_modes=list(modes), conv2_curves=curves_by,
                         conclusions=concl, summary=summary)


def write_chapter6(study: Chapter6Study, out_dir, **options) -> dict:
    """Write ``summary.json`` of the chapter-6 study.

    Parameters
    ----------
    study : Chapter6Study
        What :func:`chapter6_study` returned.
    out_dir : str or Path
        Output folder (created if missing).
    **options
        Settings of the study recorded in the file's ``provenance`` (seed, samples...).

    Returns
    -------
    dict
        The summary written (without the ``provenance``).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    write_text((out / "summary.json"), dumps({**study.summary, "provenance": provenance(**options)}))
    return study.summary


def chapter6_report(cfg: dict, out_dir, *, samples: int = 2500, mode_samples: int = 400, seed: int = 1,
                    freq_hz=None, modes=(1, 2, 3, 5, 7, 10, 15, 20, 25), progress: bool = True,
                    threads: int = 0) -> dict:
    """Run the chapter-6 study, write its figures and ``summary.json`` into ``out_dir``.

    :func:`chapter6_study` -> :func:`drillpy.figures.frf.chapter6_figures` -> :func:`write_chapter6`.

    Parameters
    ----------
    cfg, samples, mode_samples, seed, freq_hz, modes, progress, threads
        As for :func:`chapter6_study`.
    out_dir : str or Path
        Output folder (created if missing).

    Returns
    -------
    dict
        The summary (content of ``summary.json``).
    """
    from drillpy.figures.frf import chapter6_figures
    study = chapter6_study(cfg, samples=samples, mode_samples=mode_samples, seed=seed, freq_hz=freq_hz,
                           modes=modes, progress=progress, threads=threads)
    chapter6_figures(study, out_dir)
    return write_chapter6(study, out_dir, seed=seed, samples=samples, mode_samples=mode_samples)


def nominal_agreement(cfg: dict, f_hz=None) -> float:
    """Largest |dB| difference between the nominal FRFs of the modal ROM (SM_full mean) and the
    Craig-Bampton model (SM_CB2 mean) over the grid, at the three points.

    A check that the Craig-Bampton reduction reproduces the mean model before uncertainty is
    added (delta = 0, one sample each).

    Parameters
    ----------
    cfg : dict
        Configuration with Craig-Bampton substructures (e.g. ``thesis-ch6``).
    f_hz : array_like, optional
        Frequency grid [Hz] (default :func:`drillpy.uncertainty.frf.default_frequencies`).

    Returns
    -------
    float
        Largest absolute difference of the nominal acceleration FRFs [dB] over the frequencies
        and observation points.
    """
    f = default_frequencies() if f_hz is None else f_hz
    a = frf_envelope(cfg, "SM_full", 0.0, samples=1, freq_hz=f, progress=False)
    b = frf_envelope(cfg, "SM_CB2", 0.0, samples=1, freq_hz=f, progress=False)
    return float(np.abs(a.nominal_db - b.nominal_db).max())


def write_envelope(out_dir, env, title: str, summary: dict, cfg: dict, **options) -> Path:
    """Write the outputs of one FRF envelope (``drillpy frf --out``).

    Parameters
    ----------
    out_dir : str or Path
        Folder created if missing; receives ``frf_point<k>.png`` per observation point and
        ``envelope.json``.
    env : drillpy.uncertainty.frf.FrfEnvelope
        The envelope (:func:`drillpy.uncertainty.frf.frf_envelope`).
    title : str
        Legend label and title prefix of the figures.
    summary : dict
        JSON summary of the envelope, written with the configuration under ``"config"``.
    cfg : dict
        Configuration the envelope ran with.
    **options
        Settings recorded in the file's ``provenance`` (seed, samples, model, delta...).

    Returns
    -------
    Path
        The output folder.
    """
    from drillpy.figures import frf as frf_plots
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    for p, label in enumerate(env.labels):
        frf_plots.envelope_plot(out / f"frf_point{p + 1}.png", {title: env}, p, f"{title}: {label}")
    write_text((out / "envelope.json"), dumps({**summary, "config": cfg, "provenance": provenance(**options)}, indent=None))
    return out


def robust_speed_summary(severity, speeds, refine: float | None, seed: int, evaluate) -> dict:
    """The 5 % speed of a Monte Carlo SS matrix, refined and with its bootstrap interval.

    Parameters
    ----------
    severity : ndarray
        SS [-], one row per sample, one column per speed.
    speeds : array_like
        Top-drive speeds [rad/s] of the columns.
    refine : float or None
        Bisection tolerance [rad/s] of :func:`drillpy.uncertainty.robust_speed.refine_p_speed`
        (same samples at new speeds); None: no refinement.
    seed : int
        Seed of the bootstrap resampling.
    evaluate : callable
        ``evaluate(speeds)`` returns the SS matrix of the same samples at new speeds [rad/s].

    Returns
    -------
    dict
        ``p05_speed_bracket_rad_s``, ``p05_speed_rad_s`` and ``refinement_speeds_rad_s`` when refined
        to a crossing; ``p05_speed_bootstrap`` (90 % interval over the samples) with two or more samples, and
        ``p05_speed_precision_warning`` when the grid limits its precision (:func:`grid_limit`).
    """
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
        out["p05_speed_bootstrap"] = b = bootstrap_interval(severity, speeds, seed=seed)
        note = grid_limit(b, speeds)
        if note:
            out["p05_speed_precision_warning"] = note
    return out


def grid_limit(interval: dict, speeds) -> str | None:
    """The warning due when the grid, not the samples, limits the precision of the 5 % speed: its
    bootstrap interval is narrower than the grid spacing where it lies (the resamples all cross
    P = 5 % in the same grid cell, and the linear interpolation in that cell decides the rest).

    Parameters
    ----------
    interval : dict
        :func:`drillpy.uncertainty.robust_speed.bootstrap_interval` (``low``, ``high`` [rad/s]).
    speeds : array_like
        The grid [rad/s] (with any refinement speeds).

    Returns
    -------
    str or None
        The warning, None when the interval spans a grid spacing or more (or there is none).
    """
    lo, hi = interval["low"], interval["high"]
    sp = np.unique(np.asarray(speeds, float))
    if not (lo == lo and hi == hi) or sp.size < 2:
        return None
    k = int(np.clip(np.searchsorted(sp, lo, side="right") - 1, 0, sp.size - 2))
    spacing = float(sp[k + 1] - sp[k])
    if hi - lo >= spacing:
        return None
    return (f"the 90 % bootstrap interval of the 5 % speed ({lo:.2f}-{hi:.2f} rad/s) is narrower than the grid "
            f"spacing there ({spacing:.3g} rad/s): the grid, not the samples, limits its precision; --refine TOL "
            "locates it by bisection on the same samples")


def robust_severity(cfg: dict, speeds, samples: int, *, delta: float = 0.1, eta_psd=None, eta=None,
                    eta_dt: float = 0.05, refine: float | None = None, seed: int = 1, progress: bool = True,
                    threads: int = 0, runner=None) -> tuple[dict, dict]:
    """SS versus top speed per source of uncertainty with the robust speed of each (``drillpy robust-ss``).

    Parameters
    ----------
    cfg : dict
        Configuration (Craig-Bampton modes set, e.g. ``thesis-ch6``).
    speeds : array_like
        Top-drive speeds [rad/s].
    samples : int
        Monte Carlo samples per source.
    delta : float
        Dispersion of every SM_CB2 random matrix [-].
    eta_psd : PsdModel or PsdTable, optional
        One-sided PSD per Hz of eta (Eq. 4.4): adds the stochastic bit-rock law generated in the engine.
    eta : ndarray, optional
        eta(t) of Eq. (4.1), one row per sample, sampled every ``eta_dt``: adds the bit-rock law from
        given series (not with ``eta_psd``).
    eta_dt : float
        Sampling step of eta [s].
    refine : float, optional
        Locate each 5 % speed by bisection to this tolerance [rad/s].
    seed : int
        Seed of the samples and of the bootstrap.
    progress : bool
        Show a progress bar.
    threads : int
        OpenMP threads (0: default).
    runner : callable, optional
        Runs the studies of the sources of ``eta_psd`` (:func:`drillpy.uncertainty.structural.severity_sources`).

    Returns
    -------
    studies : dict
        label -> :class:`drillpy.uncertainty.structural.SeverityStudy`.
    summary : dict
        label -> the study's JSON with the :func:`robust_speed_summary` entries.
    """
    from drillpy.uncertainty.structural import severity_sources, severity_study
    kw = dict(seed=seed, progress=progress, threads=threads)
    studies = severity_sources(cfg, speeds, samples, delta=delta, eta_psd=eta_psd, eta_dt=eta_dt, runner=runner, **kw)
    if eta is not None:
        studies["bit-rock (eta)"] = severity_study(cfg, speeds, samples, delta=0.0, structural=False, eta=eta,
                                                   eta_dt=eta_dt, label="bit-rock (eta)", **kw)
        studies["structure + bit-rock"] = severity_study(cfg, speeds, samples, delta=delta, eta=eta,
                                                         eta_dt=eta_dt, label="structure + bit-rock", **kw)
    res = {label: st.to_json() for label, st in studies.items()}
    for label, st in studies.items():
        if st.ss.shape[0] < 2:
            continue
        kw_st = dict(delta=delta, seed=seed, progress=False, threads=threads, eta_dt=eta_dt, label=label,
                     structural=label != "bit-rock (eta)")
        if "bit-rock" in label:
            if eta_psd is not None:
                kw_st["eta_psd"] = eta_psd
            else:
                kw_st["eta"] = eta
            if label == "bit-rock (eta)":
                kw_st["delta"] = 0.0
        n = st.ss.shape[0]
        res[label].update(robust_speed_summary(st.ss, st.speeds, refine, seed,
                                               lambda sp, kw_st=kw_st, n=n: severity_study(cfg, sp, n, **kw_st).ss))
    return studies, res


def write_robust_severity(out_dir, speeds, studies: dict, summary: dict, cfg: dict, *, figure_units: str = "si",
                          **options) -> Path:
    """Write the outputs of :func:`robust_severity` (``drillpy robust-ss --out``).

    Parameters
    ----------
    out_dir : str or Path
        Folder created if missing; receives ``severity_bands.png`` and ``robust_ss.json``.
    speeds : array_like
        Top-drive speeds [rad/s].
    studies : dict
        label -> SeverityStudy.
    summary : dict
        label -> JSON of the study, written with the configuration under ``"config"``.
    cfg : dict
        Configuration the studies ran with.
    figure_units : str
        Axis units of the figure (``si`` or ``field``, :data:`drillpy.figures.simulation.FIGURE_UNITS`);
        ``robust_ss.json`` stays SI.
    **options
        Settings recorded in the file's ``provenance`` (seed, delta, samples...).

    Returns
    -------
    Path
        The output folder.
    """
    from drillpy.figures import frf as frf_plots
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    frf_plots.severity_bands_plot(out / "severity_bands.png", speeds, studies, units=figure_units)
    write_text((out / "robust_ss.json"), dumps({**summary, "config": cfg, "provenance": provenance(**options)}))
    return out
