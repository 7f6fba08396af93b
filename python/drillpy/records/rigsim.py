"""The test rig in simulation (beyond the thesis: its section 5.4 left this for future work).

The ``thesis-rig`` preset (Table 5.1: 1.7 m steel bar of radius 2.5 mm, 3.921 kg disk; first
frequency 2.89 Hz) with an identified bit-rock law (the non-regularized Eq. 5.1/5.3 law sticks:
the engine holds the bit while the string torque is below its static torque) and one of three
top-drive descriptions:

* ``constant``: the top turns at the record's reliable mean top speed (the thesis's clamped top);
* ``measured``: the top follows the measured top-speed signal;
* ``motor``: the rig's open-loop motor, J_m Omega' = c_m (Omega_c - Omega) - T_top
  (``drill/topdrive.hpp``), its command set so that the simulated mean top speed is the record's;
* ``rig``: the rig modelled whole (thesis chapter 5.1, 5.3.1) and self-contained: the open-loop motor
  with its own calibrated command (the rig's speed setting) and its 8 N m torque limit, the
  electrical jack's WOB as a state (``drill/axial.hpp``) driven by the record's slow WOB trend
  (below 0.5 Hz), the torque-on-bit platform's 20 Hz response (:func:`~drillpy.records.signals.
  platform_response`) and the string's GJ within the geometry's tolerance. Its inputs are constants
  and that slow trend: it predicts the cycle, the top speed's swing and the WOB's oscillation
  instead of being fed them, which makes it the predictive model (``measured`` is a diagnosis).

The simulated bit speed, top speed and torque go through the rig's 10 Hz acquisition filter
before they are compared with the measurement on SS, stick fraction, cycle frequency, torque
percentiles and the top speed's fluctuation (:func:`compare`). :func:`calibrate` chooses the
modal damping ratio (an *effective* value that lumps every dissipation the one-mode model lacks)
and the drive's parameters that match a calibration part of a record best; :func:`simulate_model`
runs a calibrated :class:`RigModel` at the operating point of any record (its reliable mean top
speed and mean WOB), which is how a model is checked on data it was not calibrated on.
"""
from __future__ import annotations

import copy
import math
import os
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np
from scipy import optimize

from drillpy.model.config import load_config, normalize
from drillpy.model.plausibility import fitted_values
from drillpy.records import stick as _stick
from drillpy.records.stick import STICK_FRACTION
from drillpy.records.io import Flag, Record
from drillpy.records.signals import (MeanCycle, derivative, mean_cycle, platform_response, rig_lowpass, segment_cycles,
                                     stick_slip_metrics)
from drillpy.model.simulation import simulate, simulate_many

#: Metrics compared between simulation and measurement (relative errors enter the mismatch).
MATCHED = ("ss", "stick_fraction", "cycle_frequency_hz", "bit_speed_p95", "torque_p5", "torque_p95",
           "top_speed_std")
#: What the whole rig model also predicts (the others take the WOB and the mean top speed as given).
MATCHED_RIG = ("ss", "stick_fraction", "median_period_s", "bit_speed_p95", "torque_p5", "torque_p95", "top_speed_std",
               "wob_std", "mean_top_speed")
DRIVES = ("constant", "measured", "motor", "rig")
#: The drives whose inputs are constants or slow signals: the candidates of a predictive model.
PREDICTIVE_DRIVES = ("constant", "motor", "rig")

#: Length of the coupling section between the drive and the bar (rig_config) [m].
COUPLING_LENGTH_M = 0.01
#: The rig's platform (rock holder and jack) natural frequency [Hz], thesis section 5.3.1.
PLATFORM_HZ = 20.0
#: The rig motor's torque limit [N m], thesis section 5.1 ("up to 300 RPM and 8 N m").
MOTOR_MAX_TORQUE_NM = 8.0
#: The jack's WOB trend: the record's WOB low-passed below this [Hz] (a slow input, not the cycle).
WOB_TREND_HZ = 0.5
#: A stick phase at least this long is a stall [s], reported apart from the regular cycle: about
#: 1.4 periods of the rig's 2.89 Hz mode; on sample 175 the regular stick phases last at most 0.09 s
#: and its one stall 1.43 s (at 28.05 s).
STALL_MIN_S = 0.5

#: The whole rig model's calibrated parameters: (low, high, unit, the source of the range).
RIG_PARAMETERS = {
    "damping_ratio": (0.005, 0.1, "-", "a steel bar between two bearings: modal damping of a few per cent; "
                                       "0.1 is the issue's plausibility bound"),
    "motor_slope_nms_rad": (0.1, 1.0, "N m s/rad", "the motor's rating, 8 N m at stall and 300 RPM no-load, gives "
                                                   "c_m = 8 / 31.4 = 0.25 for a linear DC characteristic; "
                                                   "a factor 2.5 to 4 either way"),
    "motor_inertia_kg_m2": (1e-3, 0.05, "kg m^2", "rotor, coupling and upper bearing: between a tenth and 5 times "
                                                  "the disk's 9.33e-3 kg m^2 (Table 5.1)"),
    "command_rad_s": (6.0, 31.4, "rad/s", "the motor's no-load speed: at most its 300 RPM (section 5.1); the "
                                          "nominal setting of sample 175 is 160 RPM = 16.8 rad/s"),
    "jack_gain_n_rad": (0.0, 1000.0, "N/rad", "axial stiffness x depth of cut per radian: 1e7 N/m x 0.6 mm/rev "
                                              "/ 2 pi at the top"),
    "jack_relaxation_s": (0.02, 3.0, "s", "the jack's regulation: from the platform's period to the seconds of "
                                          "its voltage switch (section 5.3.2)"),
    "platform_damping": (0.05, 1.5, "-", "the platform's 20 Hz mode held by a rod on a load cell; above 1 it is "
                                         "overdamped and flagged"),
    "gj_factor": (0.97, 1.15, "-", "the bar's GJ / L: 1.70 m (Table 5.1) or 1.53 m (section 5.1) gives x 1 to "
                                   "x 1.11, and the 2.5 mm radius +-0.02 mm +-3 %"),
    "bit_inertia_factor": (1.0, 1.4, "-", "Table 5.1's 9.33e-3 kg m^2 is the disk alone; the chuck, the mandrel and "
                                          "the masonry bit below it add to it (section 5.1)"),
    "coupling_stiffness_nm_rad": (2.0, 300.0, "N m/rad", "the shaft coupling between the motor and the bar (not in "
                                                         "Table 5.1): elastomer jaw couplings for 5-8 mm shafts are a "
                                                         "few to a few tens of N m/rad; 300 is rigid next to the "
                                                         "bar's 3.08"),
}


def rig_config(law: dict | None = None, damping_ratio: float | None = None, *, preset: str = "thesis-rig",
               duration_s: float | None = None, top_speed: float | None = None,
               wob: float | None = None, motor: tuple | None = None, axial: tuple | None = None,
               gj_factor: float = 1.0, bit_inertia_factor: float = 1.0,
               coupling_stiffness: float | None = None) -> dict:
    """The rig preset with another law, modal damping ratio and/or top drive (normalized by the engine).

    Parameters
    ----------
    law : dict, optional
        Engine bit-rock law (e.g. :attr:`drillpy.records.identification.LawFit.law`); default the
        preset's.
    damping_ratio : float, optional
        Modal damping ratio of the (single) mode [-]; default the preset's damping.
    preset : str
        Engine preset the geometry and numerics come from (``thesis-rig``: Table 5.1).
    duration_s : float, optional
        Simulated duration [s]; the transient is cut to at most half of it.
    top_speed : float, optional
        Top-drive speed [rad/s] (``operation.top_speed_rad_s``), the command Omega_c for a motor.
    wob : float, optional
        Weight on bit [N]; default the law's reference WOB, so the law is used at the WOB it was
        fitted at.
    motor : tuple of float, optional
        (c_m [N m s/rad], J_m [kg m^2]) of an open-loop motor top drive,
        J_m Omega' = c_m (Omega_c - Omega) - T_top, or (c_m, J_m, T_max [N m]) with its torque
        limit; None: an ideal top drive (any top drive of the preset is removed).
    axial : tuple of float, optional
        (g [N/rad], tau [s]) of the rig's jack: the WOB as a state (``drill/axial.hpp``), its set
        force ``wob``; None: the WOB is the input.
    gj_factor : float
        Factor on every section's Young's modulus (the GJ within the geometry's tolerance).
    bit_inertia_factor : float
        Factor on the inertia lumped at the bit (the disk of Table 5.1, and what it carries).
    coupling_stiffness : float, optional
        Torsional stiffness [N m/rad] of a massless coupling between the top drive and the bar: a
        1 cm section of the bar's steel at the top whose G J / L is this (its inertia, about 1e-13
        kg m^2, is negligible); None: the bar is clamped to the drive.

    Returns
    -------
    dict
        The normalized engine configuration.
    """
    cfg = copy.deepcopy(load_config(preset=preset))
    if law is not None:
        cfg["law"] = {k: (float(v) if isinstance(v, (np.floating, np.integer)) else v) for k, v in law.items()}
    if damping_ratio is not None:
        cfg["damping"] = {"type": "modal", "ratios": [float(damping_ratio)]}
    if duration_s is not None:
        cfg["simulation"]["duration_s"] = float(duration_s)
        cfg["simulation"]["transient_s"] = min(cfg["simulation"]["transient_s"], 0.5 * float(duration_s))
    cfg["operation"]["wob_n"] = float(cfg["law"]["wob_ref_n"] if wob is None else wob)
    if top_speed is not None:
        cfg["operation"]["top_speed_rad_s"] = float(top_speed)
    cfg.pop("top_drive", None)
    if motor is not None:
        cfg["top_drive"] = {"type": "motor", "slope_nms_rad": float(motor[0]), "inertia_kg_m2": float(motor[1])}
        if len(motor) > 2 and motor[2] is not None:
            cfg["top_drive"]["max_torque_nm"] = float(motor[2])
    cfg.pop("axial", None)
    if axial is not None:
        cfg["axial"] = {"type": "jack", "gain_n_rad": float(axial[0]), "relaxation_s": float(axial[1])}
    if gj_factor != 1.0:
        for sec in cfg["string"]["sections"]:
            sec["youngs_modulus_pa"] = float(sec["youngs_modulus_pa"]) * float(gj_factor)
    if bit_inertia_factor != 1.0:
        for li in cfg["string"].get("lumped_inertias", []):
            if li["node"] == -1:
                li["inertia_kg_m2"] = float(li["inertia_kg_m2"]) * float(bit_inertia_factor)
    if coupling_stiffness is not None:
        add_coupling(cfg, coupling_stiffness)
    return normalize(cfg)


