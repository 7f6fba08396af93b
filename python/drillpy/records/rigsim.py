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
percentiles and the top speed's fluctuation (:func:`drillpy.records.rig_comparison.compare`).
:func:`drillpy.records.rig_calibration.calibrate` chooses the modal damping ratio (an *effective*
value that lumps every dissipation the one-mode model lacks) and the drive's parameters that match
a calibration part of a record best; :func:`simulate_model` runs a calibrated :class:`RigModel` at
the operating point of any record (its reliable mean top speed and mean WOB), which is how a model
is checked on data it was not calibrated on. This module holds the model and its simulation only.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from drillpy.model.config import normalize
from drillpy.model.configuration import Configuration
from drillpy.model.plausibility import fitted_values
from drillpy.records import stick as _stick
from drillpy.records.stick import STICK_FRACTION
from drillpy.records.bit_balance import timing_of
from drillpy.records.io import Flag, Record
from drillpy.records.signals import (platform_response, rig_lowpass)
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
    "motor_max_torque_nm": (2.0, 8.0, "N m", "the motor's torque limit: its rating, 8 N m (section 5.1), or the ESC's "
                                              "current limit below it (not measured); sample 175's stall holds 3.74 N m "
                                              "at 0.42 rad/s"),
    "static_ageing": (0.0, 1.0, "-", "A, the static torque's growth with the time stuck (not in the thesis): sample "
                                     "175's stall holds 3.74 N m where the law's static torque is 3.28 (+14 %); a "
                                     "rate-and-state ageing of a few tens of % (docs/records.md section 4)"),
    "static_ageing_s": (0.05, 3.0, "s", "tau_a, the time stuck at which the static torque has grown by A / 2: from "
                                        "about the cycle's stick phases (0.09 s at most) to twice the stall's 1.43 s"),
    "static_torque_factor": (1.0, 1.2, "-", "factor on the static torque 1.36 a0 of Eqs. (5.1, 5.3) identified from the "
                                            "filtered break-away peaks: the platform and the 10 Hz filter flatten the "
                                            "peak by 8 % on the calibrated model's own simulation and 9 % on a simulated "
                                            "truth (docs/records.md section 1); up to twice that"),
}


def with_static_torque_factor(law: dict, factor: float) -> dict:
    """The law with its static torque 1.36 a0 of Eqs. (5.1), (5.3) times ``factor``.

    a0 is scaled and a1 re-tied so that the law still falls linearly from the static torque at rest
    to the cubic's value a2 at 1 % of the reference speed (identification's tie); the slip branch
    is unchanged. Any other law, or a regularized one (a0 = 0), is returned unchanged.

    Parameters
    ----------
    law : dict
        Engine bit-rock law.
    factor : float
        Positive factor on the static torque [-].

    Returns
    -------
    dict
        A new law dict (the argument is not modified).
    """
    out = dict(law)
    if factor == 1.0 or not str(law.get("type", "")).startswith("polynomial") or not law.get("a0", 0.0) > 0:
        return out
    if not (math.isfinite(factor) and factor > 0):
        raise ValueError(f"static_torque_factor = {factor!r}: must be a positive number")
    out["a0"] = float(law["a0"]) * factor
    out["a1"] = (float(law["a2"]) - out["a0"]) / (0.01 * float(law["ref_speed"]))
    return out


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
    cfg = Configuration.load(preset=preset)
    if law is not None:
        cfg = cfg.replace(law={k: (float(v) if isinstance(v, (np.floating, np.integer)) else v) for k, v in law.items()})
    if damping_ratio is not None:
        cfg = cfg.replace(damping={"type": "modal", "ratios": [float(damping_ratio)]})
    if duration_s is not None:
        cfg = cfg.replace({"simulation.duration_s": float(duration_s),
                           "simulation.transient_s": min(cfg.simulation.transient_s, 0.5 * float(duration_s))})
    cfg = cfg.replace({"operation.wob_n": float(cfg.law.wob_ref_n if wob is None else wob)})
    if top_speed is not None:
        cfg = cfg.replace({"operation.top_speed_rad_s": float(top_speed)})
    drive = None
    if motor is not None:
        drive = {"type": "motor", "slope_nms_rad": float(motor[0]), "inertia_kg_m2": float(motor[1])}
        if len(motor) > 2 and motor[2] is not None:
            drive["max_torque_nm"] = float(motor[2])
    jack = None if axial is None else {"type": "jack", "gain_n_rad": float(axial[0]), "relaxation_s": float(axial[1])}
    cfg = cfg.replace(top_drive=None, axial=None).replace(top_drive=drive, axial=jack)  # the preset's removed
    if gj_factor != 1.0:
        cfg = cfg.replace({"string.sections": [
            {**s.to_dict(), "youngs_modulus_pa": float(s.youngs_modulus_pa) * float(gj_factor)}
            for s in cfg.string.sections]})
    if bit_inertia_factor != 1.0 and "lumped_inertias" in cfg.string:
        cfg = cfg.replace({"string.lumped_inertias": [
            {**li.to_dict(), "inertia_kg_m2": float(li.inertia_kg_m2) * float(bit_inertia_factor)} if li.node == -1
            else li.to_dict() for li in cfg.string.lumped_inertias]})
    if coupling_stiffness is not None:
        cfg = with_coupling(cfg, coupling_stiffness)
    return normalize(cfg)


