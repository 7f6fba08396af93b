"""``drillpy calibrate``'s output folder: ``posterior.json`` and the figures of a Bayesian calibration."""
from __future__ import annotations

from pathlib import Path

from drillpy.calibration.posterior import calibrate_record


def calibrate_to_folder(record, out, *, map_grids=None, map_samples: int = 40, **options) -> dict:
    """Calibrate (:func:`drillpy.calibration.posterior.calibrate_record`) and write ``out``:
    ``posterior.json``, ``marginals.png``, ``pair.png`` (the most probable family's first two
    parameters) and ``predictive.png``; with ``map_grids`` also the posterior stability map
    (:func:`drillpy.calibration.stability.stability_map`, :func:`write_map`).

    Parameters
    ----------
    record : str or Path or Record
        The record.
    out : str or Path
        Output folder (created if missing).
    map_grids : tuple of array_like, optional
        (motor commands [rad/s], WOB [N]) of the stability map; None: no map.
    map_samples : int
        Monte Carlo samples of the map (posterior draw and eta realization each).
    **options
        Passed to :func:`~drillpy.calibration.posterior.calibrate_record` (its ``seed``, ``threads``,
        ``scheduler`` and ``chunk`` also to the map).

    Returns
    -------
    dict
        ``Posterior.summary()`` with ``files`` (the paths written) and, with a map, ``stability_map``
        (the :class:`~drillpy.calibration.stability.StabilityMap`).
    """
    from drillpy.figures.calibration import marginals_plot, pair_plot, predictive_plot
    from drillpy.jsonio import dumps
    post = calibrate_record(record, **options)
    s = post.summary()
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    files = [out / "posterior.json"]
    files[0].write_text(dumps(s))
    marginals_plot(out / "marginals.png", s)
    files.append(out / "marginals.png")
    best = max(s["families"], key=lambda f: s["model_probability"][f])
    names = list(s["priors"]["families"][best])
    if len(s["particles"][best]["weight"]) > 1:
        pair_plot(out / "pair.png", s, best, names[0], names[2])
        files.append(out / "pair.png")
    if s["predictive"]:
        predictive_plot(out / "predictive.png", s)
        files.append(out / "predictive.png")
    s["files"] = [str(f) for f in files]
    if map_grids is not None:
        smap, written = map_to_folder(s, out, map_grids, samples=map_samples, seed=options.get("seed", 0),
                                      threads=options.get("threads", 0), scheduler=options.get("scheduler"),
                                      chunk=options.get("chunk"))
        s["files"] += written
        s["stability_map"] = smap
    return s


def map_to_folder(posterior, out, grids, **options) -> tuple:
    """The posterior stability map of a calibration (:func:`drillpy.calibration.stability.stability_map`),
    written into ``out`` when given (:func:`write_map`).

    Parameters
    ----------
    posterior : str or Path or dict
        A calibration's ``posterior.json`` (or its dict).
    out : str or Path or None
        Output folder (created if missing); None: nothing written.
    grids : tuple of array_like
        (motor commands [rad/s], WOB [N]).
    **options
        Passed to :func:`~drillpy.calibration.stability.stability_map` (``samples``, ``seed``,
        ``threads``, ``scheduler``, ``chunk``...).

    Returns
    -------
    tuple
        (StabilityMap, list of the paths written).
    """
    from drillpy.calibration.stability import stability_map
    smap = stability_map(posterior, *grids, **options)
    if out is None:
        return smap, []
    Path(out).mkdir(parents=True, exist_ok=True)
    return smap, write_map(smap, out)


def write_map(smap, out) -> list:
    """Write a posterior stability map into ``out``: ``map.zarr`` (:meth:`StabilityMap.save`) and
    ``map.png`` (:func:`drillpy.figures.calibration.posterior_map_plot`).

    Parameters
    ----------
    smap : drillpy.calibration.stability.StabilityMap
        The map.
    out : str or Path
        Output folder (exists).

    Returns
    -------
    list of str
        The paths written.
    """
    from drillpy.figures.calibration import posterior_map_plot
    out = Path(out)
    files = [smap.save(out / "map.zarr")]
    posterior_map_plot(out / "map.png", smap)
    files.append(out / "map.png")
    return [str(f) for f in files]


