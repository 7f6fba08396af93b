"""The outputs of the uncertainty commands: the chapter-6 study written with its figures, one FRF
envelope, the robust severity per source of uncertainty.

:func:`chapter6_report` composes :func:`drillpy.uncertainty.chapter6.chapter6_study` ->
:func:`drillpy.figures.frf.chapter6_figures` -> :func:`write_chapter6` (``summary.json``);
:func:`print_conclusions` prints the verdicts of :func:`drillpy.uncertainty.chapter6.conclusions`.
"""
from __future__ import annotations

from pathlib import Path

from drillpy.outputs import write_text
from drillpy.provenance import provenance
from drillpy.jsonio import dumps
from drillpy.uncertainty.chapter6 import Chapter6Study, chapter6_study


def print_conclusions(rows: list[dict]) -> None:
    """Print each verdict of :func:`drillpy.uncertainty.chapter6.conclusions` as "[holds] claim" or "[does NOT hold] claim",
    followed by its evidence (every key but ``claim``, ``holds`` and ``test``), one per line.

    Parameters
    ----------
    rows : list of dict
        The verdicts returned by :func:`drillpy.uncertainty.chapter6.conclusions` (or the ``conclusions`` of a chapter-6
        ``summary.json``).
    """
    for r in rows:
        print(f"[{'holds' if r['holds'] else 'does NOT hold'}] {r['claim']}")
        for k, v in r.items():
            if k not in ("claim", "holds", "test"):
                print(f"    {k}: {v}")


def write_chapter6(study: Chapter6Study, out_dir, **options) -> dict:
    """Write ``summary.json`` of the chapter-6 study.

    Parameters
    ----------
    study : Chapter6Study
        What :func:`drillpy.uncertainty.chapter6.chapter6_study` returned.
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

    :func:`drillpy.uncertainty.chapter6.chapter6_study` -> :func:`drillpy.figures.frf.chapter6_figures` ->
    :func:`write_chapter6`.

    Parameters
    ----------
    cfg, samples, mode_samples, seed, freq_hz, modes, progress, threads
        As for :func:`drillpy.uncertainty.chapter6.chapter6_study`.
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


def write_robust_severity(out_dir, speeds, studies: dict, summary: dict, cfg: dict, *, figure_units: str = "si",
                          **options) -> Path:
    """Write the outputs of :func:`drillpy.uncertainty.structural.robust_severity` (``drillpy robust-ss --out``).

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
