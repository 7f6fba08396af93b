"""``drillpy calibrate``'s output folder: ``posterior.json`` and the figures of a Bayesian calibration."""
from __future__ import annotations

from pathlib import Path

from drillpy.calibration.posterior import calibrate_record


def calibrate_to_folder(record, out, **options) -> dict:
    """Calibrate (:func:`drillpy.calibration.posterior.calibrate_record`) and write ``out``:
    ``posterior.json``, ``marginals.png``, ``pair.png`` (the most probable family's first two
    parameters) and ``predictive.png``.

    Parameters
    ----------
    record : str or Path or Record
        The record.
    out : str or Path
        Output folder (created if missing).
    **options
        Passed to :func:`~drillpy.calibration.posterior.calibrate_record`.

    Returns
    -------
    dict
        ``Posterior.summary()`` with ``files`` (the paths written).
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
    return s