def add_coupling(cfg: dict, stiffness: float) -> None:
    """Put a massless shaft coupling of torsional stiffness ``stiffness`` [N m/rad] between the top
    drive and the string: a first section named ``"coupling"``, :data:`COUPLING_LENGTH_M` long, of
    the top section's material, whose G J / L is the stiffness (its inertia is negligible).

    Parameters
    ----------
    cfg : dict
        Engine configuration, modified in place (the lumped inertias' node indices shift by one).
    stiffness : float
        k_c [N m/rad], positive.
    """
    top = cfg["string"]["sections"][0]
    E, nu, L = float(top["youngs_modulus_pa"]), float(top["poisson_ratio"]), COUPLING_LENGTH_M
    G = E / (2.0 * (1.0 + nu))
    r = (2.0 * float(stiffness) * L / (math.pi * G)) ** 0.25  # G pi r^4 / 2 / L = k_c
    cfg["string"]["sections"].insert(0, {"name": "coupling", "length_m": L, "outer_radius_m": r,
                                         "inner_radius_m": 0.0, "youngs_modulus_pa": E, "poisson_ratio": nu,
                                         "density_kg_m3": float(top["density_kg_m3"]), "elements": 1})
    for li in cfg["string"].get("lumped_inertias", []):
        if li["node"] >= 0:
            li["node"] += 1  # the coupling's element comes first


def remove_coupling(cfg: dict) -> float | None:
    """Take the shaft coupling of :func:`add_coupling` out of a configuration.

    Parameters
    ----------
    cfg : dict
        Engine configuration, modified in place.

    Returns
    -------
    float or None
        Its stiffness k_c [N m/rad], or None when the configuration has no coupling section.
    """
    secs = cfg["string"]["sections"]
    if not secs or secs[0].get("name") != "coupling":
        return None
    c = secs.pop(0)
    G = float(c["youngs_modulus_pa"]) / (2.0 * (1.0 + float(c["poisson_ratio"])))
    for li in cfg["string"].get("lumped_inertias", []):
        if li["node"] >= 1:
            li["node"] -= 1
    return G * math.pi * float(c["outer_radius_m"]) ** 4 / 2.0 / float(c["length_m"])


def reliable_top_speed(record: Record) -> np.ndarray:
    """Samples whose top speed is a measurement: not excluded, and not part of an artifact stretch
    (Flag.OSCILLATION: the encoder oscillating while the bit sticks, replaced by the bit speed by
    the cleaning). Isolated spikes, interpolated over a few ms, count as measured.

    On sample 175 this leaves out the stretch at 28-29.6 s: the mean top speed over 0-40 s is
    83.8 rpm over the reliable samples against 81.1 rpm over all valid ones (docs/records.md).

    Parameters
    ----------
    record : Record
        A cleaned record (:func:`drillpy.records.cleaning.clean`) with a top-speed channel.

    Returns
    -------
    ndarray of bool
        One entry per sample.
    """
    return record.valid("top_speed") & ~record.flagged("top_speed", Flag.OSCILLATION)


def stick_threshold(record: Record, fraction: float = STICK_FRACTION) -> float:
    """The bit is stuck at or below ``fraction`` of the median reliable top speed [rad/s]
    (:func:`drillpy.records.stick.stick_threshold` over the reliable samples).

    Parameters
    ----------
    record : Record
        A cleaned record with a top-speed channel.
    fraction : float
        Fraction of the median reliable top speed (5 % by default, the engine's rule).

    Returns
    -------
    float
        The stick threshold [rad/s].

    Raises
    ------
    ValueError
        If no top-speed sample is reliable (:func:`reliable_top_speed`).
    """
    ok = reliable_top_speed(record)
    if not ok.any():
        raise ValueError("record: no reliable top-speed sample (the stick threshold is a fraction of the median "
                         "top speed)")
    return _stick.stick_threshold(record.top_speed[ok], fraction)


def operating_point(record: Record) -> dict:
    """The record's operating point: mean top speed over its reliable samples [rad/s] (repaired
    stretches, e.g. the bit speed pasted over an encoder artifact, would bias it) and mean WOB [N].

    Parameters
    ----------
    record : Record
        A cleaned record with a top-speed channel.

    Returns
    -------
    dict
        ``top_speed_rad_s``, ``reliable_top_samples`` (samples it is the mean of), ``samples``
        (length of the record) and, when the record has valid WOB samples, ``wob_n``.

    Raises
    ------
    ValueError
        With fewer than 10 reliable top-speed samples.
    """
    ok = reliable_top_speed(record)
    if ok.sum() < 10:
        raise ValueError("operating_point: the record has fewer than 10 reliable top-speed samples")
    out = {"top_speed_rad_s": float(np.mean(record.top_speed[ok])), "reliable_top_samples": int(ok.sum()),
           "samples": len(record)}
    if record.wob is not None and record.valid("wob").any():
        out["wob_n"] = float(np.mean(record.wob[record.valid("wob")]))
    return out


