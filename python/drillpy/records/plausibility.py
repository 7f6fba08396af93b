"""Plausibility warnings: a measured record checked against the declared model it is analysed with.

A record whose units are wrong reads without an error (a record in ms labelled ``time_s`` is a
valid record that happens to be 1000 times too slow) and gives numbers that look like results.
:func:`check_record` compares the record with what the declared string allows and returns a
:class:`PlausibilityWarning` for each contradiction; ``drillpy analyze`` and ``drillpy loop`` print
them on stderr (:func:`emit`) and write them into their JSON output and ``report.md``
(:func:`markdown`). A warning never stops an analysis: invalid data is refused elsewhere.

Checks (docs/records.md, "Plausibility warnings"), f1 and T1 = 1 / f1 the first natural frequency
and period of the declared string (:func:`drillpy.model.simulation.natural_frequencies`):

* ``time_unit``: sampling rate below 2 f1 or above :data:`MAX_SAMPLE_RATE_HZ`;
* ``duration``: a record shorter than :data:`MIN_DURATION_PERIODS` T1;
* ``top_speed``, ``bit_speed``: 99.5th percentile of |speed| above :data:`MAX_TOP_SPEED_RAD_S` or
  :data:`MAX_BIT_SPEED_RAD_S`, or a bit speed above :data:`MAX_BIT_TO_TOP_RATIO` times the median
  top speed;
* ``operating_point``: the median top speed more than :data:`OPERATING_POINT_FACTOR` times above or
  below the declared operating point (``operation.top_speed_rad_s``): RPM labelled rad/s is 9.5 times;
* ``torque``: 99.5th percentile of |torque on bit| above the torque that twists the strongest
  section of the declared string to a surface shear strain of :data:`MAX_SHEAR_STRAIN`;
* ``period``: median stick-slip cycle period outside :data:`PERIOD_RATIO_RANGE` times T1.
"""
from __future__ import annotations

import math
import sys
from dataclasses import dataclass

import numpy as np

from drillpy.model.configuration import Configuration
from drillpy.records import signals as sig
from drillpy.records.io import Record
from drillpy.records.stick import STICK_FRACTION, stick_threshold

#: Highest plausible sampling rate [Hz]. Drill-string speeds and torques are acquired at a few Hz
#: (surface logs) to a few kHz (downhole high-frequency recorders, lab rigs: the thesis's rig logs
#: at 1 kHz behind a 10 Hz filter); 100 kHz leaves a factor 10 above the fastest of them. A record
#: in s labelled ms is 1000 times too fast.
MAX_SAMPLE_RATE_HZ = 1.0e5
#: A record shorter than this many first natural periods cannot hold a stick-slip cycle (cycles
#: last about 1-3 first periods, and a period is measured between two cycles).
MIN_DURATION_PERIODS = 3.0
#: Highest plausible top-drive speed [rad/s] (about 2900 RPM). Rotary tables and top drives turn
#: at most a few hundred RPM (about 30 rad/s), downhole motors and turbines up to about 1500 RPM
#: (160 rad/s), lab rigs in the same range (sample 175: 15 rad/s); 300 rad/s is twice the fastest.
MAX_TOP_SPEED_RAD_S = 300.0
#: Highest plausible bit speed [rad/s]: three times :data:`MAX_TOP_SPEED_RAD_S`. In stick-slip the
#: bit peaks at about (1 + SS) times the mean top speed (SS of Eq. 3.4; sample 175: 1.26 over the
#: record), so this allows SS = 5 at twice the fastest drive.
MAX_BIT_SPEED_RAD_S = 3.0 * MAX_TOP_SPEED_RAD_S
#: The bit speed's 99.5th percentile may reach this many times the median top speed: (1 + SS) with
#: SS = 5 (sample 175: 2.4; SS 1.26 over the record, 4.6 in its most severe cycle). A bit speed in
#: RPM beside a top speed in rad/s gives about 20.
MAX_BIT_TO_TOP_RATIO = 6.0
#: Largest surface shear strain [-] of the string the torque may imply. Drill-string steels yield
#: in shear near 0.3-0.7 % (S-135 pipe: 540 MPa / 80 GPa = 0.68 %); a torque twisting the strongest
#: section of the declared string to 1 % would have yielded it. Equivalently: the section's
#: torsional stiffness G J / L times the largest twist it survives, 0.01 L / r_o. The rig's bar
#: (r = 2.5 mm) carries 21 N m at 1 %; sample 175 peaks at 4 N m.
MAX_SHEAR_STRAIN = 0.01
#: Plausible median stick-slip period in first natural periods of the declared string. Stick-slip
#: cycles last about 1-3 first periods (thesis's rig and field data; sample 175: 1.05): the slip
#: phase is about half a period of the first mode and the stick phase adds to it. Below 0.3 the
#: cycle is faster than the first mode can swing; above 10 the bit would stay stuck for 9 natural
#: periods in every cycle. A time unit off by 1000, or a model of another string, falls outside.
PERIOD_RATIO_RANGE = (0.3, 10.0)
#: A record's median top speed against the declared operating point: a factor above which the
#: record is not of that operation. A unit mix-up gives 9.55 (RPM labelled rad/s) or 60; the
#: thesis's field study spans 6-27 rad/s (a factor 4.5 end to end) around its 16 rad/s, so 4 in
#: either direction from the declared point keeps any speed of a sweep around it.
OPERATING_POINT_FACTOR = 4.0
#: Percentile of |channel| compared with the speed and torque bounds (isolated spikes stay below).
PERCENTILE = 99.5


