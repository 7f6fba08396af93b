"""A calibrated model applied to a record it was not calibrated on (``drillpy predict``).

The model is either a rig model (``drillpy analyze --calibrate``: format ``drillpy.rig_model``) or
a loop model (``drillpy loop``: format ``drillpy.loop_model``, the declared model with its
calibrated parameters and effects). Two checks, both on the record's own data only through its
operating point (reliable mean top speed and mean WOB, or its measured top speed for a drive that
follows it; see :func:`drillpy.records.rigsim.simulate_model` and :func:`drillpy.loop.longrun.simulate_record`):

* **long run**: the model simulated over the whole record, its stick-slip metrics (SS Eq. 3.4,
  stick fraction, cycle frequency, torque percentiles) against the measured ones;
* **short horizons**: the error E of docs/loop.md, the model restarted every ``horizon_s`` from
  the measured state and integrated over the horizon,
  E = sqrt(1/2 [mean (v_pred - v)^2 / sd_v^2 + mean (T_pred - T)^2 / sd_T^2]) over every horizon
  of the record (sd_v, sd_T the standard deviations over the record's first half).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from drillpy import loop
from drillpy.records import rigsim
from drillpy.records import rig_comparison
from drillpy.records import rig_fluctuation
from drillpy.records.cycle_margin import window_note
from drillpy.jsonio import jsonable
from drillpy.records.cleaning import clean
from drillpy.model.config import read_json
from drillpy.loop.effects import stripped
from drillpy.loop.longrun import simulate_record
from drillpy.loop.model import wob_errors
from drillpy.loop.run import analysis_config
from drillpy.records.io import Flag, Record, read_record


@dataclass
class Prediction:
    """What :func:`predict_record` returns: the model, the measured and simulated records, their
    comparison, the short-horizon error and the stick threshold used [rad/s].

    Attributes
    ----------
    model : RigModel or LoopModel
        The model applied (unchanged: nothing is refitted).
    measured : Record
        The record as cleaned (and windowed) for the prediction.
    simulated : Record
        The long-run simulation on the record's time grid, through the rig's 10 Hz filter for a
        rig model; ``provenance`` holds the motor command and the operating point.
    comparison : RigComparison
        Long-run stick-slip metrics, measured against predicted
        (:func:`drillpy.records.rig_comparison.compare`).
    short_horizon_error : float
        E of docs/loop.md over every horizon of the record [-]: 0 is perfect, 1 is as far off as
        the record's own spread.
    stick_threshold : float
        Bit speed at or below which the bit counted as stuck [rad/s], 5 % of the median reliable
        top speed of the predicted record itself.
    intervals : dict or None
        Predictive intervals of the long-run metrics over realizations of the rig model's torque
        fluctuation, Eq. (4.1) (:func:`drillpy.records.rig_fluctuation.predictive`); None for a
        model without one.
    wob_horizon_error : float or None
        The WOB's error over the same horizons, on the WOB's spread [-], for a model whose WOB is a
        state (the jack) on a record with a WOB channel, else None: a rig model's on its calibration
        part's spread (:func:`short_horizon_error` with ``channels="wob"``), a loop model's on the
        spread over the predicted record's first part (:func:`drillpy.loop.model.wob_errors`).
    notes : list of str
        What the numbers need beside them: a rig model applied to a window whose mean WOB is at or
        below the WOB at which it had no stick phase on its calibration part
        (:func:`drillpy.records.cycle_margin.window_note`).
    """
    model: "rigsim.RigModel | loop.LoopModel"
    measured: Record
    simulated: Record
    comparison: rig_comparison.RigComparison
    short_horizon_error: float
    stick_threshold: float
    intervals: dict | None = None
    wob_horizon_error: float | None = None
    notes: list = field(default_factory=list)

    def summary(self) -> dict:
        """The ``--json`` output (and ``summary.json``)."""
        m, s = self.comparison.measured, self.comparison.simulated

        def pair(k):
            return {"measured": m[k], "predicted": s[k], "relative_error": rig_comparison.relative_error(s[k], m[k])}

        return jsonable({
            "short_horizon_error": self.short_horizon_error, "wob_horizon_error": self.wob_horizon_error,
            "long_run": {"ss": pair("ss"), "stick_fraction": pair("stick_fraction"),
                         "cycle_frequency_hz": pair("cycle_frequency_hz"),
                         "torque_p05_p95_nm": {"measured": [m["torque_p5"], m["torque_p95"]],
                                               "predicted": [s["torque_p5"], s["torque_p95"]]},
                         "mean_top_speed_rad_s": pair("mean_top_speed"),
                         "top_speed_std_rad_s": pair("top_speed_std"), "wob_std_n": pair("wob_std"),
                         "median_period_s": pair("median_period_s"), "top_in_phase": pair("top_in_phase"),
                         "stalls": {"measured": m["stalls"], "predicted": s["stalls"]},
                         "mismatch": self.comparison.mismatch},
            "predictive": self.model.predictive,
            "model": describe(self.model), "command_rad_s": self.simulated.provenance.get("command_rad_s"),
            "operating_point": self.simulated.provenance.get("operating_point"),
            "record": {"source": str(self.measured.provenance.get("source")),
                       "window_s": [float(self.measured.time_s[0]), float(self.measured.time_s[-1])],
                       "artifacts": artifacts(self.measured)},
            "stick_threshold_rad_s": self.stick_threshold,
            "predictive_intervals": self.intervals, "notes": list(self.notes)})


def artifacts(record: Record) -> dict:
    """What the cleaning flagged in each channel of a cleaned record: the samples excluded from the
    comparison (unreliable or non-finite), the samples repaired (interpolated spikes and gaps, an
    artifact stretch of the top speed replaced by the bit speed) and the kinds of artifact found
    (:func:`drillpy.records.cleaning.clean`'s report, ``provenance["cleaning"]["by_channel"]``).

    Parameters
    ----------
    record : Record
        A record as :func:`drillpy.records.cleaning.clean` returns it.

    Returns
    -------
    dict
        ``{channel: {"excluded_samples", "repaired_samples", "kinds"}}`` for every channel with a
        flagged sample (empty: nothing flagged).
    """
    kinds = record.provenance.get("cleaning", {}).get("by_channel", {})
    out = {}
    for name in record.channels:
        excluded = int((~record.valid(name)).sum())
        repaired = int(record.flagged(name, Flag.REPAIRED).sum())
        if excluded or repaired or kinds.get(name):
            out[name] = {"excluded_samples": excluded, "repaired_samples": repaired, "kinds": dict(kinds.get(name, {}))}
    return out


def describe(model) -> str:
    """One line naming a model's kind and its parts.

    Parameters
    ----------
    model : RigModel or LoopModel
        A model from :func:`load_model`.

    Returns
    -------
    str
        ``"rig model: <drive> drive, damping ratio <z>"`` or
        ``"loop model: effects <names>, damping ratios <ratios>"`` (and the long run's torque
        fluctuation of Eq. 4.1 when the model carries one).
    """
    if isinstance(model, loop.LoopModel):
        note = "" if model.predictive else " (a diagnosis: fed a recorded channel that carries the cycle)"
        fl = ("" if model.fluctuation is None else
              f", long run with the torque fluctuation of Eq. (4.1) (std {model.fluctuation['std']:.3g})")
        return (f"loop model{note}: effects {', '.join(model.effects) or 'none'}, damping ratios "
                f"{model.damping_ratios}{fl}")
    if model.drive == "rig":
        return f"rig model: the rig modelled whole (motor, jack, platform), damping ratio {model.damping_ratio:.3g}"
    note = " (a diagnosis: fed the measured top speed)" if model.drive == "measured" else ""
    return f"rig model: {model.drive} drive{note}, damping ratio {model.damping_ratio:.3g}"


def _loop_model_at(model: "loop.LoopModel", record: Record, data) -> "loop.LoopModel":
    """A loop model at a record's operating point (its reliable mean top speed for the ideal drive,
    its mean WOB) on the analysis time grid; nothing is refitted."""
    m = model.copy()
    op = rigsim.operating_point(record)
    m.top_speed = op["top_speed_rad_s"]
    m.wob = op.get("wob_n", m.wob)
    m.cfg = analysis_config(m.cfg, data.dt)
    return m


def _timing_option(model) -> str | tuple:
    """``LoopOptions.channel_timing`` of a model: the skew its file keeps (the acquisition's, read on its
    calibration record), or ``"none"``."""
    ct = model.channel_timing
    return "none" if ct is None else (ct["top_lead_s"], ct["torque_lag_s"])


def _loop_prediction(model: "loop.LoopModel", rec: Record, thr: float, horizon_s: float, threads: int) -> tuple:
    # the law takes the same kind of WOB as in the calibration (the recorded WOB, or its trend), and the
    # channels are read at the calibration's timing (the acquisition's skew is the rig's, not the record's)
    opt = loop.LoopOptions(horizon_s=horizon_s, threads=threads, wob_input=model.wob_input,
                           channel_timing=_timing_option(model))
    data = loop.prepare(rec, model.engine_config(), opt, scale=model.metric_scale)
    m = _loop_model_at(model, rec, data)
    sim = simulate_record(m, data)
    ev = loop.evaluate(m, data, threads)
    # the WOB's error of a model whose WOB is a state, on the WOB's spread over the record's first part (a
    # loop model file keeps no WOB spread)
    e_w = float(math.sqrt(np.mean(wob_errors(ev.wob, data)))) if "axial_jack" in m.effects and data.has_wob else None
    return sim, float(math.sqrt(np.mean(ev.e_h))), e_w


#: What :func:`short_horizon_error` scores: the loop's E (bit speed, torque and top speed), the WOB alone, or all.
HORIZON_CHANNELS = ("loop", "wob", "all")


def short_horizon_error(model: rigsim.RigModel, record: Record, command: float, horizon_s: float = 0.25,
                        threads: int = 0, channels: str = "loop") -> float:
    """E of docs/loop.md over every horizon of ``record`` (restarted from the measured state).

    The rig model is expressed as a loop model (the motor drive as the ``motor`` variant of
    ``top_drive_dynamics``, the measured drive as its ``measured`` variant, the whole rig's jack as
    ``axial_jack``: its WOB state restarted from the recorded WOB and relaxed towards the WOB's
    trend) at the record's operating point, restarted from the measured bit speed, acceleration,
    torque and top speed at the start of every horizon and integrated over it. The horizons have no
    platform and no motor torque limit: the torque they predict is the contact torque. The record is
    read at the model's channel timing (``model.channel_timing``: the acquisition's skew, as the loop
    reads it; None: as recorded). E = sqrt(mean of the per-horizon normalized squared errors), 0 perfect, 1 as far off as the spread of the
    model's calibration window (``calibration.metric_scale``; a model file without it: the first
    half of ``record``), the scale the loop's E is on.

    Parameters
    ----------
    model : RigModel
        The rig model.
    record : Record
        The cleaned record, with bit speed, torque on bit and top speed.
    command : float
        Top-drive speed or motor command Omega_c [rad/s] of the long run
        (``provenance["command_rad_s"]`` of :func:`drillpy.records.rigsim.simulate_model`).
    horizon_s : float
        Length of each horizon [s].
    threads : int
        Engine threads (0: the OpenMP default).
    channels : str
        ``"loop"``: E over the bit speed, the torque and the top speed, the loop's criterion and
        issue 28's; ``"wob"``: the WOB alone, the jack's state against the recorded WOB (on the
        calibration's WOB spread, ``metric_scale["wob_n"]``; a model file without it: the record's
        first half); ``"all"``: every channel the record has, the WOB one more beside the loop's (the
        rig calibration's objective, :func:`drillpy.records.rig_calibration.calibrate_rig`).

    Returns
    -------
    float
        E [-].
    """
    if channels not in HORIZON_CHANNELS:
        raise ValueError(f"channels = {channels!r}: use one of {', '.join(HORIZON_CHANNELS)}")
    data, ev = rig_horizons(model, record, command, horizon_s, threads)
    if channels == "loop" or (channels == "all" and not data.has_wob):
        return float(math.sqrt(np.mean(ev.e_h)))
    sc = model.calibration.get("metric_scale")
    e_w = wob_errors(ev.wob, data, None if sc is None else sc.get("wob_n"))
    if channels == "wob":
        return float(math.sqrt(np.mean(e_w)))
    n = 3 if data.has_top else 2  # e_h is the mean over the loop's channels
    return float(math.sqrt(np.mean((n * ev.e_h + e_w) / (n + 1))))


def rig_horizons(model: rigsim.RigModel, record: Record, command: float, horizon_s: float = 0.25,
                 threads: int = 0) -> tuple:
    """The horizons :func:`short_horizon_error` scores: the rig model as a loop model at the record's
    operating point (see there), the record prepared at the model's channel timing and scale.

    Parameters
    ----------
    model : RigModel
        The rig model.
    record : Record
        The cleaned record, with bit speed, torque on bit and top speed.
    command : float
        Top-drive speed or motor command Omega_c [rad/s] of the long run.
    horizon_s : float
        Length of each horizon [s].
    threads : int
        Engine threads (0: the OpenMP default).

    Returns
    -------
    tuple
        (:class:`drillpy.loop.data.LoopData`, :class:`drillpy.loop.model.Evaluation`): the prepared
        record and every horizon's predictions (bit speed, torque, top speed, WOB) with their errors.
    """
    op = rigsim.operating_point(record)
    wob = op.get("wob_n", model.law["wob_ref_n"])
    # the jack's set force is the record's slow WOB trend, as in the long run (rigsim.simulate_model): never
    # the recorded WOB, which carries the cycle, whatever the record's length
    opt = loop.LoopOptions(horizon_s=horizon_s, threads=threads, channel_timing=_timing_option(model), wob_input="trend")
    cfg = model.config(command, wob)
    sc = model.calibration.get("metric_scale")
    data = loop.prepare(record, cfg, opt, scale=None if sc is None else (sc["bit_speed_rad_s"], sc["torque_on_bit_nm"]))
    cfg = analysis_config(stripped(cfg), data.dt)
    effects = {}
    if model.drive in ("motor", "rig"):
        effects["top_drive_dynamics"] = {"variant": "motor", "droop_rad_s_per_nm": 1.0 / model.motor_slope_nms_rad,
                                         "inertia_kg_m2": model.motor_inertia_kg_m2, "command_rad_s": command}
        if model.drive == "rig" and model.coupling_stiffness_nm_rad is not None:
            effects["top_drive_dynamics"]["coupling_stiffness_nm_rad"] = model.coupling_stiffness_nm_rad
    elif model.drive == "measured":
        effects["top_drive_dynamics"] = {"variant": "measured"}
    if model.drive == "rig" and model.jack_gain_n_rad is not None:
        effects["axial_jack"] = {"gain_n_rad": model.jack_gain_n_rad, "relaxation_s": model.jack_relaxation_s}
    lm = loop.LoopModel(cfg, dict(getattr(model, "engine_law", model.law)), op["top_speed_rad_s"], wob, effects)
    return data, loop.evaluate(lm, data, threads)


def predict_record(model, record: Record | str | Path, *, t0: float | None = None,
                   t1: float | None = None, horizon_s: float = 0.25, threads: int = 0, realizations: int = 100,
                   seed: int = 0) -> Prediction:
    """Apply ``model`` (a :class:`~drillpy.records.rigsim.RigModel` or a :class:`~drillpy.loop.LoopModel`) to
    a record (path or Record, cleaned here) without refitting anything.

    The model runs at the record's own operating point (reliable mean top speed and mean WOB,
    or the measured top speed for a drive that follows it); the stick threshold is 5 % of the
    record's median reliable top speed. ``drillpy predict`` calls this.

    Parameters
    ----------
    model : RigModel or LoopModel
        From :func:`load_model` (``model.json`` of ``drillpy analyze --calibrate`` or
        ``drillpy loop``).
    record : Record, str or Path
        The record or its file, with bit speed, torque on bit and top speed.
    t0, t1 : float, optional
        Window of the record to predict [s], both ends included; None: open on that side.
    horizon_s : float
        Horizon of the short-horizon error E [s].
    threads : int
        Engine threads (0: the OpenMP default).
    realizations : int
        Realizations of a rig model's torque fluctuation (Eq. 4.1) behind the predictive
        intervals (a model without one: none are drawn).
    seed : int
        Their seed.

    Returns
    -------
    Prediction

    Raises
    ------
    ValueError
        If a needed channel is missing, the window is empty, or the record cannot be cleaned or
        has no reliable top speed.
    """
    raw = read_record(record) if isinstance(record, (str, Path)) else record
    for need in ("bit_speed", "torque_on_bit", "top_speed"):
        raw.channel(need)
    if t0 is not None or t1 is not None:
        raw = raw.select(t0, t1)
    rec, _ = clean(raw)
    thr = rigsim.stick_threshold(rec)
    if isinstance(model, loop.LoopModel):
        sim, E, E_w = _loop_prediction(model, rec, thr, horizon_s, threads)
        return Prediction(model, rec, sim, rig_comparison.compare(rec, sim, thr, t_start=0.0), E, thr,
                          wob_horizon_error=E_w)
    sim = rigsim.simulate_model(model, rec)
    cmp = rig_comparison.compare(rec, sim, thr)
    E = short_horizon_error(model, rec, sim.provenance["command_rad_s"], horizon_s, threads)
    E_w = short_horizon_error(model, rec, sim.provenance["command_rad_s"], horizon_s, threads, "wob") \
        if rec.wob is not None and model.jack_gain_n_rad is not None else None  # the jack's WOB state
    iv = rig_fluctuation.predictive(model, rec, thr, realizations, seed) if model.torque_fluctuation else None
    note = window_note(model.calibration.get("cycle_margin"), rigsim.operating_point(rec).get("wob_n", math.nan))
    return Prediction(model, rec, sim, cmp, E, thr, iv, E_w, [note] if note else [])


def load_model(path: str | Path):
    """A model from ``model.json``: a rig model (``drillpy analyze --calibrate``) or a loop model
    (``drillpy loop``).

    Parameters
    ----------
    path : str or Path
        The JSON file; ``format = "drillpy.loop_model"`` gives a loop model, anything else is
        read as a rig model (``drillpy.rig_model``).

    Returns
    -------
    RigModel or LoopModel

    Raises
    ------
    ValueError
        If the file cannot be read or is not a model.
    """
    d = read_json(path, "model")
    if isinstance(d, dict) and d.get("format") == "drillpy.loop_model":
        return loop.LoopModel.from_dict(d)
    return rigsim.RigModel.from_dict(d)
