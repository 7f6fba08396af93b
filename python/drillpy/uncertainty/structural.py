"""Stick-slip severity under structural uncertainty in the time domain (thesis chapter 7, future
work item 1): random SM_CB2 (or SM_CB1 / SM_full) realizations of the string integrated with the
bit-rock law, optionally with the stochastic law T_sto = T_hys (1 + eta(t)) (Eq. 4.1).

The bit-rock uncertainty enters through ``eta_psd``, the one-sided PSD per Hz of eta (Eq. 4.4;
default calibration ``THESIS_PSD``), generated in the engine by the chapter-4 process generator:
sample i gets the same eta as sample i of :func:`drillpy.uncertainty.montecarlo.stochastic_study` with the same
seed, and the random matrices of the same sample from other random streams (independent sources).
Any other eta can be given as an array ``eta`` with one series per sample (sampled every
``eta_dt`` seconds from t = 0). Sample i carries realization i of the random matrices and of eta at
every top speed (common random numbers).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from drillpy import _core, validate
from drillpy.model.configuration import Configuration
from drillpy.uncertainty.frf import stochastic_model
from drillpy.uncertainty.montecarlo import ETA_DT_S
from drillpy.uncertainty.process import psd_on_grid
from drillpy.progress import progress_bar


def _trapezoid(*args, **kwargs):
    """scipy.integrate.trapezoid, imported when used (off the import path of `drillpy mc`)."""
    from scipy.integrate import trapezoid

    return trapezoid(*args, **kwargs)


@dataclass
class SeverityStudy:
    """SS (Eq. 3.4) for ``samples x speeds`` and its statistics per top speed (the chapter-4
    engine statistics: mean, 5 % and 95 % quantiles, P(SS > 0.5), and the speed from which
    P(SS > 0.5) <= 5 %).

    The statistics are computed on construction from ``speeds`` and ``ss``.

    Attributes
    ----------
    speeds : numpy.ndarray
        Top speeds [rad/s], shape (n_speeds,).
    ss : numpy.ndarray
        SS [-], shape (samples, n_speeds); row r is realization ``first_sample + r`` (the same at
        every speed).
    label : str
        Name of the uncertainty source (legend, JSON).
    first_sample : int
        Index of the realization of the first row (default 0).
    mean : numpy.ndarray
        Mean SS per speed [-] (computed).
    q05, q95 : numpy.ndarray
        5 % and 95 % sample quantiles of SS per speed [-] (computed).
    p_stick_slip : numpy.ndarray
        P(SS > 0.5) per speed (computed).
    p05_speed : float or None
        Lowest speed from which P(SS > 0.5) <= 5 % [rad/s] (computed; None without a crossing).
    """
    speeds: np.ndarray
    ss: np.ndarray
    label: str = ""
    first_sample: int = 0

    def __post_init__(self):
        st = _core.severity_statistics(self.ss, list(self.speeds), 0.5, 0.05, 0.05, 0.95)
        self.mean, self.q05, self.q95 = st.mean, st.q_low, st.q_high
        self.p_stick_slip = st.p_exceed
        self.p05_speed = None if math.isnan(st.p_speed) else float(st.p_speed)

    @property
    def band_width(self) -> np.ndarray:
        """Width of the 90 % band (q95 - q05) of SS per speed [-]."""
        return self.q95 - self.q05

    def to_json(self) -> dict:
        """JSON-ready summary: label, top speeds [rad/s], sample count, mean, q05, q95 and
        P(SS > 0.5) per speed (rounded to 4 decimals), ``p05_speed_rad_s`` and
        ``band_width_integral``, the integral of q95 - q05 over the speeds [rad/s] (trapezoid
        rule; 0 for a single speed)."""
        return {"label": self.label, "top_speeds_rad_s": self.speeds.tolist(), "samples": int(self.ss.shape[0]),
                "mean_ss": self.mean.round(4).tolist(), "q05_ss": self.q05.round(4).tolist(),
                "q95_ss": self.q95.round(4).tolist(), "p_ss_above_0_5": self.p_stick_slip.round(4).tolist(),
                "p05_speed_rad_s": self.p05_speed,
                "band_width_integral": float(_trapezoid(self.band_width, self.speeds)) if self.speeds.size > 1 else 0.0}


def severity_study(cfg: dict, speeds, samples: int, *, model: str = "SM_CB2", delta=0.1, case=None,
                   structural: bool = True, eta=None, eta_psd=None, eta_dt: float = ETA_DT_S,
                   seed: int = 1, first_sample: int = 0, label: str = "", progress: bool = True,
                   threads: int = 0) -> SeverityStudy:
    """SS of ``samples`` realizations at each top speed [rad/s] (constant WOB of the configuration).

    ``structural=False`` keeps the mean structure. ``eta_psd`` (a PSD, e.g. ``THESIS_PSD``) or
    ``eta`` (array (samples, n) sampled every ``eta_dt`` s) adds the bit-rock uncertainty (Eq. 4.1).
    The law, WOB, time step, duration, transient and top drive are the configuration's: a controlled
    drive (``top_drive.type = "controlled"``, docs/control.md) is tuned once, on the nominal string (the
    first natural frequency of the mean reduced model and the top section's impedance), and every
    realization runs with those gains (the rotating-frame coupling of Eq. 2.9 with the mean model's top
    load and top-torque recovery).

    Every run starts from the string at rest (Eq. 2.10; random samples keep the mean model's
    initial generalized velocity); realization i of the matrices and of eta is the same at every
    top speed (common random numbers). ``samples x speeds`` runs in all, in parallel.

    Realizations ``first_sample .. first_sample + samples - 1`` run, so a study can be computed
    in chunks: chunks stacked in sample order equal one run over all samples bit for bit.

    Parameters
    ----------
    cfg : dict
        Configuration (e.g. ``load_config(preset="thesis-ch6")``), with Craig-Bampton modes for
        SM_CB1 / SM_CB2.
    speeds : array_like
        Top speeds [rad/s].
    samples : int
        Number of realizations, >= 1.
    model : str
        Structural stochastic model: "SM_full", "SM_CB1" or "SM_CB2" (default).
    delta : float, dict or array_like
        Dispersions of the random matrices [-] (:func:`drillpy.uncertainty.frf.dispersions`;
        default 0.1).
    case : int, optional
        Case study 1-7 (Tables 6.1-6.7) instead of ``delta``.
    structural : bool
        False: every sample uses the mean structure (bit-rock uncertainty alone).
    eta : array_like, optional
        Torque fluctuation series [-], one row per sample (row r for realization
        ``first_sample + r``), shape (samples, n), sampled every ``eta_dt`` seconds from t = 0.
        Not together with ``eta_psd``.
    eta_psd : PsdModel, PsdTable or callable, optional
        One-sided PSD of eta per Hz [1/Hz] (e.g. ``THESIS_PSD``, Eq. 4.4): eta generated in the
        engine, sample i the same as in :func:`~drillpy.uncertainty.montecarlo.stochastic_study`
        with the same seed.
    eta_dt : float
        Sampling step of eta [s] (default 0.05 s).
    seed : int
        Random seed.
    first_sample : int
        Index of the first realization, 0 to 2^62; row r of ``ss`` is realization
        ``first_sample + r``.
    label : str
        Name of the study (progress bar, legend, JSON).
    progress : bool
        Show a tqdm progress bar.
    threads : int
        OpenMP threads (0: the OpenMP default).

    Returns
    -------
    SeverityStudy
        SS per sample and speed with its statistics.
    """
    sp = np.atleast_1d(np.asarray(speeds, dtype=float))
    validate.integer("samples", samples, 1)
    first = validate.integer("first_sample", first_sample, 0, 2**62)
    if eta is not None and eta_psd is not None:
        raise ValueError("give either eta or eta_psd, not both")
    S = None if eta_psd is None else psd_on_grid(eta_psd, eta_dt, Configuration.of(cfg).simulation.duration_s)[1]
    sm = stochastic_model(cfg, model, delta, case)
    eta_arg = None if eta is None else np.ascontiguousarray(eta, dtype=float)
    with progress_bar(samples * sp.size, label or "SS under structural uncertainty", progress) as cb:
        ss = sm.severity_samples(list(sp), int(samples), int(seed), bool(structural), eta_arg, S, float(eta_dt), cb,
                                 threads, first)
    return SeverityStudy(speeds=sp, ss=np.asarray(ss), label=label, first_sample=first)


def severity_sources(cfg: dict, speeds, samples: int, *, delta=0.1, eta_psd=None, eta_dt: float = ETA_DT_S,
                     seed: int = 1, progress: bool = True, threads: int = 0, runner=None) -> dict:
    """How much each source widens the SS band: the deterministic string, structural uncertainty
    (SM_CB2 with ``delta``), and, when ``eta_psd`` is given, the stochastic bit-rock law alone
    (mean structure) and both together (same eta and same matrices per sample).

    Parameters
    ----------
    cfg : dict
        Configuration (e.g. ``load_config(preset="thesis-ch6")``).
    speeds : array_like
        Top speeds [rad/s].
    samples : int
        Realizations per random study (the deterministic one runs one sample).
    delta : float, dict or array_like
        SM_CB2 dispersions [-] (default 0.1).
    eta_psd : PsdModel, PsdTable or callable, optional
        One-sided PSD of eta per Hz [1/Hz]; without it only the first two studies run.
    eta_dt : float
        Sampling step of eta [s].
    seed : int
        Random seed (shared by all studies).
    progress : bool
        Show tqdm progress bars.
    threads : int
        OpenMP threads (0: the OpenMP default).
    runner : callable, optional
        Runs one study with :func:`severity_study`'s signature (default :func:`severity_study`;
        ``drillpy robust-ss --out/--scheduler`` passes one that stores and distributes it).

    Returns
    -------
    dict
        Label -> :class:`SeverityStudy`: "deterministic", "structure (SM_CB2)" and, with
        ``eta_psd``, "bit-rock (eta)" and "structure + bit-rock".
    """
    run = runner or severity_study
    kw = dict(seed=seed, progress=progress, threads=threads)
    out = {"deterministic": run(cfg, speeds, 1, delta=0.0, structural=False, label="deterministic", **kw),
           "structure (SM_CB2)": run(cfg, speeds, samples, delta=delta, label="structure (SM_CB2)", **kw)}
    if eta_psd is not None:
        out["bit-rock (eta)"] = run(cfg, speeds, samples, delta=0.0, structural=False, eta_psd=eta_psd,
                                    eta_dt=eta_dt, label="bit-rock (eta)", **kw)
        out["structure + bit-rock"] = run(cfg, speeds, samples, delta=delta, eta_psd=eta_psd, eta_dt=eta_dt,
                                          label="structure + bit-rock", **kw)
    return out


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
        label -> the study's JSON with the :func:`drillpy.uncertainty.robust_speed.robust_speed_summary` entries.
    """
    from drillpy.uncertainty.robust_speed import robust_speed_summary
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