@dataclass
class RigModel:
    """A calibrated rig model: the law, the effective modal damping ratio and the top drive.

    ``drive`` is one of :data:`DRIVES`; ``motor_slope_nms_rad`` (c_m) and ``motor_inertia_kg_m2``
    (J_m) are used by the ``motor`` drive. ``calibration`` records how it was obtained.

    Attributes
    ----------
    law : dict
        Engine bit-rock law (its ``wob_ref_n`` is the WOB it was identified at [N]).
    damping_ratio : float
        Effective modal damping ratio of the rig's torsional mode [-], positive. It lumps every
        dissipation the one-mode model lacks (motor give, platform, axial-torsional coupling):
        0.69 for the measured drive on sample 175 (docs/records.md, section 4).
    drive : str
        ``constant`` (the record's reliable mean top speed), ``measured`` (the top follows the
        measured top speed: a diagnosis, fed the cycle it should predict), ``motor`` (open-loop
        motor, J_m Omega' = c_m (Omega_c - Omega) - T_top, its command matched to the record's
        mean top speed) or ``rig`` (the rig modelled whole: module docstring).
    motor_slope_nms_rad : float or None
        Motor slope c_m [N m s/rad]: the torque the motor gives per rad/s below its command.
    motor_inertia_kg_m2 : float or None
        Inertia J_m of the motor top drive [kg m^2].
    preset : str
        Engine preset of the geometry (``thesis-rig``, Table 5.1).
    calibration : dict
        How the model was obtained (:func:`calibrate`): calibration window, operating point,
        motor command, mismatch, matched metrics, stick threshold, per-drive results.
    command_rad_s : float or None
        The ``rig`` drive's motor command Omega_c [rad/s], the rig's speed setting (calibrated, then
        held: the mean top speed is predicted).
    jack_gain_n_rad, jack_relaxation_s : float or None
        The ``rig`` drive's jack, g [N/rad] and tau [s] (``drill/axial.hpp``).
    platform_damping : float or None
        The ``rig`` drive's platform damping ratio at :data:`PLATFORM_HZ` [-].
    gj_factor : float
        Factor on the bar's GJ (``rig`` drive; 1 for the others).
    bit_inertia_factor : float
        Factor on the inertia at the bit (``rig`` drive; 1 for the others).
    coupling_stiffness_nm_rad : float or None
        Stiffness of the coupling between the motor and the bar [N m/rad] (``rig`` drive).
    intervals : dict
        Parameter name -> [low, high], a 95 % interval (``rig`` drive: :func:`calibrate_rig`).
    """
    law: dict
    damping_ratio: float
    drive: str = "constant"
    motor_slope_nms_rad: float | None = None
    motor_inertia_kg_m2: float | None = None
    preset: str = "thesis-rig"
    calibration: dict = field(default_factory=dict)
    command_rad_s: float | None = None
    jack_gain_n_rad: float | None = None
    jack_relaxation_s: float | None = None
    platform_damping: float | None = None
    gj_factor: float = 1.0
    bit_inertia_factor: float = 1.0
    coupling_stiffness_nm_rad: float | None = None
    intervals: dict = field(default_factory=dict)

    def __post_init__(self):
        if self.drive not in DRIVES:
            raise ValueError(f"drive = {self.drive!r}: use {', '.join(DRIVES)}")
        if not (math.isfinite(self.damping_ratio) and self.damping_ratio > 0):
            raise ValueError(f"damping_ratio = {self.damping_ratio!r}: must be a positive number")
        need = {"motor": ("motor_slope_nms_rad", "motor_inertia_kg_m2"),
                "rig": ("motor_slope_nms_rad", "motor_inertia_kg_m2", "command_rad_s", "jack_relaxation_s",
                        "platform_damping", "gj_factor", "bit_inertia_factor",
                        "coupling_stiffness_nm_rad")}.get(self.drive, ())
        for k in need:
            v = getattr(self, k)
            if v is None or not (math.isfinite(v) and v > 0):
                raise ValueError(f"{k} = {v!r}: the {self.drive} drive needs a positive value")
        if self.drive == "rig" and not (self.jack_gain_n_rad is not None and math.isfinite(self.jack_gain_n_rad)
                                        and self.jack_gain_n_rad >= 0):
            raise ValueError(f"jack_gain_n_rad = {self.jack_gain_n_rad!r}: the rig drive needs a value >= 0")

    @property
    def motor(self) -> tuple | None:
        """(c_m [N m s/rad], J_m [kg m^2]) for the motor drive, with the torque limit
        :data:`MOTOR_MAX_TORQUE_NM` for the rig drive, None for the others."""
        if self.drive == "rig":
            return (self.motor_slope_nms_rad, self.motor_inertia_kg_m2, MOTOR_MAX_TORQUE_NM)
        return (self.motor_slope_nms_rad, self.motor_inertia_kg_m2) if self.drive == "motor" else None

    @property
    def axial(self) -> tuple | None:
        """(g [N/rad], tau [s]) of the rig drive's jack, None for the others."""
        return (self.jack_gain_n_rad, self.jack_relaxation_s) if self.drive == "rig" else None

    def parameters(self) -> dict:
        """The rig drive's calibrated parameters with their 95 % intervals, physical ranges and flags.

        Returns
        -------
        dict
            Name -> ``value``, ``ci95`` ([low, high] or None), ``range`` [low, high], ``unit``,
            ``source`` (of the range) and ``flag`` (None, or why the value is not plausible: at a
            bound of its range, or an overdamped platform). Empty for the other drives.
        """
        if self.drive != "rig":
            return {}
        out = {}
        for name, (lo, hi, unit, source) in RIG_PARAMETERS.items():
            v = float(getattr(self, name))
            flag = None
            if v <= lo * (1 + 1e-3) or v >= hi * (1 - 1e-3):
                flag = f"at the bound of its range [{lo:g}, {hi:g}] {unit}: an element the model lacks may be pushing it"
            elif name == "platform_damping" and v > 1.0:
                flag = "an overdamped platform: the torque channel lags more than a 20 Hz mode explains"
            out[name] = {"value": v, "ci95": self.intervals.get(name), "range": [lo, hi], "unit": unit,
                         "source": source, "flag": flag}
        return out

    def config(self, top_speed: float, wob: float | None = None, duration_s: float | None = None) -> dict:
        """Engine configuration of the model at an operating point.

        Parameters
        ----------
        top_speed : float
            Top-drive speed [rad/s] (the motor's command Omega_c for the motor drive). The
            measured drive's series is passed to the simulation separately.
        wob : float, optional
            Weight on bit [N]; default the law's reference WOB.
        duration_s : float, optional
            Simulated duration [s]; default the preset's.

        Returns
        -------
        dict
            Normalized engine configuration (:func:`rig_config`).
        """
        return rig_config(self.law, self.damping_ratio, preset=self.preset, duration_s=duration_s,
                          top_speed=top_speed, wob=wob, motor=self.motor, axial=self.axial,
                          gj_factor=self.gj_factor if self.drive == "rig" else 1.0,
                          bit_inertia_factor=self.bit_inertia_factor if self.drive == "rig" else 1.0,
                          coupling_stiffness=self.coupling_stiffness_nm_rad if self.drive == "rig" else None)

    @property
    def predictive(self) -> bool:
        """True when the drive takes from a record only constants or slow signals
        (:data:`PREDICTIVE_DRIVES`); the measured-top-speed drive is a diagnosis."""
        return self.drive in PREDICTIVE_DRIVES

    def to_dict(self, top_speed: float | None = None, wob: float | None = None) -> dict:
        """``model.json``: the engine configuration (at the calibration's operating point) and the drive.

        Parameters
        ----------
        top_speed : float, optional
            Top speed or motor command in the configuration [rad/s]; default the calibration's
            motor command, else its operating point.
        wob : float, optional
            Weight on bit [N]; default the calibration's operating point.

        Returns
        -------
        dict
            ``format = "drillpy.rig_model"``, ``version``, ``drive``, ``config`` and
            ``calibration``; read back by :meth:`from_dict`.
        """
        op = self.calibration.get("operating_point", {})
        om = top_speed if top_speed is not None else self.calibration.get("command_rad_s", op.get("top_speed_rad_s"))
        if top_speed is None and self.drive == "rig":
            om = self.command_rad_s
        out = {"format": "drillpy.rig_model", "version": 1, "drive": self.drive,
               "predictive": self.predictive,
               "config": self.config(om, wob if wob is not None else op.get("wob_n")),
               "calibration": self.calibration}
        if self.drive == "rig":
            out["rig"] = {"platform_hz": PLATFORM_HZ, "platform_damping": self.platform_damping,
                          "gj_factor": self.gj_factor, "bit_inertia_factor": self.bit_inertia_factor,
                          "coupling_stiffness_nm_rad": self.coupling_stiffness_nm_rad,
                          "wob_trend_hz": WOB_TREND_HZ,
                          "parameters": self.parameters()}
        return out

    @classmethod
    def from_dict(cls, d: dict) -> "RigModel":
        """The model of a ``model.json`` written by :meth:`to_dict` (``drillpy analyze --calibrate``).

        Only the law, the modal damping ratio, the drive and the motor parameters are taken from
        the configuration (and ``calibration`` is kept); the geometry is the ``thesis-rig``
        preset's.

        Parameters
        ----------
        d : dict
            The parsed JSON.

        Returns
        -------
        RigModel

        Raises
        ------
        ValueError
            If ``d`` is not a rig model, its damping is not modal, or its configuration lacks the
            law or the damping.
        """
        if not isinstance(d, dict) or d.get("format") != "drillpy.rig_model":
            raise ValueError("model: not a drillpy rig model (format must be 'drillpy.rig_model'; written by "
                             "drillpy analyze as model.json)")
        cfg = d.get("config") or {}
        try:
            damp = cfg["damping"]
            if damp.get("type") != "modal":
                raise ValueError(f"model: config.damping.type = {damp.get('type')!r}: a rig model has modal damping")
            td = cfg.get("top_drive", {"type": "ideal"})
            motor = td.get("type") == "motor"
            drive = d.get("drive", "constant")
            extra = {}
            if drive == "rig":
                rig, ax = d.get("rig") or {}, cfg.get("axial") or {}
                extra = {"command_rad_s": cfg["operation"]["top_speed_rad_s"], "jack_gain_n_rad": ax.get("gain_n_rad"),
                         "jack_relaxation_s": ax.get("relaxation_s"), "platform_damping": rig.get("platform_damping"),
                         "gj_factor": rig.get("gj_factor", 1.0),
                         "bit_inertia_factor": rig.get("bit_inertia_factor", 1.0),
                         "coupling_stiffness_nm_rad": rig.get("coupling_stiffness_nm_rad"),
                         "intervals": {k: v.get("ci95") for k, v in (rig.get("parameters") or {}).items()
                                       if v.get("ci95") is not None}}
            return cls(law=cfg["law"], damping_ratio=float(damp["ratios"][0]), drive=drive,
                       motor_slope_nms_rad=td.get("slope_nms_rad") if motor else None,
                       motor_inertia_kg_m2=td.get("inertia_kg_m2") if motor else None,
                       calibration=d.get("calibration", {}), **extra)  # rebuilt on the thesis-rig geometry
        except KeyError as e:
            raise ValueError(f"model: config lacks {e}") from None


