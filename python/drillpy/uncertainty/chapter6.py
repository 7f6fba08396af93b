"""The chapter-6 study of the thesis computed (nothing drawn or written): the FRF envelopes of the
three stochastic models and of the seven uncertainty cases, the Craig-Bampton convergence, Conv2
versus modes and the conclusions of section 6.6 checked on the envelopes' widths.

:func:`drillpy.figures.frf.chapter6_figures` draws a :class:`Chapter6Study`;
:func:`drillpy.reports.uncertainty.chapter6_report` writes it.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from drillpy.model.configuration import Configuration
from drillpy.model.simulation import natural_frequencies
from drillpy.uncertainty.frf import band_widths, cb_frequencies, conv2_vs_modes, default_frequencies, frf_envelope


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
    sections = Configuration.of(cfg).string.sections
    summary: dict = {"preset": cfg.get("name"), "samples": samples, "seed": seed,
                     "frequencies_hz": [float(f[0]), float(f[-1]), int(f.size)], "bands_hz": BANDS_HZ}

    n_fe = 8
    fe = natural_frequencies(cfg, n_fe)
    mode_list = [m for m in (3, 5, 7, 10, 15, 20, 25, 35, 50) if 2 * m + 1 >= n_fe]
    errs = [np.abs(cb_frequencies(cfg, n_fe, [m] * len(sections)) / fe - 1.0) for m in mode_list]
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
    for k, name in enumerate(s.name for s in sections):
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