def summary_lines(s: dict) -> list:
    """The text of a calibration's summary: the run, each family's probability with its Monte Carlo
    standard error and its parameters' medians and 90 % intervals against their priors, the
    posterior predictive 90 % intervals against the measured values, the files written.

    Parameters
    ----------
    s : dict
        :func:`calibrate_to_folder`'s summary.

    Returns
    -------
    list of str
        One line each, as ``drillpy calibrate`` prints them.
    """
    run, pred = s["run"], s["predictive"]
    here = " in this process" if (run.get("backend") or {}).get("backend") == "dask" else ""
    cpu = f", {run['cpu_s']:.0f} s of processor time{here}" if run.get("cpu_s") is not None else ""
    lines = [f"{run['abc_simulations']} simulations in {run['wall_s']:.1f} s ({run['simulations_per_s']:.1f}/s, "
             f"{_backend(run)}{cpu}), {run['generations']} generations, final eps {run['eps'][-1]:.3g} "
             f"({run['stopped']})"]
    disc = run.get("discrepancy") or {}
    if disc.get("factor"):
        lines.append(f"model discrepancy: {disc['factor']:g} x each statistic's window-to-window spread (noisy ABC); "
                     f"eps held at {disc['eps_floor']:.3g} and above")
    ess = (run.get("history") or [{}])[-1].get("model_ess")  # none in a posterior written before it
    for i, fam in enumerate(s["families"]):
        up = (s.get("model_choice") or {}).get("upper95", {}).get(fam)
        lines.append(f"P({fam}, Eq. {s['equations'][fam]}) = {s['model_probability'][fam]:.3f} "
                     f"+- {s['model_probability_se'][fam]:.3f} (Monte Carlo s.e."
                     + ("" if ess is None else f"; ESS of its particles {ess[i]:.1f}") + ")"
                     + ("" if up is None else f"; no particle left: below {up:.3f} at 95 %"))
        lines += [f"  {name}: {p['median']:.4g} [{p['ci90'][0]:.4g}, {p['ci90'][1]:.4g}] {p['unit']} "
                  f"(90 %; prior [{p['prior'][0]:g}, {p['prior'][1]:g}], width {p['width_ratio']:.2f} of it)"
                  for name, p in s["parameters"][fam].items()]
    mc = s.get("model_choice") or {}
    if mc and len(s["families"]) > 1:
        bf = "" if mc["bayes_factor"] is None else f", Bayes factor {mc['bayes_factor']:.3g} over {mc['runner_up']}"
        lines.append(f"model choice: {mc['family'] or 'cannot tell'} ({mc['reason']}; {mc['most_probable']} leads by "
                     f"{mc['lead']:.3f} +- {mc['lead_se']:.3f}{bf})")
    lines.append(f"posterior predictive 90 % intervals: {sum(v['contained'] for v in pred.values())} of "
                 f"{len(pred)} contain the measured value")
    lines += [f"  {name}: [{v['interval90'][0]:.4g}, {v['interval90'][1]:.4g}] {v['unit']}, measured "
              f"{v['measured']:.4g}{'' if v['contained'] else '  (outside)'}" for name, v in pred.items()]
    if "files" in s:
        lines.append("written: " + ", ".join(s["files"]))
    return lines


def _backend(run: dict) -> str:
    """Where the simulations ran: ``N threads`` or ``Dask SCHEDULER, N workers``."""
    b = run.get("backend") or {}
    if b.get("backend") == "dask":
        return f"Dask {b['scheduler']}, {b['workers']} worker{'s' if b['workers'] != 1 else ''}"
    return f"{run['threads']} threads"


def map_lines(m) -> list:
    """The text of a posterior stability map (:class:`drillpy.calibration.stability.StabilityMap`):
    P(SS > 0.5 or a stall) with its Wilson 90 % interval and P(stall), rows WOB, columns command.

    Parameters
    ----------
    m : StabilityMap

    Returns
    -------
    list of str
    """
    head = "| WOB [N] \\ command [rad/s] | " + " | ".join(f"{x:g}" for x in m.speeds) + " |"
    rule = "|---" * (m.speeds.size + 1) + "|"
    lines = [f"posterior stability map, {m.settings['samples']} samples (posterior draw and eta each), "
             f"{m.settings['failed_runs']} runs failed: P(SS > 0.5 or a stall) [Wilson 90 % interval]", head, rule]
    lines += [f"| {w:g} | " + " | ".join(f"{m.p_unstable[i, j]:.2f} [{m.ci90[0, i, j]:.2f}, {m.ci90[1, i, j]:.2f}]"
                                         for j in range(m.speeds.size)) + " |" for i, w in enumerate(m.wobs)]
    lines += ["P(stall)", head, rule]
    lines += [f"| {w:g} | " + " | ".join(f"{m.p_stall[i, j]:.2f}" for j in range(m.speeds.size)) + " |"
              for i, w in enumerate(m.wobs)]
    return lines