def wob_trend(record: Record, default: float) -> np.ndarray:
    """The jack's slow WOB: the record's valid WOB samples (gaps interpolated) low-passed below
    :data:`WOB_TREND_HZ` (second-order Butterworth, zero phase). A slow input of the ``rig`` drive,
    not the cycle: at 0.5 Hz the filter passes 0.01 % of the power at the rig's 2.6-2.9 Hz cycle.

    Parameters
    ----------
    record : Record
        A cleaned record.
    default : float
        The WOB [N] when the record has no valid WOB sample.

    Returns
    -------
    ndarray
        The trend [N], one value per sample.
    """
    n = len(record)
    if record.wob is None or not record.valid("wob").any():
        return np.full(n, float(default))
    ok = record.valid("wob") & np.isfinite(record.wob)
    idx = np.arange(n)
    w = np.interp(idx, idx[ok], record.wob[ok])
    fs = 1.0 / record.dt
    if n < 30 or WOB_TREND_HZ >= 0.5 * fs:
        return np.full(n, float(np.mean(w)))
    from scipy import signal as sps
    b, a = sps.butter(2, WOB_TREND_HZ, fs=fs)
    return sps.filtfilt(b, a, w, padlen=min(n - 1, 3 * int(fs / WOB_TREND_HZ)))


def drive_series(record: Record) -> np.ndarray:
    """The measured top speed as a drive signal (the ``measured`` drive): excluded samples and
    artifact stretches (not :func:`reliable_top_speed`) interpolated from the reliable ones. Those
    samples are then left out of every comparison (:func:`measured_side`): never fed in unmarked,
    never a refusal.

    Parameters
    ----------
    record : Record
        A cleaned record with a top-speed channel and at least two reliable samples.

    Returns
    -------
    ndarray
        Top speed [rad/s], one value per sample.
    """
    ok = reliable_top_speed(record) & np.isfinite(record.top_speed)
    if ok.sum() < 2:
        raise ValueError("record: fewer than 2 reliable top-speed samples; the measured drive needs a top speed")
    idx = np.arange(len(record))
    return np.interp(idx, idx[ok], record.top_speed[ok])


def _setup(model: RigModel, record: Record, command: float, wob: float) -> dict:
    """The engine configuration of ``model`` over ``record``'s span, output on its grid."""
    cfg = model.config(command, wob, duration_s=float(record.time_s[-1] - record.time_s[0]))
    cfg["simulation"]["output_stride"] = max(1, int(round(record.dt / cfg["simulation"]["dt_s"])))
    return normalize(cfg)


def _channels(res, record: Record, filtered: bool, platform_damping: float | None = None):
    """The simulated bit speed, top speed, torque on bit and WOB on ``record``'s grid (and how many
    samples); with ``platform_damping`` the torque is what the platform's load cell reads."""
    n = min(res.t.size, record.time_s.size)
    vb, vt, tq, w = res.bit_speed[:n], res.top_speed[:n], res.torque_on_bit[:n], res.wob[:n]
    fs = 1.0 / float(np.median(np.diff(res.t)))
    if platform_damping is not None:
        tq = platform_response(tq, fs, PLATFORM_HZ, platform_damping)
    if filtered:
        vb, vt, tq, w = (rig_lowpass(x, fs) for x in (vb, vt, tq, w))
    return n, vb, vt, tq, w


def _run(model: RigModel, record: Record, command: float, wob: float):
    measured, rig = model.drive == "measured", model.drive == "rig"
    return simulate(_setup(model, record, command, wob), None if measured else command,
                    top_speed_series=drive_series(record) if measured else None,
                    wob_series=wob_trend(record, wob) if rig else None, series_dt=record.dt)


def _as_record(model: RigModel, record: Record, res, command: float, op: dict, wob: float, filtered: bool) -> Record:
    """The simulation ``res`` of ``model`` as a record on ``record``'s grid (see :func:`simulate_model`)."""
    n, vb, vt, tq, w = _channels(res, record, filtered, model.platform_damping if model.drive == "rig" else None)
    t = res.t[:n] + record.time_s[0]
    return Record(time_s=t, bit_speed=vb, top_speed=vt, torque_on_bit=tq, wob=w,
                  units={"time": "s", "bit_speed": "rad_s", "top_speed": "rad_s", "torque_on_bit": "Nm", "wob": "N"},
                  provenance={"source": "simulation", "format": "drillpy.simulate", "preset": model.preset,
                              "drive": model.drive, "filtered": filtered, "command_rad_s": command,
                              "operating_point": op, "config": res.config})


def simulate_model(model: RigModel, record: Record, *, filtered: bool = True, skip_s: float = 2.0) -> Record:
    """Simulate ``model`` over the span of a cleaned ``record`` at the record's operating point.

    The constant drive turns at the record's reliable mean top speed; the measured drive follows
    the record's top-speed channel (its artifact stretches interpolated, :func:`drive_series`, and
    left out of the comparison); the motor's command is found (bracketing and bisection) so that the
    simulated mean top speed after ``skip_s`` equals the record's reliable mean; the rig drive runs at
    its own calibrated command with the jack's set force the record's slow WOB trend
    (:func:`wob_trend`). The WOB is otherwise the record's mean WOB (the law scales with W / W_ref).
    Nothing of the record but its operating point, its WOB trend (and the measured drive's top speed)
    enters: this is how a model predicts data it was not calibrated on.

    Parameters
    ----------
    model : RigModel
        The model to run.
    record : Record
        A cleaned record (:func:`drillpy.records.cleaning.clean`) with a top-speed channel.
    filtered : bool
        Pass the simulated channels through the rig's 10 Hz acquisition filter
        (:func:`drillpy.records.signals.rig_lowpass`), as the measured ones were.
    skip_s : float
        Start-up left out of the mean top speed when the motor command is searched [s].

    Returns
    -------
    Record
        The simulation on the record's time grid (bit and top speed [rad/s], torque on bit
        [N m], WOB [N]: constant, or the rig drive's jack state); ``provenance`` holds the drive,
        ``command_rad_s``, the ``operating_point`` and the engine ``config``.

    Raises
    ------
    ValueError
        When the operating point cannot be taken (:func:`operating_point`).
    """
    op = operating_point(record)
    wob = op.get("wob_n", model.law["wob_ref_n"])
    target = op["top_speed_rad_s"]
    command = model.command_rad_s if model.drive == "rig" else target
    if model.drive == "motor":
        sel = record.time_s >= record.time_s[0] + skip_s

        def gap(c):
            res = _run(model, record, c, wob)
            _, _, top, _, _ = _channels(res, record, False)
            return float(np.mean(top[sel[:top.size]])) - target

        # the mean top speed rises with the command, with jumps where the motor stalls or stick-slip
        # starts: bracket the record's mean, then bisect (a secant step can land in a stall)
        lo, hi = target, target + 2.0 / model.motor_slope_nms_rad  # droop at about 2 N m
        g_hi = gap(hi)
        for _ in range(8):
            if g_hi >= 0:
                break
            lo, hi = hi, hi + 2.0 * (hi - target)
            g_hi = gap(hi)
        best = (abs(g_hi), hi)
        for _ in range(10):
            mid = 0.5 * (lo + hi)
            g = gap(mid)
            best = min(best, (abs(g), mid))
            if abs(g) <= 5e-3 * abs(target):
                break
            lo, hi = (mid, hi) if g < 0 else (lo, mid)
        command = best[1]
    return _as_record(model, record, _run(model, record, command, wob), command, op, wob, filtered)


