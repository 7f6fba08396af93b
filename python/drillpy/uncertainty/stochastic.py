"""What the figures of chapter 4 show, computed for a finished Monte Carlo study (nothing drawn or
written): generated eta records and their PSD fit, one stochastic and one deterministic run, the
phase study.

:func:`stochastic_analysis` returns a :class:`StochasticAnalysis`;
:func:`drillpy.figures.stochastic.stochastic_figures` draws it and
:func:`drillpy.reports.stochastic.write_stochastic` writes its ``mc.json``.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from drillpy.model.config import with_overrides
from drillpy.model.configuration import Configuration
from drillpy.model.simulation import SimulationResult, simulate
from drillpy.uncertainty.montecarlo import ETA_DT_S, PhaseStudy, StochasticStudy, phase_study, stochastic_run
from drillpy.uncertainty.process import THESIS_PSD, Psd, PsdFit, fit_eta, generate, welch


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

    om = float(Configuration.of(cfg).operation.top_speed_rad_s)
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