@dataclass(frozen=True)
class PlausibilityWarning:
    """One contradiction between a record and its declared model.

    Attributes
    ----------
    code : str
        ``time_unit``, ``duration``, ``top_speed``, ``operating_point``, ``bit_speed``, ``torque`` or
        ``period``.
    channel : str
        The channel it concerns: ``time``, ``bit_speed``, ``top_speed`` or ``torque_on_bit``.
    message : str
        One line naming the channel, the value, the plausible range and the likely cause.
    value : float
        The measured value, in ``unit``.
    plausible : tuple of float
        (low, high) of the plausible range, in ``unit`` (``math.inf`` for an open end).
    unit : str
        Unit of ``value`` and ``plausible``: ``Hz``, ``s``, ``rad/s`` or ``N m``.
    """
    code: str
    channel: str
    message: str
    value: float
    plausible: tuple
    unit: str

    def as_dict(self) -> dict:
        """The warning as JSON-ready values (an open end of the range is ``None``).

        Returns
        -------
        dict
            ``code``, ``channel``, ``message``, ``value``, ``plausible`` ([low, high]) and ``unit``.
        """
        return {"code": self.code, "channel": self.channel, "message": self.message, "value": float(self.value),
                "plausible": [float(x) if math.isfinite(x) else None for x in self.plausible], "unit": self.unit}


def torque_capacity_nm(cfg: dict) -> float:
    """The torque [N m] that twists the strongest section of a string to :data:`MAX_SHEAR_STRAIN`.

    T = G gamma J / r_o with G = E / (2 (1 + nu)) and J = pi (r_o^4 - r_i^4) / 2: the largest
    torque any section of the string could carry without yielding, whatever its length.

    Parameters
    ----------
    cfg : dict
        A configuration (:func:`drillpy.model.config.load_config`); its ``string.sections`` give
        ``outer_radius_m``, ``inner_radius_m`` [m], ``youngs_modulus_pa`` [Pa] and ``poisson_ratio``.

    Returns
    -------
    float
        The torque [N m].
    """
    out = 0.0
    for s in Configuration.of(cfg).string.sections:
        ro, ri = float(s.outer_radius_m), float(s.inner_radius_m)
        g = float(s.youngs_modulus_pa) / (2.0 * (1.0 + float(s.poisson_ratio)))
        out = max(out, g * MAX_SHEAR_STRAIN * math.pi * (ro ** 4 - ri ** 4) / (2.0 * ro))
    return out


def cycle_period_s(record: Record) -> float | None:
    """Median period [s] of the record's valid stick-slip cycles, as ``drillpy analyze`` finds them.

    Cycles of :func:`drillpy.records.signals.segment_cycles` on the usable bit-speed samples, the
    bit stuck at or below 5 % of the median top speed (of the bit speed's 95th percentile without
    a top-speed channel).

    Parameters
    ----------
    record : Record
        The record (time [s], bit speed [rad/s]; top speed [rad/s] optional).

    Returns
    -------
    float or None
        The period [s]; None without a bit-speed channel or a valid cycle.
    """
    if record.bit_speed is None:
        return None
    ok = record.valid("bit_speed")
    if ok.sum() < 3:
        return None
    if record.top_speed is not None and record.valid("top_speed").any():
        thr = stick_threshold(record.top_speed[record.valid("top_speed")])
    else:
        thr = STICK_FRACTION * float(np.percentile(np.abs(record.bit_speed[ok]), 95))
    cyc = sig.segment_cycles(record.bit_speed, record.dt, thr, valid=ok)
    per = cyc.period_s[cyc.valid]
    return float(np.median(per)) if per.size else None