def simulate_models(models, record: Record, *, filtered: bool = True, threads: int = 0, batched: bool = True) -> list:
    """Simulate several constant- or measured-drive models over ``record``, as :func:`simulate_model`
    does each, in one call: models that differ only in their damping (a damping scan) run in SIMD
    lockstep (:func:`drillpy.model.simulation.simulate_many`), the others one by one in parallel.

    Parameters
    ----------
    models : sequence of RigModel
        Models with the ``constant`` or the ``measured`` drive.
    record : Record
        A cleaned record with a top-speed channel (see :func:`simulate_model`).
    filtered : bool
        Pass the simulated channels through the rig's 10 Hz acquisition filter.
    threads : int
        Engine threads (0: one per core).
    batched : bool
        ``False``: every model through the scalar reference integrator (the two agree to rounding).

    Returns
    -------
    list of Record or None
        Per model its simulation, None where it failed (diverged).

    Raises
    ------
    ValueError
        For a motor or rig drive (run by run: :func:`simulate_model`), and when the operating point
        cannot be taken.
    """
    models = list(models)
    if not models:
        return []
    op = operating_point(record)
    wob = op.get("wob_n", models[0].law["wob_ref_n"])
    command = op["top_speed_rad_s"]
    series = None
    for m in models:
        if m.drive in ("motor", "rig"):
            raise ValueError(f"simulate_models: drive = {m.drive!r}: run it by simulate_model")
        if m.drive == "measured":
            series = drive_series(record)
    if series is not None and any(m.drive != "measured" for m in models):
        raise ValueError("simulate_models: drives = " + ", ".join(sorted({m.drive for m in models}))
                         + ": one call takes one drive (its top speed drives every run)")
    results, _ = simulate_many([_setup(m, record, command, wob) for m in models],
                               top_speed_series=series, series_dt=record.dt, threads=threads, batched=batched)
    return [None if res is None else _as_record(m, record, res, command, op, wob, filtered)
            for m, res in zip(models, results)]


def simulate_rig(record: Record, law: dict | None = None, damping_ratio: float | None = None, *,
                 drive: str = "measured", motor: tuple | None = None, filtered: bool = True,
                 preset: str = "thesis-rig") -> Record:
    """Simulate the rig with ``law`` (default: the preset's) and ``damping_ratio`` (default: the
    preset's) over the span of a cleaned ``record`` (see :func:`simulate_model`); ``motor`` is
    (c_m, J_m) for ``drive="motor"``.

    Parameters
    ----------
    record : Record
        A cleaned record; its operating point (and top speed, for the measured drive) drives the
        simulation.
    law : dict, optional
        Engine bit-rock law; default the preset's.
    damping_ratio : float, optional
        Modal damping ratio [-]; default the preset's first ratio.
    drive : str
        One of :data:`DRIVES` (default ``measured``).
    motor : tuple of float, optional
        (c_m [N m s/rad], J_m [kg m^2]); required for ``drive="motor"``.
    filtered : bool
        Apply the rig's 10 Hz acquisition filter to the simulated channels.
    preset : str
        Engine preset of the rig.

    Returns
    -------
    Record
        As :func:`simulate_model`.
    """
    if drive not in DRIVES:
        raise ValueError(f"drive = {drive!r}: use {', '.join(DRIVES)}")
    if drive == "motor" and motor is None:
        raise ValueError("drive = 'motor' needs motor = (slope c_m [N m s/rad], inertia J_m [kg m^2])")
    base = load_config(preset=preset)
    law = base["law"] if law is None else law
    z = base["damping"]["ratios"][0] if damping_ratio is None else damping_ratio
    m = RigModel(law, float(z), drive, *(motor if motor else (None, None)), preset=preset)
    return simulate_model(m, record, filtered=filtered)


@dataclass
class RigComparison:
    """Measured versus simulated stick-slip metrics and torque-speed loops (made by :func:`compare`).

    Attributes
    ----------
    measured, simulated : dict
        :func:`drillpy.records.signals.stick_slip_metrics` of each record after the start-up, with
        ``top_speed_std`` [rad/s], and ``mean_top_speed`` [rad/s] and ``ss`` taken over the
        reliable top-speed samples.
    mismatch : float
        Root mean square of the relative errors of the metrics in :data:`MATCHED`
        (:func:`relative_error`) [-]; 0 is a perfect match.
    mean_cycle_measured, mean_cycle_simulated : MeanCycle or None
        Mean torque-speed cycle per branch of each record on a common speed grid; None when
        there is no stick-slip cycle.
    loop_rms_nm : float
        RMS difference of the upper and lower branch curves on the common speeds [N m]; NaN
        without both loops.
    """
    measured: dict
    simulated: dict
    mismatch: float
    mean_cycle_measured: MeanCycle | None   #: None when there is no stick-slip cycle
    mean_cycle_simulated: MeanCycle | None
    loop_rms_nm: float  #: rms difference of the branch mean curves on the common speeds [N m]

    def rows(self) -> list:
        """Table rows ``(metric, measured, simulated)`` for reports.

        Returns
        -------
        list of tuple
            For ``ss``, ``cycle_frequency_hz``, ``median_period_s``, ``stick_fraction``,
            ``bit_speed_p95`` [rad/s], ``torque_p5``, ``torque_p95``, ``torque_min`` and
            ``torque_max`` [N m].
        """
        keys = ("ss", "cycle_frequency_hz", "median_period_s", "stick_fraction", "bit_speed_p95",
                "torque_p5", "torque_p95", "torque_min", "torque_max")
        return [(k, self.measured[k], self.simulated[k]) for k in keys]


def _loop(rec: Record, thr: float, t_start: float, grid) -> MeanCycle | None:
    """Mean cycle per branch after t_start, or None when there is no stick-slip cycle."""
    sel = rec.time_s >= t_start
    v = rec.bit_speed[sel]
    tq = rec.torque_on_bit[sel]
    cyc = segment_cycles(v, rec.dt, thr)
    lab = cyc.branch_labels(v.size)
    try:
        return mean_cycle(v, tq, derivative(v, rec.dt), lab, grid=grid)
    except ValueError:
        return None


@dataclass
class MeasuredSide:
    """The measured record's side of :func:`compare` for simulations that start at ``t0 - t_start``
    with one drive: computed once, reused by every point of a scan (:func:`calibrate`).

    Attributes
    ----------
    t0 : float
        Start of the compared span [s].
    skip : ndarray of bool
        Samples left out of both records (the measured drive's unreliable top speed).
    metrics : dict
        The measured metrics over the span.
    grid : ndarray
        Bit-speed grid of the mean cycles [rad/s].
    cycle : MeanCycle or None
        The measured mean cycle.
    """
    t0: float
    skip: np.ndarray
    metrics: dict
    grid: np.ndarray
    cycle: MeanCycle | None


def stalls(bit_speed, dt: float, stick_threshold: float, valid=None, min_s: float = STALL_MIN_S) -> list:
    """The stalls of a record: stick phases (bit speed at or below the threshold) of at least ``min_s``.

    A stall is not part of the regular stick-slip cycle: the bit sticks at a torque the open-loop
    motor cannot overcome until the WOB is relieved (thesis section 5.3.2). Stalls are reported
    apart (count, starts, durations) and left out of the regular metrics (:func:`compare`).

    Parameters
    ----------
    bit_speed : array_like
        Bit speed [rad/s].
    dt : float
        Sampling interval [s].
    stick_threshold : float
        Bit speed at or below which the bit is stuck [rad/s].
    valid : array_like of bool, optional
        Usable samples (a phase is cut where they end); default all finite samples.
    min_s : float
        Shortest stall [s] (:data:`STALL_MIN_S`).

    Returns
    -------
    list of tuple
        ``(first_index, samples)`` per stall, in time order.
    """
    v = np.asarray(bit_speed, float)
    ok = np.isfinite(v) if valid is None else (np.asarray(valid, bool) & np.isfinite(v))
    st = ok & (v <= stick_threshold)
    d = np.diff(np.r_[0, st.astype(np.int8), 0])
    starts, ends = np.flatnonzero(d == 1), np.flatnonzero(d == -1)
    n_min = int(math.ceil(min_s / dt))
    return [(int(a), int(b - a)) for a, b in zip(starts, ends) if b - a >= n_min]


def _metrics(rec: Record, stick_threshold: float, t0: float, skip: np.ndarray) -> dict:
    base = (rec.time_s >= t0) & ~skip[:len(rec)]
    sel = base & rec.valid("bit_speed", "top_speed", "torque_on_bit")
    stall = np.zeros(len(rec), bool)
    found = stalls(rec.bit_speed, rec.dt, stick_threshold, valid=sel)
    after = int(round(0.1 / rec.dt))  # the break-away that ends a stall is not a regular cycle either
    for a, k in found:
        stall[a:a + k + after] = True
    if (sel & ~stall).sum() >= 3:
        sel = sel & ~stall
    m = stick_slip_metrics(rec.time_s, rec.bit_speed, rec.top_speed, rec.torque_on_bit, stick_threshold, valid=sel)
    m["stalls"] = {"count": len(found), "starts_s": [float(rec.time_s[a]) for a, _ in found],
                   "durations_s": [float(k * rec.dt) for _, k in found]}
    m["stall_fraction"] = float(sum(k for _, k in found) / max(int(base.sum()), 1))
    w = sel & (rec.valid("wob") if rec.wob is not None else np.zeros(len(rec), bool))
    m["wob_std"] = float(np.std(rec.wob[w])) if w.sum() > 1 else float("nan")
    m["wob_mean"] = float(np.mean(rec.wob[w])) if w.sum() > 1 else float("nan")
    ok = base & ~stall & reliable_top_speed(rec)
    if ok.sum() > 1:  # the mean top speed and SS (Eq. 3.4) from reliable top-speed samples only
        m["top_speed_std"] = float(np.std(rec.top_speed[ok]))
        m["mean_top_speed"] = float(np.mean(rec.top_speed[ok]))
        v = rec.bit_speed[sel]
        m["ss"] = float((np.max(v) - np.min(v)) / (2.0 * abs(m["mean_top_speed"])))
    else:
        m["top_speed_std"] = float("nan")
    return m


