"""The stochastic analysis of chapter 4 in one call: figures like Figs. 4.2-4.9 and C.1 and a
``mc.json`` summary in an output folder (used by ``drillpy mc --out``)."""
from __future__ import annotations

import json
from pathlib import Path

from drillpy.figures import simulation as plotting
from drillpy.figures import stochastic as figs
from drillpy.uncertainty.montecarlo import ETA_DT_S, StochasticStudy, phase_study, stochastic_run
from drillpy.uncertainty.process import THESIS_PSD, Psd, fit_eta, generate, welch
from drillpy.model.simulation import simulate
from drillpy.model.config import with_overrides

FIT_RECORD_S = 2000.0  #: length of the generated eta record fitted for Figs. 4.2-4.3 [s]


def write_figures(study: StochasticStudy, cfg: dict, out_dir, *, psd: Psd = THESIS_PSD,
                  eta_dt: float = ETA_DT_S, phase_cycles: int = 750, threads: int = 0,
                  progress: bool = True) -> dict:
    """Write the figures of chapter 4 for a finished study and return what they show.

    * psd_fit.png (Figs. 4.2-4.3): Schuster and Welch periodograms of a generated
      ``FIT_RECORD_S``-second eta record and the fit of Eq. (4.4) to it;
    * eta_realizations.png (Fig. 4.4); stochastic_response.png (Fig. 4.5);
    * deterministic_vs_stochastic.png (Fig. 4.6); phase_pdfs.png (Fig. 4.7, ``phase_cycles``
      cycles at the configuration's top speed);
    * severity_band.png (Figs. 4.8-4.9) and conv1.png (Fig. C.1).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    seed = study.seed
    info: dict = {}

    t, eta = generate(psd, dt=eta_dt, duration=FIT_RECORD_S, samples=2, seed=seed)
    fit, f, S = fit_eta(eta[0], eta_dt, method="schuster")
    fw, Sw = welch(eta[0], eta_dt, segment=2048)
    m = fit.model
    info["psd_fit"] = {"record_s": FIT_RECORD_S, "f0_hz": m.f0, "A0": m.A0, "a": m.a, "b": m.b,
                       "rms_log_residual": fit.rms_log_residual}
    figs.psd_fit(out / "psd_fit.png", f, S, m, S_welch=Sw, f_welch=fw,
                 target=psd if hasattr(psd, "f0") else None,
                 title=f"PSD of a generated {FIT_RECORD_S:g}-s eta record (Figs. 4.2-4.3)")
    figs.eta_realizations(out / "eta_realizations.png", t, eta, t_max=200.0)

    om = float(cfg["operation"]["top_speed_rad_s"])
    sto, _, _ = stochastic_run(cfg, om, seed, psd=psd, eta_dt=eta_dt)
    det = simulate(with_overrides(cfg, duration=200.0, transient=100.0), om)
    t_end = float(sto.t[-1])
    plotting.time_series(out / "stochastic_response.png", sto.t, sto.bit_speed, sto.torque_on_bit,
                         sto.top_speed, t_window=(t_end - 60.0, t_end),
                         title=f"One realization at {om:g} rad/s (Fig. 4.5)")
    figs.deterministic_vs_stochastic(out / "deterministic_vs_stochastic.png", det, sto,
                                     (t_end - 60.0, t_end))

    ph = phase_study(cfg, om, seed=seed, cycles=phase_cycles, psd=psd, eta_dt=eta_dt,
                     threads=threads, progress=progress)
    figs.phase_pdfs(out / "phase_pdfs.png", ph)
    info["phases"] = {
        "top_speed_rad_s": om, "cycles": int(ph.stick.size), "samples": ph.samples,
        "stick_mean_s": float(ph.stick.mean()) if ph.stick.size else None,
        "slip_mean_s": float(ph.slip.mean()) if ph.slip.size else None,
        "deterministic_period_cycles": ph.deterministic_period_cycles,
        "deterministic_stick_s": ph.deterministic_stick.tolist(),
        "deterministic_slip_s": ph.deterministic_slip.tolist()}

    figs.severity_band(out / "severity_band.png", study)
    figs.conv1_curve(out / "conv1.png", study.conv1)
    (out / "mc.json").write_text(json.dumps({**study.summary(), "figures": info,
                                             "config": study.config}, indent=2))
    return info