def _g(x: float) -> str:
    return f"{x:.4g}"


def _time_checks(rec: Record, f1: float, name: str) -> list:
    out = []
    rate, lo = rec.sample_rate_hz, 2.0 * f1
    if not lo <= rate <= MAX_SAMPLE_RATE_HZ:
        why = (f"below {_g(lo)} Hz, twice the first natural frequency {_g(f1)} Hz of the declared string "
               f"{name}: such a record cannot resolve the string's torsional oscillation" if rate < lo else
               f"above {_g(MAX_SAMPLE_RATE_HZ)} Hz, faster than any drill-string acquisition")
        hint = ""
        for factor, unit, label in ((1e3, "ms", "s"), (1e-3, "s", "ms")):
            if lo <= rate * factor <= MAX_SAMPLE_RATE_HZ:
                hint = f"; time stamps in {unit} labelled {label}? ({_g(rate * factor)} Hz then)"
        out.append(PlausibilityWarning(
            "time_unit", "time", f"time: sampling rate {_g(rate)} Hz (median interval {_g(rec.dt)} s) is {why}{hint}",
            rate, (lo, MAX_SAMPLE_RATE_HZ), "Hz"))
    dur, lo_d = rec.duration_s, MIN_DURATION_PERIODS / f1
    if dur < lo_d:
        out.append(PlausibilityWarning(
            "duration", "time", f"time: the record lasts {_g(dur)} s, less than {MIN_DURATION_PERIODS:g} first natural "
            f"periods ({_g(lo_d)} s) of the declared string {name}: too short to hold a stick-slip cycle (a record cut "
            "too short, or time stamps in s labelled ms?)", dur, (lo_d, math.inf), "s"))
    return out


def _percentile(rec: Record, name: str) -> float | None:
    x = getattr(rec, name)
    if x is None:
        return None
    ok = rec.valid(name)
    return float(np.percentile(np.abs(x[ok]), PERCENTILE)) if ok.any() else None


def _channel_checks(rec: Record, cfg: dict, name: str) -> list:
    out = []
    p = f"{PERCENTILE:g}th percentile of |{{}}|"
    top = _percentile(rec, "top_speed")
    if top is not None and top > MAX_TOP_SPEED_RAD_S:
        out.append(PlausibilityWarning(
            "top_speed", "top_speed", f"top_speed: {p.format('top speed')} {_g(top)} rad/s ({_g(top * 30 / math.pi)} "
            f"RPM) is above {_g(MAX_TOP_SPEED_RAD_S)} rad/s, beyond any top drive or downhole motor; a speed unit "
            "error (RPM labelled rad/s)?", top, (0.0, MAX_TOP_SPEED_RAD_S), "rad/s"))
    c = Configuration.of(cfg)
    declared = float(c.operation.top_speed_rad_s) if "operation" in c else 0.0
    if rec.top_speed is not None and rec.valid("top_speed").any() and declared > 0.0:
        med = float(np.median(np.abs(rec.top_speed[rec.valid("top_speed")])))
        ratio = med / declared
        if not 1.0 / OPERATING_POINT_FACTOR <= ratio <= OPERATING_POINT_FACTOR:
            out.append(PlausibilityWarning(
                "operating_point", "top_speed", f"top_speed: the median top speed {_g(med)} rad/s ({_g(med * 30 / math.pi)} "
                f"RPM) is {_g(ratio)} times the declared operating point {_g(declared)} rad/s of {name} (plausible "
                f"1/{OPERATING_POINT_FACTOR:g}-{OPERATING_POINT_FACTOR:g} times): a speed unit error (RPM labelled "
                "rad/s is 9.55 times), or a model of another operation?", med,
                (declared / OPERATING_POINT_FACTOR, declared * OPERATING_POINT_FACTOR), "rad/s"))
    bit = _percentile(rec, "bit_speed")
    if bit is not None:
        hi, why = MAX_BIT_SPEED_RAD_S, "beyond any drilling bit"
        if rec.top_speed is not None and rec.valid("top_speed").any():
            med = float(np.median(np.abs(rec.top_speed[rec.valid("top_speed")])))
            if MAX_BIT_TO_TOP_RATIO * med < hi:
                hi, why = MAX_BIT_TO_TOP_RATIO * med, (f"{MAX_BIT_TO_TOP_RATIO:g} times the median top speed "
                                                        f"{_g(med)} rad/s, beyond any stick-slip cycle")
        if bit > hi:
            out.append(PlausibilityWarning(
                "bit_speed", "bit_speed", f"bit_speed: {p.format('bit speed')} {_g(bit)} rad/s ({_g(bit * 30 / math.pi)} "
                f"RPM) is above {_g(hi)} rad/s, {why}; a speed unit error (RPM labelled rad/s)?", bit, (0.0, hi),
                "rad/s"))
    tq = _percentile(rec, "torque_on_bit")
    cap = torque_capacity_nm(cfg)
    if tq is not None and tq > cap:
        out.append(PlausibilityWarning(
            "torque", "torque_on_bit", f"torque_on_bit: {p.format('torque on bit')} {_g(tq)} N m is above {_g(cap)} N m, "
            f"the torque that twists the strongest section of the declared string {name} to a shear strain of "
            f"{100 * MAX_SHEAR_STRAIN:g} % (it would have yielded); a torque unit error (kN m labelled N m)?",
            tq, (0.0, cap), "N m"))
    return out