def measured_side(measured: Record, stick_threshold: float, start_s: float, drive: str,
                  t_start: float = 2.0) -> MeasuredSide:
    """The measured side of :func:`compare` for simulations starting at ``start_s`` with ``drive``.

    Parameters
    ----------
    measured : Record
        The cleaned measurement.
    stick_threshold : float
        Bit speed at or below which the bit counts as stuck [rad/s].
    start_s : float
        The simulations' first time [s].
    drive : str
        Their drive (:data:`DRIVES`).
    t_start : float
        Start-up discarded from both [s].

    Returns
    -------
    MeasuredSide
    """
    t0 = start_s + t_start
    skip = np.zeros(len(measured), bool)
    if drive == "measured" and measured.top_speed is not None:
        skip = ~reliable_top_speed(measured)  # what drive_series interpolated was not a measurement
    grid = np.linspace(0.0, np.percentile(measured.bit_speed[measured.time_s >= t0], 99), 40)
    return MeasuredSide(t0, skip, _metrics(measured, stick_threshold, t0, skip), grid,
                        _loop(measured, stick_threshold, t0, grid))


def compare(measured: Record, simulated: Record, stick_threshold: float, t_start: float = 2.0, *,
            side: MeasuredSide | None = None, keys: tuple | None = None) -> RigComparison:
    """Compare a simulated record with the measured one after ``t_start`` seconds of simulation
    (the start-up of the simulation is discarded from both). ``top_speed_std`` is over the
    reliable top-speed samples of the measurement (:func:`reliable_top_speed`). When the
    simulation is driven by the measured top speed, the samples where that signal is not a
    measurement (an artifact stretch the cleaning filled with the bit speed) are left out of both:
    there the drive would impose the measured stall instead of predicting it.

    Parameters
    ----------
    measured : Record
        The cleaned measurement.
    simulated : Record
        Its simulation (:func:`simulate_model`), on the same time grid.
    stick_threshold : float
        Bit speed at or below which the bit counts as stuck [rad/s] (:func:`stick_threshold`),
        the same for both records.
    t_start : float
        Start-up discarded from both, counted from the simulation's first sample [s].
    side : MeasuredSide, optional
        The measured side already computed (:func:`measured_side` with the same arguments and
        the simulation's first time and drive); default: computed here.
    keys : tuple of str, optional
        The metrics of the mismatch; default :data:`MATCHED_RIG` for the rig drive (it predicts the
        WOB's oscillation and the mean top speed), :data:`MATCHED` for the others.

    Returns
    -------
    RigComparison
        The metrics are those of the regular cycle: stalls (:func:`stalls`) are counted apart
        (``stalls``, ``stall_fraction``) and their samples left out of the rest.
    """
    if side is None:
        side = measured_side(measured, stick_threshold, float(simulated.time_s[0]),
                             simulated.provenance.get("drive", "constant"), t_start)
    m, s = side.metrics, _metrics(simulated, stick_threshold, side.t0, side.skip)
    if keys is None:
        keys = MATCHED_RIG if simulated.provenance.get("drive") == "rig" else MATCHED
    rel = [relative_error(s[k], m[k]) for k in keys]
    mis = float(np.sqrt(np.mean(np.square(rel))))
    mm = side.cycle
    ms = _loop(simulated, stick_threshold, side.t0, side.grid)
    loop = float("nan")
    if mm is not None and ms is not None:
        d = np.r_[mm.upper - ms.upper, mm.lower - ms.lower]
        d = d[np.isfinite(d)]
        loop = float(np.sqrt(np.mean(d ** 2))) if d.size else loop
    return RigComparison(m, s, mis, mm, ms, loop)


def relative_error(simulated: float, measured: float) -> float:
    """(simulated - measured) / |measured|; a missing simulated value (no cycle, so no period or
    frequency) counts as 100 %, and a zero measured value as the simulated value itself.

    Parameters
    ----------
    simulated : float
        Metric of the simulation.
    measured : float
        The same metric measured (a non-finite value also gives 1.0).

    Returns
    -------
    float
        Signed relative error [-].
    """
    if not np.isfinite(simulated) or not np.isfinite(measured):
        return 1.0
    return (simulated - measured) / abs(measured) if measured != 0 else float(simulated)


@dataclass
class Calibration:
    """What :func:`calibrate` found: the chosen model, its comparison on the calibration part and,
    per drive, the best model with its mismatch and the points scanned.

    Attributes
    ----------
    model : RigModel
        The drive and parameters with the smallest mismatch, ``calibration`` filled in.
    comparison : RigComparison
        The chosen model against the calibration record.
    per_drive : dict
        Drive -> ``damping_ratio``, ``mismatch`` and ``scan`` (the (ratio, mismatch) pairs
        tried) for the constant and measured drives; ``damping_ratio``, ``motor_slope_nms_rad``,
        ``motor_inertia_kg_m2``, ``mismatch`` and ``evaluations`` for the motor.
    """
    model: RigModel
    comparison: RigComparison
    per_drive: dict

    def summary(self) -> dict:
        """The calibration as a JSON-ready dict.

        Returns
        -------
        dict
            ``drive``, ``damping_ratio``, ``motor_slope_nms_rad``, ``motor_inertia_kg_m2``,
            ``mismatch``, the ``measured`` and ``simulated`` metrics, and ``per_drive``.
        """
        return {"drive": self.model.drive, "damping_ratio": self.model.damping_ratio,
                "motor_slope_nms_rad": self.model.motor_slope_nms_rad,
                "motor_inertia_kg_m2": self.model.motor_inertia_kg_m2,
                "mismatch": self.comparison.mismatch, "measured": self.comparison.measured,
                "simulated": self.comparison.simulated,
                "per_drive": self.per_drive}