def _shifted_inertias(cfg: Configuration, first: int, by: int) -> dict:
    """``string.lumped_inertias`` with the node indices from ``first`` on moved by ``by`` (nothing
    when the configuration lists none)."""
    if "lumped_inertias" not in cfg.string:
        return {}
    return {"string.lumped_inertias": [{**li.to_dict(), "node": li.node + by} if li.node >= first else li.to_dict()
                                       for li in cfg.string.lumped_inertias]}


def with_coupling(cfg, stiffness: float) -> Configuration:
    """The configuration with a massless shaft coupling of torsional stiffness ``stiffness`` [N m/rad]
    between the top drive and the string: a first section named ``"coupling"``,
    :data:`COUPLING_LENGTH_M` long, of the top section's material, whose G J / L is the stiffness (its
    inertia is negligible).

    Parameters
    ----------
    cfg : dict or Configuration
        Engine configuration (not modified).
    stiffness : float
        k_c [N m/rad], positive.

    Returns
    -------
    Configuration
        The copy with the coupling (the lumped inertias' node indices shifted by one).
    """
    cfg = Configuration.of(cfg)
    top = cfg.string.sections[0]
    E, nu, L = float(top.youngs_modulus_pa), float(top.poisson_ratio), COUPLING_LENGTH_M
    G = E / (2.0 * (1.0 + nu))
    r = (2.0 * float(stiffness) * L / (math.pi * G)) ** 0.25  # G pi r^4 / 2 / L = k_c
    coupling = {"name": "coupling", "length_m": L, "outer_radius_m": r, "inner_radius_m": 0.0,
                "youngs_modulus_pa": E, "poisson_ratio": nu, "density_kg_m3": float(top.density_kg_m3), "elements": 1}
    return cfg.replace({"string.sections": [coupling, *cfg.string.sections],
                        **_shifted_inertias(cfg, 0, 1)})  # the coupling's element comes first


def without_coupling(cfg) -> tuple:
    """The configuration without the shaft coupling of :func:`with_coupling`, and its stiffness.

    Parameters
    ----------
    cfg : dict or Configuration
        Engine configuration (not modified).

    Returns
    -------
    config : Configuration
        The copy without the coupling section (the configuration itself when it has none).
    stiffness : float or None
        k_c [N m/rad], or None when the configuration has no coupling section.
    """
    cfg = Configuration.of(cfg)
    secs = cfg.string.sections
    if not secs or secs[0].get("name") != "coupling":
        return cfg, None
    c = secs[0]
    G = float(c.youngs_modulus_pa) / (2.0 * (1.0 + float(c.poisson_ratio)))
    k = G * math.pi * float(c.outer_radius_m) ** 4 / 2.0 / float(c.length_m)
    return cfg.replace({"string.sections": list(secs[1:]), **_shifted_inertias(cfg, 1, -1)}), k


def _in_place(cfg: dict, new: Configuration) -> None:
    """Make the dict ``cfg`` hold ``new`` (the in-place form of the functions above)."""
    cfg.clear()
    cfg.update(new.to_dict())


def add_coupling(cfg: dict, stiffness: float) -> None:
    """:func:`with_coupling` in place.

    Parameters
    ----------
    cfg : dict
        Engine configuration, modified in place (the lumped inertias' node indices shift by one).
    stiffness : float
        k_c [N m/rad], positive.
    """
    _in_place(cfg, with_coupling(cfg, stiffness))