def check_record(record: Record, cfg: dict) -> list:
    """The plausibility warnings of a record analysed with a declared model.

    Checks the sampling rate and duration against the declared string's first natural frequency,
    the speeds and the torque on bit against physical bounds, and the median stick-slip period
    against the first natural period (module docstring; the bounds are the module's constants).
    Speeds and torques are compared by the 99.5th percentile of their usable samples, so isolated
    spikes of a record as read do not count; pass the cleaned record when there is one.

    Parameters
    ----------
    record : Record
        The measured record (SI units: time [s], speeds [rad/s], torque on bit [N m]); the
        channels it lacks are not checked.
    cfg : dict
        The declared model (:func:`drillpy.model.config.load_config`): its string sets the first
        natural frequency [Hz] and the torque capacity [N m].

    Returns
    -------
    list of PlausibilityWarning
        In the order time, speeds, torque, period; empty when everything is plausible.
    """
    from drillpy.model.simulation import natural_frequencies
    d = np.diff(record.time_s)
    if not np.any(np.isfinite(d) & (d > 0)):
        return []  # no time axis to check: the cleaning refuses such a record with its own error
    f1 = float(natural_frequencies(cfg, 1)[0])
    name = f"'{cfg.get('name', 'model')}'"
    out = _time_checks(record, f1, name) + _channel_checks(record, cfg, name)
    per = cycle_period_s(record)
    if per is not None:
        t1 = 1.0 / f1
        lo, hi = (r * t1 for r in PERIOD_RATIO_RANGE)
        if not lo <= per <= hi:
            out.append(PlausibilityWarning(
                "period", "bit_speed", f"bit_speed: the median stick-slip cycle period {_g(per)} s is {_g(per / t1)} "
                f"times the first natural period {_g(t1)} s ({_g(f1)} Hz) of the declared string {name}; stick-slip "
                f"cycles last about 1-3 first periods (plausible {PERIOD_RATIO_RANGE[0]:g}-{PERIOD_RATIO_RANGE[1]:g}: "
                f"{_g(lo)}-{_g(hi)} s): a wrong time unit, or a model of another string?", per, (lo, hi), "s"))
    return out


def emit(warnings: list, stream=None) -> None:
    """Print each warning as one ``drillpy: warning: <message>`` line.

    Written with :func:`tqdm.tqdm.write`, so that a progress bar on the same stream stays intact.

    Parameters
    ----------
    warnings : list of PlausibilityWarning
        The warnings (:func:`check_record`).
    stream : file-like, optional
        Where to write (default ``sys.stderr``).
    """
    from tqdm import tqdm
    for w in warnings:
        tqdm.write(f"drillpy: warning: {w.message}", file=stream or sys.stderr)


def markdown(warnings: list) -> list:
    """The ``## Warnings`` section of a ``report.md``: one item per warning, ``none`` when none.

    Parameters
    ----------
    warnings : list of PlausibilityWarning or dict
        The warnings, or their :meth:`PlausibilityWarning.as_dict` (as in the JSON outputs).

    Returns
    -------
    list of str
        Markdown lines, ending with an empty line.
    """
    items = [w["message"] if isinstance(w, dict) else w.message for w in warnings]
    return ["## Warnings", "", *([f"- {m}" for m in items] or ["none"]), ""]