@fitted_values()
def calibrate(record: Record, law: dict, stick_threshold: float, *, drives=DRIVES, preset: str = "thesis-rig",
              log=None, threads: int = 0) -> Calibration:
    """Calibrate the effective damping ratio and the top drive of the rig model with ``law`` on a
    cleaned ``record``: for each drive the parameters with the smallest mismatch (rms relative
    error over :data:`MATCHED`, :func:`compare`), then the drive with the smallest mismatch.

    The mismatch is not smooth in the parameters (stick-slip cycles appear and vanish), so each
    drive is searched on a grid first: the damping ratio on 14 log-spaced values in [0.01, 1.5]
    refined once around the best; for the motor, damping x slope c_m x inertia J_m on a 4 x 5 x 3
    log grid, then a Nelder-Mead polish in the logarithms from the best grid point. The motor's
    command always reproduces the record's reliable mean top speed (:func:`simulate_model`).
    A parameter set whose simulation fails (unstable, diverged) counts as an infinite mismatch.
    The grid points are independent simulations. A damping scan's models differ in their damping
    only: its points run in one call, in SIMD lockstep (:func:`simulate_models`); the motor's points
    run ``threads`` at a time (the engine releases the GIL). The results do not depend on the
    thread count.

    Parameters
    ----------
    record : Record
        The cleaned calibration part of a record, with top speed, bit speed and torque.
    law : dict
        Engine bit-rock law, identified on the same data (Eq. 5.1 or 5.3).
    stick_threshold : float
        Bit speed at or below which the bit counts as stuck [rad/s] (:func:`stick_threshold`).
    drives : iterable of str
        Drives tried, from :data:`DRIVES` (``rig``: :func:`calibrate_rig`).
    preset : str
        Engine preset of the rig.
    log : callable, optional
        Called with one progress line (str) per drive.
    threads : int
        Grid points simulated at once (0: one per core).

    Returns
    -------
    Calibration

    Raises
    ------
    ValueError
        For an unknown drive, or when the operating point cannot be taken.
    """
    drives = tuple(drives)
    for d in drives:
        if d not in DRIVES:
            raise ValueError(f"drives: unknown drive {d!r} (use {', '.join(DRIVES)})")
    op = operating_point(record)
    cache = {}

    def mismatch(drive, z, cm=None, J=None):
        key = (drive, round(z, 12), cm and round(cm, 12), J and round(J, 12))
        if key not in cache:
            try:
                m = RigModel(law, float(z), drive, cm, J, preset=preset)
                cache[key] = compare(record, simulate_model(m, record), stick_threshold).mismatch
            except (ValueError, RuntimeError):  # outside the stability bound, diverged, ...
                cache[key] = math.inf
        return cache[key]

    def scan_of(drive, grid):
        if drive == "motor":  # each point searches its own command: one simulate_model per point
            with ThreadPoolExecutor(max_workers=workers) as pool:
                return list(zip(grid, pool.map(lambda p: mismatch(drive, *p), grid)))
        # a damping scan: the grid's models differ in their damping only, one lockstep call
        todo = [z for z in grid if (drive, round(z, 12), None, None) not in cache]
        try:
            sims = simulate_models([RigModel(law, z, drive, preset=preset) for z in todo], record, threads=threads)
        except (ValueError, RuntimeError):  # outside the stability bound, ...
            sims = [None] * len(todo)
        side = measured_side(record, stick_threshold, float(record.time_s[0]), drive)
        for z, sim in zip(todo, sims):
            try:
                mis = math.inf if sim is None else compare(record, sim, stick_threshold, side=side).mismatch
            except (ValueError, RuntimeError):
                mis = math.inf
            cache[(drive, round(z, 12), None, None)] = mis
        return [(z, cache[(drive, round(z, 12), None, None)]) for z in grid]

    workers = threads if threads > 0 else (os.cpu_count() or 1)
    per = {}
    for drive in drives:
        if drive == "motor":
            grid = [(z, cm, J) for z in (0.05, 0.1, 0.2, 0.4) for cm in np.geomspace(0.05, 2.0, 5)
                    for J in np.geomspace(5e-3, 5e-2, 3)]
            scan = scan_of("motor", grid)
            best = min(scan, key=lambda q: q[1])[0]
            res = optimize.minimize(lambda x: mismatch("motor", *np.exp(x)), np.log(best), method="Nelder-Mead",
                                    options={"maxfev": 40, "xatol": 0.02, "fatol": 1e-3})
            p = tuple(np.exp(res.x)) if res.fun < mismatch("motor", *best) else best
            per[drive] = {"damping_ratio": float(p[0]), "motor_slope_nms_rad": float(p[1]),
                          "motor_inertia_kg_m2": float(p[2]), "mismatch": mismatch("motor", *p),
                          "evaluations": len(scan) + int(res.nfev)}
        else:
            grid = np.geomspace(0.01, 1.5, 14)
            grid = grid[grid <= 1.0]  # the engine refuses a damping ratio above critical
            scan = scan_of(drive, [float(z) for z in grid])
            k = int(np.argmin([m for _, m in scan]))
            scan += scan_of(drive, [float(z) for z in np.geomspace(grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)],
                                                                   7)[1:-1]])
            z, mis = min(scan, key=lambda q: q[1])
            per[drive] = {"damping_ratio": z, "mismatch": mis, "scan": sorted(scan)}
        if log:
            log(f"rig calibration: {drive} drive: mismatch {per[drive]['mismatch']:.3f} at damping ratio "
                f"{per[drive]['damping_ratio']:.3g}" + (f", c_m {per[drive]['motor_slope_nms_rad']:.3g} N m s/rad, "
                                                        f"J_m {per[drive]['motor_inertia_kg_m2']:.3g} kg m^2"
                                                        if drive == "motor" else ""))
    drive = min(per, key=lambda d: per[d]["mismatch"])
    b = per[drive]
    model = RigModel(law, b["damping_ratio"], drive, b.get("motor_slope_nms_rad"), b.get("motor_inertia_kg_m2"),
                     preset=preset)
    sim = simulate_model(model, record)
    cmp = compare(record, sim, stick_threshold)
    model.calibration = {"window_s": [float(record.time_s[0]), float(record.time_s[-1])], "operating_point": op,
                         "command_rad_s": sim.provenance["command_rad_s"], "mismatch": cmp.mismatch,
                         "matched": list(MATCHED), "stick_threshold_rad_s": float(stick_threshold),
                         "per_drive": {k: {kk: vv for kk, vv in v.items() if kk != "scan"} for k, v in per.items()}}
    return Calibration(model, cmp, per)


@dataclass
class Selection:
    """What :func:`select_model` found: per candidate (law name, drive) the mismatch of the model
    calibrated on the first half of the calibration part when it predicts the second half, the
    chosen pair, and the chosen pair recalibrated on the whole part.

    Attributes
    ----------
    scores : dict
        ``"<law>, <drive>"`` -> ``calibration_half_mismatch`` (on the first half) and
        ``prediction_half_mismatch`` (predicting the second half; inf when the simulation
        failed).
    law_name : str
        The chosen law's name (a key of the ``laws`` given).
    calibration : Calibration
        The chosen law and drive recalibrated on the whole part.
    """
    scores: dict
    law_name: str
    calibration: Calibration


@fitted_values()
def select_model(record: Record, laws: dict, stick_threshold: float, *, drives=DRIVES, preset: str = "thesis-rig",
                 log=None, threads: int = 0) -> Selection:
    """Choose the law and the top drive by how well they predict data they were not calibrated on.

    ``laws`` maps names to engine laws (identified on ``record``). Each law is calibrated
    (:func:`calibrate`) on the first half of ``record``, each drive's best model predicts the second
    half at its operating point, and the (law, drive) with the smallest mismatch there is chosen and
    recalibrated on the whole record. A calibration-only choice prefers the most flexible
    description (the motor's three parameters fit one part and extrapolate poorly: docs/records.md).

    Parameters
    ----------
    record : Record
        The cleaned calibration part, split at its midpoint in time.
    laws : dict
        Candidate name -> engine law (e.g. ``polynomial`` and ``polynomial_hysteretic``).
    stick_threshold : float
        Bit speed at or below which the bit counts as stuck [rad/s].
    drives : iterable of str
        Drives tried for every law, from :data:`DRIVES`.
    preset : str
        Engine preset of the rig.
    log : callable, optional
        Called with one progress line (str) per candidate and per drive of the final calibration.
    threads : int
        Simulations run at once by the calibrations (0: one per core).

    Returns
    -------
    Selection

    Raises
    ------
    ValueError
        If ``laws`` is empty.
    """
    if not laws:
        raise ValueError("select_model: no candidate law")
    t = record.time_s
    mid = t[0] + 0.5 * (t[-1] - t[0])
    first, second = record.select(t[0], mid), record.select(mid + 0.5 * record.dt, t[-1])
    scores = {}
    for name, law in laws.items():
        cal = calibrate(first, law, stick_threshold, drives=drives, preset=preset, threads=threads)
        for drive, b in cal.per_drive.items():
            m = RigModel(law, b["damping_ratio"], drive, b.get("motor_slope_nms_rad"), b.get("motor_inertia_kg_m2"),
                         preset=preset)
            try:
                mis = compare(second, simulate_model(m, second), stick_threshold).mismatch
            except (ValueError, RuntimeError):
                mis = math.inf
            scores[(name, drive)] = {"calibration_half_mismatch": b["mismatch"], "prediction_half_mismatch": mis}
            if log:
                log(f"rig model selection: {name}, {drive} drive: mismatch {b['mismatch']:.3f} on the first half, "
                    f"{mis:.3f} predicting the second half")
    name, drive = min(scores, key=lambda k: scores[k]["prediction_half_mismatch"])
    cal = calibrate(record, laws[name], stick_threshold, drives=(drive,), preset=preset, log=log, threads=threads)
    return Selection({f"{k[0]}, {k[1]}": v for k, v in scores.items()}, name, cal)


def droop_estimate(record: Record) -> tuple:
    """The open-loop motor's characteristic read off a record: the least-squares line of the
    reliable top speed on the measured torque, Omega_top = Omega_0 - T / c_m (sample 175: 18.1 rad/s
    and c_m = 0.225 N m s/rad). A start for :func:`calibrate_rig`, not a result: the measured torque
    is the bit's, not the top's.

    Parameters
    ----------
    record : Record
        A cleaned record with top speed and torque.

    Returns
    -------
    tuple of float
        (Omega_0 [rad/s], c_m [N m s/rad]); (mean top speed x 2, 0.25) when the line does not droop.
    """
    ok = reliable_top_speed(record) & record.valid("torque_on_bit")
    om = record.top_speed[ok]
    if ok.sum() > 10:
        slope, icpt = np.polyfit(record.torque_on_bit[ok], om, 1)
        if slope < 0:
            return float(icpt), float(-1.0 / slope)
    return float(2.0 * np.mean(om)) if om.size else 16.8, 0.25


def _metric_noise(record: Record, stick_threshold: float, keys: tuple, blocks: int = 4) -> np.ndarray:
    """Relative standard error of each metric over ``record``: the spread of the metric between
    ``blocks`` consecutive blocks, divided by sqrt(blocks) and by the metric's magnitude (at least 1 %)."""
    t = record.time_s
    edges = np.linspace(t[0], t[-1], blocks + 1)
    vals = []
    for a, b in zip(edges[:-1], edges[1:]):
        piece = record.select(a, b)
        try:
            m = _metrics(piece, stick_threshold, float(piece.time_s[0]), np.zeros(len(piece), bool))
            vals.append([m.get(k, np.nan) for k in keys])
        except (ValueError, RuntimeError):
            continue
    v = np.asarray(vals, float)
    if v.shape[0] < 2:
        return np.full(len(keys), 0.05)
    sd = np.nanstd(v, axis=0, ddof=1) / np.sqrt(v.shape[0])
    mag = np.maximum(np.abs(np.nanmean(v, axis=0)), 1e-12)
    return np.maximum(np.nan_to_num(sd / mag, nan=0.05), 0.01)


