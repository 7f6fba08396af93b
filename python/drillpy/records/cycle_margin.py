"""How far the rig model's stick-slip cycle sits from its edge in WOB, against the record's own WOB range.

The thesis's laws scale with the WOB (section 3.3), and so does their velocity weakening: below some WOB
the calibrated rig model no longer sticks. A model calibrated near that edge loses its cycle on a window
whose WOB trend is a little lower, though the rig keeps sticking there (docs/records.md, section 4,
"Another split": calibrated on 10-30 s of sample 175, no stick phase on 30-40 s at 5 % less WOB). This
module measures the edge on the calibration part itself: the model's long run with the part's WOB trend
scaled by :data:`FACTORS`, beside the record's own blocks of :data:`BLOCK_S` (their mean WOB and stick
fraction), and flags a model that stops sticking within :data:`MARGIN` of the part's WOB: the record's
own 5 s blocks vary by about that much (sample 175: 505-603 N about a mean of 561 N, every block sticking),
so a window it will be asked to predict may well sit there.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from .io import Record
from . import rig_comparison, rigsim

#: The WOB trend's scale factors of the model's long runs.
FACTORS = (0.85, 0.9, 0.95, 1.0, 1.05, 1.1)
#: Length of the record's blocks [s].
BLOCK_S = rig_comparison.BLOCK_S
#: A stick fraction below this counts as no stick phase: a cycle lost.
NO_STICK = 0.01
#: A model that has no stick phase at this factor of the part's WOB or above is flagged as marginal.
MARGIN = 0.9


def record_blocks(record: Record, stick_threshold: float, block_s: float = BLOCK_S) -> list:
    """The record's consecutive blocks of ``block_s``: their mean WOB and regular stick fraction
    (:func:`drillpy.records.rig_comparison.record_metrics`, stalls left out).

    Parameters
    ----------
    record : Record
        A cleaned record with a WOB channel.
    stick_threshold : float
        Bit speed at or below which the bit is stuck [rad/s].
    block_s : float
        Block length [s]; a last block shorter than half of it is left out.

    Returns
    -------
    list of dict
        ``window_s`` [s], ``wob_n`` [N], ``stick_fraction`` [-] per block.
    """
    t0, t1 = float(record.time_s[0]), float(record.time_s[-1])
    out = []
    for a in np.arange(t0, t1 - 0.5 * block_s, block_s):
        piece = record.select(a, min(a + block_s, t1))
        m = rig_comparison.record_metrics(piece, stick_threshold, float(piece.time_s[0]), np.zeros(len(piece), bool),
                                          phase=False)
        out.append({"window_s": [float(piece.time_s[0]), float(piece.time_s[-1])],
                    "wob_n": float(rigsim.operating_point(piece).get("wob_n", np.nan)),
                    "stick_fraction": float(m["stick_fraction"])})
    return out


def model_runs(model: rigsim.RigModel, record: Record, stick_threshold: float, factors=FACTORS) -> list:
    """The model's long runs over ``record`` (:func:`drillpy.records.rigsim.simulate_model`) with the
    record's WOB, and so its WOB trend, scaled by each factor.

    Parameters
    ----------
    model : RigModel
        The rig model.
    record : Record
        The calibration part.
    stick_threshold : float
        [rad/s].
    factors : sequence of float
        Scale factors of the WOB.

    Returns
    -------
    list of dict
        ``wob_factor``, ``wob_n`` (the scaled record's mean WOB [N]), ``ss`` and ``stick_fraction``
        of the run (NaN where it fails), and ``blocks``, the run's own blocks (:func:`record_blocks`:
        the model's mean WOB and stick fraction per block; empty where it fails).
    """
    op = rigsim.operating_point(record)
    out = []
    for f in factors:
        scaled = dataclasses.replace(record, wob=record.wob * f)
        try:
            sim = rigsim.simulate_model(model, scaled)
            m = rig_comparison.compare(scaled, sim, stick_threshold).simulated
            ss, stick = float(m["ss"]), float(m["stick_fraction"])
            blocks = record_blocks(sim, stick_threshold)
        except (ValueError, RuntimeError):
            ss = stick = float("nan")
            blocks = []
        out.append({"wob_factor": float(f), "wob_n": float(op.get("wob_n", np.nan) * f), "ss": ss,
                    "stick_fraction": stick, "blocks": blocks})
    return out


def wob_slope(blocks: list) -> float:
    """The least-squares slope of the blocks' stick fraction against their mean WOB, per 100 N [1/(100 N)]:
    how much more of the time the bit sticks per 100 N more WOB. NaN with fewer than 3 blocks or no
    spread in their WOB.

    Parameters
    ----------
    blocks : list of dict
        :func:`record_blocks` of the record or of a model's run.

    Returns
    -------
    float
        The slope per 100 N.
    """
    pts = [(b["wob_n"], b["stick_fraction"]) for b in blocks
           if np.isfinite(b["wob_n"]) and np.isfinite(b["stick_fraction"])]
    if len(pts) < 3:
        return float("nan")
    w, st = np.array(pts).T
    if np.ptp(w) <= 0:
        return float("nan")
    return float(100.0 * np.polyfit(w, st, 1)[0])


def cycle_margin(model: rigsim.RigModel, record: Record, stick_threshold: float) -> dict:
    """The model's stick-slip cycle against the WOB (:func:`model_runs`) beside the record's blocks
    (:func:`record_blocks`), and a flag when the model has no stick phase (a stick fraction below
    :data:`NO_STICK`) at :data:`MARGIN` of the part's WOB or above while it sticks at the part's own.

    Parameters
    ----------
    model : RigModel
        The calibrated rig model.
    record : Record
        The calibration part (with a WOB channel).
    stick_threshold : float
        [rad/s].

    Returns
    -------
    dict
        ``model`` (:func:`model_runs`), ``record_blocks``, ``lost_below_factor`` (the highest factor of
        the WOB below 1 at which the model has no stick phase, None if it sticks at every factor),
        ``lost_at_wob_n`` (that WOB [N], None likewise), ``flag`` (str or None) and
        ``wob_slope_per_100n``: :func:`wob_slope` of the record's blocks and of the model's own blocks in
        its run at the part's WOB (how much the stick fraction follows the WOB inside the part itself).
    """
    runs = model_runs(model, record, stick_threshold)
    blocks = record_blocks(record, stick_threshold)
    at_one = [r for r in runs if r["wob_factor"] == 1.0]
    lost = [r for r in runs if r["stick_fraction"] < NO_STICK and r["wob_factor"] < 1.0]
    top = max(lost, key=lambda r: r["wob_factor"]) if lost else None
    out = {"model": runs, "record_blocks": blocks, "lost_below_factor": top["wob_factor"] if top else None,
           "lost_at_wob_n": top["wob_n"] if top else None, "flag": None,
           "wob_slope_per_100n": {"record": wob_slope(blocks),
                                  "model": wob_slope(at_one[0]["blocks"]) if at_one else float("nan")}}
    if top is not None and top["wob_factor"] >= MARGIN and at_one and at_one[0]["stick_fraction"] >= NO_STICK:
        wobs = [b["wob_n"] for b in blocks if np.isfinite(b["wob_n"])]
        sticks = [b["stick_fraction"] for b in blocks]
        out["flag"] = (f"the model's stick-slip cycle is marginal: no stick phase at {100 * (1 - top['wob_factor']):.0f} % "
                       f"less WOB ({top['wob_n']:.0f} N), while the record's {BLOCK_S:g} s blocks stick at "
                       f"{min(wobs):.0f}-{max(wobs):.0f} N (stick fractions {min(sticks):.3f}-{max(sticks):.3f}): "
                       "a window of a little less WOB would be predicted without stick-slip")
    return out


def slope_statement(slopes: dict | None) -> str | None:
    """One sentence on how much the stick fraction follows the WOB inside the calibration part: the
    ``wob_slope_per_100n`` of :func:`cycle_margin` for the model's own blocks and the record's.

    Parameters
    ----------
    slopes : dict or None
        ``{"model": slope, "record": slope}`` per 100 N (None, or NaN slopes: no sentence).

    Returns
    -------
    str or None
        The sentence, or None.
    """
    if not slopes or not all(np.isfinite(slopes.get(k, np.nan)) for k in ("model", "record")):
        return None
    return (f"over the part's {BLOCK_S:g} s blocks the model's stick fraction rises {slopes['model']:+.3f} per 100 N of "
            f"WOB, the record's {slopes['record']:+.3f}")


def margin_lines(margin: dict) -> list:
    """The log lines of :func:`cycle_margin`'s result: :func:`slope_statement` and the flag, if any.

    Parameters
    ----------
    margin : dict
        :func:`cycle_margin`'s result.

    Returns
    -------
    list of str
    """
    out = [x for x in (slope_statement(margin.get("wob_slope_per_100n")),) if x]
    return out + (["flagged: " + margin["flag"]] if margin.get("flag") else [])


def window_note(margin: dict | None, wob_n: float) -> str | None:
    """A note for a prediction on a window of mean WOB ``wob_n`` [N] by a model whose calibration part
    showed ``margin`` (:func:`cycle_margin`, kept in ``model.json`` -> ``calibration`` -> ``cycle_margin``):
    the window's WOB is at or below the WOB at which the model had no stick phase, so a prediction of
    little or no stick-slip there is the model's edge, not the rig's (docs/records.md, section 4).

    Parameters
    ----------
    margin : dict or None
        The calibration's cycle margin (None: a model file written before it).
    wob_n : float
        The predicted window's mean WOB [N].

    Returns
    -------
    str or None
        The note, or None.
    """
    lost = None if not margin else margin.get("lost_at_wob_n")
    if lost is None or not np.isfinite(wob_n) or wob_n > lost:
        return None
    return (f"the window's mean WOB ({wob_n:.0f} N) is at or below the WOB at which this model had no stick phase on "
            f"its calibration part ({lost:.0f} N, {100 * (1 - margin['lost_below_factor']):.0f} % below that part's): "
            "its prediction of the stick-slip here is at the model's edge, not the rig's")