def remove_coupling(cfg: dict) -> float | None:
    """:func:`without_coupling` in place: take the shaft coupling out of a configuration.

    Parameters
    ----------
    cfg : dict
        Engine configuration, modified in place.

    Returns
    -------
    float or None
        Its stiffness k_c [N m/rad], or None when the configuration has no coupling section.
    """
    new, k = without_coupling(cfg)
    if k is not None:
        _in_place(cfg, new)
    return k


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
        Motor slope c_m [N m s/rad]: the torque the motor gives per rad/s below its command (``rig``
        drive: None for the rig without its motor, an ideal drive turning at ``command_rad_s``).
    motor_inertia_kg_m2 : float or None
        Inertia J_m of the motor top drive [kg m^2].
    preset : str
        Engine preset of the geometry (``thesis-rig``, Table 5.1).
    calibration : dict
        How the model was obtained (:func:`drillpy.records.rig_calibration.calibrate`): calibration window, operating point,
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
        Stiffness of the coupling between the motor and the bar [N m/rad] (``rig`` drive; None: no
        coupling, the rotor turns the bar's top rigidly).
    intervals : dict
        Parameter name -> [low, high], a 95 % interval (``rig`` drive: :func:`drillpy.records.rig_calibration.calibrate_rig`).
    torque_fluctuation : dict or None
        The stochastic torque of Eq. (4.1) identified on the calibration window
        (:func:`drillpy.records.rig_fluctuation.identify`); None: none. A simulation is deterministic
        unless it is given a realization (``eta`` of :func:`simulate_model`).
    static_torque_factor : float
        Factor on the law's static torque 1.36 a0 (``rig`` drive; 1 for the others, and by default:
        :data:`RIG_PARAMETERS`, :attr:`engine_law`).
    motor_max_torque_nm : float
        The ``rig`` drive's motor torque limit [N m]: the motor gives at most this torque, whatever its
        speed (default :data:`MOTOR_MAX_TORQUE_NM`, the rating; below it, the ESC's current limit, which
        is not measured: ``benchmarks/rig_stall.py``).
    static_ageing, static_ageing_s : float
        The ``rig`` drive's ageing of the law's static torque, A [-] and tau_a [s] (``law.static_ageing``,
        ``law.static_ageing_s``: after tau s stuck the static torque is (1 + A tau / (tau + tau_a)) times
        the law's); A = 0 (default): none.
    channel_timing : dict or None
        The acquisition's skew (``top_lead_s``, ``torque_lag_s`` [s], ``from``) at which the records
        the model is scored on are read (:func:`drillpy.records.bit_balance.aligned`): found on the
        calibration window by ``drillpy analyze --channel-timing auto`` or given; the short-horizon
        error E is computed on the record brought to it. None: as recorded.
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
    torque_fluctuation: dict | None = None
    static_torque_factor: float = 1.0
    channel_timing: dict | None = None
    motor_max_torque_nm: float = MOTOR_MAX_TORQUE_NM
    static_ageing: float = 0.0
    static_ageing_s: float = 0.3

    def __post_init__(self):
        if self.drive not in DRIVES:
            raise ValueError(f"drive = {self.drive!r}: use {', '.join(DRIVES)}")
        if not (math.isfinite(self.damping_ratio) and self.damping_ratio > 0):
            raise ValueError(f"damping_ratio = {self.damping_ratio!r}: must be a positive number")
        need = {"motor": ("motor_slope_nms_rad", "motor_inertia_kg_m2"),
                "rig": ("command_rad_s", "jack_relaxation_s", "platform_damping", "gj_factor",
                        "bit_inertia_factor")}.get(self.drive, ())
        if self.drive == "rig" and self.motor_slope_nms_rad is not None:  # None: an ideal drive at the command
            need += ("motor_slope_nms_rad", "motor_inertia_kg_m2")
        for k in need:
            v = getattr(self, k)
            if v is None or not (math.isfinite(v) and v > 0):
                raise ValueError(f"{k} = {v!r}: the {self.drive} drive needs a positive value")
        k_c = self.coupling_stiffness_nm_rad
        if k_c is not None and not (math.isfinite(k_c) and k_c > 0):
            raise ValueError(f"coupling_stiffness_nm_rad = {k_c!r}: a positive stiffness, or None for a rigid "
                             "connection (no coupling)")
        if self.drive == "rig" and not (self.jack_gain_n_rad is not None and math.isfinite(self.jack_gain_n_rad)
                                        and self.jack_gain_n_rad >= 0):
            raise ValueError(f"jack_gain_n_rad = {self.jack_gain_n_rad!r}: the rig drive needs a value >= 0")
        if not (math.isfinite(self.static_torque_factor) and self.static_torque_factor > 0):
            raise ValueError(f"static_torque_factor = {self.static_torque_factor!r}: must be a positive number")
        if not (math.isfinite(self.motor_max_torque_nm) and self.motor_max_torque_nm > 0):
            raise ValueError(f"motor_max_torque_nm = {self.motor_max_torque_nm!r}: must be a positive number")
        if not (math.isfinite(self.static_ageing) and self.static_ageing >= 0):
            raise ValueError(f"static_ageing = {self.static_ageing!r}: must be a number >= 0")
        if not (math.isfinite(self.static_ageing_s) and self.static_ageing_s > 0):
            raise ValueError(f"static_ageing_s = {self.static_ageing_s!r}: must be a positive time [s]")
        if self.drive != "rig" and self.static_ageing != 0.0:
            raise ValueError(f"static_ageing = {self.static_ageing!r}: only the rig drive calibrates it")
        if self.drive != "rig" and self.static_torque_factor != 1.0:
            raise ValueError(f"static_torque_factor = {self.static_torque_factor!r}: only the rig drive calibrates it")

    @property
    def engine_law(self) -> dict:
        """The law the engine runs: :attr:`law` (as identified) with its static torque times
        :attr:`static_torque_factor` (:func:`with_static_torque_factor`), aged by :attr:`static_ageing`
        over :attr:`static_ageing_s` where it is positive."""
        law = with_static_torque_factor(self.law, self.static_torque_factor)
        if self.static_ageing > 0:
            law |= {"static_ageing": float(self.static_ageing), "static_ageing_s": float(self.static_ageing_s)}
        return law

    @property
    def motor(self) -> tuple | None:
        """(c_m [N m s/rad], J_m [kg m^2]) for the motor drive, with the torque limit
        :attr:`motor_max_torque_nm` for the rig drive, None for the others."""
        if self.drive == "rig":
            if self.motor_slope_nms_rad is None:  # the rig without its motor: an ideal drive
                return None
            return (self.motor_slope_nms_rad, self.motor_inertia_kg_m2, self.motor_max_torque_nm)
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
        rig = (self.calibration.get("per_drive") or {}).get("rig") or {}
        # held at a value, not calibrated: no bound flag (the identified static torque as is, 1, by default)
        held = set(rig.get("fixed") or {}) | ({"static_torque_factor"} if not rig and self.static_torque_factor == 1.0
                                              else set())
        for name, (lo, hi, unit, source) in RIG_PARAMETERS.items():
            if getattr(self, name) is None:  # an element the model does not have (a rigid coupling)
                out[name] = {"value": None, "ci95": None, "range": [lo, hi], "unit": unit, "source": source,
                             "flag": None, "fixed": True}
                continue
            v = float(getattr(self, name))
            flag = None
            if name in held:
                pass
            elif v <= lo * (1 + 1e-3) or v >= hi * (1 - 1e-3):
                flag = f"at the bound of its range [{lo:g}, {hi:g}] {unit}: an element the model lacks may be pushing it"
            elif name == "platform_damping" and v > 1.0:
                flag = "an overdamped platform: the torque channel lags more than a 20 Hz mode explains"
            out[name] = {"value": v, "ci95": self.intervals.get(name), "range": [lo, hi], "unit": unit,
                         "source": source, "flag": flag, "fixed": name in held}
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
        return rig_config(self.engine_law, self.damping_ratio, preset=self.preset, duration_s=duration_s,
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
                          "wob_trend_hz": WOB_TREND_HZ, "static_torque_factor": self.static_torque_factor,
                          "static_ageing": self.static_ageing, "static_ageing_s": self.static_ageing_s,
                          "identified_law": self.law,
                          "parameters": self.parameters()}
        if self.torque_fluctuation:
            out["torque_fluctuation"] = self.torque_fluctuation
        if self.channel_timing:
            out["channel_timing"] = self.channel_timing
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
            extra, law = {}, cfg["law"]
            if drive == "rig":
                rig, ax = d.get("rig") or {}, cfg.get("axial") or {}
                # the configuration holds the law the engine runs; the model keeps the identified one
                law = rig.get("identified_law", law)
                extra["static_torque_factor"] = float(rig.get("static_torque_factor", 1.0))
                extra["motor_max_torque_nm"] = float(td.get("max_torque_nm", MOTOR_MAX_TORQUE_NM))
                extra["static_ageing"] = float(rig.get("static_ageing", cls.static_ageing))
                extra["static_ageing_s"] = float(rig.get("static_ageing_s", cls.static_ageing_s))
                extra |= {"command_rad_s": cfg["operation"]["top_speed_rad_s"], "jack_gain_n_rad": ax.get("gain_n_rad"),
                         "jack_relaxation_s": ax.get("relaxation_s"), "platform_damping": rig.get("platform_damping"),
                         "gj_factor": rig.get("gj_factor", 1.0),
                         "bit_inertia_factor": rig.get("bit_inertia_factor", 1.0),
                         "coupling_stiffness_nm_rad": rig.get("coupling_stiffness_nm_rad"),
                         "intervals": {k: v.get("ci95") for k, v in (rig.get("parameters") or {}).items()
                                       if v.get("ci95") is not None}}
            return cls(law=law, damping_ratio=float(damp["ratios"][0]), drive=drive,
                       motor_slope_nms_rad=td.get("slope_nms_rad") if motor else None,
                       motor_inertia_kg_m2=td.get("inertia_kg_m2") if motor else None,
                       calibration=d.get("calibration", {}), torque_fluctuation=d.get("torque_fluctuation"),
                       channel_timing=timing_of(d.get("channel_timing")), **extra)  # rebuilt on the thesis-rig geometry
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
    samples are then left out of every comparison (:func:`drillpy.records.rig_comparison.measured_side`): never fed in unmarked,
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
    cfg = Configuration.of(model.config(command, wob, duration_s=float(record.time_s[-1] - record.time_s[0])))
    return normalize(cfg.replace({"simulation.output_stride": max(1, int(round(record.dt / cfg.simulation.dt_s)))}))


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


def _run(model: RigModel, record: Record, command: float, wob: float, eta=None):
    measured, rig = model.drive == "measured", model.drive == "rig"
    return simulate(_setup(model, record, command, wob), None if measured else command,
                    top_speed_series=drive_series(record) if measured else None,
                    wob_series=wob_trend(record, wob) if rig else None, eta_series=eta, series_dt=record.dt)


def _as_record(model: RigModel, record: Record, res, command: float, op: dict, wob: float, filtered: bool) -> Record:
    """The simulation ``res`` of ``model`` as a record on ``record``'s grid (see :func:`simulate_model`)."""
    n, vb, vt, tq, w = _channels(res, record, filtered, model.platform_damping if model.drive == "rig" else None)
    t = res.t[:n] + record.time_s[0]
    return Record(time_s=t, bit_speed=vb, top_speed=vt, torque_on_bit=tq, wob=w,
                  units={"time": "s", "bit_speed": "rad_s", "top_speed": "rad_s", "torque_on_bit": "Nm", "wob": "N"},
                  provenance={"source": "simulation", "format": "drillpy.simulate", "preset": model.preset,
                              "drive": model.drive, "filtered": filtered, "command_rad_s": command,
                              "operating_point": op, "config": res.config})


def simulate_model(model: RigModel, record: Record, *, filtered: bool = True, skip_s: float = 2.0,
                   eta=None) -> Record:
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
    eta : array_like, optional
        A realization of the torque fluctuation of Eq. (4.1) [-] on the record's grid from its
        start (:func:`drillpy.records.rig_fluctuation.realization`); None: eta = 0.

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

        @fitted_values()  # the commands the search tries are not a user's input (and may exceed 32 rad/s)
        def gap(c):
            res = _run(model, record, c, wob, eta)
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
        with fitted_values():  # the command found: a fitted no-load speed, judged by the search, not typed
            return _as_record(model, record, _run(model, record, command, wob, eta), command, op, wob, filtered)
    return _as_record(model, record, _run(model, record, command, wob, eta), command, op, wob, filtered)


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
    base = Configuration.load(preset=preset)
    law = base.law.to_dict() if law is None else law
    z = base.damping.ratios[0] if damping_ratio is None else damping_ratio
    m = RigModel(law, float(z), drive, *(motor if motor else (None, None)), preset=preset)
    return simulate_model(m, record, filtered=filtered)
