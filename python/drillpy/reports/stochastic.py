"""The stochastic analysis of chapter 4: figures like Figs. 4.2-4.9 and C.1 and a ``mc.json``
summary in an output folder (used by ``drillpy mc --out``).

Compute, plot and write are apart (as python-control's ``TimeResponseData`` and ``timeplot``):
:func:`drillpy.uncertainty.stochastic.stochastic_analysis` runs what the figures show and returns a
:class:`~drillpy.uncertainty.stochastic.StochasticAnalysis`;
:func:`drillpy.figures.stochastic.stochastic_figures` draws it; :func:`write_stochastic` writes
``mc.json``. :func:`write_figures` composes the three.

Every study written with ``--out`` also leaves ``mc_samples.json`` (:func:`write_samples`): the SS
of every sample, exact, so chunks run apart (``--first-sample``) merge into the study run at once
(:func:`merge_outputs`, ``drillpy mc-merge``).
"""
from __future__ import annotations

import json
from pathlib import Path

from drillpy.outputs import write_text
from drillpy.uncertainty.montecarlo import ETA_DT_S, StochasticStudy, merge_studies
from drillpy.uncertainty.process import THESIS_PSD, Psd
from drillpy.jsonio import dumps
from drillpy.provenance import provenance
from drillpy.uncertainty.stochastic import StochasticAnalysis, stochastic_analysis


def write_stochastic(result: StochasticAnalysis, out_dir) -> dict:
    """Write ``mc.json``: the study's summary, the figures' numbers, the configuration and the provenance.

    Parameters
    ----------
    result : StochasticAnalysis
        What :func:`drillpy.uncertainty.stochastic.stochastic_analysis` returned.
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


def write_summary(study: StochasticStudy, out_dir, summary: dict) -> Path:
    """Write a study without its figures (``drillpy mc --out --no-figures``): ``mc.json`` (``summary``,
    the configuration and the provenance) and ``mc_samples.json`` (:func:`write_samples`).

    Parameters
    ----------
    study : StochasticStudy
        A finished study (or chunk of one).
    out_dir : str or Path
        Output folder (created if missing).
    summary : dict
        The study's summary (:meth:`~drillpy.uncertainty.montecarlo.StochasticStudy.summary`, with the
        robust speed's entries, :func:`drillpy.uncertainty.robust_speed.robust_speed_summary`).

    Returns
    -------
    Path
        The ``mc.json`` written.
    """
    write_samples(study, out_dir)
    path = Path(out_dir, "mc.json")
    write_text(path, dumps({**summary, "config": study.config, "provenance": provenance(
        seed=study.seed, samples=int(study.severity.shape[0]), first_sample=study.first_sample)}))
    return path


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

    :func:`drillpy.uncertainty.stochastic.stochastic_analysis` -> :func:`drillpy.figures.stochastic.stochastic_figures` ->
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
        As for :func:`drillpy.uncertainty.stochastic.stochastic_analysis`.
    out_dir : str or Path
        Output folder (created if missing).
    figure_units : str
        Axis units of the figures (``si`` or ``field``, :data:`drillpy.figures.simulation.FIGURE_UNITS`);
        ``mc.json`` stays SI.

    Returns
    -------
    dict
        What the figures show (:attr:`drillpy.uncertainty.stochastic.StochasticAnalysis.info`).
    """
    from drillpy.figures.stochastic import stochastic_figures
    result = stochastic_analysis(study, cfg, psd=psd, eta_dt=eta_dt, phase_cycles=phase_cycles,
                                 threads=threads, progress=progress)
    stochastic_figures(result, out_dir, figure_units)
    write_stochastic(result, out_dir)
    return result.info
