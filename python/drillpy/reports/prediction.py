"""The outputs of ``drillpy predict``: a :class:`drillpy.loop.prediction.Prediction` written with its figure."""
from __future__ import annotations

from pathlib import Path

from drillpy.figures import records as figs
from drillpy.jsonio import write_json
from drillpy.loop.prediction import Prediction, describe
from drillpy.provenance import provenance


def write_prediction(pred: Prediction, out_dir: str | Path, figure_units: str = "si") -> list:
    """``summary.json`` and the overlay figure ``overlay.png`` in ``out_dir``; returns the file names.

    Parameters
    ----------
    pred : Prediction
        From :func:`drillpy.loop.prediction.predict_record`.
    out_dir : str or Path
        Output folder (created if needed; existing files are overwritten).
    figure_units : str
        Axis unit of the overlay's torque (``si``: N m; ``field``: ft-lbf); ``summary.json`` stays SI.

    Returns
    -------
    list of str
        The names of the files written, relative to ``out_dir``.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    write_json(out / "summary.json", {**pred.summary(), "provenance": provenance()})
    fig = out / "overlay.png"
    figs.prediction_overlay_plot(fig, pred.measured, pred.simulated, pred.stick_threshold,
                                  describe(pred.model), units=figure_units)
    return ["summary.json", fig.name]