@fitted_values()
def calibrate_rig(record: Record, law: dict, stick_threshold: float, *, preset: str = "thesis-rig", screen: int = 64,
                  starts: int = 4, evaluations: int = 200, seed: int = 175, log=None, threads: int = 0) -> Calibration:
    """Calibrate the rig modelled whole (the ``rig`` drive) on a cleaned calibration part.

    The parameters of :data:`RIG_PARAMETERS`, each inside its physical range (a logistic map of
    the range, so that no value outside it is tried), minimize the mismatch over
    :data:`MATCHED_RIG` (:func:`compare`; the regular cycle's SS, stick fraction, cycle frequency,
    bit-speed p95, torque p5 and p95, the top speed's standard deviation and mean, the WOB's
    standard deviation). The mismatch jumps where cycles appear and vanish, so the search screens
    ``screen`` points, a start from the record's droop line (:func:`droop_estimate`) and typical
    values and others scattered around it (normal, sd 0.7 in the logistic coordinates, from
    ``seed``: most of the ranges' corners stall the rig or stop the cycle, where the mismatch is
    flat), and runs a Nelder-Mead from the ``starts`` best; the best result is polished once more
    from its own point. The result depends on the seed, never on the thread count.

    95 % intervals: the relative errors are linearized around the optimum (central differences at
    6 % of each range) and weighted by each metric's own sampling uncertainty, the spread of the
    metric between four blocks of the part (:func:`_metric_noise`). A parameter gets no interval when
    the metrics do not determine it, or when its slope at 2 % of the range differs from the one at
    6 % by more than half (a cycle or a stall appears in between: no local linearization holds).

    Parameters
    ----------
    record : Record
        The cleaned calibration part (with top speed, bit speed, torque and WOB).
    law : dict
        Engine bit-rock law identified on it (the measured-WOB fit suits: the WOB is a state here).
    stick_threshold : float
        Bit speed at or below which the bit counts as stuck [rad/s].
    preset : str
        Engine preset of the rig.
    screen : int
        Points screened for the starts (at least 1).
    starts : int
        Nelder-Mead starts, the best screened points (at least 1).
    evaluations : int
        Simulations per start.
    seed : int
        Seed of the random starts.
    log : callable, optional
        Called with one progress line (str) per start.
    threads : int
        Starts run at once (0: one per core).

    Returns
    -------
    Calibration
        ``per_drive["rig"]`` holds the parameters, their intervals, the mismatch and the
        evaluations.
    """
    names = list(RIG_PARAMETERS)
    lo = np.array([RIG_PARAMETERS[k][0] for k in names])
    hi = np.array([RIG_PARAMETERS[k][1] for k in names])
    op = operating_point(record)

    def params(x):
        return dict(zip(names, lo + (hi - lo) / (1.0 + np.exp(-np.clip(x, -30, 30)))))

    def internal(p):
        u = np.clip((np.array([p[k] for k in names]) - lo) / (hi - lo), 1e-6, 1 - 1e-6)
        return np.log(u / (1 - u))

    def model_of(p):
        return RigModel(law, p["damping_ratio"], "rig", p["motor_slope_nms_rad"], p["motor_inertia_kg_m2"],
                        preset=preset, command_rad_s=p["command_rad_s"], jack_gain_n_rad=p["jack_gain_n_rad"],
                        jack_relaxation_s=p["jack_relaxation_s"], platform_damping=p["platform_damping"],
                        gj_factor=p["gj_factor"], bit_inertia_factor=p["bit_inertia_factor"],
                        coupling_stiffness_nm_rad=p["coupling_stiffness_nm_rad"])

    side = measured_side(record, stick_threshold, float(record.time_s[0]), "rig")

    def comparison(p):
        return compare(record, simulate_model(model_of(p), record), stick_threshold, side=side, keys=MATCHED_RIG)

    def cost(x):
        try:
            return comparison(params(x)).mismatch
        except (ValueError, RuntimeError):  # diverged, unstable step
            return math.inf

    om0, cm0 = droop_estimate(record)
    first = {"damping_ratio": 0.04, "motor_slope_nms_rad": float(np.clip(cm0, lo[1], hi[1])),
             "motor_inertia_kg_m2": 0.015, "command_rad_s": float(np.clip(om0, lo[3], hi[3])),
             "jack_gain_n_rad": 150.0, "jack_relaxation_s": 0.2, "platform_damping": 0.7, "gj_factor": 1.05,
             "bit_inertia_factor": 1.05, "coupling_stiffness_nm_rad": 30.0}
    rng = np.random.default_rng(seed)
    scatter = [internal(first)] + [internal(first) + rng.normal(0.0, 0.7, len(names)) for _ in range(screen - 1)]
    workers = threads if threads > 0 else (os.cpu_count() or 1)
    with ThreadPoolExecutor(max_workers=workers) as pool:
        screened = list(pool.map(cost, scatter))
    order = sorted(range(len(scatter)), key=lambda i: (screened[i], i))
    x0s = [scatter[i] for i in order[:max(starts, 1)]]

    def search(x0):
        return optimize.minimize(cost, x0, method="Nelder-Mead",
                                 options={"maxfev": evaluations, "xatol": 1e-3, "fatol": 1e-4, "adaptive": True})

    with ThreadPoolExecutor(max_workers=workers) as pool:
        results = list(pool.map(search, x0s))
    for i, r in enumerate(results):
        if log:
            log(f"rig calibration (whole rig): start {i + 1} of {len(results)}: mismatch {r.fun:.3f} "
                f"after {r.nfev} simulations")
    best = min(results, key=lambda r: (r.fun, results.index(r)))
    polish = search(best.x)
    if polish.fun < best.fun:
        best = polish
    p = params(best.x)
    cmp = comparison(p)
    # 95 % intervals from the linearized relative errors weighted by the metrics' own noise
    sigma = _metric_noise(record, stick_threshold, MATCHED_RIG)

    def residuals(q):
        c = compare(record, simulate_model(model_of(q), record), stick_threshold, side=side, keys=MATCHED_RIG)
        return np.array([relative_error(c.simulated[k], c.measured[k]) for k in MATCHED_RIG])

    intervals = {}
    try:
        def slope(j, k, frac):
            h = frac * (hi[j] - lo[j])
            up, dn = dict(p), dict(p)
            up[k], dn[k] = min(p[k] + h, hi[j]), max(p[k] - h, lo[j])
            return (residuals(up) - residuals(dn)) / (up[k] - dn[k])

        cols, kept = [], []
        for j, k in enumerate(names):
            fine, coarse = slope(j, k, 0.02), slope(j, k, 0.06)
            # a metric that jumps (a cycle or a stall appearing) between the two steps: no local slope
            if np.linalg.norm(fine - coarse) <= 0.5 * max(np.linalg.norm(coarse), 1e-12):
                cols.append(coarse)
                kept.append(j)
        if cols:
            A = np.column_stack(cols) / sigma[:, None]
            cov = np.linalg.pinv(A.T @ A, rcond=1e-10)
            for c, j in enumerate(kept):
                k = names[j]
                sd = math.sqrt(cov[c, c]) if cov[c, c] > 0 else math.inf
                if math.isfinite(sd) and sd < (hi[j] - lo[j]):  # determined by the metrics
                    intervals[k] = [float(max(p[k] - 1.96 * sd, lo[j])), float(min(p[k] + 1.96 * sd, hi[j]))]
    except (ValueError, RuntimeError, np.linalg.LinAlgError):
        intervals = {}
    model = model_of(p)
    model.intervals = intervals
    per = {"rig": {**{k: float(v) for k, v in p.items()},
                   "mismatch": cmp.mismatch, "evaluations": int(sum(r.nfev for r in results) + polish.nfev),
                   "intervals": intervals, "metric_noise": dict(zip(MATCHED_RIG, map(float, sigma)))}}
    model.calibration = {"window_s": [float(record.time_s[0]), float(record.time_s[-1])], "operating_point": op,
                         "command_rad_s": p["command_rad_s"], "mismatch": cmp.mismatch,
                         "matched": list(MATCHED_RIG), "stick_threshold_rad_s": float(stick_threshold),
                         "per_drive": per}
    if log:
        log("rig calibration (whole rig): mismatch %.3f; " % cmp.mismatch
            + ", ".join(f"{k} {v:.4g}" for k, v in p.items()))
    return Calibration(model, cmp, per)
