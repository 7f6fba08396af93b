"""The stochastic analysis of chapter 4: figures like Figs. 4.2-4.9 and C.1 and a ``mc.json``
summary in an output folder (used by ``drillpy mc --out``).

Compute, plot and write are apart (as python-control's ``TimeResponseData`` and ``timeplot``):
:func:`stochastic_analysis` runs what the figures show and returns a :class:`StochasticAnalysis`;
:func:`drillpy.figures.stochastic.stochastic_figures` draws it; :func:`write_stochastic` writes
``mc.json``. :func:`write_figures` composes the three.

Every study written with ``--out`` also leaves ``mc_samples.json`` (:func:`write_samples`): the SS
of every sample, exact, so chunks run apart (``--first-sample``) merge into the study run at once
(:func:`merge_outputs`, ``drillpy mc-merge``).
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from drillpy.outputs import write_text
from drillpy.uncertainty.montecarlo import (ETA_DT_S, PhaseStudy, StochasticStudy, merge_studies, phase_study,
                                            stochastic_run)
from drillpy.uncertainty.process import THESIS_PSD, Psd, PsdFit, fit_eta, generate, welch
from drillpy.model.simulation import SimulationResult, simulate
from drillpy.model.config import with_overrides
from drillpy.jsonio import dumps
from drillpy.provenance import provenance

FIT_RECORD_S = 2000.0  #: length of the generated eta record fitted for Figs. 4.2-4.3 [s]
RESPONSE_WINDOW_S = 60.0  #: last part of the runs shown in Figs. 4.5-4.6 [s]


@dataclass
class StochasticAnalysis:
    """What the figures of chapter 4 show for a finished study (:func:`stochastic_analysis`).

    Attributes
    ----------
    study : StochasticStudy
        The Monte Carlo study of SS versus top speed (Figs. 4.8-4.9, C.1).
    config : dict
        Configuration of the runs.
    psd : Psd
        PSD [1/Hz, one-sided] the eta records are generated from.
    eta_dt_s : float
        Time step of the eta records [s].
    fit_record_s : float
        Length of the generated eta record whose PSD is fitted [s].
    eta_t_s : ndarray
        Time of the generated eta records [s], shape (n,).
    eta : ndarray
        Two independent realizations of eta [-], shape (2, n).
    psd_fit : PsdFit
        Fit of Eq. (4.4) to the Schuster periodogram of ``eta[0]``.
    freq_hz, periodogram : ndarray
        Schuster periodogram of ``eta[0]``: frequency [Hz] and one-sided PSD [1/Hz].
    welch_freq_hz, welch_psd : ndarray
        Welch periodogram of ``eta[0]`` (2048-point segments): frequency [Hz], PSD [1/Hz].
    top_speed_rad_s : float
        Top speed of the single runs and of the phase study [rad/s].
    stochastic : SimulationResult
        One stochastic run from rest at ``top_speed_rad_s`` (Fig. 4.5).
    deterministic : SimulationResult
        The deterministic run at the same speed, 200 s with 100 s transient (Fig. 4.6).
    window_s : (float, float)
        Time window shown in Figs. 4.5-4.6 [s]: the last ``RESPONSE_WINDOW_S`` of the stochastic run.
    phases : PhaseStudy
        Stick and slip durations [s] pooled over samples (Fig. 4.7).
    info : dict
        The JSON-ready numbers of the figures (``mc.json``'s ``figures``): ``psd_fit`` (record_s [s],
        f0_hz [Hz], A0, a, b, rms_log_residual) and ``phases`` (top_speed_rad_s, cycles, samples,
        stick_mean_s / slip_mean_s [s], deterministic_period_cycles, deterministic_stick_s /
        deterministic_slip_s [s]).
    """
    study: StochasticStudy
    config: dict
    psd: Psd
    eta_dt_s: float
    fit_record_s: float
    eta_t_s: np.ndarray
    eta: np.ndarray
    psd_fit: PsdFit
    freq_hz: np.ndarray
    periodogram: np.ndarray
    welch_freq_hz: np.ndarray
    welch_psd: np.ndarray
    top_speed_rad_s: float
    stochastic: SimulationResult
    deterministic: SimulationResult
    window_s: tuple
    phases: PhaseStudy
    info: dict = field(default_factory=dict)


def stochastic_analysis(study: StochasticStudy, cfg: dict, *, psd: Psd = THESIS_PSD, eta_dt: float = ETA_DT_S,
                        phase_cycles: int = 750, threads: int = 0, progress: bool = True) -> StochasticAnalysis:
    """Run what the figures of chapter 4 show, for a finished study (nothing is drawn or written).

    Parameters
    ----------
    study : StochasticStudy
        A finished study (:func:`drillpy.uncertainty.montecarlo.stochastic_study`); its seed seeds
        every run here.
    cfg : dict
        Configuration of the study.
    psd : Psd
        PSD of eta [1/Hz, one-sided] (default: the thesis's field model).
    eta_dt : float
        Time step of the eta records [s].
    phase_cycles : int
        Stick-slip cycles collected by the phase study (Fig. 4.7).
    threads : int
        Engine threads (0: all cores).
    progress : bool
        Show a progress bar during the phase study.

    Returns
    -------
    StochasticAnalysis
        The generated eta records and their PSD fit, one stochastic and one deterministic run at
        the configuration's top speed, the phase study and the numbers for ``mc.json``.
    """
    seed = study.seed
    t, eta = generate(psd, dt=eta_dt, duration=FIT_RECORD_S, samples=2, seed=seed)
    fit, f, S = fit_eta(eta[0], eta_dt, method="schuster")
    fw, Sw = welch(eta[0], eta_dt, segment=2048)
    m = fit.model
    info: dict = {"psd_fit": {"record_s": FIT_RECORD_S, "f0_hz": m.f0, "A0": m.A0, "a": m.a, "b": m.b,
                              "rms_log_residual": fit.rms_log_residual}}

    om = float(cfg["operation"]["top_speed_rad_s"])
    sto, _, _ = stochastic_run(cfg, om, seed, psd=psd, eta_dt=eta_dt)
    det = simulate(with_overrides(cfg, duration=200.0, transient=100.0), om)
    t_end = float(sto.t[-1])

    ph = phase_study(cfg, om, seed=seed, cycles=phase_cycles, psd=psd, eta_dt=eta_dt,
                     threads=threads, progress=progress)
    info["phases"] = {
        "top_speed_rad_s": om, "cycles": int(ph.stick.size), "samples": ph.samples,
        "stick_mean_s": float(ph.stick.mean()) if ph.stick.size else None,
        "slip_mean_s": float(ph.slip.mean()) if ph.slip.size else None,
        "deterministic_period_cycles": ph.deterministic_period_cycles,
        "deterministic_stick_s": ph.deterministic_stick.tolist(),
        "deterministic_slip_s": ph.deterministic_slip.tolist()}
    return StochasticAnalysis(study=study, config=cfg, psd=psd, eta_dt_s=eta_dt, fit_record_s=FIT_RECORD_S,
                              eta_t_s=t, eta=eta, psd_fit=fit, freq_hz=f, periodogram=S, welch_freq_hz=fw,
                              welch_psd=Sw, top_speed_rad_s=om, stochastic=sto, deterministic=det,
                              window_s=(t_end - RESPONSE_WINDOW_S, t_end), phases=ph, info=info)


def write_stochastic(result: StochasticAnalysis, out_dir) -> dict:
    """Write ``mc.json``: the study's summary, the figures' numbers, the configuration and the provenance.

    Parameters
    ----------
    result : StochasticAnalysis
        What :func:`stochastic_analysis` returned.
    out_dir : str or Path
        Output folder (created if missing).

    Returns
    -------
    dict
        The content of ``mc.json``.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    js = {**result.study.summary(), "figures": result.info, "config": result.study.config}
    prov = provenance(seed=result.study.seed, samples=int(result.study.severity.shape[0]))
    write_text((out / "mc.json"), dumps({**js, "provenance": prov}))
    write_samples(result.study, out)
    return js


SAMPLES_FILE = "mc_samples.json"  #: per-sample SS of a study, in its output folder


def write_samples(study: StochasticStudy, out_dir) -> Path:
    """Write ``mc_samples.json``: the SS of every sample at every speed and what rebuilds the study.

    Parameters
    ----------
    study : StochasticStudy
        A finished study (or chunk of one).
    out_dir : str or Path
        Output folder (created if missing).

    Returns
    -------
    Path
        The file written.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    prov = provenance(seed=study.seed, samples=int(study.severity.shape[0]), first_sample=study.first_sample)
    path = out / SAMPLES_FILE
    write_text(path, dumps({**study.samples_dict(), "provenance": prov}, indent=None))
    return path


def read_samples(path) -> StochasticStudy:
    """Read a study written by :func:`write_samples` (a folder or the file itself).

    Parameters
    ----------
    path : str or Path
        ``mc_samples.json`` or the folder holding it.

    Returns
    -------
    StochasticStudy
        The study, bit-identical to the one written.

    Raises
    ------
    ValueError
        One line naming the file: missing, not JSON, or not a samples file.
    """
    p = Path(path)
    if p.is_dir():
        p = p / SAMPLES_FILE
    if not p.is_file():
        raise ValueError(f"chunk = {str(path)!r}: no {SAMPLES_FILE} there (written by drillpy mc --out)")
    try:
        d = json.loads(p.read_text())
    except (UnicodeDecodeError, json.JSONDecodeError) as e:
        raise ValueError(f"chunk = {str(p)!r}: not a JSON samples file ({e})") from None
    if not isinstance(d, dict):
        raise ValueError(f"chunk = {str(p)!r}: not a samples file (a JSON object is expected)")
    try:
        return StochasticStudy.from_samples_dict(d)
    except ValueError as e:
        raise ValueError(f"chunk = {str(p)!r}: {e}") from None


def merge_outputs(chunks, out_dir=None, figure_units: str = "si") -> StochasticStudy:
    """Merge chunks of one study (``drillpy mc-merge``) and write the merged outputs.

    Parameters
    ----------
    chunks : sequence of str or Path
        Output folders (or ``mc_samples.json`` files) of ``drillpy mc --out`` runs of the same
        study with different ``--first-sample``.
    out_dir : str or Path, optional
        Folder for the merged ``mc.json`` (summary, configuration, provenance with the chunks),
        ``mc_samples.json``, severity_band.png (Fig. 4.9) and conv1.png (Fig. C.1).
    figure_units : str
        Axis units of the figures (``si`` or ``field``, :data:`drillpy.figures.simulation.FIGURE_UNITS`).

    Returns
    -------
    StochasticStudy
        The merged study (:func:`drillpy.uncertainty.montecarlo.merge_studies`).
    """
    study = merge_studies([read_samples(c) for c in chunks])
    if out_dir is not None:
        from drillpy.figures.stochastic import conv1_plot, severity_band_plot
        out = Path(out_dir)
        out.mkdir(parents=True, exist_ok=True)
        prov = provenance(seed=study.seed, samples=int(study.severity.shape[0]),
                          chunks=[str(c) for c in chunks])
        write_text((out / "mc.json"), dumps({**study.summary(), "config": study.config, "provenance": prov}))
        write_samples(study, out)
        severity_band_plot(out / "severity_band.png", study, units=figure_units)
        conv1_plot(out / "conv1.png", study.conv1)
    return study


def write_figures(study: StochasticStudy, cfg: dict, out_dir, *, psd: Psd = THESIS_PSD,
                  eta_dt: float = ETA_DT_S, phase_cycles: int = 750, threads: int = 0,
                  progress: bool = True, figure_units: str = "si") -> dict:
    """Compute, draw and write the chapter-4 outputs of a finished study (``drillpy mc --out``).

    :func:`stochastic_analysis` -> :func:`drillpy.figures.stochastic.stochastic_figures` ->
    :func:`write_stochastic`. Files written to ``out_dir``:

    * psd_fit.png (Figs. 4.2-4.3): Schuster and Welch periodograms of a generated
      ``FIT_RECORD_S``-second eta record and the fit of Eq. (4.4) to it;
    * eta_realizations.png (Fig. 4.4); stochastic_response.png (Fig. 4.5);
    * deterministic_vs_stochastic.png (Fig. 4.6); phase_pdfs.png (Fig. 4.7, ``phase_cycles``
      cycles at the configuration's top speed);
    * severity_band.png (Figs. 4.8-4.9), conv1.png (Fig. C.1) and mc.json.

    Parameters
    ----------
    study, cfg, psd, eta_dt, phase_cycles, threads, progress
        As for :func:`stochastic_analysis`.
    out_dir : str or Path
        Output folder (created if missing).
    figure_units : str
        Axis units of the figures (``si`` or ``field``, :data:`drillpy.figures.simulation.FIGURE_UNITS`);
        ``mc.json`` stays SI.

    Returns
    -------
    dict
        What the figures show (:attr:`StochasticAnalysis.info`).
    """
    from drillpy.figures.stochastic import stochastic_figures
    result = stochastic_analysis(study, cfg, psd=psd, eta_dt=eta_dt, phase_cycles=phase_cycles,
                                 threads=threads, progress=progress)
    stochastic_figures(result, out_dir, figure_units)
    write_stochastic(result, out_dir)
    return result.info
